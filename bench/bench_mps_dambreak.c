/*
 * bench_mps_dambreak: the MPS method's speed on Koshizuka & Oka's dam break
 * (cases/mps_dambreak.json: a column L = 0.146 m wide and 2L high in a tank 4L long) at three
 * resolutions (L/20, L/40, L/80: 800, 3,200 and 12,800 fluid particles), 1 and 2 threads, against
 * WCSPH on the same dam break. Each run advances the first `--time` simulated seconds (default 0.1
 * s, T = 1.2: the column collapsing, the front on the floor). Prints per run: particles, steps, the
 * mean time step, particle-steps per second (all particles), ms per step, for MPS the share of the
 * step spent in the pressure equation (assembly and CG) and the mean CG iterations per step, and
 * the wall time per simulated second, the figure that compares the methods (MPS takes steps about
 * ten times longer than WCSPH's acoustic ones, each costing a linear solve).
 *
 * MPS: the case's settings (the quartic weight, re = 2 dx, the mixed source with relaxation 0.005,
 * the corrected gradient, the stabilization at 0.9 dx, IC(0)-preconditioned CG to 1e-8, cfl 0.1).
 * WCSPH: cases/dambreak.json's (Wendland C2, h = 1.414 dx, alpha = 0.1, delta-SPH 0.1, wall
 * viscosity factor 0, cfl 0.2) with c0 = 25 m/s (10 sqrt(2 g 2L)). Never fails on time.
 *
 * Figures (2026-11-23, eighth session, medians of 3, default wait policy, the machine otherwise
 * idle), MPS / WCSPH, wall seconds per simulated second, 1 thread: 4.5 / 2.1 at L/20, 45 / 19 at
 * L/40, 617 / 144 at L/80; 2 threads: 4.7 / 2.1, 42 / 13, 634 / 102. CG iterations per step 24,
 * 49, 105; the pressure equation 50-52%, 64-66%, 80-81% of the step (1 thread), 74-76% and 88-89%
 * with 2 at L/40 and L/80: IC(0)'s triangular solves are serial, so MPS gains nothing from the
 * second thread. Under Koshizuka & Oka's settings (the case before the eighth session) the CG
 * took 24, 29, 35 iterations and MPS cost 4.8, 34, 268 s per simulated second: their number-density
 * source put p = 0 on most of the column (false free surface, 90% of it at L/40 by t = 0.05 s),
 * which left small systems; the case's settings solve the whole column.
 *
 * Block IC(0) (mps.preconditioner "bic0", 2026-11-27, --time 0.02, medians of 3, ms per step,
 * IC(0) / bic0): 1 thread 1.59 / 1.98, 7.64 / 8.01, 41.7 / 48.6 at L/20, L/40, L/80; 2 threads
 * 1.59 / 1.95, 6.39 / 8.04, 32.9 / 29.7, and 361 / 242 at L/160 (one run of 0.004 s); CG
 * iterations per step 22 / 38, 43 / 62, 86 / 110, 144 / 179 (README).
 *
 * Usage: bench_mps_dambreak SOURCE_DIR [--time T] [--threads "1 2"] [--sizes "20 40 80"]
 * [--methods "mps wcsph"]   (SOURCE_DIR: where cases/mps_dambreak.json is; a method "mps:PC"
 * runs MPS with the preconditioner PC, e.g. "mps:bic0", "mps:amg")
 */
#include "bench_opts.h"
#include "sph_case.h"
#include "sph_json.h"
#include "sph_sim.h"

#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define L_COLUMN 0.146 /* [m], the case's column width */

/* The case file, read once (cases/mps_dambreak.json). */
static json_t *mps_case;

/* The dam break at dx = L/n to time t_end: MPS as cases/mps_dambreak.json has it, or WCSPH on
 * the same geometry with cases/dambreak.json's settings and c0 = 25 m/s. Returns 0, or -1 with
 * the case's error printed. */
static int dambreak(int mps, const char *pc, int n, double t_end, sph_config *out)
{
    char dx[64], end[64], pcs[64];
    snprintf(dx, sizeof dx, "dx=%.17g", L_COLUMN / n);
    snprintf(end, sizeof end, "time.end=%.17g", t_end);
    if (pc)
        snprintf(pcs, sizeof pcs, "mps.preconditioner=\"%s\"", pc);
    json_t *root = json_deep_copy(mps_case);
    sph_case *cs = calloc(1, sizeof *cs);
    sph_error err;
    int rc = !root || !cs ? -1 : 0;
    if (rc == 0 &&
        (sph_json_apply_set(root, dx, &err) || sph_json_apply_set(root, end, &err) ||
         (pc && sph_json_apply_set(root, pcs, &err)) || sph_case_from_json(root, cs, &err))) {
        fprintf(stderr, "bench_mps_dambreak: %s\n", err.message);
        rc = -1;
    }
    if (rc == 0 && mps) {
        *out = cs->sim;
    } else if (rc == 0) { /* the same geometry, WCSPH's settings */
        const sph_config *m = &cs->sim;
        sph_config c = sph_config_default();
        c.dx = m->dx;
        c.domain = m->domain;
        c.nfluid = m->nfluid;
        memcpy(c.fluid, m->fluid, sizeof c.fluid);
        c.boundary = m->boundary;
        c.has_tank = m->has_tank;
        c.tank = m->tank;
        c.t_end = m->t_end;
        c.kernel = sph_kernel_spec_default(SPH_KERNEL_WENDLAND_C2);
        c.h_over_dx = 1.414;
        c.layers = 3;
        c.wall_viscosity = 0.0;
        c.eos = SPH_EOS_LINEAR;
        c.c0 = 25.0;
        c.visc = SPH_VISC_ARTIFICIAL;
        c.alpha = 0.1;
        c.delta_sph = 0.1;
        c.cfl = 0.2;
        *out = c;
    }
    json_decref(root);
    free(cs);
    return rc;
}

