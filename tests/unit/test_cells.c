/*
 * The cell-list pair loops (each pair once, applied to both particles, strips in parallel)
 * against the obvious all-pairs loop on a random cloud, for every SPH kernel and each option:
 * accelerations, density rates and SPS velocity gradients must agree to round-off.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "sph_shapes.h"
#include "sph_wcsph.h"

#include <math.h>
#include <stdio.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>

/* cmocka 1.1 has no assert_double_equal */
static void close_to(double got, double want, double tol, const char *what)
{
    if (!(fabs(got - want) <= tol))
        fail_msg("%s: %.17g, expected %.17g within %g", what, got, want, tol);
}
#define assert_double_equal(a, b, tol) close_to((a), (b), (tol), #a)

#define NCLOUD 400

static double urand(unsigned *s)
{
    *s = *s * 1103515245u + 12345u;
    return ((*s >> 8) & 0xffffff) / (double)0x1000000;
}

/* A sim whose particles are replaced by a random cloud of fluid and boundary particles. */
/* boundary.viscosity_factor of the clouds (test_wall_viscosity changes it) */
static double cloud_wall_visc = 1.0;

static sph_sim *cloud(sph_kernel_type type, sph_visc_type visc, sph_turb_type turb, double delta)
{
    sph_config c = sph_config_default();
    c.kernel = sph_kernel_spec_default(type);
    if (type == SPH_KERNEL_DOUBLE_COSINE)
        c.kernel.kappa = 2.5;
    c.dx = 0.01;
    c.h_over_dx = 1.3;
    c.domain = (sph_box){{0, 0, 0}, {0.2, 0.2, 0}};
    c.nfluid = 1;
    c.fluid[0] = (sph_box){{0, 0, 0}, {0.2, 0.2, 0}}; /* 400 particles */
    c.boundary = SPH_BOUNDARY_NONE;
    c.visc = visc;
    c.alpha = 0.1;
    c.nu = 1e-3;
    c.turb = turb;
    c.delta_sph = delta;
    c.wall_viscosity = cloud_wall_visc;
    c.t_end = 1.0;
    sph_error err;
    sph_sim *s = sph_sim_create(&c, &err);
    assert_non_null(s);
    assert_int_equal(s->P.n, NCLOUD);
    unsigned seed = 12345u + (unsigned)type;
    sph_particles *P = &s->P;
    for (long i = 0; i < P->n; i++) {
        P->x[i] = 0.2 * urand(&seed);
        P->y[i] = 0.2 * urand(&seed);
        P->vx[i] = urand(&seed) - 0.5;
        P->vy[i] = urand(&seed) - 0.5;
        P->rho[i] = 990.0 + 20.0 * urand(&seed);
        P->type[i] = urand(&seed) < 0.3 ? SPH_BOUNDARY : SPH_FLUID;
        if (P->gxx) { /* velocity gradients of a "previous" evaluation, for the SPS stresses */
            P->gxx[i] = urand(&seed) - 0.5;
            P->gxy[i] = urand(&seed) - 0.5;
            P->gyy[i] = urand(&seed) - 0.5;
        }
    }
    return s;
}

typedef struct ref {
    double ax[NCLOUD], ay[NCLOUD], drho[NCLOUD], gxx[NCLOUD], gxy[NCLOUD], gyy[NCLOUD];
    double txx[NCLOUD], txy[NCLOUD], tyy[NCLOUD];
} ref;

/* The obvious loop, over every ordered pair (a, b), in creation order. The SPS stresses are
 * taken from the sim (computed from the "previous" gradients, which the test does not check). */
