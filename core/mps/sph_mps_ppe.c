#include "sph_mps_ppe.h"

#include "sph_mps_ops.h"
#include "sph_particles.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Dot products sum blocks of this many entries, then the block sums in order. */
#define DOT_BLOCK 2048

static int grow(void **p, long need, size_t size)
{
    void *q = realloc(*p, (size_t)(need > 0 ? need : 1) * size);
    if (!q)
        return -1;
    *p = q;
    return 0;
}

static int reserve_particles(sph_mps_ppe *S, long np)
{
    if (np <= S->cap_part)
        return 0;
    const long cap = np + np / 4 + 16;
    if (grow((void **)&S->row, cap, sizeof(int)) || grow((void **)&S->part, cap, sizeof(int)) ||
        grow((void **)&S->flag, cap, 1) || grow((void **)&S->queue, cap, sizeof(int)))
        return -1;
    S->cap_part = cap;
    return 0;
}

static int reserve_unknowns(sph_mps_ppe *S, long n)
{
    if (n <= S->cap_n)
        return 0;
    const long cap = n + n / 4 + 16;
    if (grow((void **)&S->ptr, cap + 1, sizeof(long)) ||
        grow((void **)&S->lend, cap, sizeof(long)) || grow((void **)&S->lbeg, cap, sizeof(long)) ||
        grow((void **)&S->diag, cap, sizeof(double)) ||
        grow((void **)&S->ldiag, cap, sizeof(double)) ||
        grow((void **)&S->partial, cap / DOT_BLOCK + 1, sizeof(double)))
        return -1;
    for (int v = 0; v < 6; v++)
        if (grow((void **)&S->w[v], cap, sizeof(double)))
            return -1;
    S->cap_n = cap;
    return 0;
}

static int reserve_entries(sph_mps_ppe *S, long nnz)
{
    if (nnz <= S->cap_nnz)
        return 0;
    const long cap = nnz + nnz / 4 + 16;
    if (grow((void **)&S->col, cap, sizeof(int)) || grow((void **)&S->val, cap, sizeof(double)) ||
        grow((void **)&S->lval, cap, sizeof(double)))
        return -1;
    S->cap_nnz = cap;
    return 0;
}

/* flag bits */
enum { F_CAND = 1, F_SEEN = 2, F_SURF = 4 };

/* The fluid and wall neighbours of i within re, in list order: BODY runs with j and r2 set. */
#define FOR_PRESSURE_NEIGHBOURS(L, i, BODY)                                                        \
    for (long e_ = (L)->ptr[i]; e_ < (L)->ptr[(i) + 1]; e_++) {                                    \
        const long j = (L)->j[e_];                                                                 \
        if (kind[j] > maxk)                                                                        \
            continue;                                                                              \
        const double dx_ = x[j] - x[i], dy_ = y[j] - y[i];                                         \
        const double r2 = dx_ * dx_ + dy_ * dy_;                                                   \
        if (r2 >= re2)                                                                             \
            continue;                                                                              \
        BODY                                                                                       \
    }

static inline __attribute__((always_inline)) double weight(sph_kernel_type T, const sph_kernel *k,
                                                           double r2)
{
    const double r = sqrt(r2), rmin = SPH_MPS_RMIN * k->support;
    double d;
    return sph_kernel_eval_t(T, k, r > rmin ? r : rmin, &d);
}

static inline __attribute__((always_inline)) void
fill_generic(sph_kernel_type T, sph_mps_ppe *S, const sph_mps_nbr *L, const double *restrict x,
             const double *restrict y, const unsigned char *restrict kind,
             const double *restrict ghost, const sph_kernel *k, double c, int maxk)
{
    const long n = S->n;
    const double re2 = k->support * k->support;
    const int *row = S->row;
#pragma omp parallel for schedule(dynamic, SPH_OMP_CHUNK) if (n >= SPH_OMP_MIN)
    for (long u = 0; u < n; u++) {
        const long i = S->part[u];
        long e = S->ptr[u];
        double d = 0.0;
        FOR_PRESSURE_NEIGHBOURS(L, i, {
            const double w = c * weight(T, k, r2);
            d += w;
            if (row[j] >= 0) {
                S->col[e] = row[j];
                S->val[e] = -w;
                e++;
            }
        })
        S->diag[u] = d + (ghost ? ghost[i] : 0.0);
        /* the lists are in ascending particle order and unknowns are numbered in particle
         * order, so the columns are ascending: the lower part is a prefix */
        long le = S->ptr[u];
        while (le < e && S->col[le] < u)
            le++;
        S->lend[u] = le;
    }
}

