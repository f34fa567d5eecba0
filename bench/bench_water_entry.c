/*
 * bench_water_entry: the solver's speed with a rigid body (cases/water_entry.json, the cylinder
 * entering still water), for a fixed number of steps from the entry, with 1 and 2 threads.
 * Prints, per run: particles (fluid, walls, body), particle-steps per second (all particles), the
 * time per step split into neighbour search / interactions / integration, and the share of the
 * wall time the body coupling takes (the body particles' pressure from the fluid, forces summed
 * over the body's particles, the body moved, its particles placed: sph_timing.bodies). The pair loop's own extra work for body particles is part
 * of the interactions. Never fails on time.
 *
 * Usage: bench_water_entry SOURCE_DIR [--steps N] [--threads "1 2"] [--dx DX]
 */
#include "sph_case.h"
#include "sph_json.h"
#include "sph_sim.h"

#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int main(int argc, char **argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: bench_water_entry SOURCE_DIR [--steps N] [--threads \"1 2\"] "
                        "[--dx DX]\n");
        return 64;
    }
    long steps = 300;
    const char *threads = "1 2", *dx = NULL;
    for (int i = 2; i + 1 < argc; i += 2) {
        if (strcmp(argv[i], "--steps") == 0)
            steps = atol(argv[i + 1]);
        else if (strcmp(argv[i], "--threads") == 0)
            threads = argv[i + 1];
        else if (strcmp(argv[i], "--dx") == 0)
            dx = argv[i + 1];
    }
    char file[4096], set[64];
    snprintf(file, sizeof file, "%s/cases/water_entry.json", argv[1]);
    sph_error err;
    json_t *root;
    sph_case *c = calloc(1, sizeof *c);
    if (!c || sph_case_load(file, &root, &err)) {
        fprintf(stderr, "bench_water_entry: %s\n", err.message);
        return 1;
    }
    snprintf(set, sizeof set, "dx=%s", dx ? dx : "0.005");
    if (sph_json_apply_set(root, set, &err) || sph_case_from_json(root, c, &err)) {
        fprintf(stderr, "bench_water_entry: %s\n", err.message);
        return 1;
    }
    json_decref(root);
    printf("%8s %7s %7s %6s %3s %12s %10s %10s %10s %8s\n", "fluid", "walls", "body", "steps",
           "thr", "p-steps/s", "nb ms", "int ms", "integ ms", "body %");
    for (const char *p = threads; *p;) {
        char *end;
        const long th = strtol(p, &end, 10);
        if (end == p)
            break;
        p = end;
        omp_set_num_threads((int)th);
        sph_sim *s = sph_sim_create(&c->sim, &err);
        if (!s) {
            fprintf(stderr, "bench_water_entry: %s\n", err.message);
            return 1;
        }
        sph_timing t0, t1;
        sph_sim_timing(s, &t0);
        const double w0 = omp_get_wtime();
        if (sph_sim_step(s, steps, &err)) {
            fprintf(stderr, "bench_water_entry: %s\n", err.message);
            return 1;
        }
        const double wall = omp_get_wtime() - w0;
        sph_sim_timing(s, &t1);
        const sph_diag *d = sph_sim_diag(s);
        const long n = d->nfluid + d->nboundary + d->nbody;
        printf("%8ld %7ld %7ld %6ld %3ld %12.4g %10.3f %10.3f %10.3f %8.2f\n", d->nfluid,
               d->nboundary, d->nbody, steps, th, (double)n * (double)steps / wall,
               1e3 * (t1.neighbours - t0.neighbours) / (double)steps,
               1e3 * (t1.interactions - t0.interactions) / (double)steps,
               1e3 * (t1.integration - t0.integration) / (double)steps,
               100.0 * (t1.bodies - t0.bodies) / wall);
        sph_sim_destroy(s);
    }
    free(c);
    return 0;
}
