/*
 * sph_mps_ppe: the pressure Poisson equation of MPS and its linear solve.
 *
 * The equation (Koshizuka & Oka 1996): lap p_i = -(rho / dt^2) (n*_i - n0) / n0, with the
 * Laplacian model (3.5). Written as A p = b with
 *
 *     A_ii = c sum_j w_ij,   A_ij = -c w_ij (j an unknown),   c = 2d / (lambda n0),
 *
 * the sums over the fluid and wall neighbours j of i within re (dummy particles carry no
 * pressure). The unknowns are the fluid and wall particles that are not on the free surface;
 * free-surface particles (the caller's `surface` flags, n* < beta n0) are Dirichlet nodes with
 * p = 0: they drop out of the system but stay in the diagonal sums. Unknowns with no path
 * through the neighbour graph to any free-surface particle (a closed cluster) would make A
 * singular: they are found by a breadth-first search from the unknowns next to the surface,
 * get p = 0 and are counted in `isolated`.
 *
 * Symmetric: w_ij and w_ji are computed from the same r^2 = dx^2 + dy^2, whose terms only change
 * sign between the two orders, so A_ij and A_ji are bitwise equal (tested). Positive definite:
 * A is a weakly diagonally dominant M-matrix, strictly dominant in the rows next to a Dirichlet
 * node, and every unknown is connected to one of those rows (the search above), so A is
 * irreducibly diagonally dominant, hence nonsingular, and being symmetric with a positive
 * diagonal, positive definite.
 *
 * The system is assembled as a sparse matrix in compressed rows (off-diagonals in ascending
 * column order, the diagonal apart) and solved by preconditioned conjugate gradients: none,
 * Jacobi (the diagonal) or IC(0) (incomplete Cholesky on A's own pattern; it exists for M-matrices,
 * Meijerink & van der Vorst 1977), or by hypre's CG with an algebraic multigrid V-cycle (AMG,
 * sph_mps_amg.c; builds with -DSPH_HYPRE=ON). Warm start from the caller's p. Converged when
 * ||b - A p||_2 <= tol ||b||_2. Parallel with OpenMP (matrix-vector product and vector updates
 * by rows; dot products as partial sums over fixed blocks of 2048 entries added in block order,
 * so the result is bitwise the same with any number of threads); the IC(0) factorisation and its
 * triangular solves are serial, block IC(0)'s (block Jacobi over SPH_MPS_BIC0_BLOCKS IC(0)
 * blocks) run a block per thread.
 */
#ifndef SPH_MPS_PPE_H
#define SPH_MPS_PPE_H

#include "sph_mps_nbr.h"
#include "sph_kernel.h"

typedef enum {
    SPH_MPS_PC_NONE = 0,
    SPH_MPS_PC_JACOBI,
    SPH_MPS_PC_IC0,
    SPH_MPS_PC_AMG, /* hypre's CG with a BoomerAMG V-cycle: builds with -DSPH_HYPRE=ON only */
    SPH_MPS_PC_BIC0 /* block IC(0): SPH_MPS_BIC0_BLOCKS independent factors, solved in parallel */
} sph_mps_precond;

/* Block IC(0) cuts the unknowns (in particle order: cell order, so the blocks are slabs of the
 * domain) into this many contiguous blocks, whatever the number of threads, and drops the
 * entries that couple two blocks: each block is factored and solved on its own, in parallel. A
 * fixed count keeps the results the same with any number of threads. Measured on Koshizuka &
 * Oka's dam break at L/80 (bench_mps_dambreak, 12,800 unknowns): CG iterations per step 86 with
 * IC(0), 102, 110, 125 and 149 with 2, 4, 8 and 16 blocks; 4 was the fastest on 2 threads (25.8
 * ms a step against IC(0)'s 31.7), and caps the triangular solves at 4 threads. */
#define SPH_MPS_BIC0_BLOCKS 4

typedef struct sph_mps_cg_stats {
    long iterations; /* CG iterations of the latest solve [-] */
    double residual; /* ||b - A p|| / ||b|| at its end [-] */
    int converged;   /* 1 if residual <= tol */
} sph_mps_cg_stats;

