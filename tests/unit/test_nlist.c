/*
 * The reused neighbour list ("neighbours": {"skin": S}, WCSPH on the CPU; core/wcsph/sph_wcsph.c):
 *   - the same physics as the cells searched every step: the 2D dam break and the 3D dam break
 *     with a box (Test 2's geometry) over 60 steps, every particle (matched by id) within 1e-9
 *     m (2D) of the binned run's position and 1e-6 of its density relative, and the same number
 *     of interacting pairs at every step (the pairs are the same; only the order in which a
 *     particle's sums are added differs, so the bits may not);
 *   - exact restarts: a run saved at several steps between two builds of the list, restored and
 *     run on, equals the uninterrupted run bit for bit, with 1 thread and 2 (the same bits);
 *   - its refusals at /neighbours/skin, each naming what needs the cells every step.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "sph_sim.h"
#include "unit_case.h"

#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* A sim's fields by particle id: position (dim), density. */
typedef struct by_id {
    long n;
    int dim;
    double *x[3], *rho;
} by_id;

static by_id take(const sph_sim *s)
{
    sph_particle_view v;
    sph_sim_particles(s, &v);
    by_id b = {.n = v.n, .dim = v.dim};
    for (int d = 0; d < 3; d++)
        b.x[d] = calloc((size_t)v.n, sizeof(double));
    b.rho = calloc((size_t)v.n, sizeof(double));
    for (long i = 0; i < v.n; i++) {
        const int id = v.id[i];
        assert_true(id >= 0 && id < v.n);
        for (int d = 0; d < v.dim; d++)
            b.x[d][id] = v.pos[d][i];
        b.rho[id] = v.rho[i];
    }
    return b;
}

static void drop(by_id *b)
{
    for (int d = 0; d < 3; d++)
        free(b->x[d]);
    free(b->rho);
}

/* Runs the case binned and listed for `steps` steps side by side: the same pairs at each step,
 * then the positions within tol_x [m] and the densities within 1e-6 relative, by id. */
static void same_physics(const char *name, const char *dx, long steps, double tol_x)
{
    const char *const binned[] = {dx, NULL};
    const char *const listed[] = {dx, "neighbours.skin=0.1", NULL};
    const sph_config cb = load_case(name, binned), cl = load_case(name, listed);
    assert_true(cl.neighbour_skin == 0.1);
    sph_error err;
    sph_sim *a = sph_sim_create(&cb, &err), *b = sph_sim_create(&cl, &err);
    assert_non_null(a);
    assert_non_null(b);
    for (long k = 0; k < steps; k++) {
        assert_int_equal(sph_sim_step(a, 1, &err), 0);
        assert_int_equal(sph_sim_step(b, 1, &err), 0);
        sph_timing ta, tb;
        sph_sim_timing(a, &ta);
        sph_sim_timing(b, &tb);
        assert_int_equal(ta.pairs, tb.pairs);
        assert_int_equal(ta.active, tb.active);
    }
    by_id pa = take(a), pb = take(b);
    assert_int_equal(pa.n, pb.n);
    double ex = 0.0, er = 0.0;
    for (long i = 0; i < pa.n; i++) {
        for (int d = 0; d < pa.dim; d++)
            ex = fmax(ex, fabs(pa.x[d][i] - pb.x[d][i]));
        er = fmax(er, fabs(pa.rho[i] - pb.rho[i]) / pa.rho[i]);
    }
    sph_timing t;
    sph_sim_timing(b, &t);
    printf("%s (%s), %ld steps, %ld lists built, %ld particles, %ld pairs: listed against "
           "binned: largest position difference %.3g m, density %.3g relative\n",
           name, dx, steps, t.lists, pa.n, t.pairs, ex, er);
    assert_true(t.lists >= 2 && t.lists <= steps / 3); /* reused, and built anew */
    assert_true(ex <= tol_x);
    assert_true(er <= 1e-6);
    drop(&pa);
    drop(&pb);
    sph_sim_destroy(a);
    sph_sim_destroy(b);
}

static void test_same_physics_2d(void **state)
{
    (void)state;
    same_physics("dambreak.json", "dx=0.005", 400, 1e-9);
}

static void test_same_physics_3d(void **state)
{
    (void)state;
    same_physics("dambreak3d.json", "dx=0.06", 150, 1e-9);
}

/* Saved after n1, n1 + 1, ... n1 + 4 steps (some of them between two builds of the list),
 * restored and run to n1 + n2: each equals the run that went on, bit for bit. Returns that run. */
