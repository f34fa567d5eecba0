/*
 * bench_nlist: would a neighbour list reused over several steps (a Verlet list: the pairs
 * within the support plus a skin, rebuilt when a particle may have moved half the skin) beat
 * binning every step, as sph_wcsph_forces does? (issue 24)
 *
 * On the benchmark's 2D dam break and SPHERIC Test 2 (bench_cases.h), one thread, after a few
 * steps from rest, it times per force evaluation:
 *   - "cells": the solver's own evaluation, sph_wcsph_forces (its neighbour phase: cell keys,
 *     sort, permutation; its interactions: p, the strip pair loops over the cell ranges, gravity);
 *   - "build": a list holding, per particle, its half-stencil candidates within (1 + skin)
 *     support, in the order the strip loops visit them;
 *   - "list": the same interactions over the list (the same pair_of and the same strip order, so
 *     the same bits, checked).
 * A list reused for k steps costs per step (build + sort) / k + list, against sort + cells. k is
 * what the skin allows: the list stays right while no two particles have closed in by more than
 * the skin, i.e. for skin / (2 vmax dt) steps, with vmax = sqrt(2 g H) (the dam break's surge
 * speed, H the column's height) and the solver's dt = cfl h / (c0 + vmax); the figures print k
 * and the cost per step it gives. The list's bytes per particle are printed too.
 *
 * Usage: bench_nlist [--sizes "320000"] [--sizes3d "400000"] [--skins "0.05 0.1 0.2"]
 *                    [--repeats 3]
 * An empty list ("") leaves its rows out.
 */
#include "bench_cases.h"
#include "sph_wcsph.h"
#include "sph_wcsph_particle.h"

#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct nlist {
    long *off; /* n + 1 offsets into j */
    int *j;    /* the candidates of each particle, in the strip loops' order */
    long len, cap;
} nlist;

static int push(nlist *L, long j)
{
    if (L->len == L->cap) {
        const long cap = L->cap ? 2 * L->cap : 1 << 20;
        int *p = realloc(L->j, (size_t)cap * sizeof *p);
        if (!p)
            return -1;
        L->j = p;
        L->cap = cap;
    }
    L->j[L->len++] = (int)j;
    return 0;
}

/* Particle i's candidates in [jb, je) within reach (r^2 < reach2). */
static int add_range(nlist *L, const sph_particles *P, int D, long i, long jb, long je,
                     double reach2)
{
    for (long j = jb; j < je; j++) {
        const double dx = P->x[i] - P->x[j], dy = P->y[i] - P->y[j];
        const double dz = D == 3 ? P->z[i] - P->z[j] : 0.0;
        if (dx * dx + dy * dy + dz * dz < reach2 && push(L, j))
            return -1;
    }
    return 0;
}

/* The list over the cells, in the strip loops' order (sph_wcsph.c, strip_generic): each
 * particle's cell from it on, the cell above, and the cells of the next column (2D) or the next
 * y column and the next x slab (3D). Serial: a measurement, not a solver path. */
static int build(const sph_sim *s, double reach2, nlist *L)
{
    const sph_cells *g = &s->cells;
    const sph_particles *P = &s->P;
    const int D = s->cfg.dim, nx = g->nx, ny = g->ny, nz = D == 3 ? g->nz : 1;
    const int *start = g->start;
    const long n = s->nactive;
    L->len = 0;
    for (int cx = 1; cx < nx - 1; cx++)
        for (int cy = 1; cy < ny - 1; cy++)
            for (int cz = D == 3 ? 1 : 0; cz < (D == 3 ? nz - 1 : 1); cz++) {
                const long cell = D == 3 ? ((long)cx * ny + cy) * nz + cz : (long)cx * ny + cy;
                long rb[4], re[4];
                const int nr = half_stencil(D, start, cell, ny, nz, rb, re);
                const long up = start[cell + 2]; /* end of the cell above */
                for (long i = start[cell]; i < start[cell + 1]; i++) {
                    L->off[i] = L->len;
                    if (add_range(L, P, D, i, i + 1, up, reach2))
                        return -1;
                    for (int k = 0; k < nr; k++)
                        if (add_range(L, P, D, i, rb[k], re[k], reach2))
                            return -1;
                }
            }
    L->off[n] = L->len;
    return 0;
}

/* The interactions over the list: p, the pairs in the strips' order (even strips, then odd), then
 * gravity: what sph_wcsph_forces computes after its sort. T, F, D constants at each call. */