int sph_mps_ppe_assemble(sph_mps_ppe *S, const sph_mps_nbr *L, const double *x, const double *y,
                         const unsigned char *kind, const unsigned char *surface,
                         const sph_kernel *k, double c)
{
    return sph_mps_ppe_assemble_kinds(S, L, x, y, kind, surface, NULL, k, c, SPH_MPS_WALL);
}

int sph_mps_ppe_assemble_kinds(sph_mps_ppe *S, const sph_mps_nbr *L, const double *x,
                               const double *y, const unsigned char *kind,
                               const unsigned char *surface, const double *ghost,
                               const sph_kernel *k, double c, int maxk)
{
    const long np = L->n;
    const double re2 = k->support * k->support;
    S->n = 0;
    S->nnz = 0;
    S->np = 0;
    S->factored = 0;
    if (reserve_particles(S, np))
        return -1;
    S->np = np;
    unsigned char *flag = S->flag;
    /* candidates (fluid and wall, not on the surface); those next to the surface are seeds */
    long nsurf = 0;
    for (long i = 0; i < np; i++) {
        flag[i] = 0;
        if (kind[i] <= maxk)
            flag[i] = surface[i] && !(ghost && ghost[i] > 0.0) ? F_SURF : F_CAND;
        nsurf += surface[i] && kind[i] <= maxk;
    }
    /* breadth-first search from the seeds over candidate-candidate edges (serial, in particle
     * order: deterministic) */
    int *queue = S->queue;
    long head = 0, tail = 0;
    for (long i = 0; i < np; i++) {
        if (!(flag[i] & F_CAND))
            continue;
        int seed = ghost && surface[i] && ghost[i] > 0.0; /* a row of its own dominance */
        if (!seed) {
            FOR_PRESSURE_NEIGHBOURS(L, i, {
                (void)r2;
                if (flag[j] & F_SURF) {
                    seed = 1;
                    break;
                }
            })
        }
        if (seed) {
            flag[i] |= F_SEEN;
            queue[tail++] = (int)i;
        }
    }
    while (head < tail) {
        const long i = queue[head++];
        FOR_PRESSURE_NEIGHBOURS(L, i, {
            (void)r2;
            if ((flag[j] & (F_CAND | F_SEEN)) == F_CAND) {
                flag[j] |= F_SEEN;
                queue[tail++] = (int)j;
            }
        })
    }
    /* number the unknowns in particle order; count their entries */
    long n = 0, isolated = 0;
    for (long i = 0; i < np; i++) {
        S->row[i] = -1;
        if ((flag[i] & (F_CAND | F_SEEN)) == (F_CAND | F_SEEN))
            S->row[i] = (int)n++;
        else if (flag[i] & F_CAND)
            isolated++;
    }
    S->surface = nsurf;
    S->isolated = isolated;
    if (reserve_unknowns(S, n))
        return -1;
    for (long i = 0; i < np; i++)
        if (S->row[i] >= 0)
            S->part[S->row[i]] = (int)i;
    const int *row = S->row;
#pragma omp parallel for schedule(dynamic, SPH_OMP_CHUNK) if (n >= SPH_OMP_MIN)
    for (long u = 0; u < n; u++) {
        const long i = S->part[u];
        long cnt = 0;
        FOR_PRESSURE_NEIGHBOURS(L, i, {
            (void)r2;
            cnt += row[j] >= 0;
        })
        S->ptr[u + 1] = cnt;
    }
    S->ptr[0] = 0;
    for (long u = 0; u < n; u++)
        S->ptr[u + 1] += S->ptr[u];
    if (reserve_entries(S, S->ptr[n]))
        return -1;
    S->n = n;
    S->nnz = S->ptr[n];
#define FILL(T) fill_generic(T, S, L, x, y, kind, ghost, k, c, maxk)
    SPH_KERNEL_DISPATCH(k->type, FILL);
#undef FILL
    return 0;
}

