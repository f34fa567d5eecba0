/*
 * sph_body: rigid bodies of boundary particles (sph_body.h). Yang, Peng & Liu 2014, section 2.3.
 *
 * Beside the fill in the set-up pipeline (DESIGN.md section 2), above the shapes: the bodies'
 * checks, state and dynamics. May call: the bodies' shapes (sph_body_shape.h), the other shapes
 * (sph_shapes.h: the tank's walls, the hydrostatic density), libm. Never the fill or the sim; the
 * methods' steps (wcsph/) and the sim call it.
 */
#include "sph_body.h"

#include "sph_shapes.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* More body particles than this is refused (the checks below visit them all). */
#define SPH_BODY_MAX_PARTICLES 50000000L

/* ---- configuration ------------------------------------------------------------------------ */

/* An error at /bodies/i/field. */
static int body_error(sph_error *err, int i, const char *field, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));
static int body_error(sph_error *err, int i, const char *field, const char *fmt, ...)
{
    char path[SPH_ERROR_PATH_MAX], msg[SPH_ERROR_TEXT_MAX];
    snprintf(path, sizeof path, "/bodies/%d/%s", i, field);
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    return sph_error_set(err, SPH_ERR_INVALID, path, "%s", msg);
}

/* The case field that places body b: a polygon's corners, or the others' centre. */
static const char *place_field(const sph_body_spec *b)
{
    return b->shape == SPH_SHAPE_POLYGON ? "polygon" : "center";
}

