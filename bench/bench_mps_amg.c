/*
 * bench_mps_amg: sphd's preconditioned CG against hypre's BoomerAMG-preconditioned CG on the
 * pressure equations that the MPS dam break really builds (issue 12: "measure both on the dam
 * break at three resolutions"). Built only with -DSPH_HYPRE=ON (libhypre-dev).
 *
 * For each resolution L/dx (default 20, 40, 80: dx = 7.3, 3.65, 1.825 mm) the case
 * cases/mps_dambreak.json runs (1 thread) to `--time` (default 0.1 s: the column collapsing, the
 * front on the floor), the pressures are kept by particle id, and one more step is taken. That
 * step's system A p = b (sph_mps_latest_system) is then solved again, from the pressures of the
 * step before it (the warm start the sim itself used, so sphd's IC(0) run repeats the sim's own
 * iteration count: checked), to the case's relative tolerance ||b - A p||_2 <= tol ||b||_2, by
 *
 *   ic0          sphd's CG with IC(0) (setup: the factorisation; its triangular solves serial)
 *   jacobi       sphd's CG with the diagonal (no setup)
 *   amg-hmis     hypre PCG (two-norm stopping test) with one BoomerAMG V(1,1)-cycle per
 *                application: HMIS coarsening, extended+i interpolation (at most 4 entries a
 *                row), l1-scaled symmetric Gauss-Seidel, strong threshold 0.25, Gaussian
 *                elimination on the coarsest level
 *   amg-falgout  the same with Falgout coarsening, classical interpolation and hybrid
 *                symmetric Gauss-Seidel
 *   amg-hmis-agg amg-hmis with its first level coarsened aggressively (the cheapest setup)
 *
 * The matrix changes every MPS step (the particles move), so a solver's setup is paid every step:
 * for hypre it is the copy of sphd's compressed rows into an IJ matrix and vectors (also printed
 * alone), the AMG hierarchy, and their release; for IC(0) the factorisation. The common assembly
 * of A (sphd's, part of every solver's step) is not counted. The solvers run in turn `--reps`
 * times (default 7) and the medians are printed: wall times and the process's CPU time, the
 * steadier figure on a shared machine. sphd's solvers run with each of `--threads` where the
 * system is large enough for sphd to use threads (SPH_OMP_MIN unknowns), hypre with one
 * (Debian's build has no OpenMP, HYPRE_USING_OPENMP; it would run with each otherwise). One MPI
 * rank: hypre's sequential use of the IJ interface on MPI_COMM_WORLD. AMG_PRINT=1 in the
 * environment prints BoomerAMG's setup statistics (levels, grid and operator complexity) at
 * every setup.
 *
 * Figures and what follows from them: README, "bench_mps_amg". Under Koshizuka & Oka's settings
 * (most of the column at p = 0) IC(0) was 2-3 times faster than the best AMG setting at L/20 to
 * L/160; on the case's present settings (the whole column solved; eighth session) IC(0)'s
 * iterations double per halving of dx (20, 40, 100, 223) and aggressive AMG is 1.2 and 2.5 times
 * faster at L/80 and L/160 (IC(0) 2.2 and 1.7 times faster at L/20 and L/40).
 *
 * Usage: bench_mps_amg SOURCE_DIR [--time T] [--sizes "20 40 80"] [--threads "1 2"] [--reps N]
 * (SOURCE_DIR: where cases/mps_dambreak.json is). Never fails on time.
 */
#include "bench_opts.h"
#include "sph_case.h"
#include "sph_json.h"
#include "sph_mps.h"
#include "sph_particles.h"
#include "sph_sim.h"

#include <HYPRE.h>
#include <HYPRE_IJ_mv.h>
#include <HYPRE_parcsr_ls.h>
#include <math.h>
#include <mpi.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define L_COLUMN  0.146 /* [m], the case's column width */
#define MAX_REPS  99
#define STEP_RING 20 /* the step time is the median of this many latest steps */

