/*
 * The inside of a sph_sim, shared by the core's own files (sph_sim.c, sph_wcsph.c,
 * sph_integrate.c, sph_diag.c). Not installed, not for the server.
 */
#ifndef SPH_SIM_IMPL_H
#define SPH_SIM_IMPL_H

#include "sph_cells.h"
#include "sph_config.h"
#include "sph_kernel.h"
#include "sph_particles.h"
#include "sph_sim.h"

struct sph_sim {
    sph_config cfg;    /* copy of the configuration */
    sph_kernel kernel; /* initialised for h */
    double h;          /* smoothing length [m] */
    double mass;       /* particle mass rho0 dx^dim [kg] (per metre in 2D) */
    sph_particles P;   /* the particles */
    sph_cells cells;   /* the cell list */
    long nactive;      /* particles in cells after the latest sort [-] */
    long nfluid;       /* fluid particles created [-] */
    long nboundary;    /* boundary particles [-] */
    long max_lost;     /* more lost fluid particles than this is a blow-up [-] */
    double t;          /* time [s] */
    long step;         /* steps done [-] */
    double dt;         /* latest time step [s] */
    double amax;       /* largest fluid acceleration of the latest evaluation [m/s^2] */
    double vmax;       /* largest fluid speed at the end of the latest step [m/s] */
    int failed;        /* 1 after a blow-up */
    sph_diag diag;     /* latest diagnostics */
    sph_timing timing; /* cumulative timers */
    long nbins;        /* histogram bins of the front and height probes [-] */
    int *bin_count;    /* particles per bin [-] */
    double *bin_max;   /* largest coordinate in each bin [m] */
};

/* The equation of state: pressure [Pa] at density rho [kg/m^3]. */
static inline double sph_eos(const sph_config *c, double rho)
{
    if (c->eos == SPH_EOS_TAIT) {
        const double q = rho / c->rho0, q2 = q * q;
        return c->c0 * c->c0 * c->rho0 / 7.0 * (q2 * q2 * q2 * q - 1.0); /* Tait, gamma = 7 */
    }
    return c->c0 * c->c0 * (rho - c->rho0); /* Yang et al. 2014, eq. (16) */
}

/* sph_wcsph.c: sorts the particles by cell, computes p, then the accelerations (gravity
 * included, zero for boundary particles) and density rates into P.ax, P.ay, P.drho. */
/* sph_sim.c: the checks sph_sim_create makes of a configuration. */
int sph_sim_check_config(const sph_config *c, sph_error *err);

void sph_wcsph_forces(sph_sim *s);

/* sph_integrate.c: one time step of at most dt_cap; returns 0 or SPH_ERR_UNSTABLE. */
int sph_integrate_step(sph_sim *s, double dt_cap, sph_error *err);
/* The adaptive (or fixed) time step for the current state [s]. */
double sph_integrate_dt(const sph_sim *s);

/* sph_diag.c: fills s->diag from the current state. */
void sph_diag_compute(sph_sim *s);

#endif
