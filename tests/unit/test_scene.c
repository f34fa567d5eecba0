/*
 * The geometry list (core/scene/sph_scene.h) through the case parser and the sim: fills against
 * exact volumes (a sphere of radius 20 dx, a torus given as a mesh, the same scaled and rotated;
 * tolerance 1% of the mass, the bound), a 720-sided polygon against the circle it is
 * inscribed in (the same lattice points), the wall shells, and the bad inputs that must be
 * refused at their paths.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>

#include <cmocka.h>

#include "sph_body_shape.h"
#include "sph_case.h"
#include "sph_fill.h"
#include "sph_mesh.h"
#include "sph_scene.h"
#include "sph_sim.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define PI 3.14159265358979323846

/* A case from JSON text; NULL (err filled) when the parser refuses it. */
static sph_case *parse(const char *text, sph_error *err)
{
    json_error_t je;
    json_t *root = json_loads(text, 0, &je);
    if (!root)
        fail_msg("bad JSON in the test at %d: %s", je.line, je.text);
    sph_case *c = calloc(1, sizeof *c);
    assert_non_null(c);
    const int rc = sph_case_from_json(root, c, err);
    json_decref(root);
    if (rc) {
        free(c);
        return NULL;
    }
    return c;
}

static void drop(sph_case *c)
{
    sph_case_clear(c);
    free(c);
}

/* A 3D case around the geometry items GEO (JSON array text), dx 0.01 m, no tank. */
static char *case3d(const char *geo, const char *extra)
{
    static char buf[8192];
    snprintf(
        buf, sizeof buf,
        "{\"name\": \"g\", \"method\": \"wcsph\", \"dim\": 3, \"dx\": 0.01,"
        " \"domain\": {\"min\": [-1, -1, -1], \"max\": [1, 1, 1]},"
        " \"physics\": {\"gravity\": [0, 0, -9.81], \"eos\": {\"type\": \"linear\", \"c0\": 20}},"
        " \"time\": {\"end\": 0.1}, \"geometry\": %s %s}",
        geo, extra ? extra : "");
    return buf;
}

static long fluid_count(sph_config *c)
{
    sph_error err;
    if (sph_fill_prepare(c, &err))
        fail_msg("%s: %s", err.path, err.message);
    return c->geometry_fluid;
}

/* The fluid's mass against rho0 times the exact volume: within 1%. */
static void check_volume(const char *geo, double volume)
{
    sph_error err;
    sph_case *c = parse(case3d(geo, NULL), &err);
    if (!c)
        fail_msg("%s: %s", err.path, err.message);
    const long n = fluid_count(&c->sim);
    const double filled = (double)n * 1e-6;
    const double rel = filled / volume - 1.0;
    printf("  %ld particles: %.6g m^3 against %.6g (%+.3f%%)\n", n, filled, volume, 100.0 * rel);
    assert_true(fabs(rel) < 0.01);
    drop(c);
}

static void sphere_volume(void **state)
{
    (void)state;
    const double r = 0.2; /* 20 dx */
    check_volume("[{\"sphere\": {\"center\": [0.013, -0.007, 0.021], \"radius\": 0.2}, "
                 "\"role\": \"fluid\"}]",
                 4.0 / 3.0 * PI * r * r * r);
    /* radius 10 dx, scaled by 2 and turned: the same sphere */
    check_volume("[{\"sphere\": {\"center\": [0, 0, 0], \"radius\": 0.1}, \"role\": \"fluid\","
                 " \"transform\": {\"scale\": 2, \"rotate\": [30, 45, 60], "
                 "\"translate\": [0.013, -0.007, 0.021]}}]",
                 4.0 / 3.0 * PI * r * r * r);
    /* a cylinder along x, turned about z by 90 degrees */
    check_volume("[{\"cylinder\": {\"center\": [0, 0, 0], \"radius\": 0.2, \"axis\": \"x\", "
                 "\"length\": 0.6}, \"role\": \"fluid\", \"transform\": {\"rotate\": [0, 0, 90]}}]",
                 PI * 0.2 * 0.2 * 0.6);
}

static sph_mesh torus(double R, double r, int nu, int nv)
{
    sph_mesh m;
    assert_int_equal(sph_mesh_torus(&m, R, r, nu, nv), 0);
    return m;
}