static void all_pairs(const sph_sim *s, ref *R)
{
    const sph_particles *P = &s->P;
    const sph_config *c = &s->cfg;
    const long n = P->n;
    memset(R->ax, 0, sizeof R->ax);
    memset(R->ay, 0, sizeof R->ay);
    memset(R->drho, 0, sizeof R->drho);
    memset(R->gxx, 0, sizeof R->gxx);
    memset(R->gxy, 0, sizeof R->gxy);
    memset(R->gyy, 0, sizeof R->gyy);
    const double m = s->mass, h = s->h, eta2 = 0.01 * h * h;
    for (long a = 0; a < n; a++) {
        const double pa = c->c0 * c->c0 * (P->rho[a] - c->rho0);
        for (long b = 0; b < n; b++) {
            if (a == b || (P->type[a] == SPH_BOUNDARY && P->type[b] == SPH_BOUNDARY))
                continue;
            const double rv[2] = {P->x[a] - P->x[b], P->y[a] - P->y[b]};
            const double r2 = rv[0] * rv[0] + rv[1] * rv[1];
            if (r2 >= s->kernel.support * s->kernel.support)
                continue;
            double g[2];
            sph_kernel_grad(&s->kernel, rv, g);
            const double pb = c->c0 * c->c0 * (P->rho[b] - c->rho0);
            const double ra = P->rho[a], rb = P->rho[b];
            const double v[2] = {P->vx[a] - P->vx[b], P->vy[a] - P->vy[b]};
            const double vr = v[0] * rv[0] + v[1] * rv[1];
            R->drho[a] += m * (v[0] * g[0] + v[1] * g[1]);
            double pt = pa / (ra * ra) + pb / (rb * rb);
            const double vf = (P->type[a] == SPH_BOUNDARY || P->type[b] == SPH_BOUNDARY)
                                  ? c->wall_viscosity
                                  : 1.0;
            if (c->visc == SPH_VISC_MONAGHAN || (c->visc == SPH_VISC_ARTIFICIAL && vr < 0.0))
                pt += -vf *
                      (c->visc == SPH_VISC_MONAGHAN ? sph_config_monaghan_alpha(c) : c->alpha) *
                      c->c0 * (h * vr / (r2 + eta2)) / (0.5 * (ra + rb));
            for (int d = 0; d < 2; d++) {
                double acc = -m * pt * g[d];
                if (c->visc == SPH_VISC_LAMINAR)
                    acc += vf * 8.0 * c->rho0 * c->nu * m * (rv[0] * g[0] + rv[1] * g[1]) /
                           ((ra + rb) * (ra + rb) * (r2 + eta2)) * v[d];
                if (c->turb == SPH_TURB_SPS) {
                    const double t0 = P->txx[a] + P->txx[b], t1 = P->txy[a] + P->txy[b],
                                 t2 = P->tyy[a] + P->tyy[b];
                    acc += m * (d == 0 ? t0 * g[0] + t1 * g[1] : t1 * g[0] + t2 * g[1]);
                }
                if (d == 0)
                    R->ax[a] += acc;
                else
                    R->ay[a] += acc;
            }
            if (c->turb == SPH_TURB_SPS) {
                const double w = m / rb; /* sum_b V_b (v_b - v_a) (x) grad_a W */
                R->gxx[a] += w * -v[0] * g[0];
                R->gxy[a] += w * (-v[0] * g[1] - v[1] * g[0]);
                R->gyy[a] += w * -v[1] * g[1];
            }
            if (c->delta_sph > 0.0 && P->type[a] == SPH_FLUID && P->type[b] == SPH_FLUID)
                R->drho[a] += c->delta_sph * h * c->c0 * 2.0 * (rb - ra) *
                              -(rv[0] * g[0] + rv[1] * g[1]) / (r2 + eta2) * m / rb;
        }
        if (P->type[a] == SPH_FLUID) {
            R->ax[a] += c->gravity[0];
            R->ay[a] += c->gravity[1];
        } else {
            R->ax[a] = R->ay[a] = 0.0;
        }
    }
}

static double maxabs(const double *a, long n)
{
    double m = 0.0;
    for (long i = 0; i < n; i++)
        m = fmax(m, fabs(a[i]));
    return m;
}

/* |fast - ref| <= 1e-10 max|ref| for every particle, matched by id. */
static void compare(const char *what, const double *fast, const int *id, const double *want, long n)
{
    const double scale = maxabs(want, n) + 1e-300;
    for (long i = 0; i < n; i++) {
        const double d = fabs(fast[i] - want[id[i]]);
        if (d > 1e-10 * scale)
            fail_msg("%s: particle %d: cell list %.17g, all pairs %.17g (scale %g)", what, id[i],
                     fast[i], want[id[i]], scale);
    }
}

static void check(sph_kernel_type type, sph_visc_type visc, sph_turb_type turb, double delta)
{
    sph_sim *s = cloud(type, visc, turb, delta);
    ref *R = calloc(1, sizeof *R);
    assert_non_null(R);
    sph_wcsph_forces(s); /* computes the SPS stresses from the gradients, sorts by cell */
    /* the reference in creation order: undo the sort into a copy */
    sph_sim *u = cloud(type, visc, turb, delta);
    sph_particles *P = &s->P, *Q = &u->P;
    for (long i = 0; i < P->n; i++) {
        const int k = P->id[i];
        Q->x[k] = P->x[i];
        Q->y[k] = P->y[i];
        Q->vx[k] = P->vx[i];
        Q->vy[k] = P->vy[i];
        Q->rho[k] = P->rho[i];
        Q->type[k] = P->type[i];
        if (P->txx) {
            Q->txx[k] = P->txx[i];
            Q->txy[k] = P->txy[i];
            Q->tyy[k] = P->tyy[i];
        }
    }
    all_pairs(u, R);
    assert_true(s->nactive == P->n);
    compare("ax", P->ax, P->id, R->ax, P->n);
    compare("ay", P->ay, P->id, R->ay, P->n);
    compare("drho", P->drho, P->id, R->drho, P->n);
    if (turb == SPH_TURB_SPS) {
        compare("du/dx", P->gxx, P->id, R->gxx, P->n);
        compare("du/dy+dv/dx", P->gxy, P->id, R->gxy, P->n);
        compare("dv/dy", P->gyy, P->id, R->gyy, P->n);
    }
    assert_true(s->timing.pairs > 0);
    free(R);
    sph_sim_destroy(s);
    sph_sim_destroy(u);
}

