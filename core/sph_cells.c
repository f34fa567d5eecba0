#include "sph_cells.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static int axis_cells(double lo, double hi, double size)
{
    return (int)ceil((hi - lo) / size) + 2; /* plus one padding cell at each end */
}

double sph_cells_count(const double lo[2], const double hi[2], double size)
{
    return ((hi[0] - lo[0]) / size + 3.0) * ((hi[1] - lo[1]) / size + 3.0);
}

int sph_cells_alloc(sph_cells *g, const double lo[2], const double hi[2], double size, long n)
{
    memset(g, 0, sizeof *g);
    g->size = size;
    g->inv_size = 1.0 / size;
    g->nx = axis_cells(lo[0], hi[0], size);
    g->ny = axis_cells(lo[1], hi[1], size);
    g->x0 = lo[0] - size;
    g->y0 = lo[1] - size;
    g->ncells = (long)g->nx * g->ny;
    g->start = calloc((size_t)g->ncells + 2, sizeof *g->start);
    g->key = calloc((size_t)(n > 0 ? n : 1), sizeof *g->key);
    g->perm = calloc((size_t)(n > 0 ? n : 1), sizeof *g->perm);
    if (!g->start || !g->key || !g->perm) {
        sph_cells_free(g);
        return -1;
    }
    return 0;
}

void sph_cells_free(sph_cells *g)
{
    free(g->start);
    free(g->key);
    free(g->perm);
    memset(g, 0, sizeof *g);
}

long sph_cells_sort(sph_cells *g, sph_particles *P)
{
    const long n = P->n, ncells = g->ncells;
    const int nx = g->nx, ny = g->ny;
    int *restrict key = g->key;
#pragma omp parallel for schedule(static) if (n >= SPH_OMP_MIN)
    for (long i = 0; i < n; i++) {
        const double fx = (P->x[i] - g->x0) * g->inv_size, fy = (P->y[i] - g->y0) * g->inv_size;
        int k = (int)ncells;
        /* the comparisons are false for NaN: a non-finite particle is lost, never indexed */
        if (P->type[i] != SPH_LOST && fx >= 1.0 && fx < nx - 1.0 && fy >= 1.0 && fy < ny - 1.0)
            k = (int)fx * ny + (int)fy;
        else
            P->type[i] = SPH_LOST;
        key[i] = k;
    }
    long *restrict start = g->start;
    memset(start, 0, (size_t)(ncells + 2) * sizeof *start);
    for (long i = 0; i < n; i++)
        start[key[i] + 1]++;
    for (long c = 0; c <= ncells; c++)
        start[c + 1] += start[c];
    /* stable scatter: start[c] walks through cell c, then is restored */
    long moved = 0;
    for (long i = 0; i < n; i++) {
        const long to = start[key[i]]++;
        g->perm[to] = i;
        moved += to != i;
    }
    for (long c = ncells; c > 0; c--)
        start[c] = start[c - 1];
    start[0] = 0;
    const int sorted = moved == 0;
    if (!sorted)
        sph_particles_permute(P, g->perm);
    return start[ncells];
}