static void torus_mesh_volume(void **state)
{
    (void)state;
    sph_error err;
    const char *geo[2] = {
        "[{\"mesh\": \"torus.stl\", \"role\": \"fluid\"}]",
        "[{\"mesh\": \"torus.stl\", \"role\": \"fluid\", \"transform\": {\"scale\": 1.5, "
        "\"rotate\": [20, 70, 10], \"translate\": [0.05, 0, 0.02]}}]"};
    const double scale[2] = {1.0, 1.5};
    for (int k = 0; k < 2; k++) {
        sph_case *c = parse(case3d(geo[k], NULL), &err);
        if (!c)
            fail_msg("%s: %s", err.path, err.message);
        /* R 0.3, r 0.1: 10 dx across the tube; 512 x 128 facets */
        sph_mesh *m = calloc(1, sizeof *m);
        *m = torus(0.3, 0.1, 512, 128);
        const double exact = 2 * PI * PI * 0.3 * 0.1 * 0.1 * pow(scale[k], 3);
        const double faceted = sph_mesh_volume(m) * pow(scale[k], 3);
        c->meshes[0] = m;
        c->sim.geometry[0].mesh = m;
        const long n = fluid_count(&c->sim);
        const double rel = (double)n * 1e-6 / exact - 1.0;
        printf("  torus x%.1f: %ld particles, %+.3f%% of the exact volume (the facets' %+.3f%%)\n",
               scale[k], n, 100 * rel, 100 * (faceted / exact - 1));
        assert_true(fabs(rel) < 0.01);
        /* a point in the hole is outside, one in the tube inside */
        sph_scene *sc = sph_scene_create(&c->sim, &err);
        assert_non_null(sc);
        const int k0 = sph_scene_count(sc) - 1;
        double hole[3] = {0.05 * k, 0.0, 0.02 * k};
        assert_int_equal(sph_scene_inside(sc, k0, hole), 0);
        if (k == 0) {
            const double tube[3] = {0.3, 0.0, 0.0};
            assert_int_equal(sph_scene_inside(sc, k0, tube), 1);
            assert_true(fabs(sph_scene_distance(sc, k0, tube, NULL) - 0.1) < 0.002);
        }
        sph_scene_destroy(sc);
        drop(c);
    }
}

/* A 720-sided polygon inscribed in a circle fills the circle's lattice points, and the fill's
 * particles through the sim are those the scene counted. */
static void polygon_against_circle(void **state)
{
    (void)state;
    char geo[40000];
    int at = snprintf(geo, sizeof geo, "[{\"role\": \"fluid\", \"polygon\": [");
    for (int k = 0; k < 720; k++)
        at += snprintf(geo + at, sizeof geo - (size_t)at, "%s[%.17g, %.17g]", k ? ", " : "",
                       0.5 + 0.2 * cos(2 * PI * k / 720), 0.3 + 0.2 * sin(2 * PI * k / 720));
    snprintf(geo + at, sizeof geo - (size_t)at, "]}]");
    char text[48000];
    const char *fmt = "{\"name\": \"g\", \"method\": \"wcsph\", \"dim\": 2, \"dx\": 0.005,"
                      " \"domain\": {\"min\": [0, 0], \"max\": [1, 0.6]}, \"physics\": {\"eos\": "
                      "{\"type\": \"linear\", \"c0\": 20}},"
                      " \"time\": {\"end\": 0.1}, \"geometry\": %s}";
    snprintf(text, sizeof text, fmt, geo);
    sph_error err;
    sph_case *p = parse(text, &err);
    if (!p)
        fail_msg("%s: %s", err.path, err.message);
    snprintf(text, sizeof text, fmt,
             "[{\"role\": \"fluid\", \"sphere\": {\"center\": [0.5, 0.3], \"radius\": 0.2}}]");
    sph_case *c = parse(text, &err);
    assert_non_null(c);
    sph_sim *a = sph_sim_create(&p->sim, &err);
    if (!a)
        fail_msg("%s: %s", err.path, err.message);
    sph_sim *b = sph_sim_create(&c->sim, &err);
    assert_non_null(b);
    sph_particle_view va, vb;
    sph_sim_particles(a, &va);
    sph_sim_particles(b, &vb);
    printf("  720-gon: %ld particles, circle: %ld (area %.0f dx^2)\n", va.n, vb.n,
           PI * 0.04 / 25e-6);
    assert_int_equal(va.n, vb.n);
    for (long i = 0; i < va.n; i++) {
        assert_true(va.pos[0][i] == vb.pos[0][i]);
        assert_true(va.pos[1][i] == vb.pos[1][i]);
        assert_true(va.rho[i] == vb.rho[i]);
    }
    /* the hydrostatic density under the circle's top: the deepest particle's */
    sph_sim_destroy(a);
    sph_sim_destroy(b);
    drop(p);
    drop(c);
}

