/* Meshes (core/scene/sph_mesh.h) and mesh files (protocol/sph_mesh_io.h): a unit cube as triangle
 * soup (welded, volume 1, closed; turned over: -1), the same cube written as binary STL, ASCII STL,
 * OBJ and PLY and read back, the ways a surface is not closed (a face missing, two cubes on one
 * edge, a face turned over, two cubes through each other), degenerate triangles, the files refused
 * (too large, unknown format, garbage, binary PLY, missing, empty), that assimp prints nothing, and
 * polygons (square, bow-tie, too few points, repeated points, a large circle with and without a
 * crossing).
 */
#include "sph_mesh.h"
#include "sph_mesh_io.h"

#include <fcntl.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include <cmocka.h>

/* The unit cube's corners: bit 0 x, bit 1 y, bit 2 z; its 12 triangles, outward. */
static const int cube_tris[12][3] = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6},
                                     {0, 1, 5}, {0, 5, 4}, {2, 6, 7}, {2, 7, 3},
                                     {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};

static void corner(int i, double ox, double oy, double oz, double *p)
{
    p[0] = ox + (i & 1), p[1] = oy + ((i >> 1) & 1), p[2] = oz + ((i >> 2) & 1);
}

/* Appends the cube at (ox, oy, oz) as soup to xyz (108 doubles), triangles `skip` left out
 * (bit k: triangle k). Returns the number of triangles written. */
static long cube_soup(double *xyz, double ox, double oy, double oz, unsigned skip)
{
    long n = 0;
    for (int t = 0; t < 12; t++) {
        if (skip & (1u << t))
            continue;
        for (int c = 0; c < 3; c++)
            corner(cube_tris[t][c], ox, oy, oz, xyz + 9 * n + 3 * c);
        n++;
    }
    return n;
}

static void unit_cube(sph_mesh *m)
{
    double xyz[108];
    sph_mesh_limits lim = sph_mesh_limits_default();
    sph_error err;
    assert_int_equal(
        sph_mesh_from_triangles(m, xyz, cube_soup(xyz, 0, 0, 0, 0), &lim, "/g/0", &err), 0);
}

static void test_cube(void **state)
{
    (void)state;
    sph_mesh m;
    sph_error err;
    unit_cube(&m);
    assert_int_equal(m.dim, 3);
    assert_int_equal(m.nv, 8); /* 36 corners welded */
    assert_int_equal(m.nt, 12);
    assert_int_equal(m.degenerate, 0);
    assert_true(fabs(sph_mesh_volume(&m) - 1.0) < 1e-12);
    assert_int_equal(sph_mesh_check_closed(&m, "/g/0", &err), 0);
    sph_mesh_flip(&m);
    assert_true(fabs(sph_mesh_volume(&m) + 1.0) < 1e-12);
    assert_int_equal(sph_mesh_check_closed(&m, "/g/0", &err), 0); /* inward, still closed */
    sph_mesh_free(&m);
    assert_null(m.v);
    sph_mesh_free(NULL);
}

/* one face (two triangles) missing: its four edges are open */
static void test_open(void **state)
{
    (void)state;
    double xyz[108];
    sph_mesh m;
    sph_error err;
    long nt = cube_soup(xyz, 0, 0, 0, 3u << 2); /* the z = 1 face */
    assert_int_equal(sph_mesh_from_triangles(&m, xyz, nt, NULL, "/geometry/2", &err), 0);
    assert_int_equal(sph_mesh_check_closed(&m, "/geometry/2", &err), SPH_ERR_INVALID);
    assert_string_equal(err.path, "/geometry/2");
    assert_non_null(strstr(err.message, "not closed: 4 open edges, one from ("));
    assert_non_null(strstr(err.message, ", 1) to (")); /* an edge of the z = 1 face */
    sph_mesh_free(&m);
}

/* two cubes on one edge: that edge is in four triangles */
static void test_nonmanifold(void **state)
{
    (void)state;
    double xyz[216];
    sph_mesh m;
    sph_error err;
    long nt = cube_soup(xyz, 0, 0, 0, 0);
    nt += cube_soup(xyz + 9 * nt, 1, 1, 0, 0);
    assert_int_equal(sph_mesh_from_triangles(&m, xyz, nt, NULL, "/g", &err), 0);
    assert_int_equal(m.nv, 14);
    assert_int_equal(sph_mesh_check_closed(&m, "/g", &err), SPH_ERR_INVALID);
    assert_non_null(strstr(err.message, "not manifold: 1 edge in more than two triangles"));
    assert_non_null(strstr(err.message, "(1, 1, 0) to (1, 1, 1) in 4"));
    sph_mesh_free(&m);
}