static int one(const char *method, int n, int threads, double t_sim)
{
    omp_set_num_threads(threads);
    const int mps = strncmp(method, "mps", 3) == 0;
    const char *pc = mps && method[3] == ':' ? method + 4 : NULL;
    sph_config c;
    if (dambreak(mps, pc, n, t_sim, &c))
        return -1;
    sph_error err;
    sph_sim *s = sph_sim_create(&c, &err);
    if (!s) {
        fprintf(stderr, "bench_mps_dambreak: %s\n", err.message);
        return -1;
    }
    sph_timing t0, t1;
    sph_sim_timing(s, &t0);
    long cg = 0;
    const double w0 = omp_get_wtime();
    while (sph_sim_time(s) < t_sim) { /* one step at a time: the CG count is per step */
        if (sph_sim_advance(s, 1, t_sim, &err)) {
            fprintf(stderr, "bench_mps_dambreak: %s\n", err.message);
            sph_sim_destroy(s);
            return -1;
        }
        cg += sph_sim_diag(s)->cg_iterations;
    }
    const double wall = omp_get_wtime() - w0;
    sph_sim_timing(s, &t1);
    const sph_diag *d = sph_sim_diag(s);
    const long np = d->nfluid + d->nboundary, steps = d->step;
    const double solve = t1.solve - t0.solve;
    printf("%9s %5d %7ld %7ld %7d %6ld %9.2e %10.3f %8.3f", method, n, d->nfluid, np, threads,
           steps, d->t / (double)steps, (double)np * (double)steps / wall / 1e6,
           1e3 * wall / (double)steps);
    if (mps)
        printf(" %6.0f%% %7.1f", 100.0 * solve / wall, (double)cg / (double)steps);
    else
        printf(" %7s %7s", "-", "-");
    printf(" %9.1f\n", wall / d->t);
    fflush(stdout);
    sph_sim_destroy(s);
    return 0;
}

static int usage(const char *prog)
{
    fprintf(stderr,
            "usage: %s SOURCE_DIR [--time T] [--threads LIST] [--sizes LIST] [--methods LIST]\n",
            prog);
    return 64;
}

int main(int argc, char **argv)
{
    double t_sim = 0.1;
    const char *threads = "1 2", *sizes = "20 40 80", *methods = "mps wcsph";
    if (argc < 2 || argv[1][0] == '-')
        return usage(argv[0]);
    const bench_opt opts[] = {{"--time", BENCH_OPT_DOUBLE, &t_sim},
                              {"--threads", BENCH_OPT_TEXT, &threads},
                              {"--sizes", BENCH_OPT_TEXT, &sizes},
                              {"--methods", BENCH_OPT_TEXT, &methods},
                              {NULL, 0, NULL}};
    if (bench_options(argc, argv, 2, opts))
        return usage(argv[0]);
    if (!(t_sim > 0.0 && t_sim <= 10.0)) {
        fprintf(stderr, "bench_mps_dambreak: --time must be in (0, 10] s\n");
        return 64;
    }
    char file[4096];
    snprintf(file, sizeof file, "%s/cases/mps_dambreak.json", argv[1]);
    sph_error err;
    if (sph_case_load(file, &mps_case, &err)) {
        fprintf(stderr, "bench_mps_dambreak: %s\n", err.message);
        return 1;
    }
    printf("Koshizuka & Oka's dam break (L = %.3f m), the first %.3g s; sizes are L/dx\n", L_COLUMN,
           t_sim);
    printf("%9s %5s %7s %7s %7s %6s %9s %10s %8s %7s %7s %9s\n", "method", "L/dx", "fluid", "total",
           "threads", "steps", "dt [s]", "Mpart-st/s", "ms/step", "solve", "CG/step", "s per s");
    char sz[128];
    snprintf(sz, sizeof sz, "%s", sizes);
    for (char *sp = NULL, *sv = strtok_r(sz, " ,", &sp); sv; sv = strtok_r(NULL, " ,", &sp)) {
        const int n = atoi(sv);
        if (n < 4 || n > 1000) {
            fprintf(stderr, "bench_mps_dambreak: sizes are L/dx in [4, 1000], not %s\n", sv);
            return 64;
        }
        char ml[256];
        snprintf(ml, sizeof ml, "%s", methods);
        for (char *mp = NULL, *mv = strtok_r(ml, " ,", &mp); mv; mv = strtok_r(NULL, " ,", &mp)) {
            if (strcmp(mv, "wcsph") != 0 && strcmp(mv, "mps") != 0 && strncmp(mv, "mps:", 4) != 0) {
                fprintf(stderr,
                        "bench_mps_dambreak: methods are mps, mps:PRECONDITIONER and wcsph, not "
                        "%s\n",
                        mv);
                return 64;
            }
            char th[64];
            snprintf(th, sizeof th, "%s", threads);
            for (char *tp = NULL, *tv = strtok_r(th, " ,", &tp); tv; tv = strtok_r(NULL, " ,", &tp))
                if (one(mv, n, atoi(tv), t_sim))
                    return 1;
        }
    }
    json_decref(mps_case);
    printf("solve: the share of the wall time in the pressure equation's assembly and CG; s per s: "
           "wall seconds per simulated second. Timings on a shared machine are noisy.\n");
    return 0;
}