/* The water entry's case (cases/water_entry.json) as it is, and with its cylinder given as a
 * 720-sided polygon inscribed in it (a body's polygon, "shape": "polygon"): the same particles,
 * the body's within dx/100 of the circle's (the bound; its rings are placed as the
 * circle's), the fluid's and walls' the same bits; the mass from the polygon's area within its
 * shortfall against the circle's (1 - sin(2 pi/720) 720/(2 pi) = 1.3e-5); the restored run the
 * same bits (the polygon is kept in the state). */
static void body_polygon_against_circle(void **state)
{
    (void)state;
    const char *src = getenv("SPH_SOURCE_DIR");
    char path[4096];
    snprintf(path, sizeof path, "%s/cases/water_entry.json", src ? src : ".");
    json_error_t je;
    json_t *root = json_load_file(path, 0, &je);
    if (!root)
        fail_msg("%s: %s", path, je.text);
    sph_error err;
    sph_case *c = calloc(1, sizeof *c);
    assert_non_null(c);
    if (sph_case_from_json(root, c, &err))
        fail_msg("%s: %s", err.path, err.message);
    /* the same body, its shape a polygon: corner k at angle 2 pi k / 720 on the circle */
    json_t *body = json_array_get(json_object_get(root, "bodies"), 0);
    const double R = 0.5 * json_number_value(json_object_get(body, "diameter"));
    const json_t *ctr = json_object_get(body, "center");
    const double cx = json_number_value(json_array_get(ctr, 0));
    const double cy = json_number_value(json_array_get(ctr, 1));
    json_t *poly = json_array();
    for (int k = 0; k < 720; k++)
        json_array_append_new(poly, json_pack("[ff]", cx + R * cos(2 * PI * k / 720),
                                              cy + R * sin(2 * PI * k / 720)));
    json_object_set_new(body, "shape", json_string("polygon"));
    json_object_set_new(body, "polygon", poly);
    json_object_del(body, "diameter");
    json_object_del(body, "center");
    sph_case *p = calloc(1, sizeof *p);
    assert_non_null(p);
    if (sph_case_from_json(root, p, &err))
        fail_msg("polygon: %s: %s", err.path, err.message);
    json_decref(root);
    sph_sim *a = sph_sim_create(&c->sim, &err);
    assert_non_null(a);
    sph_sim *b = sph_sim_create(&p->sim, &err);
    if (!b)
        fail_msg("polygon: %s: %s", err.path, err.message);
    sph_particle_view va, vb;
    sph_sim_particles(a, &va);
    sph_sim_particles(b, &vb);
    assert_int_equal(va.n, vb.n);
    const double dx = c->sim.dx;
    double worst = 0.0;
    long nbody = 0;
    for (long i = 0; i < va.n; i++) {
        assert_int_equal(va.id[i], vb.id[i]);
        assert_int_equal(va.type[i], vb.type[i]);
        const double d = hypot(va.pos[0][i] - vb.pos[0][i], va.pos[1][i] - vb.pos[1][i]);
        if (va.type[i] == SPH_BODY) {
            worst = fmax(worst, d);
            nbody++;
        } else {
            assert_true(d == 0.0);
        }
    }
    printf("  water entry: %ld body particles of %ld; the 720-gon's at most %.3g dx from the "
           "circle's (bound 0.01 dx)\n",
           nbody, va.n, worst / dx);
    assert_true(nbody > 300);
    assert_true(worst <= 0.01 * dx);
    const double shortfall = 1.0 - sin(2 * PI / 720) * 720 / (2 * PI);
    const double mc = sph_body_shape_area(&c->sim.bodies[0]);
    const double mp = sph_body_shape_area(&p->sim.bodies[0]);
    const double ic = sph_body_shape_inertia(&c->sim.bodies[0], 1.0);
    const double ip = sph_body_shape_inertia(&p->sim.bodies[0], 1.0);
    printf("  area short of the circle's by %.4g (exact %.4g); inertia per kg by %.4g\n",
           1.0 - mp / mc, shortfall, 1.0 - ip / ic);
    assert_true(fabs(1.0 - mp / mc - shortfall) < 1e-9);
    /* a regular n-gon's I/M is R^2 (2 + cos(2 pi/n)) / 6, the circle's R^2 / 2 */
    assert_true(fabs(ip / ic - (2.0 + cos(2 * PI / 720)) / 3.0) < 1e-9);
    /* 20 steps, saved, restored without the case: the same bits as 20 more steps straight on */
    assert_int_equal(sph_sim_step(b, 20, &err), 0);
    void *buf;
    size_t len;
    assert_int_equal(sph_sim_save(b, &buf, &len, &err), 0);
    drop(p);
    sph_sim *r = sph_sim_restore(buf, len, &err);
    if (!r)
        fail_msg("restore: %s", err.message);
    free(buf);
    assert_int_equal(sph_sim_step(b, 20, &err), 0);
    assert_int_equal(sph_sim_step(r, 20, &err), 0);
    sph_sim_particles(b, &vb);
    sph_particle_view vr;
    sph_sim_particles(r, &vr);
    assert_int_equal(vb.n, vr.n);
    for (long i = 0; i < vb.n; i++)
        assert_true(vb.pos[0][i] == vr.pos[0][i] && vb.pos[1][i] == vr.pos[1][i]);
    sph_sim_destroy(a);
    sph_sim_destroy(b);
    sph_sim_destroy(r);
    drop(c);
}

