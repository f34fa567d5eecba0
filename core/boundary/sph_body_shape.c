/*
 * sph_body_shape: the shapes of rigid bodies (sph_body_shape.h). Mass and moment of inertia are
 * those of the uniform solid shape, analytically (circle M = rho pi D^2/4, I = M D^2/8; box
 * M = rho w h, I = M (w^2 + h^2)/12; a polygon's from its corners, M = rho A and I the polar
 * moment of its area about its centroid), whatever the particles that represent its surface.
 *
 * Layer 3 of the set-up pipeline (shapes). May call: libm, sph_config.h. Nothing else: the
 * bodies' dynamics (sph_body.c), the fill and the sim sit above it.
 */
#include "sph_body_shape.h"

#include <math.h>
#include <stdlib.h>

/* ---- polygons: corners v[0 .. n) counter-clockwise about the centroid ------------------- */

/* Corner i of polygon b, i taken modulo its count. */
static const double *corner(const sph_body_spec *b, long i)
{
    const long n = b->ncorners;
    return b->corners[((i % n) + n) % n];
}

/* 1 if b's polygon has a usable count of corners (a fuzzed state's may not). */
static int polygon_ok(const sph_body_spec *b)
{
    return b->ncorners >= 3 && b->ncorners <= SPH_BODY_POLYGON_MAX;
}

/* The distance from u (the body's frame) to the polygon's sides [m]. */
static double polygon_distance(const sph_body_spec *b, const double *u)
{
    double best = INFINITY;
    for (long i = 0; i < b->ncorners; i++) {
        const double *p = corner(b, i), *q = corner(b, i + 1);
        const double ex = q[0] - p[0], ey = q[1] - p[1], wx = u[0] - p[0], wy = u[1] - p[1];
        const double ll = ex * ex + ey * ey;
        double t = ll > 0.0 ? (wx * ex + wy * ey) / ll : 0.0;
        t = t < 0.0 ? 0.0 : t > 1.0 ? 1.0 : t;
        const double rx = wx - t * ex, ry = wy - t * ey;
        best = fmin(best, rx * rx + ry * ry);
    }
    return sqrt(best);
}

/* 1 if u (the body's frame) is inside the polygon (crossings of the ray to +x; a point on a side
 * may go either way: the callers grow or shrink the shape by more than round-off). */
static int polygon_inside(const sph_body_spec *b, const double *u)
{
    int in = 0;
    for (long i = 0; i < b->ncorners; i++) {
        const double *p = corner(b, i), *q = corner(b, i + 1);
        if ((p[1] > u[1]) != (q[1] > u[1]) &&
            u[0] < p[0] + (u[1] - p[1]) * (q[0] - p[0]) / (q[1] - p[1]))
            in = !in;
    }
    return in;
}

/* The inward offset of the polygon at depth d, as pieces: sides moved in by d (a side that has
 * vanished at that depth, its ends passed over each other, has no length) and arcs of radius d
 * about the concave corners. */
typedef struct ring_piece {
    double a[2];    /* a side's start; an arc's centre */
    double t[2];    /* a side's unit direction */
    double r, phi0; /* an arc: radius and the angle it starts at (turning clockwise) */
    double len;     /* its length [m] */
    int arc;
} ring_piece;

/* The pieces of the offset at depth d into ring (2 n of them at most); returns their count and
 * their length into *total. */
