/*
 * sph_scene: shapes with roles and transforms, their inside tests and distances, and the fill of
 * one lattice from them (sph_scene.h).
 *
 * Layer 3 of the set-up pipeline. May call: sph_mesh.h, sph_body_shape.h (what a body covers),
 * sph_eos.h, Embree, libm. Never sph_fill.c, the bodies' dynamics or the sim.
 */
#include "sph_scene.h"

#include "sph_body_shape.h"
#include "sph_eos.h"
#include "sph_mesh.h"

#include <embree3/rtcore.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define PI 3.14159265358979323846

/* The most shapes a scene holds: the built-in ones (fluid boxes, the tank's 5 walls, obstacles)
 * and the geometry list's (the fill marks a wall point with its shape in a byte). */
#define SCENE_MAX_SHAPES (SPH_CONFIG_MAX_BOXES * 2 + 8 + SPH_CONFIG_MAX_GEOMETRY)
_Static_assert(SCENE_MAX_SHAPES + 2 <= 255, "a lattice point's byte names its wall's shape");

typedef struct shape {
    sph_geom_kind kind;
    sph_geom_role role;
    int layers;
    double R[3][3], s, t[3]; /* world = t + s R local */
    double min[3], max[3], center[3], radius, length;
    int axis;
    sph_mesh m; /* polygon, mesh: in world coordinates (a copy) */
    double lo[3], hi[3];
    RTCScene rtc; /* a 3D mesh's hierarchy */
    int item;     /* the geometry item it is (its index in the case's list), -1 built in */
    /* mDBC's wet faces (sph_scene_mark_wet): per triangle or side of a surface (wet), per face of
     * a box (2 d + side) or cap of a 3D cylinder (side) */
    unsigned char *wet;
    unsigned char face_wet[6];
    double orient; /* a surface's winding: +1 when its faces wind outwards, -1 inwards */
} shape;

struct sph_scene {
    int dim;
    double dx;
    int n;
    shape *s;
    RTCDevice dev;
    long long rtc_bytes;         /* what Embree holds (its memory monitor) */
    double dom_lo[3], dom_hi[3]; /* the domain, for the wet faces [m] */
};

static bool memory_monitor(void *user, ssize_t bytes, bool post)
{
    (void)post;
    __atomic_add_fetch((long long *)user, (long long)bytes, __ATOMIC_RELAXED);
    return true;
}

double sph_scene_bytes(const sph_scene *s)
{
    double b = (double)sizeof *s + (double)s->n * sizeof *s->s + (double)s->rtc_bytes;
    for (int k = 0; k < s->n; k++)
        b += (double)s->s[k].m.nv * 3 * sizeof(double) +
             (double)s->s[k].m.nt * ((s->dim == 3 ? 3 : 2) * sizeof(int) + (s->s[k].wet ? 1 : 0));
    return b;
}

/* ---- transforms ---- */

static void rotation(const double *deg, double R[3][3])
{
    const double ax = deg[0] * PI / 180.0, ay = deg[1] * PI / 180.0, az = deg[2] * PI / 180.0;
    const double cx = cos(ax), sx = sin(ax), cy = cos(ay), sy = sin(ay), cz = cos(az), sz = sin(az);
    /* Rz Ry Rx: about x first */
    R[0][0] = cz * cy;
    R[0][1] = cz * sy * sx - sz * cx;
    R[0][2] = cz * sy * cx + sz * sx;
    R[1][0] = sz * cy;
    R[1][1] = sz * sy * sx + cz * cx;
    R[1][2] = sz * sy * cx - cz * sx;
    R[2][0] = -sy;
    R[2][1] = cy * sx;
    R[2][2] = cy * cx;
}

static void to_world(const shape *sh, const double *p, double *x)
{
    for (int i = 0; i < 3; i++)
        x[i] = sh->t[i] + sh->s * (sh->R[i][0] * p[0] + sh->R[i][1] * p[1] + sh->R[i][2] * p[2]);
}

static void to_local(const shape *sh, const double *x, double *p)
{
    const double d[3] = {x[0] - sh->t[0], x[1] - sh->t[1], x[2] - sh->t[2]};
    for (int i = 0; i < 3; i++)
        p[i] = (sh->R[0][i] * d[0] + sh->R[1][i] * d[1] + sh->R[2][i] * d[2]) / sh->s;
}

/* ---- primitives, in local coordinates ---- */

static int prim_inside(const shape *sh, int dim, const double *p)
{
    switch (sh->kind) {
    case SPH_GEOM_BOX:
        for (int d = 0; d < dim; d++)
            if (!(p[d] > sh->min[d] && p[d] < sh->max[d]))
                return 0;
        return 1;
    case SPH_GEOM_SPHERE: {
        double r2 = 0.0;
        for (int d = 0; d < dim; d++)
            r2 += (p[d] - sh->center[d]) * (p[d] - sh->center[d]);
        return r2 < sh->radius * sh->radius;
    }
    case SPH_GEOM_CYLINDER: {
        double r2 = 0.0;
        for (int d = 0; d < dim; d++)
            if (dim == 2 || d != sh->axis)
                r2 += (p[d] - sh->center[d]) * (p[d] - sh->center[d]);
        if (dim == 3 && !(fabs(p[sh->axis] - sh->center[sh->axis]) < 0.5 * sh->length))
            return 0;
        return r2 < sh->radius * sh->radius;
    }
    default:
        return 0;
    }
}

/* Distance from p to the primitive's surface (local units), and its nearest point q. */
static double prim_distance(const shape *sh, int dim, const double *p, double *q)
{
    for (int d = 0; d < 3; d++)
        q[d] = p[d];
    switch (sh->kind) {
    case SPH_GEOM_BOX: {
        if (prim_inside(sh, dim, p)) {
            double best = INFINITY;
            int bd = 0;
            double at = 0.0;
            for (int d = 0; d < dim; d++) {
                if (p[d] - sh->min[d] < best) {
                    best = p[d] - sh->min[d];
                    bd = d;
                    at = sh->min[d];
                }
                if (sh->max[d] - p[d] < best) {
                    best = sh->max[d] - p[d];
                    bd = d;
                    at = sh->max[d];
                }
            }
            q[bd] = at;
            return best;
        }
        double e2 = 0.0;
        for (int d = 0; d < dim; d++) {
            q[d] = fmin(fmax(p[d], sh->min[d]), sh->max[d]);
            e2 += (p[d] - q[d]) * (p[d] - q[d]);
        }
        return sqrt(e2);
    }
    case SPH_GEOM_SPHERE:
    case SPH_GEOM_CYLINDER: {
        const int cyl3 = sh->kind == SPH_GEOM_CYLINDER && dim == 3;
        double r2 = 0.0;
        for (int d = 0; d < dim; d++)
            if (!cyl3 || d != sh->axis)
                r2 += (p[d] - sh->center[d]) * (p[d] - sh->center[d]);
        const double r = sqrt(r2);
        const double dr = fabs(sh->radius - r);
        if (!cyl3 || !prim_inside(sh, dim, p)) {
            /* a sphere, a circle; outside a 3D cylinder: its side (an approximation past the
             * ends, used for the shell inside only) */
            for (int d = 0; d < dim; d++)
                if ((!cyl3 || d != sh->axis) && r > 0.0)
                    q[d] = sh->center[d] + (p[d] - sh->center[d]) * sh->radius / r;
            return dr;
        }
        const double along = fabs(p[sh->axis] - sh->center[sh->axis]);
        const double de = 0.5 * sh->length - along;
        if (de < dr) {
            q[sh->axis] = sh->center[sh->axis] +
                          (p[sh->axis] > sh->center[sh->axis] ? 0.5 : -0.5) * sh->length;
            return de;
        }
        for (int d = 0; d < 3; d++)
            if (d != sh->axis && r > 0.0)
                q[d] = sh->center[d] + (p[d] - sh->center[d]) * sh->radius / r;
        return dr;
    }
    default:
        return INFINITY;
    }
}

