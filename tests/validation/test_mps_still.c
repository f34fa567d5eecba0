/*
 * MPS still water (issue 12): a tank of water H deep at rest, both MPS kernels. After 2 s the
 * largest speed must be below 1% of sqrt(g H) and the mean pressure of the bottom fluid row
 * within 5% of rho0 g H (the row's centres are dx/2 above the floor: rho0 g (H - dx/2) is what
 * it should hold; the tolerance is against rho0 g H, so both are printed and the
 * hydrostatic value of the row is also held to 5%).
 *
 * Usage: test_mps_still [DX [KERNEL [SURFACE]]] (default 0.01 m: 20 x 40 particles, seconds;
 * KERNEL koshizuka or sheu_quartic for one only; SURFACE the mps.surface condition). Prints the
 * figures at 0.5, 1 and 1.5 s too. Built only with -DSPH_EXPERIMENTAL_MPS=ON.
 *
 * Settings: mixed source (Tanaka & Masunaga) with relax 0.005, corrected gradient (without the
 * local minimum), dt = 0.1 dx / sqrt(2 g H) (the method's CFL limit with cfl 0.1), nu = 1e-6.
 *
 * State (issue 12, third session): passes at dx 0.01 with sheu_quartic and at dx 0.005 with both
 * kernels; koshizuka at dx 0.01 misses the bottom-row bound by 0.02% (the p = 0 placement below).
 * Not yet a ctest. Figures after 2 s (vmax in % of sqrt(gH), bottom row in % of rho0 g H):
 *
 *                         koshizuka 0.01  sheu 0.01     koshizuka 0.005     sheu 0.005
 *   before (2nd session)  0.04   -5.02    0.12  -4.93   blow-up at 1.74 s   0.04  -2.59
 *   walls: normal only    0.01   -5.02    0.01  -4.96   0.25  -3.74         0.002 -2.58
 *   + mps.surface = 1     0.04   -2.55    0.05  -2.49   34 (grows > 1.5 s)  0.08  -1.34
 *
 * (1) What drove the growing mode at the contact line: the Neumann walls' ghost gradient was
 *   (rho/dt) u* in every direction, so a wall also "stopped" the tangential motion of the fluid
 *   next to it with a gain rho/dt (hence faster growth with a smaller dt): an odd-even mode of
 *   the columns next to each side wall under the free surface (vx, vy and n* alternating column
 *   by column, spreading from the wall; the free-surface set never flickered before the mode
 *   was large: flicker is its consequence, not its cause). The ghost now holds (rho/dt) u* only
 *   on the wall's normal and the body forces rho (u* - u)/dt along it (Adami, Hu & Adams 2012's
 *   wall pressure; sph_mps_ops.h). vmax fell 4-20x and koshizuka at dx 0.005 no longer blows
 *   up, but the same odd-even mode still grows slowly from the side walls with koshizuka at
 *   dx 0.005 (0.006% at 1 s, 0.026% at 1.5 s, 0.25% at 2 s). Dropping the velocity term
 *   altogether (G = rho g) blows up at once (no-penetration is lost).
 * (2) The -dx/H bias: mps.surface = 1 (sph_config.h; `test_mps_still DX KERNEL 1`) puts p = 0 on
 *   the water line dx/2 above the top row's centres by the ghost-fluid extrapolation of Gibou
 *   et al. 2002 (surface particles become unknowns with a diagonal term from their missing
 *   neighbours, sph_mps.c): the bottom row is then within 0.1% of rho0 g (H - dx/2) at both
 *   resolutions, but the near-wall odd-even mode grows faster with it, and blows koshizuka up
 *   at dx 0.005 after 1.5 s; so the default stays 0 (Koshizuka & Oka). With the one-sided
 *   velocity divergence in the surface rows' source, the surface row itself went odd-even
 *   unstable within 0.2 s: their source is 0.
 * Next: the odd-even column mode next to the side walls (koshizuka, fine resolution). It is
 *   invisible to the interior gradient; candidates not yet tried: the walls' share of the
 *   velocity divergence (now fluid neighbours only), a wall treatment consistent between the
 *   PPE's Laplacian and the gradient/divergence pair, Tsuruta et al. 2013's dynamic
 *   stabilisation, Khayyer & Gotoh's ECS source.
 *
 * Earlier sessions: the first (walls as unknowns of the pressure equation): vmax after 2 s
 *   0.11-0.4 m/s (8-29% of sqrt(gH)) over every option tried: the fluid column next to each side
 *   wall slid down and drove a circulation that never settled. Walls as a Neumann boundary cured
 *   that. The second then found the slowly growing contact-line mode: it grows faster with a
 *   larger relax (relax 1 and 0.2 blow up within 0.3-0.7 s, 0.05 at 1.5 s, 0.01 grows at
 *   dx 0.01); the local minimum with the corrective matrix drives a row-sliding mode instead
 *   (the plain gradient with the local minimum: 34% of sqrt(gH) by 1.6 s at dx 0.005, third
 *   session); a split of the source (number density moving positions only) and particle
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

static int run(sph_kernel_type type, double dx, int surface)
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
    if (surface >= 0)
        c.mps.surface = surface;
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
    const char *only = argc > 2 && strcmp(argv[2], "both") ? argv[2] : NULL; /* one kernel */
    const int surface = argc > 3 ? atoi(argv[3]) : -1;
    int rc = 0;
    if (!only || strcmp(only, "koshizuka") == 0)
        rc |= run(SPH_KERNEL_KOSHIZUKA, dx, surface);
    if (!only || strcmp(only, "sheu_quartic") == 0)
        rc |= run(SPH_KERNEL_SHEU_QUARTIC, dx, surface);
    return rc;
}