/* A 2D case with one body given by BODY (JSON text) in a tank of water, dx 0.01 m. */
static sph_case *body_case(const char *body, sph_error *err)
{
    char text[8192];
    snprintf(text, sizeof text,
             "{\"name\": \"b\", \"method\": \"wcsph\", \"dim\": 2, \"dx\": 0.01,"
             " \"domain\": {\"min\": [-0.05, -0.05], \"max\": [1.05, 1.2]},"
             " \"fluid\": [{\"box\": {\"min\": [0, 0], \"max\": [1, 0.4]}}],"
             " \"boundary\": {\"type\": \"dynamic\", \"layers\": 3, \"tank\": {\"min\": [0, "
             "0], \"max\": [1, 1]}},"
             " \"physics\": {\"eos\": {\"type\": \"linear\", \"c0\": 20}},"
             " \"time\": {\"end\": 0.1}, \"bodies\": [%s]}",
             body);
    return parse(text, err);
}

/* A concave polygon body (an L of arms 0.3 m and 0.12 m thick, given clockwise) placed in rings:
 * every particle inside, none closer than dx/2 to the surface, none closer than dx/2 to
 * another, one particle for each dx^2 of its area within 5%; and the bad polygons refused at
 * their paths. */
static void body_polygon_concave(void **state)
{
    (void)state;
    sph_error err;
    sph_case *c = body_case("{\"name\": \"ell\", \"shape\": \"polygon\", \"density\": 500,"
                            " \"polygon\": [[0.3, 0.5], [0.3, 0.8], [0.42, 0.8], [0.42, 0.62], "
                            "[0.6, 0.62], [0.6, 0.5]]}",
                            &err);
    if (!c)
        fail_msg("%s: %s", err.path, err.message);
    const sph_body_spec *b = &c->sim.bodies[0];
    const double dx = c->sim.dx, area = 0.3 * 0.12 + 0.18 * 0.12;
    assert_true(fabs(sph_body_shape_area(b) - area) < 1e-12);
    long np;
    double *xy = sph_body_shape_world_points(b, dx, &np);
    assert_non_null(xy);
    const double L[6][2] = {{0.3, 0.5},   {0.3, 0.8},  {0.42, 0.8},
                            {0.42, 0.62}, {0.6, 0.62}, {0.6, 0.5}};
    double nearest = INFINITY, closest = INFINITY;
    for (long i = 0; i < np; i++) {
        const double x = xy[2 * i], y = xy[2 * i + 1];
        const int in = (x > 0.3 && x < 0.42 && y > 0.5 && y < 0.8) ||
                       (x > 0.3 && x < 0.6 && y > 0.5 && y < 0.62);
        assert_true(in);
        for (int k = 0; k < 6; k++) { /* distance to side k */
            const double *p = L[k], *q = L[(k + 1) % 6];
            const double ex = q[0] - p[0], ey = q[1] - p[1];
            double t = ((x - p[0]) * ex + (y - p[1]) * ey) / (ex * ex + ey * ey);
            t = t < 0 ? 0 : t > 1 ? 1 : t;
            nearest = fmin(nearest, hypot(x - p[0] - t * ex, y - p[1] - t * ey));
        }
        for (long j = 0; j < i; j++)
            closest = fmin(closest, hypot(x - xy[2 * j], y - xy[2 * j + 1]));
    }
    printf("  L body: %ld particles for %.0f dx^2; nearest the surface %.4f dx, closest pair "
           "%.3f dx\n",
           np, area / (dx * dx), nearest / dx, closest / dx);
    assert_true(fabs((double)np / (area / (dx * dx)) - 1.0) < 0.05);
    assert_true(nearest >= 0.5 * dx * (1.0 - 1e-6));
    assert_true(closest >= 0.5 * dx);
    free(xy);
    sph_sim *s = sph_sim_create(&c->sim, &err);
    if (!s)
        fail_msg("%s: %s", err.path, err.message);
    assert_int_equal(sph_sim_step(s, 5, &err), 0);
    sph_sim_destroy(s);
    drop(c);

    static const char *const bad[][2] = {
        {"{\"name\": \"x\", \"shape\": \"polygon\", \"density\": 500, \"polygon\": [[0.3, "
         "0.5], [0.5, 0.7], [0.5, 0.5], [0.3, 0.7]]}",
         "/bodies/0/polygon"},
        {"{\"name\": \"x\", \"shape\": \"polygon\", \"density\": 500, \"polygon\": [[0.3, "
         "0.5], [0.5, 0.5]]}",
         "/bodies/0/polygon"},
        {"{\"name\": \"x\", \"shape\": \"polygon\", \"density\": 500, \"polygon\": [[0.3, "
         "0.5], [0.5, 0.5], [0.4, \"a\"]]}",
         "/bodies/0/polygon/2"},
        {"{\"name\": \"x\", \"shape\": \"polygon\", \"density\": 500, \"center\": [0.4, 0.6],"
         " \"polygon\": [[0.3, 0.5], [0.5, 0.5], [0.4, 0.7]]}",
         "/bodies/0/center"},
        {"{\"name\": \"x\", \"shape\": \"polygon\", \"density\": 500}", "/bodies/0/polygon"},
        {"{\"name\": \"x\", \"shape\": \"polygon\", \"density\": 500, \"polygon\": [[0.3, "
         "0.5], [0.312, 0.5], [0.306, 0.51]]}",
         "/bodies/0/polygon"},
        {"{\"name\": \"x\", \"shape\": \"polygon\", \"density\": 500, \"polygon\": [[0.3, "
         "1.1], [0.5, 1.1], [0.4, 1.3]]}",
         "/bodies/0/polygon"},
    };
    for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
        memset(&err, 0, sizeof err);
        c = body_case(bad[k][0], &err);
        sph_sim *t = NULL;
        if (c) { /* the parser took it: the sim's checks must not */
            t = sph_sim_create(&c->sim, &err);
            drop(c);
        }
        printf("  %s: %s\n", err.path, err.message);
        assert_null(t);
        assert_string_equal(err.path, bad[k][1]);
    }
}