/* ---- surfaces (polygons, meshes) ---- */

/* Closest point to p on triangle abc (Ericson, Real-Time Collision Detection, 5.1.5). */
static void closest_on_triangle(const double *p, const double *a, const double *b, const double *c,
                                double *q)
{
    double ab[3], ac[3], ap[3];
    for (int i = 0; i < 3; i++) {
        ab[i] = b[i] - a[i];
        ac[i] = c[i] - a[i];
        ap[i] = p[i] - a[i];
    }
#define DOT(u, v) ((u)[0] * (v)[0] + (u)[1] * (v)[1] + (u)[2] * (v)[2])
    const double d1 = DOT(ab, ap), d2 = DOT(ac, ap);
    if (d1 <= 0.0 && d2 <= 0.0) {
        memcpy(q, a, 3 * sizeof *q);
        return;
    }
    double bp[3];
    for (int i = 0; i < 3; i++)
        bp[i] = p[i] - b[i];
    const double d3 = DOT(ab, bp), d4 = DOT(ac, bp);
    if (d3 >= 0.0 && d4 <= d3) {
        memcpy(q, b, 3 * sizeof *q);
        return;
    }
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
        const double v = d1 / (d1 - d3);
        for (int i = 0; i < 3; i++)
            q[i] = a[i] + v * ab[i];
        return;
    }
    double cp[3];
    for (int i = 0; i < 3; i++)
        cp[i] = p[i] - c[i];
    const double d5 = DOT(ab, cp), d6 = DOT(ac, cp);
    if (d6 >= 0.0 && d5 <= d6) {
        memcpy(q, c, 3 * sizeof *q);
        return;
    }
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
        const double w = d2 / (d2 - d6);
        for (int i = 0; i < 3; i++)
            q[i] = a[i] + w * ac[i];
        return;
    }
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
        const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        for (int i = 0; i < 3; i++)
            q[i] = b[i] + w * (c[i] - b[i]);
        return;
    }
    const double den = 1.0 / (va + vb + vc);
    const double v = vb * den, w = vc * den;
    for (int i = 0; i < 3; i++)
        q[i] = a[i] + ab[i] * v + ac[i] * w;
#undef DOT
}

typedef struct point_query {
    const sph_mesh *m;
    const unsigned char *wet; /* NULL: every triangle; else only those with wet[t] */
    double p[3], q[3], best2;
} point_query;

static bool point_query_cb(struct RTCPointQueryFunctionArguments *args)
{
    point_query *u = (point_query *)args->userPtr;
    if (u->wet && !u->wet[args->primID])
        return false;
    const int *t = u->m->t + 3 * (size_t)args->primID;
    double q[3];
    closest_on_triangle(u->p, u->m->v + 3 * (size_t)t[0], u->m->v + 3 * (size_t)t[1],
                        u->m->v + 3 * (size_t)t[2], q);
    const double d2 = (q[0] - u->p[0]) * (q[0] - u->p[0]) + (q[1] - u->p[1]) * (q[1] - u->p[1]) +
                      (q[2] - u->p[2]) * (q[2] - u->p[2]);
    if (d2 < u->best2) {
        u->best2 = d2;
        memcpy(u->q, q, sizeof q);
        args->query->radius = (float)(sqrt(d2) * (1.0 + 1e-6)) + 1e-30f;
        return true;
    }
    return false;
}

/* Distance to a mesh's surface (its triangles t with wet[t], wet not NULL), looking no farther
 * than reach (INFINITY: anywhere); reach or more when nothing is nearer. */
static double mesh_distance(const shape *sh, const double *x, double reach,
                            const unsigned char *wet, double *near)
{
    point_query u = {.m = &sh->m, .wet = wet, .p = {x[0], x[1], x[2]}, .best2 = reach * reach};
    struct RTCPointQuery q;
    q.x = (float)x[0];
    q.y = (float)x[1];
    q.z = (float)x[2];
    q.time = 0.0f;
    q.radius = isfinite(reach) ? (float)(reach * (1.0 + 1e-6)) + 1e-30f : INFINITY;
    struct RTCPointQueryContext ctx;
    rtcInitPointQueryContext(&ctx);
    rtcPointQuery(sh->rtc, &q, &ctx, point_query_cb, &u);
    if (near)
        memcpy(near, u.q, sizeof u.q);
    return u.best2 < reach * reach ? sqrt(u.best2) : reach;
}

/* Distance to a polygon's sides (those k with wet[k], wet not NULL; INFINITY when none). */
static double polygon_distance(const shape *sh, const double *x, const unsigned char *wet,
                               double *near)
{
    double best2 = INFINITY;
    for (long k = 0; k < sh->m.nt; k++) {
        if (wet && !wet[k])
            continue;
        const double *a = sh->m.v + 3 * (size_t)sh->m.t[2 * k];
        const double *b = sh->m.v + 3 * (size_t)sh->m.t[2 * k + 1];
        const double ex = b[0] - a[0], ey = b[1] - a[1];
        const double l2 = ex * ex + ey * ey;
        double u = l2 > 0.0 ? ((x[0] - a[0]) * ex + (x[1] - a[1]) * ey) / l2 : 0.0;
        u = fmin(fmax(u, 0.0), 1.0);
        const double qx = a[0] + u * ex, qy = a[1] + u * ey;
        const double d2 = (x[0] - qx) * (x[0] - qx) + (x[1] - qy) * (x[1] - qy);
        if (d2 < best2) {
            best2 = d2;
            if (near) {
                near[0] = qx;
                near[1] = qy;
                near[2] = 0.0;
            }
        }
    }
    return sqrt(best2);
}

/* Winding number of a polygon about x (crossings of the ray from x towards +x, the half-open
 * rule: a vertex on the ray counts with the side above it). */
static int polygon_winding(const sph_mesh *m, const double *x)
{
    int w = 0;
    for (long k = 0; k < m->nt; k++) {
        const double *a = m->v + 3 * (size_t)m->t[2 * k];
        const double *b = m->v + 3 * (size_t)m->t[2 * k + 1];
        if ((a[1] <= x[1]) == (b[1] <= x[1]))
            continue;
        const double xc = a[0] + (x[1] - a[1]) * (b[0] - a[0]) / (b[1] - a[1]);
        if (xc > x[0])
            w += b[1] > a[1] ? 1 : -1;
    }
    return w;
}

/* A 3D mesh's inside at any point: the parity of a ray's crossings, the majority of three rays
 * in directions no face of a CAD model is likely to hold (a ray through an edge could count it
 * twice). */
