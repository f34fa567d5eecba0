/*
 * Kernel library: every kernel in every dimension is normalised (by quadrature here, independent
 * of the closed forms in core/kernel/sph_kernel.c), zero outside its support, has a gradient equal
 * to a central finite difference of its value, and is symmetric. The MPS quartic kernel meets every
 * constraint Sheu et al. state. Tolerances are stated next to each check.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "sph_kernel.h"

#include <math.h>
#include <stdio.h>

/* Gauss-Legendre nodes and weights on [-1, 1], computed by Newton on P_n. */
#define GL_N 12
static double gl_x[GL_N], gl_w[GL_N];

static void gl_init(void)
{
    for (int i = 0; i < GL_N; i++) {
        double x = cos(M_PI * (i + 0.75) / (GL_N + 0.5)), dp = 0.0;
        for (int it = 0; it < 100; it++) {
            double p0 = 1.0, p1 = x;
            for (int k = 2; k <= GL_N; k++) {
                double p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
                p0 = p1;
                p1 = p2;
            }
            dp = GL_N * (x * p1 - p0) / (x * x - 1.0);
            double dx = p1 / dp;
            x -= dx;
            if (fabs(dx) < 1e-16)
                break;
        }
        gl_x[i] = x;
        gl_w[i] = 2.0 / ((1.0 - x * x) * dp * dp);
    }
}

/* Integral of r^(p) W(r) over [a, b] by composite Gauss-Legendre with m panels. */
static double integrate(const sph_kernel *k, int p, double a, double b, int m)
{
    double s = 0.0, step = (b - a) / m;
    for (int j = 0; j < m; j++) {
        double lo = a + j * step, mid = lo + 0.5 * step;
        for (int i = 0; i < GL_N; i++) {
            double r = mid + 0.5 * step * gl_x[i];
            s += gl_w[i] * 0.5 * step * pow(r, p) * sph_kernel_w(k, r);
        }
    }
    return s;
}

/* Integral of W over R^dim: sphere measure times the radial integral, split at r = h (the cubic
 * spline's joint) so each panel sees a smooth integrand. */
static double volume_integral(const sph_kernel *k)
{
    const double S = k->dim == 1 ? 2.0 : k->dim == 2 ? 2.0 * M_PI : 4.0 * M_PI;
    const double R = k->support;
    double s = integrate(k, k->dim - 1, 0.0, k->h, 200);
    s += integrate(k, k->dim - 1, k->h, R, 400);
    return S * s;
}

typedef struct {
    sph_kernel_type type;
    double kappa, radius;
} variant;

static const variant sph_variants[] = {
    {SPH_KERNEL_CUBIC_SPLINE, 2, 3},    {SPH_KERNEL_GAUSSIAN, 2, 3},
    {SPH_KERNEL_GAUSSIAN, 2, 4.5},      {SPH_KERNEL_DOUBLE_COSINE, 2.0, 3},
    {SPH_KERNEL_DOUBLE_COSINE, 2.5, 3}, {SPH_KERNEL_DOUBLE_COSINE, 3.0, 3},
    {SPH_KERNEL_WENDLAND_C2, 2, 3},     {SPH_KERNEL_RENORMALIZED_GAUSSIAN, 2, 3},
};
#define NVARIANTS (sizeof sph_variants / sizeof sph_variants[0])

static void make(sph_kernel *k, const variant *v, int dim, double h)
{
    sph_kernel_spec spec = sph_kernel_spec_default(v->type);
    spec.kappa = v->kappa;
    spec.radius = v->radius;
    sph_error err;
    assert_int_equal(sph_kernel_init(k, &spec, dim, h, &err), 0);
}