/* The fluid and wall particles of a 2D case 1 m square at dx = 0.01 m whose geometry list holds
 * ITEMS (JSON text). */
static void counts2d(const char *items, long *fluid, long *wall)
{
    char text[2048];
    snprintf(text, sizeof text,
             "{\"name\": \"g\", \"method\": \"wcsph\", \"dim\": 2, \"dx\": 0.01, \"domain\": "
             "{\"min\": [0, 0], \"max\": [1, 1]}, \"time\": {\"end\": 0.1}, \"physics\": {\"eos\": "
             "{\"type\": \"linear\", \"c0\": 20}}, \"boundary\": {\"type\": \"dynamic\"}, "
             "\"geometry\": [%s]}",
             items);
    sph_error err;
    sph_case *c = parse(text, &err);
    if (!c)
        fail_msg("%s: %s", err.path, err.message);
    assert_int_equal(sph_fill_prepare(&c->sim, &err), 0);
    *fluid = c->sim.geometry_fluid;
    *wall = c->sim.geometry_wall;
    drop(c);
}

/* A wall's shell: `layers` rows inside the surface; an obstacle's inside past it carves the
 * fluid before it, a wall's does not; a void carves fluid, never a wall. */
static void wall_shells(void **state)
{
    (void)state;
    long nf, nw;
    /* a 40 x 40 box with a 2-layer shell: 40^2 - 36^2 wall points */
    counts2d("{\"box\": {\"min\": [0.3, 0.3], \"max\": [0.7, 0.7]}, \"role\": \"wall\", "
             "\"layers\": 2}",
             &nf, &nw);
    assert_int_equal(nw, 40 * 40 - 36 * 36);
    /* fluid, then an obstacle in it: the fluid less the obstacle's whole box */
    const char *fluid = "{\"box\": {\"min\": [0, 0], \"max\": [1, 0.5]}, \"role\": \"fluid\"}";
    char items[1024];
    snprintf(items, sizeof items,
             "%s, {\"box\": {\"min\": [0.3, 0.1], \"max\": [0.7, 0.3]}, \"role\": \"obstacle\", "
             "\"layers\": 2}",
             fluid);
    counts2d(items, &nf, &nw);
    assert_int_equal(nf, 100 * 50 - 40 * 20);
    assert_int_equal(nw, 40 * 20 - 36 * 16);
    /* the same as a wall: its inside past the shell stays fluid */
    snprintf(items, sizeof items,
             "%s, {\"box\": {\"min\": [0.3, 0.1], \"max\": [0.7, 0.3]}, \"role\": \"wall\", "
             "\"layers\": 2}",
             fluid);
    counts2d(items, &nf, &nw);
    assert_int_equal(nf, 100 * 50 - (40 * 20 - 36 * 16));
    /* a void carves; a fluid after it fills again */
    snprintf(items, sizeof items,
             "%s, {\"sphere\": {\"center\": [0.5, 0.25], \"radius\": 0.2}, \"role\": \"void\"},"
             "{\"box\": {\"min\": [0, 0], \"max\": [1, 0.1]}, \"role\": \"fluid\"}",
             fluid);
    counts2d(items, &nf, &nw);
    const long carved = 100 * 50 - nf;
    printf("  the void carved %ld points (a circle of %.0f, less its part under y = 0.1)\n", carved,
           PI * 400);
    assert_true(carved > 0 && carved < (long)(PI * 400));
    /* a void over a wall's shell leaves the shell whole */
    counts2d("{\"box\": {\"min\": [0.3, 0.3], \"max\": [0.7, 0.7]}, \"role\": \"wall\", "
             "\"layers\": 2}, {\"box\": {\"min\": [0, 0], \"max\": [1, 0.5]}, \"role\": \"void\"}",
             &nf, &nw);
    assert_int_equal(nw, 40 * 40 - 36 * 36);
}