int sph_body_check(const sph_config *c, sph_error *err)
{
    if (c->nbodies < 0 || c->nbodies > SPH_CONFIG_MAX_BODIES)
        return sph_error_set(err, SPH_ERR_INVALID, "/bodies", "at most %d bodies",
                             SPH_CONFIG_MAX_BODIES);
    if (c->nbodies > 0 && c->method != SPH_METHOD_WCSPH)
        return sph_error_set(err, SPH_ERR_INVALID, "/bodies",
                             "rigid bodies are available with wcsph only in this version");
    /* A body meets the tank through the dynamic wall particles (the wall's particles push it
     * back); ghost walls mirror only the fluid and would let a body pass through a wall. */
    if (c->nbodies > 0 && c->boundary == SPH_BOUNDARY_GHOST)
        return sph_error_set(err, SPH_ERR_INVALID, "/bodies",
                             "rigid bodies need dynamic boundary particles (boundary.type "
                             "'dynamic'): with ghost walls a body would not meet the walls");
    if ((c->probes & SPH_PROBE_PENETRATION) && c->nbodies == 0)
        return sph_error_set(err, SPH_ERR_INVALID, "/diagnostics/probes",
                             "the probe 'penetration' needs a body (the first in 'bodies')");
    const double dx = c->dx;
    for (int i = 0; i < c->nbodies; i++) {
        const sph_body_spec *b = &c->bodies[i];
        const char *name = b->name;
        if (!name[0] || strnlen(name, SPH_BODY_NAME_MAX) >= SPH_BODY_NAME_MAX)
            return body_error(err, i, "name", "a body needs a name of 1 to %d characters",
                              SPH_BODY_NAME_MAX - 1);
        if (name[strspn(name, "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789_-")])
            return body_error(err, i, "name",
                              "the body name '%s' may hold only letters, digits, '_' and '-' (it "
                              "names the body's series in diag.h5)",
                              name);
        for (int j = 0; j < i; j++)
            if (strcmp(c->bodies[j].name, name) == 0)
                return body_error(err, i, "name", "two bodies are named '%s'", name);
        if ((unsigned)b->shape > SPH_SHAPE_POLYGON)
            return body_error(err, i, "shape", "unknown shape");
        if (b->shape == SPH_SHAPE_POLYGON) {
            if (!(b->ncorners >= 3 && b->ncorners <= SPH_BODY_POLYGON_MAX))
                return body_error(err, i, "polygon", "a polygon has 3 to %d corners",
                                  SPH_BODY_POLYGON_MAX);
            for (int k = 0; k < b->ncorners; k++)
                if (!isfinite(b->corners[k][0]) || !isfinite(b->corners[k][1]))
                    return body_error(err, i, "polygon", "a corner is not a finite number");
            if (!(sph_body_shape_area(b) > 0.0))
                return body_error(err, i, "polygon",
                                  "the polygon '%s' must wind counter-clockwise about its "
                                  "centroid and enclose an area",
                                  name);
            sph_body_spec outer = *b; /* its outermost ring: the offset dx/2 inside */
            outer.layers = 1;
            if (sph_body_shape_points(&outer, dx, NULL) < 3)
                return body_error(err, i, "polygon",
                                  "the polygon '%s' is too small for dx: no ring of particles "
                                  "fits dx/2 inside it (at least 2 dx = %g m across)",
                                  name, 2.0 * dx);
        }
        if (b->density > 0.0 && b->mass > 0.0)
            return body_error(err, i, "mass", "give the density or the mass of '%s', not both",
                              name);
        if (!(b->density > 0.0) && !(b->mass > 0.0))
            return body_error(err, i, b->mass == 0.0 ? "density" : "mass",
                              "the density or mass of '%s' must be a positive number", name);
        if (!(b->free <= SPH_DOF_ALL))
            return body_error(err, i, "free", "unknown degrees of freedom");
        if (b->shape == SPH_SHAPE_CIRCLE && !(b->diameter >= 2.0 * dx * (1.0 - SPH_BODY_EPS)))
            return body_error(err, i, "diameter",
                              "the circle '%s' (D = %g m) is too small for dx: D must be at least "
                              "2 dx = %g m",
                              name, b->diameter, 2.0 * dx);
        if (b->shape == SPH_SHAPE_BOX)
            for (int d = 0; d < 2; d++)
                if (!(b->size[d] >= 2.0 * dx * (1.0 - SPH_BODY_EPS))) {
                    const char *f = d == 0 ? "size/0" : "size/1";
                    return body_error(err, i, f,
                                      "the box '%s' (edge %g m) is too small for dx: each edge "
                                      "must be at least 2 dx = %g m",
                                      name, b->size[d], 2.0 * dx);
                }
        double lo[2], hi[2];
        sph_body_shape_extent(b, b->angle, lo, hi);
        for (int d = 0; d < 2; d++)
            if (!(b->center[d] + lo[d] >= c->domain.min[d] &&
                  b->center[d] + hi[d] <= c->domain.max[d]))
                return body_error(err, i, place_field(b),
                                  "the body '%s' is not inside the domain (centre %g, %g)", name,
                                  b->center[0], b->center[1]);
    }
    if (sph_body_count(c) > SPH_BODY_MAX_PARTICLES)
        return sph_error_set(err, SPH_ERR_NOMEM, "/dx",
                             "the bodies would need more than %ld particles: use a larger dx",
                             SPH_BODY_MAX_PARTICLES);
    /* overlaps: with each other (a particle of one within dx/2 of the other's surface), with the
     * tank's walls (a particle closer than dx/2 to a wall's particles' region) */
    for (int i = 0; i < c->nbodies; i++) {
        long np;
        double *xy = sph_body_shape_world_points(&c->bodies[i], dx, &np);
        if (!xy)
            return sph_error_set(err, SPH_ERR_NOMEM, "", "out of memory");
        int bad = -1, wall = 0;
        for (long p = 0; p < np && bad < 0 && !wall; p++) {
            for (int j = i + 1; j < c->nbodies && bad < 0; j++)
                if (sph_body_shape_contains(&c->bodies[j], xy + 2 * p,
                                            0.5 * dx * (1.0 - SPH_BODY_EPS)))
                    bad = j;
            wall = c->has_tank && c->boundary == SPH_BOUNDARY_DYNAMIC &&
                   sph_shapes_tank_distance(c, xy + 2 * p) < 0.5 * dx * (1.0 - SPH_BODY_EPS);
        }
        free(xy);
        if (bad >= 0)
            return body_error(err, bad, place_field(&c->bodies[bad]),
                              "the body '%s' overlaps the body '%s'", c->bodies[bad].name,
                              c->bodies[i].name);
        if (wall)
            return body_error(err, i, place_field(&c->bodies[i]),
                              "the body '%s' overlaps a wall of the tank", c->bodies[i].name);
    }
    return 0;
}

/* ---- the bodies of a simulation ----------------------------------------------------------- */

