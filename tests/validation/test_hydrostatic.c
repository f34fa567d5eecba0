/*
 * Hydrostatic tank (cases/hydrostatic.json): water H = 0.2 m deep at rest in a closed tank for
 * 1 s. Passes when, at the end, the largest fluid speed is below 1% of sqrt(g H) and the mean
 * pressure of the bottom layer of fluid particles is within 3% of rho0 g H.
 * Usage: test_hydrostatic SOURCE_DIR
 */
#include "sph_case.h"
#include "sph_sim.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#define SPEED_BOUND    0.01 /* of sqrt(g H) */
#define PRESSURE_BOUND 0.03 /* relative to rho0 g H */

int main(int argc, char **argv)
{
    char file[4096];
    snprintf(file, sizeof file, "%s/cases/hydrostatic.json", argc > 1 ? argv[1] : ".");
    sph_error err;
    json_t *root;
    sph_case *c = calloc(1, sizeof *c);
    if (!c || sph_case_load(file, &root, &err) || sph_case_from_json(root, c, &err)) {
        fprintf(stderr, "FAIL: %s: %s\n", file, err.message);
        return 1;
    }
    json_decref(root);
    const sph_config *cfg = &c->sim;
    sph_sim *s = sph_sim_create(cfg, &err);
    if (!s) {
        fprintf(stderr, "FAIL: %s\n", err.message);
        return 1;
    }
    while (sph_sim_time(s) < cfg->t_end)
        if (sph_sim_advance(s, 1000, cfg->t_end, &err)) {
            fprintf(stderr, "FAIL: %s\n", err.message);
            return 1;
        }
    const double H = cfg->fluid[0].max[1] - cfg->fluid[0].min[1];
    const double g = -cfg->gravity[1];
    const sph_diag *d = sph_sim_diag(s);
    sph_particle_view v;
    sph_sim_particles(s, &v);
    double psum = 0.0;
    long np = 0;
    for (long i = 0; i < v.n; i++)
        if (v.type[i] == 0 && v.pos[1][i] < cfg->fluid[0].min[1] + cfg->dx) {
            psum += v.p[i];
            np++;
        }
    const double pmean = psum / (double)np, pref = cfg->rho0 * g * H;
    const double speed = d->vmax / sqrt(g * H);
    const double perr = fabs(pmean - pref) / pref;
    printf("hydrostatic: t = %g s, %ld steps, vmax = %.3g m/s = %.3g%% of sqrt(gH) (bound %g%%)\n",
           d->t, d->step, d->vmax, 100.0 * speed, 100.0 * SPEED_BOUND);
    printf("hydrostatic: bottom layer (%ld particles): mean p = %.1f Pa, rho0 g H = %.1f Pa, "
           "difference %.2f%% (bound %g%%)\n",
           np, pmean, pref, 100.0 * perr, 100.0 * PRESSURE_BOUND);
    int ok = np > 0 && speed < SPEED_BOUND && perr < PRESSURE_BOUND;
    printf("%s\n", ok ? "PASS" : "FAIL");
    sph_sim_destroy(s);
    free(c);
    return ok ? 0 : 1;
}
