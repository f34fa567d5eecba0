/*
 * sph_shapes: fluid boxes, the tank, the hydrostatic density (sph_shapes.h).
 *
 * Layer 3 of the set-up pipeline (shapes). May call: sph_body_shape.h (what a body covers, its
 * bounding radius), sph_initial.h (the surface elevation), sph_lattice.h, sph_eos.h, libm. Never
 * the fill (sph_fill.c), the bodies' dynamics (sph_body.c) or the sim.
 */
#include "sph_shapes.h"

#include "sph_body_shape.h"
#include "sph_eos.h"
#include "sph_initial.h"
#include "sph_lattice.h"

#include <math.h>

/* Bodies take their place out of the fluid boxes: a box that overlaps one is counted particle
 * by particle (unless it is too large to be built anyway). */
#define SPH_CARVE_MAX 1000000000L

/* 1 if an obstacle grown by dx (beyond the region sph_shapes_in_obstacle carves) meets the
 * fluid box f. */
static int box_meets_obstacles(const sph_config *c, const sph_box *f)
{
    for (int k = 0; k < c->nobstacles; k++) {
        const sph_box *o = &c->obstacles[k];
        int meets = 1;
        for (int d = 0; d < c->dim && meets; d++)
            meets = o->max[d] + c->dx > f->min[d] && o->min[d] - c->dx < f->max[d];
        if (meets)
            return 1;
    }
    return 0;
}

/* The obstacle b's lattice along axis d: n points dx apart, centred in the box, n = L / dx rounded
 * (at least 1), so that its faces lie within dx/4 of the box's (a lattice from the min corner
 * with L / dx rounded down recessed the max faces by up to dx: a box 0.161 m high at dx = 34 mm
 * stood 24 mm short). Returns n; the first point's coordinate in *first. */
static long obstacle_axis(const sph_box *b, int d, double dx, double *first)
{
    const double len = b->max[d] - b->min[d];
    const double r = floor(len / dx + 0.5);
    const long n = r >= 1.0 ? (long)r : 1;
    *first = 0.5 * (b->min[d] + b->max[d]) - 0.5 * (double)(n - 1) * dx;
    return n;
}

int sph_shapes_in_obstacle(const sph_config *c, const double *x)
{
    const double g = c->dx * (1.0 - 1e-9); /* a point dx from the lattice's last one is outside */
    for (int k = 0; k < c->nobstacles; k++) {
        const sph_box *o = &c->obstacles[k];
        int in = 1;
        for (int d = 0; d < c->dim && in; d++) {
            double first;
            const long n = obstacle_axis(o, d, c->dx, &first);
            in = x[d] > first - g && x[d] < first + (double)(n - 1) * c->dx + g;
        }
        if (in)
            return 1;
    }
    return 0;
}

/* The faces a box's particles stand for along axis d, dx/2 beyond its outermost particles: on
 * the obstacle's own lattice (centred in the box), or, when the scene filled the case
 * (sph_config_by_scene), on the lattice anchored at the domain's min corner, whose points inside
 * the box are its particles (for the tank, whose particles lie outside it: the faces of its
 * inside, dx/2 beyond the fluid's lattice points nearest them). */
static void box_faces(const sph_config *c, const sph_box *b, int d, int centred, double *lo,
                      double *hi)
{
    const double dx = c->dx;
    if (c->geometry_filled) {
        const double o = c->domain.min[d] + 0.5 * dx;
        lo[d] = o + (ceil((b->min[d] - o) / dx - 1e-9) - 0.5) * dx;
        hi[d] = o + (floor((b->max[d] - o) / dx + 1e-9) + 0.5) * dx;
        return;
    }
    if (!centred) {
        lo[d] = b->min[d];
        hi[d] = b->max[d];
        return;
    }
    double first;
    const long n = obstacle_axis(b, d, dx, &first);
    lo[d] = first - 0.5 * dx;
    hi[d] = first + (double)(n - 1) * dx + 0.5 * dx;
}

