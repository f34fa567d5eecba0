/*
 * bench_dambreak: the WCSPH solver's speed on the dam break (Yang et al. 2014, section 4.1) at
 * three resolutions (about 20k, 80k and 320k fluid particles in 2D), for a fixed number of steps,
 * with 1 and 2 threads, with dynamic boundary particles and with free-slip ghost walls. Prints, per
 * run (the median of --repeats runs): particles, neighbours per particle (wall-wall pairs are not
 * computed and not counted), particle-steps per second (all particles, as DualSPHysics counts them,
 * and fluid particles only), time per step split into neighbour search / interactions /
 * integration, and resident memory per particle (measured, and the sim's own storage).
 *
 * The configuration is the one used to compare with DualSPHysics: Wendland C2, h = 1.414 dx,
 * artificial viscosity alpha = 0.01, linear EOS with c0 = 25 m/s, 3 layers of dynamic boundary
 * particles, CFL 0.2. Never fails on time. Ghost walls have no wall particles: their rows compare
 * by fluid particle-steps per second (the ghosts, rebuilt every step, are in the time, and their
 * pairs in the neighbour count).
 *
 * 3D rows (issue 23), --steps3d steps each: SPHERIC Test 2's geometry
 * (cases/dambreak3d.json) at about 100k, 400k and 1.6M particles (fluid and walls), and
 * DualSPHysics' own 3D dam break (examples/main/01_DamBreak) at dx = 7.4 mm (about 250k particles),
 * the case DualSPHysics 5.4's CPU build ran side by side on this machine at 486k particle-steps/s
 * on 2 threads (251k on 1) in 31 MiB (about 130 bytes per particle).
 *
 * --device gpu (a build with -DSPH_CUDA=ON, on a machine with a GPU) runs every row on the GPU
 * (dynamic walls, continuity density; the threads are the host's, which only launch): the first
 * step, which copies the particles to the device, is not timed, and "store B/p" is the device's.
 * Usage: bench_dambreak [--steps N] [--repeats R] [--threads "1 2"] [--sizes "20000 80000 320000"]
 *                       [--walls "dynamic ghost"] [--steps3d 10]
 *                       [--sizes3d "100000 400000 1600000"] [--dsph "0.0074"] [--device cpu]
 *                       [--precision double] [--skin 0]
 * --precision mixed: every row with the particles' hot fields in float (positions in double).
 * --skin S: the pair loop over a neighbour list reused over steps ("neighbours": {"skin": S},
 * dynamic walls only); the "steps/list" column then gives the timed steps per list built (the
 * builds are in "nb ms"). Give --steps several times that so the runs pay their share.
 * --start flowing (the default since 2026-11-28): the fluid moving at sqrt(g H) along x
 * (start_flowing), so that the particles cross cells and the neighbour search reorders the arrays
 * in every step, as in a flowing run; --start rest: the case's start, at rest (the figures before
 * that date), where no particle changes cells in a benchmark's steps.
 * An empty list ("") leaves its rows out.
 *
 * "serial %": the share of the timed steps spent outside every OpenMP parallel region (set-up
 * excluded), the part of a step that more threads cannot shorten. Measured, not listed: this
 * program interposes libgomp's GOMP_parallel, the entry every `#pragma omp parallel` of gcc's
 * goes through, and adds up the wall time inside it; the rest of the steps' wall time is serial.
 * "-" where the OpenMP runtime is not libgomp (clang's libomp: the entry is never called). Every
 * region of the core goes through GOMP_parallel today (nm: no GOMP_parallel_loop_*, sections or
 * teams entry); one that went through another entry would be counted as serial. Regions run on
 * one thread because they are small (their `if` clause) count as parallel.
 */
#define _GNU_SOURCE /* RTLD_NEXT */
#include "bench_cases.h"
#include "sph_sim.h"
#include "sph_sim_impl.h" /* the particles, for the flowing start */

#include <dlfcn.h>

#include <malloc.h>
#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* Wall time inside parallel regions [s], and how many were entered (the master thread's count:
 * the bench's runs are sequential and the core does not nest parallel regions). */
static double par_time;
static long par_regions;

typedef void (*gomp_parallel_fn)(void (*)(void *), void *, unsigned, unsigned);

