#include "sph_mps_nbr.h"

#include <stdlib.h>
#include <string.h>

static int reserve(sph_mps_nbr *L, long n, long entries)
{
    if (n + 1 > L->cap_n) {
        const long cap = n + 1 + n / 4;
        long *p = realloc(L->ptr, (size_t)cap * sizeof *p);
        if (!p)
            return -1;
        L->ptr = p;
        L->cap_n = cap;
    }
    if (entries > L->cap_j) {
        const long cap = entries + entries / 4 + 16;
        int *j = realloc(L->j, (size_t)cap * sizeof *j);
        if (!j)
            return -1;
        L->j = j;
        L->cap_j = cap;
    }
    return 0;
}

/* Visits the neighbours of particle i within rc in the cells around it, in ascending index
 * order: the three cells of a column are one contiguous range of the sorted particles, and the
 * columns come left to right. FILL = 0 counts them, FILL = 1 also stores them at out. */
static inline __attribute__((always_inline)) long visit(int fill, const sph_cells *g,
                                                        const double *restrict x,
                                                        const double *restrict y, long i,
                                                        double rc2, int *restrict out)
{
    int cx, cy;
    sph_cells_of(g, x[i], y[i], &cx, &cy);
    const double xi = x[i], yi = y[i];
    long k = 0;
    for (int c = cx - 1; c <= cx + 1; c++) {
        long jb, je;
        sph_cells_column3(g, c, cy, &jb, &je);
        for (long j = jb; j < je; j++) {
            const double dx = xi - x[j], dy = yi - y[j];
            if (j == i || dx * dx + dy * dy >= rc2)
                continue;
            if (fill)
                out[k] = (int)j;
            k++;
        }
    }
    return k;
}

int sph_mps_nbr_build(sph_mps_nbr *L, const sph_cells *g, const double *x, const double *y, long n,
                      double rc)
{
    L->n = 0;
    L->entries = 0;
    L->rc = rc;
    if (reserve(L, n, 0))
        return -1;
    const double rc2 = rc * rc;
    long *ptr = L->ptr;
#pragma omp parallel for schedule(dynamic, SPH_OMP_CHUNK) if (n >= SPH_OMP_MIN)
    for (long i = 0; i < n; i++)
        ptr[i + 1] = visit(0, g, x, y, i, rc2, NULL);
    ptr[0] = 0;
    for (long i = 0; i < n; i++)
        ptr[i + 1] += ptr[i];
    if (reserve(L, n, ptr[n]))
        return -1;
    int *j = L->j;
#pragma omp parallel for schedule(dynamic, SPH_OMP_CHUNK) if (n >= SPH_OMP_MIN)
    for (long i = 0; i < n; i++)
        (void)visit(1, g, x, y, i, rc2, j + ptr[i]);
    L->n = n;
    L->entries = ptr[n];
    return 0;
}

int sph_mps_nbr_build_all_pairs(sph_mps_nbr *L, const double *x, const double *y, long n, double rc)
{
    L->n = 0;
    L->entries = 0;
    L->rc = rc;
    const double rc2 = rc * rc;
    long cnt = 0;
    for (long i = 0; i < n; i++)
        for (long j = 0; j < n; j++)
            cnt += j != i && (x[i] - x[j]) * (x[i] - x[j]) + (y[i] - y[j]) * (y[i] - y[j]) < rc2;
    if (reserve(L, n, cnt))
        return -1;
    long k = 0;
    L->ptr[0] = 0;
    for (long i = 0; i < n; i++) {
        for (long j = 0; j < n; j++)
            if (j != i && (x[i] - x[j]) * (x[i] - x[j]) + (y[i] - y[j]) * (y[i] - y[j]) < rc2)
                L->j[k++] = (int)j;
        L->ptr[i + 1] = k;
    }
    L->n = n;
    L->entries = k;
    return 0;
}

void sph_mps_nbr_free(sph_mps_nbr *L)
{
    free(L->ptr);
    free(L->j);
    memset(L, 0, sizeof *L);
}

double sph_mps_nbr_bytes(const sph_mps_nbr *L)
{
    return (double)L->cap_n * sizeof(long) + (double)L->cap_j * sizeof(int);
}
