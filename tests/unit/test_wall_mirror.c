/*
 * mDBC's mirror points for the walls of the geometry list (core/scene/sph_scene.h,
 * sph_scene_mirror; the table sph_fill writes and the sim keeps, saves and restores):
 *   - a 3D tank given as a closed mesh (an open-top cup, as scripts/make-meshes.py --only test2
 *     writes Test 2's) gives every wall particle the built-in tank's mirror point (the box rule,
 *     sph_shapes_wall_mirror) within 1e-12 m; its walls as five box items, the inner layer's;
 *   - a sphere's and a cylinder's shells mirror along the radial line (a cylinder: or across a
 *     wet cap), at the distance 2 R - r from the centre (the cylinder's cap on the domain's floor
 *     is dry: never mirrored across);
 *   - a 2D polygon obstacle on the floor, wound clockwise, mirrors as the built-in obstacle box
 *     does (its face on the floor dry), and the tank's particles in the same table keep the box
 *     rule;
 *   - a shape holding the water (every face dry) is refused at its path;
 *   - a sim with a cup mesh and mDBC, saved and restored without its surface, goes on with the
 *     bits of the run that was not stopped.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>

#include <cmocka.h>

#include "sph_case.h"
#include "sph_fill.h"
#include "sph_mesh.h"
#include "sph_shapes.h"
#include "sph_sim.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define PI 3.14159265358979323846

/* A case from JSON text; the test fails when the parser refuses it. */
static sph_case *parse(const char *text)
{
    json_error_t je;
    json_t *root = json_loads(text, 0, &je);
    if (!root)
        fail_msg("bad JSON in the test at %d: %s", je.line, je.text);
    sph_case *c = calloc(1, sizeof *c);
    assert_non_null(c);
    sph_error err;
    if (sph_case_from_json(root, c, &err))
        fail_msg("%s: %s", err.path, err.message);
    json_decref(root);
    return c;
}

static void drop(sph_case *c)
{
    sph_case_clear(c);
    free(c);
}

/* ---- the cup: a tank's walls as one closed solid ---- */

typedef struct tris {
    double *xyz;
    long n;
} tris;