/* libgomp's entry of `#pragma omp parallel` (gcc), timed around the real one. */
void GOMP_parallel(void (*fn)(void *), void *data, unsigned num_threads, unsigned flags);
void GOMP_parallel(void (*fn)(void *), void *data, unsigned num_threads, unsigned flags)
{
    static gomp_parallel_fn real;
    if (!real) {
        void *sym = dlsym(RTLD_NEXT, "GOMP_parallel");
        if (!sym) {
            fprintf(stderr, "bench_dambreak: libgomp's GOMP_parallel not found\n");
            abort();
        }
        memcpy(&real, &sym, sizeof real); /* (object to function pointer: ISO C has no cast) */
    }
    const double t0 = omp_get_wtime();
    real(fn, data, num_threads, flags);
    par_time += omp_get_wtime() - t0;
    par_regions++;
}

/* Resident set size of the process [bytes]. */
static double rss_bytes(void)
{
    FILE *f = fopen("/proc/self/statm", "r");
    long pages = 0, resident = 0;
    if (f) {
        if (fscanf(f, "%ld %ld", &pages, &resident) != 2)
            resident = 0;
        fclose(f);
    }
    return (double)resident * (double)sysconf(_SC_PAGESIZE);
}

/* DualSPHysics' own 3D dam break (its examples/main/01_DamBreak) at spacing dx: tank 1.6 x 0.67 x
 * 0.4 m, water 0.4 x 0.67 x 0.3 m in a corner, a square column 0.12 x 0.12 x 0.45 m with its
 * corner at (0.9, 0.24); cubic spline, h = 1.732 dx, artificial viscosity 0.1, delta-SPH 0.1,
 * c0 = 20 sqrt(g 0.3), fixed (dynamic) boundary particles in one layer, as that case draws them
 * (so about its 249,061 particles at dx = 7.4 mm). */
static sph_config dsph01(double dx)
{
    sph_config c = sph_config_default();
    c.dim = 3;
    c.dx = dx;
    c.kernel = sph_kernel_spec_default(SPH_KERNEL_CUBIC_SPLINE);
    c.h_over_dx = 1.732;
    c.domain = (sph_box){{0, 0, 0}, {1.6, 0.67, 0.6}};
    c.nfluid = 1;
    c.fluid[0] = (sph_box){{0, 0, 0}, {0.4, 0.67, 0.3}};
    c.boundary = SPH_BOUNDARY_DYNAMIC;
    c.layers = 1;
    c.wall_viscosity = 1.0;
    c.has_tank = 1;
    c.tank = (sph_box){{0, 0, 0}, {1.6, 0.67, 0.4}};
    c.nobstacles = 1;
    c.obstacles[0] = (sph_box){{0.9, 0.24, 0}, {1.02, 0.36, 0.45}};
    c.gravity[0] = c.gravity[1] = 0.0;
    c.gravity[2] = -9.81;
    c.eos = SPH_EOS_TAIT;
    c.c0 = 20.0 * sqrt(9.81 * 0.3);
    c.visc = SPH_VISC_ARTIFICIAL;
    c.alpha = 0.1;
    c.delta_sph = 0.1;
    c.cfl = 0.2;
    c.t_end = 1.5;
    return c;
}

typedef struct run {
    double rate;                 /* particle-steps per second (all particles) */
    double neighbours;           /* neighbours per particle */
    double t_nb, t_int, t_integ; /* per step [s] */
    double serial;               /* share of the steps' wall time outside parallel regions, or
                                    -1 when not measured (no libgomp) */
    double rss;                  /* resident bytes per particle */
    double own;                  /* the sim's own storage per particle */
    double per_list;             /* timed steps per neighbour list built (0: none built) */
    long n, nfluid;
} run;

/* --device: where the runs go (gpu: the device's bytes in the "store B/p" column) */
static sph_device device = SPH_DEVICE_CPU;
/* --precision: the particles' storage (sph_config.precision) */
static sph_precision precision = SPH_PRECISION_DOUBLE;
/* --skin: a reused neighbour list's skin (sph_config.neighbour_skin), 0 none */
static double skin = 0.0;
/* --start: 1 flowing (the default), 0 the case's start, at rest */
static int flowing = 1;

