#include "sph_cells.h"

#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>

static int axis_cells(double lo, double hi, double size)
{
    return (int)ceil((hi - lo) / size) + 2; /* plus one padding cell at each end */
}

double sph_cells_count(int dim, const double lo[3], const double hi[3], double size)
{
    double n = 1.0;
    for (int d = 0; d < dim; d++)
        n *= (hi[d] - lo[d]) / size + 3.0;
    return n;
}

int sph_cells_alloc(sph_cells *g, int dim, const double lo[3], const double hi[3], double size,
                    long n)
{
    memset(g, 0, sizeof *g);
    g->dim = dim;
    g->size = size;
    g->inv_size = 1.0 / size;
    g->nx = axis_cells(lo[0], hi[0], size);
    g->ny = axis_cells(lo[1], hi[1], size);
    g->nz = dim == 3 ? axis_cells(lo[2], hi[2], size) : 1;
    g->x0 = lo[0] - size;
    g->y0 = lo[1] - size;
    g->z0 = dim == 3 ? lo[2] - size : 0.0;
    g->ncells = (long)g->nx * g->ny * g->nz;
    g->counts = calloc((size_t)g->ncells + 4, sizeof *g->counts);
    g->start = g->counts ? g->counts + 2 : NULL;
    g->perm = calloc((size_t)(n > 0 ? n : 1), sizeof *g->perm);
    g->cap = n > 0 ? n : 1;
    if (!g->start || !g->perm) {
        sph_cells_free(g);
        return -1;
    }
    return 0;
}

void sph_cells_free(sph_cells *g)
{
    free(g->counts);
    free(g->perm);
    free(g->wet);
    free(g->walls);
    memset(g, 0, sizeof *g);
}

int sph_cells_reserve(sph_cells *g, long n)
{
    if (n <= g->cap)
        return 0;
    int *perm = realloc(g->perm, (size_t)n * sizeof *perm);
    if (!perm)
        return -1;
    g->perm = perm;
    g->cap = n;
    return 0;
}

/* Each particle's cell into key: cell_keys2 and cell_keys3 (D a literal there). The grid is
 * copied into each thread (firstprivate), so that its constants stay in registers: the store of
 * a lost particle's type, a char, may alias anything read through g. */
/* clang-format off */
#define SPH_CELL_KEYS(D)                                                                           \
    static void cell_keys##D(const sph_cells *g, sph_particles *P, int *restrict key)              \
    {                                                                                              \
        const long n = P->n;                                                                       \
        const sph_cells grid = *g;                                                                 \
        _Pragma("omp parallel for schedule(dynamic, SPH_OMP_CHUNK) firstprivate(grid) if (n >= SPH_OMP_MIN)") \
        for (long i = 0; i < n; i++)                                                               \
            key[i] = sph_cells_key(D, &grid, P, i);                                                     \
    }
/* clang-format on */
SPH_CELL_KEYS(2)
SPH_CELL_KEYS(3)

/* 3D: the particles of each cell in the order of their z (stable: insertion sort of the cell's
 * part of perm, which is nearly sorted already from the previous step), so that a column of
 * cells along z is one range sorted by z, which the pair loops cut to the particles within
 * reach of z (sph_wcsph.c). Returns how many particles the whole permutation moves. */
static long sort_cells_by_z(sph_cells *g, const sph_particles *P)
{
    const long n = P->n, ncells = g->ncells;
    const int *restrict start = g->start;
    int *restrict perm = g->perm;
    const double *restrict z = P->z;
    long moved = 0;
#pragma omp parallel for schedule(dynamic, 4096) reduction(+ : moved) if (n >= SPH_OMP_MIN)
    for (long c = 0; c < ncells; c++) {
        const long b = start[c], e = start[c + 1];
        for (long k = b + 1; k < e; k++) {
            const int pk = perm[k];
            const double zk = z[pk];
            long m = k;
            while (m > b && z[perm[m - 1]] > zk) {
                perm[m] = perm[m - 1];
                m--;
            }
            perm[m] = pk;
        }
        for (long k = b; k < e; k++)
            moved += perm[k] != k;
    }
    for (long k = start[ncells]; k < n; k++) /* the lost ones, in the stable sort's order */
        moved += perm[k] != k;
    return moved;
}

