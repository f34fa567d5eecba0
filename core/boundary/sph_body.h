/*
 * sph_body: rigid bodies made of boundary particles (Yang, Peng & Liu 2014, section 2.3: the
 * particles of a solid "can move as a rigid body but not as separate particles ... the sum of all
 * the reaction forces on the body particles from fluid particles is applied to the whole body").
 *
 * A body is a shape (sph_body_shape.h: a circle of diameter D, or a box of edges w x h) filled
 * with boundary particles at spacing dx (rings for the circle, a lattice for the box), all of it or
 * `layers` layers inside its surface; the outermost particles sit dx/2 inside the surface, as the
 * tank's wall particles sit dx/2 outside its faces. Its mass and moment of inertia are those of
 * the uniform solid shape, analytically, whatever the particles that represent its surface.
 *
 * In the pair loops body particles are boundary particles that move: their pressure is the
 * fluid's around them (sph_body_pressure.c; or, with `pressure` "continuity", their density
 * follows continuity and they carry the EOS pressure), and they interact with fluid, walls and
 * other bodies, but not with the particles of their own body. What a body particle receives from a
 * pair is the opposite of what its partner receives, so the force and torque the fluid puts on a
 * body are exactly what the body takes from the fluid: each force evaluation sums m a over the
 * body's particles (sph_bodies_gather). The body then moves as one (Newton-Euler, 2D: x, y and
 * the angle theta) under gravity and that force, integrated with the method's own scheme; its
 * particles follow rigidly: x_p = X + R(theta) r_p, v_p = V + omega x (x_p - X).
 *
 * A degree of freedom that is not free keeps its initial velocity (a prescribed velocity;
 * zero: fixed). Body particles are identified by their creation id: body particles have ids
 * [first_id, first_id + np), and the tables here are indexed by id - first_id, so nothing
 * follows them through the cell sort.
 *
 * Dimension-generic where cheap: positions and velocities have 3 components; rotation is 2D
 * (one angle) in this version.
 */
#ifndef SPH_BODY_H
#define SPH_BODY_H

#include "sph_body_shape.h"
#include "sph_cells.h"
#include "sph_config.h"
#include "sph_error.h"
#include "sph_kernel.h"
#include "sph_particles.h"

/* The state of one body that lives from one step to the next (what a checkpoint saves). */
typedef struct sph_body_state {
    double x[3];     /* centre of mass [m] */
    double v[3];     /* velocity of the centre of mass [m/s] */
    double theta;    /* angle from the initial orientation's frame [rad] */
    double omega;    /* angular velocity [rad/s] */
    double a[3];     /* acceleration of the latest force evaluation [m/s^2] */
    double alpha;    /* angular acceleration of the latest force evaluation [rad/s^2] */
    double force[3]; /* force of the latest evaluation from fluid and walls [N] (per metre in 2D) */
    double torque;   /* its torque about the centre of mass [N m] (per metre in 2D) */
} sph_body_state;

typedef struct sph_body {
    double mass;    /* [kg] (per metre in 2D) */
    double inertia; /* about the centre of mass [kg m^2] (per metre in 2D) */
    double rmax;    /* farthest particle from the centre [m] */
    unsigned free;  /* SPH_DOF_* mask of the free degrees of freedom */
    int from_fluid; /* its particles' pressure from the fluid (sph_bodies_pressure), or 0 */
    long first, np; /* the body's particles: ids [first, first + np) */
    sph_body_state s;
    double a0[3];  /* within a step: the acceleration before it [m/s^2] */
    double alpha0; /* and the angular one [rad/s^2] */
} sph_body;

typedef struct sph_bodies {
    int n;                             /* bodies */
    int dim;                           /* 2 */
    sph_body b[SPH_CONFIG_MAX_BODIES]; /* the bodies */
    long first;                        /* id of the first body particle */
    long np;                           /* body particles of all bodies */
    double *local;                     /* dim per body particle: offset from its body's centre
                                          in the body's frame (angle 0) [m], by id - first */
    int *owner;                        /* body of each body particle, by id - first */
    double gravity[3];                 /* [m/s^2] */
    double level;                      /* initial still-water level: top of the fluid [m] */
} sph_bodies;

/* Checks the bodies of c (after the shared checks: dx, domain): density or mass (one of them,
 * positive), names (given, distinct), a shape no smaller than 2 dx, inside the domain, not
 * overlapping another body or a tank wall. err->path names the case field (/bodies/i/...). */
int sph_body_check(const sph_config *c, sph_error *err);

/* Builds the bodies of c, their particles getting ids from `first` on. Returns 0 or -1 (out of
 * memory). sph_bodies_free() frees what it allocated. */
int sph_bodies_init(sph_bodies *B, const sph_config *c, long first);
void sph_bodies_free(sph_bodies *B);

/* Writes the body particles into P at indices [first, first + np) (ids the same), positions and
 * velocities from the bodies' state, density hydrostatic under the fluid (as the walls'): the
 * last of the set-up's particles, after sph_fill()'s. */
void sph_bodies_fill(const sph_bodies *B, const sph_config *c, sph_particles *P);

/* Sets the position and velocity of every body particle among P's first n from its body's
 * state. */
void sph_bodies_move(const sph_bodies *B, sph_particles *P, long n);

/* The predictor of the velocity-Verlet scheme (sph_wcsph_step.c): x += dt v + dt^2/2 a,
 * v += dt a (free degrees of freedom; the others move at their prescribed velocity). Returns
 * -1, or the index of a body that would leave `domain` (a blow-up). */
int sph_bodies_predict(sph_bodies *B, double dt, const sph_box *domain);

/* The corrector: v += dt/2 (a(n+1) - a(n)), with a(n) as the predictor saved it. */
void sph_bodies_correct(sph_bodies *B, double dt);

/* Sums the force and torque that the latest pair loop left on the body particles among P's
 * first n (accelerations P.ax, P.ay of particles of mass m) and sets each body's acceleration:
 * force / mass + gravity and torque / inertia on the free degrees of freedom, 0 on the others.
 * Serial, in the particles' order: the same whatever the number of threads. */
void sph_bodies_gather(sph_bodies *B, const sph_particles *P, long n, double m);

/* Sets p / rho^2 of every body particle among P's first n (sorted into the cells g, the fluid's
 * rho current) from the pressure of the fluid around it (Adami et al. 2012;
 * sph_body_pressure.c); p: every particle's EOS pressure of its current density. */
void sph_bodies_pressure(const sph_bodies *B, const sph_config *c, const sph_kernel *k,
                         const sph_cells *g, const double *p, sph_particles *P, long n);

/* The largest speed and acceleration of a body particle [m/s], [m/s^2]. */
double sph_bodies_vmax(const sph_bodies *B);
double sph_bodies_amax(const sph_bodies *B);

/* The depth of body k's lowest point below the initial still-water level [m]. */
double sph_bodies_penetration(const sph_bodies *B, const sph_config *c, int k);

#endif