static long polygon_ring(const sph_body_spec *b, double d, ring_piece *ring, double *total)
{
    const long n = b->ncorners;
    long np = 0;
    *total = 0.0;
    for (long i = 0; i < n; i++) {
        /* side i runs from corner i to corner i + 1: its direction t, inward normal nn (left) */
        const double *v0 = corner(b, i), *v1 = corner(b, i + 1);
        double t[2] = {v1[0] - v0[0], v1[1] - v0[1]};
        const double l = hypot(t[0], t[1]);
        t[0] /= l;
        t[1] /= l;
        const double nn[2] = {-t[1], t[0]};
        /* the sides before (p) and after (q) it, for the corners at its ends */
        const double *vp = corner(b, i - 1), *v2 = corner(b, i + 2);
        double tp[2] = {v0[0] - vp[0], v0[1] - vp[1]}, tq[2] = {v2[0] - v1[0], v2[1] - v1[1]};
        const double lp = hypot(tp[0], tp[1]), lq = hypot(tq[0], tq[1]);
        tp[0] /= lp, tp[1] /= lp, tq[0] /= lq, tq[1] /= lq;
        const double np_[2] = {-tp[1], tp[0]}, nq[2] = {-tq[1], tq[0]};
        const double turn0 = tp[0] * t[1] - tp[1] * t[0], turn1 = t[0] * tq[1] - t[1] * tq[0];
        double s[2], e[2];
        if (turn0 > 0.0) { /* convex corner i: the mitre of the two moved sides */
            const double f = d / (1.0 + np_[0] * nn[0] + np_[1] * nn[1]);
            s[0] = v0[0] + f * (np_[0] + nn[0]);
            s[1] = v0[1] + f * (np_[1] + nn[1]);
        } else { /* concave (or straight): the arc about corner i, then the moved side */
            s[0] = v0[0] + d * nn[0];
            s[1] = v0[1] + d * nn[1];
            const double sweep =
                atan2(np_[0] * nn[1] - np_[1] * nn[0], np_[0] * nn[0] + np_[1] * nn[1]);
            if (sweep < 0.0 && d > 0.0) {
                ring_piece *q = &ring[np++];
                q->arc = 1;
                q->a[0] = v0[0];
                q->a[1] = v0[1];
                q->r = d;
                q->phi0 = atan2(np_[1], np_[0]);
                q->len = -sweep * d;
                *total += q->len;
            }
        }
        if (turn1 > 0.0) {
            const double f = d / (1.0 + nn[0] * nq[0] + nn[1] * nq[1]);
            e[0] = v1[0] + f * (nn[0] + nq[0]);
            e[1] = v1[1] + f * (nn[1] + nq[1]);
        } else {
            e[0] = v1[0] + d * nn[0];
            e[1] = v1[1] + d * nn[1];
        }
        ring_piece *q = &ring[np++];
        q->arc = 0;
        q->a[0] = s[0];
        q->a[1] = s[1];
        q->t[0] = t[0];
        q->t[1] = t[1];
        q->len = fmax((e[0] - s[0]) * t[0] + (e[1] - s[1]) * t[1], 0.0);
        *total += q->len;
    }
    return np;
}

/* The point at length s along the pieces (walked from piece *k, at *k0 of the length, forward). */
static void ring_point(const ring_piece *ring, long np, long *k, double *k0, double s, double *u)
{
    while (*k < np - 1 && s > *k0 + ring[*k].len) {
        *k0 += ring[*k].len;
        (*k)++;
    }
    const ring_piece *q = &ring[*k];
    const double w = s - *k0;
    if (q->arc) {
        const double phi = q->phi0 - w / q->r;
        u[0] = q->a[0] + q->r * cos(phi);
        u[1] = q->a[1] + q->r * sin(phi);
    } else {
        u[0] = q->a[0] + w * q->t[0];
        u[1] = q->a[1] + w * q->t[1];
    }
}

/* A polygon body's points (sph_body_shape_points); SPH_BODY_COUNT_CAP + 1 when out of memory
 * for its pieces or past the cap. */
static long polygon_points(const sph_body_spec *b, double dx, long L, double *xy)
{
    if (!polygon_ok(b) || !(dx > 0.0) || !isfinite(dx))
        return xy ? 0 : SPH_BODY_COUNT_CAP + 1;
    /* no point inside lies deeper than half the box's narrower side: there the rings end (a
     * concave corner's arc would grow for ever) */
    double lo[2], hi[2];
    sph_body_shape_extent(b, 0.0, lo, hi);
    const double deepest = 0.5 * fmin(hi[0] - lo[0], hi[1] - lo[1]);
    /* a count alone of a shape far past any body's particles (a fuzzed state's) is not visited:
     * each point is checked against every side (about 1e9 checks: seconds) */
    if (!xy && !(sph_body_shape_area(b) / (dx * dx) * (double)b->ncorners < 1e9))
        return SPH_BODY_COUNT_CAP + 1;
    ring_piece *ring = malloc((size_t)(2 * b->ncorners) * sizeof *ring);
    if (!ring)
        return xy ? 0 : SPH_BODY_COUNT_CAP + 1;
    long n = 0;
    double centre[2] = {0.0, 0.0};
    for (long k = 0; k < L; k++) {
        const double d = (k + 0.5) * dx;
        double total = 0.0;
        const long np = d < deepest + dx ? polygon_ring(b, d, ring, &total) : 0;
        if (!(total >= M_PI * dx * (1.0 - SPH_BODY_POLYGON_TOL))) {
            /* what is left inside, less than dx across: one particle, as the circle's */
            const double farther = (double)k * dx * (1.0 + SPH_BODY_EPS);
            if (k > 0 && polygon_inside(b, centre) && polygon_distance(b, centre) > farther) {
                if (xy) {
                    xy[2 * n] = centre[0];
                    xy[2 * n + 1] = centre[1];
                }
                n++;
            }
            break;
        }
        const double md = total / dx;
        if (!(md < (double)SPH_BODY_COUNT_CAP)) {
            n = SPH_BODY_COUNT_CAP + 1;
            break;
        }
        long m = lround(md);
        m = m < 3 ? 3 : m;
        long piece = 0, kept = 0;
        double at = 0.0, sum[2] = {0.0, 0.0};
        for (long j = 0; j < m; j++) {
            double u[2];
            ring_point(ring, np, &piece, &at,
                       total * ((double)j + 0.5 * (double)(k % 2)) / (double)m, u);
            if (!polygon_inside(b, u) || polygon_distance(b, u) < d - 1e-6 * dx)
                continue; /* nearer another part of the surface: not on this ring */
            if (xy) {
                xy[2 * n] = u[0];
                xy[2 * n + 1] = u[1];
            }
            sum[0] += u[0];
            sum[1] += u[1];
            n++;
            kept++;
        }
        if (kept) {
            centre[0] = sum[0] / (double)kept;
            centre[1] = sum[1] / (double)kept;
        }
        if (n > SPH_BODY_COUNT_CAP)
            break;
    }
    free(ring);
    return n;
}

