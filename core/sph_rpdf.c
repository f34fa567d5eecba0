#include "sph_rpdf.h"

#include "sph_particles.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Bins the pairs (a, b) for b in [b0, b1) of the cell-ordered positions x, y (z: NULL in 2D)
 * closer than sqrt(rmax2) into hist (integer counts: the sum is the same in any order). */
static void bin_pairs(const double *x, const double *y, const double *z, long a, long b0, long b1,
                      double rmax2, double inv, int nbins, long *hist)
{
    const double xa = x[a], ya = y[a];
    if (z) {
        const double za = z[a];
        for (long b = b0; b < b1; b++) {
            const double ex = xa - x[b], ey = ya - y[b], ez = za - z[b];
            const double r2 = ex * ex + ey * ey + ez * ez;
            if (r2 < rmax2) {
                const long k = (long)(sqrt(r2) * inv);
                hist[k < nbins ? k : nbins - 1]++;
            }
        }
        return;
    }
    for (long b = b0; b < b1; b++) {
        const double ex = xa - x[b], ey = ya - y[b];
        const double r2 = ex * ex + ey * ey;
        if (r2 < rmax2) {
            const long k = (long)(sqrt(r2) * inv);
            hist[k < nbins ? k : nbins - 1]++;
        }
    }
}

/* The cell of particle i in the grid of nx x ny cells of edge rmax from lo. */
static long cell_of(const sph_rpdf_input *in, long i, const double lo[2], double rmax, long nx,
                    long ny)
{
    const long cx = (long)((in->pos[0][i] - lo[0]) / rmax);
    const long cy = (long)((in->pos[1][i] - lo[1]) / rmax);
    return (cx < nx ? cx : nx - 1) * ny + (cy < ny ? cy : ny - 1);
}

int sph_rpdf_compute(const sph_rpdf_input *in, double qmax, int nbins, double *q, double *count,
                     double *density, sph_error *err)
{
    if (nbins < 1 || nbins > SPH_RPDF_MAX_BINS)
        return sph_error_set(err, SPH_ERR_INVALID, "/rpdf/bins", "bins must be in [1, %d], got %d",
                             SPH_RPDF_MAX_BINS, nbins);
    if (!(qmax > 0.0 && qmax <= 10.0))
        return sph_error_set(err, SPH_ERR_INVALID, "/rpdf/qmax",
                             "qmax must be in (0, 10] (units of h), got %g", qmax);
    const int dim = in->dim;
    const double rmax = qmax * in->h, dq = qmax / nbins;
    for (int b = 0; b < nbins; b++) {
        q[b] = (b + 0.5) * dq;
        count[b] = 0.0;
        density[b] = 0.0;
    }
    /* the fluid particles' bounding box, cut in cells of edge rmax (a 2D grid over the first two
     * axes; in 3D the third is checked per pair), numbered column by column (cx * ny + cy) */
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    long nf = 0;
    for (long i = 0; i < in->n; i++) {
        if (in->type[i] != SPH_FLUID)
            continue;
        for (int d = 0; d < 2; d++) {
            lo[d] = fmin(lo[d], in->pos[d][i]);
            hi[d] = fmax(hi[d], in->pos[d][i]);
        }
        nf++;
    }
    if (nf < 2)
        return 0;
    const double nxd = floor((hi[0] - lo[0]) / rmax) + 1, nyd = floor((hi[1] - lo[1]) / rmax) + 1;
    if (!(nxd * nyd < 1e8))
        return sph_error_set(err, SPH_ERR_NOMEM, "", "the fluid is too spread out for an RPDF");
    const long nx = (long)nxd, ny = (long)nyd, nc = nx * ny;
    const int nz = dim == 3;
    long *start = calloc((size_t)nc + 1, sizeof *start);
    long *fill = malloc((size_t)nc * sizeof *fill);
    long *hist = calloc((size_t)nbins, sizeof *hist);
    double *xyz = malloc((size_t)nf * (size_t)(2 + nz) * sizeof *xyz);
    if (!start || !fill || !hist || !xyz) {
        free(start);
        free(fill);
        free(hist);
        free(xyz);
        return sph_error_set(err, SPH_ERR_NOMEM, "", "out of memory for the RPDF");
    }
    for (long i = 0; i < in->n; i++)
        if (in->type[i] == SPH_FLUID)
            start[cell_of(in, i, lo, rmax, nx, ny) + 1]++;
    for (long c = 0; c < nc; c++)
        start[c + 1] += start[c];
    memcpy(fill, start, (size_t)nc * sizeof *fill);
    /* the positions in cell order, contiguous: the pair loop streams through them */
    double *x = xyz, *y = xyz + nf, *z = nz ? xyz + 2 * nf : NULL;
    for (long i = 0; i < in->n; i++) {
        if (in->type[i] != SPH_FLUID)
            continue;
        const long k = fill[cell_of(in, i, lo, rmax, nx, ny)]++;
        x[k] = in->pos[0][i];
        y[k] = in->pos[1][i];
        if (z)
            z[k] = in->pos[2][i];
    }
    free(fill);
    /* each unordered pair once: a particle with those after it in its cell and in the cell above
     * (one range), and with the three cells of the next column (one range too); the threads
     * share the columns, each with its own histogram, summed at the end (integers: the same
     * counts with any number of threads) */
    const double rmax2 = rmax * rmax, inv = 1.0 / (dq * in->h);
#pragma omp parallel for schedule(dynamic, 1) reduction(+ : hist[:nbins]) if (nf >= SPH_OMP_MIN)
    for (long cx = 0; cx < nx; cx++)
        for (long cy = 0; cy < ny; cy++) {
            const long c = cx * ny + cy;
            const long up = start[cy + 1 < ny ? c + 2 : c + 1];
            const long next0 = cx + 1 < nx ? start[c + ny - (cy > 0)] : 0;
            const long next1 = cx + 1 < nx ? start[c + ny + (cy + 1 < ny) + 1] : 0;
            for (long a = start[c]; a < start[c + 1]; a++) {
                bin_pairs(x, y, z, a, a + 1, up, rmax2, inv, nbins, hist);
                bin_pairs(x, y, z, a, next0, next1, rmax2, inv, nbins, hist);
            }
        }
    free(start);
    free(xyz);
    for (int b = 0; b < nbins; b++)
        count[b] = (double)hist[b];
    free(hist);
    const double n0 = 1.0 / pow(in->dx, dim);
    for (int b = 0; b < nbins; b++) {
        const double r0 = b * dq * in->h, r1 = (b + 1) * dq * in->h;
        const double shell = dim == 2   ? M_PI * (r1 * r1 - r0 * r0)
                             : dim == 3 ? 4.0 / 3.0 * M_PI * (r1 * r1 * r1 - r0 * r0 * r0)
                                        : 2.0 * (r1 - r0);
        density[b] = 2.0 * count[b] / ((double)nf * n0 * shell);
    }
    return 0;
}
