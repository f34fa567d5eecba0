/*
 * sphd_reflect (server/sphd_reflect.h): the incident and reflected waves of a flume from its
 * gauges. On series made from linear theory's standing pattern, an incident wave of height Hi and
 * a reflected one of Kr Hi with a phase of their own, each gauge offset by a still-water level:
 *   - three gauges, sampled every 20 ms over 7.3 periods (not a whole number): Hi and Kr to 1e-9;
 *   - two gauges a fifth of a wavelength apart (Goda & Suzuki): the same;
 *   - with noise of a tenth of the reflected height on each sample: Kr within 0.01;
 *   - no reflection: Kr below 1e-9; full reflection (a standing wave, Kr = 1): 1 to 1e-9;
 *   - refused: one gauge, two half a wavelength apart (cond 0), a window shorter than a period,
 *     a window with fewer than 8 samples.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "sphd_reflect.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#define NS 2000 /* samples */

typedef struct wave {
    double hi, kr;   /* incident height [m], reflection coefficient [-] */
    double omega, k; /* [rad/s], [1/m] */
    double phi, psi; /* the incident and reflected phases [rad] */
    double level;    /* still-water offset of the series [m] */
    double noise;    /* amplitude of uniform noise on each sample [m] */
} wave;

/* eta at gauge x: Hi/2 cos(omega t - k x + phi) + Kr Hi/2 cos(omega t + k x + psi) + level. */
static void series(const wave *w, const double *x, int m, double *t, double (*eta)[NS])
{
    srand(7);
    for (long i = 0; i < NS; i++) {
        t[i] = 3.0 + 0.02 * (double)i;
        for (int j = 0; j < m; j++) {
            const double u = (double)rand() / RAND_MAX * 2.0 - 1.0;
            eta[j][i] = 0.5 * w->hi * cos(w->omega * t[i] - w->k * x[j] + w->phi) +
                        0.5 * w->kr * w->hi * cos(w->omega * t[i] + w->k * x[j] + w->psi) +
                        w->level + w->noise * u;
        }
    }
}

/* The analysis of w at gauges x over [t0, t1]: its return code, *out. */
static int analyse(const wave *w, const double *x, int m, double t0, double t1,
                   sphd_reflect_out *out)
{
    static double t[NS], eta[4][NS];
    series(w, x, m, t, eta);
    const long cols[4] = {0, NS, 2 * NS, 3 * NS}; /* each gauge's series in a row of its own */
    return sphd_reflect(t, &eta[0][0], 1, cols, x, m, NS, t0, t1, w->omega, w->k, out);
}

/* kd = 1.2 in d = 0.4 m: the wave flume's waves (cases/wave_flume.json). */
static wave flume(double kr)
{
    const double k = 1.2 / 0.4, g = 9.81;
    const wave w = {.hi = 0.05,
                    .kr = kr,
                    .omega = sqrt(g * k * tanh(1.2)),
                    .k = k,
                    .phi = 0.4,
                    .psi = -1.3,
                    .level = 0.4};
    return w;
}

static void test_three_gauges(void **state)
{
    (void)state;
    const wave w = flume(0.2);
    const double L = 2.0 * M_PI / w.k, T = 2.0 * M_PI / w.omega;
    const double x[3] = {4.0, 4.0 + 0.2 * L, 4.0 + 0.45 * L};
    sphd_reflect_out o;
    assert_int_equal(analyse(&w, x, 3, 5.0, 5.0 + 7.3 * T, &o), 0);
    printf("three gauges: Hi %.9f (0.05), Kr %.9f (0.2), cond %.3f\n", o.hi, o.kr, o.cond);
    assert_true(fabs(o.hi - 0.05) < 1e-9 && fabs(o.kr - 0.2) < 1e-9);
    assert_true(fabs(o.hr - 0.01) < 1e-9);
}

static void test_two_gauges(void **state)
{
    (void)state;
    const wave w = flume(0.35);
    const double L = 2.0 * M_PI / w.k, T = 2.0 * M_PI / w.omega;
    const double x[2] = {3.1, 3.1 + 0.2 * L};
    sphd_reflect_out o;
    assert_int_equal(analyse(&w, x, 2, 4.0, 4.0 + 5.0 * T, &o), 0);
    printf("two gauges: Hi %.9f, Kr %.9f, cond %.3f (sin^2(0.4 pi) = %.3f)\n", o.hi, o.kr, o.cond,
           pow(sin(0.4 * M_PI), 2));
    assert_true(fabs(o.hi - 0.05) < 1e-9 && fabs(o.kr - 0.35) < 1e-9);
    assert_true(fabs(o.cond - pow(sin(0.4 * M_PI), 2)) < 1e-12);
}

static void test_noise_and_limits(void **state)
{
    (void)state;
    wave w = flume(0.1);
    const double L = 2.0 * M_PI / w.k, T = 2.0 * M_PI / w.omega;
    const double x[3] = {4.0, 4.0 + 0.2 * L, 4.0 + 0.45 * L};
    sphd_reflect_out o;
    w.noise = 0.1 * w.kr * w.hi;
    assert_int_equal(analyse(&w, x, 3, 5.0, 5.0 + 10.0 * T, &o), 0);
    printf("with noise: Kr %.5f (0.1)\n", o.kr);
    assert_true(fabs(o.kr - 0.1) < 0.01);
    w = flume(0.0);
    assert_int_equal(analyse(&w, x, 3, 5.0, 5.0 + 4.0 * T, &o), 0);
    assert_true(o.kr < 1e-9);
    w = flume(1.0);
    assert_int_equal(analyse(&w, x, 3, 5.0, 5.0 + 4.0 * T, &o), 0);
    printf("standing wave: Kr %.9f\n", o.kr);
    assert_true(fabs(o.kr - 1.0) < 1e-9);
}

static void test_refused(void **state)
{
    (void)state;
    const wave w = flume(0.2);
    const double L = 2.0 * M_PI / w.k, T = 2.0 * M_PI / w.omega;
    sphd_reflect_out o;
    const double one[1] = {4.0};
    assert_int_equal(analyse(&w, one, 1, 5.0, 5.0 + 4.0 * T, &o), -1);
    const double half[2] = {4.0, 4.0 + 0.5 * L}; /* the split is singular */
    assert_int_equal(analyse(&w, half, 2, 5.0, 5.0 + 4.0 * T, &o), -1);
    assert_true(o.cond < 1e-12);
    const double near[2] = {4.0, 4.0 + 0.02 * L}; /* Goda & Suzuki's range starts at 0.05 L */
    assert_int_equal(analyse(&w, near, 2, 5.0, 5.0 + 4.0 * T, &o), -1);
    assert_true(o.cond > 0.0 && o.cond < SPHD_REFLECT_MIN_COND);
    const double x[2] = {4.0, 4.0 + 0.25 * L};
    assert_int_equal(analyse(&w, x, 2, 5.0, 5.0 + 0.5 * T, &o), -1); /* shorter than T */
    assert_int_equal(analyse(&w, x, 2, 5.0, 5.0 + 4.0 * T, &o), 0);
    assert_true(fabs(o.cond - 1.0) < 1e-12);
    /* a window past the series: no samples */
    assert_int_equal(analyse(&w, x, 2, 100.0, 100.0 + 4.0 * T, &o), -1);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_three_gauges),
        cmocka_unit_test(test_two_gauges),
        cmocka_unit_test(test_noise_and_limits),
        cmocka_unit_test(test_refused),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