/* ---- vector kernels ------------------------------------------------------------------------ */

void sph_mps_ppe_matvec(const sph_mps_ppe *S, const double *restrict xv, double *restrict yv)
{
    const long n = S->n;
    const long *ptr = S->ptr;
    const int *col = S->col;
    const double *val = S->val, *diag = S->diag;
#pragma omp parallel for schedule(dynamic, SPH_OMP_CHUNK) if (n >= SPH_OMP_MIN)
    for (long u = 0; u < n; u++) {
        double s = diag[u] * xv[u];
        for (long e = ptr[u]; e < ptr[u + 1]; e++)
            s += val[e] * xv[col[e]];
        yv[u] = s;
    }
}

/* sum a_u b_u: per block in order, then the blocks in order (thread-count independent) */
static double dot(const sph_mps_ppe *S, const double *restrict a, const double *restrict b)
{
    const long n = S->n, nb = (n + DOT_BLOCK - 1) / DOT_BLOCK;
    double *partial = S->partial;
#pragma omp parallel for schedule(dynamic, 1) if (n >= SPH_OMP_MIN)
    for (long blk = 0; blk < nb; blk++) {
        const long u1 = (blk + 1) * DOT_BLOCK < n ? (blk + 1) * DOT_BLOCK : n;
        double s = 0.0;
        for (long u = blk * DOT_BLOCK; u < u1; u++)
            s += a[u] * b[u];
        partial[blk] = s;
    }
    double s = 0.0;
    for (long blk = 0; blk < nb; blk++)
        s += partial[blk];
    return s;
}

/* The unknowns of block b of nb: [*u0, *u1). */
static void block_range(long n, int nb, int b, long *u0, long *u1)
{
    const long size = (n + nb - 1) / nb;
    *u0 = (long)b * size < n ? (long)b * size : n;
    *u1 = (long)(b + 1) * size < n ? (long)(b + 1) * size : n;
}

/* IC(0) of the rows [u0, u1), the entries of columns below u0 left out (lbeg[u]: the first
 * entry of row u kept). */
static void factor_block(sph_mps_ppe *S, long u0, long u1)
{
    const long *ptr = S->ptr, *lend = S->lend;
    long *lbeg = S->lbeg;
    const int *col = S->col;
    const double *val = S->val;
    double *l = S->lval, *ld = S->ldiag;
    for (long u = u0; u < u1; u++) {
        long e0 = ptr[u];
        while (e0 < lend[u] && col[e0] < u0)
            e0++;
        lbeg[u] = e0;
    }
    for (long u = u0; u < u1; u++) {
        double dsum = 0.0;
        for (long e = lbeg[u]; e < lend[u]; e++) {
            const long v = col[e];
            double s = val[e];
            /* minus sum over m < v of L_um L_vm: merge row u's and row v's lower entries */
            long a = lbeg[u], b = lbeg[v];
            while (a < e && b < lend[v]) {
                if (col[a] == col[b])
                    s -= l[a++] * l[b++];
                else if (col[a] < col[b])
                    a++;
                else
                    b++;
            }
            l[e] = s / ld[v];
            dsum += l[e] * l[e];
        }
        const double piv = S->diag[u] - dsum;
        /* never below zero for an M-matrix; guarded all the same (the factor stays usable) */
        ld[u] = sqrt(piv > 1e-12 * S->diag[u] ? piv : S->diag[u]);
    }
}

/* Solves L L^T z = r over the rows [u0, u1) of a factor_block() factor. */
static void solve_block(const sph_mps_ppe *S, long u0, long u1, const double *restrict r,
                        double *restrict z)
{
    const long *lbeg = S->lbeg, *lend = S->lend;
    const int *col = S->col;
    const double *l = S->lval, *ld = S->ldiag;
    for (long u = u0; u < u1; u++) { /* L y = r */
        double s = r[u];
        for (long e = lbeg[u]; e < lend[u]; e++)
            s -= l[e] * z[col[e]];
        z[u] = s / ld[u];
    }
    for (long u = u1 - 1; u >= u0; u--) { /* L^T z = y */
        const double zu = z[u] / ld[u];
        z[u] = zu;
        for (long e = lbeg[u]; e < lend[u]; e++)
            z[col[e]] -= l[e] * zu;
    }
}

