/*
 * sph_wavemaker: a wave flume's paddle and damping zone (sph_config.h: sph_wavemaker_spec,
 * sph_absorption_spec); the physics is sph_wave_law.h's, written once for host and device.
 *
 * The paddle is a block of dynamic wall particles: `layers` columns behind its wet face at x
 * (the face towards +x, the particles dx/2, 3dx/2, ... behind it, as the tank's walls sit
 * outside their faces), the tank's height in rows from its bottom (in 3D, where z is the vertical,
 * also its width in y). They are the last wall
 * particles of the fill (after the tank's and the obstacles'), with ids [first, first + np); the
 * table of their rest positions is indexed by id - first, so nothing follows them through the
 * cell sort. Each step places them rigidly: a piston at rest + X(t) with the velocity dX/dt, a
 * flap turned about its hinge (on the face, `hinge` above the tank's bottom) so that its face at
 * the still water level is X(t) ahead of rest (sph_wave_law.h).
 * The paddle's motion is a function of time alone: nothing of it lives across steps but the
 * configuration (a restart rebuilds the table from the fill).
 *
 * The fluid must lie in front of the paddle (every fluid box from x on); the still water depth
 * d is the fluid boxes' top above the tank's bottom.
 */
#ifndef SPH_WAVEMAKER_H
#define SPH_WAVEMAKER_H

#include "sph_config.h"
#include "sph_error.h"
#include "sph_hd.h"
#include "sph_particles.h"
#include "sph_wave_law.h"

/* Active absorption's state across steps (zero without it). */
typedef struct sph_paddle_state {
    double xc;     /* the correction's displacement so far [m] */
    double vc;     /* the correction's velocity of the last step [m/s] */
    double ebar;   /* the level error's running mean [m] */
    double level0; /* the level read in front of the face at t = 0 [m] */
} sph_paddle_state;

typedef struct sph_paddle {
    long first, np;       /* the paddle's particles: ids [first, first + np) */
    double *rest;         /* 2 per particle: its position at rest [m], by id - first */
    sph_paddle_law law;   /* its motion (its arrays: comp and series) */
    double *comp;         /* irregular waves: the components (law.comp), owned */
    sph_wave_series rows; /* a series' rows (law.st, .sx), owned */
    /* active absorption (a piston; sph_paddle_absorb): the velocity correction -sqrt(g/d) (eta -
     * eta_target - ebar) - xc / tau, eta the level read over [face + dx, face + 3 dx] less its
     * reading at t = 0, ebar its mean error (an exponential average over tau), xc the correction's
     * displacement so far */
    int active;
    double face, dx, bottom; /* the face at rest, the strip's unit, the tank's bottom [m] */
    double sgd, hs, tau;     /* sqrt(g / d) [1/s], the transfer function H/S, tau [s] */
    double *tf;              /* an irregular sea's transfer functions, a component each, owned */
    sph_paddle_state st;     /* what lives across steps (a checkpoint saves it) */
} sph_paddle;

/* The design of c's wavemaker (sph_config.h; type not none): 0, or -1 when the depth or gravity
 * leaves no waves. */
int sph_wave_design_of(const sph_config *c, sph_wave_design *w);

/* The components of c's irregular sea at the still water depth depth (sph_wave_law.h: 3 a
 * component, the displacement's amplitude A_i [m], omega_i [rad/s], phase [rad]) into a new
 * array *comp, and with tf not NULL each one's transfer function H/S into a new array *tf (the
 * caller frees them); their count, 0 with none (NULLs), -1 out of memory. */
int sph_wave_components(const sph_config *c, double depth, double **comp, double **tf);

/* Checks c's wavemaker and damping zone (after the shared checks: dx, domain, tank), err->path
 * at the field: a method, dimension, device or wall treatment that cannot move a paddle, fluid
 * behind the paddle's face, a regular wave without a period or steeper than the breaking limit,
 * a solitary wave with one, higher than SPH_SOLITARY_MAX d or from a flap, a hinge outside the
 * water column (or given for a piston), a stroke the tank cannot hold, a damping zone outside the
 * domain or over the paddle's travel. */
