/*
 * sph_mps_nbr: neighbour lists for the MPS operators, in compressed-row form. Particle i's
 * neighbours within the cut-off radius rc (i itself excluded) are j[ptr[i] .. ptr[i + 1]), in
 * ascending index order.
 *
 * Built from the cell grid (sph_cells) after the particles have been sorted by cell: a count pass
 * and a fill pass, each parallel over the particles (a particle writes only its own row), with
 * the offsets summed serially between them. The lists, and so everything computed from them, are
 * the same whatever the number of threads. MPS sums over one list several times per step (number
 * density, Poisson matrix, gradient), so the list is built once and read many times.
 */
#ifndef SPH_MPS_NBR_H
#define SPH_MPS_NBR_H

#include "sph_cells.h"

typedef struct sph_mps_nbr {
    long n;       /* particles with a list [-] */
    long *ptr;    /* n + 1 offsets into j */
    int *j;       /* neighbour indices */
    long cap_n;   /* particles ptr has room for [-] */
    long cap_j;   /* entries j has room for [-] */
    double rc;    /* cut-off radius of the latest build [m] */
    long entries; /* ptr[n]: entries of the latest build (each pair twice) [-] */
} sph_mps_nbr;

/* Builds the lists of particles [0, n) (sorted by cell in g, positions x, y) within radius rc,
 * which must not exceed the cell size. Grows the storage as needed. Returns 0, or -1 when out of
 * memory (the lists are then empty). */
int sph_mps_nbr_build(sph_mps_nbr *L, const sph_cells *g, const double *x, const double *y, long n,
                      double rc);

/* The same lists by testing every pair (O(n^2)): the obvious loop the fast one is checked
 * against, for tests. Returns 0 or -1. */
int sph_mps_nbr_build_all_pairs(sph_mps_nbr *L, const double *x, const double *y, long n,
                                double rc);

/* Frees the storage; the struct is left empty (free of an empty struct is a no-op). */
void sph_mps_nbr_free(sph_mps_nbr *L);

/* Bytes held by the lists. */
double sph_mps_nbr_bytes(const sph_mps_nbr *L);

#endif
