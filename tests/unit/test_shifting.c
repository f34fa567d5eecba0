/*
 * Particle shifting's physics (core/wcsph/sph_shifting.h: sph_shifting_pair,
 * sph_shifting_displacement) on square (2D) and cubic (3D) lattices of spacing dx, the Wendland
 * C2 kernel at h = 1.414 dx (the dam break's), every lattice neighbour within the support summed
 * by brute force:
 *   - a particle of a uniform lattice far from the surface: grad C zero to round-off, so no
 *     shift (below 1e-12 dx at |v| dt = dx), and div r close to the dimension;
 *   - a particle displaced from its lattice site: shifted back towards it (dr . offset < 0,
 *     within 30 degrees of -offset), down the concentration's gradient;
 *   - a particle of the top row of a half lattice (the free surface above it): div r below the
 *     threshold, no shift at all, though grad C points into the fluid along the surface normal
 *     (without the free-surface treatment it would be pushed out of the water).
 * And the step: the 2D dam break with shifting on moves its fluid differently from the same run
 * without (the pass is called).
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "sph_kernel.h"
#include "sph_shifting.h"
#include "sph_sim.h"
#include "unit_case.h"

#include <math.h>
#include <string.h>

#define DX  0.01
#define RHO 1000.0

typedef struct lattice {
    int dim;
    sph_kernel k;
    double h, m, support;
} lattice;

static lattice lattice_make(int dim)
{
    lattice L;
    memset(&L, 0, sizeof L);
    L.dim = dim;
    L.h = 1.414 * DX;
    const sph_kernel_spec spec = sph_kernel_spec_default(SPH_KERNEL_WENDLAND_C2);
    sph_error err;
    assert_int_equal(sph_kernel_init(&L.k, &spec, dim, L.h, &err), 0);
    L.support = L.k.support;
    L.m = RHO * pow(DX, dim);
    return L;
}

/* The sums of a particle at xa (in dx) against the lattice sites (i, j, k) dx, |i|, |j|, |k| <=
 * 6, with j <= top (the rows above it empty), the site at the origin left out when skip0. */
static sph_shift_sum sums(const lattice *L, const double *xa, int top, int skip0)
{
    sph_shift_sum s = {{0.0, 0.0, 0.0}, 0.0};
    const int kz = L->dim == 3 ? 6 : 0;
    for (int i = -6; i <= 6; i++)
        for (int j = -6; j <= (top < 6 ? top : 6); j++)
            for (int k = -kz; k <= kz; k++) {
                if (skip0 && i == 0 && j == 0 && k == 0)
                    continue;
                double d[3] = {(xa[0] - i) * DX, (xa[1] - j) * DX, (xa[2] - k) * DX};
                if (L->dim == 2)
                    d[2] = 0.0;
                const double r2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
                const double r = sqrt(r2);
                if (r >= L->support || r == 0.0)
                    continue;
                double dwdr;
                (void)sph_kernel_eval_t(SPH_KERNEL_WENDLAND_C2, &L->k, r, &dwdr);
                sph_shifting_pair(L->dim, d, r2, dwdr / r, L->m / RHO, &s);
            }
    return s;
}

/* |v| dt = dx, A = -2, the dimension's threshold. */
static sph_shift_const consts(const lattice *L, double tfs)
{
    const sph_shift_const k = {.ahdt = -2.0 * L->h * DX, .tfs = tfs, .maxd = 0.1 * DX};
    return k;
}

static void uniform(int dim)
{
    const lattice L = lattice_make(dim);
    const double xa[3] = {0.0, 0.0, 0.0};
    const sph_shift_sum s = sums(&L, xa, 6, 1);
    const sph_shift_const k = consts(&L, dim == 3 ? 2.75 : 1.5);
    double dr[3] = {0.0, 0.0, 0.0};
    sph_shifting_displacement(dim, &k, &s, 1.0, dr);
    for (int c = 0; c < dim; c++)
        if (!(fabs(dr[c]) < 1e-12 * DX))
            fail_msg("%dD uniform lattice: dr[%d] = %g m", dim, c, dr[c]);
    if (!(fabs(s.div - dim) < 0.05 * dim))
        fail_msg("%dD uniform lattice: div r = %.6f, expected about %d", dim, s.div, dim);
}

static void test_uniform_no_shift(void **state)
{
    (void)state;
    uniform(2);
    uniform(3);
}