/* one triangle turned over: its three edges each used twice the same way */
static void test_orientation(void **state)
{
    (void)state;
    sph_mesh m;
    sph_error err;
    unit_cube(&m);
    int x = m.t[1];
    m.t[1] = m.t[2], m.t[2] = x;
    assert_int_equal(sph_mesh_check_closed(&m, "/g", &err), SPH_ERR_INVALID);
    assert_non_null(strstr(err.message, "not consistently oriented: 3 edges"));
    sph_mesh_free(&m);
}

/* two cubes through each other in one mesh; apart, they pass */
static void test_self_intersection(void **state)
{
    (void)state;
    double xyz[216];
    sph_mesh m;
    sph_error err;
    long nt = cube_soup(xyz, 0, 0, 0, 0);
    nt += cube_soup(xyz + 9 * nt, 0.5, 0.25, 0.125, 0);
    assert_int_equal(sph_mesh_from_triangles(&m, xyz, nt, NULL, "/g", &err), 0);
    assert_int_equal(sph_mesh_check_closed(&m, "/g", &err), SPH_ERR_INVALID);
    assert_non_null(strstr(err.message, "intersects itself"));
    sph_mesh_free(&m);
    nt = cube_soup(xyz, 0, 0, 0, 0);
    nt += cube_soup(xyz + 9 * nt, 1.5, 0.25, 0.125, 0);
    assert_int_equal(sph_mesh_from_triangles(&m, xyz, nt, NULL, "/g", &err), 0);
    assert_int_equal(sph_mesh_check_closed(&m, "/g", &err), 0);
    assert_true(fabs(sph_mesh_volume(&m) - 2.0) < 1e-12);
    sph_mesh_free(&m);
    /* a cube inside a larger one, turned inward (a hollow shell): closed, nothing crosses */
    nt = cube_soup(xyz, 0, 0, 0, 0);
    for (int i = 0; i < 108; i++)
        xyz[i] = 4 * xyz[i] - 1.5; /* [-1.5, 2.5] */
    long n2 = cube_soup(xyz + 9 * nt, 0, 0, 0, 0);
    for (long i = nt; i < nt + n2; i++) { /* inward: swap two corners */
        double tmp[3];
        memcpy(tmp, xyz + 9 * i + 3, sizeof tmp);
        memcpy(xyz + 9 * i + 3, xyz + 9 * i + 6, sizeof tmp);
        memcpy(xyz + 9 * i + 6, tmp, sizeof tmp);
    }
    assert_int_equal(sph_mesh_from_triangles(&m, xyz, nt + n2, NULL, "/g", &err), 0);
    assert_int_equal(sph_mesh_check_closed(&m, "/g", &err), 0);
    assert_true(fabs(sph_mesh_volume(&m) - 63.0) < 1e-12);
    sph_mesh_free(&m);
}

/* a repeated corner and a flat (collinear) triangle dropped and counted; their lone vertex too */
static void test_degenerate(void **state)
{
    (void)state;
    double xyz[108 + 18];
    sph_mesh m;
    sph_error err;
    long nt = cube_soup(xyz, 0, 0, 0, 0);
    double extra[18] = {0, 0, 0, 1,   0, 0, 0, 0, 0,  /* corner 0 twice */
                        0, 0, 0, 0.5, 0, 0, 1, 0, 0}; /* on the edge from corner 0 to 1 */
    memcpy(xyz + 9 * nt, extra, sizeof extra);
    assert_int_equal(sph_mesh_from_triangles(&m, xyz, nt + 2, NULL, "/g", &err), 0);
    assert_int_equal(m.degenerate, 2);
    assert_int_equal(m.nt, 12);
    assert_int_equal(m.nv, 8);
    assert_int_equal(sph_mesh_check_closed(&m, "/g", &err), 0);
    sph_mesh_free(&m);
    /* nothing left, non-finite, too many */
    assert_int_equal(sph_mesh_from_triangles(&m, extra, 2, NULL, "/g", &err), SPH_ERR_INVALID);
    assert_non_null(strstr(err.message, "no triangle left"));
    xyz[4] = NAN;
    assert_int_equal(sph_mesh_from_triangles(&m, xyz, nt, NULL, "/g", &err), SPH_ERR_INVALID);
    assert_non_null(strstr(err.message, "triangle 0 has a non-finite"));
    sph_mesh_limits lim = {11, 1000};
    cube_soup(xyz, 0, 0, 0, 0);
    assert_int_equal(sph_mesh_from_triangles(&m, xyz, nt, &lim, "/g", &err), SPH_ERR_INVALID);
    assert_non_null(strstr(err.message, "12 triangles, more than the limit of 11"));
    assert_null(m.v);
}