/* A solver: sphd's CG with preconditioner pc, or hypre's PCG with a BoomerAMG V-cycle. */
typedef struct solver {
    const char *name;
    int hypre;          /* 1: hypre with the settings below; 0: sphd with pc */
    sph_mps_precond pc; /* sphd's preconditioner */
    int coarsen;        /* HYPRE_BoomerAMGSetCoarsenType */
    int interp;         /* HYPRE_BoomerAMGSetInterpType */
    int pmax;           /* HYPRE_BoomerAMGSetPMaxElmts (0: no limit) */
    int relax;          /* HYPRE_BoomerAMGSetCycleRelaxType, down and up */
    int agg;            /* HYPRE_BoomerAMGSetAggNumLevels: levels of aggressive coarsening */
} solver;

static const solver solvers[] = {
    {"ic0", 0, SPH_MPS_PC_IC0, 0, 0, 0, 0, 0}, {"jacobi", 0, SPH_MPS_PC_JACOBI, 0, 0, 0, 0, 0},
    {"amg-hmis", 1, 0, 10, 6, 4, 8, 0},     /* HMIS, extended+i, l1 symmetric Gauss-Seidel */
    {"amg-falgout", 1, 0, 6, 0, 0, 6, 0},   /* Falgout, classical, hybrid symmetric G.-S. */
    {"amg-hmis-agg", 1, 0, 10, 6, 4, 8, 1}, /* amg-hmis, its first level aggressive */
};
#define NSOLVERS (int)(sizeof solvers / sizeof solvers[0])

/* One solve's figures. */
typedef struct sample {
    double copy;  /* [s], hypre: the copy of A, b and the start into its own storage */
    double setup; /* [s], copy included */
    double cpu;   /* [s], the process's CPU time in setup and solve (all threads) */
    double solve; /* [s] */
    long iterations;
    double residual; /* ||b - A p|| / ||b||, recomputed here [-] */
} sample;

/* The captured system and the bench's work arrays. */
typedef struct bench_system {
    sph_mps_ppe *S;                 /* the sim's latest matrix (borrowed) */
    const double *rhs;              /* its right-hand side per particle (borrowed) */
    double tol;                     /* the case's relative tolerance */
    long sim_iterations;            /* the sim's own IC(0) iterations on this system */
    long maxit;                     /* the case's iteration cap */
    double *p0;                     /* per particle: the warm start */
    double *p;                      /* per particle: sphd's solution */
    double *b, *x0, *x;             /* per unknown: b, the warm start, hypre's solution */
    double *q;                      /* per unknown: scratch */
    HYPRE_Int *rows, *ncols, *cols; /* the IJ copy of A: n rows, n + nnz entries */
    double *vals;
} bench_system;

