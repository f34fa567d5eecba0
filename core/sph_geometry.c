#include "sph_geometry.h"

#include "sph_body.h"
#include "sph_eos.h"
#include "sph_initial.h"
#include "sph_lattice.h"

#include <math.h>

/* Wall particles: bottom row (with the corners) and the two sides. */
static void tank_counts(const sph_config *c, long *nbottom, long *nside)
{
    const long L = c->layers;
    *nbottom = (sph_lattice_axis_count(c->tank.min[0], c->tank.max[0], c->dx) + 2 * L) * L;
    *nside = sph_lattice_axis_count(c->tank.min[1], c->tank.max[1], c->dx) * L;
}

/* Bodies take their place out of the fluid boxes: a box that overlaps one is counted particle
 * by particle (unless it is too large to be built anyway). */
#define SPH_CARVE_MAX 1000000000L

static int box_meets_bodies(const sph_config *c, const sph_box *f)
{
    if (c->nbodies == 0 || sph_lattice_box_count(f, c->dim, c->dx) > SPH_CARVE_MAX)
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

/* The free surface above a fluid box at abscissa x, for the hydrostatic density: the box's top,
 * raised by the initial field's surface elevation (the solitary wave's hump). */
static double column_top(const sph_config *c, const sph_box *f, double x)
{
    return f->max[1] + sph_initial_elevation(c, x);
}

/* The fluid box's particles, column by column; `P` NULL only counts them. */
static long fluid_box_put(const sph_config *c, const sph_box *f, sph_particles *P, long i0);

static long fluid_box_count(const sph_config *c, const sph_box *f)
{
    if (!box_meets_bodies(c, f) && !(sph_initial_elevation_max(c) > 0.0))
        return sph_lattice_box_count(f, c->dim, c->dx);
    return fluid_box_put(c, f, NULL, 0);
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

/* Hydrostatic density at (x, y): the deepest fluid column above it (within `margin` in x). */
static double initial_density(const sph_config *c, double x, double y, double margin)
{
    const double g = -c->gravity[1];
    double depth = 0.0;
    if (g > 0.0)
        for (int b = 0; b < c->nfluid; b++) {
            const sph_box *f = &c->fluid[b];
            const double top = column_top(c, f, x);
            if (x >= f->min[0] - margin && x <= f->max[0] + margin && y < top && top - y > depth)
                depth = top - y;
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

static long fluid_box_put(const sph_config *c, const sph_box *f, sph_particles *P, long i0)
{
    const double dx = c->dx;
    const long nx = sph_lattice_axis_count(f->min[0], f->max[0], dx);
    const long ny0 = sph_lattice_axis_count(f->min[1], f->max[1], dx);
    const int carve = box_meets_bodies(c, f);
    /* The columns are raised by the initial field's elevation, in whole particles, by error
     * diffusion: column ix gets the rows of round(S_ix) - round(S_ix-1), S the running sum of
     * the elevation over dx. Each column's top is then within dx of the surface and the hump's
     * volume within dx^2 / 2 of the sum's (rounding each column alone would drop the tails
     * below dx/2: 11% of a solitary wave's volume at d/dx = 12). */
    double raised = 0.0;
    long rows = 0;
    long i = i0;
    for (long ix = 0; ix < nx; ix++) {
        const double x = f->min[0] + (ix + 0.5) * dx;
        raised += fmax(sph_initial_elevation(c, x), 0.0) / dx;
        const double r = floor(raised + 0.5);
        const long raise = r < (double)SPH_LATTICE_AXIS_MAX ? (long)r - rows : 0;
        rows += raise;
        const long ny = ny0 + raise;
        if (!P && !carve) {
            i += ny;
            continue;
        }
        for (long iy = 0; iy < ny; iy++) {
            const double y = f->min[1] + (iy + 0.5) * dx;
            const double xy[2] = {x, y};
            if (carve && sph_body_covers(c, xy))
                continue;
            if (P)
                put(P, i, x, y, SPH_FLUID, initial_density(c, x, y, 0.0));
            i++;
        }
    }
    return i - i0;
}

void sph_geometry_fill(const sph_config *c, sph_particles *P)
{
    const double dx = c->dx;
    long i = 0;
    for (int b = 0; b < c->nfluid; b++)
        i += fluid_box_put(c, &c->fluid[b], P, i);
    if (!(c->has_tank && c->boundary == SPH_BOUNDARY_DYNAMIC))
        return;
    const long L = c->layers;
    const double margin = (L + 0.5) * dx;
    const sph_box *t = &c->tank;
    const long nx = sph_lattice_axis_count(t->min[0], t->max[0], dx);
    const long ny = sph_lattice_axis_count(t->min[1], t->max[1], dx);
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