/* The flowing start: every fluid particle moving at sqrt(g H) along x, towards the tank's middle
 * (H the depth of the first fluid box: a dam break's speed). From rest no particle leaves its cell
 * in a benchmark's steps, so the neighbour search never reorders the arrays, which a flowing run
 * does every step; at this speed a step moves the particles 0.1-0.5% of a cell, and some cross in
 * every step. The pairs, and their physics, are those of the water at rest. */
static void start_flowing(sph_sim *s)
{
    const sph_config *c = &s->cfg;
    const int up = c->dim - 1;
    const double g = fabs(c->gravity[up]), depth = c->fluid[0].max[up] - c->fluid[0].min[up];
    const double mid = 0.5 * (c->tank.min[0] + c->tank.max[0]);
    const double u =
        copysign(sqrt(g * depth), mid - 0.5 * (c->fluid[0].min[0] + c->fluid[0].max[0]));
    sph_particles *P = &s->P;
    for (long i = 0; i < P->n; i++)
        if (P->type[i] == SPH_FLUID)
            SPH_SET(P->mixed, P, vx, i, u);
}

static int one(const sph_config *cfg, int threads, long steps, run *r)
{
    omp_set_num_threads(threads);
    sph_config c = *cfg;
    c.device = device;
    c.precision = precision;
    c.neighbour_skin = c.boundary == SPH_BOUNDARY_GHOST ? 0.0 : skin;
    if (device == SPH_DEVICE_GPU) /* the GPU's walls: continuity density (DBC) */
        c.wall_density = SPH_WALL_CONTINUITY;
    sph_error err;
    const double rss0 = rss_bytes();
    sph_sim *s = sph_sim_create(&c, &err);
    if (!s) {
        fprintf(stderr, "bench_dambreak: %s (at %s)\n", err.message, err.path);
        return -1;
    }
    if (flowing)
        start_flowing(s);
    /* the GPU's first step copies the particles to the device: not timed */
    if (device == SPH_DEVICE_GPU && sph_sim_step(s, 1, &err)) {
        fprintf(stderr, "bench_dambreak: %s\n", err.message);
        sph_sim_destroy(s);
        return -1;
    }
    const double rss1 = rss_bytes();
    sph_timing t0, t1;
    sph_sim_timing(s, &t0);
    const double p0 = par_time;
    const long n0 = par_regions;
    const double w0 = omp_get_wtime();
    if (sph_sim_step(s, steps, &err)) {
        fprintf(stderr, "bench_dambreak: %s\n", err.message);
        sph_sim_destroy(s);
        return -1;
    }
    const double wall = omp_get_wtime() - w0;
    r->serial = par_regions > n0 ? 1.0 - (par_time - p0) / wall : -1.0;
    const double rss2 = rss_bytes();
    sph_sim_timing(s, &t1);
    const sph_diag *d = sph_sim_diag(s);
    r->nfluid = d->nfluid;
    r->n = d->nfluid + d->nboundary;
    r->rate = (double)r->n * (double)steps / wall;
    r->neighbours = 2.0 * (double)t1.pairs / (double)t1.active;
    r->t_nb = (t1.neighbours - t0.neighbours) / (double)steps;
    r->t_int = (t1.interactions - t0.interactions) / (double)steps;
    r->t_integ = (t1.integration - t0.integration) / (double)steps;
    r->rss = (fmax(rss1, rss2) - rss0) / (double)r->n;
    r->per_list = t1.lists > t0.lists ? (double)steps / (double)(t1.lists - t0.lists) : 0.0;
    r->own = (device == SPH_DEVICE_GPU ? sph_sim_device_bytes(s) : sph_sim_bytes(s)) / (double)r->n;
    sph_sim_destroy(s);
    return 0;
}

static int by_rate(const void *a, const void *b)
{
    const double x = ((const run *)a)->rate, y = ((const run *)b)->rate;
    return (x > y) - (x < y);
}