static int cmp_double(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static double median(double *v, int n)
{
    qsort(v, (size_t)n, sizeof *v, cmp_double);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/* The process's CPU time [s]: on this shared machine, what a solve costs apart from the time
 * it waited for a core. */
static double cpu_time(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* ||b - A x|| / ||b|| over the unknowns */
static double residual(const bench_system *B, const double *x)
{
    const long n = B->S->n;
    sph_mps_ppe_matvec(B->S, x, B->q);
    double rr = 0.0, bb = 0.0;
    for (long u = 0; u < n; u++) {
        rr += (B->b[u] - B->q[u]) * (B->b[u] - B->q[u]);
        bb += B->b[u] * B->b[u];
    }
    return bb > 0.0 ? sqrt(rr / bb) : 0.0;
}

static void sphd_solve(bench_system *B, sph_mps_precond pc, sample *out)
{
    sph_mps_ppe *S = B->S;
    memcpy(B->p, B->p0, (size_t)S->np * sizeof *B->p);
    sph_mps_cg_stats st;
    const double c0 = cpu_time(), t0 = omp_get_wtime();
    S->factored = 0;
    if (pc == SPH_MPS_PC_IC0)
        sph_mps_ppe_factor(S);
    const double t1 = omp_get_wtime();
    sph_mps_ppe_solve(S, B->rhs, B->p, pc, B->tol, B->maxit, &st);
    const double t2 = omp_get_wtime(), c2 = cpu_time();
    for (long u = 0; u < S->n; u++)
        B->x[u] = B->p[S->part[u]];
    *out = (sample){0.0, t1 - t0, c2 - c0, t2 - t1, st.iterations, residual(B, B->x)};
}

/* hypre PCG + BoomerAMG from B->x0 into B->x. Returns 0, or -1 if hypre failed (not: did not
 * converge, which the residual shows). */
static int amg_solve(bench_system *B, const solver *v, sample *out)
{
    const sph_mps_ppe *S = B->S;
    const HYPRE_Int n = (HYPRE_Int)S->n;
    HYPRE_IJMatrix A = NULL;
    HYPRE_IJVector b = NULL, x = NULL;
    HYPRE_ParCSRMatrix pA;
    HYPRE_ParVector pb, px;
    HYPRE_Solver amg = NULL, pcg = NULL;
    int bad = 0;
    const double c0 = cpu_time(), t0 = omp_get_wtime();
    /* A in compressed rows, the diagonal first (as ParCSR stores it) */
    long e = 0;
    for (long u = 0; u < S->n; u++) {
        B->rows[u] = (HYPRE_Int)u;
        B->ncols[u] = (HYPRE_Int)(1 + S->ptr[u + 1] - S->ptr[u]);
        B->cols[e] = (HYPRE_Int)u;
        B->vals[e++] = S->diag[u];
        for (long k = S->ptr[u]; k < S->ptr[u + 1]; k++) {
            B->cols[e] = S->col[k];
            B->vals[e++] = S->val[k];
        }
    }
    bad |= HYPRE_IJMatrixCreate(MPI_COMM_WORLD, 0, n - 1, 0, n - 1, &A);
    bad |= HYPRE_IJMatrixSetObjectType(A, HYPRE_PARCSR);
    bad |= HYPRE_IJMatrixSetRowSizes(A, B->ncols);
    bad |= HYPRE_IJMatrixInitialize(A);
    bad |= HYPRE_IJMatrixSetValues(A, n, B->ncols, B->rows, B->cols, B->vals);
    bad |= HYPRE_IJMatrixAssemble(A);
    bad |= HYPRE_IJMatrixGetObject(A, (void **)&pA);
    HYPRE_IJVector *vec[2] = {&b, &x};
    const double *val[2] = {B->b, B->x0};
    for (int k = 0; k < 2; k++) {
        bad |= HYPRE_IJVectorCreate(MPI_COMM_WORLD, 0, n - 1, vec[k]);
        bad |= HYPRE_IJVectorSetObjectType(*vec[k], HYPRE_PARCSR);
        bad |= HYPRE_IJVectorInitialize(*vec[k]);
        bad |= HYPRE_IJVectorSetValues(*vec[k], n, B->rows, val[k]);
        bad |= HYPRE_IJVectorAssemble(*vec[k]);
    }
    bad |= HYPRE_IJVectorGetObject(b, (void **)&pb);
    bad |= HYPRE_IJVectorGetObject(x, (void **)&px);
    const double tc = omp_get_wtime();

    bad |= HYPRE_BoomerAMGCreate(&amg);
    bad |= HYPRE_BoomerAMGSetCoarsenType(amg, v->coarsen);
    bad |= HYPRE_BoomerAMGSetInterpType(amg, v->interp);
    bad |= HYPRE_BoomerAMGSetPMaxElmts(amg, v->pmax);
    bad |= HYPRE_BoomerAMGSetAggNumLevels(amg, v->agg);
    bad |= HYPRE_BoomerAMGSetStrongThreshold(amg, 0.25); /* 2D */
    bad |= HYPRE_BoomerAMGSetCycleRelaxType(amg, v->relax, 1);
    bad |= HYPRE_BoomerAMGSetCycleRelaxType(amg, v->relax, 2);
    bad |= HYPRE_BoomerAMGSetCycleRelaxType(amg, 9, 3); /* the coarsest: Gaussian elimination */
    bad |= HYPRE_BoomerAMGSetNumSweeps(amg, 1);
    bad |= HYPRE_BoomerAMGSetMaxIter(amg, 1); /* one V-cycle per application */
    bad |= HYPRE_BoomerAMGSetTol(amg, 0.0);
    bad |= HYPRE_BoomerAMGSetPrintLevel(amg, getenv("AMG_PRINT") ? 1 : 0);
    bad |= HYPRE_ParCSRPCGCreate(MPI_COMM_WORLD, &pcg);
    bad |= HYPRE_PCGSetTol(pcg, B->tol);
    bad |= HYPRE_PCGSetAbsoluteTol(pcg, 0.0);
    bad |= HYPRE_PCGSetTwoNorm(pcg, 1); /* ||r||_2 <= tol ||b||_2, as sphd's */
    bad |= HYPRE_PCGSetMaxIter(pcg, (HYPRE_Int)B->maxit);
    bad |= HYPRE_PCGSetPrintLevel(pcg, 0);
    bad |= HYPRE_PCGSetPrecond(pcg, (HYPRE_PtrToSolverFcn)HYPRE_BoomerAMGSolve,
                               (HYPRE_PtrToSolverFcn)HYPRE_BoomerAMGSetup, amg);
    bad |= HYPRE_ParCSRPCGSetup(pcg, pA, pb, px);
    const double t1 = omp_get_wtime();
    HYPRE_ParCSRPCGSolve(pcg, pA, pb, px); /* not converged: the residual below says so */
    HYPRE_ClearAllErrors();
    const double t2 = omp_get_wtime();
    HYPRE_Int it = 0;
    bad |= HYPRE_PCGGetNumIterations(pcg, &it);
    bad |= HYPRE_IJVectorGetValues(x, n, B->rows, B->x);
    bad |= HYPRE_ParCSRPCGDestroy(pcg);
    bad |= HYPRE_BoomerAMGDestroy(amg);
    bad |= HYPRE_IJVectorDestroy(x);
    bad |= HYPRE_IJVectorDestroy(b);
    bad |= HYPRE_IJMatrixDestroy(A);
    const double t3 = omp_get_wtime(), c3 = cpu_time();
    *out = (sample){tc - t0, (t1 - t0) + (t3 - t2), c3 - c0, t2 - t1, it, residual(B, B->x)};
    return bad ? -1 : 0;
}

/* Runs every solver (hypre's only with one thread unless it has OpenMP) reps times, in turn
 * (the machine's other load falls on all alike), and prints the medians. Returns -1 if hypre
 * failed. */
static int measure(bench_system *B, int threads, int reps)
{
    omp_set_num_threads(threads);
    static double copy[NSOLVERS][MAX_REPS], setup[NSOLVERS][MAX_REPS], solve[NSOLVERS][MAX_REPS],
        total[NSOLVERS][MAX_REPS], cpu[NSOLVERS][MAX_REPS];
    sample last[NSOLVERS];
    int run[NSOLVERS];
    for (int k = 0; k < NSOLVERS; k++) {
        run[k] = !solvers[k].hypre || threads == 1;
#ifdef HYPRE_USING_OPENMP
        run[k] = 1;
#endif
    }
    for (int r = 0; r < reps; r++)
        for (int k = 0; k < NSOLVERS; k++) {
            sample *s = &last[k];
            if (!run[k])
                continue;
            if (!solvers[k].hypre) {
                sphd_solve(B, solvers[k].pc, s);
            } else if (amg_solve(B, &solvers[k], s)) {
                fprintf(stderr, "bench_mps_amg: hypre failed (%s)\n", solvers[k].name);
                return -1;
            }
            copy[k][r] = s->copy;
            setup[k][r] = s->setup;
            solve[k][r] = s->solve;
            total[k][r] = s->setup + s->solve;
            cpu[k][r] = s->cpu;
        }
    for (int k = 0; k < NSOLVERS; k++) {
        if (!run[k])
            continue;
        const sample *s = &last[k];
        printf("  %-12s %7d %6ld %9.1e %9.3f %9.3f %9.3f %9.3f %9.3f%s%s\n", solvers[k].name,
               threads, s->iterations, s->residual, 1e3 * median(copy[k], reps),
               1e3 * median(setup[k], reps), 1e3 * median(solve[k], reps),
               1e3 * median(total[k], reps), 1e3 * median(cpu[k], reps),
               s->residual <= B->tol ? "" : "  NOT CONVERGED",
               solvers[k].pc == SPH_MPS_PC_IC0 && !solvers[k].hypre &&
                       s->iterations != B->sim_iterations
                   ? "  NOT THE SIM'S COUNT"
                   : "");
    }
    fflush(stdout);
    return 0;
}

/* One step, not past t_until, its wall time kept in ring. Returns 0 or -1 (printed). */
static int timed_step(sph_sim *s, double t_until, double *ring, long *nstep)
{
    sph_error err;
    const double w0 = omp_get_wtime();
    if (sph_sim_advance(s, 1, t_until, &err)) {
        fprintf(stderr, "bench_mps_amg: %s\n", err.message);
        return -1;
    }
    ring[(*nstep)++ % STEP_RING] = omp_get_wtime() - w0;
    return 0;
}

/* Runs the dam break at L/res to t_cap plus one step and measures its system. */
static int one(const json_t *mps_case, int res, double t_cap, const int *threads, int nthreads,
               int reps)
{
    char dx[64];
    snprintf(dx, sizeof dx, "dx=%.17g", L_COLUMN / res);
    json_t *root = json_deep_copy(mps_case);
    sph_case *cs = calloc(1, sizeof *cs);
    sph_error err;
    if (!root || !cs || sph_json_apply_set(root, dx, &err) || sph_case_from_json(root, cs, &err)) {
        fprintf(stderr, "bench_mps_amg: %s\n", root && cs ? err.message : "out of memory");
        json_decref(root);
        free(cs);
        return -1;
    }
    json_decref(root);
    omp_set_num_threads(1);
    sph_sim *s = sph_sim_create(&cs->sim, &err);
    const double tol = cs->sim.mps.tol;
    const long maxit = cs->sim.mps.maxit;
    free(cs);
    if (!s) {
        fprintf(stderr, "bench_mps_amg: %s\n", err.message);
        return -1;
    }
    /* to t_cap, then one step from the pressures kept by id */
    double ring[STEP_RING];
    long nstep = 0;
    int rc = 0;
    while (!rc && sph_sim_time(s) < t_cap)
        rc = timed_step(s, t_cap, ring, &nstep);
    sph_particle_view view;
    double *by_id = NULL;
    if (!rc) {
        sph_sim_particles(s, &view);
        by_id = malloc((size_t)view.n * sizeof *by_id);
        if (by_id) {
            for (long i = 0; i < view.n; i++)
                by_id[view.id[i]] = view.p[i];
            rc = timed_step(s, INFINITY, ring, &nstep);
        } else {
            rc = -1;
        }
    }
    const double *rhs = NULL;
    sph_mps_ppe *S = rc ? NULL : sph_mps_latest_system(s, &rhs);
    bench_system B = {.S = S, .rhs = rhs, .tol = tol, .maxit = maxit};
    const long np = S ? S->np : 0, n = S ? S->n : 0, ne = S ? S->n + S->nnz : 0;
    if (S) {
        B.p0 = malloc((size_t)np * sizeof(double));
        B.p = malloc((size_t)np * sizeof(double));
        B.b = malloc((size_t)n * sizeof(double));
        B.x0 = malloc((size_t)n * sizeof(double));
        B.x = malloc((size_t)n * sizeof(double));
        B.q = malloc((size_t)n * sizeof(double));
        B.rows = malloc((size_t)n * sizeof(HYPRE_Int));
        B.ncols = malloc((size_t)n * sizeof(HYPRE_Int));
        B.cols = malloc((size_t)ne * sizeof(HYPRE_Int));
        B.vals = malloc((size_t)ne * sizeof(double));
    }
    if (!S || !B.p0 || !B.p || !B.b || !B.x0 || !B.x || !B.q || !B.rows || !B.ncols || !B.cols ||
        !B.vals) {
        if (!rc)
            fprintf(stderr, "bench_mps_amg: no system to measure (or out of memory)\n");
        rc = -1;
    }
    if (!rc) {
        sph_sim_particles(s, &view);
        for (long i = 0; i < np; i++)
            B.p0[i] = by_id[view.id[i]];
        for (long u = 0; u < n; u++) {
            B.b[u] = rhs[S->part[u]];
            B.x0[u] = B.p0[S->part[u]];
        }
        const sph_diag *d = sph_sim_diag(s);
        B.sim_iterations = d->cg_iterations;
        const int ns = nstep < STEP_RING ? (int)nstep : STEP_RING;
        printf("L/dx %d (dx = %.4g mm): step %ld at t = %.4f s, %ld fluid particles; unknowns %ld, "
               "nonzeros %ld (diagonal included), surface particles %ld; a step takes %.2f ms "
               "(1 thread, median of the last %d); the sim's IC(0) solve took %ld iterations\n",
               res, 1e3 * L_COLUMN / res, d->step, d->t, d->nfluid, n, ne, S->surface,
               1e3 * median(ring, ns), ns, d->cg_iterations);
        printf("  %-12s %7s %6s %9s %9s %9s %9s %9s %9s\n", "solver", "threads", "iters",
               "residual", "copy ms", "setup ms", "solve ms", "total ms", "CPU ms");
        for (int t = 0; !rc && t < nthreads; t++)
            if (t == 0 || n >= SPH_OMP_MIN) /* sphd runs smaller systems on one thread */
                rc = measure(&B, threads[t], reps);
    }
    free(B.p0);
    free(B.p);
    free(B.b);
    free(B.x0);
    free(B.x);
    free(B.q);
    free(B.rows);
    free(B.ncols);
    free(B.cols);
    free(B.vals);
    free(by_id);
    sph_sim_destroy(s);
    return rc;
}

static int usage(const char *prog)
{
    fprintf(stderr, "usage: %s SOURCE_DIR [--time T] [--sizes LIST] [--threads LIST] [--reps N]\n",
            prog);
    return 64;
}

/* A list of at most max integers in [lo, hi] ("20 40 80" or "20,40,80"). Returns how many, or
 * -1 if one is out of range. */
static int int_list(const char *text, int *v, int max, int lo, int hi)
{
    char buf[256];
    snprintf(buf, sizeof buf, "%s", text);
    int k = 0;
    for (char *sp = NULL, *tok = strtok_r(buf, " ,", &sp); tok; tok = strtok_r(NULL, " ,", &sp)) {
        const long x = strtol(tok, NULL, 10);
        if (k == max || x < lo || x > hi)
            return -1;
        v[k++] = (int)x;
    }
    return k;
}

int main(int argc, char **argv)
{
    double t_cap = 0.1;
    const char *sizes = "20 40 80", *threads = "1 2";
    int reps = 7;
    if (argc < 2 || argv[1][0] == '-')
        return usage(argv[0]);
    const bench_opt opts[] = {{"--time", BENCH_OPT_DOUBLE, &t_cap},
                              {"--sizes", BENCH_OPT_TEXT, &sizes},
                              {"--threads", BENCH_OPT_TEXT, &threads},
                              {"--reps", BENCH_OPT_INT, &reps},
                              {NULL, 0, NULL}};
    if (bench_options(argc, argv, 2, opts))
        return usage(argv[0]);
    int res[16], th[8];
    const int nres = int_list(sizes, res, 16, 4, 1000), nth = int_list(threads, th, 8, 1, 256);
    if (!(t_cap > 0.0 && t_cap <= 10.0) || nres < 1 || nth < 1 || reps < 1 || reps > MAX_REPS) {
        fprintf(stderr, "bench_mps_amg: --time in (0, 10] s, sizes L/dx in [4, 1000], threads in "
                        "[1, 256], reps in [1, 99]\n");
        return 64;
    }
    char file[4096];
    snprintf(file, sizeof file, "%s/cases/mps_dambreak.json", argv[1]);
    json_t *mps_case;
    sph_error err;
    if (sph_case_load(file, &mps_case, &err)) {
        fprintf(stderr, "bench_mps_amg: %s\n", err.message);
        return 1;
    }
    if (MPI_Init(&argc, &argv) != MPI_SUCCESS || HYPRE_Init() != 0) {
        fprintf(stderr, "bench_mps_amg: MPI or hypre did not start\n");
        json_decref(mps_case);
        return 1;
    }
    printf(
        "Koshizuka & Oka's MPS dam break (cases/mps_dambreak.json), the system of the first step "
        "after t = %.3g s, warm-started; medians of %d solves; hypre %s%s\n",
        t_cap, reps, HYPRE_RELEASE_VERSION,
#ifdef HYPRE_USING_OPENMP
        " (OpenMP)"
#else
        " (serial: built without OpenMP)"
#endif
    );
    int rc = 0;
    for (int r = 0; !rc && r < nres; r++)
        rc = one(mps_case, res[r], t_cap, th, nth, reps);
    printf("setup: IC(0) factorisation; hypre: the IJ copy of A, b and the start, the AMG "
           "hierarchy and their release. The assembly of A, common to all, is not counted.\n");
    json_decref(mps_case);
    HYPRE_Finalize();
    MPI_Finalize();
    return rc ? 1 : 0;
}
