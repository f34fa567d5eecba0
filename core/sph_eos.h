/*
 * sph_eos: the equation of state and its inverse, shared by the methods (pressure from density),
 * the initial lattices and the ghost walls (density from a prescribed pressure).
 */
#ifndef SPH_EOS_H
#define SPH_EOS_H

#include "sph_config.h"
#include "sph_hd.h"

#include <math.h>

/* Pressure [Pa] at density rho [kg/m^3]. */
SPH_HD static inline double sph_eos_pressure(const sph_config *c, double rho)
{
    if (c->eos == SPH_EOS_TAIT) {
        const double q = rho / c->rho0, q2 = q * q;
        return c->c0 * c->c0 * c->rho0 / 7.0 * (q2 * q2 * q2 * q - 1.0); /* Tait, gamma = 7 */
    }
    return c->c0 * c->c0 * (rho - c->rho0); /* Yang et al. 2014, eq. (16) */
}

/* Density [kg/m^3] at pressure p [Pa]: the inverse of sph_eos_pressure(). Tait below the
 * pressure of zero density (p < -B) gives 0. */
SPH_HD static inline double sph_eos_density(const sph_config *c, double p)
{
    if (c->eos == SPH_EOS_TAIT) {
        const double B = c->c0 * c->c0 * c->rho0 / 7.0; /* p = B ((rho/rho0)^7 - 1) */
        const double u = 1.0 + p / B;
        return u > 0.0 ? c->rho0 * pow(u, 1.0 / 7.0) : 0.0;
    }
    return c->rho0 + p / (c->c0 * c->c0);
}

#endif
