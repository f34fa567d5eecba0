/*
 * The WCSPH method's private interface (core/wcsph/ only): the pair loops (sph_wcsph.c) and the
 * integrator and table row (sph_wcsph_step.c).
 */
#ifndef SPH_WCSPH_H
#define SPH_WCSPH_H

#include "sph_sim_impl.h"

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
void sph_wcsph_forces(sph_sim *s);

/* sph_wcsph_step.c: the method's row of the table. */
extern const sph_method_ops sph_wcsph_ops;

#endif