static sph_sim *restarts(const sph_config *cfg, long n1, long n2)
{
    sph_error err;
    sph_sim *a = sph_sim_create(cfg, &err);
    assert_non_null(a);
    assert_int_equal(sph_sim_step(a, n1, &err), 0);
    void *buf[5];
    size_t len[5];
    for (int k = 0; k < 5; k++) {
        assert_int_equal(sph_sim_save(a, &buf[k], &len[k], &err), 0);
        if (k < 4)
            assert_int_equal(sph_sim_step(a, 1, &err), 0);
    }
    assert_int_equal(sph_sim_step(a, n2 - 4, &err), 0);
    sph_timing t;
    sph_sim_timing(a, &t);
    printf("%ld steps, %ld lists built\n", n1 + n2, t.lists);
    assert_true(t.lists >= 2 && t.lists <= (n1 + n2) / 3); /* so the saves fell between builds */
    for (int k = 0; k < 5; k++) {
        sph_sim *b = sph_sim_restore(buf[k], len[k], &err);
        assert_non_null(b);
        assert_int_equal(sph_sim_diag(b)->step, n1 + k);
        assert_int_equal(sph_sim_step(b, n2 - k, &err), 0);
        unit_same_bits(a, b);
        sph_sim_destroy(b);
    }
    /* a damaged cell list is refused: the last start, the particle count, made wrong */
    const size_t at = len[0] - sizeof(int);
    ((unsigned char *)buf[0])[at] ^= 1;
    assert_null(sph_sim_restore(buf[0], len[0], &err));
    assert_int_equal(err.code, SPH_ERR_IO);
    for (int k = 0; k < 5; k++)
        free(buf[k]);
    return a;
}

static void test_restarts(void **state)
{
    (void)state;
    static const char *const d2[] = {"dx=0.005", "neighbours.skin=0.1", NULL};
    static const char *const d3[] = {"dx=0.06", "neighbours.skin=0.2", NULL};
    const sph_config cfgs[] = {load_case("dambreak.json", d2), load_case("dambreak3d.json", d3)};
    const int saved = omp_get_max_threads();
    for (size_t k = 0; k < sizeof cfgs / sizeof cfgs[0]; k++) {
        sph_sim *run[2];
        for (int t = 0; t < 2; t++) {
            omp_set_num_threads(t + 1);
            run[t] = restarts(&cfgs[k], 100, 40);
        }
        unit_same_bits(run[0], run[1]); /* 1 thread and 2: the same bits */
        sph_sim_destroy(run[0]);
        sph_sim_destroy(run[1]);
    }
    omp_set_num_threads(saved);
}

/* cases/NAME with the skin and `set` is refused at `at`, the message naming why. */
static void refused_at(const char *name, const char *set, const char *at, const char *why)
{
    const char *const sets[] = {"neighbours.skin=0.1", set, NULL};
    sph_config cfg;
    sph_error err;
    assert_int_not_equal(parse_case(name, sets, &cfg, &err), 0);
    printf("%s with %s: refused at %s: %s\n", name, set ? set : "a skin", err.path, err.message);
    assert_int_equal(err.code, SPH_ERR_INVALID);
    assert_string_equal(err.path, at);
    assert_non_null(strstr(err.message, why));
}

static void refused(const char *name, const char *set, const char *why)
{
    refused_at(name, set, "/neighbours/skin", why);
}

static void test_refusals(void **state)
{
    (void)state;
    refused("dambreak_ghost.json", NULL, "ghost walls");
    refused("dambreak.json", "boundary.density=mdbc", "mDBC");
    refused("water_entry.json", NULL, "rigid bodies");
    refused("wave_flume.json", NULL, "wavemaker");
    refused("dambreak.json", "physics.shifting.type=lind", "shifting");
    refused_at("mps_dambreak.json", NULL, "/neighbours", "method wcsph");
    /* out of range: the case's own bounds */
    const char *const big[] = {"neighbours.skin=1.5", NULL};
    sph_config cfg;
    sph_error err;
    assert_int_not_equal(parse_case("dambreak.json", big, &cfg, &err), 0);
    assert_string_equal(err.path, "/neighbours/skin");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_refusals),
        cmocka_unit_test(test_same_physics_2d),
        cmocka_unit_test(test_same_physics_3d),
        cmocka_unit_test(test_restarts),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
