/*
 * The gather loop (core/wcsph/sph_wcsph.c, gather_one: each particle against every neighbour, its
 * own side alone; what a GPU thread runs) against the symmetric strip loop the CPU runs: the same
 * accelerations, density rates and SPS gradients to rounding (the sums run in another order), the
 * same pair count, on the cases of cases/ after 40 steps of motion: the 2D dam break (dynamic
 * walls, delta-SPH), laminar viscosity with SPS, ghost walls, a rigid body (water entry), and the
 * 3D Test 2 (mDBC walls, an obstacle). Tolerance: 1e-10 of the array's largest magnitude (a
 * missed neighbour range or a term on the wrong side is of order 1).
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

/* Largest |a - b| over n values, relative to the largest |a|. */
static double rel_diff(const double *a, const double *b, long n)
{
    double m = 0.0, d = 0.0;
    for (long i = 0; i < n; i++) {
        m = fmax(m, fabs(a[i]));
        d = fmax(d, fabs(a[i] - b[i]));
    }
    return m > 0.0 ? d / m : d;
}

#define NF 10
/* The fields a force evaluation writes (NULL where the case has none). */
static void fields(const sph_particles *P, double **f)
{
    double *const all[NF] = {P->ax,  P->ay,  P->az,  P->drho, P->gxx,
                             P->gxy, P->gyy, P->gzz, P->gxz,  P->gyz};
    memcpy(f, all, sizeof all);
}

static void check_case(const char *name, const char *const *sets)
{
    const sph_config cfg = load_case(name, sets);
    sph_error err;
    sph_sim *s = sph_sim_create(&cfg, &err);
    if (!s)
        fail_msg("%s: %s", name, err.message);
    assert_int_equal(sph_sim_step(s, 40, &err), 0);
    sph_particles *P = &s->P;
    static const char *const names[NF] = {"ax",  "ay",  "az",  "drho", "gxx",
                                          "gxy", "gyy", "gzz", "gxz",  "gyz"};
    double *f[NF];
    /* what a force evaluation reads besides the particles' state, which it also changes: the
     * SPS gradients (the stresses come from the previous evaluation's) and the bodies' motion
     * (their particles' pressure from the fluid uses it): kept, and put back for the second */
    assert_int_equal(sph_wcsph_forces(s), 0); /* sorted: the next sorts keep the order */
    const long n = P->n;
    double *g0[NF] = {0};
    fields(P, f);
    for (int k = 4; k < NF; k++)
        if (f[k]) {
            g0[k] = malloc((size_t)n * sizeof(double));
            memcpy(g0[k], f[k], (size_t)n * sizeof(double));
        }
    sph_body_state b0[SPH_CONFIG_MAX_BODIES];
    for (int k = 0; k < s->bodies.n; k++)
        b0[k] = s->bodies.b[k].s;

    assert_int_equal(sph_wcsph_forces(s), 0);
    const long pairs = s->timing.pairs;
    double *sym[NF] = {0};
    fields(P, f);
    for (int k = 0; k < NF; k++)
        if (f[k]) {
            sym[k] = malloc((size_t)n * sizeof(double));
            memcpy(sym[k], f[k], (size_t)n * sizeof(double));
        }
    fields(P, f);
    for (int k = 4; k < NF; k++)
        if (f[k]) {
            memcpy(f[k], g0[k], (size_t)n * sizeof(double));
            free(g0[k]);
        }
    for (int k = 0; k < s->bodies.n; k++)
        s->bodies.b[k].s = b0[k];
    assert_int_equal(sph_wcsph_forces_gather(s), 0);
    assert_int_equal(P->n, n);
    printf("%s: %ld particles, %ld pairs (gather %ld)", name, n, pairs, s->timing.pairs);
    assert_true(pairs > n);
    assert_int_equal(s->timing.pairs, pairs);
    fields(P, f); /* the arrays' addresses may change (a sort swaps them) */
    for (int k = 0; k < NF; k++) {
        if (!f[k])
            continue;
        const double e = rel_diff(sym[k], f[k], n);
        printf(", %s %.1e", names[k], e);
        if (!(e <= 1e-10)) {
            long w = 0;
            for (long i = 0; i < n; i++)
                if (fabs(sym[k][i] - f[k][i]) > fabs(sym[k][w] - f[k][w]))
                    w = i;
            printf("\nworst: particle %ld (id %d, type %d): %g against %g\n", w, P->id[w],
                   P->type[w], sym[k][w], f[k][w]);
            fail_msg("%s: %s differs by %g of its largest value", name, names[k], e);
        }
        free(sym[k]);
    }
    printf("\n");
    sph_sim_destroy(s);
}

static void test_dambreak2d(void **state)
{
    (void)state;
    static const char *const sets[] = {"dx=0.008", NULL};
    check_case("dambreak.json", sets);
}

static void test_laminar_sps(void **state)
{
    (void)state;
    static const char *const sets[] = {"dx=0.008",
                                       "physics.viscosity={\"type\": \"laminar\", \"nu\": 1e-6}",
                                       "physics.turbulence=\"sps\"", NULL};
    check_case("dambreak.json", sets);
}

static void test_ghost_walls(void **state)
{
    (void)state;
    static const char *const sets[] = {"dx=0.008", NULL};
    check_case("dambreak_ghost.json", sets);
}

static void test_body(void **state)
{
    (void)state;
    static const char *const sets[] = {NULL};
    check_case("water_entry.json", sets);
}

static void test_dambreak3d(void **state)
{
    (void)state;
    static const char *const sets[] = {"dx=0.06", NULL};
    check_case("dambreak3d.json", sets);
}

int main(void)
{
    sph_core_init();
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_dambreak2d),  cmocka_unit_test(test_laminar_sps),
        cmocka_unit_test(test_ghost_walls), cmocka_unit_test(test_body),
        cmocka_unit_test(test_dambreak3d),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
