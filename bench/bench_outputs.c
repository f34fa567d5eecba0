/*
 * bench_outputs: what a job's files cost. For the dam break at a given dx (default: about 100k
 * particles) prints the bytes per particle of a snapshot without and with compression (deflate
 * level 4 + shuffle) at t = 0 and after some steps, and the median time to write one as a job does
 * (sphd_outputs_snapshot: gather, write, fsync, rename, XDMF); what ParaView's VTKHDF layout adds
 * to a snapshot (bytes and write time, the same fields written with and without it); what its RPDF
 * costs (its time and share of the snapshot's); and the time to write a checkpoint (state
 * serialisation + file write + fsync), as medians of several runs.
 * Never fails on time.
 * Usage: bench_outputs [DX] [RUNS]   (run from the source directory, or set SPH_SOURCE_DIR)
 */
#include "sph_case.h"
#include "sph_json.h"
#include "sph_sim.h"
#include "sphd.h"
#include "sphd_ckpt.h"
#include "sphd_h5.h"
#include "sphd_outputs.h"

#include <stdint.h>
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

/* What the RPDF (the group rpdf of every snapshot: sph_sim_rpdf over the fluid) costs: median
 * time, against the whole snapshot's (ms, uncompressed and deflate 4). */
static void rpdf_cost(const sph_sim *s, int runs, double *t, const double *snap_ms)
{
    double q[SPH_SIM_RPDF_BINS], count[SPH_SIM_RPDF_BINS], dens[SPH_SIM_RPDF_BINS];
    sph_error err;
    for (int i = 0; i < runs; i++) {
        const double t0 = now();
        if (sph_sim_rpdf(s, SPH_SIM_RPDF_QMAX, SPH_SIM_RPDF_BINS, q, count, dens, &err)) {
            fprintf(stderr, "bench_outputs: %s\n", err.message);
            exit(1);
        }
        t[i] = now() - t0;
    }
    qsort(t, (size_t)runs, sizeof *t, cmp);
    const double ms = 1e3 * t[runs / 2];
    printf("RPDF (%d bins, in every snapshot): %.1f ms, %.0f%% of the uncompressed snapshot after "
           "200 steps, %.0f%% of the compressed one\n",
           SPH_SIM_RPDF_BINS, ms, 100.0 * ms / snap_ms[0], 100.0 * ms / snap_ms[1]);
}

/* The same snapshot written with the VTKHDF group (fields pos and id) and without it (the id
 * field renamed, so no group): bytes and median write times (fsync included). */
static void vtkhdf_cost(const char *dir, const sph_sim *s, int runs, double *t)
{
    sph_particle_view v;
    sph_sim_particles(s, &v);
    const long n = v.n;
    int32_t *id = malloc((size_t)n * sizeof *id);
    for (long k = 0; k < n; k++)
        id[k] = (int32_t)v.id[k];
    for (int compress = 0; compress <= 4; compress += 4) {
        double med[2];
        long bytes[2];
        for (int with = 1; with >= 0; with--) {
            sphd_h5_field f[] = {{"pos", "m", SPHD_H5_F64, 2, {v.pos[0], v.pos[1]}},
                                 {"vel", "m/s", SPHD_H5_F64, 2, {v.vel[0], v.vel[1]}},
                                 {"rho", "kg/m^3", SPHD_H5_F64, 1, {v.rho}},
                                 {"p", "Pa", SPHD_H5_F64, 1, {v.p}},
                                 {"type", "", SPHD_H5_I8, 1, {v.type}},
                                 {with ? "id" : "ident", "1", SPHD_H5_I32, 1, {id}}};
            sphd_h5_header h = {.t = 0, .dim = 2, .n = n, .n_fluid = n};
            char path[4200];
            snprintf(path, sizeof path, "%s/vtkhdf_%d_%d.h5", dir, with, compress);
            sph_error err;
            for (int i = 0; i < runs; i++) {
                const double t0 = now();
                if (sphd_h5_write_snapshot(path, &h, f, 6, compress, &err)) {
                    fprintf(stderr, "bench_outputs: %s\n", err.message);
                    exit(1);
                }
                t[i] = now() - t0;
            }
            qsort(t, (size_t)runs, sizeof *t, cmp);
            med[with] = t[runs / 2];
            bytes[with] = file_size(path);
        }
        printf("VTKHDF layout, %s: +%ld bytes (%.2f bytes/particle, %.1f%%), write %.1f ms "
               "against %.1f ms (+%.1f%%)\n",
               compress ? "deflate 4" : "uncompressed", bytes[1] - bytes[0],
               (double)(bytes[1] - bytes[0]) / (double)n,
               100.0 * (double)(bytes[1] - bytes[0]) / (double)bytes[0], 1e3 * med[1], 1e3 * med[0],
               100.0 * (med[1] - med[0]) / med[0]);
    }
    free(id);
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
    double *t = calloc((size_t)runs, sizeof *t), snap_ms[2][2] = {{0}};
    printf("%-28s %12s %12s %10s\n", "snapshot (pos,vel,rho,p,type,id)", "bytes", "bytes/part",
           "write ms");
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
            sphd_outputs *o = sphd_outputs_open(sub, "bench", c, s, -1, &err);
            long bytes = -1;
            /* the whole snapshot as a job writes it: gathered in creation order, written, fsync'd,
             * renamed, and the XDMF rewritten; a new file each run */
            for (int i = 0; i < runs; i++) {
                const double t0 = now();
                json_t *ev = o ? sphd_outputs_snapshot(o, s, &err) : NULL;
                t[i] = now() - t0;
                if (!ev) {
                    fprintf(stderr, "bench_outputs: %s\n", err.message);
                    return 1;
                }
                if (i == 0) {
                    char snap[4400];
                    snprintf(snap, sizeof snap, "%s/%s", sub,
                             json_string_value(json_object_get(ev, "file")));
                    bytes = file_size(snap);
                }
                json_decref(ev);
            }
            qsort(t, (size_t)runs, sizeof *t, cmp);
            snap_ms[phase][compress / 4] = 1e3 * t[runs / 2];
            printf("%-28s %12ld %12.1f %10.1f\n",
                   phase == 0 ? (compress ? "t = 0, deflate 4" : "t = 0, none")
                              : (compress ? "after 200 steps, deflate 4" : "after 200 steps, none"),
                   bytes, (double)bytes / (double)v.n, 1e3 * t[runs / 2]);
            sphd_outputs_close(o);
        }
    }
    rpdf_cost(s, runs, t, snap_ms[1]);
    vtkhdf_cost(dir, s, runs, t);
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
