/*
 * sph_cells: the cell list. A 2D or 3D grid of square (cubic) cells no smaller than the support
 * radius, with an empty layer of padding cells on every side so that the neighbour loops need no
 * bounds checks. In 2D cells are numbered column by column (cell = cx * ny + cy), so the three
 * cells of a neighbouring column that a cell interacts with are one contiguous range of particles
 * once the particles are sorted by cell; in 3D the last axis runs fastest (cell = (cx * ny + cy)
 * * nz + cz), so the three cells of a neighbouring (cx, cy) column are one range likewise.
 *
 * sph_cells_sort() is a stable counting sort of the particles by cell (lost particles go to the
 * end), in parallel passes, and in 3D then by z within each cell (stable), so that a column of
 * cells along z is one range sorted by z; the pair loops then read cell cell's particles as
 * [start[cell], start[cell + 1]).
 */
#ifndef SPH_CELLS_H
#define SPH_CELLS_H

#include "sph_hd.h"
#include "sph_particles.h"

#include <math.h>

/* The most threads the sort uses. */
#define SPH_CELLS_SORT_THREADS 64

typedef struct sph_cells {
    int dim;              /* 2 or 3 */
    double x0, y0, z0;    /* lower corner of cell (0, 0, 0), the padding cell [m] (z0: 3D) */
    double size;          /* cell edge [m], >= support radius */
    double inv_size;      /* 1 / size [1/m] */
    int nx, ny, nz;       /* cells per axis, padding included [-] (nz = 1 in 2D) */
    long ncells;          /* nx * ny * nz */
    int *start;           /* ncells + 2 offsets: cell c holds [start[c], start[c + 1]) */
    int *counts;          /* ncells + 4: the counting sort's array, start = counts + 2 */
    int *perm;            /* n: sorting permutation, new index -> old index */
    unsigned char *wet;   /* ncells, made on first use: cells that hold fluid (sph_cells_wet) */
    unsigned char *walls; /* the same for wall particles (sph_cells_walls) */
    long cap;             /* particles perm can hold */
} sph_cells;

/* Number of cells of the dim-dimensional grid covering [lo, hi] with cells of edge >= size
 * (padding included); used to refuse grids too large before allocating them. */
double sph_cells_count(int dim, const double lo[3], const double hi[3], double size);

/* Allocates the dim-dimensional grid covering [lo, hi] (the first dim components) for n
 * particles. Returns 0 or -1 (out of memory). */
int sph_cells_alloc(sph_cells *g, int dim, const double lo[3], const double hi[3], double size,
                    long n);
void sph_cells_free(sph_cells *g);

/* Makes room for n particles. Returns 0 or -1 (out of memory; g unchanged). */
int sph_cells_reserve(sph_cells *g, long n);

/* 2D grids: the column and row of the cell holding (x, y), which must lie inside the grid. */
static inline void sph_cells_of(const sph_cells *g, double x, double y, int *cx, int *cy)
{
    *cx = (int)((x - g->x0) * g->inv_size);
    *cy = (int)((y - g->y0) * g->inv_size);
}

/* The index of cell (cx, cy, cz), cz = 0 in 2D (nz = 1). The last axis runs fastest: cells
 * index - 1 .. index + 1 are one contiguous range of particles once they are sorted. */
static inline long sph_cells_index(const sph_cells *g, int cx, int cy, int cz)
{
    return ((long)cx * g->ny + cy) * g->nz + cz;
}

/* The cell of the point x (D components; D the grid's dimension, a constant at the call) into c
 * (c[2] = 0 in 2D) when x lies in the grid's inner cells, the padding excluded; returns 1 then, 0
 * otherwise (NaN included). */
static inline int sph_cells_locate(const int D, const sph_cells *g, const double *x, int c[3])
{
    const double f[3] = {(x[0] - g->x0) * g->inv_size, (x[1] - g->y0) * g->inv_size,
                         D == 3 ? (x[2] - g->z0) * g->inv_size : 1.5};
    if (!(f[0] >= 1.0 && f[0] < g->nx - 1.0 && f[1] >= 1.0 && f[1] < g->ny - 1.0 &&
          (D == 2 || (f[2] >= 1.0 && f[2] < g->nz - 1.0))))
        return 0;
    c[0] = (int)f[0];
    c[1] = (int)f[1];
    c[2] = D == 3 ? (int)f[2] : 0;
    return 1;
}

