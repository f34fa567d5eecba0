/*
 * Hydrostatic tank: water H deep at rest in a tank with an open top, run to the case's end.
 * Passes when, at the end, the largest fluid speed is below 1% of sqrt(g H) and the mean
 * pressure of the bottom layer of fluid particles is within the bound of rho0 g H.
 *   - cases/hydrostatic.json (2D, the default): H = 0.2 m, 1 s, bound 3%;
 *   - cases/hydrostatic3d.json (3D, issue 23): H = 1 m at dx = H/40 in a tank 0.5 x 0.25 m,
 *     2 s, bound 2%;
 *   - tests/cases/ghost_still3d.json (3D, free-slip ghost walls): H = 0.5 m at dx = H/20 in a
 *     tank 0.25 x 0.25 m, 1 s, bound 2%;
 *   - tests/cases/mdbc_geometry_still3d.json (3D, mDBC walls from the geometry list: the tank a
 *     mesh, its files read from the case's folder): H = 0.5 m at dx = H/20 in a tank 0.2 x
 *     0.2 m, 1 s, bound 2%.
 * The vertical is the last axis (y in 2D, z in 3D).
 * SPH_TEST_DEVICE=gpu runs it on the GPU (exit 77, skipped, when the case is refused there).
 * Usage: test_hydrostatic SOURCE_DIR [CASE [PRESSURE_BOUND]]   (CASE relative to SOURCE_DIR)
 */
#include "sph_case.h"
#include "sph_sim.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define SPEED_BOUND 0.01 /* of sqrt(g H) */

int main(int argc, char **argv)
{
    char file[4096];
    snprintf(file, sizeof file, "%s/%s", argc > 1 ? argv[1] : ".",
             argc > 2 ? argv[2] : "cases/hydrostatic.json");
    const double pressure_bound = argc > 3 ? atof(argv[3]) : 0.03; /* relative to rho0 g H */
    sph_error err;
    json_t *root;
    sph_case *c = calloc(1, sizeof *c);
    char dir[4096];
    snprintf(dir, sizeof dir, "%s", file);
    *strrchr(dir, '/') = '\0'; /* the case's folder: its meshes are named relative to it */
    if (!c || sph_case_load(file, &root, &err) || sph_case_from_json(root, c, &err) ||
        sph_case_load_files(c, dir, NULL, &err)) {
        fprintf(stderr, "FAIL: %s: %s %s\n", file, err.path, err.message);
        return 1;
    }
    json_decref(root);
    const char *device = getenv("SPH_TEST_DEVICE");
    if (device && strcmp(device, "gpu") == 0) {
        c->sim.device = SPH_DEVICE_GPU;
        if (sph_sim_check(&c->sim, &err)) {
            printf("skipped: %s\n", err.message);
            return 77;
        }
    }
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
    const int V = cfg->dim - 1; /* the vertical axis */
    const double H = cfg->fluid[0].max[V] - cfg->fluid[0].min[V];
    const double g = -cfg->gravity[V];
    const sph_diag *d = sph_sim_diag(s);
    sph_particle_view v;
    sph_sim_particles(s, &v);
    double psum = 0.0;
    long np = 0;
    for (long i = 0; i < v.n; i++)
        if (v.type[i] == 0 && v.pos[V][i] < cfg->fluid[0].min[V] + cfg->dx) {
            psum += v.p[i];
            np++;
        }
    const double pmean = psum / (double)np, pref = cfg->rho0 * g * H;
    const double speed = d->vmax / sqrt(g * H);
    const double perr = fabs(pmean - pref) / pref;
    printf("hydrostatic (%dD): t = %g s, %ld steps, vmax = %.3g m/s = %.3g%% of sqrt(gH) (bound "
           "%g%%)\n",
           cfg->dim, d->t, d->step, d->vmax, 100.0 * speed, 100.0 * SPEED_BOUND);
    printf("hydrostatic: bottom layer (%ld particles): mean p = %.1f Pa, rho0 g H = %.1f Pa, "
           "difference %.2f%% (bound %g%%)\n",
           np, pmean, pref, 100.0 * perr, 100.0 * pressure_bound);
    int ok = np > 0 && speed < SPEED_BOUND && perr < pressure_bound;
    printf("%s\n", ok ? "PASS" : "FAIL");
    sph_sim_destroy(s);
    sph_case_clear(c);
    free(c);
    return ok ? 0 : 1;
}
