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
} shape;

struct sph_scene {
    int dim;
    double dx;
    int n;
    shape *s;
    RTCDevice dev;
    long long rtc_bytes; /* what Embree holds (its memory monitor) */
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
             (double)s->s[k].m.nt * (s->dim == 3 ? 3 : 2) * sizeof(int);
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
    double p[3], q[3], best2;
} point_query;

static bool point_query_cb(struct RTCPointQueryFunctionArguments *args)
{
    point_query *u = (point_query *)args->userPtr;
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

/* Distance to a mesh's surface, looking no farther than reach (INFINITY: anywhere); reach or
 * more when nothing is nearer. */
static double mesh_distance(const shape *sh, const double *x, double reach, double *near)
{
    point_query u = {.m = &sh->m, .p = {x[0], x[1], x[2]}, .best2 = reach * reach};
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

static double polygon_distance(const shape *sh, const double *x, double *near)
{
    double best2 = INFINITY;
    for (long k = 0; k < sh->m.nt; k++) {
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
        return polygon_distance(sh, x, near);
    if (sh->kind == SPH_GEOM_MESH)
        return mesh_distance(sh, x, INFINITY, near);
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
    const int cap = SPH_CONFIG_MAX_BOXES * 2 + 8 + SPH_CONFIG_MAX_GEOMETRY;
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

enum { CELL_NONE = 0, CELL_FLUID = 1, CELL_WALL = 2 };

int sph_scene_fill(const sph_scene *s, const sph_config *c, sph_scene_counts *cnt,
                   double *const *pos, double *rho, sph_error *err)
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
                            dist = mesh_distance(sh, x, shell, NULL);
                        else
                            dist = sph_scene_distance(s, q, x, NULL);
                        if (dist < shell)
                            *cell = CELL_WALL;
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
                here += grid[dim == 3 ? AT(i, j, u) : AT(i, u, 0)] == want;
            count += here;
            if (!pos) {
                for (long u = nup - 1; u >= 0; u--) {
                    if (grid[dim == 3 ? AT(i, j, u) : AT(i, u, 0)] != want)
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
                if (cell != want)
                    continue;
                w--;
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