/* ---- files ---- */

static char dir[64];

static const char *in_dir(const char *name)
{
    static char p[128];
    snprintf(p, sizeof p, "%s/%s", dir, name);
    return p;
}

static void write_bytes(const char *name, const void *b, size_t n)
{
    FILE *f = fopen(in_dir(name), "wb");
    assert_non_null(f);
    assert_int_equal(fwrite(b, 1, n, f), n);
    assert_int_equal(fclose(f), 0);
}

static void write_stl_binary(const char *name)
{
    unsigned char buf[84 + 12 * 50];
    memset(buf, 0, sizeof buf);
    memcpy(buf, "binary cube", 11);
    uint32_t n = 12;
    memcpy(buf + 80, &n, 4);
    for (int t = 0; t < 12; t++)
        for (int c = 0; c < 3; c++) {
            double p[3];
            corner(cube_tris[t][c], 0, 0, 0, p);
            for (int k = 0; k < 3; k++) {
                float x = (float)p[k];
                memcpy(buf + 84 + 50 * t + 12 + 12 * c + 4 * k, &x, 4);
            }
        }
    write_bytes(name, buf, sizeof buf);
}

static void write_text(const char *name, const char *text)
{
    write_bytes(name, text, strlen(text));
}

static void write_stl_ascii(const char *name)
{
    char buf[4096];
    size_t n = (size_t)snprintf(buf, sizeof buf, "solid cube\n");
    for (int t = 0; t < 12; t++) {
        n += (size_t)snprintf(buf + n, sizeof buf - n, " facet normal 0 0 0\n  outer loop\n");
        for (int c = 0; c < 3; c++) {
            double p[3];
            corner(cube_tris[t][c], 0, 0, 0, p);
            n +=
                (size_t)snprintf(buf + n, sizeof buf - n, "   vertex %g %g %g\n", p[0], p[1], p[2]);
        }
        n += (size_t)snprintf(buf + n, sizeof buf - n, "  endloop\n endfacet\n");
    }
    snprintf(buf + n, sizeof buf - n, "endsolid cube\n");
    write_text(name, buf);
}

/* OBJ and PLY with quads (the cube's faces), which the reader triangulates */
static const int cube_quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                     {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};

static void write_obj(const char *name)
{
    char buf[1024];
    size_t n = (size_t)snprintf(buf, sizeof buf, "# cube\no cube\n");
    for (int i = 0; i < 8; i++) {
        double p[3];
        corner(i, 0, 0, 0, p);
        n += (size_t)snprintf(buf + n, sizeof buf - n, "v %g %g %g\n", p[0], p[1], p[2]);
    }
    for (int f = 0; f < 6; f++)
        n += (size_t)snprintf(buf + n, sizeof buf - n, "f %d %d %d %d\n", cube_quads[f][0] + 1,
                              cube_quads[f][1] + 1, cube_quads[f][2] + 1, cube_quads[f][3] + 1);
    write_text(name, buf);
}

static void write_ply(const char *name)
{
    char buf[1024];
    size_t n = (size_t)snprintf(buf, sizeof buf,
                                "ply\nformat ascii 1.0\nelement vertex 8\nproperty float x\n"
                                "property float y\nproperty float z\nelement face 6\n"
                                "property list uchar int vertex_indices\nend_header\n");
    for (int i = 0; i < 8; i++) {
        double p[3];
        corner(i, 0, 0, 0, p);
        n += (size_t)snprintf(buf + n, sizeof buf - n, "%g %g %g\n", p[0], p[1], p[2]);
    }
    for (int f = 0; f < 6; f++)
        n += (size_t)snprintf(buf + n, sizeof buf - n, "4 %d %d %d %d\n", cube_quads[f][0],
                              cube_quads[f][1], cube_quads[f][2], cube_quads[f][3]);
    write_text(name, buf);
}

