/*
 * sph_mps_amg: the pressure equation's solve by hypre's conjugate gradient with one BoomerAMG
 * V-cycle as the preconditioner (mps.preconditioner "amg"). Compiled only with -DSPH_HYPRE=ON
 * (libhypre-dev); sph_mps_ppe.c calls it for SPH_MPS_PC_AMG.
 *
 * The setting is the cheapest of the three bench_mps_amg measured (README, "bench_mps_amg"):
 * HMIS coarsening with its first level coarsened aggressively, extended+i interpolation (4 a
 * row), l1 symmetric Gauss-Seidel, strong threshold 0.25 (2D), Gaussian elimination on the
 * coarsest level. The particles move every step, so the matrix, its copy and the hierarchy are
 * built every solve.
 *
 * hypre is MPI-parallel in Debian's build: the process becomes an MPI singleton on the first
 * solve (MPI_Init_thread, MPI_THREAD_SERIALIZED; never finalised), in Open MPI's isolated mode
 * when the program called sph_core_init first (sphd does: no orted helper process is forked),
 * and every solve runs under one mutex, since hypre's global state (its error flag, memory
 * bookkeeping) is not documented as thread-safe: the solves of concurrent jobs take turns.
 * Serial and deterministic: the same system and start give the same bits.
 */
#include "sph_mps_ppe.h"

#include <HYPRE.h>
#include <HYPRE_krylov.h>
#include <HYPRE_parcsr_ls.h>
#include <mpi.h>
#include <pthread.h>
#include <stdlib.h>

static pthread_mutex_t amg_lock = PTHREAD_MUTEX_INITIALIZER;
static int mpi_ready, hypre_ready; /* under amg_lock */

/* Before any thread (sph_core_init): Open MPI's singleton in isolated mode, so that its
 * MPI_Init forks no orted helper process (the user's own setting is kept). */
void sph_mps_amg_process_init(void)
{
    setenv("OMPI_MCA_ess_singleton_isolated", "1", 0);
}

static int amg_init(void)
{
    if (!mpi_ready) {
        int inited = 0;
        if (MPI_Initialized(&inited) != MPI_SUCCESS)
            return -1;
        if (inited) { /* the program did both (bench_mps_amg) */
            hypre_ready = 1;
        } else {
            int provided = 0;
            if (MPI_Init_thread(NULL, NULL, MPI_THREAD_SERIALIZED, &provided) != MPI_SUCCESS ||
                provided < MPI_THREAD_SERIALIZED)
                return -1;
        }
        mpi_ready = 1;
    }
    if (!hypre_ready) {
        if (HYPRE_Init() != 0)
            return -1;
        hypre_ready = 1;
    }
    return 0;
}

/* A x = b over S's unknowns, x the warm start on entry. Returns 0 when converged, 1 when maxit
 * iterations did not reach tol, -1 when hypre failed or memory ran out. */
