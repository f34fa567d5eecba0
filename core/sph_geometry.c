#include "sph_geometry.h"

#include "sph_body.h"
#include "sph_eos.h"

#include <math.h>

/* Particles along one axis, capped at SPH_AXIS_MAX so that counts never overflow (a case that
 * large is refused as too large anyway). */
#define SPH_AXIS_MAX 10000000L

static long axis_count(double lo, double hi, double dx)
{
    const double n = floor((hi - lo) / dx + 1e-6);
    if (!(n > 0))
        return 0;
    return n < (double)SPH_AXIS_MAX ? (long)n : SPH_AXIS_MAX;
}

long sph_geometry_box_count(const sph_box *b, int dim, double dx)
{
    long n = 1;
    for (int d = 0; d < dim; d++)
        n *= axis_count(b->min[d], b->max[d], dx);
    return n;
}

/* Wall particles: bottom row (with the corners) and the two sides. */
static void tank_counts(const sph_config *c, long *nbottom, long *nside)
{
    const long L = c->layers;
    *nbottom = (axis_count(c->tank.min[0], c->tank.max[0], c->dx) + 2 * L) * L;
    *nside = axis_count(c->tank.min[1], c->tank.max[1], c->dx) * L;
}

/* Bodies take their place out of the fluid boxes: a box that overlaps one is counted particle
 * by particle (unless it is too large to be built anyway). */
#define SPH_CARVE_MAX 1000000000L

static int box_meets_bodies(const sph_config *c, const sph_box *f)
{
    if (c->nbodies == 0 || sph_geometry_box_count(f, c->dim, c->dx) > SPH_CARVE_MAX)
        return 0;
    for (int k = 0; k < c->nbodies; k++) {
        const sph_body_spec *b = &c->bodies[k];
        const double r =
            0.5 * (b->shape == SPH_SHAPE_CIRCLE ? b->diameter : hypot(b->size[0], b->size[1])) +
            c->dx;
        if (b->center[0] + r > f->min[0] && b->center[0] - r < f->max[0] &&
            b->center[1] + r > f->min[1] && b->center[1] - r < f->max[1])
            return 1;
    }
    return 0;
}

static long fluid_box_count(const sph_config *c, const sph_box *f)
{
    if (!box_meets_bodies(c, f))
        return sph_geometry_box_count(f, c->dim, c->dx);
    const double dx = c->dx;
    const long nx = axis_count(f->min[0], f->max[0], dx), ny = axis_count(f->min[1], f->max[1], dx);
    long n = 0;
    for (long ix = 0; ix < nx; ix++)
        for (long iy = 0; iy < ny; iy++) {
            const double x[2] = {f->min[0] + (ix + 0.5) * dx, f->min[1] + (iy + 0.5) * dx};
            n += !sph_body_covers(c, x);
        }
    return n;
}

void sph_geometry_count(const sph_config *c, long *nfluid, long *nboundary)
{
    *nfluid = 0;
    for (int b = 0; b < c->nfluid; b++)
        *nfluid += fluid_box_count(c, &c->fluid[b]);
    *nboundary = 0;
    if (c->has_tank && c->boundary == SPH_BOUNDARY_DYNAMIC) {
        long nb, ns;
        tank_counts(c, &nb, &ns);
        *nboundary = nb + 2 * ns;
    }
}

/* Hydrostatic density at (x, y): the deepest fluid box above it (within `margin` in x). */
static double initial_density(const sph_config *c, double x, double y, double margin)
{
    const double g = -c->gravity[1];
    double depth = 0.0;
    if (g > 0.0)
        for (int b = 0; b < c->nfluid; b++) {
            const sph_box *f = &c->fluid[b];
            if (x >= f->min[0] - margin && x <= f->max[0] + margin && y < f->max[1] &&
                f->max[1] - y > depth)
                depth = f->max[1] - y;
        }
    return sph_eos_density(c, c->rho0 * g * depth);
}

double sph_geometry_hydrostatic_density(const sph_config *c, double x, double y)
{
    return initial_density(c, x, y, 0.0);
}

static void put(sph_particles *P, long i, double x, double y, int type, double rho)
{
    P->x[i] = x;
    P->y[i] = y;
    P->vx[i] = 0.0;
    P->vy[i] = 0.0;
    P->rho[i] = rho;
    P->type[i] = (unsigned char)type;
    P->id[i] = (int)i;
}

void sph_geometry_fill(const sph_config *c, sph_particles *P)
{
    const double dx = c->dx;
    long i = 0;
    for (int b = 0; b < c->nfluid; b++) {
        const sph_box *f = &c->fluid[b];
        const long nx = axis_count(f->min[0], f->max[0], dx);
        const long ny = axis_count(f->min[1], f->max[1], dx);
        const int carve = box_meets_bodies(c, f);
        for (long ix = 0; ix < nx; ix++)
            for (long iy = 0; iy < ny; iy++) {
                const double x = f->min[0] + (ix + 0.5) * dx, y = f->min[1] + (iy + 0.5) * dx;
                const double xy[2] = {x, y};
                if (carve && sph_body_covers(c, xy))
                    continue;
                put(P, i++, x, y, SPH_FLUID, initial_density(c, x, y, 0.0));
            }
    }
    if (!(c->has_tank && c->boundary == SPH_BOUNDARY_DYNAMIC))
        return;
    const long L = c->layers;
    const double margin = (L + 0.5) * dx;
    const sph_box *t = &c->tank;
    const long nx = axis_count(t->min[0], t->max[0], dx);
    const long ny = axis_count(t->min[1], t->max[1], dx);
    for (long k = 0; k < L; k++) {
        const double y = t->min[1] - (k + 0.5) * dx;
        for (long ix = -L; ix < nx + L; ix++) {
            const double x = t->min[0] + (ix + 0.5) * dx;
            put(P, i++, x, y, SPH_BOUNDARY, initial_density(c, x, y, margin));
        }
    }
    for (long k = 0; k < L; k++)
        for (long iy = 0; iy < ny; iy++) {
            const double y = t->min[1] + (iy + 0.5) * dx;
            const double xl = t->min[0] - (k + 0.5) * dx, xr = t->max[0] + (k + 0.5) * dx;
            put(P, i++, xl, y, SPH_BOUNDARY, initial_density(c, xl, y, margin));
            put(P, i++, xr, y, SPH_BOUNDARY, initial_density(c, xr, y, margin));
        }
}
