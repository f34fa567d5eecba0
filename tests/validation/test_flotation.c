/*
 * Flotation (issue 11): a circle of D = 0.1 m released at rest, half submerged, in still water
 * 0.2 m deep in a tank 0.4 m wide, for 2 s.
 *  - density 500 kg/m^3: Archimedes' equilibrium is half submerged (penetration D/2). Passes when
 *    the penetration stays within 0.1 D of D/2 all along and its mean over the last 0.2 s is
 *    within 0.05 D of it;
 *  - density 1500 kg/m^3: passes when the body ends on the bottom (its lowest point within 2 dx of
 *    the tank's floor over the last 0.2 s) and at rest there (speed below 2% of sqrt(g D));
 *  - both: no fluid particle lost, the fluid count unchanged (the body neither swallows nor makes
 *    water).
 * Usage: test_flotation [DX]   (default D/12)
 */
#include "sph_sim.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#define D 0.1

static sph_config flotation(double density, double dx)
{
    sph_config c = sph_config_default();
    c.dx = dx;
    c.domain = (sph_box){{-0.25, -0.05, 0}, {0.25, 0.5, 0}};
    c.has_tank = 1;
    c.tank = (sph_box){{-0.2, 0.0, 0}, {0.2, 0.45, 0}};
    c.nfluid = 1;
    c.fluid[0] = (sph_box){{-0.2, 0.0, 0}, {0.2, 0.2, 0}};
    c.c0 = 20.0;
    c.alpha = 0.05;
    c.delta_sph = 0.1;
    c.t_end = 2.0;
    c.nbodies = 1;
    sph_body_spec *b = &c.bodies[0];
    snprintf(b->name, sizeof b->name, "float");
    b->shape = SPH_SHAPE_CIRCLE;
    b->diameter = D;
    b->density = density;
    b->center[1] = 0.2; /* half submerged */
    b->free = SPH_DOF_ALL;
    return c;
}

/* Runs one case; returns 1 when it passes. */
static int run(double density, double dx)
{
    const sph_config c = flotation(density, dx);
    sph_error err;
    sph_sim *s = sph_sim_create(&c, &err);
    if (!s) {
        fprintf(stderr, "FAIL: %s (at %s)\n", err.message, err.path);
        return 0;
    }
    const long nfluid0 = sph_sim_diag(s)->nfluid;
    double worst = 0.0, tail_sum = 0.0, tail_low = 0.0, tail_speed = 0.0;
    long tail_n = 0;
    const double g = 9.81;
    int ok = 1;
    while (sph_sim_time(s) < c.t_end - 1e-12) {
        if (sph_sim_advance(s, 20, c.t_end, &err)) {
            fprintf(stderr, "FAIL: %s\n", err.message);
            sph_sim_destroy(s);
            return 0;
        }
        const sph_diag *d = sph_sim_diag(s);
        const sph_body_diag *b = &d->body[0];
        worst = fmax(worst, fabs(b->penetration - 0.5 * D));
        if (d->t >= c.t_end - 0.2) {
            tail_sum += b->penetration;
            tail_low = fmax(tail_low, (b->x[1] - 0.5 * D) - c.tank.min[1]);
            tail_speed = fmax(tail_speed, hypot(b->v[0], b->v[1]));
            tail_n++;
        }
        if (d->lost != 0 || d->nfluid != nfluid0) {
            fprintf(stderr, "FAIL: fluid lost (%ld) or created (%ld, was %ld) at t = %g s\n",
                    d->lost, d->nfluid, nfluid0, d->t);
            ok = 0;
            break;
        }
    }
    const sph_diag *d = sph_sim_diag(s);
    printf("flotation, density %g, dx = D/%.0f: %ld fluid particles, %ld steps to t = %g s\n",
           density, D / dx, d->nfluid, d->step, d->t);
    if (density < 1000.0) {
        const double mean = tail_sum / (double)tail_n;
        printf("  penetration: worst distance from D/2 %.4f D (bound 0.1 D); mean over the last "
               "0.2 s %.4f D, %.4f D from D/2 (bound 0.05 D)\n",
               worst / D, mean / D, fabs(mean - 0.5 * D) / D);
        ok = ok && worst < 0.1 * D && fabs(mean - 0.5 * D) < 0.05 * D;
    } else {
        printf("  lowest point above the floor over the last 0.2 s: at most %.4f m = %.2f dx "
               "(bound 2 dx); speed at most %.4f m/s (bound %.4f)\n",
               tail_low, tail_low / dx, tail_speed, 0.02 * sqrt(g * D));
        ok = ok && tail_low < 2.0 * dx && tail_speed < 0.02 * sqrt(g * D);
    }
    printf("  %s\n", ok ? "PASS" : "FAIL");
    sph_sim_destroy(s);
    return ok;
}

int main(int argc, char **argv)
{
    const double dx = argc > 1 ? atof(argv[1]) : D / 12.0;
    const int a = run(500.0, dx);
    const int b = run(1500.0, dx);
    printf("%s\n", a && b ? "PASS" : "FAIL");
    return a && b ? 0 : 1;
}
