/*
 * sph_lattice: lattice counts (sph_lattice.h).
 *
 * Layer 1 of the set-up pipeline. May call: libm only.
 */
#include "sph_lattice.h"

#include <math.h>

long sph_lattice_axis_count(double lo, double hi, double dx)
{
    const double n = floor((hi - lo) / dx + 1e-6);
    if (!(n > 0))
        return 0;
    return n < (double)SPH_LATTICE_AXIS_MAX ? (long)n : SPH_LATTICE_AXIS_MAX;
}

long sph_lattice_box_count(const sph_box *b, int dim, double dx)
{
    long n = 1;
    for (int d = 0; d < dim; d++)
        n *= sph_lattice_axis_count(b->min[d], b->max[d], dx);
    return n;
}