static int mesh_inside(const shape *sh, const double *x)
{
    static const float dirs[3][3] = {{0.5773503f, 0.5773491f, 0.5773515f},
                                     {-0.3015113f, 0.9045340f, 0.3015113f},
                                     {0.2672612f, -0.5345225f, -0.8017837f}};
    int votes = 0;
    for (int r = 0; r < 3; r++) {
        int hits = 0;
        float tnear = 0.0f;
        for (int guard = 0; guard < 100000; guard++) {
            struct RTCIntersectContext ctx;
            rtcInitIntersectContext(&ctx);
            struct RTCRayHit rh;
            memset(&rh, 0, sizeof rh);
            rh.ray.org_x = (float)x[0];
            rh.ray.org_y = (float)x[1];
            rh.ray.org_z = (float)x[2];
            rh.ray.dir_x = dirs[r][0];
            rh.ray.dir_y = dirs[r][1];
            rh.ray.dir_z = dirs[r][2];
            rh.ray.tnear = tnear;
            rh.ray.tfar = INFINITY;
            rh.ray.mask = 0xFFFFFFFFu;
            rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
            rtcIntersect1(sh->rtc, &ctx, &rh);
            if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID)
                break;
            hits++;
            tnear = nextafterf(rh.ray.tfar, INFINITY);
        }
        votes += hits & 1;
    }
    return votes >= 2;
}

/* ---- the scene ---- */

int sph_scene_count(const sph_scene *s)
{
    return s->n;
}

void sph_scene_bounds(const sph_scene *s, int k, double *lo, double *hi)
{
    memcpy(lo, s->s[k].lo, 3 * sizeof *lo);
    memcpy(hi, s->s[k].hi, 3 * sizeof *hi);
}

int sph_scene_inside(const sph_scene *s, int k, const double *x)
{
    const shape *sh = &s->s[k];
    for (int d = 0; d < s->dim; d++)
        if (!(x[d] >= sh->lo[d] && x[d] <= sh->hi[d]))
            return 0;
    if (sh->kind == SPH_GEOM_POLYGON)
        return polygon_winding(&sh->m, x) != 0;
    if (sh->kind == SPH_GEOM_MESH)
        return mesh_inside(sh, x);
    double p[3];
    to_local(sh, x, p);
    return prim_inside(sh, s->dim, p);
}

double sph_scene_distance(const sph_scene *s, int k, const double *x, double *near)
{
    const shape *sh = &s->s[k];
    if (sh->kind == SPH_GEOM_POLYGON)
        return polygon_distance(sh, x, NULL, near);
    if (sh->kind == SPH_GEOM_MESH)
        return mesh_distance(sh, x, INFINITY, NULL, near);
    double p[3], q[3];
    to_local(sh, x, p);
    const double d = prim_distance(sh, s->dim, p, q);
    if (near)
        to_world(sh, q, near);
    return d * sh->s;
}

void sph_scene_destroy(sph_scene *s)
{
    if (!s)
        return;
    for (int k = 0; k < s->n; k++) {
        if (s->s[k].rtc)
            rtcReleaseScene(s->s[k].rtc);
        sph_mesh_free(&s->s[k].m);
        free(s->s[k].wet);
    }
    if (s->dev)
        rtcReleaseDevice(s->dev);
    free(s->s);
    free(s);
}

static void item_path(char *buf, size_t n, int item, const char *leaf)
{
    snprintf(buf, n, "/geometry/%d%s", item, leaf);
}

/* A copy of mesh m moved into the world by sh's transform; bounds into sh. */
static int place_mesh(shape *sh, const sph_mesh *m)
{
    sh->m.dim = m->dim;
    sh->m.nv = m->nv;
    sh->m.nt = m->nt;
    const int per = m->dim == 3 ? 3 : 2;
    sh->m.v = malloc(3 * (size_t)m->nv * sizeof *sh->m.v);
    sh->m.t = malloc((size_t)per * (size_t)m->nt * sizeof *sh->m.t);
    if (!sh->m.v || !sh->m.t)
        return -1;
    memcpy(sh->m.t, m->t, (size_t)per * (size_t)m->nt * sizeof *sh->m.t);
    for (int d = 0; d < 3; d++) {
        sh->lo[d] = INFINITY;
        sh->hi[d] = -INFINITY;
    }
    for (long i = 0; i < m->nv; i++) {
        double *x = sh->m.v + 3 * (size_t)i;
        to_world(sh, m->v + 3 * (size_t)i, x);
        if (m->dim == 2)
            x[2] = 0.0;
        for (int d = 0; d < 3; d++) {
            sh->lo[d] = fmin(sh->lo[d], x[d]);
            sh->hi[d] = fmax(sh->hi[d], x[d]);
        }
    }
    return 0;
}

static int build_rtc(RTCDevice dev, shape *sh)
{
    sh->rtc = rtcNewScene(dev);
    if (!sh->rtc)
        return -1;
    rtcSetSceneFlags(sh->rtc, RTC_SCENE_FLAG_ROBUST);
    RTCGeometry g = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_TRIANGLE);
    if (!g)
        return -1;
    float *vb = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                        3 * sizeof(float), (size_t)sh->m.nv);
    unsigned *ib = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                           3 * sizeof(unsigned), (size_t)sh->m.nt);
    if (!vb || !ib) {
        rtcReleaseGeometry(g);
        return -1;
    }
    for (long i = 0; i < 3 * sh->m.nv; i++)
        vb[i] = (float)sh->m.v[i];
    for (long i = 0; i < 3 * sh->m.nt; i++)
        ib[i] = (unsigned)sh->m.t[i];
    rtcCommitGeometry(g);
    rtcAttachGeometry(sh->rtc, g);
    rtcReleaseGeometry(g);
    rtcCommitScene(sh->rtc);
    return rtcGetDeviceError(dev) == RTC_ERROR_NONE ? 0 : -1;
}

/* The local box a primitive lies in, moved into the world: the bounds of its corners. */
static void prim_bounds(shape *sh, int dim)
{
    double lo[3], hi[3];
    for (int d = 0; d < 3; d++) {
        if (sh->kind == SPH_GEOM_BOX) {
            lo[d] = sh->min[d];
            hi[d] = sh->max[d];
        } else {
            const double r = sh->kind == SPH_GEOM_CYLINDER && dim == 3 && d == sh->axis
                                 ? 0.5 * sh->length
                                 : sh->radius;
            lo[d] = sh->center[d] - r;
            hi[d] = sh->center[d] + r;
        }
        if (d >= dim)
            lo[d] = hi[d] = 0.0;
    }
    for (int d = 0; d < 3; d++) {
        sh->lo[d] = INFINITY;
        sh->hi[d] = -INFINITY;
    }
    for (int c = 0; c < 8; c++) {
        const double p[3] = {c & 1 ? hi[0] : lo[0], c & 2 ? hi[1] : lo[1], c & 4 ? hi[2] : lo[2]};
        double x[3];
        to_world(sh, p, x);
        for (int d = 0; d < 3; d++) {
            sh->lo[d] = fmin(sh->lo[d], x[d]);
            sh->hi[d] = fmax(sh->hi[d], x[d]);
        }
    }
    if (dim == 2)
        sh->lo[2] = sh->hi[2] = 0.0;
}