/* Normalisation to 1e-8 relative, every SPH kernel, 1D to 3D, two smoothing lengths. */
static void test_normalisation(void **state)
{
    (void)state;
    for (size_t v = 0; v < NVARIANTS; v++)
        for (int dim = 1; dim <= 3; dim++)
            for (int hi = 0; hi < 2; hi++) {
                sph_kernel k;
                make(&k, &sph_variants[v], dim, hi ? 0.013 : 1.0);
                double integral = volume_integral(&k);
                if (fabs(integral - 1.0) > 1e-8)
                    fail_msg("%s (kappa %g radius %g) in %dD: integral %.12f, want 1 +- 1e-8",
                             sph_kernel_type_name(k.type), sph_variants[v].kappa,
                             sph_variants[v].radius, dim, integral);
            }
}

/* W and dW/dr vanish at and beyond the support radius, and are positive inside it. */
static void test_compact_support(void **state)
{
    (void)state;
    for (size_t v = 0; v < NVARIANTS; v++)
        for (int dim = 1; dim <= 3; dim++) {
            sph_kernel k;
            make(&k, &sph_variants[v], dim, 0.5);
            const double outside[] = {k.support, k.support * (1 + 1e-12), 1.5 * k.support, 1e3};
            for (size_t i = 0; i < 4; i++) {
                assert_true(sph_kernel_w(&k, outside[i]) == 0.0);
                assert_true(sph_kernel_dwdr(&k, outside[i]) == 0.0);
            }
            for (int i = 0; i < 100; i++) {
                double r = k.support * (i + 0.5) / 100.0 * (1 - 1e-9);
                assert_true(sph_kernel_w(&k, r) > 0.0);
                assert_true(sph_kernel_dwdr(&k, r) <= 0.0);
            }
        }
}

/* dW/dr equals the central difference of W: relative 1e-6 of max |dW/dr|. */
static void test_gradient_fd(void **state)
{
    (void)state;
    for (size_t v = 0; v < NVARIANTS; v++)
        for (int dim = 1; dim <= 3; dim++) {
            sph_kernel k;
            make(&k, &sph_variants[v], dim, 0.7);
            double scale = 0.0;
            for (int i = 1; i < 1000; i++)
                scale = fmax(scale, fabs(sph_kernel_dwdr(&k, k.support * i / 1000.0)));
            const double eps = 1e-6 * k.h;
            for (int i = 1; i < 200; i++) {
                double r = k.support * i / 200.0;
                if (fabs(r - k.h) < 2 * eps || r + eps >= k.support)
                    continue; /* the cubic spline's joint; the gaussian's cut */
                double fd = (sph_kernel_w(&k, r + eps) - sph_kernel_w(&k, r - eps)) / (2 * eps);
                double an = sph_kernel_dwdr(&k, r);
                if (fabs(fd - an) > 1e-6 * scale)
                    fail_msg("%s %dD r/h=%g: dW/dr %.10g, finite difference %.10g",
                             sph_kernel_type_name(k.type), dim, r / k.h, an, fd);
            }
        }
}

/* W(x) = W(-x) and grad W(-x) = -grad W(x); W depends on |x| only (rotations agree to 1e-14). */
static void test_symmetry(void **state)
{
    (void)state;
    for (size_t v = 0; v < NVARIANTS; v++)
        for (int dim = 1; dim <= 3; dim++) {
            sph_kernel k;
            make(&k, &sph_variants[v], dim, 0.3);
            for (int i = 0; i < 50; i++) {
                double x[3] = {0.011 * i, -0.007 * i, 0.003 * i}, mx[3], g[3], mg[3];
                for (int d = 0; d < 3; d++)
                    mx[d] = -x[d];
                double w = sph_kernel_grad(&k, x, g), mw = sph_kernel_grad(&k, mx, mg);
                assert_true(w == mw);
                for (int d = 0; d < dim; d++)
                    assert_true(g[d] == -mg[d]);
                /* same distance along the first axis */
                double r = 0.0;
                for (int d = 0; d < dim; d++)
                    r += x[d] * x[d];
                double ax[3] = {sqrt(r), 0, 0}, ag[3];
                double aw = sph_kernel_grad(&k, ax, ag);
                assert_true(fabs(aw - w) <= 1e-14 * fabs(w) + 1e-300);
            }
        }
}

