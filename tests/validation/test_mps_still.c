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
 * Settings: mixed source (Tanaka & Masunaga) with relax 0.005, corrected gradient (without the
 * local minimum), dt = 0.1 dx / sqrt(2 g H) (the method's CFL limit with cfl 0.1), nu = 1e-6.
 *
 * State (issue 12, second session): still FAILS, for other reasons than in the first.
 *   First session (walls as unknowns of the pressure equation): vmax after 2 s 0.11-0.4 m/s
 *   (8-29% of sqrt(gH)) over every option tried: the fluid column next to each side wall slid
 *   down (the wall pressures were off hydrostatic at the floor corners and above the contact
 *   line) and drove a circulation that never settled.
 *   Walls as a Neumann boundary (sph_mps.c) cure that: after 60 steps vmax 1.7 mm/s instead of
 *   50 mm/s, the bottom row at hydrostatic pressure to 0.1%. Figures after 2 s:
 *     dx 0.01:  koshizuka vmax 0.5 mm/s (0.04%), sheu_quartic 1.6 mm/s (0.12%): speed passes;
 *               bottom row -5.4% of rho0 g H (-2.9% of rho0 g (H - dx/2)): fails by 0.4%. The
 *               free-surface condition p = 0 sits at the centres of the top row, dx/2 below the
 *               water line, so p_bottom = rho0 g (H - dx) = -5% at this resolution by
 *               construction.
 *     dx 0.005: sheu_quartic vmax 0.6 mm/s (0.04%), bottom -2.6%: passes; koshizuka grows
 *               from 1 s on at the contact line (x = 0.016 m, y = 0.187 m: 2% at 1.5 s) and
 *               blows up at 1.74 s.
 *   What is left: a slowly growing mode at the contact line / free surface (a checkerboard of
 *   the pressure in the rows below the surface, invisible to the (p_j - p_i) gradient), worst
 *   with the koshizuka weight; it grows faster with a smaller dt and a larger relax (relax 1 and
 *   0.2 blow up within 0.3-0.7 s, 0.05 at 1.5 s, 0.01 grows at dx 0.01, 0.005 holds 2 s at
 *   dx 0.01 but not at 0.005). The local minimum with the corrective matrix drives a row-sliding
 *   mode instead; a split of the source (number density moving positions only) and particle
 *   shifting (Lind et al. 2012, tangential at the surface) made it worse.
 */
#include "sph_sim.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Mean pressure of the bottom fluid row (centres below dx) and its size. */
static double bottom_pressure_n(sph_sim *s, double dx, long *nrow)
{
    sph_particle_view v;
    sph_sim_particles(s, &v);
    double psum = 0.0;
    long n = 0;
    for (long i = 0; i < v.n; i++)
        if (v.type[i] == 0 && v.pos[1][i] < dx) {
            psum += v.p[i];
            n++;
        }
    *nrow = n;
    return n ? psum / n : 0.0;
}

static double bottom_pressure(sph_sim *s, double dx)
{
    long n;
    return bottom_pressure_n(s, dx, &n);
}

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
    c.cfl = 0.1;      /* dt = 0.1 dx / sqrt(2 g H) */
    c.mps.source = 1; /* mixed (Tanaka & Masunaga 2010) */
    c.mps.relax = 0.005;
    c.mps.corrected = 1;
    if (type == SPH_KERNEL_SHEU_QUARTIC) /* Sheu et al.: re = 2h, h the spacing */
        c.mps.re = c.mps.re_grad = 2.0;
    sph_error err;
    sph_sim *s = sph_sim_create(&c, &err);
    if (!s) {
        fprintf(stderr, "create: %s: %s\n", err.path, err.message);
        return 1;
    }
    const double pH = c.rho0 * g * H, prow = c.rho0 * g * (H - 0.5 * dx), vref = sqrt(g * H);
    for (int q = 1; q <= 4; q++) { /* figures at 0.5, 1, 1.5 and 2 s */
        const double tq = 0.25 * q * c.t_end;
        while (sph_sim_time(s) < tq)
            if (sph_sim_advance(s, 1000, tq, &err)) {
                fprintf(stderr, "%s dx %g: %s\n", sph_kernel_type_name(type), dx, err.message);
                sph_sim_destroy(s);
                return 1;
            }
        if (q < 4) {
            const sph_diag *d = sph_sim_diag(s);
            printf("  %-12s dx %g t %.2f s: vmax %.3f%% of sqrt(gH), bottom row %+.2f%% of "
                   "rho0 g H\n",
                   sph_kernel_type_name(type), dx, d->t, 100 * d->vmax / vref,
                   100 * (bottom_pressure(s, dx) / pH - 1));
            fflush(stdout);
        }
    }
    const sph_diag *d = sph_sim_diag(s);
    long nrow = 0;
    const double pb = bottom_pressure_n(s, dx, &nrow);
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
    const char *only = argc > 2 ? argv[2] : NULL; /* a kernel's name: that kernel only */
    int rc = 0;
    if (!only || strcmp(only, "koshizuka") == 0)
        rc |= run(SPH_KERNEL_KOSHIZUKA, dx);
    if (!only || strcmp(only, "sheu_quartic") == 0)
        rc |= run(SPH_KERNEL_SHEU_QUARTIC, dx);
    return rc;
}
