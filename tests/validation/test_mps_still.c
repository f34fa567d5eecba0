/*
 * MPS still water (issue 12): a tank of water H deep at rest, both MPS kernels. After 2 s the
 * largest speed must be below 1% of sqrt(g H) and the mean pressure of the bottom fluid row
 * within 5% of rho0 g H (the row's centres are dx/2 above the floor: rho0 g (H - dx/2) is what
 * it should hold; the tolerance is against rho0 g H, so both are printed and the
 * hydrostatic value of the row is also held to 5%).
 *
 * Usage: test_mps_still [DX] (default 0.01 m: 20 x 40 particles, seconds). Built only with
 * -DSPH_EXPERIMENTAL_MPS=ON.
 *
 * State (issue 12, first session): FAILS. The interior settles (bottom pressure within 2% of
 * hydrostatic), but free-surface particles next to the side walls keep moving: vmax after 2 s
 * is 0.11-0.4 m/s (8-29% of sqrt(gH)) over the options tried (both kernels, re 2.1 and 3.1,
 * number-density or mixed source, relax 0.01-1, corrected gradient, collision 0.5 dx, dt 1e-3).
 */
#include "sph_sim.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

static int run(sph_kernel_type type, double dx)
{
    const double H = 0.2, W = 0.4, g = 9.81;
    sph_config c = sph_config_default();
    c.method = SPH_METHOD_MPS;
    c.kernel = sph_kernel_spec_default(type);
    c.dx = dx;
    c.domain = (sph_box){{-0.1, -0.1, 0}, {W + 0.1, 0.5, 0}};
    c.nfluid = 1;
    c.fluid[0] = (sph_box){{0, 0, 0}, {W, H, 0}};
    c.boundary = SPH_BOUNDARY_DYNAMIC;
    c.layers = 4;
    c.has_tank = 1;
    c.tank = (sph_box){{0, 0, 0}, {W, 0.4, 0}};
    c.visc = SPH_VISC_LAMINAR;
    c.nu = 1e-6;
    c.t_end = 2.0;
    c.cfl = 0.2;
    if (type == SPH_KERNEL_SHEU_QUARTIC) /* Sheu et al.: re = 2h, h the spacing */
        c.mps.re = c.mps.re_grad = 2.0;
    sph_error err;
    sph_sim *s = sph_sim_create(&c, &err);
    if (!s) {
        fprintf(stderr, "create: %s: %s\n", err.path, err.message);
        return 1;
    }
    while (sph_sim_time(s) < c.t_end)
        if (sph_sim_advance(s, 1000, c.t_end, &err)) {
            fprintf(stderr, "%s: %s\n", sph_kernel_type_name(type), err.message);
            sph_sim_destroy(s);
            return 1;
        }
    const sph_diag *d = sph_sim_diag(s);
    sph_particle_view v;
    sph_sim_particles(s, &v);
    double psum = 0.0;
    long nrow = 0;
    for (long i = 0; i < v.n; i++)
        if (v.type[i] == 0 && v.pos[1][i] < dx) {
            psum += v.p[i];
            nrow++;
        }
    const double pb = psum / nrow, pH = c.rho0 * g * H, prow = c.rho0 * g * (H - 0.5 * dx);
    const double vref = sqrt(g * H);
    const int ok = d->vmax < 0.01 * vref && fabs(pb / pH - 1) < 0.05 && fabs(pb / prow - 1) < 0.05;
    printf("mps still water %-12s dx %g: t %.3f s, %ld steps, vmax %.3e m/s = %.2f%% of sqrt(gH) "
           "(limit 1%%); bottom row (%ld) mean p %.1f Pa: %+.2f%% of rho0 g H, %+.2f%% of "
           "rho0 g (H - dx/2) (limit 5%%); CG %ld iterations, free surface %ld: %s\n",
           sph_kernel_type_name(type), dx, d->t, d->step, d->vmax, 100 * d->vmax / vref, nrow, pb,
           100 * (pb / pH - 1), 100 * (pb / prow - 1), d->cg_iterations, d->free_surface,
           ok ? "ok" : "FAILED");
    sph_sim_destroy(s);
    return !ok;
}

int main(int argc, char **argv)
{
    const double dx = argc > 1 ? atof(argv[1]) : 0.01;
    int rc = run(SPH_KERNEL_KOSHIZUKA, dx);
    rc |= run(SPH_KERNEL_SHEU_QUARTIC, dx);
    return rc;
}