static void builtin_box(shape *sh, sph_geom_role role, int layers, const double *lo,
                        const double *hi)
{
    memset(sh, 0, sizeof *sh);
    sh->kind = SPH_GEOM_BOX;
    sh->item = -1;
    sh->role = role;
    sh->layers = layers;
    sh->s = 1.0;
    for (int d = 0; d < 3; d++) {
        sh->R[d][d] = 1.0;
        sh->min[d] = lo[d];
        sh->max[d] = hi[d];
    }
}

/* The built-in fields as shapes: the fluid boxes, the tank's walls (dynamic particles: its
 * bottom, then its sides, `layers` thick), the obstacles (filled). Returns how many. */
static int builtins(const sph_config *c, shape *out)
{
    int n = 0;
    const int up = c->dim - 1;
    for (int b = 0; b < c->nfluid; b++)
        builtin_box(&out[n++], SPH_ROLE_FLUID, 0, c->fluid[b].min, c->fluid[b].max);
    if (c->has_tank && c->boundary == SPH_BOUNDARY_DYNAMIC) {
        const double w = c->layers * c->dx;
        const sph_box *t = &c->tank;
        double lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
        for (int d = 0; d < c->dim; d++) {
            lo[d] = t->min[d] - w;
            hi[d] = t->max[d] + w;
        }
        hi[up] = t->min[up];
        builtin_box(&out[n++], SPH_ROLE_WALL, c->layers, lo, hi);
        for (int d = 0; d < up; d++)
            for (int side = 0; side < 2; side++) {
                double a[3] = {0, 0, 0}, b[3] = {0, 0, 0};
                for (int e = 0; e < c->dim; e++) {
                    a[e] = e == up ? t->min[e] : e < d ? t->min[e] : t->min[e] - w;
                    b[e] = e == up ? t->max[e] : e < d ? t->max[e] : t->max[e] + w;
                }
                if (side == 0)
                    b[d] = t->min[d];
                else
                    a[d] = t->max[d];
                builtin_box(&out[n++], SPH_ROLE_WALL, c->layers, a, b);
            }
    }
    if (c->boundary == SPH_BOUNDARY_DYNAMIC)
        for (int k = 0; k < c->nobstacles; k++)
            builtin_box(&out[n++], SPH_ROLE_OBSTACLE, 1 << 20, c->obstacles[k].min,
                        c->obstacles[k].max);
    return n;
}

sph_scene *sph_scene_create(const sph_config *c, sph_error *err)
{
    char path[SPH_ERROR_PATH_MAX];
    sph_scene *s = calloc(1, sizeof *s);
    const int cap = SCENE_MAX_SHAPES;
    if (!s || !(s->s = calloc((size_t)cap, sizeof *s->s))) {
        free(s);
        sph_error_set(err, SPH_ERR_NOMEM, "", "out of memory for the scene");
        return NULL;
    }
    s->dim = c->dim;
    s->dx = c->dx;
    s->n = builtins(c, s->s);
    for (int k = 0; k < s->n; k++)
        prim_bounds(&s->s[k], c->dim);
    for (int k = 0; k < c->ngeometry; k++) {
        const sph_geometry_spec *g = &c->geometry[k];
        shape *sh = &s->s[s->n++];
        memset(sh, 0, sizeof *sh);
        sh->kind = g->kind;
        sh->item = k;
        sh->role = g->role;
        sh->layers = g->layers;
        sh->s = g->transform.scale;
        if (!(sh->s > 0.0) || !isfinite(sh->s)) {
            item_path(path, sizeof path, k, "/transform/scale");
            sph_error_set(err, SPH_ERR_INVALID, path, "the scale must be positive, not %g", sh->s);
            goto fail;
        }
        double rot[3] = {g->transform.rotate[0], g->transform.rotate[1], g->transform.rotate[2]};
        if (c->dim == 2)
            rot[0] = rot[1] = 0.0;
        rotation(rot, sh->R);
        for (int d = 0; d < 3; d++) {
            sh->t[d] = d < c->dim ? g->transform.translate[d] : 0.0;
            sh->min[d] = g->min[d];
            sh->max[d] = g->max[d];
            sh->center[d] = g->center[d];
        }
        sh->radius = g->radius;
        sh->length = g->length;
        sh->axis = g->axis;
        if (g->kind == SPH_GEOM_POLYGON || g->kind == SPH_GEOM_MESH) {
            const sph_mesh *m = g->mesh;
            item_path(path, sizeof path, k, g->kind == SPH_GEOM_MESH ? "/mesh" : "/polygon");
            if (!m) {
                sph_error_set(err, SPH_ERR_INVALID, path, "the %s was not read",
                              g->kind == SPH_GEOM_MESH ? "mesh" : "polygon");
                goto fail;
            }
            if (m->dim != c->dim) {
                sph_error_set(err, SPH_ERR_INVALID, path,
                              g->kind == SPH_GEOM_MESH
                                  ? "a mesh is a 3D surface: use \"polygon\" in 2D"
                                  : "a polygon is 2D: use a mesh in 3D");
                goto fail;
            }
            if (sph_mesh_check_closed(m, path, err))
                goto fail;
            if (place_mesh(sh, m)) {
                sph_error_set(err, SPH_ERR_NOMEM, path, "out of memory for the surface");
                goto fail;
            }
            sh->orient = sph_mesh_volume(&sh->m) < 0.0 ? -1.0 : 1.0;
            if (g->kind == SPH_GEOM_MESH) {
                if (!s->dev) {
                    if (!(s->dev = rtcNewDevice("threads=1"))) {
                        sph_error_set(err, SPH_ERR_INTERNAL, path, "Embree could not start");
                        goto fail;
                    }
                    rtcSetDeviceMemoryMonitorFunction(s->dev, memory_monitor, &s->rtc_bytes);
                }
                if (build_rtc(s->dev, sh)) {
                    sph_error_set(err, SPH_ERR_NOMEM, path,
                                  "Embree could not build the mesh's hierarchy");
                    goto fail;
                }
            }
        } else {
            prim_bounds(sh, c->dim);
        }
        /* a fluid's inside must lie in the domain; anything else must meet it */
        for (int d = 0; d < c->dim; d++) {
            const double tol = 1e-9 * (fabs(c->domain.max[d]) + fabs(c->domain.min[d]) + c->dx);
            const int out_fluid =
                g->role == SPH_ROLE_FLUID &&
                (sh->lo[d] < c->domain.min[d] - tol || sh->hi[d] > c->domain.max[d] + tol);
            const int out_any = sh->hi[d] < c->domain.min[d] || sh->lo[d] > c->domain.max[d];
            if (out_fluid || out_any) {
                item_path(path, sizeof path, k, "");
                sph_error_set(err, SPH_ERR_INVALID, path,
                              "the shape (from %g to %g along axis %d, as placed) is %s the "
                              "domain (%g to %g)",
                              sh->lo[d], sh->hi[d], d, out_any ? "outside" : "not inside",
                              c->domain.min[d], c->domain.max[d]);
                goto fail;
            }
        }
    }
    return s;
fail:
    sph_scene_destroy(s);
    return NULL;
}

/* ---- mDBC's mirror points ---- */

int sph_scene_item(const sph_scene *s, int k)
{
    return s->s[k].item;
}