/* The constants the papers print, where they are right: Wendland beta = 7/(64 pi) in 2D, the
 * renormalised Gaussian M = 0.717082 in 2D (to its 6 printed digits), the double cosine alphas. */
static void test_printed_constants(void **state)
{
    (void)state;
    sph_kernel_spec w = sph_kernel_spec_default(SPH_KERNEL_WENDLAND_C2);
    assert_true(fabs(sph_kernel_sigma(&w, 2) - 7.0 / (64.0 * M_PI)) < 1e-15);
    sph_kernel_spec g = sph_kernel_spec_default(SPH_KERNEL_RENORMALIZED_GAUSSIAN);
    assert_true(fabs(sph_kernel_sigma(&g, 2) - 0.717082) < 5e-7);
    sph_kernel_spec dc = sph_kernel_spec_default(SPH_KERNEL_DOUBLE_COSINE);
    dc.kappa = 2.5;
    assert_true(fabs(sph_kernel_sigma(&dc, 1) - 1.0 / (6 * 2.5)) < 1e-15);
    assert_true(fabs(sph_kernel_sigma(&dc, 2) - M_PI / ((3 * M_PI * M_PI - 16) * 6.25)) < 1e-15);
    /* Yang et al. print alpha_2 = 15/(14 pi) for the cubic spline: it does not normalise (22). */
    sph_kernel_spec cs = sph_kernel_spec_default(SPH_KERNEL_CUBIC_SPLINE);
    assert_true(fabs(sph_kernel_sigma(&cs, 2) - 15.0 / (14.0 * M_PI)) > 0.1);
}

/* Sheu et al. 2011 quartic kernel (4.8): every constraint the paper states. */
static void test_sheu_quartic(void **state)
{
    (void)state;
    const double h = 0.25, re = 2 * h;
    sph_kernel k;
    variant v = {SPH_KERNEL_SHEU_QUARTIC, 2, 3};
    make(&k, &v, 2, h);
    assert_true(fabs(k.support - re) < 1e-15);
    double a, c, d, e;
    sph_kernel_sheu_coefficients(&a, &c, &d, &e);
    /* (4.3): a + b + c + d + e = 0, b + 2c + 3d + 4e = 0, a + c/3 + d/4 + e/5 = 1/2, b = 0 */
    assert_true(fabs(a + c + d + e) < 1e-12);
    assert_true(fabs(2 * c + 3 * d + 4 * e) < 1e-12);
    assert_true(fabs(a + c / 3 + d / 4 + e / 5 - 0.5) < 1e-12);
    /* a = 1 - e/15, c = -3 + 6e/5, d = 2 - 32e/15 */
    assert_true(fabs(a - (1 - e / 15)) < 1e-12);
    assert_true(fabs(c - (-3 + 6 * e / 5)) < 1e-12);
    assert_true(fabs(d - (2 - 32 * e / 15)) < 1e-12);
    /* (4.7) */
    assert_true(fabs(3 * a + (2 - 0.25) * c + (sqrt(2) - 0.125) * d + (1 - 1.0 / 16) * e) < 1e-12);
    /* w(re) = 0, w'(re) = 0, w'(0) = 0 (evaluated just inside re) */
    const double in = re * (1 - 1e-12);
    assert_true(fabs(sph_kernel_w(&k, in)) < 1e-9 / re);
    assert_true(fabs(sph_kernel_dwdr(&k, in)) < 1e-9 / (re * re));
    assert_true(fabs(sph_kernel_dwdr(&k, 0.0)) == 0.0);
    /* (4.1)/(4.10): integral over [-re, re] is 1, i.e. over [0, re] is 1/2 */
    double half = integrate(&k, 0, 0.0, re, 400);
    assert_true(fabs(half - 0.5) < 1e-12);
    /* (4.9): w(sqrt2 h) = w(h) / 4 */
    double w1 = sph_kernel_w(&k, h), w2 = sph_kernel_w(&k, sqrt(2.0) * h);
    assert_true(fabs(w2 - 0.25 * w1) < 1e-12 * w1);
    /* maximum at r = 0 (the paper's point against re/r - 1) */
    for (int i = 1; i < 100; i++)
        assert_true(sph_kernel_w(&k, re * i / 100.0) < sph_kernel_w(&k, 0.0));
}

