/*
 * sph_sim: a particle simulation behind an opaque handle. Method-agnostic: the configuration says
 * which method (cfg.method; a table inside the core, sph_method.h, holds each); the handle is
 * created, stepped, observed and destroyed:
 *
 *     sph_sim *s = sph_sim_create(&cfg, &err);
 *     while (sph_sim_time(s) < cfg.t_end)
 *         if (sph_sim_advance(s, 100, cfg.t_end, &err)) ... err.code == SPH_ERR_UNSTABLE ...
 *     const sph_diag *d = sph_sim_diag(s);
 *     sph_sim_destroy(s);
 *
 * No global state: any number of sims may live in one process. The core parallelises inside a
 * step with OpenMP, with the number of threads of the calling thread (omp_set_num_threads() in a
 * worker thread sets it for that worker's jobs); jobs under 4096 particles run on the calling
 * thread alone. Runs are bitwise reproducible, and the same with any number of threads (the pair
 * loops visit pairs in an order fixed by the cell grid; reductions are max/min or serial).
 * Not thread-safe: one thread drives a sim at a time.
 */
#ifndef SPH_SIM_H
#define SPH_SIM_H

#include "sph_config.h"
#include <stddef.h>
#include "sph_error.h"

typedef struct sph_sim sph_sim;

/* One rigid body in the diagnostics (SI units; per metre in 2D). */
typedef struct sph_body_diag {
    double x[3];        /* centre of mass [m] */
    double v[3];        /* its velocity [m/s] */
    double angle;       /* [rad], counter-clockwise */
    double omega;       /* angular velocity [rad/s] */
    double force[3];    /* force of the fluid (and of walls in contact) on the body [N] */
    double torque;      /* its torque about the centre of mass [N m] */
    double penetration; /* depth of the lowest point below the initial still-water level [m] */
} sph_body_diag;

/* Diagnostics of the latest completed step (SI units). */
typedef struct sph_diag {
    double t;           /* time [s] */
    long step;          /* steps done [-] */
    double dt;          /* latest time step [s] */
    double ekin;        /* kinetic energy of the fluid, sum m v^2 / 2 [J] (per metre in 2D) */
    double epot;        /* potential energy of the fluid, -sum m g.x [J] (per metre in 2D) */
    double vmax;        /* largest fluid speed [m/s] */
    double rho_min;     /* smallest fluid density [kg/m^3] */
    double rho_max;     /* largest fluid density [kg/m^3] */
    double front_x;     /* x of the leading edge of the connected fluid [m] */
    double height_left; /* water height at the left wall (tank or domain) above its bottom [m] */
    long lost;          /* fluid particles that left the domain [-] */
    long nfluid;        /* fluid particles (lost included) [-] */
    long nboundary;     /* boundary particles [-] */
    double runup;       /* fluid top at the right wall (tank or domain) above its bottom [m] */
    /* MPS only (0 for other methods): the pressure solve of the latest step */
    long cg_iterations; /* conjugate-gradient iterations [-] */
    double cg_residual; /* relative residual ||b - A p|| / ||b|| reached [-] */
    long free_surface;  /* particles on the free surface (Dirichlet p = 0) [-] */
    long nbody;         /* particles of the rigid bodies [-] */
    double penetration; /* the first body's penetration (NAN without bodies) [m] */
    int nbodies;        /* rigid bodies, in the configuration's order (names there) */
    sph_body_diag body[SPH_CONFIG_MAX_BODIES];
    int ngauges;                            /* height gauges, in the configuration's order */
    double gauge[SPH_CONFIG_MAX_GAUGES];    /* their water heights (0: dry) [m] */
    int npressure;                          /* pressure probes, in the configuration's order */
    double pressure[SPH_CONFIG_MAX_GAUGES]; /* their pressures (0: dry) [Pa] */
} sph_diag;

/* Read access to the particles. Arrays are in the sim's current (cell-sorted) order; `id` maps
 * them to their creation index. Valid until the next step or destroy. */
typedef struct sph_particle_view {
    long n;                    /* particles (fluid, boundary and lost) */
    int dim;                   /* 2 */
    const double *pos[3];      /* position components [m] (pos[2] NULL in 2D) */
    const double *vel[3];      /* velocity components [m/s] */
    const double *rho;         /* density [kg/m^3] */
    const double *p;           /* pressure [Pa] */
    const float *vel32[3];     /* mixed precision ("precision": "mixed"): vel, rho and p in */
    const float *rho32, *p32;  /* float, the double pointers NULL (sph_view_get reads either) */
    const unsigned char *type; /* 0 fluid, 1 boundary, 2 lost, 4 body (sph_particles.h) */
    const int *id;             /* creation index */
} sph_particle_view;

