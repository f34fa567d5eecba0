/*
 * ctest gpu_solver (built with -DSPH_CUDA=ON; needs a GPU, exits 77, "skipped", without one):
 * the WCSPH step on the GPU against the CPU's.
 *   - the same case on both, 100 steps: every particle (matched by id) within 1e-8 m and 1e-6
 *     m/s, densities within 1e-9 relative (the GPU's gather loop sums in another order than the
 *     CPU's symmetric one; test_wcsph_gather shows the two agree to 2e-15 per evaluation): the 2D
 *     dam break (Wendland C2, delta-SPH, artificial viscosity), the same with laminar viscosity
 *     and SPS, and the 3D Test 2 (dynamic walls, continuity density); wave flumes (issue 45): a
 *     piston with a damping zone, a flap, a solitary wave, the 3D flume (the paddle's particles
 *     placed by the law on both devices, to rounding);
 *   - a GPU run saved at step 50 and restored continues like the run that was not interrupted;
 *     a GPU run's state restores on the CPU (the same arrays) and continues within the tolerance
 *     above of the GPU's own continuation.
 */
#include "sph_case.h"
#include "sph_json.h"
#include "sph_sim.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int failures;

#define CHECK(cond, ...)                                                                           \
    do {                                                                                           \
        if (!(cond)) {                                                                             \
            printf("FAIL: " __VA_ARGS__);                                                          \
            printf("\n");                                                                          \
            failures++;                                                                            \
        }                                                                                          \
    } while (0)

static int load_case(const char *name, const char *const *sets, sph_config *cfg)
{
    char path[4096];
    const char *src = getenv("SPH_SOURCE_DIR");
    snprintf(path, sizeof path, "%s/cases/%s", src ? src : ".", name);
    json_t *root;
    sph_error err;
    if (sph_case_load(path, &root, &err) != 0) {
        printf("FAIL: %s: %s\n", name, err.message);
        return -1;
    }
    for (; *sets; sets++)
        if (sph_json_apply_set(root, *sets, &err) != 0) {
            printf("FAIL: --set %s: %s\n", *sets, err.message);
            json_decref(root);
            return -1;
        }
    sph_case *c = calloc(1, sizeof *c);
    const int rc = c ? sph_case_from_json(root, c, &err) : -1;
    if (rc == 0)
        *cfg = c->sim;
    else
        printf("FAIL: %s: %s (at %s)\n", name, err.message, err.path);
    free(c);
    json_decref(root);
    return rc;
}

/* Largest differences between two runs' particles, matched by id. */
static void compare(const char *what, const sph_sim *a, const sph_sim *b)
{
    sph_particle_view va, vb;
    sph_sim_particles(a, &va);
    sph_sim_particles(b, &vb);
    CHECK(va.n == vb.n, "%s: %ld particles against %ld", what, va.n, vb.n);
    if (va.n != vb.n)
        return;
    long *at = malloc((size_t)vb.n * sizeof *at);
    for (long i = 0; i < vb.n; i++)
        at[vb.id[i]] = i;
    double dx = 0.0, dv = 0.0, dr = 0.0;
    for (long i = 0; i < va.n; i++) {
        const long j = at[va.id[i]];
        for (int d = 0; d < va.dim; d++) {
            dx = fmax(dx, fabs(va.pos[d][i] - vb.pos[d][j]));
            dv = fmax(dv, fabs(va.vel[d][i] - vb.vel[d][j]));
        }
        dr = fmax(dr, fabs(va.rho[i] - vb.rho[j]) / va.rho[i]);
        if (va.type[i] != vb.type[j])
            dx = INFINITY;
    }
    free(at);
    printf("%s: %ld particles, t %.6g / %.6g s: |dx| %.2e m, |dv| %.2e m/s, |drho|/rho %.2e\n",
           what, va.n, sph_sim_time(a), sph_sim_time(b), dx, dv, dr);
    CHECK(fabs(sph_sim_time(a) - sph_sim_time(b)) <= 1e-12, "%s: times differ", what);
    CHECK(dx <= 1e-8 && dv <= 1e-6 && dr <= 1e-9, "%s: beyond the tolerance", what);
}

static sph_sim *run(const sph_config *cfg, long steps)
{
    sph_error err;
    sph_sim *s = sph_sim_create(cfg, &err);
    if (!s) {
        printf("FAIL: create: %s (at %s)\n", err.message, err.path);
        failures++;
        return NULL;
    }
    if (sph_sim_step(s, steps, &err) != 0) {
        printf("FAIL: %s\n", err.message);
        failures++;
    }
    return s;
}