static const sph_kernel_type kernels[] = {SPH_KERNEL_CUBIC_SPLINE, SPH_KERNEL_GAUSSIAN,
                                          SPH_KERNEL_DOUBLE_COSINE, SPH_KERNEL_WENDLAND_C2,
                                          SPH_KERNEL_RENORMALIZED_GAUSSIAN};

static void test_artificial(void **state)
{
    (void)state;
    for (size_t k = 0; k < sizeof kernels / sizeof kernels[0]; k++)
        check(kernels[k], SPH_VISC_ARTIFICIAL, SPH_TURB_NONE, 0.0);
}

static void test_laminar_sps(void **state)
{
    (void)state;
    for (size_t k = 0; k < sizeof kernels / sizeof kernels[0]; k++)
        check(kernels[k], SPH_VISC_LAMINAR, SPH_TURB_SPS, 0.0);
}

static void test_delta(void **state)
{
    (void)state;
    for (size_t k = 0; k < sizeof kernels / sizeof kernels[0]; k++)
        check(kernels[k], SPH_VISC_ARTIFICIAL, SPH_TURB_SPS, 0.1);
}

/* Monaghan's term as a physical viscosity: every pair, alpha = 2 (d + 2) nu / (h c0). */
static void test_monaghan(void **state)
{
    (void)state;
    for (size_t k = 0; k < sizeof kernels / sizeof kernels[0]; k++)
        check(kernels[k], SPH_VISC_MONAGHAN, SPH_TURB_NONE, 0.1);
    sph_sim *s = cloud(SPH_KERNEL_WENDLAND_C2, SPH_VISC_MONAGHAN, SPH_TURB_NONE, 0.0);
    assert_double_equal(sph_config_monaghan_alpha(&s->cfg), 8.0 * 1e-3 / (1.3 * 0.01 * 20.0),
                        1e-15);
    sph_sim_destroy(s);
}

/* The viscous terms between fluid and wall particles scaled by boundary.viscosity_factor. */
static void test_wall_viscosity(void **state)
{
    (void)state;
    cloud_wall_visc = 0.25;
    check(SPH_KERNEL_WENDLAND_C2, SPH_VISC_ARTIFICIAL, SPH_TURB_NONE, 0.0);
    check(SPH_KERNEL_CUBIC_SPLINE, SPH_VISC_LAMINAR, SPH_TURB_NONE, 0.0);
    check(SPH_KERNEL_WENDLAND_C2, SPH_VISC_MONAGHAN, SPH_TURB_NONE, 0.0);
    cloud_wall_visc = 1.0;
}

/* The counting sort: cells hold exactly the particles whose positions fall in them. */
static void test_sort(void **state)
{
    (void)state;
    sph_sim *s = cloud(SPH_KERNEL_WENDLAND_C2, SPH_VISC_ARTIFICIAL, SPH_TURB_NONE, 0.0);
    sph_particles *P = &s->P;
    P->x[7] = -5.0; /* outside the grid: lost, sorted to the end */
    const long n = sph_cells_sort(&s->cells, P);
    assert_int_equal(n, P->n - 1);
    assert_int_equal(P->type[P->n - 1], SPH_LOST);
    const sph_cells *g = &s->cells;
    for (long c = 0; c < g->ncells; c++)
        for (long i = g->start[c]; i < g->start[c + 1]; i++) {
            const int cx = (int)((P->x[i] - g->x0) * g->inv_size);
            const int cy = (int)((P->y[i] - g->y0) * g->inv_size);
            assert_int_equal((long)cx * g->ny + cy, c);
        }
    sph_sim_destroy(s);
}

/* The parallel counting sort, 3D, 40,000 particles in random order (some lost, some outside the
 * grid), with 1, 2, 3, 5 and 7 threads, then again after each particle moved by up to 0.6 cell
 * (nearly in order: few cross into another thread's range): the same order as a stable sort by
 * cell, then by z within each cell (checked against the keys computed here), the same cell
 * starts, and every particle kept. */