static int is_wall(const shape *sh)
{
    return sh->role == SPH_ROLE_WALL || sh->role == SPH_ROLE_OBSTACLE;
}

/* 1 if o, a point of shape k's surface moved dx/2 out along its normal, is wet: inside the domain
 * and inside no other wall or obstacle shape of the scene. */
static int wet_at(const sph_scene *s, int k, const double *o)
{
    for (int d = 0; d < s->dim; d++)
        if (!(o[d] >= s->dom_lo[d] && o[d] <= s->dom_hi[d]))
            return 0;
    for (int j = 0; j < s->n; j++)
        if (j != k && is_wall(&s->s[j]) && sph_scene_inside(s, j, o))
            return 0;
    return 1;
}

/* 1 if a face of shape k (world coordinates: its centroid c, its corners p[0 .. np), its unit
 * outward normal n) is wet: the outside point of its centroid, or of a point half way from the
 * centroid to a corner, is (wet_at; so that a large face partly covered by another wall is wet). */
static int face_wet(const sph_scene *s, int k, const double *c, const double (*p)[3], int np,
                    const double *n)
{
    for (int m = -1; m < np; m++) {
        double o[3];
        for (int d = 0; d < 3; d++)
            o[d] = (m < 0 ? c[d] : 0.5 * (c[d] + p[m][d])) + 0.5 * s->dx * n[d];
        if (wet_at(s, k, o))
            return 1;
    }
    return 0;
}

/* The world direction of the local direction u (a unit vector: rotated, not scaled). */
static void rotate_to_world(const shape *sh, const double *u, double *n)
{
    for (int i = 0; i < 3; i++)
        n[i] = sh->R[i][0] * u[0] + sh->R[i][1] * u[1] + sh->R[i][2] * u[2];
}

/* A surface's triangles (3D) or sides (2D): wet[t]. Returns how many are wet, or -1 when out of
 * memory. */
static long mark_surface(sph_scene *s, int k)
{
    shape *sh = &s->s[k];
    const sph_mesh *m = &sh->m;
    const int per = s->dim == 3 ? 3 : 2;
    sh->wet = calloc((size_t)(m->nt > 0 ? m->nt : 1), 1);
    if (!sh->wet)
        return -1;
    long nwet = 0;
    for (long f = 0; f < m->nt; f++) {
        double p[3][3], c[3] = {0, 0, 0}, n[3];
        for (int v = 0; v < per; v++)
            for (int d = 0; d < 3; d++) {
                p[v][d] = m->v[3 * (size_t)m->t[per * f + v] + d];
                c[d] += p[v][d] / per;
            }
        if (per == 3) {
            const double ab[3] = {p[1][0] - p[0][0], p[1][1] - p[0][1], p[1][2] - p[0][2]};
            const double ac[3] = {p[2][0] - p[0][0], p[2][1] - p[0][1], p[2][2] - p[0][2]};
            n[0] = ab[1] * ac[2] - ab[2] * ac[1];
            n[1] = ab[2] * ac[0] - ab[0] * ac[2];
            n[2] = ab[0] * ac[1] - ab[1] * ac[0];
        } else { /* a side a -> b of a counter-clockwise polygon has the outside on its right */
            n[0] = p[1][1] - p[0][1];
            n[1] = -(p[1][0] - p[0][0]);
            n[2] = 0.0;
        }
        const double len = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        if (!(len > 0.0))
            continue; /* no area: no normal, never wet */
        for (int d = 0; d < 3; d++)
            n[d] *= sh->orient / len;
        sh->wet[f] = (unsigned char)face_wet(s, k, c, (const double(*)[3])p, per, n);
        nwet += sh->wet[f];
    }
    return nwet;
}

/* A box's faces (2 d + side) and a 3D cylinder's caps (side): face_wet[]. Returns how many are
 * wet. */
static int mark_flat_faces(sph_scene *s, int k)
{
    shape *sh = &s->s[k];
    const int dim = s->dim;
    int nwet = 0;
    if (sh->kind == SPH_GEOM_BOX) {
        for (int d = 0; d < dim; d++)
            for (int side = 0; side < 2; side++) {
                /* the face's centre and corners, local */
                int other[2] = {0, 0}, no = 0;
                for (int e = 0; e < dim; e++)
                    if (e != d)
                        other[no++] = e;
                const int np = 1 << no;
                double cl[3], pl[4][3];
                for (int e = 0; e < 3; e++)
                    cl[e] = e >= dim ? 0.0
                            : e == d ? (side ? sh->max[e] : sh->min[e])
                                     : 0.5 * (sh->min[e] + sh->max[e]);
                for (int q = 0; q < np; q++) {
                    memcpy(pl[q], cl, sizeof cl);
                    for (int o = 0; o < no; o++)
                        pl[q][other[o]] = q & (1 << o) ? sh->max[other[o]] : sh->min[other[o]];
                }
                double c[3], p[4][3], n[3], u[3] = {0, 0, 0};
                u[d] = side ? 1.0 : -1.0;
                to_world(sh, cl, c);
                for (int q = 0; q < np; q++)
                    to_world(sh, pl[q], p[q]);
                rotate_to_world(sh, u, n);
                if (dim == 2)
                    c[2] = p[0][2] = p[1][2] = n[2] = 0.0;
                sh->face_wet[2 * d + side] =
                    (unsigned char)face_wet(s, k, c, (const double(*)[3])p, np, n);
                nwet += sh->face_wet[2 * d + side];
            }
    } else if (sh->kind == SPH_GEOM_CYLINDER && dim == 3) {
        const int a = sh->axis, e1 = (a + 1) % 3, e2 = (a + 2) % 3;
        for (int side = 0; side < 2; side++) {
            double cl[3], pl[4][3];
            for (int e = 0; e < 3; e++)
                cl[e] = sh->center[e];
            cl[a] += (side ? 0.5 : -0.5) * sh->length;
            for (int q = 0; q < 4; q++) {
                memcpy(pl[q], cl, sizeof cl);
                pl[q][q < 2 ? e1 : e2] += (q & 1 ? 1.0 : -1.0) * sh->radius;
            }
            double c[3], p[4][3], n[3], u[3] = {0, 0, 0};
            u[a] = side ? 1.0 : -1.0;
            to_world(sh, cl, c);
            for (int q = 0; q < 4; q++)
                to_world(sh, pl[q], p[q]);
            rotate_to_world(sh, u, n);
            sh->face_wet[side] = (unsigned char)face_wet(s, k, c, (const double(*)[3])p, 4, n);
            nwet += sh->face_wet[side];
        }
    }
    return nwet;
}