/* 2D grids: the particles of the cells (cx, cy - 1), (cx, cy), (cx, cy + 1): one contiguous range
 * [*jb, *je) once they are sorted. Over cx - 1 .. cx + 1 it visits every neighbour within the
 * cell size of a particle in cell (cx, cy). */
static inline void sph_cells_column3(const sph_cells *g, int cx, int cy, long *jb, long *je)
{
    const long cell = sph_cells_index(g, cx, cy, 0);
    *jb = g->start[cell - 1];
    *je = g->start[cell + 2];
}

/* The reach that cuts of the cells' ranges use for a support radius (in z), and their margin on
 * distances across (x, y): wider than the support by far more than the rounding of positions
 * and of the cells' keys, so that a cut only drops points beyond the support (sph_wcsph.c: the 3D
 * pair loop, mDBC). */
SPH_HD static inline void sph_cells_cut_margins(const sph_cells *g, double support, double *reach,
                                                double *lat)
{
    const double size = 1.0 / g->inv_size;
    *reach = support * (1.0 + 1e-9) + 1e-12 * (fabs(g->z0) + (double)g->nz * size);
    *lat = 1e-9 * size + 1e-12 * (fabs(g->x0) + fabs(g->y0) + (double)(g->nx + g->ny) * size);
}

/* 3D: the part of the range [*b, *e) of a column of cells along z (sorted by z: sph_cells_sort)
 * whose z lies strictly within rz of zc, by bisection; the caller's rz carries its margin. */
SPH_HD static inline void sph_cells_cut_z(const double *z, double zc, double rz, long *b, long *e)
{
    long lo = *b, hi = *e;
    while (lo < hi) { /* the first z > zc - rz */
        const long mid = lo + (hi - lo) / 2;
        if (z[mid] <= zc - rz)
            lo = mid + 1;
        else
            hi = mid;
    }
    long lo2 = lo, hi2 = *e;
    while (lo2 < hi2) { /* the first z >= zc + rz */
        const long mid = lo2 + (hi2 - lo2) / 2;
        if (z[mid] < zc + rz)
            lo2 = mid + 1;
        else
            hi2 = mid;
    }
    *b = lo;
    *e = lo2;
}

/* 3D: the range [*b, *e) of the column of cells (cx, cy, ...) along z (sorted by z) cut to the
 * particles that can be within reach of point p: 0 when the whole column is out of reach across
 * (x, y), else 1 with the range cut to the z within sqrt(reach2 - d^2) of p's, d the distance
 * across to the column less lat. reach2 and lat from sph_cells_cut_margins: only points beyond
 * the support go. The grid's origin (x0, y0) and cell size. */
SPH_HD static inline int sph_cells_cut_column(double x0, double y0, double size, const double *z,
                                              const double *p, int cx, int cy, double reach2,
                                              double lat, long *b, long *e)
{
    const double xl = x0 + cx * size, yl = y0 + cy * size;
    const double dx = fmax(fmax(xl - p[0], p[0] - (xl + size)) - lat, 0.0);
    const double dy = fmax(fmax(yl - p[1], p[1] - (yl + size)) - lat, 0.0);
    const double d2 = dx * dx + dy * dy;
    if (d2 >= reach2)
        return 0;
    sph_cells_cut_z(z, p[2], sqrt(reach2 - d2), b, e);
    return 1;
}

/* Particle i's cell (ncells for a lost particle, and for one outside the grid, which becomes
 * lost). Shared by the C sort (cell_keys2, cell_keys3 in sph_cells.c)
 * and the GPU's (core/gpu/). */
SPH_HD static inline __attribute__((always_inline)) int
sph_cells_key(const int D, const sph_cells *g, sph_particles *P, long i)
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

/* Sorts P by cell. Particles of type SPH_LOST, or outside the grid (they become SPH_LOST), go
 * to the end. Returns the number of particles in cells (the active ones). The sort's keys and
 * outlier lists live in P->scratch (n doubles), whose contents it overwrites, as the
 * permutation of P's fields does (sph_particles_permute). */
long sph_cells_sort(sph_cells *g, sph_particles *P);

/* After a sort: for each cell, 1 if it holds a fluid particle (into g->wet, allocated on the
 * first call). Returns g->wet, or NULL when out of memory. */
const unsigned char *sph_cells_wet(sph_cells *g, const sph_particles *P);

/* The same for the dynamic walls' particles (SPH_BOUNDARY), into g->walls, built on the first
 * call only: wall particles never move, so the cells that hold them stay the same (the sort
 * reorders particles within and between cells, not the walls' cells). */
const unsigned char *sph_cells_walls(sph_cells *g, const sph_particles *P);

#endif