static void sort_cloud(int threads, int *ids, int *starts, long *active)
{
    const long n = 40000;
    sph_particles P;
    assert_int_equal(sph_particles_alloc(&P, n, 3, 0), 0);
    srand(12345);
    for (long i = 0; i < n; i++) {
        P.x[i] = 1.2 * rand() / (double)RAND_MAX - 0.1; /* some outside [0, 1] */
        P.y[i] = rand() / (double)RAND_MAX;
        P.z[i] = 0.5 * rand() / (double)RAND_MAX;
        P.type[i] = i % 97 == 0 ? SPH_LOST : (i % 5 == 0 ? SPH_BOUNDARY : SPH_FLUID);
        P.id[i] = (int)i;
    }
    sph_cells g;
    const double lo[3] = {0, 0, 0}, hi[3] = {1.0, 1.0, 0.5};
    assert_int_equal(sph_cells_alloc(&g, 3, lo, hi, 0.05, n), 0);
    omp_set_num_threads(threads);
    *active = sph_cells_sort(&g, &P);
    for (long i = 0; i < n; i++) { /* moved by their id, whatever their order */
        P.x[i] += 0.03 * sin(0.7 * P.id[i]);
        P.z[i] += 0.02 * cos(1.3 * P.id[i]);
    }
    *active = sph_cells_sort(&g, &P);
    long k = 0;
    for (long c = 0; c < g.ncells; c++)
        for (long i = g.start[c]; i < g.start[c + 1]; i++, k++) {
            assert_int_equal(i, k);
            const int cx = (int)((P.x[i] - g.x0) * g.inv_size);
            const int cy = (int)((P.y[i] - g.y0) * g.inv_size);
            const int cz = (int)((P.z[i] - g.z0) * g.inv_size);
            assert_int_equal(((long)cx * g.ny + cy) * g.nz + cz, c);
            /* in 3D by z within the cell, stable: ties keep the particles' order */
            assert_true(i == g.start[c] || P.z[i - 1] < P.z[i] ||
                        (P.z[i - 1] == P.z[i] && P.id[i - 1] < P.id[i]));
        }
    assert_int_equal(k, *active);
    assert_int_equal(g.start[g.ncells + 1], n);
    for (long i = *active; i < n; i++) /* (their order: the same with any threads, below) */
        assert_int_equal(P.type[i], SPH_LOST);
    memcpy(ids, P.id, (size_t)n * sizeof *ids);
    memcpy(starts, g.start, ((size_t)g.ncells + 2) * sizeof *starts);
    sph_cells_free(&g);
    sph_particles_free(&P);
}

static void test_sort_parallel(void **state)
{
    (void)state;
    const int saved = omp_get_max_threads();
    const long n = 40000, nstart = 22 * 22 * 12 + 2; /* the grid's cells + 2 */
    const int threads[] = {1, 2, 3, 5, 7}, nt = (int)(sizeof threads / sizeof threads[0]);
    int *ids = calloc((size_t)nt * (size_t)n, sizeof *ids),
        *starts = calloc((size_t)nt * (size_t)nstart, sizeof *starts);
    long active[5];
    for (int t = 0; t < nt; t++)
        sort_cloud(threads[t], ids + t * n, starts + t * nstart, &active[t]);
    omp_set_num_threads(saved);
    assert_true(active[0] > n / 2 && active[0] < n);
    for (int t = 1; t < nt; t++) {
        assert_int_equal(active[t], active[0]);
        assert_memory_equal(ids, ids + t * n, (size_t)n * sizeof *ids);
        assert_memory_equal(starts, starts + t * nstart, (size_t)nstart * sizeof *starts);
    }
    free(ids);
    free(starts);
}

/* mDBC's mirror points (sph_shapes_wall_mirror): tank walls through the nearest face, edge or
 * corner; an obstacle's particles through its nearest face that can be wet (not the one on the
 * floor, not one against a tank wall); points of no wall stay. */
static void mirror_is(const sph_config *c, double x, double y, double z, double gx, double gy,
                      double gz)
{
    const double p[3] = {x, y, z};
    double g[3];
    sph_shapes_wall_mirror(c, p, g);
    close_to(g[0], gx, 1e-12, "mirror x");
    close_to(g[1], gy, 1e-12, "mirror y");
    close_to(g[2], gz, 1e-12, "mirror z");
}

static void test_wall_mirror(void **state)
{
    (void)state;
    sph_config c = sph_config_default();
    c.dim = 3;
    c.dx = 0.1;
    c.has_tank = 1;
    c.tank = (sph_box){{0, 0, 0}, {1, 1, 1}};
    c.nobstacles = 2;
    c.obstacles[0] = (sph_box){{0.3, 0.3, 0}, {0.6, 0.6, 0.3}}; /* on the floor */
    c.obstacles[1] = (sph_box){{0, 0.8, 0.5}, {0.2, 1, 0.7}};   /* in the corner x 0, y 1 */
    mirror_is(&c, 0.25, 0.75, -0.05, 0.25, 0.75, 0.05);         /* floor */
    mirror_is(&c, 0.25, 0.75, -0.25, 0.25, 0.75, 0.25);         /* floor, third layer */
    mirror_is(&c, -0.05, -0.15, -0.05, 0.05, 0.15, 0.05);       /* a corner of the walls */
    mirror_is(&c, 1.05, 0.5, 0.9, 0.95, 0.5, 0.9);              /* side wall, near the open top */
    mirror_is(&c, 1.05, 0.5, 1.3, 0.95, 0.5, 1.3);              /* above the top: across x only */
    mirror_is(&c, 0.45, 0.45, 0.25, 0.45, 0.45, 0.35);          /* the obstacle's top */
    mirror_is(&c, 0.35, 0.45, 0.15, 0.25, 0.45, 0.15);          /* its face at x 0.3 */
    /* the second obstacle: particles at x 0.05, 0.15; y 0.85, 0.95; z 0.55, 0.65. Its faces at x
     * 0 and y 1 are against tank walls: its particle (0.05, 0.95, 0.55), 0.05 from them and from
     * z 0.5, goes across z 0.5 */
    mirror_is(&c, 0.05, 0.95, 0.55, 0.05, 0.95, 0.45);
    mirror_is(&c, 0.5, 0.5, 0.5, 0.5, 0.5, 0.5); /* in the water: no wall */
    c.dim = 2;
    c.nobstacles = 0;
    mirror_is(&c, -0.05, -0.05, 0, 0.05, 0.05, 0);
    mirror_is(&c, 1.15, 0.5, 0, 0.85, 0.5, 0);
}

