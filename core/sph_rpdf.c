#include "sph_rpdf.h"

#include "sph_particles.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

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
     * axes; in 3D the third is checked per pair) */
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
    long *start = calloc((size_t)nc + 1, sizeof *start);
    long *order = malloc((size_t)nf * sizeof *order);
    long *cell = malloc((size_t)in->n * sizeof *cell);
    if (!start || !order || !cell) {
        free(start);
        free(order);
        free(cell);
        return sph_error_set(err, SPH_ERR_NOMEM, "", "out of memory for the RPDF");
    }
    for (long i = 0; i < in->n; i++) {
        cell[i] = -1;
        if (in->type[i] != SPH_FLUID)
            continue;
        const long cx = (long)((in->pos[0][i] - lo[0]) / rmax);
        const long cy = (long)((in->pos[1][i] - lo[1]) / rmax);
        cell[i] = (cx < nx ? cx : nx - 1) * ny + (cy < ny ? cy : ny - 1);
        start[cell[i] + 1]++;
    }
    for (long c = 0; c < nc; c++)
        start[c + 1] += start[c];
    long *fill = malloc((size_t)nc * sizeof *fill);
    if (!fill) {
        free(start);
        free(order);
        free(cell);
        return sph_error_set(err, SPH_ERR_NOMEM, "", "out of memory for the RPDF");
    }
    memcpy(fill, start, (size_t)nc * sizeof *fill);
    for (long i = 0; i < in->n; i++)
        if (cell[i] >= 0)
            order[fill[cell[i]]++] = i;
    free(fill);
    const double rmax2 = rmax * rmax, inv = 1.0 / (dq * in->h);
    for (long k = 0; k < nf; k++) {
        const long i = order[k], c = cell[i], cx = c / ny, cy = c % ny;
        for (long ox = cx - 1; ox <= cx + 1; ox++)
            for (long oy = cy - 1; oy <= cy + 1; oy++) {
                if (ox < 0 || ox >= nx || oy < 0 || oy >= ny)
                    continue;
                const long o = ox * ny + oy;
                for (long m = start[o]; m < start[o + 1]; m++) {
                    const long j = order[m];
                    if (j <= i)
                        continue; /* each unordered pair once */
                    double r2 = 0.0;
                    for (int d = 0; d < dim; d++) {
                        const double e = in->pos[d][i] - in->pos[d][j];
                        r2 += e * e;
                    }
                    if (r2 >= rmax2)
                        continue;
                    const long b = (long)(sqrt(r2) * inv);
                    count[b < nbins ? b : nbins - 1] += 1.0;
                }
            }
    }
    free(start);
    free(order);
    free(cell);
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
