#include "sph_cells.h"

#include <math.h>
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
    g->key = calloc((size_t)(n > 0 ? n : 1), sizeof *g->key);
    g->perm = calloc((size_t)(n > 0 ? n : 1), sizeof *g->perm);
    g->cap = n > 0 ? n : 1;
    if (!g->start || !g->key || !g->perm) {
        sph_cells_free(g);
        return -1;
    }
    return 0;
}

void sph_cells_free(sph_cells *g)
{
    free(g->counts);
    free(g->key);
    free(g->perm);
    memset(g, 0, sizeof *g);
}

int sph_cells_reserve(sph_cells *g, long n)
{
    if (n <= g->cap)
        return 0;
    int *key = realloc(g->key, (size_t)n * sizeof *key);
    if (!key)
        return -1;
    g->key = key;
    long *perm = realloc(g->perm, (size_t)n * sizeof *perm);
    if (!perm)
        return -1;
    g->perm = perm;
    g->cap = n;
    return 0;
}

/* Particle i's cell (ncells for a lost particle, and for one outside the grid, which becomes
 * lost). The loops over the particles are written once per dimension (cell_keys2, cell_keys3),
 * the dimension a literal there: an OpenMP loop in a function that takes D outlines its body
 * before D is known, and tests D per particle. */
static inline __attribute__((always_inline)) int cell_key(const int D, const sph_cells *g,
                                                          sph_particles *P, long i)
{
    const double fx = (P->x[i] - g->x0) * g->inv_size, fy = (P->y[i] - g->y0) * g->inv_size;
    const double fz = D == 3 ? (P->z[i] - g->z0) * g->inv_size : 1.0;
    const int nx = g->nx, ny = g->ny, nz = g->nz;
    /* the comparisons are false for NaN: a non-finite particle is lost, never indexed */
    if (P->type[i] != SPH_LOST && fx >= 1.0 && fx < nx - 1.0 && fy >= 1.0 && fy < ny - 1.0 &&
        (D == 2 || (fz >= 1.0 && fz < nz - 1.0)))
        return D == 3 ? ((int)fx * ny + (int)fy) * nz + (int)fz : (int)fx * ny + (int)fy;
    P->type[i] = SPH_LOST;
    return (int)g->ncells;
}

/* Each particle's cell into g->key: cell_keys2 and cell_keys3 (D a literal there). The grid is
 * copied into each thread (firstprivate), so that its constants stay in registers: the store of
 * a lost particle's type, a char, may alias anything read through g. */
/* clang-format off */
#define SPH_CELL_KEYS(D)                                                                           \
    static void cell_keys##D(sph_cells *g, sph_particles *P)                                       \
    {                                                                                              \
        const long n = P->n;                                                                       \
        int *restrict key = g->key;                                                                \
        const sph_cells grid = *g;                                                                 \
        _Pragma("omp parallel for schedule(dynamic, SPH_OMP_CHUNK) firstprivate(grid) if (n >= SPH_OMP_MIN)") \
        for (long i = 0; i < n; i++)                                                               \
            key[i] = cell_key(D, &grid, P, i);                                                     \
    }
/* clang-format on */
SPH_CELL_KEYS(2)
SPH_CELL_KEYS(3)

long sph_cells_sort(sph_cells *g, sph_particles *P)
{
    const long n = P->n, ncells = g->ncells;
    const int *restrict key = g->key;
    if (g->dim == 3)
        cell_keys3(g, P);
    else
        cell_keys2(g, P);
    /* counts[k + 2]: particles in cell k; the prefix sum makes it the end of cell k; the
     * backward scatter moves it down to the beginning of cell k, so that start = counts + 2
     * holds the beginnings, start[ncells] the active count and start[ncells + 1] = n. Stable:
     * particles of one cell keep their order. */
    int *restrict counts = g->counts;
    const long nc = ncells + 4;
#pragma omp parallel for schedule(dynamic, SPH_OMP_CHUNK) if (nc >= 16 * SPH_OMP_MIN)
    for (long c = 0; c < nc; c++)
        counts[c] = 0;
    for (long i = 0; i < n; i++)
        counts[key[i] + 2]++;
    for (long c = 0; c + 1 < nc; c++)
        counts[c + 1] += counts[c];
    long moved = 0;
    for (long i = n - 1; i >= 0; i--) {
        const long to = --counts[key[i] + 2];
        g->perm[to] = i;
        moved += to != i;
    }
    const int sorted = moved == 0;
    if (!sorted)
        sph_particles_permute(P, g->perm);
    const int *start = g->start;
    return start[ncells];
}