int sph_scene_mark_wet(sph_scene *s, const sph_box *domain, sph_error *err)
{
    for (int d = 0; d < 3; d++) {
        s->dom_lo[d] = d < s->dim ? domain->min[d] : 0.0;
        s->dom_hi[d] = d < s->dim ? domain->max[d] : 0.0;
    }
    for (int k = 0; k < s->n; k++) {
        shape *sh = &s->s[k];
        if (sh->item < 0 || !is_wall(sh))
            continue;
        long nwet;
        if (sh->kind == SPH_GEOM_MESH || sh->kind == SPH_GEOM_POLYGON) {
            free(sh->wet);
            sh->wet = NULL;
            nwet = mark_surface(s, k);
        } else {
            nwet = mark_flat_faces(s, k);
            /* a sphere's and a cylinder's round side are wet point by point (sph_scene_mirror) */
            if (sh->kind != SPH_GEOM_BOX)
                nwet = 1;
        }
        char path[SPH_ERROR_PATH_MAX];
        item_path(path, sizeof path, sh->item, "");
        if (nwet < 0)
            return sph_error_set(err, SPH_ERR_NOMEM, path, "out of memory for the wet faces");
        if (nwet == 0)
            return sph_error_set(
                err, SPH_ERR_INVALID, path,
                "no face of this %s has water on its outer side (dx/2 out along its normal: in the "
                "domain, in no other wall): mDBC has nothing to mirror its particles across. A "
                "container is the solid of its walls (scripts/make-meshes.py --only test2), not a "
                "shape holding the water; or use boundary.density \"continuity\"",
                sh->role == SPH_ROLE_WALL ? "wall" : "obstacle");
    }
    return 0;
}

/* The nearest point s (world) of a round side (a sphere, a circle, a 3D cylinder's side; the
 * local point p, not on the axis) and its distance (local units) if the side is wet there
 * (INFINITY if not). */
static double round_side(const sph_scene *s, int k, const double *p, double *near)
{
    const shape *sh = &s->s[k];
    const int cyl3 = sh->kind == SPH_GEOM_CYLINDER && s->dim == 3;
    double u[3] = {0, 0, 0}, r2 = 0.0;
    for (int d = 0; d < s->dim; d++)
        if (!cyl3 || d != sh->axis) {
            u[d] = p[d] - sh->center[d];
            r2 += u[d] * u[d];
        }
    const double r = sqrt(r2);
    if (!(r > 0.0))
        return INFINITY;
    double q[3] = {p[0], p[1], p[2]};
    for (int d = 0; d < s->dim; d++)
        if (!cyl3 || d != sh->axis) {
            u[d] /= r;
            q[d] = sh->center[d] + sh->radius * u[d];
        }
    if (cyl3) /* the side's point nearest p, within the cylinder's length */
        q[sh->axis] = fmin(fmax(p[sh->axis], sh->center[sh->axis] - 0.5 * sh->length),
                           sh->center[sh->axis] + 0.5 * sh->length);
    double n[3], o[3];
    to_world(sh, q, near);
    rotate_to_world(sh, u, n);
    for (int d = 0; d < 3; d++)
        o[d] = d < s->dim ? near[d] + 0.5 * s->dx * n[d] : 0.0;
    if (!wet_at(s, k, o))
        return INFINITY;
    double e2 = 0.0;
    for (int d = 0; d < 3; d++)
        e2 += (p[d] - q[d]) * (p[d] - q[d]);
    return sqrt(e2);
}

/* The nearest point (world) of a primitive's wet faces to x, and its distance (local units;
 * INFINITY when none is wet). */
static double prim_wet_distance(const sph_scene *s, int k, const double *x, double *near)
{
    const shape *sh = &s->s[k];
    const int dim = s->dim;
    double p[3], q[3] = {0, 0, 0}, best = INFINITY;
    to_local(sh, x, p);
    if (sh->kind == SPH_GEOM_BOX) {
        for (int d = 0; d < dim; d++)
            for (int side = 0; side < 2; side++) {
                if (!sh->face_wet[2 * d + side])
                    continue;
                double f[3] = {p[0], p[1], p[2]}, e2 = 0.0;
                for (int e = 0; e < dim; e++) {
                    f[e] = e == d ? (side ? sh->max[e] : sh->min[e])
                                  : fmin(fmax(p[e], sh->min[e]), sh->max[e]);
                    e2 += (p[e] - f[e]) * (p[e] - f[e]);
                }
                if (e2 < best * best) {
                    best = sqrt(e2);
                    memcpy(q, f, sizeof q);
                }
            }
        if (isfinite(best))
            to_world(sh, q, near);
        return best;
    }
    best = round_side(s, k, p, near);
    if (sh->kind == SPH_GEOM_CYLINDER && dim == 3) {
        const int a = sh->axis;
        for (int side = 0; side < 2; side++) {
            if (!sh->face_wet[side])
                continue;
            double f[3] = {p[0], p[1], p[2]}, r2 = 0.0;
            f[a] = sh->center[a] + (side ? 0.5 : -0.5) * sh->length;
            for (int d = 0; d < 3; d++)
                if (d != a)
                    r2 += (p[d] - sh->center[d]) * (p[d] - sh->center[d]);
            if (r2 > sh->radius * sh->radius) /* beyond the cap's rim: onto it */
                for (int d = 0; d < 3; d++)
                    if (d != a)
                        f[d] = sh->center[d] + (p[d] - sh->center[d]) * sh->radius / sqrt(r2);
            double e2 = 0.0;
            for (int d = 0; d < 3; d++)
                e2 += (p[d] - f[d]) * (p[d] - f[d]);
            if (e2 < best * best) {
                best = sqrt(e2);
                to_world(sh, f, near);
            }
        }
    }
    return best;
}

int sph_scene_mirror(const sph_scene *s, int k, const double *x, double *g)
{
    const shape *sh = &s->s[k];
    double near[3] = {0, 0, 0}, dist;
    if (sh->kind == SPH_GEOM_MESH)
        dist = sh->wet ? mesh_distance(sh, x, INFINITY, sh->wet, near) : INFINITY;
    else if (sh->kind == SPH_GEOM_POLYGON)
        dist = sh->wet ? polygon_distance(sh, x, sh->wet, near) : INFINITY;
    else
        dist = prim_wet_distance(s, k, x, near);
    for (int d = 0; d < 3; d++)
        g[d] = d >= s->dim ? 0.0 : isfinite(dist) ? 2.0 * near[d] - x[d] : x[d];
    return isfinite(dist) ? 0 : -1;
}

/* ---- the fill ---- */

/* A lattice of spacing dx from o: index of the first point at or above v, and the last at or
 * below it. */
static long first_at(double v, double o, double dx)
{
    return (long)ceil((v - o) / dx - 1e-9);
}

static long last_at(double v, double o, double dx)
{
    return (long)floor((v - o) / dx + 1e-9);
}

typedef struct crossing {
    long row;
    double x;
    int sign;
} crossing;

typedef struct crossings {
    crossing *c;
    long n, cap;
} crossings;

static int push(crossings *cs, long row, double x, int sign)
{
    if (cs->n == cs->cap) {
        const long cap = cs->cap ? 2 * cs->cap : 1024;
        crossing *p = realloc(cs->c, (size_t)cap * sizeof *p);
        if (!p)
            return -1;
        cs->c = p;
        cs->cap = cap;
    }
    cs->c[cs->n++] = (crossing){row, x, sign};
    return 0;
}

static int by_row_x(const void *a, const void *b)
{
    const crossing *p = a, *q = b;
    if (p->row != q->row)
        return p->row < q->row ? -1 : 1;
    return (p->x > q->x) - (p->x < q->x);
}

/* The side of the perturbed row point p (y + eps, z + eps^2) of the directed edge a -> b in the
 * (y, z) plane, +1 left, -1 right: evaluated on the edge's canonical direction (lower vertex
 * index first) so that the two faces that share the edge see exactly opposite values. */