static int amg_locked(const sph_mps_ppe *S, const double *b, double *x, double tol, long maxit,
                      long *iterations)
{
    const HYPRE_Int n = (HYPRE_Int)S->n;
    const long entries = S->n + S->nnz;
    HYPRE_Int *rows = malloc((size_t)S->n * sizeof *rows);
    HYPRE_Int *ncols = malloc((size_t)S->n * sizeof *ncols);
    HYPRE_Int *cols = malloc((size_t)entries * sizeof *cols);
    double *vals = malloc((size_t)entries * sizeof *vals);
    HYPRE_IJMatrix A = NULL;
    HYPRE_IJVector bv = NULL, xv = NULL;
    HYPRE_ParCSRMatrix pA;
    HYPRE_ParVector pb, px;
    HYPRE_Solver amg = NULL, pcg = NULL;
    int bad = !rows || !ncols || !cols || !vals || amg_init() != 0, rc = -1;
    if (bad)
        goto out;
    /* A in compressed rows, the diagonal first (as ParCSR stores it) */
    long e = 0;
    for (long u = 0; u < S->n; u++) {
        rows[u] = (HYPRE_Int)u;
        ncols[u] = (HYPRE_Int)(1 + S->ptr[u + 1] - S->ptr[u]);
        cols[e] = (HYPRE_Int)u;
        vals[e++] = S->diag[u];
        for (long k = S->ptr[u]; k < S->ptr[u + 1]; k++) {
            cols[e] = S->col[k];
            vals[e++] = S->val[k];
        }
    }
    bad |= HYPRE_IJMatrixCreate(MPI_COMM_SELF, 0, n - 1, 0, n - 1, &A);
    bad |= HYPRE_IJMatrixSetObjectType(A, HYPRE_PARCSR);
    bad |= HYPRE_IJMatrixSetRowSizes(A, ncols);
    bad |= HYPRE_IJMatrixInitialize(A);
    bad |= HYPRE_IJMatrixSetValues(A, n, ncols, rows, cols, vals);
    bad |= HYPRE_IJMatrixAssemble(A);
    bad |= HYPRE_IJMatrixGetObject(A, (void **)&pA);
    HYPRE_IJVector *vec[2] = {&bv, &xv};
    const double *val[2] = {b, x};
    for (int k = 0; k < 2; k++) {
        bad |= HYPRE_IJVectorCreate(MPI_COMM_SELF, 0, n - 1, vec[k]);
        bad |= HYPRE_IJVectorSetObjectType(*vec[k], HYPRE_PARCSR);
        bad |= HYPRE_IJVectorInitialize(*vec[k]);
        bad |= HYPRE_IJVectorSetValues(*vec[k], n, rows, val[k]);
        bad |= HYPRE_IJVectorAssemble(*vec[k]);
    }
    bad |= HYPRE_IJVectorGetObject(bv, (void **)&pb);
    bad |= HYPRE_IJVectorGetObject(xv, (void **)&px);
    bad |= HYPRE_BoomerAMGCreate(&amg);
    bad |= HYPRE_BoomerAMGSetCoarsenType(amg, 10);       /* HMIS */
    bad |= HYPRE_BoomerAMGSetInterpType(amg, 6);         /* extended+i */
    bad |= HYPRE_BoomerAMGSetPMaxElmts(amg, 4);          /* 4 a row */
    bad |= HYPRE_BoomerAMGSetAggNumLevels(amg, 1);       /* the first level aggressively */
    bad |= HYPRE_BoomerAMGSetStrongThreshold(amg, 0.25); /* 2D */
    bad |= HYPRE_BoomerAMGSetCycleRelaxType(amg, 8, 1);  /* l1 symmetric Gauss-Seidel */
    bad |= HYPRE_BoomerAMGSetCycleRelaxType(amg, 8, 2);
    bad |= HYPRE_BoomerAMGSetCycleRelaxType(amg, 9, 3); /* the coarsest: Gaussian elimination */
    bad |= HYPRE_BoomerAMGSetNumSweeps(amg, 1);
    bad |= HYPRE_BoomerAMGSetMaxIter(amg, 1); /* one V-cycle per application */
    bad |= HYPRE_BoomerAMGSetTol(amg, 0.0);
    bad |= HYPRE_BoomerAMGSetPrintLevel(amg, 0);
    bad |= HYPRE_ParCSRPCGCreate(MPI_COMM_SELF, &pcg);
    bad |= HYPRE_PCGSetTol(pcg, tol);
    bad |= HYPRE_PCGSetAbsoluteTol(pcg, 0.0);
    bad |= HYPRE_PCGSetTwoNorm(pcg, 1);           /* ||r||_2 <= tol ||b||_2, as sphd's CG */
    bad |= HYPRE_PCGSetRecomputeResidual(pcg, 1); /* that ||r|| recomputed, not the recurrence's */
    bad |= HYPRE_PCGSetMaxIter(pcg, (HYPRE_Int)(maxit < 1000000000L ? maxit : 1000000000L));
    bad |= HYPRE_PCGSetPrintLevel(pcg, 0);
    bad |= HYPRE_PCGSetPrecond(pcg, (HYPRE_PtrToSolverFcn)HYPRE_BoomerAMGSolve,
                               (HYPRE_PtrToSolverFcn)HYPRE_BoomerAMGSetup, amg);
    if (bad)
        goto out;
    bad |= HYPRE_ParCSRPCGSetup(pcg, pA, pb, px);
    HYPRE_ParCSRPCGSolve(pcg, pA, pb, px); /* not converged: an error flag, read below */
    HYPRE_ClearAllErrors();
    HYPRE_Int it = 0, conv = 0;
    bad |= HYPRE_PCGGetNumIterations(pcg, &it);
    bad |= HYPRE_PCGGetConverged(pcg, &conv);
    bad |= HYPRE_IJVectorGetValues(xv, n, rows, x);
    *iterations = (long)it;
    if (!bad)
        rc = conv ? 0 : 1;
out:
    if (pcg)
        HYPRE_ParCSRPCGDestroy(pcg);
    if (amg)
        HYPRE_BoomerAMGDestroy(amg);
    if (xv)
        HYPRE_IJVectorDestroy(xv);
    if (bv)
        HYPRE_IJVectorDestroy(bv);
    if (A)
        HYPRE_IJMatrixDestroy(A);
    HYPRE_ClearAllErrors();
    free(rows);
    free(ncols);
    free(cols);
    free(vals);
    return rc;
}

int sph_mps_amg_solve(const sph_mps_ppe *S, const double *b, double *x, double tol, long maxit,
                      long *iterations)
{
    *iterations = 0;
    if (S->n == 0)
        return 0;
    pthread_mutex_lock(&amg_lock);
    const int rc = amg_locked(S, b, x, tol, maxit, iterations);
    pthread_mutex_unlock(&amg_lock);
    return rc;
}