static void read_back(const char *name)
{
    sph_mesh m;
    sph_error err;
    sph_mesh_limits lim = sph_mesh_limits_default();
    int rc = sph_mesh_read_file(in_dir(name), name, &lim, &m, "/geometry/0/mesh", &err);
    if (rc != 0)
        fail_msg("%s: %s", name, err.message);
    assert_int_equal(m.nt, 12);
    assert_int_equal(m.nv, 8);
    assert_int_equal(sph_mesh_check_closed(&m, "/geometry/0", &err), 0);
    assert_true(fabs(sph_mesh_volume(&m) - 1.0) < 1e-12);
    sph_mesh_free(&m);
}

static void test_files(void **state)
{
    (void)state;
    write_stl_binary("bin.stl");
    write_stl_ascii("ascii.stl");
    write_obj("cube.obj");
    write_ply("cube.ply");
    write_stl_binary("upper.STL");
    read_back("bin.stl");
    read_back("ascii.stl");
    read_back("cube.obj");
    read_back("cube.ply");
    read_back("upper.STL");
}

static void test_files_refused(void **state)
{
    (void)state;
    sph_mesh m;
    sph_error err;
    sph_mesh_limits lim = sph_mesh_limits_default();
    write_stl_binary("big.stl");
    lim.max_bytes = 683; /* the file has 684 */
    assert_int_equal(sph_mesh_read_file(in_dir("big.stl"), "big.stl", &lim, &m, "/g", &err),
                     SPH_ERR_INVALID);
    assert_non_null(strstr(err.message, "684 bytes, more than the limit of 683"));
    lim.max_bytes = 684;
    assert_int_equal(sph_mesh_read_file(in_dir("big.stl"), "big.stl", &lim, &m, "/g", &err), 0);
    sph_mesh_free(&m);
    lim.max_bytes = 10;
    assert_int_equal(
        sph_mesh_read_memory("solid x\nendsolid x\n", 19, "a.stl", &lim, &m, "/g", &err),
        SPH_ERR_INVALID);
    assert_non_null(strstr(err.message, "more than the limit of 10"));
    lim = sph_mesh_limits_default();

    write_text("cube.xyz", "0 0 0\n");
    assert_int_equal(sph_mesh_read_file(in_dir("cube.xyz"), "cube.xyz", &lim, &m, "/g", &err),
                     SPH_ERR_INVALID);
    assert_non_null(strstr(err.message, "unknown mesh format '.xyz'"));
    assert_non_null(strstr(err.message, "use .stl, .obj or .ply"));

    unsigned char junk[777];
    uint32_t s = 12345;
    for (size_t i = 0; i < sizeof junk; i++)
        junk[i] = (unsigned char)((s = s * 1103515245u + 12345u) >> 24);
    write_bytes("junk.stl", junk, sizeof junk);
    assert_int_equal(sph_mesh_read_file(in_dir("junk.stl"), "junk.stl", &lim, &m, "/g", &err),
                     SPH_ERR_INVALID);
    /* random bytes: neither a binary STL (its size) nor text */
    assert_non_null(strstr(err.message, "junk.stl is not a binary STL"));
    assert_null(m.v);
    /* text that is not STL: assimp's own message */
    write_text("words.stl", "solid x\n this is not a facet\nendsolid\n");
    assert_int_equal(sph_mesh_read_file(in_dir("words.stl"), "words.stl", &lim, &m, "/g", &err),
                     SPH_ERR_INVALID);
    assert_non_null(strstr(err.message, "words.stl"));
    assert_null(m.v);
    /* a PLY header with a NUL in it (assimp 5.2 loops without end on it: fuzz_mesh) and one
     * that declares more elements than the file holds */
    write_bytes("nul.ply", "ply\nformat ascii 1.0\nelem\0ent vertex 3\nend_header\n", 45);
    assert_int_equal(sph_mesh_read_file(in_dir("nul.ply"), "nul.ply", &lim, &m, "/g", &err),
                     SPH_ERR_INVALID);
    assert_non_null(strstr(err.message, "control character"));
    write_text("many.ply", "ply\nformat ascii 1.0\nelement vertex 4000000000\nend_header\n");
    assert_int_equal(sph_mesh_read_file(in_dir("many.ply"), "many.ply", &lim, &m, "/g", &err),
                     SPH_ERR_INVALID);
    assert_non_null(strstr(err.message, "more than the file"));

    write_text("b.ply", "ply\nformat binary_little_endian 1.0\nelement vertex 4\nend_header\n");
    assert_int_equal(sph_mesh_read_file(in_dir("b.ply"), "b.ply", &lim, &m, "/g", &err),
                     SPH_ERR_INVALID);
    assert_non_null(strstr(err.message, "b.ply is a binary PLY, which is not read"));

    write_text("empty.obj", "");
    assert_int_equal(sph_mesh_read_file(in_dir("empty.obj"), "empty.obj", &lim, &m, "/g", &err),
                     SPH_ERR_INVALID);
    assert_non_null(strstr(err.message, "empty.obj is empty"));
    write_text("lines.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nl 1 2\nl 2 3\n");
    assert_int_equal(sph_mesh_read_file(in_dir("lines.obj"), "lines.obj", &lim, &m, "/g", &err),
                     SPH_ERR_INVALID);
    assert_string_equal(err.path, "/g");

    assert_int_equal(sph_mesh_read_file(in_dir("missing.stl"), NULL, &lim, &m, "/g", &err),
                     SPH_ERR_IO);
    assert_non_null(strstr(err.message, "cannot open "));
    assert_non_null(strstr(err.message, "missing.stl: No such file or directory"));
}