int sph_bodies_init(sph_bodies *B, const sph_config *c, long first)
{
    memset(B, 0, sizeof *B);
    B->n = c->nbodies;
    B->dim = 2;
    B->first = first;
    B->np = sph_body_count(c);
    for (int d = 0; d < 3; d++)
        B->gravity[d] = c->gravity[d];
    B->level = c->nfluid > 0 ? -INFINITY : NAN;
    for (int f = 0; f < c->nfluid; f++)
        B->level = fmax(B->level, c->fluid[f].max[1]);
    if (B->n == 0)
        return 0;
    B->local = malloc((size_t)B->np * 2 * sizeof *B->local);
    B->owner = malloc((size_t)B->np * sizeof *B->owner);
    if (!B->local || !B->owner) {
        sph_bodies_free(B);
        return -1;
    }
    long p = 0;
    for (int k = 0; k < B->n; k++) {
        const sph_body_spec *bs = &c->bodies[k];
        sph_body *b = &B->b[k];
        const double area = sph_body_shape_area(bs);
        b->mass = bs->mass > 0.0 ? bs->mass : bs->density * area;
        b->inertia = sph_body_shape_inertia(bs, b->mass);
        b->free = bs->free;
        b->from_fluid = bs->pressure == SPH_BODY_PRESSURE_FLUID;
        b->first = first + p;
        b->np = sph_body_shape_points(bs, c->dx, B->local + 2 * p);
        for (long q = 0; q < b->np; q++) {
            const double *u = B->local + 2 * (p + q);
            B->owner[p + q] = k;
            b->rmax = fmax(b->rmax, sqrt(u[0] * u[0] + u[1] * u[1]));
        }
        p += b->np;
        for (int d = 0; d < 3; d++) {
            b->s.x[d] = bs->center[d];
            b->s.v[d] = bs->velocity[d];
        }
        b->s.theta = bs->angle;
        b->s.omega = bs->omega;
        /* a body at rest before the first evaluation: gravity on its free axes */
        b->s.a[0] = (b->free & SPH_DOF_X) ? B->gravity[0] : 0.0;
        b->s.a[1] = (b->free & SPH_DOF_Y) ? B->gravity[1] : 0.0;
    }
    return 0;
}

void sph_bodies_free(sph_bodies *B)
{
    free(B->local);
    free(B->owner);
    B->local = NULL;
    B->owner = NULL;
}

/* Places body particle q (q = id - first) at row i of P: position and velocity from its body's
 * state and the cosine and sine of its angle (cs[body], rotation_of). The rotated offset is
 * computed from theta afresh, so the body stays rigid to round-off. */
/* cos and sin of every body's angle, once per placement of its particles. */
static void rotation_of(const sph_bodies *B, double cs[][2])
{
    for (int k = 0; k < B->n; k++) {
        cs[k][0] = cos(B->b[k].s.theta);
        cs[k][1] = sin(B->b[k].s.theta);
    }
}

static inline void place(const sph_bodies *B, const double (*cs)[2], long q, sph_particles *P,
                         long i)
{
    const int k = B->owner[q];
    const sph_body_state *s = &B->b[k].s;
    const double c = cs[k][0], sn = cs[k][1];
    const double u = B->local[2 * q], w = B->local[2 * q + 1];
    const double rx = c * u - sn * w, ry = sn * u + c * w;
    P->x[i] = s->x[0] + rx;
    P->y[i] = s->x[1] + ry;
    P->vx[i] = s->v[0] - s->omega * ry;
    P->vy[i] = s->v[1] + s->omega * rx;
}

void sph_bodies_fill(const sph_bodies *B, const sph_config *c, sph_particles *P)
{
    double cs[SPH_CONFIG_MAX_BODIES][2];
    rotation_of(B, cs);
    for (long q = 0; q < B->np; q++) {
        const long i = B->first + q;
        place(B, (const double(*)[2])cs, q, P, i);
        /* with the pressure from the fluid, the density is the contact's alone (rho0 at rest) */
        P->rho[i] =
            B->b[B->owner[q]].from_fluid
                ? c->rho0
                : sph_shapes_hydrostatic_density(c, (const double[]){P->x[i], P->y[i]}, 0.0);
        P->type[i] = SPH_BODY;
        P->id[i] = (int)i;
    }
}