/* Each bad item is refused at its path. */
static void bad_items(void **state)
{
    (void)state;
    static const struct {
        const char *geo, *path, *words;
    } bad[] = {
        {"[{\"sphere\": {\"center\": [0, 0, 0], \"radius\": 0.1}, \"role\": \"fluid\", "
         "\"transform\": {\"scale\": 0}}]",
         "/geometry/0/transform/scale", "positive"},
        {"[{\"sphere\": {\"center\": [0, 0, 0], \"radius\": 0.1}, \"role\": \"water\"}]",
         "/geometry/0/role", "fluid"},
        {"[{\"sphere\": {\"center\": [0, 0, 0], \"radius\": 0.1}, \"box\": {\"min\": [0, 0, 0], "
         "\"max\": [1, 1, 1]}, \"role\": \"fluid\"}]",
         "/geometry/0", "one shape"},
        {"[{\"role\": \"fluid\"}]", "/geometry/0", "needs a shape"},
        {"[{\"polygon\": [[0, 0], [1, 0], [0, 1]], \"role\": \"fluid\"}]", "/geometry/0/polygon",
         "2D"},
        {"[{\"mesh\": \"../x.stl\", \"role\": \"fluid\"}]", "/geometry/0/mesh", ".."},
        {"[{\"sphere\": {\"center\": [0, 0, 0], \"radius\": -1}, \"role\": \"fluid\"}]",
         "/geometry/0/sphere/radius", ""},
        {"[{\"sphere\": {\"center\": [0, 0, 0], \"radius\": 0.1}, \"role\": \"fluid\", "
         "\"colour\": 1}]",
         "/geometry/0/colour", ""},
    };
    for (size_t k = 0; k < sizeof bad / sizeof *bad; k++) {
        sph_error err;
        sph_case *c = parse(case3d(bad[k].geo, NULL), &err);
        if (c)
            fail_msg("accepted: %s", bad[k].geo);
        printf("  %s: %s\n", err.path, err.message);
        assert_string_equal(err.path, bad[k].path);
        assert_non_null(strstr(err.message, bad[k].words));
    }
    /* a fluid shape that reaches out of the domain: at the scene, when it is built */
    sph_error err;
    sph_case *c = parse(case3d("[{\"sphere\": {\"center\": [0.95, 0, 0], \"radius\": 0.1}, "
                               "\"role\": \"fluid\"}]",
                               NULL),
                        &err);
    assert_non_null(c);
    assert_null(sph_sim_create(&c->sim, &err));
    assert_string_equal(err.path, "/geometry/0");
    assert_non_null(strstr(err.message, "domain"));
    drop(c);
    /* ghost walls mirror a tank's box only */
    c = parse(case3d("[{\"sphere\": {\"center\": [0, 0, 0], \"radius\": 0.1}, \"role\": "
                     "\"fluid\"}]",
                     ", \"boundary\": {\"type\": \"ghost\", \"tank\": {\"min\": [-1, -1, -1], "
                     "\"max\": [1, 1, 1]}}"),
              &err);
    assert_null(c);
    assert_string_equal(err.path, "/geometry");
    assert_non_null(strstr(err.message, "dynamic"));
    /* a 2D polygon with 2 points */
    c = parse("{\"name\": \"g\", \"method\": \"wcsph\", \"dim\": 2, \"dx\": 0.01, \"domain\": "
              "{\"min\": [0, 0], \"max\": [1, 1]}, \"physics\": {\"eos\": {\"type\": \"linear\", "
              "\"c0\": 20}}, \"time\": {\"end\": 0.1}, "
              "\"geometry\": "
              "[{\"polygon\": [[0, 0], [1, 0]], \"role\": \"fluid\"}]}",
              &err);
    assert_null(c);
    assert_string_equal(err.path, "/geometry/0/polygon");
}