/* The blocks of IC(0) (one: the plain factor) and of block IC(0). */
static int ic_blocks(sph_mps_precond pc)
{
    return pc == SPH_MPS_PC_BIC0 ? SPH_MPS_BIC0_BLOCKS : 1;
}

/* The factor in nb blocks, in parallel when there are several. */
static void factor_blocks(sph_mps_ppe *S, int nb)
{
    const long n = S->n;
#pragma omp parallel for schedule(dynamic, 1) if (nb > 1 && n >= SPH_OMP_MIN)
    for (int b = 0; b < nb; b++) {
        long u0, u1;
        block_range(n, nb, b, &u0, &u1);
        factor_block(S, u0, u1);
    }
    S->factored = nb;
}

void sph_mps_ppe_factor(sph_mps_ppe *S)
{
    factor_blocks(S, 1);
}

/* z = M^-1 r */
static void precondition(const sph_mps_ppe *S, sph_mps_precond pc, const double *restrict r,
                         double *restrict z)
{
    const long n = S->n;
    if (pc == SPH_MPS_PC_JACOBI) {
        const double *diag = S->diag;
#pragma omp parallel for schedule(dynamic, SPH_OMP_CHUNK) if (n >= SPH_OMP_MIN)
        for (long u = 0; u < n; u++)
            z[u] = r[u] / diag[u];
    } else if (pc == SPH_MPS_PC_IC0 || pc == SPH_MPS_PC_BIC0) {
        const int nb = ic_blocks(pc);
#pragma omp parallel for schedule(dynamic, 1) if (nb > 1 && n >= SPH_OMP_MIN)
        for (int b = 0; b < nb; b++) {
            long u0, u1;
            block_range(n, nb, b, &u0, &u1);
            solve_block(S, u0, u1, r, z);
        }
    } else {
        memcpy(z, r, (size_t)n * sizeof *z);
    }
}

/* p per particle from the unknowns' x (0 for every particle that is not an unknown). */
static void scatter(const sph_mps_ppe *S, const double *xv, double *p)
{
    const long np = S->np;
    const int *row = S->row;
#pragma omp parallel for schedule(dynamic, SPH_OMP_CHUNK) if (np >= SPH_OMP_MIN)
    for (long i = 0; i < np; i++)
        p[i] = row[i] >= 0 ? xv[row[i]] : 0.0;
}

/* ||b - A x|| / bnorm over the unknowns; r = b - A x, q scratch. */
static double residual_of(const sph_mps_ppe *S, const double *b, const double *xv, double *r,
                          double *q, double bnorm)
{
    const long n = S->n;
    sph_mps_ppe_matvec(S, xv, q);
#pragma omp parallel for schedule(dynamic, SPH_OMP_CHUNK) if (n >= SPH_OMP_MIN)
    for (long u = 0; u < n; u++)
        r[u] = b[u] - q[u];
    return sqrt(dot(S, r, r)) / bnorm;
}

/* SPH_MPS_PC_AMG: hypre's CG and BoomerAMG (sph_mps_amg.c) on b, the warm start xv; the
 * residual reported is recomputed here, as sphd's CG defines it. */
static int solve_amg(sph_mps_ppe *S, const double *b, double *xv, double bnorm, double tol,
                     long maxit, sph_mps_cg_stats *st, double *p)
{
#ifdef SPH_HYPRE
    double *r = S->w[2], *q = S->w[5];
    int rc = 0;
    st->residual = residual_of(S, b, xv, r, q, bnorm);
    if (st->residual > tol) { /* hypre's CG always iterates: not on a start that meets tol */
        rc = sph_mps_amg_solve(S, b, xv, tol, maxit, &st->iterations);
        if (rc < 0)
            return -2;
        st->residual = residual_of(S, b, xv, r, q, bnorm);
    }
    st->converged = rc == 0;
    scatter(S, xv, p);
    return rc;
#else
    (void)S, (void)b, (void)xv, (void)bnorm, (void)tol, (void)maxit, (void)st, (void)p;
    return -2; /* refused before: sph_mps_amg_available() */
#endif
}