void sph_bodies_move(const sph_bodies *B, sph_particles *P, long n)
{
    if (B->n == 0)
        return;
    const long first = B->first, np = B->np;
    double cs[SPH_CONFIG_MAX_BODIES][2];
    rotation_of(B, cs);
#pragma omp parallel for schedule(dynamic, SPH_OMP_CHUNK) if (n >= SPH_OMP_MIN)
    for (long i = 0; i < n; i++) {
        if (P->type[i] != SPH_BODY)
            continue;
        const long q = P->id[i] - first;
        if (q < 0 || q >= np)
            continue;
        place(B, (const double(*)[2])cs, q, P, i);
    }
}

int sph_bodies_predict(sph_bodies *B, double dt, const sph_box *domain)
{
    int out = -1;
    for (int k = 0; k < B->n; k++) {
        sph_body *b = &B->b[k];
        sph_body_state *s = &b->s;
        for (int d = 0; d < B->dim; d++) {
            b->a0[d] = s->a[d];
            s->x[d] += dt * (s->v[d] + 0.5 * dt * s->a[d]);
            s->v[d] += dt * s->a[d];
            if (out < 0 &&
                !(s->x[d] - b->rmax >= domain->min[d] && s->x[d] + b->rmax <= domain->max[d]))
                out = k;
        }
        b->alpha0 = s->alpha;
        s->theta += dt * (s->omega + 0.5 * dt * s->alpha);
        s->omega += dt * s->alpha;
    }
    return out;
}

void sph_bodies_correct(sph_bodies *B, double dt)
{
    for (int k = 0; k < B->n; k++) {
        sph_body *b = &B->b[k];
        for (int d = 0; d < B->dim; d++)
            b->s.v[d] += 0.5 * dt * (b->s.a[d] - b->a0[d]);
        b->s.omega += 0.5 * dt * (b->s.alpha - b->alpha0);
    }
}

void sph_bodies_gather(sph_bodies *B, const sph_particles *P, long n, double m)
{
    if (B->n == 0)
        return;
    double f[SPH_CONFIG_MAX_BODIES][2] = {{0.0}}, t[SPH_CONFIG_MAX_BODIES] = {0.0};
    for (long i = 0; i < n; i++) {
        if (P->type[i] != SPH_BODY)
            continue;
        const long q = P->id[i] - B->first;
        if (q < 0 || q >= B->np)
            continue;
        const int k = B->owner[q];
        const double fx = m * P->ax[i], fy = m * P->ay[i];
        const double rx = P->x[i] - B->b[k].s.x[0], ry = P->y[i] - B->b[k].s.x[1];
        f[k][0] += fx;
        f[k][1] += fy;
        t[k] += rx * fy - ry * fx;
    }
    static const unsigned axis[2] = {SPH_DOF_X, SPH_DOF_Y};
    for (int k = 0; k < B->n; k++) {
        sph_body *b = &B->b[k];
        for (int d = 0; d < 2; d++) {
            b->s.force[d] = f[k][d];
            b->s.a[d] = (b->free & axis[d]) ? f[k][d] / b->mass + B->gravity[d] : 0.0;
        }
        b->s.torque = t[k];
        b->s.alpha = (b->free & SPH_DOF_ROTATION) ? t[k] / b->inertia : 0.0;
    }
}

double sph_bodies_vmax(const sph_bodies *B)
{
    double vmax = 0.0;
    for (int k = 0; k < B->n; k++) {
        const sph_body_state *s = &B->b[k].s;
        const double v =
            sqrt(s->v[0] * s->v[0] + s->v[1] * s->v[1]) + fabs(s->omega) * B->b[k].rmax;
        vmax = fmax(vmax, v);
    }
    return vmax;
}

double sph_bodies_amax(const sph_bodies *B)
{
    double amax = 0.0;
    for (int k = 0; k < B->n; k++) {
        const sph_body_state *s = &B->b[k].s;
        const double a = sqrt(s->a[0] * s->a[0] + s->a[1] * s->a[1]) +
                         fabs(s->alpha) * B->b[k].rmax + s->omega * s->omega * B->b[k].rmax;
        amax = fmax(amax, a);
    }
    return amax;
}

double sph_bodies_penetration(const sph_bodies *B, const sph_config *c, int k)
{
    double lo[2], hi[2];
    sph_body_shape_extent(&c->bodies[k], B->b[k].s.theta, lo, hi);
    return B->level - (B->b[k].s.x[1] + lo[1]);
}