static inline __attribute__((always_inline)) void
list_forces(sph_kernel_type T, unsigned F, const int D, sph_sim *s, const nlist *L)
{
    sph_particles *P = &s->P;
    const long n = s->nactive;
    sph_wcsph_consts kc;
    sph_wcsph_consts_of(s, &kc);
    for (long i = 0; i < n; i++)
        prepare_one(D, 0, &s->cfg, P, kc.smag, kc.blin, i);
    fctx cl;
    fctx_init(&cl, P, &s->cells, s->cells.start, &s->kernel, &kc);
    const fctx *c = &cl;
    const sph_cells *g = &s->cells;
    const long slab = (long)g->ny * (D == 3 ? g->nz : 1);
    const int nstrips = (g->nx - 2 + 1) / 2;
    for (int parity = 0; parity < 2; parity++)
        for (int st = parity; st < nstrips; st += 2) {
            const int cx0 = 1 + 2 * st, cx1 = cx0 + 2 < g->nx - 1 ? cx0 + 2 : g->nx - 1;
            for (long i = g->start[cx0 * slab]; i < g->start[cx1 * slab]; i++) {
                pair_i q;
                pair_i_load(F, D, c, i, &q);
                acc a = {0};
                for (long t = L->off[i]; t < L->off[i + 1]; t++) {
                    const long j = L->j[t];
                    sph_wcsph_pair_out o;
                    pair_take tk;
                    if (!pair_of(T, F, D, c, &q, j, &o, &tk))
                        continue;
                    take_i(F, D, &o, &tk, &a);
                    take_j(F, D, c, cl.ax, cl.ay, cl.az, cl.drho, j, &o, &tk);
                }
                add_acc(F, D, c, i, &a);
            }
        }
    const double gv[3] = {s->cfg.gravity[0], s->cfg.gravity[1], s->cfg.gravity[2]};
    for (long i = 0; i < n; i++)
        (void)gravity_one(D, 0, gv, P, i);
}

/* The cases' own options: the 2D dam break without options, Test 2 with delta-SPH. */
static void list_forces_of(sph_sim *s, const nlist *L)
{
    if (s->cfg.dim == 3)
        list_forces(SPH_KERNEL_WENDLAND_C2, F_DELTA, 3, s, L);
    else
        list_forces(SPH_KERNEL_WENDLAND_C2, 0, 2, s, L);
}