void sph_shapes_wall_mirror(const sph_config *c, const double *x, double *g)
{
    const int dim = c->dim, up = sph_shapes_up(dim);
    const double dx = c->dx;
    double tlo[3] = {0, 0, 0}, thi[3] = {0, 0, 0}; /* the tank's inside */
    if (c->has_tank)
        for (int d = 0; d < dim; d++)
            box_faces(c, &c->tank, d, 0, tlo, thi);
    for (int d = 0; d < 3; d++)
        g[d] = d < dim ? x[d] : 0.0;
    for (int k = 0; k < c->nobstacles; k++) { /* a point of an obstacle: across its nearest face */
        const sph_box *o = &c->obstacles[k];
        double lo[3], hi[3];
        int in = 1;
        for (int d = 0; d < dim && in; d++) {
            box_faces(c, o, d, 1, lo, hi); /* the faces the particles stand for */
            in = x[d] > lo[d] && x[d] < hi[d];
        }
        if (!in)
            continue;
        double best = INFINITY, at = 0.0;
        int axis = -1;
        for (int d = 0; d < dim; d++) {
            /* a face on the tank's floor or against one of its walls faces no water */
            const int lo_wet = !c->has_tank || lo[d] > tlo[d] + 0.25 * dx;
            const int hi_wet = !c->has_tank || d == up || hi[d] < thi[d] - 0.25 * dx;
            if (lo_wet && x[d] - lo[d] < best) {
                best = x[d] - lo[d];
                at = lo[d];
                axis = d;
            }
            if (hi_wet && hi[d] - x[d] < best) {
                best = hi[d] - x[d];
                at = hi[d];
                axis = d;
            }
        }
        if (axis >= 0)
            g[axis] = 2.0 * at - x[axis];
        return;
    }
    if (!c->has_tank)
        return;
    for (int d = 0; d < dim; d++) { /* a point of the tank's walls: across the nearest point of
                                       the tank's inside (a face, an edge or a corner) */
        if (x[d] < tlo[d])
            g[d] = 2.0 * tlo[d] - x[d];
        else if (x[d] > thi[d] && d != up)
            g[d] = 2.0 * thi[d] - x[d];
    }
}

long sph_shapes_obstacle_points(const sph_config *c, const sph_box *b, double *const *pos)
{
    const int dim = c->dim;
    const double dx = c->dx;
    long n[3] = {1, 1, 1};
    double first[3] = {0.0, 0.0, 0.0};
    for (int d = 0; d < dim; d++)
        n[d] = obstacle_axis(b, d, dx, &first[d]);
    if (!pos)
        return n[0] * n[1] * (dim == 3 ? n[2] : 1);
    long i = 0;
    for (long ix = 0; ix < n[0]; ix++)
        for (long iy = 0; iy < n[1]; iy++)
            for (long iz = 0; iz < (dim == 3 ? n[2] : 1); iz++, i++) {
                pos[0][i] = first[0] + (double)ix * dx;
                pos[1][i] = first[1] + (double)iy * dx;
                if (dim == 3)
                    pos[2][i] = first[2] + (double)iz * dx;
            }
    return i;
}

/* 1 if a body's bounding circle (grown by dx) meets the fluid box f. */
static int box_meets_bodies(const sph_config *c, const sph_box *f)
{
    if (c->nbodies == 0 || sph_lattice_box_count(f, c->dim, c->dx) > SPH_CARVE_MAX)
        return 0;
    for (int k = 0; k < c->nbodies; k++) {
        const sph_body_spec *b = &c->bodies[k];
        const double r = sph_body_shape_radius(b) + c->dx;
        int meets = 1;
        for (int d = 0; d < c->dim && meets; d++)
            meets = b->center[d] + r > f->min[d] && b->center[d] - r < f->max[d];
        if (meets)
            return 1;
    }
    return 0;
}

double sph_shapes_fluid_top(const sph_config *c, const sph_box *f, const double *x)
{
    return f->max[sph_shapes_up(c->dim)] + sph_initial_elevation(c, x[0]);
}

sph_box sph_shapes_fluid_bounds(const sph_config *c, const sph_box *f)
{
    const int up = sph_shapes_up(c->dim);
    sph_box r = *f;
    r.max[up] = f->max[up] + sph_initial_elevation_max(c);
    return r;
}

