/*
 * bench_outputs: what a job's files cost. For the dam break at a given dx (default: about 100k
 * particles) prints the bytes per particle of a snapshot without and with compression (deflate
 * level 4 + shuffle) at t = 0 and after some steps, and the time to write a checkpoint (state
 * serialisation + file write + fsync), as medians of several runs. Never fails on time.
 * Usage: bench_outputs [DX] [RUNS]   (run from the source directory, or set SPH_SOURCE_DIR)
 */
#include "sph_case.h"
#include "sph_json.h"
#include "sph_sim.h"
#include "sphd.h"
#include "sphd_ckpt.h"
#include "sphd_outputs.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int cmp(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return x < y ? -1 : x > y;
}

static long file_size(const char *path)
{
    struct stat st;
    return stat(path, &st) == 0 ? (long)st.st_size : -1;
}

int main(int argc, char **argv)
{
    const char *dx = argc > 1 ? argv[1] : "0.00045";
    const int runs = argc > 2 ? atoi(argv[2]) : 5;
    const char *src = getenv("SPH_SOURCE_DIR") ? getenv("SPH_SOURCE_DIR") : ".";
    char path[4096], set[64];
    snprintf(path, sizeof path, "%s/cases/dambreak.json", src);
    snprintf(set, sizeof set, "dx=%s", dx);
    json_t *root;
    sph_error err;
    sph_case *c = calloc(1, sizeof *c);
    if (sph_case_load(path, &root, &err) || sph_json_apply_set(root, set, &err) ||
        sph_case_from_json(root, c, &err)) {
        fprintf(stderr, "bench_outputs: %s\n", err.message);
        return 1;
    }
    char dir[] = "/tmp/sphd-bench-outputs-XXXXXX";
    if (!mkdtemp(dir))
        return 1;
    sph_sim *s = sph_sim_create(&c->sim, &err);
    if (!s) {
        fprintf(stderr, "bench_outputs: %s\n", err.message);
        return 1;
    }
    sph_particle_view v;
    sph_sim_particles(s, &v);
    printf("dam break, dx = %s m: %ld particles\n", dx, v.n);
    printf("%-28s %12s %12s\n", "snapshot (pos,vel,rho,p,type)", "bytes", "bytes/part");
    for (int phase = 0; phase < 2; phase++) {
        if (phase == 1 && sph_sim_step(s, 200, &err)) {
            fprintf(stderr, "bench_outputs: %s\n", err.message);
            return 1;
        }
        for (int compress = 0; compress <= 4; compress += 4) {
            char sub[4200];
            snprintf(sub, sizeof sub, "%s/p%d_c%d", dir, phase, compress);
            sphd_mkdirs(sub);
            c->output.compress = compress;
            c->output.every = 1.0;
            sphd_outputs *o = sphd_outputs_open(sub, "bench", c, -1, &err);
            json_t *ev = o ? sphd_outputs_snapshot(o, s, &err) : NULL;
            if (!ev) {
                fprintf(stderr, "bench_outputs: %s\n", err.message);
                return 1;
            }
            char snap[4400];
            snprintf(snap, sizeof snap, "%s/%s", sub,
                     json_string_value(json_object_get(ev, "file")));
            long bytes = file_size(snap);
            printf("%-28s %12ld %12.1f\n",
                   phase == 0 ? (compress ? "t = 0, deflate 4" : "t = 0, none")
                              : (compress ? "after 200 steps, deflate 4" : "after 200 steps, none"),
                   bytes, (double)bytes / (double)v.n);
            json_decref(ev);
            sphd_outputs_close(o);
        }
    }
    double *t = calloc((size_t)runs, sizeof *t);
    size_t len = 0;
    for (int i = 0; i < runs; i++) {
        const double t0 = now();
        void *state;
        if (sph_sim_save(s, &state, &len, &err))
            return 1;
        sphd_ckpt_section sec[] = {{"sim", state, len}};
        if (sphd_ckpt_write(dir, sec, 1, &err)) {
            fprintf(stderr, "bench_outputs: %s\n", err.message);
            return 1;
        }
        free(state);
        t[i] = now() - t0;
    }
    qsort(t, (size_t)runs, sizeof *t, cmp);
    printf("checkpoint: %zu bytes (%.1f bytes/particle), median %.1f ms over %d runs "
           "(min %.1f, max %.1f), fsync included\n",
           len, (double)len / (double)v.n, 1e3 * t[runs / 2], runs, 1e3 * t[0], 1e3 * t[runs - 1]);
    char cmd[128];
    snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
    if (system(cmd) != 0)
        fprintf(stderr, "bench_outputs: could not remove %s\n", dir);
    free(t);
    sph_sim_destroy(s);
    free(c);
    json_decref(root);
    return 0;
}