/* ---- every shape ------------------------------------------------------------------------- */

double sph_body_shape_area(const sph_body_spec *b)
{
    if (b->shape == SPH_SHAPE_CIRCLE)
        return 0.25 * M_PI * b->diameter * b->diameter;
    if (b->shape == SPH_SHAPE_POLYGON) {
        double a = 0.0;
        for (long i = 0; polygon_ok(b) && i < b->ncorners; i++) {
            const double *p = corner(b, i), *q = corner(b, i + 1);
            a += p[0] * q[1] - q[0] * p[1];
        }
        return 0.5 * a;
    }
    return b->size[0] * b->size[1];
}

double sph_body_shape_inertia(const sph_body_spec *b, double m)
{
    if (b->shape == SPH_SHAPE_CIRCLE)
        return m * b->diameter * b->diameter / 8.0; /* M R^2 / 2 */
    if (b->shape == SPH_SHAPE_POLYGON) { /* the polar moment of the area about its centroid */
        double j = 0.0;
        for (long i = 0; polygon_ok(b) && i < b->ncorners; i++) {
            const double *p = corner(b, i), *q = corner(b, i + 1);
            const double w = p[0] * q[1] - q[0] * p[1];
            j += w * (p[0] * p[0] + p[0] * q[0] + q[0] * q[0] + p[1] * p[1] + p[1] * q[1] +
                      q[1] * q[1]);
        }
        const double a = sph_body_shape_area(b);
        return a > 0.0 ? m * (j / 12.0) / a : 0.0;
    }
    return m * (b->size[0] * b->size[0] + b->size[1] * b->size[1]) / 12.0;
}

void sph_body_shape_extent(const sph_body_spec *b, double th, double lo[2], double hi[2])
{
    if (b->shape == SPH_SHAPE_POLYGON) {
        const double c = cos(th), s = sin(th);
        lo[0] = lo[1] = INFINITY;
        hi[0] = hi[1] = -INFINITY;
        for (long i = 0; polygon_ok(b) && i < b->ncorners; i++) {
            const double *p = corner(b, i);
            const double x = c * p[0] - s * p[1], y = s * p[0] + c * p[1];
            lo[0] = fmin(lo[0], x);
            hi[0] = fmax(hi[0], x);
            lo[1] = fmin(lo[1], y);
            hi[1] = fmax(hi[1], y);
        }
        return;
    }
    double ext[2];
    if (b->shape == SPH_SHAPE_CIRCLE) {
        ext[0] = ext[1] = 0.5 * b->diameter;
    } else {
        const double c = fabs(cos(th)), s = fabs(sin(th));
        ext[0] = 0.5 * (b->size[0] * c + b->size[1] * s);
        ext[1] = 0.5 * (b->size[0] * s + b->size[1] * c);
    }
    for (int d = 0; d < 2; d++) {
        lo[d] = -ext[d];
        hi[d] = ext[d];
    }
}

double sph_body_shape_radius(const sph_body_spec *b)
{
    if (b->shape == SPH_SHAPE_POLYGON) {
        double r = 0.0;
        for (long i = 0; polygon_ok(b) && i < b->ncorners; i++)
            r = fmax(r, hypot(b->corners[i][0], b->corners[i][1]));
        return r;
    }
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
    if (b->shape == SPH_SHAPE_POLYGON) {
        const double w[2] = {u, v};
        return polygon_ok(b) && (polygon_inside(b, w) || polygon_distance(b, w) < grow);
    }
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
    if (b->shape == SPH_SHAPE_POLYGON)
        return polygon_points(b, dx, L, xy);
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