/* A small dam break stepped with 1 and with 2 threads: bitwise the same state (the pair loops
 * visit pairs in an order fixed by the grid, the sort and the ghost build keep the particles'
 * order whatever the threads, and the reductions are max/min or serial). dx 0.004: 3750 fluid
 * and 843 wall particles, above SPH_OMP_MIN, so the loops run in parallel; dx 0.0025 (9600
 * fluid particles, above 2 SPH_OMP_MIN) so that the sort and the ghost build do too. */
static sph_sim *small_dambreak(int threads, double dx, sph_boundary_type walls, long steps)
{
    sph_config c = sph_config_default();
    c.dx = dx;
    c.h_over_dx = 1.414;
    c.domain = (sph_box){{0, 0, 0}, {0.5, 0.5, 0}};
    c.nfluid = 1;
    c.fluid[0] = (sph_box){{0, 0, 0}, {0.3, 0.2, 0}};
    c.boundary = walls;
    c.has_tank = 1;
    c.tank = (sph_box){{0, 0, 0}, {0.5, 0.3, 0}};
    c.c0 = 25.0;
    c.alpha = 0.1;
    c.turb = SPH_TURB_SPS;
    c.delta_sph = 0.1;
    c.t_end = 1.0;
    omp_set_num_threads(threads);
    sph_error err;
    sph_sim *s = sph_sim_create(&c, &err);
    assert_non_null(s);
    assert_true(s->P.n >= SPH_OMP_MIN);
    assert_int_equal(sph_sim_step(s, steps, &err), 0);
    return s;
}

static void reproducible(double dx, sph_boundary_type walls, long steps)
{
    const int saved = omp_get_max_threads();
    sph_sim *a = small_dambreak(1, dx, walls, steps), *b = small_dambreak(1, dx, walls, steps),
            *c = small_dambreak(2, dx, walls, steps);
    omp_set_num_threads(saved);
    const sph_sim *other[2] = {b, c};
    for (int k = 0; k < 2; k++) {
        const sph_particles *P = &a->P, *Q = &other[k]->P;
        assert_int_equal(P->n, Q->n);
        const size_t nb = (size_t)P->n * sizeof(double);
        assert_memory_equal(P->x, Q->x, nb);
        assert_memory_equal(P->y, Q->y, nb);
        assert_memory_equal(P->vx, Q->vx, nb);
        assert_memory_equal(P->vy, Q->vy, nb);
        assert_memory_equal(P->rho, Q->rho, nb);
        assert_memory_equal(P->id, Q->id, (size_t)P->n * sizeof(int));
        assert_memory_equal(&a->diag, &other[k]->diag, sizeof a->diag);
    }
    assert_true(a->diag.ekin > 0.0);
    sph_sim_destroy(a);
    sph_sim_destroy(b);
    sph_sim_destroy(c);
}

static void test_reproducible(void **state)
{
    (void)state;
    reproducible(0.004, SPH_BOUNDARY_DYNAMIC, 150);
    reproducible(0.0025, SPH_BOUNDARY_DYNAMIC, 40);
    reproducible(0.0025, SPH_BOUNDARY_GHOST, 40);
}

/* A block of 20 x 10 fluid particles (dx = 0.01 m) at the left of a 1 m domain, no walls. */
static sph_config block_config(void)
{
    sph_config c = sph_config_default();
    c.dx = 0.01;
    c.domain = (sph_box){{0, 0, 0}, {1.0, 1.0, 0}};
    c.nfluid = 1;
    c.fluid[0] = (sph_box){{0, 0, 0}, {0.2, 0.1, 0}};
    c.boundary = SPH_BOUNDARY_NONE;
    c.t_end = 1.0;
    return c;
}

/* No fluid particle nearer than dx to a wall particle. */
static void assert_fluid_clear(const sph_particles *P, double dx)
{
    for (long i = 0; i < P->n; i++)
        for (long j = 0; j < P->n; j++)
            if (P->type[i] == SPH_FLUID && P->type[j] == SPH_BOUNDARY) {
                double r2 = (P->x[i] - P->x[j]) * (P->x[i] - P->x[j]) +
                            (P->y[i] - P->y[j]) * (P->y[i] - P->y[j]);
                if (P->z)
                    r2 += (P->z[i] - P->z[j]) * (P->z[i] - P->z[j]);
                assert_true(r2 > 0.99 * dx * dx);
            }
}

