/*
 * mDBC's no-penetration control (core/wcsph/sph_wcsph.c, sph_wcsph_no_penetration), on the 2D
 * dam break and the 3D Test 2 with mDBC walls: a fluid particle placed close over the floor
 * and moving into it loses that part of its velocity, reversed in part the closer it is (v_n
 * -> v_n (1 - f), f = 2.5 - 2 max(d / norm, 1/4), d its height over the first layer of the
 * floor's wall particles and norm their distance to their mirror points across the floor); one
 * moving away, or farther than 3/4 norm over them, keeps its velocity; the tangential part is
 * kept. Tolerance: 1e-12 m/s (the arithmetic of one particle).
 *
 * And the walls' fit (mdbc_one) on the same cases at rest: a wall particle with no fluid within
 * its support (found here by brute force) is not fitted and holds rho0 exactly; one under the
 * water with fluid within its support is fitted, above rho0 (the hydrostatic density at the
 * floor, 0.4% above it in Test 2). A skip that reached one wall particle too many, or none,
 * fails it.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "sph_wcsph.h"
#include "unit_case.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static double *axis(sph_particles *P, int d)
{
    return d == 0 ? P->x : d == 1 ? P->y : P->z;
}

static double *vel(sph_particles *P, int d)
{
    return d == 0 ? P->vx : d == 1 ? P->vy : P->vz;
}

/* The row of the particle with creation index id. */
static long row_of(const sph_particles *P, int id)
{
    for (long i = 0; i < P->n; i++)
        if (P->id[i] == id)
            return i;
    fail_msg("no particle %d", id);
    return -1;
}

/* Places fluid particle `id` at height `over` (in dx) above the floor's face, re-sorts, gives it
 * the velocity (vt along x, vn up) and runs the control; checks the result against expect_f (the
 * factor on vn's loss, 0: untouched). */
static void place(sph_sim *s, int id, double over, double vt, double vn, double expect_f)
{
    sph_particles *P = &s->P;
    const int up = s->cfg.dim - 1;
    long i = row_of(P, id);
    axis(P, up)[i] = s->cfg.tank.min[up] + over * s->cfg.dx;
    assert_int_equal(sph_wcsph_forces(s), 0); /* sorts by cell */
    i = row_of(P, id);
    for (int d = 0; d < s->cfg.dim; d++)
        vel(P, d)[i] = 0.0;
    vel(P, 0)[i] = vt;
    vel(P, up)[i] = vn;
    assert_int_equal(sph_wcsph_no_penetration(s), 0);
    i = row_of(P, id);
    assert_true(fabs(vel(P, 0)[i] - vt) < 1e-12);
    const double got = vel(P, up)[i], want = vn * (1.0 - expect_f);
    if (!(fabs(got - want) < 1e-12))
        fail_msg("%dD, %.2f dx over the floor, v_n %g: v_n %.15g, expected %.15g", s->cfg.dim, over,
                 vn, got, want);
}

static void check(const char *name, const char *const *sets)
{
    const sph_config cfg = load_case(name, sets);
    sph_error err;
    sph_sim *s = sph_sim_create(&cfg, &err);
    if (!s)
        fail_msg("%s: %s", name, err.message);
    sph_particles *P = &s->P;
    const int D = cfg.dim, up = D - 1;
    /* the fluid particle of the bottom row nearest the middle of the fluid's first box, and the
     * floor's first layer of wall particles (the highest below the floor's face) */
    double mid[3];
    for (int d = 0; d < D; d++)
        mid[d] = 0.5 * (cfg.fluid[0].min[d] + cfg.fluid[0].max[d]);
    int id = -1;
    double best = INFINITY, wall = -INFINITY;
    for (long i = 0; i < P->n; i++) {
        const double h = axis(P, up)[i];
        if (P->type[i] == SPH_BOUNDARY && h < cfg.tank.min[up] && h > wall)
            wall = h;
        if (P->type[i] != SPH_FLUID || h > cfg.tank.min[up] + cfg.dx)
            continue;
        double r2 = 0.0;
        for (int d = 0; d < up; d++)
            r2 += (axis(P, d)[i] - mid[d]) * (axis(P, d)[i] - mid[d]);
        if (r2 < best) {
            best = r2;
            id = P->id[i];
        }
    }
    assert_true(id >= 0 && isfinite(wall));
    const double norm = 2.0 * (cfg.tank.min[up] - wall) / cfg.dx; /* in dx */
    const double below = (cfg.tank.min[up] - wall) / cfg.dx;      /* the face over the layer */
#define F(over) (2.5 - 2.0 * fmax(((over) + below) / norm, 0.25))
    place(s, id, 0.10, 0.3, -1.0, F(0.10));  /* close, moving in */
    place(s, id, 0.05, -0.2, -2.0, F(0.05)); /* closer */
    place(s, id, -0.3, 0.1, -1.0, F(-0.3));  /* inside the wall already: reversed, f = 2 */
    assert_true(fabs(F(-0.3) - 2.0) < 1e-12);
    place(s, id, 0.10, 0.3, 1.0, 0.0);  /* moving away */
    place(s, id, 0.30, 0.3, -1.0, 0.0); /* beyond 3/4 of norm */
#undef F
    sph_sim_destroy(s);
}