/* The quad a b c d (corners in turn) as two triangles whose normal points along out. */
static void quad(tris *t, const double *a, const double *b, const double *c, const double *d,
                 const double *out)
{
    const double ab[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    const double ac[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    const double n[3] = {ab[1] * ac[2] - ab[2] * ac[1], ab[2] * ac[0] - ab[0] * ac[2],
                         ab[0] * ac[1] - ab[1] * ac[0]};
    const int flip = n[0] * out[0] + n[1] * out[1] + n[2] * out[2] < 0.0;
    const double *v[2][3] = {{a, flip ? c : b, flip ? b : c}, {a, flip ? d : c, flip ? c : d}};
    for (int h = 0; h < 2; h++, t->n++)
        for (int k = 0; k < 3; k++)
            memcpy(t->xyz + 9 * t->n + 3 * k, v[h][k], 3 * sizeof(double));
}

/* A box's faces but its top, facing out (or in: a cavity's). */
static void box_faces_open(tris *t, const double *lo, const double *hi, int inward)
{
    for (int d = 0; d < 3; d++)
        for (int side = 0; side < 2; side++) {
            if (d == 2 && side == 1)
                continue;
            const int e1 = (d + 1) % 3, e2 = (d + 2) % 3;
            double p[4][3], out[3] = {0, 0, 0};
            static const int u[4] = {0, 1, 1, 0}, v[4] = {0, 0, 1, 1};
            for (int k = 0; k < 4; k++) {
                p[k][d] = side ? hi[d] : lo[d];
                p[k][e1] = u[k] ? hi[e1] : lo[e1];
                p[k][e2] = v[k] ? hi[e2] : lo[e2];
            }
            out[d] = (side ? 1.0 : -1.0) * (inward ? -1.0 : 1.0);
            quad(t, p[0], p[1], p[2], p[3], out);
        }
}

/* The walls of the open tank lo..hi, w thick (but at the top), as one closed surface. */
static sph_mesh *cup(const double *lo, const double *hi, double w)
{
    tris t = {calloc(9 * 28, sizeof(double)), 0};
    assert_non_null(t.xyz);
    const double olo[3] = {lo[0] - w, lo[1] - w, lo[2] - w}, ohi[3] = {hi[0] + w, hi[1] + w, hi[2]};
    box_faces_open(&t, olo, ohi, 0);
    box_faces_open(&t, lo, hi, 1);
    const double z = hi[2], up[3] = {0, 0, 1};
    const double o[4][3] = {
        {olo[0], olo[1], z}, {ohi[0], olo[1], z}, {ohi[0], ohi[1], z}, {olo[0], ohi[1], z}};
    const double in[4][3] = {
        {lo[0], lo[1], z}, {hi[0], lo[1], z}, {hi[0], hi[1], z}, {lo[0], hi[1], z}};
    for (int k = 0; k < 4; k++) /* the rim */
        quad(&t, o[k], o[(k + 1) % 4], in[(k + 1) % 4], in[k], up);
    assert_int_equal(t.n, 28);
    sph_mesh *m = calloc(1, sizeof *m);
    sph_error err;
    assert_non_null(m);
    if (sph_mesh_from_triangles(m, t.xyz, t.n, NULL, "/cup", &err) ||
        sph_mesh_check_closed(m, "/cup", &err))
        fail_msg("the cup: %s", err.message);
    assert_true(sph_mesh_volume(m) > 0.0);
    free(t.xyz);
    return m;
}

/* ---- a case's particles and mirror points through the fill ---- */

typedef struct filled {
    sph_config cfg; /* prepared (sph_fill_prepare) */
    sph_particles P;
    long nf, nw;
    double *mirror; /* the fill's table (sph_fill_has_mirrors), else NULL */
} filled;

static void fill_case(filled *f, const sph_config *c)
{
    memset(f, 0, sizeof *f);
    f->cfg = *c;
    sph_error err;
    if (sph_fill_prepare(&f->cfg, &err))
        fail_msg("%s: %s", err.path, err.message);
    sph_fill_counts n;
    sph_fill_count(&f->cfg, &n);
    f->nf = n.fluid;
    f->nw = n.wall;
    assert_int_equal(sph_particles_alloc(&f->P, n.fluid + n.wall, c->dim, 0), 0);
    if (sph_fill_has_mirrors(&f->cfg)) {
        f->mirror = calloc((size_t)(n.wall * c->dim), sizeof *f->mirror);
        assert_non_null(f->mirror);
    }
    if (sph_fill(&f->cfg, &f->P, f->mirror, &err))
        fail_msg("fill: %s: %s", err.path, err.message);
}

static void unfill(filled *f)
{
    sph_particles_free(&f->P);
    free(f->mirror);
}

static void position(const filled *f, long i, double *x)
{
    x[0] = f->P.x[i];
    x[1] = f->P.y[i];
    x[2] = f->cfg.dim == 3 ? f->P.z[i] : 0.0;
}

/* Wall particle k's mirror point from the table. */
static void table(const filled *f, long k, double *g)
{
    g[2] = 0.0;
    for (int d = 0; d < f->cfg.dim; d++)
        g[d] = f->mirror[(size_t)f->cfg.dim * (size_t)k + (size_t)d];
}

/* The same particles, in the same order, the same types. */
static void same_particles(const filled *a, const filled *b)
{
    assert_int_equal(a->nf, b->nf);
    assert_int_equal(a->nw, b->nw);
    for (long i = 0; i < a->nf + a->nw; i++) {
        double xa[3], xb[3];
        position(a, i, xa);
        position(b, i, xb);
        for (int d = 0; d < 3; d++)
            assert_true(xa[d] == xb[d]);
        assert_int_equal(a->P.type[i], b->P.type[i]);
    }
}

/* A 3D tank 0.3 x 0.2 x 0.3 m (dx 0.02 m: its faces on the lattice's half points) with water
 * 0.2 m deep, the domain the tank's inside: the tank as WALLS (JSON text: "boundary" and
 * "geometry" members). */
static sph_case *tank3d(const char *walls)
{
    char text[4096];
    snprintf(text, sizeof text,
             "{\"name\": \"m\", \"method\": \"wcsph\", \"dim\": 3, \"dx\": 0.02,"
             " \"kernel\": {\"type\": \"wendland_c2\", \"h_over_dx\": 1.414},"
             " \"domain\": {\"min\": [0, 0, 0], \"max\": [0.3, 0.2, 0.3]},"
             " \"fluid\": [{\"box\": {\"min\": [0, 0, 0], \"max\": [0.3, 0.2, 0.2]}}],"
             " \"physics\": {\"gravity\": [0, 0, -9.81], \"eos\": {\"type\": \"linear\", "
             "\"c0\": 20}, \"viscosity\": {\"type\": \"artificial\", \"alpha\": 0.1}},"
             " \"time\": {\"end\": 0.1}, %s}",
             walls);
    return parse(text);
}

static const char *builtin_tank =
    "\"boundary\": {\"type\": \"dynamic\", \"layers\": 3, \"density\": \"mdbc\", \"tank\": "
    "{\"min\": [0, 0, 0], \"max\": [0.3, 0.2, 0.3]}}";

static const char *cup_tank =
    "\"boundary\": {\"type\": \"dynamic\", \"layers\": 3, \"density\": \"mdbc\"},"
    " \"geometry\": [{\"mesh\": \"cup.stl\", \"role\": \"wall\", \"layers\": 3}]";

/* The cup (lo, hi: the tank's inside; 3 dx thick) as c's geometry item k. */
static void give_cup(sph_case *c, int k)
{
    const double lo[3] = {0, 0, 0}, hi[3] = {0.3, 0.2, 0.3};
    c->meshes[k] = cup(lo, hi, 3 * c->sim.dx);
    c->sim.geometry[k].mesh = c->meshes[k];
}

static void cup_against_builtin_tank(void **state)
{
    (void)state;
    sph_case *a = tank3d(builtin_tank), *b = tank3d(cup_tank);
    give_cup(b, 0);
    filled fa, fb;
    fill_case(&fa, &a->sim);
    fill_case(&fb, &b->sim);
    assert_null(fa.mirror); /* no geometry walls: the box rule, where the loops need it */
    assert_non_null(fb.mirror);
    same_particles(&fa, &fb);
    double worst = 0.0, far = 0.0;
    for (long k = 0; k < fa.nw; k++) {
        double x[3], ga[3], gb[3];
        position(&fa, fa.nf + k, x);
        sph_shapes_wall_mirror(&fa.cfg, x, ga);
        table(&fb, k, gb);
        for (int d = 0; d < 3; d++) {
            worst = fmax(worst, fabs(ga[d] - gb[d]));
            far = fmax(far, fabs(gb[d] - x[d]));
        }
    }
    printf("  %ld wall particles: the cup's mirror points within %.3g m of the box rule's (the "
           "farthest %.3g m from its particle)\n",
           fa.nw, worst, far);
    assert_true(worst < 1e-12);
    assert_true(far > 4.0 * a->sim.dx); /* (the deepest layer's, not all at their particles) */
    unfill(&fa);
    unfill(&fb);
    drop(a);
    drop(b);
}

/* The largest difference of the particles' positions [m] and densities [kg/m^3] of two sims
 * with the same particles, matched by id. */
static void sim_difference(const sph_sim *a, const sph_sim *b, double *dpos, double *drho)
{
    sph_particle_view va, vb;
    sph_sim_particles(a, &va);
    sph_sim_particles(b, &vb);
    assert_int_equal(va.n, vb.n);
    long *at = malloc((size_t)va.n * sizeof *at);
    assert_non_null(at);
    for (long i = 0; i < vb.n; i++)
        at[vb.id[i]] = i;
    *dpos = *drho = 0.0;
    for (long i = 0; i < va.n; i++) {
        const long j = at[va.id[i]];
        for (int d = 0; d < 3; d++)
            *dpos = fmax(*dpos, fabs(va.pos[d][i] - vb.pos[d][j]));
        *drho = fmax(*drho, fabs(va.rho[i] - vb.rho[j]));
    }
    free(at);
}

/* The same tanks through the sim with mDBC, 40 steps from rest: the cup's run (its mirror
 * points from the sim's table) stays with the built-in tank's (the box rule's) to rounding. */
static void cup_sim_against_builtin(void **state)
{
    (void)state;
    sph_case *a = tank3d(builtin_tank), *b = tank3d(cup_tank);
    give_cup(b, 0);
    sph_error err;
    sph_sim *sa = sph_sim_create(&a->sim, &err), *sb = sph_sim_create(&b->sim, &err);
    assert_non_null(sa);
    if (!sb)
        fail_msg("%s: %s", err.path, err.message);
    assert_int_equal(sph_sim_step(sa, 40, &err), 0);
    assert_int_equal(sph_sim_step(sb, 40, &err), 0);
    double dpos, drho;
    sim_difference(sa, sb, &dpos, &drho);
    printf("  40 steps: positions within %.3g m, densities within %.3g kg/m^3 of the built-in "
           "tank's run\n",
           dpos, drho);
    assert_true(dpos < 1e-12 && drho < 1e-9);
    sph_sim_destroy(sa);
    sph_sim_destroy(sb);
    drop(a);
    drop(b);
}

/* The tank's walls as five boxes of the geometry list (the floor under the sides, as the
 * built-in tank's): the inner layer facing the water mirrors as the box rule. */
static void box_walls_inner_layer(void **state)
{
    (void)state;
    const char *boxes =
        "\"boundary\": {\"type\": \"dynamic\", \"layers\": 3, \"density\": \"mdbc\"},"
        " \"geometry\": ["
        "{\"box\": {\"min\": [-0.06, -0.06, -0.06], \"max\": [0.36, 0.26, 0]}, \"role\": \"wall\"},"
        "{\"box\": {\"min\": [-0.06, -0.06, 0], \"max\": [0, 0.26, 0.3]}, \"role\": \"wall\"},"
        "{\"box\": {\"min\": [0.3, -0.06, 0], \"max\": [0.36, 0.26, 0.3]}, \"role\": \"wall\"},"
        "{\"box\": {\"min\": [0, -0.06, 0], \"max\": [0.3, 0, 0.3]}, \"role\": \"wall\"},"
        "{\"box\": {\"min\": [0, 0.2, 0], \"max\": [0.3, 0.26, 0.3]}, \"role\": \"wall\"}]";
    sph_case *a = tank3d(builtin_tank), *b = tank3d(boxes);
    filled fa, fb;
    fill_case(&fa, &a->sim);
    fill_case(&fb, &b->sim);
    same_particles(&fa, &fb);
    const double dx = a->sim.dx;
    long inner = 0;
    double worst = 0.0;
    for (long k = 0; k < fa.nw; k++) {
        double x[3], ga[3], gb[3];
        position(&fa, fa.nf + k, x);
        sph_shapes_wall_mirror(&fa.cfg, x, ga);
        const double r = sqrt((ga[0] - x[0]) * (ga[0] - x[0]) + (ga[1] - x[1]) * (ga[1] - x[1]) +
                              (ga[2] - x[2]) * (ga[2] - x[2]));
        if (fabs(r - dx) > 1e-12) /* not of the inner layer facing the water */
            continue;
        table(&fb, k, gb);
        for (int d = 0; d < 3; d++)
            worst = fmax(worst, fabs(ga[d] - gb[d]));
        inner++;
    }
    printf("  the inner layer (%ld particles): within %.3g m of the box rule\n", inner, worst);
    /* the floor's 15 x 10, the sides' 2 (10 + 15) x 15 */
    assert_int_equal(inner, 15 * 10 + 2 * (10 + 15) * 15);
    assert_true(worst < 1e-12);
    unfill(&fa);
    unfill(&fb);
    drop(a);
    drop(b);
}

/* A 3D case with the fluid filling the domain [-0.5, 0.5]^3 around the walls ITEMS. */
static sph_case *open3d(const char *items)
{
    char text[4096];
    snprintf(text, sizeof text,
             "{\"name\": \"m\", \"method\": \"wcsph\", \"dim\": 3, \"dx\": 0.02,"
             " \"domain\": {\"min\": [-0.5, -0.5, -0.5], \"max\": [0.5, 0.5, 0.5]},"
             " \"physics\": {\"gravity\": [0, 0, -9.81], \"eos\": {\"type\": \"linear\", "
             "\"c0\": 20}}, \"time\": {\"end\": 0.1},"
             " \"boundary\": {\"type\": \"dynamic\", \"layers\": 3, \"density\": \"mdbc\"},"
             " \"geometry\": [{\"box\": {\"min\": [-0.5, -0.5, -0.5], \"max\": [0.5, 0.5, 0.5]}, "
             "\"role\": \"fluid\"}, %s]}",
             items);
    return parse(text);
}

/* A sphere's shell, placed by a transform (radius 0.1 scaled by 2, turned, moved): each mirror
 * point on the radial line, 2 R - r from the centre. */
static void sphere_radial(void **state)
{
    (void)state;
    sph_case *c = open3d("{\"sphere\": {\"center\": [0.01, 0, 0], \"radius\": 0.1}, \"role\": "
                         "\"obstacle\", \"layers\": 3, \"transform\": {\"scale\": 2, "
                         "\"rotate\": [30, 45, 60], \"translate\": [0.013, -0.007, 0.021]}}");
    filled f;
    fill_case(&f, &c->sim);
    /* the centre: translate + R (2 * (0.01, 0, 0)), R = Rz(60) Ry(45) Rx(30) on the x axis */
    const double ay = 45.0 * PI / 180, az = 60.0 * PI / 180, R = 0.2;
    const double ctr[3] = {0.013 + 0.02 * cos(az) * cos(ay), -0.007 + 0.02 * sin(az) * cos(ay),
                           0.021 - 0.02 * sin(ay)};
    double worst = 0.0;
    for (long k = 0; k < f.nw; k++) {
        double x[3], g[3], r = 0.0;
        position(&f, f.nf + k, x);
        table(&f, k, g);
        for (int d = 0; d < 3; d++)
            r += (x[d] - ctr[d]) * (x[d] - ctr[d]);
        r = sqrt(r);
        assert_true(r < R && r > R - 3.5 * c->sim.dx);
        for (int d = 0; d < 3; d++)
            worst = fmax(worst, fabs(g[d] - (ctr[d] + (x[d] - ctr[d]) * (2.0 * R - r) / r)));
    }
    printf("  sphere: %ld wall particles, mirror points within %.3g m of the radial line's\n", f.nw,
           worst);
    assert_true(f.nw > 1000);
    assert_true(worst < 1e-12);
    unfill(&f);
    drop(c);
}

/* A cylinder standing on the domain's floor (its bottom cap dry: outside the domain): each
 * particle mirrored across the side along the radial line (2 R - r from the axis) or across the
 * top cap, whichever is nearer, never across the bottom. */
static void cylinder_radial_or_cap(void **state)
{
    (void)state;
    sph_case *c = open3d("{\"cylinder\": {\"center\": [0.01, -0.01, -0.3], \"radius\": 0.15, "
                         "\"axis\": \"z\", \"length\": 0.4}, \"role\": \"obstacle\", "
                         "\"layers\": 3}");
    filled f;
    fill_case(&f, &c->sim);
    const double cx = 0.01, cy = -0.01, R = 0.15, top = -0.1;
    double worst = 0.0;
    long side = 0, cap = 0;
    for (long k = 0; k < f.nw; k++) {
        double x[3], g[3], e[3];
        position(&f, f.nf + k, x);
        table(&f, k, g);
        const double r = hypot(x[0] - cx, x[1] - cy);
        const double ds = R - r, dt = top - x[2];
        if (fabs(ds - dt) < 1e-9)
            continue; /* a tie: either is right */
        if (ds < dt) {
            e[0] = cx + (x[0] - cx) * (2.0 * R - r) / r;
            e[1] = cy + (x[1] - cy) * (2.0 * R - r) / r;
            e[2] = x[2];
            side++;
        } else {
            e[0] = x[0];
            e[1] = x[1];
            e[2] = 2.0 * top - x[2];
            cap++;
        }
        for (int d = 0; d < 3; d++)
            worst = fmax(worst, fabs(g[d] - e[d]));
    }
    printf("  cylinder: %ld across the side, %ld across the top, within %.3g m\n", side, cap,
           worst);
    assert_true(side > 1000 && cap > 200);
    assert_true(worst < 1e-12);
    unfill(&f);
    drop(c);
}

/* 2D: a square obstacle on the floor of a built-in tank, as a polygon wound clockwise, against
 * the same square as a built-in obstacle (both filled through the scene): the same mirror points
 * for the obstacle's particles (but where two faces are equally near) and the tank's. */
static void polygon_obstacle_2d(void **state)
{
    (void)state;
    const char *fmt =
        "{\"name\": \"m\", \"method\": \"wcsph\", \"dim\": 2, \"dx\": 0.01,"
        " \"domain\": {\"min\": [0, 0], \"max\": [1, 0.6]},"
        " \"fluid\": [{\"box\": {\"min\": [0, 0], \"max\": [0.4, 0.3]}}],"
        " \"physics\": {\"eos\": {\"type\": \"linear\", \"c0\": 20}}, \"time\": {\"end\": 0.1},"
        " \"boundary\": {\"type\": \"dynamic\", \"layers\": 3, \"density\": \"mdbc\", \"tank\": "
        "{\"min\": [0, 0], \"max\": [1, 0.6]}%s}, \"geometry\": [%s]}";
    char text[2048];
    /* the built-in obstacle, and a void far from everything to fill through the scene */
    snprintf(text, sizeof text, fmt,
             ", \"obstacles\": [{\"box\": {\"min\": [0.6, 0], \"max\": [0.7, 0.12]}}]",
             "{\"box\": {\"min\": [0.9, 0.5], \"max\": [0.95, 0.55]}, \"role\": \"void\"}");
    sph_case *a = parse(text);
    snprintf(text, sizeof text, fmt, "",
             "{\"box\": {\"min\": [0.9, 0.5], \"max\": [0.95, 0.55]}, \"role\": \"void\"}, "
             "{\"polygon\": [[0.6, 0], [0.6, 0.12], [0.7, 0.12], [0.7, 0]], \"role\": "
             "\"obstacle\", \"layers\": 64}");
    sph_case *b = parse(text);
    filled fa, fb;
    fill_case(&fa, &a->sim);
    fill_case(&fb, &b->sim);
    same_particles(&fa, &fb);
    double worst = 0.0;
    long compared = 0, obstacle = 0;
    for (long k = 0; k < fa.nw; k++) {
        double x[3], ga[3], gb[3];
        position(&fa, fa.nf + k, x);
        const int in = x[0] > 0.6 && x[0] < 0.7 && x[1] > 0.0 && x[1] < 0.12;
        if (in) { /* equally near two wet faces (left, right, top): either is right */
            const double dl = x[0] - 0.6, dr = 0.7 - x[0], dt = 0.12 - x[1];
            const double m = fmin(dl, fmin(dr, dt));
            if ((fabs(dl - m) < 1e-9) + (fabs(dr - m) < 1e-9) + (fabs(dt - m) < 1e-9) > 1)
                continue;
            obstacle++;
        }
        sph_shapes_wall_mirror(&fa.cfg, x, ga);
        table(&fb, k, gb);
        for (int d = 0; d < 3; d++)
            worst = fmax(worst, fabs(ga[d] - gb[d]));
        compared++;
    }
    printf("  2D: %ld wall particles (%ld of the obstacle) within %.3g m of the box rule\n",
           compared, obstacle, worst);
    assert_true(obstacle > 100);
    assert_true(worst < 1e-12);
    unfill(&fa);
    unfill(&fb);
    drop(a);
    drop(b);
}

/* A box wall holding the water, the domain its inside: no face has water on its outer side. */
static void refused_without_wet_face(void **state)
{
    (void)state;
    sph_case *c = parse(
        "{\"name\": \"m\", \"method\": \"wcsph\", \"dim\": 3, \"dx\": 0.02,"
        " \"domain\": {\"min\": [0, 0, 0], \"max\": [0.3, 0.2, 0.3]},"
        " \"physics\": {\"gravity\": [0, 0, -9.81], \"eos\": {\"type\": \"linear\", \"c0\": 20}},"
        " \"time\": {\"end\": 0.1},"
        " \"boundary\": {\"type\": \"dynamic\", \"layers\": 3, \"density\": \"mdbc\"},"
        " \"geometry\": [{\"box\": {\"min\": [0, 0, 0], \"max\": [0.3, 0.2, 0.3]}, \"role\": "
        "\"wall\"}, {\"box\": {\"min\": [0.06, 0.06, 0.06], \"max\": [0.24, 0.14, 0.2]}, "
        "\"role\": \"fluid\"}]}");
    sph_error err;
    assert_null(sph_sim_create(&c->sim, &err));
    printf("  %s: %s\n", err.path, err.message);
    assert_int_equal(err.code, SPH_ERR_INVALID);
    assert_string_equal(err.path, "/geometry/0");
    assert_non_null(strstr(err.message, "outer side"));
    assert_non_null(strstr(err.message, "continuity"));
    /* with continuity walls it runs */
    c->sim.wall_density = SPH_WALL_CONTINUITY;
    sph_sim *s = sph_sim_create(&c->sim, &err);
    if (!s)
        fail_msg("%s: %s", err.path, err.message);
    sph_sim_destroy(s);
    drop(c);
}

/* The cup with mDBC, saved after 10 steps and restored where its surface is not at hand: the
 * mirror points come from the state, and 10 more steps give the bits of the run that went on. */
static void restart_with_mirrors(void **state)
{
    (void)state;
    sph_case *c = tank3d(cup_tank);
    give_cup(c, 0);
    sph_error err;
    sph_sim *a = sph_sim_create(&c->sim, &err);
    if (!a)
        fail_msg("%s: %s", err.path, err.message);
    drop(c); /* the surface goes */
    assert_int_equal(sph_sim_step(a, 10, &err), 0);
    void *buf;
    size_t len;
    assert_int_equal(sph_sim_save(a, &buf, &len, &err), 0);
    sph_sim *b = sph_sim_restore(buf, len, &err);
    if (!b)
        fail_msg("restore: %s", err.message);
    /* the state without its mirror points does not restore */
    assert_null(sph_sim_restore(buf, len - sizeof(double), &err));
    free(buf);
    assert_int_equal(sph_sim_step(a, 10, &err), 0);
    assert_int_equal(sph_sim_step(b, 10, &err), 0);
    sph_particle_view va, vb;
    sph_sim_particles(a, &va);
    sph_sim_particles(b, &vb);
    assert_int_equal(va.n, vb.n);
    long walls = 0;
    double rho_min = INFINITY, rho_max = -INFINITY;
    for (long i = 0; i < va.n; i++) {
        for (int d = 0; d < 3; d++) {
            assert_true(va.pos[d][i] == vb.pos[d][i]);
            assert_true(va.vel[d][i] == vb.vel[d][i]);
        }
        assert_true(va.rho[i] == vb.rho[i]);
        if (va.type[i] == 1) {
            walls++;
            rho_min = fmin(rho_min, va.rho[i]);
            rho_max = fmax(rho_max, va.rho[i]);
        }
    }
    printf("  %ld particles (%ld of the walls, density %.2f to %.2f kg/m^3): the restored run's "
           "bits after 10 more steps\n",
           va.n, walls, rho_min, rho_max);
    assert_true(rho_max > 1000.5); /* the walls' densities come from the water (mDBC) */
    sph_sim_destroy(a);
    sph_sim_destroy(b);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(cup_against_builtin_tank), cmocka_unit_test(cup_sim_against_builtin),
        cmocka_unit_test(box_walls_inner_layer),    cmocka_unit_test(sphere_radial),
        cmocka_unit_test(cylinder_radial_or_cap),   cmocka_unit_test(polygon_obstacle_2d),
        cmocka_unit_test(refused_without_wet_face), cmocka_unit_test(restart_with_mirrors),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