long sph_shapes_fluid_points(const sph_config *c, const sph_box *f, double *const *pos)
{
    const int dim = c->dim, up = sph_shapes_up(dim);
    const int carve_bodies = box_meets_bodies(c, f);
    const int carve_obstacles = box_meets_obstacles(c, f);
    const int carve = carve_bodies || carve_obstacles;
    if (!pos && !carve && !(sph_initial_elevation_max(c) > 0.0))
        return sph_lattice_box_count(f, dim, c->dx);
    const double dx = c->dx;
    long n[3] = {0, 0, 0};
    for (int d = 0; d < dim; d++)
        n[d] = sph_lattice_axis_count(f->min[d], f->max[d], dx);
    long across = 1; /* columns at each abscissa: the lattice of the middle axes (none in 2D) */
    for (int d = 1; d < up; d++)
        across *= n[d];
    /* The columns are raised by the initial field's elevation, in whole particles, by error
     * diffusion: the columns at abscissa ix get the rows of round(S_ix) - round(S_ix-1), S the
     * running sum of the elevation over dx. Each column's top is then within dx of the surface
     * and the hump's volume within dx^2 / 2 of the sum's (rounding each column alone would drop
     * the tails below dx/2: 11% of a solitary wave's volume at d/dx = 12). */
    double raised = 0.0;
    long rows = 0;
    long i = 0;
    for (long ix = 0; ix < n[0]; ix++) {
        double p[3] = {0.0, 0.0, 0.0};
        p[0] = f->min[0] + (ix + 0.5) * dx;
        raised += fmax(sph_initial_elevation(c, p[0]), 0.0) / dx;
        const double r = floor(raised + 0.5);
        const long raise = r < (double)SPH_LATTICE_AXIS_MAX ? (long)r - rows : 0;
        rows += raise;
        const long nup = n[up] + raise;
        for (long j = 0; j < across; j++) {
            long q = j;
            for (int d = up - 1; d >= 1; q /= n[d], d--)
                p[d] = f->min[d] + (q % n[d] + 0.5) * dx;
            if (!pos && !carve) {
                i += nup;
                continue;
            }
            for (long iu = 0; iu < nup; iu++) {
                p[up] = f->min[up] + (iu + 0.5) * dx;
                if ((carve_bodies && sph_body_covers(c, p)) ||
                    (carve_obstacles && sph_shapes_in_obstacle(c, p)))
                    continue;
                if (pos)
                    for (int d = 0; d < dim; d++)
                        pos[d][i] = p[d];
                i++;
            }
        }
    }
    return i;
}

long sph_shapes_tank_points(const sph_config *c, double *const *pos)
{
    if (c->dim == 3) /* 3D tanks of wall particles are the scene's (sph_config_by_scene) */
        return 0;
    const double dx = c->dx;
    const long L = c->layers;
    const sph_box *t = &c->tank;
    const long nx = sph_lattice_axis_count(t->min[0], t->max[0], dx);
    const long ny = sph_lattice_axis_count(t->min[1], t->max[1], dx);
    if (!pos)
        return (nx + 2 * L) * L + 2 * (ny * L);
    long i = 0;
    for (long k = 0; k < L; k++) {
        const double y = t->min[1] - (k + 0.5) * dx;
        for (long ix = -L; ix < nx + L; ix++, i++) {
            pos[0][i] = t->min[0] + (ix + 0.5) * dx;
            pos[1][i] = y;
        }
    }
    for (long k = 0; k < L; k++)
        for (long iy = 0; iy < ny; iy++, i += 2) {
            const double y = t->min[1] + (iy + 0.5) * dx;
            pos[0][i] = t->min[0] - (k + 0.5) * dx;
            pos[1][i] = y;
            pos[0][i + 1] = t->max[0] + (k + 0.5) * dx;
            pos[1][i + 1] = y;
        }
    return i;
}

/* Distance from (x, y) to the rectangle [x0, x1] x [y0, y1] (0 inside). */
static double rect_distance(double x, double y, double x0, double x1, double y0, double y1)
{
    const double ex = x < x0 ? x0 - x : x > x1 ? x - x1 : 0.0;
    const double ey = y < y0 ? y0 - y : y > y1 ? y - y1 : 0.0;
    return sqrt(ex * ex + ey * ey);
}

double sph_shapes_tank_distance(const sph_config *c, const double *p)
{
    const sph_box *t = &c->tank;
    const double w = c->layers * c->dx, x = p[0], y = p[1];
    const double db = rect_distance(x, y, t->min[0] - w, t->max[0] + w, t->min[1] - w, t->min[1]);
    const double dl = rect_distance(x, y, t->min[0] - w, t->min[0], t->min[1], t->max[1]);
    const double dr = rect_distance(x, y, t->max[0], t->max[0] + w, t->min[1], t->max[1]);
    return fmin(db, fmin(dl, dr));
}

double sph_shapes_hydrostatic_density(const sph_config *c, const double *x, double margin)
{
    const int up = sph_shapes_up(c->dim);
    const double g = -c->gravity[up];
    double depth = 0.0;
    if (g > 0.0)
        for (int b = 0; b < c->nfluid; b++) {
            const sph_box *f = &c->fluid[b];
            const double top = sph_shapes_fluid_top(c, f, x);
            int above = x[up] < top && top - x[up] > depth;
            for (int d = 0; d < up && above; d++)
                above = x[d] >= f->min[d] - margin && x[d] <= f->max[d] + margin;
            if (above)
                depth = top - x[up];
        }
    return sph_eos_density(c, c->rho0 * g * depth);
}