/* One row per thread count of `threads`: the median of `repeats` runs of c. */
static int rows(const char *label, const sph_config *c, const char *threads, long steps,
                int repeats)
{
    char th[64];
    snprintf(th, sizeof th, "%s", threads);
    for (char *tp = NULL, *tv = strtok_r(th, " ,", &tp); tv; tv = strtok_r(NULL, " ,", &tp)) {
        run rs[50];
        for (int k = 0; k < repeats; k++)
            if (one(c, atoi(tv), steps, &rs[k]))
                return -1;
        qsort(rs, (size_t)repeats, sizeof rs[0], by_rate);
        const run *r = &rs[repeats / 2];
        const double ms = 1e3 / (r->rate / (double)r->n);
        char serial[16] = "-";
        if (r->serial >= 0.0)
            snprintf(serial, sizeof serial, "%.2f", 100.0 * r->serial);
        char per_list[16] = "-";
        if (r->per_list > 0.0)
            snprintf(per_list, sizeof per_list, "%.1f", r->per_list);
        printf("%8s %8ld %8ld %7s %6.1f %10.3f %11.3f %9.3f %8.3f %8.3f %8.3f %8s %8.0f %9.0f "
               "%9s\n",
               label, r->nfluid, r->n, tv, r->neighbours, r->rate / 1e6,
               r->rate / 1e6 * (double)r->nfluid / (double)r->n, ms, 1e3 * r->t_nb, 1e3 * r->t_int,
               1e3 * r->t_integ, serial, r->rss, r->own, per_list);
        fflush(stdout);
    }
    return 0;
}

