/*
 * The inside of a sph_sim, shared by the handle (sph_sim.c, sph_diag.c, sph_checkpoint.c) and
 * the methods' files (wcsph/, ...). Not installed, not for the server.
 */
#ifndef SPH_SIM_IMPL_H
#define SPH_SIM_IMPL_H

#include "sph_body.h"
#include "sph_cells.h"
#include "sph_config.h"
#include "sph_envelope.h"
#include "sph_eos.h"
#include "sph_initial.h"
#include "sph_kernel.h"
#include "sph_method.h"
#include "sph_particles.h"
#include "sph_sim.h"
#include "sph_wall_ghost.h"
#include "sph_wavemaker.h"

/* The particle storage options of a configuration (sph_particles_alloc). */
static inline unsigned sph_sim_particle_opts(const sph_config *c)
{
    return (c->turb == SPH_TURB_SPS ? SPH_PARTICLES_SPS : 0) |
           (c->precision == SPH_PRECISION_MIXED ? SPH_PARTICLES_MIXED : 0) |
           (c->method == SPH_METHOD_MPS ? SPH_PARTICLES_PRESSURE : 0);
}

/* A neighbour list reused over steps (the case's neighbours.skin; wcsph/sph_wcsph.c): each
 * particle's half-stencil candidates within the support and its skin, in the order the strip
 * loops visit them, from the particles' order and cells at the latest build (the particles keep
 * that order until the next). */
typedef struct sph_nlist {
    long *off;      /* n + 1 offsets: particle i's candidates, of column (2D) or x slab (3D) cx,
                       are cb[cx][off[i] - ca[cx] .. off[i + 1] - ca[cx]) */
    const int **cb; /* each column's candidates, where its thread built them (tb) */
    long *ca;       /* each column's first offset */
    int ncol;       /* columns cb and ca hold [-] */
    long off_cap;   /* particles off can hold [-] */
    double moved;   /* a bound on any particle's displacement since the build [m] */
    int built;      /* 1 while the list holds; 0: built at the next force evaluation */
    struct sph_nlist_buf {
        int *b;
        long len, cap;
    } * tb;  /* the threads' candidates: the list itself, by column (cb), kept for the next
                build */
    int ntb; /* threads tb holds [-] */
} sph_nlist;

struct sph_sim {
    sph_config cfg;            /* copy of the configuration */
    const sph_method_ops *ops; /* the method's table */
    void *mstate;              /* the method's own state (its destroy frees it) */
    sph_kernel kernel;         /* initialised for h */
    double h;                  /* smoothing length [m] */
    double mass;               /* particle mass rho0 dx^dim [kg] (per metre in 2D) */
    sph_particles P;           /* the particles */
    sph_cells cells;           /* the cell list */
    sph_nlist nlist;           /* a neighbour list reused over steps (WCSPH, neighbours.skin) */
    long nactive;              /* particles in cells after the latest sort [-] */
    long nfluid;               /* fluid particles created [-] */
    long nboundary;            /* boundary particles [-] */
    sph_bodies bodies;         /* rigid bodies (their particles follow the walls') */
    sph_paddle paddle;    /* a wavemaker's paddle (np 0 without one): the last wall particles */
    sph_wall_ghost ghost; /* the free-slip walls, with boundary == SPH_BOUNDARY_GHOST */
    double *shift;        /* particle shifting's displacements of the latest step, dim per
                             particle (sph_wcsph.c; NULL without shifting) [m] */
    long shift_cap;       /* particles shift can hold [-] */
    double *mirror;       /* mDBC's ghost nodes of the wall particles of a case with geometry
                             walls (sph_fill_has_mirrors): dim coordinates per wall particle,
                             by its id - mirror_first, so that no sort moves them; NULL: the
                             built-in boxes' rule (sph_shapes_wall_mirror) [m] */
    long mirror_first;    /* the first wall particle's id [-] */
    long nmirror;         /* wall particles in the table [-] */
    long nghost;          /* ghosts of the latest force evaluation [-] */
    long max_lost;        /* more lost fluid particles than this is a blow-up [-] */
    double t;             /* time [s] */
    long step;            /* steps done [-] */
    double dt;            /* latest time step [s] */
    double amax;          /* largest fluid acceleration of the latest evaluation [m/s^2] */
    double vmax;          /* largest fluid or body speed at the end of the latest step [m/s] */
    int failed;           /* 1 after a blow-up */
    sph_diag diag;        /* latest diagnostics */
    sph_timing timing;    /* cumulative timers */
    long nbins;           /* histogram bins of the front and height probes [-] */
    int *bin_count;       /* particles per bin [-] */
    double *bin_max;      /* largest coordinate in each bin [m] */
    int has_theory;       /* 1 when the initial field has a theory to compare with */
    sph_initial_theory theory; /* what it says (period, decay rate, initial energy) */
    sph_envelope wave;         /* the kinetic-energy peaks, sampled every step */
};

/* For a method's step, after s->t and s->step have moved: more than max_lost fluid particles
 * lost is a blow-up (SPH_ERR_UNSTABLE with err); 0 otherwise. */
static inline int sph_sim_check_lost(const sph_sim *s, long lost, sph_error *err)
{
    if (lost <= s->max_lost)
        return 0;
    return sph_error_set(err, SPH_ERR_UNSTABLE, "",
                         "blow-up at step %ld (t = %g s): %ld fluid particles left the domain "
                         "(more than %ld allowed)",
                         s->step, s->t, lost, s->max_lost);
}

/* sph_diag.c: fills s->diag from the current state. */
void sph_diag_compute(sph_sim *s);

#endif