static void displaced(int dim, const double *off)
{
    const lattice L = lattice_make(dim);
    const sph_shift_sum s = sums(&L, off, 6, 1); /* its own site is empty */
    const sph_shift_const k = consts(&L, dim == 3 ? 2.75 : 1.5);
    double dr[3] = {0.0, 0.0, 0.0};
    sph_shifting_displacement(dim, &k, &s, 1.0, dr);
    double dot = 0.0, n2 = 0.0, o2 = 0.0;
    for (int c = 0; c < dim; c++) {
        dot += dr[c] * off[c];
        n2 += dr[c] * dr[c];
        o2 += off[c] * off[c];
    }
    const double cosang = dot / sqrt(n2 * o2);
    if (!(n2 > 0.0 && cosang < -0.8660254))
        fail_msg("%dD, offset (%g, %g, %g) dx: dr (%g, %g, %g) m, cos to the offset %g", dim,
                 off[0], off[1], off[2], dr[0], dr[1], dr[2], cosang);
}

static void test_displaced_back(void **state)
{
    (void)state;
    const double offs[][3] = {{0.2, 0.0, 0.0}, {0.0, -0.25, 0.0}, {0.15, 0.1, 0.0}};
    for (size_t q = 0; q < sizeof offs / sizeof offs[0]; q++)
        displaced(2, offs[q]);
    const double off3[][3] = {{0.2, 0.0, 0.0}, {0.1, -0.1, 0.15}};
    for (size_t q = 0; q < sizeof off3 / sizeof off3[0]; q++)
        displaced(3, off3[q]);
}

static void surface(int dim)
{
    const lattice L = lattice_make(dim);
    /* the top row, slightly off its site along the surface (a tangential gradient too) */
    const double xa[3] = {0.1, 0.0, 0.0};
    const sph_shift_sum s = sums(&L, xa, 0, 0);
    const double tfs = dim == 3 ? 2.75 : 1.5;
    if (!(s.div < tfs))
        fail_msg("%dD top row: div r = %g, not below the threshold %g", dim, s.div, tfs);
    assert_true(s.g[1] < 0.0); /* grad C points down, into the fluid */
    const sph_shift_const k = consts(&L, tfs);
    double dr[3] = {1.0, 1.0, 1.0};
    sph_shifting_displacement(dim, &k, &s, 1.0, dr);
    for (int c = 0; c < dim; c++)
        if (dr[c] != 0.0)
            fail_msg("%dD top row: dr[%d] = %g m, expected none", dim, c, dr[c]);
    /* without the treatment: pushed up, out of the water, along the normal */
    const sph_shift_const k0 = consts(&L, 0.0);
    sph_shifting_displacement(dim, &k0, &s, 1.0, dr);
    assert_true(dr[1] > 0.0);
    /* two rows down (div r at the bulk's D): shifted as in the bulk */
    const double xb[3] = {0.1, -2.0, 0.0};
    const sph_shift_sum sb = sums(&L, xb, 0, 0);
    assert_true(sb.div > tfs);
}

static void test_free_surface_no_normal_shift(void **state)
{
    (void)state;
    surface(2);
    surface(3);
}

/* The step: shifting moves the 2D dam break's fluid (dx 0.01, 200 steps) off the run without
 * it. */
static void test_step(void **state)
{
    (void)state;
    static const char *const sets[] = {"dx=0.01", NULL};
    sph_config cfg = load_case("dambreak.json", sets);
    sph_error err;
    sph_sim *a = sph_sim_create(&cfg, &err);
    assert_non_null(a);
    cfg.shifting.type = SPH_SHIFT_LIND;
    sph_sim *b = sph_sim_create(&cfg, &err);
    assert_non_null(b);
    assert_int_equal(sph_sim_step(a, 200, &err), 0);
    assert_int_equal(sph_sim_step(b, 200, &err), 0);
    sph_particle_view va, vb;
    sph_sim_particles(a, &va);
    sph_sim_particles(b, &vb);
    assert_int_equal(va.n, vb.n);
    long moved = 0;
    for (long i = 0; i < va.n; i++)
        moved += va.pos[0][i] != vb.pos[0][i] || va.pos[1][i] != vb.pos[1][i];
    assert_true(moved > 0);
    sph_sim_destroy(a);
    sph_sim_destroy(b);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_uniform_no_shift),
        cmocka_unit_test(test_displaced_back),
        cmocka_unit_test(test_free_surface_no_normal_shift),
        cmocka_unit_test(test_step),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