static void cpu_against_gpu(const char *name, const char *const *sets)
{
    sph_config cpu;
    if (load_case(name, sets, &cpu)) {
        failures++;
        return;
    }
    sph_config gpu = cpu;
    cpu.device = SPH_DEVICE_CPU;
    gpu.device = SPH_DEVICE_GPU;
    sph_sim *a = run(&cpu, 100), *b = run(&gpu, 100);
    if (a && b)
        compare(name, a, b);
    sph_sim_destroy(a);
    sph_sim_destroy(b);
}

/* A saved state with its configuration's device changed (the state's layout is the same on
 * both devices). */
static sph_sim *restore_on(const void *buf, size_t len, sph_device device)
{
    sph_error err;
    sph_sim *s = sph_sim_restore_on(buf, len, device, &err);
    if (!s) {
        printf("FAIL: restore: %s\n", err.message);
        failures++;
    }
    return s;
}

static void checkpoints(void)
{
    static const char *const sets[] = {"dx=0.005", "device=\"gpu\"", NULL};
    sph_config gpu;
    if (load_case("dambreak.json", sets, &gpu)) {
        failures++;
        return;
    }
    sph_error err;
    sph_sim *whole = run(&gpu, 100), *half = run(&gpu, 50);
    if (!whole || !half)
        return;
    void *buf = NULL;
    size_t len = 0;
    CHECK(sph_sim_save(half, &buf, &len, &err) == 0, "save: %s", err.message);
    sph_sim *again = restore_on(buf, len, SPH_DEVICE_GPU);
    sph_sim *on_cpu = restore_on(buf, len, SPH_DEVICE_CPU);
    if (again && on_cpu) {
        CHECK(sph_sim_step(again, 50, &err) == 0, "%s", err.message);
        CHECK(sph_sim_step(on_cpu, 50, &err) == 0, "%s", err.message);
        compare("GPU saved at 50, restored on the GPU", whole, again);
        compare("GPU saved at 50, restored on the CPU", whole, on_cpu);
    }
    free(buf);
    sph_sim_destroy(whole);
    sph_sim_destroy(half);
    sph_sim_destroy(again);
    sph_sim_destroy(on_cpu);
}

int main(void)
{
    sph_core_init();
    const int ngpus = sph_sim_gpu_count();
    if (ngpus < 1) {
        printf("gpu_solver: no GPU visible: skipped\n");
        return 77;
    }
    char name[256];
    double bytes = 0.0;
    sph_sim_gpu_describe(0, name, sizeof name, &bytes);
    printf("gpu_solver: %s, %.1f GiB\n", name, bytes / (1 << 30));
    static const char *const dam[] = {"dx=0.005", NULL};
    static const char *const sps[] = {"dx=0.005",
                                      "physics.viscosity={\"type\": \"laminar\", \"nu\": 1e-6}",
                                      "physics.turbulence=\"sps\"", NULL};
    static const char *const test2[] = {"dx=0.05", "boundary.density=\"continuity\"", NULL};
    cpu_against_gpu("dambreak.json", dam);
    cpu_against_gpu("dambreak.json", sps);
    cpu_against_gpu("dambreak3d.json", test2);
    /* wave flumes: no ramp, so that the paddle moves from the first step; the damping zone over
     * most of the fluid */
    static const char *const piston[] = {"dx=0.05",          "wavemaker.layers=3",
                                         "wavemaker.ramp=0", "absorption.from=0.5",
                                         "absorption.to=2",  NULL};
    static const char *const flap[] = {"dx=0.05",
                                       "wavemaker.layers=3",
                                       "wavemaker.ramp=0",
                                       "wavemaker.type=\"flap\"",
                                       "wavemaker.hinge=0.1",
                                       "wavemaker.x=0.3",
                                       "fluid.0.box.min.0=0.3",
                                       NULL};
    static const char *const solitary[] = {"dx=0.05", "wavemaker.layers=3", NULL};
    static const char *const flume3d[] = {"domain.max.0=2",
                                          "boundary.tank.max.0=2",
                                          "fluid.0.box.max.0=2",
                                          "absorption.from=1.5",
                                          "absorption.to=2",
                                          "wavemaker.ramp=0",
                                          "diagnostics.gauges.0.x=1",
                                          "diagnostics.gauges.1.x=1.2",
                                          NULL};
    cpu_against_gpu("wave_flume.json", piston);
    cpu_against_gpu("wave_flume.json", flap);
    cpu_against_gpu("wave_solitary.json", solitary);
    cpu_against_gpu("wave_flume3d.json", flume3d);
    checkpoints();
    printf("gpu_solver: %s\n", failures ? "FAILED" : "passed");
    return failures ? 1 : 0;
}