int sph_mps_amg_available(void)
{
#ifdef SPH_HYPRE
    return 1;
#else
    return 0;
#endif
}

int sph_mps_ppe_solve(sph_mps_ppe *S, const double *rhs, double *p, sph_mps_precond pc, double tol,
                      long maxit, sph_mps_cg_stats *st)
{
    const long n = S->n;
    double *b = S->w[0], *xv = S->w[1], *r = S->w[2], *z = S->w[3], *d = S->w[4], *q = S->w[5];
    st->iterations = 0;
    st->residual = 0.0;
    st->converged = 1;
    const int *part = S->part;
#pragma omp parallel for schedule(dynamic, SPH_OMP_CHUNK) if (n >= SPH_OMP_MIN)
    for (long u = 0; u < n; u++) {
        b[u] = rhs[part[u]];
        xv[u] = p[part[u]];
    }
    const double bnorm = sqrt(dot(S, b, b));
    int rc = 0;
    if (bnorm == 0.0) {
        memset(xv, 0, (size_t)n * sizeof *xv);
    } else {
        if (pc == SPH_MPS_PC_AMG)
            return solve_amg(S, b, xv, bnorm, tol, maxit, st, p);
        if ((pc == SPH_MPS_PC_IC0 || pc == SPH_MPS_PC_BIC0) && S->factored != ic_blocks(pc))
            factor_blocks(S, ic_blocks(pc));
        double res = residual_of(S, b, xv, r, q, bnorm);
        long it = 0;
        if (res > tol) {
            precondition(S, pc, r, z);
            memcpy(d, z, (size_t)n * sizeof *d);
            double rz = dot(S, r, z);
            while (it < maxit) {
                sph_mps_ppe_matvec(S, d, q);
                const double alpha = rz / dot(S, d, q);
#pragma omp parallel for schedule(dynamic, SPH_OMP_CHUNK) if (n >= SPH_OMP_MIN)
                for (long u = 0; u < n; u++) {
                    xv[u] += alpha * d[u];
                    r[u] -= alpha * q[u];
                }
                it++;
                res = sqrt(dot(S, r, r)) / bnorm;
                if (!(res > tol)) /* also stops on NaN */
                    break;
                precondition(S, pc, r, z);
                const double rz1 = dot(S, r, z);
                const double beta = rz1 / rz;
                rz = rz1;
#pragma omp parallel for schedule(dynamic, SPH_OMP_CHUNK) if (n >= SPH_OMP_MIN)
                for (long u = 0; u < n; u++)
                    d[u] = z[u] + beta * d[u];
            }
        }
        st->iterations = it;
        st->residual = res;
        st->converged = res <= tol;
        rc = st->converged ? 0 : 1;
    }
    scatter(S, xv, p);
    return rc;
}

void sph_mps_ppe_free(sph_mps_ppe *S)
{
    void *all[] = {S->lbeg, S->ptr,  S->lend,    S->col,  S->val,  S->diag, S->row,
                   S->part, S->lval, S->ldiag,   S->w[0], S->w[1], S->w[2], S->w[3],
                   S->w[4], S->w[5], S->partial, S->flag, S->queue};
    for (size_t i = 0; i < sizeof all / sizeof all[0]; i++)
        free(all[i]);
    memset(S, 0, sizeof *S);
}

double sph_mps_ppe_bytes(const sph_mps_ppe *S)
{
    return (double)S->cap_part * (2 * sizeof(int) + 1 + sizeof(int)) +
           (double)S->cap_n * (3 * sizeof(long) + 8 * sizeof(double)) +
           (double)S->cap_nnz * (sizeof(int) + 2 * sizeof(double));
}

static const char *const pc_names[] = {"none", "jacobi", "ic0", "amg", "bic0"};
#define NPC (int)(sizeof pc_names / sizeof pc_names[0])

const char *sph_mps_precond_name(sph_mps_precond pc)
{
    return (unsigned)pc < NPC ? pc_names[pc] : NULL;
}

int sph_mps_precond_from_name(const char *name)
{
    for (int i = 0; i < NPC; i++)
        if (strcmp(name, pc_names[i]) == 0)
            return i;
    return -1;
}