typedef struct sph_mps_ppe {
    long np;             /* particles of the latest assembly [-] */
    long n;              /* unknowns [-] */
    long nnz;            /* off-diagonal entries [-] */
    long *ptr;           /* n + 1 row offsets into col, val */
    long *lend;          /* n: end of the entries of row u with col < u */
    long *lbeg;          /* n: the first of them the IC(0) factor keeps (block IC(0): in u's
                            block) */
    int *col;            /* off-diagonal columns (unknown indices), ascending per row */
    double *val;         /* off-diagonal values [1/m^2] */
    double *diag;        /* diagonal [1/m^2] */
    int *row;            /* per particle: its unknown, or -1 */
    int *part;           /* per unknown: its particle */
    long surface;        /* Dirichlet (free-surface) particles of the latest assembly [-] */
    long isolated;       /* pressure particles cut off from every free surface: p = 0 [-] */
    int factored;        /* lval, ldiag hold the current matrix's IC(0) factor in this many
                            blocks (1: IC(0), SPH_MPS_BIC0_BLOCKS: block IC(0)); 0: none */
    double *lval;        /* IC(0): strictly lower factor entries, parallel to val */
    double *ldiag;       /* IC(0): factor diagonal */
    double *w[6];        /* CG vectors: b, x, r, z, d, q */
    double *partial;     /* dot-product block sums */
    unsigned char *flag; /* per particle scratch of the search */
    int *queue;          /* per particle scratch of the search */
    long cap_part, cap_n, cap_nnz; /* allocated sizes */
} sph_mps_ppe;

/* Assembles A for particles [0, L->n) from their neighbour lists: kind per particle
 * (SPH_MPS_* of sph_mps_ops.h), surface[i] != 0 for Dirichlet particles, weight k with radius
 * re, c = 2d/(lambda n0). Returns 0 or -1 when out of memory. */
int sph_mps_ppe_assemble(sph_mps_ppe *S, const sph_mps_nbr *L, const double *x, const double *y,
                         const unsigned char *kind, const unsigned char *surface,
                         const sph_kernel *k, double c);

/* The same with the pressure particles those of kind <= maxk: SPH_MPS_WALL (the above: walls are
 * unknowns), or SPH_MPS_FLUID (walls are no unknowns and drop out of A altogether, diagonal
 * included: the caller puts their Neumann terms in b). ghost: NULL, or per particle the
 * diagonal term [1/m^2] of a surface particle's missing neighbours whose pressures are
 * extrapolated to p = 0 beyond it (sph_mps.c): a surface particle with ghost[i] > 0 is then an
 * unknown with that term added to A_ii (its row strictly diagonally dominant, like the rows
 * next to a Dirichlet node), one with ghost[i] <= 0 stays a Dirichlet node. */
int sph_mps_ppe_assemble_kinds(sph_mps_ppe *S, const sph_mps_nbr *L, const double *x,
                               const double *y, const unsigned char *kind,
                               const unsigned char *surface, const double *ghost,
                               const sph_kernel *k, double c, int maxk);

/* Solves A p = b for the latest assembly; rhs and p are per particle. p holds the starting
 * guess on entry (its unknowns' entries; warm start), the solution on return, and 0 for every
 * particle that is not an unknown. Returns 0 when converged, 1 when maxit iterations did not
 * reach tol (p then holds the last iterate), -1 when out of memory, -2 when the AMG solve failed
 * (hypre or MPI: sph_mps_amg_solve) or is not in this build. */
int sph_mps_ppe_solve(sph_mps_ppe *S, const double *rhs, double *p, sph_mps_precond pc, double tol,
                      long maxit, sph_mps_cg_stats *st);

/* Computes the IC(0) factor of the latest assembly (sph_mps_ppe_solve does it when it needs
 * it; apart, it can be timed apart: benchmarks). Clear S->factored first to compute it again. */
void sph_mps_ppe_factor(sph_mps_ppe *S);

/* y = A x over the unknowns (for tests). */
void sph_mps_ppe_matvec(const sph_mps_ppe *S, const double *x, double *y);

void sph_mps_ppe_free(sph_mps_ppe *S);

/* Bytes held. */
double sph_mps_ppe_bytes(const sph_mps_ppe *S);

/* 1 if this build has SPH_MPS_PC_AMG (-DSPH_HYPRE=ON), else 0: sph_mps_ppe_solve then fails
 * with -1 for it. */
int sph_mps_amg_available(void);

/* sph_mps_amg.c (with SPH_HYPRE only): A x = b over the unknowns of the latest assembly, x the
 * warm start on entry, by hypre's CG to ||b - A x|| <= tol ||b|| with one BoomerAMG V-cycle as
 * the preconditioner. Returns 0 when converged, 1 when maxit iterations did not reach tol, -1
 * when hypre failed or memory ran out. Thread-safe (the solves take turns). */
int sph_mps_amg_solve(const sph_mps_ppe *S, const double *b, double *x, double tol, long maxit,
                      long *iterations);

/* sph_mps_amg.c: once at the start of a program, before its threads (sph_core_init). */
void sph_mps_amg_process_init(void);

/* Case-file name of a preconditioner ("none", "jacobi", "ic0", "amg", "bic0") and back (-1 if
 * unknown). */
const char *sph_mps_precond_name(sph_mps_precond pc);
int sph_mps_precond_from_name(const char *name);

#endif