static int by_value(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static double median(double *v, int k)
{
    qsort(v, (size_t)k, sizeof *v, by_value);
    return v[k / 2];
}

/* One case: the cells' timings, then per skin the list's; prints a row per skin. */
static int run_case(const char *label, const sph_config *cfg, double height, const char *skins,
                    int repeats)
{
    sph_error err;
    sph_sim *s = sph_sim_create(cfg, &err);
    if (!s) {
        fprintf(stderr, "bench_nlist: %s (at %s)\n", err.message, err.path);
        return -1;
    }
    if (sph_sim_step(s, 5, &err)) { /* off the lattice */
        fprintf(stderr, "bench_nlist: %s\n", err.message);
        sph_sim_destroy(s);
        return -1;
    }
    sph_particles *P = &s->P;
    const int D = cfg->dim;
    const long np = P->n;
    double t_sort[50], t_cells[50];
    for (int r = 0; r < repeats; r++) {
        sph_timing a, b;
        sph_sim_timing(s, &a);
        if (sph_wcsph_forces(s))
            return -1;
        sph_sim_timing(s, &b);
        t_sort[r] = b.neighbours - a.neighbours;
        t_cells[r] = b.interactions - a.interactions;
    }
    const long n = s->nactive;
    /* the solver's result, to compare bits with */
    double *ref[4] = {NULL};
    double *const out[4] = {P->ax, P->ay, P->drho, P->az};
    for (int k = 0; k < 4; k++)
        if (out[k]) {
            ref[k] = malloc((size_t)n * sizeof(double));
            if (!ref[k])
                return -1;
            memcpy(ref[k], out[k], (size_t)n * sizeof(double));
        }
    const double ts = median(t_sort, repeats), tc = median(t_cells, repeats);
    const double g = 9.81, vmax = sqrt(2.0 * g * height);
    const double dt = cfg->cfl * s->h / (cfg->c0 + vmax);
    const double support = s->kernel.support;
    char sk[128];
    snprintf(sk, sizeof sk, "%s", skins);
    for (char *sp = NULL, *sv = strtok_r(sk, " ,", &sp); sv; sv = strtok_r(NULL, " ,", &sp)) {
        const double skin = atof(sv); /* a fraction of the support */
        const double reach = (1.0 + skin) * support;
        nlist L = {0};
        L.off = malloc((size_t)(n + 1) * sizeof *L.off);
        if (!L.off)
            return -1;
        double t_build[50], t_list[50];
        for (int r = 0; r < repeats; r++) {
            double t0 = omp_get_wtime();
            if (build(s, reach * reach, &L))
                return -1;
            t_build[r] = omp_get_wtime() - t0;
            t0 = omp_get_wtime();
            list_forces_of(s, &L);
            t_list[r] = omp_get_wtime() - t0;
        }
        int same = 1;
        for (int k = 0; k < 4; k++)
            if (ref[k] && memcmp(ref[k], out[k], (size_t)n * sizeof(double)) != 0)
                same = 0;
        const double tb = median(t_build, repeats), tl = median(t_list, repeats);
        const double k = floor(skin * support / (2.0 * vmax * dt));
        const double reuse = k >= 1.0 ? (tb + ts) / k + tl : NAN;
        printf("%7s %8ld %2d %5.2f %9.3f %9.3f %9.3f %9.3f %5.0f %9.3f %9.3f %6.2f %8.1f %5s\n",
               label, np, D, skin, 1e3 * ts, 1e3 * tc, 1e3 * tb, 1e3 * tl, k, 1e3 * (ts + tc),
               1e3 * reuse, (ts + tc) / reuse,
               (double)L.len * sizeof(int) / (double)np + sizeof(long), same ? "yes" : "NO");
        fflush(stdout);
        free(L.off);
        free(L.j);
    }
    for (int k = 0; k < 4; k++)
        free(ref[k]);
    sph_sim_destroy(s);
    return 0;
}

int main(int argc, char **argv)
{
    const char *sizes = "320000", *sizes3d = "400000", *skins = "0.05 0.1 0.2";
    int repeats = 3;
    for (int i = 1; i < argc; i += 2) {
        const char *opt = i + 1 < argc ? argv[i] : "";
        if (strcmp(opt, "--sizes") == 0)
            sizes = argv[i + 1];
        else if (strcmp(opt, "--sizes3d") == 0)
            sizes3d = argv[i + 1];
        else if (strcmp(opt, "--skins") == 0)
            skins = argv[i + 1];
        else if (strcmp(opt, "--repeats") == 0)
            repeats = atoi(argv[i + 1]);
        else {
            fprintf(stderr,
                    "usage: %s [--sizes LIST] [--sizes3d LIST] [--skins LIST] [--repeats R]\n",
                    argv[0]);
            return 64;
        }
    }
    if (repeats < 1 || repeats > 50) {
        fprintf(stderr, "bench_nlist: --repeats must be in [1, 50]\n");
        return 64;
    }
    omp_set_num_threads(1);
    printf("per force evaluation, 1 thread, medians of %d; skin as a fraction of the support; k "
           "steps per list; ms\n",
           repeats);
    printf("%7s %8s %2s %5s %9s %9s %9s %9s %5s %9s %9s %6s %8s %5s\n", "case", "total", "D",
           "skin", "sort", "cells", "build", "list", "k", "binning", "reuse", "gain", "list B/p",
           "bits");
    char sz[256];
    snprintf(sz, sizeof sz, "%s", sizes);
    for (char *sp = NULL, *sv = strtok_r(sz, " ,", &sp); sv; sv = strtok_r(NULL, " ,", &sp)) {
        const sph_config c = dambreak(atol(sv), 0);
        if (run_case("dam2d", &c, 0.2, skins, repeats))
            return 1;
    }
    snprintf(sz, sizeof sz, "%s", sizes3d);
    for (char *sp = NULL, *sv = strtok_r(sz, " ,", &sp); sv; sv = strtok_r(NULL, " ,", &sp)) {
        const sph_config c = test2(test2_dx(atof(sv)));
        if (run_case("test2", &c, 0.55, skins, repeats))
            return 1;
    }
    printf("binning: sort + cells per step; reuse: (build + sort) / k + list per step; gain: "
           "binning / reuse (above 1: the list wins)\n");
    return 0;
}
