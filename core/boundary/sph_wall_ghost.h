/*
 * sph_wall_ghost: free-slip walls made of ghost (mirror) particles, for the straight walls of an
 * axis-aligned tank (Colagrossi & Landrini 2003, section 2.3; Macia et al. section IV-C, their
 * ref. [9]). Dimension-generic: the walls are the planes at the tank's min and max along every
 * horizontal axis and at its min along the vertical (last) axis; the top is open.
 *
 * For every force evaluation each fluid particle closer than one kernel support to a wall is
 * mirrored across it, and across both walls of a corner (the double mirror) when it is that close
 * to both. A ghost has
 *   - the mirrored position,
 *   - the mirrored velocity for free slip: the normal component reversed, the tangential kept,
 *   - the pressure that keeps still water in equilibrium, p_g = p_f + rho0 g.(x_g - x_f)
 *     (Colagrossi & Landrini 2003, eq. (27)), and the density of that pressure by the EOS,
 *   - the fluid particle's mass and id.
 * Ghosts are appended after the real particles as SPH_GHOST; the pair loops treat them as fluid
 * neighbours (continuity, pressure, viscosity, delta-SPH) and discard what they receive; they
 * are removed again after the evaluation (sph_particles_remove): never integrated, never in
 * outputs or diagnostics. They carry no SPS stress.
 *
 * The ghosts' own pressure gradient keeps fluid out of the walls, but the Wendland kernel's
 * gradient vanishes at zero distance, so a fast particle can still cross a wall within a step:
 * sph_wall_ghost_reflect() puts it back (a specular reflection, which is what free slip means
 * for one particle), called by the integrator after each position update.
 */
#ifndef SPH_WALL_GHOST_H
#define SPH_WALL_GHOST_H

#include "sph_hd.h"
#include "sph_config.h"
#include "sph_error.h"

#define SPH_GHOST_MAX_WALLS 6

/* One straight wall: the plane x[axis] = pos, with the fluid on the side of `dir`. */
typedef struct sph_ghost_plane {
    int axis;   /* normal axis: 0 x, 1 y, 2 z */
    double pos; /* the plane's coordinate [m] */
    int dir;    /* +1: fluid at larger coordinates (a min wall), -1: at smaller (a max wall) */
} sph_ghost_plane;

typedef struct sph_wall_ghost {
    int dim;                                   /* 2 or 3 */
    int nwalls;                                /* planes in wall[] */
    sph_ghost_plane wall[SPH_GHOST_MAX_WALLS]; /* left, right, (front, back,) bottom */
    double band;                               /* fluid nearer than this is mirrored [m] */
    double rho0g[3];                           /* rho0 times gravity [Pa/m] */
} sph_wall_ghost;

/* What a build reads (real particles [0, n)) and writes (ghosts from n on). */
typedef struct sph_ghost_arrays {
    double *pos[3];      /* position components [m] */
    double *vel[3];      /* velocity components [m/s] */
    double *rho;         /* density [kg/m^3] */
    unsigned char *type; /* SPH_FLUID ... SPH_GHOST */
    int *id;             /* creation index; a ghost has its fluid particle's */
    float *vel32[3];     /* mixed precision: the velocity in float (vel NULL) */
    float *rho32;        /* mixed precision: the density in float (rho NULL) */
    int mixed;           /* 1: vel32 and rho32 instead of vel and rho */
} sph_ghost_arrays;

/* The walls of c's tank, mirrored within `support` [m]. Fails with SPH_ERR_INVALID at the JSON
 * path of the case field when c has no tank (/boundary/tank), a tank whose max does not exceed
 * its min, gravity with a horizontal component (/physics/gravity: the tank's top must be open)
 * or a fluid box outside the tank (/fluid/i/box). */
int sph_wall_ghost_init(sph_wall_ghost *w, const sph_config *c, double support, sph_error *err);

/* Widens [lo, hi] (dim components) to hold every ghost: the tank grown by the band. */
void sph_wall_ghost_bounds(const sph_wall_ghost *w, double *lo, double *hi);

/* Appends the ghosts of the fluid particles among [0, n) at [n, cap) and returns how many the
 * walls need; when that is more than cap - n the caller makes room and builds again. Runs in
 * parallel; the ghosts come in the particles' order, so runs stay the same with any number of
 * threads.
 * c gives the EOS. */
long sph_wall_ghost_build(const sph_wall_ghost *w, const sph_config *c, const sph_ghost_arrays *a,
                          long n, long cap);

/* Puts a particle that crossed a wall back: its position mirrored into the tank and its normal
 * velocity turned inwards. x and v have w->dim components. */
SPH_HD static inline void sph_wall_ghost_reflect(const sph_wall_ghost *w, double *x, double *v)
{
    for (int k = 0; k < w->nwalls; k++) {
        const sph_ghost_plane *p = &w->wall[k];
        const double d = (x[p->axis] - p->pos) * p->dir;
        if (d < 0.0) {
            x[p->axis] = p->pos - d * p->dir;
            if (v[p->axis] * p->dir < 0.0)
                v[p->axis] = -v[p->axis];
        }
    }
}

#endif