int main(int argc, char **argv)
{
    long steps = 200, steps3d = 10;
    int repeats = 3;
    const char *threads = "1 2", *sizes = "20000 80000 320000", *walls = "dynamic ghost";
    const char *sizes3d = "100000 400000 1600000", *dsph = "0.0074";
    for (int i = 1; i < argc; i += 2) {
        /* an option without its value (--help among them) matches none: the usage */
        const char *opt = i + 1 < argc ? argv[i] : "";
        if (strcmp(opt, "--steps") == 0)
            steps = atol(argv[i + 1]);
        else if (strcmp(opt, "--repeats") == 0)
            repeats = atoi(argv[i + 1]);
        else if (strcmp(opt, "--threads") == 0)
            threads = argv[i + 1];
        else if (strcmp(opt, "--sizes") == 0)
            sizes = argv[i + 1];
        else if (strcmp(opt, "--walls") == 0)
            walls = argv[i + 1];
        else if (strcmp(opt, "--steps3d") == 0)
            steps3d = atol(argv[i + 1]);
        else if (strcmp(opt, "--sizes3d") == 0)
            sizes3d = argv[i + 1];
        else if (strcmp(opt, "--dsph") == 0)
            dsph = argv[i + 1];
        else if (strcmp(opt, "--device") == 0 &&
                 (strcmp(argv[i + 1], "cpu") == 0 || strcmp(argv[i + 1], "gpu") == 0))
            device = strcmp(argv[i + 1], "gpu") == 0 ? SPH_DEVICE_GPU : SPH_DEVICE_CPU;
        else if (strcmp(opt, "--precision") == 0 &&
                 (strcmp(argv[i + 1], "double") == 0 || strcmp(argv[i + 1], "mixed") == 0))
            precision =
                strcmp(argv[i + 1], "mixed") == 0 ? SPH_PRECISION_MIXED : SPH_PRECISION_DOUBLE;
        else if (strcmp(opt, "--skin") == 0 && atof(argv[i + 1]) >= 0.0 &&
                 atof(argv[i + 1]) <= SPH_NEIGHBOUR_SKIN_MAX)
            skin = atof(argv[i + 1]);
        else if (strcmp(opt, "--start") == 0 &&
                 (strcmp(argv[i + 1], "rest") == 0 || strcmp(argv[i + 1], "flowing") == 0))
            flowing = strcmp(argv[i + 1], "flowing") == 0;
        else {
            fprintf(
                stderr,
                "usage: %s [--steps N] [--repeats R] [--threads LIST] [--sizes LIST] "
                "[--walls LIST] [--steps3d N] [--sizes3d LIST] [--dsph LIST] [--device cpu|gpu] "
                "[--precision double|mixed] [--skin S] [--start flowing|rest]\n",
                argv[0]);
            return 64;
        }
    }
    if (repeats < 1 || repeats > 50 || steps < 1 || steps3d < 1) {
        fprintf(stderr, "bench_dambreak: bad --steps or --repeats\n");
        return 64;
    }
    /* every large array gets its own mapping and returns it when freed, so that the resident
     * size measured around a run is that run's */
    mallopt(M_MMAP_THRESHOLD, 64 * 1024);
    const char *start = flowing ? "from a flowing start" : "from rest";
    char how[64] = "the cells searched every step";
    if (skin > 0.0)
        snprintf(how, sizeof how, "a neighbour list of skin %g (dynamic walls)", skin);
    printf("dam break, Wendland C2, h = 1.414 dx, alpha = 0.01, c0 = 25 m/s, %ld steps %s, median "
           "of %d runs, %s precision, %s\n",
           steps, start, repeats, precision == SPH_PRECISION_MIXED ? "mixed" : "double", how);
    printf("%8s %8s %8s %7s %6s %10s %11s %9s %8s %8s %8s %8s %8s %9s %9s\n", "walls", "fluid",
           "total", "threads", "neigh", "Mpart-st/s", "Mfluid-st/s", "ms/step", "nb ms", "inter ms",
           "integ ms", "serial %", "RSS B/p", "store B/p", "steps/list");
    char sz[256];
    snprintf(sz, sizeof sz, "%s", sizes);
    for (char *sp = NULL, *sv = strtok_r(sz, " ,", &sp); sv; sv = strtok_r(NULL, " ,", &sp)) {
        char wl[64];
        snprintf(wl, sizeof wl, "%s", walls);
        for (char *wp = NULL, *wv = strtok_r(wl, " ,", &wp); wv; wv = strtok_r(NULL, " ,", &wp)) {
            const int ghost = strcmp(wv, "ghost") == 0;
            if (!ghost && strcmp(wv, "dynamic") != 0) {
                fprintf(stderr, "bench_dambreak: walls are dynamic or ghost, not %s\n", wv);
                return 64;
            }
            if (ghost && device == SPH_DEVICE_GPU) {
                printf("%8s (the GPU runs dynamic walls only)\n", wv);
                continue;
            }
            const sph_config c = dambreak(atol(sv), ghost);
            if (rows(wv, &c, threads, steps, repeats))
                return 1;
        }
    }
    if (*sizes3d || *dsph) {
        printf("\n3D, %ld steps %s, median of %d runs: 'test2' is SPHERIC Test 2 "
               "(cases/dambreak3d.json: Wendland C2, h = 1.414 dx, alpha = 0.01, Fourtakas' "
               "delta-SPH, "
               "c0 = 35 m/s); "
               "'dsph01' DualSPHysics' examples/main/01_DamBreak (cubic spline, h = 1.732 dx, "
               "alpha = 0.1, Tait, c0 = 20 sqrt(g 0.3))\n",
               steps3d, start, repeats);
        printf("%8s %8s %8s %7s %6s %10s %11s %9s %8s %8s %8s %8s %8s %9s %9s\n", "case", "fluid",
               "total", "threads", "neigh", "Mpart-st/s", "Mfluid-st/s", "ms/step", "nb ms",
               "inter ms", "integ ms", "serial %", "RSS B/p", "store B/p", "steps/list");
    }
    snprintf(sz, sizeof sz, "%s", sizes3d);
    for (char *sp = NULL, *sv = strtok_r(sz, " ,", &sp); sv; sv = strtok_r(NULL, " ,", &sp)) {
        const sph_config c = test2(test2_dx(atof(sv)));
        if (rows("test2", &c, threads, steps3d, repeats))
            return 1;
    }
    snprintf(sz, sizeof sz, "%s", dsph);
    for (char *sp = NULL, *sv = strtok_r(sz, " ,", &sp); sv; sv = strtok_r(NULL, " ,", &sp)) {
        const sph_config c = dsph01(atof(sv));
        if (rows("dsph01", &c, threads, steps3d, repeats))
            return 1;
    }
    printf("reference: DualSPHysics 5.4 CPU, same configuration at about 20k fluid particles, 2 "
           "threads, this machine: about 1.9 M particle-steps/s (target here: >= 3.8).\n"
           "dsph01: DualSPHysics 5.4 CPU on this machine, 249,061 particles: 486k particle-steps/s "
           "on 2 threads, 251k on 1, 31 MiB (about 130 B/particle); target here >= 3x.\n"
           "A step here is one force evaluation (velocity Verlet); DualSPHysics' symplectic step "
           "makes two. Timings on a machine shared with other work are noisy: compare medians.\n");
    return 0;
}