/* Obstacles (issue 23): a box of wall particles on a lattice of dx centred in it, its faces
 * within dx/4 of the box's, in 2D and 3D; the fluid box that overlaps it leaves its place (no
 * fluid particle nearer than dx to an obstacle's particle); refused with ghost walls. */
static void test_obstacles(void **state)
{
    (void)state;
    for (int dim = 2; dim <= 3; dim++) {
        sph_config c = block_config();
        c.dim = dim;
        c.boundary = SPH_BOUNDARY_DYNAMIC;
        c.gravity[1] = dim == 3 ? 0.0 : -9.81;
        c.gravity[2] = dim == 3 ? -9.81 : 0.0;
        c.domain.max[2] = dim == 3 ? 0.3 : 0.0;
        c.fluid[0] = (sph_box){{0, 0, 0}, {0.2, 0.1, dim == 3 ? 0.1 : 0}};
        c.nobstacles = 1; /* 4 x 3 (x 2) particles, overlapping the fluid's corner */
        c.obstacles[0] = (sph_box){{0.16, 0.07, 0.08}, {0.2, 0.1, 0.1}};
        if (dim == 2)
            c.obstacles[0].min[2] = c.obstacles[0].max[2] = 0.0;
        sph_error err;
        sph_sim *s = sph_sim_create(&c, &err);
        assert_non_null(s);
        const long nfluid_box = dim == 3 ? 20 * 10 * 10 : 20 * 10;
        const long nobst = dim == 3 ? 4 * 3 * 2 : 4 * 3;
        assert_int_equal(s->nboundary, nobst);
        assert_int_equal(s->nfluid, nfluid_box - nobst);
        const sph_particles *P = &s->P;
        assert_fluid_clear(P, c.dx);
        sph_sim_destroy(s);
        /* a box whose sides are no multiple of dx (0.047 x 0.024 (x 0.033) at dx 0.01, 5 x 2 (x
         * 3) points): in 2D the lattice centred in it, its faces (the outer points plus dx/2)
         * within dx/4 of the box's; in 3D the scene's one lattice (sph_config_by_scene), its
         * points inside the box, so its faces within dx/2 of the box's; and still no fluid
         * particle nearer than dx */
        c.obstacles[0] = (sph_box){{0.1535, 0.076, 0.067}, {0.2005, 0.1, 0.1}};
        if (dim == 2)
            c.obstacles[0].min[2] = c.obstacles[0].max[2] = 0.0;
        s = sph_sim_create(&c, &err);
        assert_non_null(s);
        assert_int_equal(s->nboundary, dim == 3 ? 5 * 2 * 3 : 5 * 2);
        P = &s->P;
        double lo[3] = {1e9, 1e9, 1e9}, hi[3] = {-1e9, -1e9, -1e9};
        for (long j = 0; j < P->n; j++)
            if (P->type[j] == SPH_BOUNDARY) {
                const double q[3] = {P->x[j], P->y[j], dim == 3 ? P->z[j] : 0.0};
                for (int d = 0; d < dim; d++) {
                    lo[d] = q[d] < lo[d] ? q[d] : lo[d];
                    hi[d] = q[d] > hi[d] ? q[d] : hi[d];
                }
            }
        const double tol = (dim == 3 ? 0.5 : 0.25) * c.dx + 1e-12;
        for (int d = 0; d < dim; d++) {
            assert_true(fabs(lo[d] - 0.5 * c.dx - c.obstacles[0].min[d]) <= tol);
            assert_true(fabs(hi[d] + 0.5 * c.dx - c.obstacles[0].max[d]) <= tol);
        }
        assert_fluid_clear(P, c.dx);
        sph_sim_destroy(s);
        c.boundary = SPH_BOUNDARY_GHOST;
        c.has_tank = 1;
        c.tank = (sph_box){{0, 0, 0}, {1.0, 1.0, dim == 3 ? 0.3 : 0}};
        assert_null(sph_sim_create(&c, &err));
        assert_string_equal(err.path, "/boundary/obstacles");
    }
}

/* Pressure probes: at rest the fluid's pressure is rho0 g (H - y) (its initial density is the
 * hydrostatic one), so Shepard's interpolation at a point of the lattice's symmetry inside the
 * fluid reads that value (the field is linear and the kernel weights symmetric: exact but for the
 * volumes m / rho_j, which vary by 0.1% across the support; 2.8e-5 in 2D); a probe on the
 * bottom face sees the fluid above it only, and reads less than rho0 g H by the weights' mean
 * height (within rho0 g h); one in the air reads 0. A probe on the bottom with the normal up
 * (of any length) reads where a probe placed 1.5 h above the bottom reads, the same bits, and is
 * nearer the hydrostatic pressure there (within 0.1%: 0.02%) than the probe on the bottom is to
 * its own (6.5% low). In 2D and 3D. Names are checked with the gauges', positions (and where a
 * normal makes a probe read) against the domain. */
