/*
 * Still water in a ghost-walled tank (issue 10): water H = 0.2 m deep at rest in a tank 0.4 m
 * wide with free-slip ghost walls, Wendland C2 with h = 2 dx, H/dx = 40, for 2 s. Passes when,
 * at the end,
 *   - the largest fluid speed is below 1% of sqrt(g H), and
 *   - the pressure at the bottom, the mean pressure of the layer of fluid particles nearest the
 *     bottom (y < dx), is within 2% of rho0 g H.
 * Printed beside it: the least-squares line p(y) through the particles deeper than a kernel
 * support below the surface, its value at y = 0 and its slope (-rho0 g). The line is not the
 * criterion: it hardly feels the wall (without the hydrostatic term in the ghosts' pressure the
 * bottom layer is 5% too high, the line's value at y = 0 still within 1.1%).
 * Usage: test_ghost_still [END_TIME]
 */
#include "sph_sim.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#define SPEED_BOUND    0.01 /* of sqrt(g H) */
#define PRESSURE_BOUND 0.02 /* relative to rho0 g H */

int main(int argc, char **argv)
{
    const double H = 0.2, L = 0.4, dx = 0.005;
    sph_config c = sph_config_default();
    c.kernel = sph_kernel_spec_default(SPH_KERNEL_WENDLAND_C2);
    c.h_over_dx = 2.0;
    c.dx = dx;
    c.domain = (sph_box){{0, 0, 0}, {L, 0.3, 0}};
    c.nfluid = 1;
    c.fluid[0] = (sph_box){{0, 0, 0}, {L, H, 0}};
    c.boundary = SPH_BOUNDARY_GHOST;
    c.has_tank = 1;
    c.tank = (sph_box){{0, 0, 0}, {L, 0.3, 0}};
    c.c0 = 20.0;
    c.visc = SPH_VISC_ARTIFICIAL;
    c.alpha = 0.1;
    c.t_end = argc > 1 ? atof(argv[1]) : 2.0;
    sph_error err;
    sph_sim *s = sph_sim_create(&c, &err);
    if (!s) {
        fprintf(stderr, "FAIL: %s (%s)\n", err.message, err.path);
        return 1;
    }
    while (sph_sim_time(s) < c.t_end)
        if (sph_sim_advance(s, 1000, c.t_end, &err)) {
            fprintf(stderr, "FAIL: %s\n", err.message);
            return 1;
        }
    const double g = -c.gravity[1], support = 2.0 * c.h_over_dx * dx;
    const sph_diag *d = sph_sim_diag(s);
    sph_particle_view v;
    sph_sim_particles(s, &v);
    double sy = 0, sp = 0, syy = 0, syp = 0, bsum = 0;
    long n = 0, nb = 0;
    for (long i = 0; i < v.n; i++) {
        if (v.type[i] != 0)
            continue;
        const double y = v.pos[1][i], p = v.p[i];
        if (y < dx) {
            bsum += p;
            nb++;
        }
        if (y > H - support)
            continue;
        sy += y;
        sp += p;
        syy += y * y;
        syp += y * p;
        n++;
    }
    const double slope = (n * syp - sy * sp) / (n * syy - sy * sy);
    const double p0 = (sp - slope * sy) / n, pref = c.rho0 * g * H, pb = bsum / nb;
    const double speed = d->vmax / sqrt(g * H), perr = fabs(pb - pref) / pref;
    printf("ghost still water: t = %g s, %ld steps, %ld particles, vmax = %.3g m/s = %.3g%% of "
           "sqrt(gH) (bound %g%%)\n",
           d->t, d->step, d->nfluid, d->vmax, 100.0 * speed, 100.0 * SPEED_BOUND);
    printf("ghost still water: pressure at the bottom (mean of the %ld particles at y < dx) %.1f "
           "Pa, rho0 g H = %.1f Pa, difference %.2f%% (bound %g%%)\n",
           nb, pb, pref, 100.0 * perr, 100.0 * PRESSURE_BOUND);
    printf("ghost still water: least-squares line over %ld particles: %.1f Pa at y = 0, slope %.1f "
           "Pa/m (-rho0 g = %.1f)\n",
           n, p0, slope, -c.rho0 * g);
    const int ok = nb > 0 && speed < SPEED_BOUND && perr < PRESSURE_BOUND && d->lost == 0;
    printf("%s\n", ok ? "PASS" : "FAIL");
    sph_sim_destroy(s);
    return ok ? 0 : 1;
}