/* assimp writes nothing to stdout or stderr, reading good files or bad */
static void test_quiet(void **state)
{
    (void)state;
    fflush(stdout), fflush(stderr);
    int o = dup(1), e = dup(2);
    int fd = open(in_dir("out.txt"), O_WRONLY | O_CREAT | O_TRUNC, 0600);
    assert_true(o >= 0 && e >= 0 && fd >= 0);
    dup2(fd, 1), dup2(fd, 2);
    sph_mesh m;
    sph_error err;
    write_stl_ascii("q.stl");
    write_text("q.ply", "ply\nformat ascii 1.0\nelement vertex 3\nend_header\n1 2\n");
    write_text("q.obj", "v 0 0\nf 1 2 3 4\nusemtl nothing\nmtllib none.mtl\n");
    int r0 = sph_mesh_read_file(in_dir("q.stl"), "q.stl", NULL, &m, "", &err);
    sph_mesh_free(&m);
    int r1 = sph_mesh_read_file(in_dir("q.ply"), "q.ply", NULL, &m, "", &err);
    int r2 = sph_mesh_read_file(in_dir("q.obj"), "q.obj", NULL, &m, "", &err);
    fflush(stdout), fflush(stderr);
    dup2(o, 1), dup2(e, 2);
    close(o), close(e);
    off_t size = lseek(fd, 0, SEEK_END);
    close(fd);
    assert_int_equal(r0, 0);
    assert_int_not_equal(r1, 0);
    assert_int_not_equal(r2, 0);
    assert_int_equal(size, 0);
}

/* ---- polygons ---- */

static void test_polygon_square(void **state)
{
    (void)state;
    double sq[] = {0, 0, 2, 0, 2, 2, 0, 2, 0, 0}; /* closing point repeated */
    sph_mesh m;
    sph_error err;
    assert_int_equal(sph_mesh_polygon(&m, sq, 5, "/geometry/1/polygon", &err), 0);
    assert_int_equal(m.dim, 2);
    assert_int_equal(m.nt, 4);
    assert_int_equal(m.nv, 4);
    assert_true(fabs(sph_mesh_volume(&m) - 4.0) < 1e-12);
    assert_int_equal(sph_mesh_check_closed(&m, "/geometry/1", &err), 0);
    sph_mesh_flip(&m);
    assert_true(fabs(sph_mesh_volume(&m) + 4.0) < 1e-12);
    sph_mesh_free(&m);
}