static void test_pressure_probes(void **state)
{
    (void)state;
    for (int dim = 2; dim <= 3; dim++) {
        sph_config c = block_config();
        const int V = dim - 1;
        c.dim = dim;
        c.gravity[1] = 0.0;
        c.gravity[V] = -9.81;
        c.domain.max[2] = dim == 3 ? 1.0 : 0.0;
        if (dim == 3) /* 0.2 x 0.1 x 0.1 m, 0.1 deep */
            c.fluid[0] = (sph_box){{0, 0, 0}, {0.2, 0.1, 0.1}};
        const double H = 0.1, g = 9.81, pH = c.rho0 * g * H;
        c.npressure = 5;
        c.pressure[0] = (sph_pressure_spec){.name = "mid", .at = {0.1, 0.05, 0.05}};
        c.pressure[1] = (sph_pressure_spec){.name = "floor", .at = {0.1, 0.0, 0.0}};
        c.pressure[2] = (sph_pressure_spec){.name = "air", .at = {0.6, 0.6, 0.6}};
        c.pressure[3] = (sph_pressure_spec){.name = "floor_n", .at = {0.1, 0.0, 0.0}};
        c.pressure[3].normal[V] = 2.0;
        c.pressure[4] = (sph_pressure_spec){.name = "above", .at = {0.1, 0.0, 0.0}};
        if (dim == 3)
            c.pressure[1].at[1] = c.pressure[3].at[1] = c.pressure[4].at[1] = 0.05;
        const double h = c.h_over_dx * c.dx;
        c.pressure[4].at[V] = 1.5 * h;
        sph_error err;
        sph_sim *s = sph_sim_create(&c, &err);
        assert_non_null(s);
        assert_int_equal(s->diag.npressure, 5);
        const double *pp = s->diag.pressure, pn = c.rho0 * g * (H - 1.5 * h);
        printf("  %dD: mid %.6f of rho0 g H / 2, floor %.4f of rho0 g H, 1.5 h off the floor "
               "%.4f of rho0 g (H - 1.5 h)\n",
               dim, pp[0] / (0.5 * pH), pp[1] / pH, pp[3] / pn);
        assert_true(fabs(pp[0] / (0.5 * pH) - 1.0) < 1e-4);
        assert_true(pp[1] < pH && pp[1] > pH - c.rho0 * g * s->h);
        assert_true(pp[2] == 0.0);
        assert_true(pp[3] == pp[4]);
        assert_true(fabs(pp[3] / pn - 1.0) < 1e-3 && fabs(pp[3] - pn) < 0.5 * fabs(pp[1] - pH));
        sph_sim_destroy(s);

        c.pressure[3].normal[V] = -1.0; /* reads below the bottom, outside the domain */
        assert_null(sph_sim_create(&c, &err));
        assert_string_equal(err.path, "/diagnostics/pressure/3/normal");
        c.npressure = 3;

        c.ngauges = 1;
        c.gauges[0] = (sph_gauge_spec){"floor", 0.1, 0.05, NAN};
        assert_null(sph_sim_create(&c, &err));
        assert_string_equal(err.path, "/diagnostics/pressure/1/name");
        c.ngauges = 0;
        c.pressure[2].at[V] = 2.0;
        assert_null(sph_sim_create(&c, &err));
        assert_string_equal(err.path, dim == 3 ? "/diagnostics/pressure/2/at/2"
                                               : "/diagnostics/pressure/2/at/1");
    }
}

/* The front and height probes ignore a droplet far ahead of (or above) the connected fluid. */
static void test_probes(void **state)
{
    (void)state;
    sph_config c = block_config();
    sph_error err;
    sph_sim *s = sph_sim_create(&c, &err);
    assert_non_null(s);
    assert_true(fabs(s->diag.front_x - 0.2) < 1e-12);
    assert_true(fabs(s->diag.height_left - 0.1) < 1e-12);
    /* two particles from inside the block become droplets: one far ahead, one high above the
     * column at the wall (id = 10 ix + iy, at x = (ix + 0.5) dx, y = (iy + 0.5) dx) */
    for (long i = 0; i < s->P.n; i++) {
        if (s->P.id[i] == 195) {
            s->P.x[i] = 0.7;
            s->P.y[i] = 0.005;
        }
        if (s->P.id[i] == 105) {
            s->P.x[i] = 0.005;
            s->P.y[i] = 0.6;
        }
    }
    sph_diag_compute(s);
    assert_true(fabs(s->diag.front_x - 0.2) < 1e-12);
    assert_true(fabs(s->diag.height_left - 0.1) < 1e-12);
    /* a tongue of fluid along the bed, one particle thick, is connected: it counts */
    for (long i = 0; i < s->P.n; i++)
        if (s->P.id[i] == 195) {
            s->P.x[i] = 0.215;
            s->P.y[i] = 0.005;
        }
    sph_diag_compute(s);
    assert_true(fabs(s->diag.front_x - 0.22) < 1e-12);
    sph_sim_destroy(s);
}