/* Element i of a view's field, stored in double (d) or, under mixed precision, in float (f). */
static inline double sph_view_get(const double *d, const float *f, long i)
{
    return d ? d[i] : (double)f[i];
}

/* The types a view shows, as a units string for files and by name for clients. */
#define SPH_PARTICLE_TYPES_DOC "0 fluid, 1 boundary, 2 lost, 4 body"

/* "fluid", "boundary", "lost" or "body" for a view's type value; NULL for any other. */
const char *sph_particle_type_name(int type);

/* Cumulative wall-clock time spent in each part of the steps (for benchmarks). */
typedef struct sph_timing {
    double neighbours;   /* cell list build and particle reordering [s] */
    double interactions; /* pair loops [s] */
    double integration;  /* time integration, checks, diagnostics [s] */
    double bodies;       /* rigid bodies: their particles' pressure from the fluid, forces
                            summed, bodies moved, particles placed [s] (part of interactions
                            and integration) */
    double solve;        /* MPS: the pressure equation's assembly and solve [s] */
    long pairs;          /* interacting pairs (r < support) in the latest force evaluation */
    long active;         /* particles in the latest force evaluation */
    long lists;          /* reused neighbour lists built (neighbours.skin; this sim's, not a
                            restored state's before it) */
} sph_timing;

/* Once at the start of a program that runs simulations, before it starts any thread: the
 * process-wide set-up of the optional libraries of this build (with -DSPH_HYPRE, Open MPI's
 * singleton in isolated mode for MPS's AMG solves: no helper process). Does nothing otherwise;
 * a program that skips it still works. */
void sph_core_init(void);

/* The GPUs a case may run on ("device": "gpu"): their count (0 in a build without CUDA), and
 * the name and memory [bytes] of GPU k (returns 0, or -1 when there is no such GPU). */
int sph_sim_gpu_count(void);
int sph_sim_gpu_describe(int k, char *name, size_t len, double *bytes);

/* 1 if this build runs method m as a particle simulation (a row of the method table). */
int sph_sim_has_method(sph_method m);

/* Checks a configuration as sph_sim_create() does, without building anything: the shared rules
 * and the method's own (err->path names the case field). */
int sph_sim_check(const sph_config *cfg, sph_error *err);

/* Creates the simulation: builds the particles, the cell list and the initial forces. Fails with
 * SPH_ERR_INVALID (bad configuration, path names the case field), SPH_ERR_NOMEM ("too_large": the
 * case needs more than cfg->max_bytes, or memory ran out). */
sph_sim *sph_sim_create(const sph_config *cfg, sph_error *err);

/* Advances by at most max_steps steps and not past time t_until (the last step is shortened to
 * land on it). Returns 0, or SPH_ERR_UNSTABLE with a message naming the step and the quantity
 * (non-finite values, density collapse, too many particles lost, time step collapse); a failed
 * sim refuses further steps. The diagnostics are updated at the end of every call. */
int sph_sim_advance(sph_sim *s, long max_steps, double t_until, sph_error *err);

/* sph_sim_advance(s, nsteps, INFINITY, err). */
int sph_sim_step(sph_sim *s, long nsteps, sph_error *err);

const sph_diag *sph_sim_diag(const sph_sim *s);
double sph_sim_time(const sph_sim *s);

/* What first-order wavemaker theory gives for c's wavemaker (boundary/sph_wavemaker.h): 0, or -1
 * without a wavemaker or when its depth or gravity leaves no waves. */
int sph_sim_wave_design(const sph_config *c, sph_wave_design *w);
/* 1 if the method solves a pressure equation every step (MPS): sph_diag's cg_iterations,
 * cg_residual and free_surface are its figures. */