static void test_polygon_bad(void **state)
{
    (void)state;
    sph_mesh m;
    sph_error err;
    double bow[] = {0, 0, 1, 1, 1, 0, 0, 1};
    assert_int_equal(sph_mesh_polygon(&m, bow, 4, "/geometry/1/polygon", &err), SPH_ERR_INVALID);
    assert_string_equal(err.path, "/geometry/1/polygon");
    assert_non_null(strstr(err.message, "sides 0 (points 0-1) and 2 (points 2-3) cross or touch "
                                        "at (0.5, 0.5)"));
    assert_null(m.v);
    double two[] = {0, 0, 1, 1};
    assert_int_equal(sph_mesh_polygon(&m, two, 2, "/p", &err), SPH_ERR_INVALID);
    assert_non_null(strstr(err.message, "2 distinct points: a closed polygon needs at least 3"));
    double rep[] = {0, 0, 1, 0, 1, 0, 1, 1};
    assert_int_equal(sph_mesh_polygon(&m, rep, 4, "/p", &err), SPH_ERR_INVALID);
    assert_non_null(strstr(err.message, "points 1 and 2 are the same point (1, 0)"));
    double touch[] = {0, 0, 4, 0, 4, 4, 2, 0.0, 0, 4}; /* point 3 on side 0 */
    assert_int_equal(sph_mesh_polygon(&m, touch, 5, "/p", &err), SPH_ERR_INVALID);
    assert_non_null(strstr(err.message, "sides 0 (points 0-1) and 2 (points 2-3)"));
    assert_non_null(strstr(err.message, "at (2, 0)"));
    double fold[] = {0, 0, 2, 0, 1, 0};
    assert_int_equal(sph_mesh_polygon(&m, fold, 3, "/p", &err), SPH_ERR_INVALID);
    assert_non_null(strstr(err.message, "fold back"));
    double inf[] = {0, 0, 1, INFINITY, 1, 1};
    assert_int_equal(sph_mesh_polygon(&m, inf, 3, "/p", &err), SPH_ERR_INVALID);
    assert_non_null(strstr(err.message, "point 1 has a non-finite"));
}

/* a circle of 100000 points: passes (area within 1e-6); one point pulled across it, its two
 * sides crossing the far side of the circle (side 48979 first): found */
static void test_polygon_large(void **state)
{
    (void)state;
    long n = SPH_POLYGON_MAX_POINTS;
    double *xy = malloc((size_t)(2 * n) * sizeof *xy);
    assert_non_null(xy);
    const double pi = 3.14159265358979323846;
    for (long i = 0; i < n; i++)
        xy[2 * i] = cos(2 * pi * (double)i / (double)n), xy[2 * i + 1] = sin(2 * pi * i / n);
    sph_mesh m;
    sph_error err;
    assert_int_equal(sph_mesh_polygon(&m, xy, n, "/p", &err), 0);
    assert_true(fabs(sph_mesh_volume(&m) - pi) < 1e-6);
    sph_mesh_free(&m);
    xy[2 * 5000] = -1.5, xy[2 * 5000 + 1] = 0.001; /* point 5000 across and out of the circle */
    assert_int_equal(sph_mesh_polygon(&m, xy, n, "/p", &err), SPH_ERR_INVALID);
    assert_non_null(
        strstr(err.message, "sides 4999 (points 4999-5000) and 48979 (points 48979-48980) cross"));
    free(xy);
}

static int setup(void **state)
{
    (void)state;
    snprintf(dir, sizeof dir, "/tmp/test_mesh.XXXXXX");
    return mkdtemp(dir) ? 0 : -1;
}

static int teardown(void **state)
{
    (void)state;
    char cmd[128];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    return system(cmd) == 0 ? 0 : -1;
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_cube),
        cmocka_unit_test(test_open),
        cmocka_unit_test(test_nonmanifold),
        cmocka_unit_test(test_orientation),
        cmocka_unit_test(test_self_intersection),
        cmocka_unit_test(test_degenerate),
        cmocka_unit_test(test_files),
        cmocka_unit_test(test_files_refused),
        cmocka_unit_test(test_quiet),
        cmocka_unit_test(test_polygon_square),
        cmocka_unit_test(test_polygon_bad),
        cmocka_unit_test(test_polygon_large),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