long sph_cells_sort(sph_cells *g, sph_particles *P)
{
    const long n = P->n, ncells = g->ncells, nc = ncells + 4;
    /* the cells' keys and the outlier lists (n ints each) in the particles' scratch array (n
     * doubles), free until the permutation below takes it over */
    int *const ws = (int *)P->scratch;
    int *restrict key = ws;
    if (g->dim == 3)
        cell_keys3(g, P, key);
    else
        cell_keys2(g, P, key);
    /* A stable counting sort in parallel passes, no pass over the particles or the cells left
     * serial, and no per-thread copy of the counts. With k = key + 2 (lost particles: k =
     * ncells + 2), counts[k + 1] counts cell k's particles, then holds where its next particle
     * goes, and ends as the beginning of cell k + 1: start = counts + 2 then holds the
     * beginnings of the cells, start[ncells] the active count and start[ncells + 1] = n.
     *
     * Each thread t takes one contiguous chunk of the particles, [lo, hi), and owns the range
     * of k [bnd[t], bnd[t + 1]) that its chunk's first particle opens. The particles are still
     * nearly in cell order from the previous step, so a chunk's particles nearly all fall into
     * its own range; the others (the outliers: particles that crossed into another thread's
     * range, lost ones, and all of them on the first sort) are listed in out[lo ..]. Only the
     * owner of a cell counts and places its particles: those of the outlier lists of the
     * chunks before its own, then its own chunk's, then those of the lists after, each in
     * particle order, so that particles of one cell keep their order: the result is the serial
     * stable sort's, whatever the number of threads. The passes over the cells (zeroing, the
     * prefix sum) are split evenly among the threads, apart from the ownership. */
    int nt = n >= 2 * SPH_OMP_MIN ? omp_get_max_threads() : 1;
    nt = nt < SPH_CELLS_SORT_THREADS ? nt : SPH_CELLS_SORT_THREADS;
    int *restrict counts = g->counts, *restrict out = ws + n;
    int *restrict perm = g->perm;
    long bnd[SPH_CELLS_SORT_THREADS + 1], nout[SPH_CELLS_SORT_THREADS];
    long block[SPH_CELLS_SORT_THREADS];
    long moved = 0;
#pragma omp parallel num_threads(nt) reduction(+ : moved)
    {
        const int t = omp_get_thread_num(), m = omp_get_num_threads();
        const long lo = n * t / m, hi = n * (t + 1) / m;
        const long clo = nc * t / m, chi = nc * (t + 1) / m; /* the even split of the cells */
        memset(counts + clo, 0, (size_t)(chi - clo) * sizeof *counts);
#pragma omp single
        {
            bnd[0] = 0;
            for (int u = 1; u < m; u++) {
                const long k = key[n * u / m] + 2;
                bnd[u] = k > bnd[u - 1] ? k : bnd[u - 1];
            }
            bnd[m] = nc - 1;
        } /* (a barrier: the counts are zero) */
        const long blo = bnd[t], bhi = bnd[t + 1];
        long no = 0;
        for (long i = lo; i < hi; i++) {
            const long k = key[i] + 2;
            if (k >= blo && k < bhi)
                counts[k + 1]++;
            else
                out[lo + no++] = (int)i;
        }
        nout[t] = no;
#pragma omp barrier
        for (int u = 0; u < m; u++) {
            if (u == t)
                continue;
            const int *o = out + n * u / m;
            for (long j = 0; j < nout[u]; j++) {
                const long k = key[o[j]] + 2;
                if (k >= blo && k < bhi)
                    counts[k + 1]++;
            }
        }
#pragma omp barrier
        if (m > 1) { /* each block's total, for the offsets of the blocks after it */
            long sum = 0;
            for (long c = clo; c < chi; c++)
                sum += counts[c];
            block[t] = sum;
#pragma omp barrier
        }
        long off = 0;
        for (int u = 0; u < t; u++)
            off += block[u];
        for (long c = clo; c < chi; c++) {
            const int k = counts[c];
            counts[c] = (int)off;
            off += k;
        }
#pragma omp barrier
        for (int u = 0; u < m; u++) {
            if (u == t) {
                for (long i = lo; i < hi; i++) {
                    const long k = key[i] + 2;
                    if (k >= blo && k < bhi) {
                        const long to = counts[k + 1]++;
                        perm[to] = (int)i;
                        moved += to != i;
                    }
                }
                continue;
            }
            const int *o = out + n * u / m;
            for (long j = 0; j < nout[u]; j++) {
                const long k = key[o[j]] + 2;
                if (k >= blo && k < bhi) {
                    const long to = counts[k + 1]++;
                    perm[to] = o[j];
                    moved += to != o[j];
                }
            }
        }
    }
    if (g->dim == 3)
        moved = sort_cells_by_z(g, P);
    const int sorted = moved == 0;
    if (!sorted)
        sph_particles_permute(P, g->perm);
    const int *start = g->start;
    return start[ncells];
}

/* For each cell, 1 if it holds a particle of type `type`, into *buf (allocated on the first
 * call); returns *buf, or NULL when out of memory. */
static const unsigned char *mark(sph_cells *g, const sph_particles *P, unsigned char type,
                                 unsigned char **buf)
{
    if (!*buf && !(*buf = malloc((size_t)g->ncells)))
        return NULL;
    const long nc = g->ncells;
    const int *start = g->start;
    const unsigned char *restrict types = P->type;
    unsigned char *restrict out = *buf;
#pragma omp parallel for schedule(dynamic, 16 * SPH_OMP_CHUNK) if (P->n >= SPH_OMP_MIN)
    for (long c = 0; c < nc; c++) {
        unsigned char w = 0;
        for (long j = start[c]; j < start[c + 1]; j++)
            w |= types[j] == type;
        out[c] = w;
    }
    return out;
}

const unsigned char *sph_cells_wet(sph_cells *g, const sph_particles *P)
{
    return mark(g, P, SPH_FLUID, &g->wet);
}

const unsigned char *sph_cells_walls(sph_cells *g, const sph_particles *P)
{
    return g->walls ? g->walls : mark(g, P, SPH_BOUNDARY, &g->walls);
}
