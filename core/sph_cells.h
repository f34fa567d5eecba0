/*
 * sph_cells: the cell list. A 2D grid of square cells no smaller than the support radius, with
 * an empty column and row of padding on every side so that the neighbour loops need no bounds
 * checks. Cells are numbered column by column (cell = cx * ny + cy), so the three cells of a
 * neighbouring column that a cell interacts with are one contiguous range of particles once the
 * particles are sorted by cell.
 *
 * sph_cells_sort() is a stable counting sort of the particles by cell (lost particles go to the
 * end); the pair loops then read cell cell's particles as [start[cell], start[cell + 1]).
 */
#ifndef SPH_CELLS_H
#define SPH_CELLS_H

#include "sph_particles.h"

typedef struct sph_cells {
    double x0, y0;   /* lower corner of cell (0, 0), the padding cell [m] */
    double size;     /* cell edge [m], >= support radius */
    double inv_size; /* 1 / size [1/m] */
    int nx, ny;      /* cells per axis, padding included [-] */
    long ncells;     /* nx * ny */
    int *start;      /* ncells + 2 offsets: cell c holds [start[c], start[c + 1]) */
    int *counts;     /* ncells + 4: the counting sort's array, start = counts + 2 */
    int *key;        /* n: cell of each particle (ncells for lost particles) */
    long *perm;      /* n: sorting permutation, new index -> old index */
    long cap;        /* particles key and perm can hold */
} sph_cells;

/* Number of cells of the grid covering [lo, hi] with cells of edge >= size (padding included);
 * used to refuse grids too large before allocating them. */
double sph_cells_count(const double lo[2], const double hi[2], double size);

/* Allocates the grid covering [lo, hi] for n particles. Returns 0 or -1 (out of memory). */
int sph_cells_alloc(sph_cells *g, const double lo[2], const double hi[2], double size, long n);
void sph_cells_free(sph_cells *g);

/* Makes room for n particles. Returns 0 or -1 (out of memory; g unchanged). */
int sph_cells_reserve(sph_cells *g, long n);

/* The column and row of the cell holding (x, y), which must lie inside the grid. */
static inline void sph_cells_of(const sph_cells *g, double x, double y, int *cx, int *cy)
{
    *cx = (int)((x - g->x0) * g->inv_size);
    *cy = (int)((y - g->y0) * g->inv_size);
}

/* The particles of the cells (cx, cy - 1), (cx, cy), (cx, cy + 1): one contiguous range
 * [*jb, *je) once they are sorted. Over cx - 1 .. cx + 1 it visits every neighbour within the
 * cell size of a particle in cell (cx, cy). */
static inline void sph_cells_column3(const sph_cells *g, int cx, int cy, long *jb, long *je)
{
    const long cell = (long)cx * g->ny + cy;
    *jb = g->start[cell - 1];
    *je = g->start[cell + 2];
}

/* Sorts P by cell. Particles of type SPH_LOST, or outside the grid (they become SPH_LOST), go
 * to the end. Returns the number of particles in cells (the active ones). */
long sph_cells_sort(sph_cells *g, sph_particles *P);

#endif
