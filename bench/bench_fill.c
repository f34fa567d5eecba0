/*
 * bench_fill: filling a mesh (core/scene/sph_scene.c). A closed surface of about 200k triangles
 * (a torus, or a sphere: --shape), filled with about 1M fluid particles (the target: at
 * most 5 s on this machine's 2 cores), then the same surface as an obstacle's 3-layer shell (the
 * closest-point queries). Prints, per row: triangles, particles, the seconds of the scene (Embree's
 * hierarchy), of the count and of the fill with positions, and the hierarchy's bytes. Never fails
 * on time.
 *
 * Usage: bench_fill [--triangles N] [--particles N] [--shape torus|sphere] [--repeat R]
 */
#include "sph_config.h"
#include "sph_mesh.h"
#include "sph_scene.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define PI 3.14159265358979323846

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* A torus (R, r: sph_mesh_torus) or a sphere (radius R) of nu x nv quads, two triangles each (the
 * sphere's poles as fans), outward. */
static sph_mesh surface(int sphere, double R, double r, int nu, int nv)
{
    sph_mesh m = {.dim = 3};
    if (!sphere) {
        if (sph_mesh_torus(&m, R, r, nu, nv))
            exit(1);
        return m;
    }
    m.nv = (long)nu * (nv - 1) + 2;
    m.nt = 2L * nu * (nv - 1);
    m.v = malloc(3 * (size_t)m.nv * sizeof *m.v);
    m.t = malloc(3 * (size_t)m.nt * sizeof *m.t);
    if (!m.v || !m.t)
        exit(1);
    long f = 0;
#define TRI(a, b, c)                                                                               \
    do {                                                                                           \
        m.t[3 * f] = (a), m.t[3 * f + 1] = (b), m.t[3 * f + 2] = (c);                              \
        f++;                                                                                       \
    } while (0)
    { /* rings 1 .. nv-1 of latitude, then the poles */
        for (int j = 1; j < nv; j++)
            for (int i = 0; i < nu; i++) {
                const double th = PI * j / nv, ph = 2 * PI * i / nu;
                double *p = m.v + 3 * (size_t)((j - 1) * nu + i);
                p[0] = R * sin(th) * cos(ph);
                p[1] = R * sin(th) * sin(ph);
                p[2] = R * cos(th);
            }
        const int top = nu * (nv - 1), bottom = top + 1;
        m.v[3 * top] = m.v[3 * top + 1] = 0.0;
        m.v[3 * top + 2] = R;
        m.v[3 * bottom] = m.v[3 * bottom + 1] = 0.0;
        m.v[3 * bottom + 2] = -R;
        for (int i = 0; i < nu; i++) {
            const int i1 = (i + 1) % nu;
            TRI(top, i, i1);
            for (int j = 1; j < nv - 1; j++) {
                const int a = (j - 1) * nu + i, b = (j - 1) * nu + i1;
                const int c = j * nu + i1, d = j * nu + i;
                TRI(a, d, c);
                TRI(a, c, b);
            }
            TRI(bottom, (nv - 2) * nu + i1, (nv - 2) * nu + i);
        }
    }
#undef TRI
    m.nt = f;
    if (sph_mesh_volume(&m) < 0.0)
        sph_mesh_flip(&m);
    return m;
}

int main(int argc, char **argv)
{
    long triangles = 200000, particles = 1000000;
    int sphere = 0, repeat = 3;
    for (int i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--triangles") == 0 && i + 1 < argc)
            triangles = atol(argv[++i]);
        else if (strcmp(argv[i], "--particles") == 0 && i + 1 < argc)
            particles = atol(argv[++i]);
        else if (strcmp(argv[i], "--shape") == 0 && i + 1 < argc)
            sphere = strcmp(argv[++i], "sphere") == 0;
        else if (strcmp(argv[i], "--repeat") == 0 && i + 1 < argc)
            repeat = atoi(argv[++i]);
        else {
            fprintf(stderr, "usage: bench_fill [--triangles N] [--particles N] "
                            "[--shape torus|sphere] [--repeat R]\n");
            return 64;
        }
    }
    /* nu x nv quads, nu = 4 nv (torus) or 2 nv (sphere) */
    const int nv = (int)sqrt((double)triangles / (sphere ? 4.0 : 8.0));
    const int nu = sphere ? 2 * nv : 4 * nv;
    const double R = 1.0, r = 0.35;
    sph_mesh m = surface(sphere, R, r, nu, nv);
    const double volume = sph_mesh_volume(&m);
    const double dx = cbrt(volume / (double)particles);
    sph_config c = sph_config_default();
    c.dim = 3;
    c.dx = dx;
    c.gravity[1] = 0.0;
    c.gravity[2] = -9.81;
    for (int d = 0; d < 3; d++) {
        c.domain.min[d] = -1.5;
        c.domain.max[d] = 1.5;
    }
    c.ngeometry = 1;
    sph_geometry_spec *g = &c.geometry[0];
    g->kind = SPH_GEOM_MESH;
    g->transform.scale = 1.0;
    g->layers = 3;
    g->mesh = &m;
    printf("bench_fill: a %s of %ld triangles, dx %.5g m (%.0f particles in its volume)\n",
           sphere ? "sphere" : "torus", m.nt, dx, volume / (dx * dx * dx));
    printf("%-9s %10s %10s %9s %9s %9s %9s %12s\n", "role", "triangles", "particles", "scene_s",
           "count_s", "fill_s", "total_s", "bvh_bytes");
    for (int role = 0; role < 2; role++)
        for (int rep = 0; rep < repeat; rep++) {
            g->role = role == 0 ? SPH_ROLE_FLUID : SPH_ROLE_OBSTACLE;
            sph_error err;
            const double t0 = now();
            sph_scene *s = sph_scene_create(&c, &err);
            if (!s) {
                fprintf(stderr, "bench_fill: %s: %s\n", err.path, err.message);
                return 1;
            }
            const double t1 = now();
            sph_scene_counts n;
            if (sph_scene_fill(s, &c, &n, NULL, NULL, NULL, &err)) {
                fprintf(stderr, "bench_fill: %s\n", err.message);
                return 1;
            }
            const double t2 = now();
            const long np = n.fluid + n.wall;
            double *x = malloc((size_t)np * sizeof *x), *y = malloc((size_t)np * sizeof *y),
                   *z = malloc((size_t)np * sizeof *z), *rho = malloc((size_t)np * sizeof *rho);
            double *const pos[3] = {x, y, z};
            if (!x || !y || !z || !rho || sph_scene_fill(s, &c, &n, pos, rho, NULL, &err))
                return 1;
            const double t3 = now();
            printf("%-9s %10ld %10ld %9.3f %9.3f %9.3f %9.3f %12.0f\n",
                   role == 0 ? "fluid" : "obstacle", m.nt, np, t1 - t0, t2 - t1, t3 - t2, t3 - t0,
                   sph_scene_bytes(s));
            fflush(stdout);
            free(x);
            free(y);
            free(z);
            free(rho);
            sph_scene_destroy(s);
        }
    sph_mesh_free(&m);
    return 0;
}
