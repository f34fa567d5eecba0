/*
 * sph_body_shape: the shapes of rigid bodies (sph_body_shape.h). Mass and moment of inertia are
 * those of the uniform solid shape, analytically (circle M = rho pi D^2/4, I = M D^2/8; box
 * M = rho w h, I = M (w^2 + h^2)/12), whatever the particles that represent its surface.
 *
 * Layer 3 of the set-up pipeline (shapes). May call: libm, sph_config.h. Nothing else: the
 * bodies' dynamics (sph_body.c), the fill and the sim sit above it.
 */
#include "sph_body_shape.h"

#include <math.h>
#include <stdlib.h>

double sph_body_shape_area(const sph_body_spec *b)
{
    if (b->shape == SPH_SHAPE_CIRCLE)
        return 0.25 * M_PI * b->diameter * b->diameter;
    return b->size[0] * b->size[1];
}

double sph_body_shape_inertia(const sph_body_spec *b, double m)
{
    if (b->shape == SPH_SHAPE_CIRCLE)
        return m * b->diameter * b->diameter / 8.0; /* M R^2 / 2 */
    return m * (b->size[0] * b->size[0] + b->size[1] * b->size[1]) / 12.0;
}

void sph_body_shape_half_extent(const sph_body_spec *b, double th, double ext[2])
{
    if (b->shape == SPH_SHAPE_CIRCLE) {
        ext[0] = ext[1] = 0.5 * b->diameter;
        return;
    }
    const double c = fabs(cos(th)), s = fabs(sin(th));
    ext[0] = 0.5 * (b->size[0] * c + b->size[1] * s);
    ext[1] = 0.5 * (b->size[0] * s + b->size[1] * c);
}

double sph_body_shape_radius(const sph_body_spec *b)
{
    return 0.5 * (b->shape == SPH_SHAPE_CIRCLE ? b->diameter : hypot(b->size[0], b->size[1]));
}

int sph_body_shape_contains(const sph_body_spec *b, const double *x, double grow)
{
    const double dx = x[0] - b->center[0], dy = x[1] - b->center[1];
    if (b->shape == SPH_SHAPE_CIRCLE) {
        const double r = 0.5 * b->diameter + grow;
        return dx * dx + dy * dy < r * r;
    }
    const double c = cos(b->angle), s = sin(b->angle);
    const double u = c * dx + s * dy, v = -s * dx + c * dy; /* into the body's frame */
    return fabs(u) < 0.5 * b->size[0] + grow && fabs(v) < 0.5 * b->size[1] + grow;
}

/* Particles along an edge of length w at spacing dx (at least 1). */
static long edge_count(double w, double dx)
{
    const long n = (long)floor(w / dx + 1e-6);
    return n > 0 ? n : 1;
}

long sph_body_shape_points(const sph_body_spec *b, double dx, double *xy)
{
    long n = 0;
    const long L = b->layers > 0 ? b->layers : (long)1 << 30;
    if (b->shape == SPH_SHAPE_CIRCLE) {
        const double R = 0.5 * b->diameter;
        /* a fuzzed state's dx or diameter that is not a positive number: rings that never end */
        if (!(dx > 0.0) || !(R >= 0.0) || !isfinite(dx) || !isfinite(R))
            return xy ? 0 : SPH_BODY_COUNT_CAP + 1;
        for (long k = 0; k < L; k++) {
            const double r = R - (k + 0.5) * dx;
            if (r < 0.5 * dx * (1.0 - SPH_BODY_EPS)) {
                if (r > -0.5 * dx * (1.0 - SPH_BODY_EPS)) {
                    if (xy)
                        xy[2 * n] = xy[2 * n + 1] = 0.0;
                    n++;
                }
                break;
            }
            /* (a ring past the cap is not rounded to a long: lround overflows, and a circle of
             * 1e20 dx counted 3 per ring took minutes) */
            const double md = 2.0 * M_PI * r / dx;
            if (!xy && !(md < (double)SPH_BODY_COUNT_CAP))
                return SPH_BODY_COUNT_CAP + 1;
            long m = lround(md);
            m = m < 3 ? 3 : m;
            if (!xy) { /* counted, not visited: a fuzzed state's absurd circle returns at once */
                n += m;
                if (n > SPH_BODY_COUNT_CAP)
                    return n;
                continue;
            }
            for (long j = 0; j < m; j++, n++) {
                const double phi = 2.0 * M_PI * ((double)j + 0.5 * (double)(k % 2)) / (double)m;
                xy[2 * n] = r * cos(phi);
                xy[2 * n + 1] = r * sin(phi);
            }
        }
        return n;
    }
    const long nx = edge_count(b->size[0], dx), ny = edge_count(b->size[1], dx);
    if (!xy) { /* counted without visiting the lattice: all of it less the hollow core */
        const long cx = nx - 2 * L > 0 ? nx - 2 * L : 0, cy = ny - 2 * L > 0 ? ny - 2 * L : 0;
        return nx * ny - (b->layers > 0 ? cx * cy : 0);
    }
    for (long i = 0; i < nx; i++)
        for (long j = 0; j < ny; j++) {
            /* layers from the surface: the least of the distances to the four edges */
            long depth = i < nx - 1 - i ? i : nx - 1 - i;
            depth = j < depth ? j : depth;
            depth = ny - 1 - j < depth ? ny - 1 - j : depth;
            if (depth >= L)
                continue;
            xy[2 * n] = -0.5 * (double)nx * dx + ((double)i + 0.5) * dx;
            xy[2 * n + 1] = -0.5 * (double)ny * dx + ((double)j + 0.5) * dx;
            n++;
        }
    return n;
}

double *sph_body_shape_world_points(const sph_body_spec *b, double dx, long *np)
{
    *np = sph_body_shape_points(b, dx, NULL);
    double *xy = malloc((size_t)*np * 2 * sizeof *xy);
    if (!xy)
        return NULL;
    sph_body_shape_points(b, dx, xy);
    const double c = cos(b->angle), s = sin(b->angle);
    for (long p = 0; p < *np; p++) {
        const double u = xy[2 * p], v = xy[2 * p + 1];
        xy[2 * p] = b->center[0] + c * u - s * v;
        xy[2 * p + 1] = b->center[1] + s * u + c * v;
    }
    return xy;
}

long sph_body_count(const sph_config *c)
{
    long n = 0;
    for (int i = 0; i < c->nbodies; i++)
        n += sph_body_shape_points(&c->bodies[i], c->dx, NULL);
    return n;
}

int sph_body_covers(const sph_config *c, const double *x)
{
    for (int i = 0; i < c->nbodies; i++)
        if (sph_body_shape_contains(&c->bodies[i], x, 0.5 * c->dx * (1.0 - SPH_BODY_EPS)))
            return 1;
    return 0;
}
