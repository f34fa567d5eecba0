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
 * Usage: bench_dambreak [--steps N] [--repeats R] [--threads "1 2"] [--sizes "20000 80000 320000"]
 *                       [--walls "dynamic ghost"]
 */
#include "sph_sim.h"

#include <malloc.h>
#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

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

static sph_config dambreak(long nfluid, int ghost)
{
    sph_config c = sph_config_default();
    c.dx = sqrt(0.1 * 0.2 / (double)nfluid);
    c.kernel = sph_kernel_spec_default(SPH_KERNEL_WENDLAND_C2);
    c.h_over_dx = 1.414;
    c.domain = (sph_box){{0, 0, 0}, {1.0, 0.6, 0}};
    c.nfluid = 1;
    c.fluid[0] = (sph_box){{0, 0, 0}, {0.1, 0.2, 0}};
    c.boundary = ghost ? SPH_BOUNDARY_GHOST : SPH_BOUNDARY_DYNAMIC;
    c.layers = 3;
    c.has_tank = 1;
    c.tank = (sph_box){{0, 0, 0}, {1.0, 0.6, 0}};
    c.eos = SPH_EOS_LINEAR;
    c.c0 = 25.0;
    c.visc = SPH_VISC_ARTIFICIAL;
    c.alpha = 0.01;
    c.cfl = 0.2;
    c.t_end = 1.0;
    return c;
}

typedef struct run {
    double rate;                 /* particle-steps per second (all particles) */
    double neighbours;           /* neighbours per particle */
    double t_nb, t_int, t_integ; /* per step [s] */
    double rss;                  /* resident bytes per particle */
    double own;                  /* the sim's own storage per particle */
    long n, nfluid;
} run;

static int one(long nfluid, int ghost, int threads, long steps, run *r)
{
    omp_set_num_threads(threads);
    sph_config c = dambreak(nfluid, ghost);
    sph_error err;
    const double rss0 = rss_bytes();
    sph_sim *s = sph_sim_create(&c, &err);
    if (!s) {
        fprintf(stderr, "bench_dambreak: %s\n", err.message);
        return -1;
    }
    const double rss1 = rss_bytes();
    sph_timing t0, t1;
    sph_sim_timing(s, &t0);
    const double w0 = omp_get_wtime();
    if (sph_sim_step(s, steps, &err)) {
        fprintf(stderr, "bench_dambreak: %s\n", err.message);
        sph_sim_destroy(s);
        return -1;
    }
    const double wall = omp_get_wtime() - w0;
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
    r->own = sph_sim_bytes(s) / (double)r->n;
    sph_sim_destroy(s);
    return 0;
}

static int by_rate(const void *a, const void *b)
{
    const double x = ((const run *)a)->rate, y = ((const run *)b)->rate;
    return (x > y) - (x < y);
}

int main(int argc, char **argv)
{
    long steps = 200;
    int repeats = 3;
    const char *threads = "1 2", *sizes = "20000 80000 320000", *walls = "dynamic ghost";
    for (int i = 1; i + 1 < argc; i += 2) {
        if (strcmp(argv[i], "--steps") == 0)
            steps = atol(argv[i + 1]);
        else if (strcmp(argv[i], "--repeats") == 0)
            repeats = atoi(argv[i + 1]);
        else if (strcmp(argv[i], "--threads") == 0)
            threads = argv[i + 1];
        else if (strcmp(argv[i], "--sizes") == 0)
            sizes = argv[i + 1];
        else if (strcmp(argv[i], "--walls") == 0)
            walls = argv[i + 1];
        else {
            fprintf(stderr,
                    "usage: %s [--steps N] [--repeats R] [--threads LIST] [--sizes LIST] "
                    "[--walls LIST]\n",
                    argv[0]);
            return 64;
        }
    }
    if (repeats < 1 || repeats > 50 || steps < 1) {
        fprintf(stderr, "bench_dambreak: bad --steps or --repeats\n");
        return 64;
    }
    /* every large array gets its own mapping and returns it when freed, so that the resident
     * size measured around a run is that run's */
    mallopt(M_MMAP_THRESHOLD, 64 * 1024);
    printf("dam break, Wendland C2, h = 1.414 dx, alpha = 0.01, c0 = 25 m/s, %ld steps, median of "
           "%d runs\n",
           steps, repeats);
    printf("%8s %8s %8s %7s %6s %10s %11s %9s %8s %8s %8s %8s %9s\n", "walls", "fluid", "total",
           "threads", "neigh", "Mpart-st/s", "Mfluid-st/s", "ms/step", "nb ms", "inter ms",
           "integ ms", "RSS B/p", "store B/p");
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
            char th[64];
            snprintf(th, sizeof th, "%s", threads);
            for (char *tp = NULL, *tv = strtok_r(th, " ,", &tp); tv;
                 tv = strtok_r(NULL, " ,", &tp)) {
                run rs[50];
                int ok = 1;
                for (int k = 0; k < repeats && ok; k++)
                    ok = one(atol(sv), ghost, atoi(tv), steps, &rs[k]) == 0;
                if (!ok)
                    return 1;
                qsort(rs, (size_t)repeats, sizeof rs[0], by_rate);
                const run *r = &rs[repeats / 2];
                const double ms = 1e3 / (r->rate / (double)r->n);
                printf(
                    "%8s %8ld %8ld %7s %6.1f %10.3f %11.3f %9.3f %8.3f %8.3f %8.3f %8.0f %9.0f\n",
                    wv, r->nfluid, r->n, tv, r->neighbours, r->rate / 1e6,
                    r->rate / 1e6 * (double)r->nfluid / (double)r->n, ms, 1e3 * r->t_nb,
                    1e3 * r->t_int, 1e3 * r->t_integ, r->rss, r->own);
                fflush(stdout);
            }
        }
    }
    printf("reference: DualSPHysics 5.4 CPU, same configuration at about 20k fluid particles, 2 "
           "threads, this machine: about 1.9 M particle-steps/s (target here: >= 3.8).\n"
           "A step here is one force evaluation (velocity Verlet); DualSPHysics' symplectic step "
           "makes two. Timings on a machine shared with other work are noisy: compare medians.\n");
    return 0;
}