int sph_sim_solves_pressure(const sph_sim *s);
/* The smoothing length h [m] (MPS: half the larger effective radius). */
double sph_sim_h(const sph_sim *s);
const sph_config *sph_sim_config(const sph_sim *s);
/* Steering: takes from next, between two steps, the parameters a simulation can change without a
 * new set-up (PROTOCOL.md 3.12): the viscous term's coefficients (alpha, nu), delta-SPH's
 * coefficient, gravity, the CFL number, the end time and the diagnostics' schedule (diag_every,
 * diag_interval: the caller's, kept for a restore); the rest of next is not looked at.
 * What each step derives from them is derived afresh (the pair loop's constants; the bodies'
 * gravity). SPH_ERR_INVALID (s unchanged) on the GPU (its copy of the parameters is made once)
 * and for a new gravity under ghost walls (their pressure's hydrostatic part is set up for the
 * gravity they were made with). */
int sph_sim_steer(sph_sim *s, const sph_config *next, sph_error *err);
/* A view of the particle arrays (valid until the next step); the pressures are computed from
 * the densities when it is taken. */
void sph_sim_particles(const sph_sim *s, sph_particle_view *view);
void sph_sim_timing(const sph_sim *s, sph_timing *timing);
/* Resident bytes of the sim's particle and cell storage. */
double sph_sim_bytes(const sph_sim *s);
/* Bytes the simulation holds on its device (a GPU's; 0 on the CPU or before the first step). */
double sph_sim_device_bytes(const sph_sim *s);

/* An oscillating run against its theory (initial fields that have one, sph_initial.h): the
 * kinetic-energy envelope's decay rate and the period fitted over the peaks up to
 * min(t_fit, now), and what theory says. */
typedef struct sph_sim_wave {
    int peaks;                /* peaks fitted [-] */
    double t_fit;             /* fitted up to this time [s] */
    double decay_rate;        /* fitted decay rate of the envelope [1/s] */
    double period;            /* fitted period [s] */
    double decay_rate_theory; /* 4 nu k^2 for the standing wave [1/s] */
    double period_theory;     /* 2 pi / omega [s] */
    double ekin0_theory;      /* initial kinetic energy [J] (per metre in 2D) */
    double nu;                /* the viscosity compared with [m^2/s] */
    double alpha;             /* Monaghan's alpha of the run (0 for laminar viscosity) [-] */
} sph_sim_wave;

/* Fills *w for the peaks up to t_fit [s] (INFINITY: all). Returns 0, or -1 when the initial
 * field has no theory or fewer than 3 peaks have been seen. */
int sph_sim_wave_fit(const sph_sim *s, double t_fit, sph_sim_wave *w);

/* The binning the server reports the RPDF with (query field `rpdf`, the snapshots' group
 * `rpdf`) and the validation prints: SPH_SIM_RPDF_BINS bins of q = r / h over
 * [0, SPH_SIM_RPDF_QMAX), i.e. out to the kernels' support. */
#define SPH_SIM_RPDF_BINS 40
#define SPH_SIM_RPDF_QMAX 2.0

/* The radial particle density function of the fluid now (sph_rpdf.h): nbins bins of q = r / h
 * over [0, qmax); q (bin centres), count (pairs) and density (relative to a uniform fluid at the
 * initial spacing) each get nbins values (zeros with fewer than two fluid particles). Returns 0,
 * SPH_ERR_INVALID (path /rpdf/bins or /rpdf/qmax) or SPH_ERR_NOMEM. */
int sph_sim_rpdf(const sph_sim *s, double qmax, int nbins, double *q, double *count,
                 double *density, sph_error *err);

/* destroy(NULL) is a no-op. */
void sph_sim_destroy(sph_sim *s);

/* The state needed to continue the run exactly (configuration included), as a new malloc'd
 * buffer in *buf (the caller frees it). Returns 0 or SPH_ERR_NOMEM. */
int sph_sim_save(const sph_sim *s, void **buf, size_t *len, sph_error *err);

/* A sim from a saved state: continues bitwise as the saved one would have (same thread count
 * or not: runs do not depend on it). Returns NULL with SPH_ERR_IO for a state that is not one,
 * or the errors of sph_sim_create. */
sph_sim *sph_sim_restore(const void *buf, size_t len, sph_error *err);

/* The same, run on `device` whichever the state was saved on (a GPU job's state continues on the
 * CPU and the other way round); refused as a new case on that device would be. */
sph_sim *sph_sim_restore_on(const void *buf, size_t len, sph_device device, sph_error *err);

/* Bytes sph_sim_create() would need for cfg (what max_bytes is compared with). Also reports the
 * particle counts. */
double sph_sim_estimate_bytes(const sph_config *cfg, long *nfluid, long *nboundary);

#endif