static int edge_side(const sph_mesh *m, int ia, int ib, double py, double pz)
{
    const int flip = ia > ib;
    const double *u = m->v + 3 * (size_t)(flip ? ib : ia);
    const double *v = m->v + 3 * (size_t)(flip ? ia : ib);
    double e = (v[1] - u[1]) * (pz - u[2]) - (v[2] - u[2]) * (py - u[1]);
    if (e == 0.0)
        e = v[2] != u[2] ? -(v[2] - u[2]) : (v[1] - u[1]);
    const int side = e > 0.0 ? 1 : -1;
    return flip ? -side : side;
}

/* The crossings of a surface with the lattice rows (along x) at (y_j, z_k), j in [j0, j0 + nj),
 * k in [k0, k0 + nk): row (j - j0) + nj (k - k0). sign +1 where the surface is left going
 * towards +x (an outward face), -1 where it is entered. */
static int surface_crossings(const shape *sh, int dim, const double *o, double dx, long j0, long nj,
                             long k0, long nk, crossings *cs)
{
    const sph_mesh *m = &sh->m;
    if (dim == 2) {
        for (long e = 0; e < m->nt; e++) {
            const double *a = m->v + 3 * (size_t)m->t[2 * e];
            const double *b = m->v + 3 * (size_t)m->t[2 * e + 1];
            if (a[1] == b[1])
                continue;
            const long ja = first_at(fmin(a[1], b[1]), o[1], dx) - 1;
            const long jb = last_at(fmax(a[1], b[1]), o[1], dx) + 1;
            for (long j = ja > j0 ? ja : j0; j <= jb && j < j0 + nj; j++) {
                const double y = o[1] + (double)j * dx;
                if ((a[1] <= y) == (b[1] <= y))
                    continue;
                const double xc = a[0] + (y - a[1]) * (b[0] - a[0]) / (b[1] - a[1]);
                if (push(cs, j - j0, xc, b[1] > a[1] ? 1 : -1))
                    return -1;
            }
        }
    } else {
        for (long f = 0; f < m->nt; f++) {
            const int *t = m->t + 3 * (size_t)f;
            const double *a = m->v + 3 * (size_t)t[0], *b = m->v + 3 * (size_t)t[1],
                         *c = m->v + 3 * (size_t)t[2];
            const double ylo = fmin(a[1], fmin(b[1], c[1])), yhi = fmax(a[1], fmax(b[1], c[1]));
            const double zlo = fmin(a[2], fmin(b[2], c[2])), zhi = fmax(a[2], fmax(b[2], c[2]));
            long ja = first_at(ylo, o[1], dx) - 1, jb = last_at(yhi, o[1], dx) + 1;
            long ka = first_at(zlo, o[2], dx) - 1, kb = last_at(zhi, o[2], dx) + 1;
            if (ja < j0)
                ja = j0;
            if (jb > j0 + nj - 1)
                jb = j0 + nj - 1;
            if (ka < k0)
                ka = k0;
            if (kb > k0 + nk - 1)
                kb = k0 + nk - 1;
            double n[3];
            const double ab[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
            const double ac[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
            n[0] = ab[1] * ac[2] - ab[2] * ac[1];
            n[1] = ab[2] * ac[0] - ab[0] * ac[2];
            n[2] = ab[0] * ac[1] - ab[1] * ac[0];
            const double xlo = fmin(a[0], fmin(b[0], c[0])), xhi = fmax(a[0], fmax(b[0], c[0]));
            for (long k = ka; k <= kb; k++)
                for (long j = ja; j <= jb; j++) {
                    const double y = o[1] + (double)j * dx, z = o[2] + (double)k * dx;
                    const int s1 = edge_side(m, t[0], t[1], y, z);
                    if (edge_side(m, t[1], t[2], y, z) != s1 ||
                        edge_side(m, t[2], t[0], y, z) != s1)
                        continue;
                    double xc = n[0] != 0.0 ? a[0] - (n[1] * (y - a[1]) + n[2] * (z - a[2])) / n[0]
                                            : 0.5 * (xlo + xhi);
                    xc = fmin(fmax(xc, xlo), xhi);
                    if (push(cs, (j - j0) + nj * (k - k0), xc, s1))
                        return -1;
                }
        }
    }
    if (cs->n > 1) /* (no row crossed: no array, and qsort may not be given NULL) */
        qsort(cs->c, (size_t)cs->n, sizeof *cs->c, by_row_x);
    return 0;
}

/* A lattice point's state: none, fluid, or a wall particle of shape k (CELL_WALL + k; the scene
 * holds fewer than 254 shapes). */
enum { CELL_NONE = 0, CELL_FLUID = 1, CELL_WALL = 2 };

/* 1 if a lattice point in state cell is what pass `want` (CELL_FLUID or CELL_WALL) writes. */
static int cell_is(unsigned char cell, unsigned char want)
{
    return want == CELL_WALL ? cell >= CELL_WALL : cell == want;
}

int sph_scene_fill(const sph_scene *s, const sph_config *c, sph_scene_counts *cnt,
                   double *const *pos, double *rho, int *owner, sph_error *err)
{
    const int dim = c->dim, up = dim - 1;
    const double dx = c->dx;
    double o[3] = {0, 0, 0};
    for (int d = 0; d < dim; d++)
        o[d] = c->domain.min[d] + 0.5 * dx;
    /* the lattice walked: the fluid's and the walls' shapes */
    double lo[3] = {INFINITY, INFINITY, 0}, hi[3] = {-INFINITY, -INFINITY, 0};
    for (int k = 0; k < s->n; k++) {
        if (s->s[k].role == SPH_ROLE_VOID)
            continue;
        for (int d = 0; d < dim; d++) {
            lo[d] = fmin(lo[d], s->s[k].lo[d]);
            hi[d] = fmax(hi[d], s->s[k].hi[d]);
        }
    }
    memset(cnt, 0, sizeof *cnt);
    for (int d = 0; d < 3; d++) {
        cnt->lo[d] = INFINITY;
        cnt->hi[d] = -INFINITY;
    }
    long i0[3] = {0, 0, 0}, n[3] = {1, 1, 1};
    double cells = 1.0;
    for (int d = 0; d < dim; d++) {
        if (!(lo[d] <= hi[d]))
            return 0;
        i0[d] = first_at(lo[d], o[d], dx);
        const long i1 = last_at(hi[d], o[d], dx);
        if (i1 < i0[d])
            return 0;
        n[d] = i1 - i0[d] + 1;
        cells *= (double)n[d];
    }
    if (cells > c->max_bytes || cells > 4e9)
        return sph_error_set(err, SPH_ERR_NOMEM, "/dx",
                             "the geometry spans %.3g lattice points at dx = %g m, more than the "
                             "memory allowed can walk: use a larger dx",
                             cells, dx);
    unsigned char *grid = calloc((size_t)cells, 1);
    if (!grid)
        return sph_error_set(err, SPH_ERR_NOMEM, "", "out of memory for the fill's lattice");
#define AT(i, j, k) ((size_t)(i) + (size_t)n[0] * ((size_t)(j) + (size_t)n[1] * (size_t)(k)))
    int rc = 0;
    for (int q = 0; q < s->n && rc == 0; q++) {
        const shape *sh = &s->s[q];
        /* the shape's part of the lattice */
        long a[3] = {0, 0, 0}, b[3] = {0, 0, 0};
        int empty = 0;
        for (int d = 0; d < dim; d++) {
            a[d] = first_at(sh->lo[d], o[d], dx) - i0[d];
            b[d] = last_at(sh->hi[d], o[d], dx) - i0[d];
            if (a[d] < 0)
                a[d] = 0;
            if (b[d] > n[d] - 1)
                b[d] = n[d] - 1;
            empty |= b[d] < a[d];
        }
        if (empty)
            continue;
        const int surface = sh->kind == SPH_GEOM_POLYGON || sh->kind == SPH_GEOM_MESH;
        crossings cs = {0};
        const long nj = b[1] - a[1] + 1, nk = dim == 3 ? b[2] - a[2] + 1 : 1;
        if (surface && surface_crossings(sh, dim, o, dx, i0[1] + a[1], nj,
                                         dim == 3 ? i0[2] + a[2] : 0, nk, &cs)) {
            free(cs.c);
            rc = sph_error_set(err, SPH_ERR_NOMEM, "", "out of memory for the fill");
            break;
        }
        const double shell = sh->layers * dx;
        long next = 0; /* the first crossing of the current row */
        for (long k = 0; k < nk; k++)
            for (long j = 0; j < nj; j++) {
                const long row = j + nj * k;
                long cb = next, ce = next;
                if (surface) {
                    while (cb < cs.n && cs.c[cb].row < row)
                        cb++;
                    ce = cb;
                    while (ce < cs.n && cs.c[ce].row == row)
                        ce++;
                    next = ce;
                    if (ce == cb)
                        continue;
                }
                int w = 0; /* winding number, from the right */
                long cc = ce;
                for (long i = b[0]; i >= a[0]; i--) {
                    double x[3] = {o[0] + (double)(i0[0] + i) * dx,
                                   o[1] + (double)(i0[1] + a[1] + j) * dx,
                                   dim == 3 ? o[2] + (double)(i0[2] + a[2] + k) * dx : 0.0};
                    int in;
                    if (surface) {
                        while (cc > cb && cs.c[cc - 1].x > x[0])
                            w += cs.c[--cc].sign;
                        in = w != 0;
                    } else {
                        double p[3];
                        to_local(sh, x, p);
                        in = prim_inside(sh, dim, p);
                    }
                    if (!in)
                        continue;
                    unsigned char *cell = &grid[AT(i, a[1] + j, dim == 3 ? a[2] + k : 0)];
                    switch (sh->role) {
                    case SPH_ROLE_FLUID:
                        *cell = CELL_FLUID;
                        break;
                    case SPH_ROLE_VOID: /* carves the fluid, never a wall */
                        if (*cell == CELL_FLUID)
                            *cell = CELL_NONE;
                        break;
                    default: {
                        double dist;
                        if (sh->kind == SPH_GEOM_MESH)
                            dist = mesh_distance(sh, x, shell, NULL, NULL);
                        else
                            dist = sph_scene_distance(s, q, x, NULL);
                        if (dist < shell)
                            *cell = (unsigned char)(CELL_WALL + q);
                        else if (sh->role == SPH_ROLE_OBSTACLE && *cell == CELL_FLUID)
                            *cell = CELL_NONE;
                    }
                    }
                }
            }
        free(cs.c);
    }
    if (rc) {
        free(grid);
        return rc;
    }
    /* the bodies take their place out of the fluid (2D) */
    if (c->nbodies > 0)
        for (long k = 0; k < n[2]; k++)
            for (long j = 0; j < n[1]; j++)
                for (long i = 0; i < n[0]; i++) {
                    unsigned char *cell = &grid[AT(i, j, k)];
                    const double x[3] = {o[0] + (double)(i0[0] + i) * dx,
                                         o[1] + (double)(i0[1] + j) * dx,
                                         dim == 3 ? o[2] + (double)(i0[2] + k) * dx : 0.0};
                    if (*cell == CELL_FLUID && sph_body_covers(c, x))
                        *cell = CELL_NONE;
                }
    const double g = -c->gravity[up];
    for (int pass = 0; pass < 2; pass++) { /* the fluid, then the walls */
        const unsigned char want = pass == 0 ? CELL_FLUID : CELL_WALL;
        long at = pass == 0 ? 0 : cnt->fluid;
        long count = 0;
        /* columns along the vertical axis, walked from the top down for the depth */
        const long ncol = dim == 3 ? n[0] * n[1] : n[0];
        for (long col = 0; col < ncol; col++) {
            const long i = dim == 3 ? col / n[1] : col, j = dim == 3 ? col % n[1] : 0;
            const long nup = n[up];
            double top = NAN;
            long first = at; /* this column's points are written bottom up */
            long here = 0;
            for (long u = 0; u < nup; u++)
                here += cell_is(grid[dim == 3 ? AT(i, j, u) : AT(i, u, 0)], want);
            count += here;
            if (!pos) {
                for (long u = nup - 1; u >= 0; u--) {
                    if (!cell_is(grid[dim == 3 ? AT(i, j, u) : AT(i, u, 0)], want))
                        continue;
                    double x[3] = {o[0] + (double)(i0[0] + i) * dx, 0.0, 0.0};
                    if (dim == 3) {
                        x[1] = o[1] + (double)(i0[1] + j) * dx;
                        x[2] = o[2] + (double)(i0[2] + u) * dx;
                    } else {
                        x[1] = o[1] + (double)(i0[1] + u) * dx;
                    }
                    for (int d = 0; d < dim; d++) {
                        cnt->lo[d] = fmin(cnt->lo[d], x[d] - 0.5 * dx);
                        cnt->hi[d] = fmax(cnt->hi[d], x[d] + 0.5 * dx);
                    }
                }
                continue;
            }
            long w = first + here; /* written downwards from the column's top */
            for (long u = nup - 1; u >= 0; u--) {
                const unsigned char cell = grid[dim == 3 ? AT(i, j, u) : AT(i, u, 0)];
                const double z = o[up] + (double)(i0[up] + u) * dx;
                if (cell == CELL_FLUID) {
                    const unsigned char above =
                        u + 1 < nup ? grid[dim == 3 ? AT(i, j, u + 1) : AT(i, u + 1, 0)] : 0;
                    if (above != CELL_FLUID)
                        top = z + 0.5 * dx;
                }
                if (!cell_is(cell, want))
                    continue;
                w--;
                if (owner && want == CELL_WALL)
                    owner[w - cnt->fluid] = cell - CELL_WALL;
                pos[0][w] = o[0] + (double)(i0[0] + i) * dx;
                if (dim == 3) {
                    pos[1][w] = o[1] + (double)(i0[1] + j) * dx;
                    pos[2][w] = z;
                } else {
                    pos[1][w] = z;
                }
                const double depth = isnan(top) || !(g > 0.0) ? 0.0 : top - z;
                rho[w] = sph_eos_density(c, c->rho0 * g * depth);
            }
            at = first + here;
        }
        if (pass == 0)
            cnt->fluid = count;
        else
            cnt->wall = count;
    }
#undef AT
    free(grid);
    return 0;
}
