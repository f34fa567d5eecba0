/*
 * sph_rpdf: the radial particle density function (Robinson 2009, "Turbulence and viscous mixing
 * using SPH", Monash; Macia et al., paper 001, figs. 8, 9, 11): how the distances between
 * neighbouring fluid particles are distributed, a picture of clustering (a peak at q = 0) and of
 * a kept lattice (sharp peaks at dx, sqrt(2) dx, 2 dx, ...) or a scattered one (smeared peaks).
 *
 * Over the unordered pairs of fluid particles closer than qmax h, binned by q = r / h into nbins
 * equal bins:
 *   count[b]   pairs in bin b (the paper's histogram H)
 *   density[b] 2 count[b] / (N n0 A_b): neighbours per particle in the bin's ring (area A_b, a
 *              shell volume in 3D) over what a uniform fluid of the initial number density
 *              n0 = 1 / dx^d would put there (the paper's R_rho; 1 for an ideal gas, less near a
 *              free surface, where particles lack neighbours).
 * The calling thread's OpenMP threads share the pair loop (from SPH_OMP_MIN fluid particles on);
 * the counts are integers, so the figures are the same with any number of threads.
 */
#ifndef SPH_RPDF_H
#define SPH_RPDF_H

#include "sph_error.h"

#define SPH_RPDF_MAX_BINS 1000

/* The particles an RPDF is taken over. */
typedef struct sph_rpdf_input {
    int dim;                   /* 2 (3 later) */
    long n;                    /* particles */
    const double *pos[3];      /* position components [m] */
    const unsigned char *type; /* only SPH_FLUID particles count */
    double h;                  /* smoothing length [m] */
    double dx;                 /* initial spacing, for n0 [m] */
} sph_rpdf_input;

/* Fills q (bin centres, in units of h), count and density, nbins each, for the pairs closer
 * than qmax h. Returns 0, SPH_ERR_INVALID (nbins outside [1, SPH_RPDF_MAX_BINS], qmax not in
 * (0, 10]) or SPH_ERR_NOMEM. */
int sph_rpdf_compute(const sph_rpdf_input *in, double qmax, int nbins, double *q, double *count,
                     double *density, sph_error *err);

#endif