/* The walls' densities after one force evaluation at rest (see the top). */
static void check_fit(const char *name, const char *const *sets)
{
    const sph_config cfg = load_case(name, sets);
    sph_error err;
    sph_sim *s = sph_sim_create(&cfg, &err);
    if (!s)
        fail_msg("%s: %s", name, err.message);
    assert_int_equal(sph_wcsph_forces(s), 0);
    sph_particles *P = &s->P;
    const int D = cfg.dim, up = D - 1;
    const double support2 = s->kernel.support * s->kernel.support;
    long fitted = 0, skipped = 0;
    for (long i = 0; i < P->n; i++) {
        if (P->type[i] != SPH_BOUNDARY)
            continue;
        int near = 0;
        for (long j = 0; j < P->n && !near; j++) {
            if (P->type[j] != SPH_FLUID)
                continue;
            double r2 = 0.0;
            for (int d = 0; d < D; d++)
                r2 += (axis(P, d)[i] - axis(P, d)[j]) * (axis(P, d)[i] - axis(P, d)[j]);
            near = r2 < support2;
        }
        /* under the water: below the floor's face, under the fluid's first box a support
         * away from its sides */
        int under = axis(P, up)[i] < cfg.tank.min[up];
        for (int d = 0; d < up; d++)
            under &= axis(P, d)[i] > cfg.fluid[0].min[d] + s->kernel.support &&
                     axis(P, d)[i] < cfg.fluid[0].max[d] - s->kernel.support;
        const double rho = P->rho[i];
        if (!near && rho != cfg.rho0)
            fail_msg("%s: wall particle %d, no fluid within its support: rho %.17g, not rho0", name,
                     P->id[i], rho);
        if (near && under && !(rho > cfg.rho0))
            fail_msg("%s: wall particle %d under the water: rho %.17g, not fitted", name, P->id[i],
                     rho);
        fitted += near && under;
        skipped += !near && under;
    }
    /* the first two layers under the water are fitted, the third is out of reach (h = 1.414
     * dx: the support 2.83 dx, the third layer 3 dx from the fluid) */
    print_message("%s: %ld wall particles under the water fitted, %ld skipped\n", name, fitted,
                  skipped);
    assert_true(fitted > 0 && skipped > 0);
    assert_true(labs(fitted - 2 * skipped) <= skipped / 4);
    sph_sim_destroy(s);
}

static void test_fit_2d(void **state)
{
    (void)state;
    static const char *const sets[] = {"boundary.density=\"mdbc\"", NULL};
    check_fit("dambreak.json", sets);
}

static void test_fit_3d(void **state)
{
    (void)state;
    static const char *const sets[] = {"dx=0.0458333", "boundary.density=\"mdbc\"", NULL};
    check_fit("dambreak3d.json", sets);
}

static void test_2d(void **state)
{
    (void)state;
    static const char *const sets[] = {"boundary.density=\"mdbc\"", NULL};
    check("dambreak.json", sets);
}

static void test_3d(void **state)
{
    (void)state;
    static const char *const sets[] = {"dx=0.0458333", "boundary.density=\"mdbc\"", NULL};
    check("dambreak3d.json", sets);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_2d),
        cmocka_unit_test(test_3d),
        cmocka_unit_test(test_fit_2d),
        cmocka_unit_test(test_fit_3d),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