/* A height gauge reads the water's height on its line: a droplet above it does not count, a
 * hump on the surface does, a sheet above with air between does not, a dry line reads 0; a
 * run-up gauge over [x, to] reads the highest water there, across gaps of a support (the sheet
 * counts, the droplet does not) and 0 over a dry range; the checks refuse a bad gauge at its
 * path. */
static void test_gauges(void **state)
{
    (void)state;
    sph_config c = block_config();
    c.ngauges = 4;
    c.gauges[0] = (sph_gauge_spec){"wet", 0.105, 0.0, NAN};
    c.gauges[1] = (sph_gauge_spec){"dry", 0.5, 0.0, NAN};
    c.gauges[2] = (sph_gauge_spec){"top", 0.05, 0.0, 0.3};
    c.gauges[3] = (sph_gauge_spec){"dryrange", 0.4, 0.0, 0.6};
    sph_error err;
    sph_sim *s = sph_sim_create(&c, &err);
    assert_non_null(s);
    assert_int_equal(s->diag.ngauges, 4);
    assert_true(fabs(s->diag.gauge[0] - 0.1) < 1e-12);
    assert_true(s->diag.gauge[1] == 0.0);
    assert_true(fabs(s->diag.gauge[2] - 0.1) < 1e-12 && s->diag.gauge[3] == 0.0);
    /* column ix = 10 (x = 0.105): its top particle raised by 1.5 dx stays connected (the hump
     * counts); one from column 11, within dx of the line, lifted far above is a droplet */
    for (long i = 0; i < s->P.n; i++) {
        if (s->P.id[i] == 109)
            s->P.y[i] = 0.11;
        if (s->P.id[i] == 115)
            s->P.y[i] = 0.8;
    }
    sph_diag_compute(s);
    assert_true(fabs(s->diag.gauge[0] - 0.115) < 1e-12);
    assert_true(s->diag.gauge[1] == 0.0);
    assert_true(fabs(s->diag.gauge[2] - 0.115) < 1e-12); /* the droplet at 0.8 does not count */
    /* the gauge reads the continuous column: a particle (from column 9, x = 0.095, within dx of
     * the line) one empty bin above the hump (y = 0.11, the bin [0.11, 0.12)) counts; two empty
     * bins above (air between, though within a kernel support) it does not */
    for (long i = 0; i < s->P.n; i++)
        if (s->P.id[i] == 98)
            s->P.y[i] = 0.135;
    sph_diag_compute(s);
    assert_true(fabs(s->diag.gauge[0] - 0.14) < 1e-12);
    for (long i = 0; i < s->P.n; i++)
        if (s->P.id[i] == 98)
            s->P.y[i] = 0.145;
    sph_diag_compute(s);
    assert_true(fabs(s->diag.gauge[0] - 0.115) < 1e-12);
    /* the run-up gauge: two empty bins (less than a support) between: the sheet counts */
    assert_true(fabs(s->diag.gauge[2] - 0.15) < 1e-12);
    sph_sim_destroy(s);
    c.gauges[2].to = 0.05; /* not past x */
    assert_null(sph_sim_create(&c, &err));
    assert_string_equal(err.path, "/diagnostics/gauges/2/to");
    c.gauges[2].to = 1.5; /* past the tank */
    assert_null(sph_sim_create(&c, &err));
    assert_string_equal(err.path, "/diagnostics/gauges/2/to");
    c.ngauges = 2;

    c.gauges[1].x = 1.0; /* on the domain's edge */
    assert_null(sph_sim_create(&c, &err));
    assert_string_equal(err.path, "/diagnostics/gauges/1/x");
    c.gauges[1] = (sph_gauge_spec){"wet", 0.5, 0.0, NAN};
    assert_null(sph_sim_create(&c, &err));
    assert_string_equal(err.path, "/diagnostics/gauges/1/name");
    c.gauges[1] = (sph_gauge_spec){"runup", 0.5, 0.0, NAN};
    assert_null(sph_sim_create(&c, &err));
    assert_string_equal(err.path, "/diagnostics/gauges/1/name");
    c.gauges[1] = (sph_gauge_spec){"a.b", 0.5, 0.0, NAN};
    assert_null(sph_sim_create(&c, &err));
    assert_string_equal(err.path, "/diagnostics/gauges/1/name");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sort),
        cmocka_unit_test(test_sort_parallel),
        cmocka_unit_test(test_artificial),
        cmocka_unit_test(test_laminar_sps),
        cmocka_unit_test(test_delta),
        cmocka_unit_test(test_reproducible),
        cmocka_unit_test(test_probes),
        cmocka_unit_test(test_gauges),
        cmocka_unit_test(test_monaghan),
        cmocka_unit_test(test_obstacles),
        cmocka_unit_test(test_pressure_probes),
        cmocka_unit_test(test_wall_viscosity),
        cmocka_unit_test(test_wall_mirror),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