/* Koshizuka & Oka 1996: w = re/r - 1 for r < re, with re = 2h. */
static void test_koshizuka(void **state)
{
    (void)state;
    const double h = 0.1, re = 0.2;
    sph_kernel k;
    variant v = {SPH_KERNEL_KOSHIZUKA, 2, 3};
    make(&k, &v, 2, h);
    for (int i = 1; i < 100; i++) {
        double r = re * i / 100.0;
        assert_true(fabs(sph_kernel_w(&k, r) - (re / r - 1.0)) < 1e-12 * (re / r));
        assert_true(fabs(sph_kernel_dwdr(&k, r) + re / (r * r)) < 1e-12 * re / (r * r));
    }
    assert_true(sph_kernel_w(&k, re) == 0.0);
}

/* Bad parameters are refused with the field named. */
static void test_init_errors(void **state)
{
    (void)state;
    sph_kernel k;
    sph_error err;
    sph_kernel_spec s = sph_kernel_spec_default(SPH_KERNEL_DOUBLE_COSINE);
    s.kappa = 3.5;
    assert_int_equal(sph_kernel_init(&k, &s, 2, 0.1, &err), SPH_ERR_INVALID);
    assert_string_equal(err.path, "/kappa");
    s = sph_kernel_spec_default(SPH_KERNEL_GAUSSIAN);
    s.radius = 1.0;
    assert_int_equal(sph_kernel_init(&k, &s, 2, 0.1, &err), SPH_ERR_INVALID);
    assert_string_equal(err.path, "/radius");
    s = sph_kernel_spec_default(SPH_KERNEL_WENDLAND_C2);
    assert_int_equal(sph_kernel_init(&k, &s, 4, 0.1, &err), SPH_ERR_INVALID);
    assert_int_equal(sph_kernel_init(&k, &s, 2, -1.0, &err), SPH_ERR_INVALID);
    assert_int_equal(sph_kernel_init(&k, &s, 2, NAN, &err), SPH_ERR_INVALID);
    assert_int_equal(sph_kernel_type_from_name("wendland_c2"), SPH_KERNEL_WENDLAND_C2);
    assert_int_equal(sph_kernel_type_from_name("wendland"), -1);
}

/* The per-type inlined path (SPH_KERNEL_DISPATCH) gives the same numbers as the generic switch. */
static double sum_t(sph_kernel_type t, const sph_kernel *k)
{
    double s = 0.0;
    for (int i = 0; i < 1000; i++) {
        double d;
        s += sph_kernel_eval_t(t, k, k->support * i / 1000.0, &d) + d;
    }
    return s;
}

static void test_dispatch(void **state)
{
    (void)state;
    for (size_t v = 0; v < NVARIANTS; v++) {
        sph_kernel k;
        make(&k, &sph_variants[v], 3, 0.2);
        double a = 0.0, b = 0.0;
#define CALL(T) a = sum_t(T, &k)
        SPH_KERNEL_DISPATCH(k.type, CALL);
#undef CALL
        for (int i = 0; i < 1000; i++) {
            double r = k.support * i / 1000.0;
            b += sph_kernel_w(&k, r) + sph_kernel_dwdr(&k, r);
        }
        assert_true(a == b);
    }
}

int main(void)
{
    gl_init();
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_normalisation),     cmocka_unit_test(test_compact_support),
        cmocka_unit_test(test_gradient_fd),       cmocka_unit_test(test_symmetry),
        cmocka_unit_test(test_printed_constants), cmocka_unit_test(test_sheu_quartic),
        cmocka_unit_test(test_koshizuka),         cmocka_unit_test(test_init_errors),
        cmocka_unit_test(test_dispatch),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