/* A case with a mesh, saved and restored where its surface is not at hand (the state holds its
 * particles, counts and reach): it goes on with the bits of the run that was not stopped. */
static void restore_without_surface(void **state)
{
    (void)state;
    sph_error err;
    sph_case *c =
        parse(case3d("[{\"box\": {\"min\": [-0.3, -0.3, -0.3], \"max\": [0.3, 0.3, "
                     "0.0]}, \"role\": \"fluid\"}, {\"mesh\": \"torus.stl\", \"role\": "
                     "\"obstacle\", \"layers\": 2, \"transform\": {\"rotate\": [90, 0, 0]}}]",
                     ", \"boundary\": {\"type\": \"dynamic\", \"tank\": {\"min\": [-0.4, "
                     "-0.4, -0.4], \"max\": [0.4, 0.4, 0.4]}}"),
              &err);
    if (!c)
        fail_msg("%s: %s", err.path, err.message);
    c->sim.dx = 0.04;
    sph_mesh *m = calloc(1, sizeof *m);
    *m = torus(0.2, 0.08, 64, 16);
    c->meshes[1] = m;
    c->sim.geometry[1].mesh = m;
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
    free(buf);
    assert_int_equal(sph_sim_step(a, 10, &err), 0);
    assert_int_equal(sph_sim_step(b, 10, &err), 0);
    sph_particle_view va, vb;
    sph_sim_particles(a, &va);
    sph_sim_particles(b, &vb);
    assert_int_equal(va.n, vb.n);
    printf("  %ld particles: the restored run's bits after 10 more steps\n", va.n);
    for (long i = 0; i < va.n; i++)
        for (int d = 0; d < 3; d++)
            assert_true(va.pos[d][i] == vb.pos[d][i]);
    sph_sim_destroy(a);
    sph_sim_destroy(b);
}