int sph_wavemaker_check(const sph_config *c, sph_error *err);

/* The paddle's particles of c (0 without a wavemaker); with pos, their positions into pos[0] ..
 * pos[dim - 1]. */
long sph_wavemaker_points(const sph_config *c, double *const *pos);

/* Builds c's paddle over P's particles [first, first + np) as the fill left them (ids their
 * indices), with its own copy of an irregular sea's components or a series' rows: 0, -1 out of
 * memory, -2 for a series not read (c's wavemaker.series NULL). A no-op (np 0) without a
 * wavemaker. */
int sph_paddle_init(sph_paddle *p, const sph_config *c, const sph_particles *P, long first);
void sph_paddle_free(sph_paddle *p);

/* The law of motion of c's paddle, of design d (sph_wave_design_of). */
void sph_paddle_law_of(const sph_config *c, const sph_wave_design *d, sph_paddle_law *law);

/* Places the paddle's particles among P's first n at time t (sph_paddle_place: a piston at rest +
 * X(t) with the velocity dX/dt, a flap turned about its hinge; with active absorption the
 * correction's displacement and velocity added). */
void sph_paddle_move(const sph_paddle *p, sph_particles *P, long n, double t);

/* Active absorption after a step of dt that ended at t (a no-op without it): reads the water
 * level in front of the piston among P's first n particles and updates the correction
 * (Schaffer & Klopman 2000's shallow-water absorption, as DualSPHysics' AWAS applies it, with
 * its mean error and displacement relaxed over tau = 10 periods so the paddle does not drift). */
void sph_paddle_absorb(sph_paddle *p, const sph_particles *P, long n, double t, double dt);

/* Particle i of P, when it is one of the paddle's (ids [first, first + np), a wall particle):
 * placed by the law at the displacement X with the rate v (sph_paddle_motion; rest: its table,
 * 2 a particle, by id - first), in the plane x-y (2D) or x-z (3D). The C loop's and a GPU
 * thread's work; M: mixed storage. */
SPH_HD static inline void sph_paddle_particle(const sph_paddle_law *law, const double *rest,
                                              long first, long np, sph_particles *P, int M, long i,
                                              double X, double v)
{
    const long q = P->id[i] - first;
    if (q < 0 || q >= np || P->type[i] != SPH_BOUNDARY)
        return;
    double x[2], u[2];
    sph_paddle_place(law, rest[2 * q], rest[2 * q + 1], X, v, x, u);
    P->x[i] = x[0];
    SPH_SET(M, P, vx, i, u[0]);
    if (P->dim == 3) {
        P->z[i] = x[1];
        SPH_SET(M, P, vy, i, 0.0);
        SPH_SET(M, P, vz, i, u[1]);
    } else {
        P->y[i] = x[1];
        SPH_SET(M, P, vy, i, u[1]);
    }
}

/* Fluid particle i of P after a step of dt in a damping zone [from, to] of rate beta: its
 * velocity times sph_damping_factor (the C loop's and a GPU thread's work). */
SPH_HD static inline void sph_damping_particle(sph_particles *P, int M, long i, double dt,
                                               double beta, double from, double to)
{
    if (P->type[i] != SPH_FLUID)
        return;
    const double f = sph_damping_factor(P->x[i], dt, beta, from, to);
    if (f == 1.0)
        return;
    SPH_SET(M, P, vx, i, f * SPH_GET(M, P, vx, i));
    SPH_SET(M, P, vy, i, f * SPH_GET(M, P, vy, i));
    if (P->dim == 3)
        SPH_SET(M, P, vz, i, f * SPH_GET(M, P, vz, i));
}

/* The damping zone of c after a step of dt: every fluid particle's velocity among P's first n
 * times sph_damping_factor. A no-op without one. */
void sph_damping_apply(const sph_config *c, sph_particles *P, long n, double dt);

#endif
