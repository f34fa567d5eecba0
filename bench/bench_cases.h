/*
 * bench_cases: cases the benchmarks share (bench_dambreak). Header-only.
 */
#ifndef BENCH_CASES_H
#define BENCH_CASES_H

#include "sph_sim.h"

#include <math.h>

/* The dam break of Yang et al. 2014 (section 4.1) at about nfluid fluid particles: water 0.1 x
 * 0.2 m in a 1.0 x 0.6 m tank; Wendland C2, h = 1.414 dx, artificial viscosity 0.01, linear EOS
 * with c0 = 25 m/s, 3 layers of dynamic walls (ghost: free-slip ghost walls), CFL 0.2. */
static inline sph_config dambreak(long nfluid, int ghost)
{
    sph_config c = sph_config_default();
    c.dx = sqrt(0.1 * 0.2 / (double)nfluid);
    c.kernel = sph_kernel_spec_default(SPH_KERNEL_WENDLAND_C2);
    c.h_over_dx = 1.414;
    c.domain = (sph_box){{0, 0, 0}, {1.0, 0.6, 0}};
    c.nfluid = 1;
    c.fluid[0] = (sph_box){{0, 0, 0}, {0.1, 0.2, 0}};
    c.boundary = ghost ? SPH_BOUNDARY_GHOST : SPH_BOUNDARY_DYNAMIC;
    c.layers = 3;
    c.has_tank = 1;
    c.tank = (sph_box){{0, 0, 0}, {1.0, 0.6, 0}};
    c.eos = SPH_EOS_LINEAR;
    c.c0 = 25.0;
    c.visc = SPH_VISC_ARTIFICIAL;
    c.alpha = 0.01;
    c.cfl = 0.2;
    c.t_end = 1.0;
    return c;
}

/* SPHERIC Test 2 (cases/dambreak3d.json, Kleefsman et al. 2005) at spacing dx: tank 3.22 x 1 x 1 m
 * (open roof), water 1.228 x 1 x 0.55 m against the far wall, the box obstacle; Wendland C2,
 * h = 1.414 dx, artificial viscosity 0.01, delta-SPH 0.1 in Fourtakas et al.'s form, c0 = 35 m/s,
 * 3 layers of dynamic walls, as the case (alpha 0.1 and Molteni's form before 2026-11-28, when the
 * case had changed to these: the same pairs, 3 more products in each delta-SPH pair). */
static inline sph_config test2(double dx)
{
    sph_config c = sph_config_default();
    c.dim = 3;
    c.dx = dx;
    c.kernel = sph_kernel_spec_default(SPH_KERNEL_WENDLAND_C2);
    c.h_over_dx = 1.414;
    c.domain = (sph_box){{0, 0, 0}, {3.22, 1.0, 1.5}};
    c.nfluid = 1;
    c.fluid[0] = (sph_box){{1.992, 0, 0}, {3.22, 1.0, 0.55}};
    c.boundary = SPH_BOUNDARY_DYNAMIC;
    c.layers = 3;
    c.wall_viscosity = 0.0;
    c.has_tank = 1;
    c.tank = (sph_box){{0, 0, 0}, {3.22, 1.0, 1.0}};
    c.nobstacles = 1;
    c.obstacles[0] = (sph_box){{0.6635, 0.295, 0}, {0.8245, 0.698, 0.161}};
    c.gravity[0] = c.gravity[1] = 0.0;
    c.gravity[2] = -9.81;
    c.eos = SPH_EOS_LINEAR;
    c.c0 = 35.0;
    c.visc = SPH_VISC_ARTIFICIAL;
    c.alpha = 0.01;
    c.delta_sph = 0.1;
    c.delta_form = SPH_DELTA_FOURTAKAS;
    c.cfl = 0.2;
    c.t_end = 6.0;
    return c;
}

/* Test 2's spacing for about `total` particles (fluid and walls), by bisection on the counts. */
static inline double test2_dx(double total)
{
    double lo = 1e-3, hi = 0.2;
    for (int k = 0; k < 60; k++) {
        const double mid = sqrt(lo * hi);
        sph_config c = test2(mid);
        long nf = 0, nb = 0;
        sph_sim_estimate_bytes(&c, &nf, &nb);
        if ((double)(nf + nb) > total)
            lo = mid;
        else
            hi = mid;
    }
    return hi;
}

#endif