/* A mesh file read through the case (sph_case_load_files): a box as ASCII STL with one
 * degenerate facet more, which is dropped and counted in the job's note; the box fills as the
 * built-in box would on the same lattice. */
static void mesh_file_through_case(void **state)
{
    (void)state;
    char dir[] = "/tmp/test_scene.XXXXXX";
    assert_non_null(mkdtemp(dir));
    char file[64];
    snprintf(file, sizeof file, "%s/box.stl", dir);
    FILE *f = fopen(file, "w");
    assert_non_null(f);
    const double lo[3] = {-0.2, -0.1, -0.3}, hi[3] = {0.2, 0.1, 0.3};
    static const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                    {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    fprintf(f, "solid box\n");
    for (int q = 0; q < 6; q++)
        for (int h = 0; h < 2; h++) {
            const int tri[3] = {quads[q][0], quads[q][h + 1], quads[q][h + 2]};
            fprintf(f, " facet normal 0 0 0\n  outer loop\n");
            for (int v = 0; v < 3; v++)
                fprintf(f, "   vertex %g %g %g\n", tri[v] & 1 ? hi[0] : lo[0],
                        tri[v] & 2 ? hi[1] : lo[1], tri[v] & 4 ? hi[2] : lo[2]);
            fprintf(f, "  endloop\n endfacet\n");
        }
    fprintf(f, " facet normal 0 0 0\n  outer loop\n   vertex 0 0 0\n   vertex 0 0 0\n"
               "   vertex 0.1 0 0\n  endloop\n endfacet\nendsolid box\n");
    fclose(f);
    sph_error err;
    sph_case *c = parse(case3d("[{\"mesh\": \"box.stl\", \"role\": \"fluid\"}]", NULL), &err);
    assert_non_null(c);
    if (sph_case_load_files(c, dir, NULL, &err))
        fail_msg("%s: %s", err.path, err.message);
    char note[256];
    int warn = 0;
    assert_int_equal(sph_case_mesh_note(c, 0, note, sizeof note, &warn), 0);
    printf("  %s\n", note);
    assert_int_equal(warn, 1);
    assert_non_null(strstr(note, "12 triangles"));
    assert_non_null(strstr(note, "1 degenerate"));
    sph_case *b = parse(case3d("[{\"box\": {\"min\": [-0.2, -0.1, -0.3], \"max\": [0.2, 0.1, "
                               "0.3]}, \"role\": \"fluid\"}]",
                               NULL),
                        &err);
    assert_non_null(b);
    assert_int_equal(fluid_count(&c->sim), 40 * 20 * 60);
    assert_int_equal(fluid_count(&b->sim), 40 * 20 * 60);
    drop(c);
    drop(b);
    /* the file gone: refused at its path */
    remove(file);
    c = parse(case3d("[{\"mesh\": \"box.stl\", \"role\": \"fluid\"}]", NULL), &err);
    assert_non_null(c);
    assert_int_not_equal(sph_case_load_files(c, dir, NULL, &err), 0);
    assert_string_equal(err.path, "/geometry/0/mesh");
    assert_non_null(strstr(err.message, "box.stl"));
    drop(c);
    rmdir(dir);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(sphere_volume),
        cmocka_unit_test(torus_mesh_volume),
        cmocka_unit_test(polygon_against_circle),
        cmocka_unit_test(body_polygon_against_circle),
        cmocka_unit_test(body_polygon_concave),
        cmocka_unit_test(wall_shells),
        cmocka_unit_test(bad_items),
        cmocka_unit_test(restore_without_surface),
        cmocka_unit_test(mesh_file_through_case),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
