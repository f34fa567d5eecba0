/*
 * The radial particle density function (core/sph_rpdf.c):
 *   - a square lattice of 40 x 40 particles: the pairs fall at r = dx, sqrt(2) dx, 2 dx, ...
 *     and nowhere else, with exactly the counts of the lattice (2 n (n - 1) at dx, 2 (n - 1)^2
 *     at sqrt(2) dx), and the density of the sqrt(2) dx ring is that count over the ring's
 *     expected share;
 *   - particles moved onto others (clustering) show in the first bin;
 *   - the cell-list pair loop against an all-pairs one (2D and 3D, scattered particles, some
 *     of them walls): the same counts in every bin;
 *   - the sim's view (fluid only: walls and ghosts never count) and the argument errors.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "sph_particles.h"
#include "sph_rpdf.h"
#include "sph_sim.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define N  40
#define NB 42 /* bins of h/21: no lattice distance below 2 dx on a bin edge */

static double x[N * N], y[N * N];
static unsigned char type[N * N];

static sph_rpdf_input lattice(double dx)
{
    for (int i = 0; i < N; i++)
        for (int j = 0; j < N; j++) {
            x[i * N + j] = (i + 0.5) * dx;
            y[i * N + j] = (j + 0.5) * dx;
            type[i * N + j] = SPH_FLUID;
        }
    const sph_rpdf_input in = {2, N * N, {x, y, NULL}, type, 2.0 * dx, dx};
    return in;
}

static void test_lattice(void **state)
{
    (void)state;
    const double dx = 0.01;
    sph_rpdf_input in = lattice(dx);
    double q[NB], count[NB], dens[NB];
    assert_int_equal(sph_rpdf_compute(&in, 2.0, NB, q, count, dens, NULL), 0);
    /* r = dx is q = 0.5, bin 10; sqrt(2) dx is q = 0.707, bin 14 */
    assert_true(fabs(q[10] - 0.5) < 1e-12);
    const double at_dx = 2.0 * N * (N - 1), at_diag = 2.0 * (N - 1) * (N - 1);
    if (count[10] != at_dx || count[14] != at_diag)
        fail_msg("counts %g at dx (want %g), %g at sqrt2 dx (want %g)", count[10], at_dx, count[14],
                 at_diag);
    for (int b = 0; b < 10; b++)
        assert_true(count[b] == 0.0); /* nothing closer than dx */
    assert_true(count[12] == 0.0 && count[16] == 0.0);
    const double ring = M_PI * (pow(15.0 / 21.0 * 0.02, 2) - pow(14.0 / 21.0 * 0.02, 2));
    const double want = 2.0 * at_diag / (N * N / (dx * dx) * ring);
    assert_true(fabs(dens[14] - want) < 1e-9 * want);
    /* clustering: ten particles put next to their neighbours show at q < 0.1 */
    for (int k = 0; k < 10; k++) {
        x[k * N + 1] = x[k * N] + 0.001 * dx;
        y[k * N + 1] = y[k * N];
    }
    assert_int_equal(sph_rpdf_compute(&in, 2.0, NB, q, count, dens, NULL), 0);
    assert_true(count[0] == 10.0);
}

static void test_errors(void **state)
{
    (void)state;
    sph_rpdf_input in = lattice(0.01);
    double q[NB], count[NB], dens[NB];
    sph_error err;
    assert_int_equal(sph_rpdf_compute(&in, 2.0, 0, q, count, dens, &err), SPH_ERR_INVALID);
    assert_string_equal(err.path, "/rpdf/bins");
    assert_int_equal(sph_rpdf_compute(&in, -1.0, NB, q, count, dens, &err), SPH_ERR_INVALID);
    assert_string_equal(err.path, "/rpdf/qmax");
}

/* The obvious loop: every pair of fluid particles once, r^2 summed over the axes in order. */
static void all_pairs(const sph_rpdf_input *in, double qmax, int nbins, double *count)
{
    const double rmax = qmax * in->h, dq = qmax / nbins;
    for (int b = 0; b < nbins; b++)
        count[b] = 0.0;
    for (long i = 0; i < in->n; i++)
        for (long j = i + 1; j < in->n; j++) {
            if (in->type[i] != SPH_FLUID || in->type[j] != SPH_FLUID)
                continue;
            double r2 = 0.0;
            for (int d = 0; d < in->dim; d++)
                r2 += (in->pos[d][i] - in->pos[d][j]) * (in->pos[d][i] - in->pos[d][j]);
            if (r2 < rmax * rmax) {
                const long b = (long)(sqrt(r2) * (1.0 / (dq * in->h)));
                count[b < nbins ? b : nbins - 1] += 1.0;
            }
        }
}

static void test_all_pairs(void **state)
{
    (void)state;
    enum { M = 5000 }; /* above SPH_OMP_MIN: the threads share the loop */
    static double px[M], py[M], pz[M];
    static unsigned char pt[M];
    srand(7);
    for (int dim = 2; dim <= 3; dim++) {
        /* a cloud 0.1 m wide (thinner in z), denser in one corner, a tenth of it walls */
        for (int i = 0; i < M; i++) {
            const double u = (double)rand() / RAND_MAX, v = (double)rand() / RAND_MAX;
            px[i] = i % 3 ? 0.1 * u : 0.02 * u;
            py[i] = i % 3 ? 0.1 * v : 0.02 * v;
            pz[i] = 0.01 * rand() / RAND_MAX;
            pt[i] = i % 10 == 0 ? SPH_BOUNDARY : SPH_FLUID;
        }
        const sph_rpdf_input in = {dim, M, {px, py, dim == 3 ? pz : NULL}, pt, 0.004, 0.0025};
        double q[NB], count[NB], dens[NB], want[NB];
        for (int k = 0; k < 2; k++) {
            const double qmax = k ? 3.5 : 2.0;
            assert_int_equal(sph_rpdf_compute(&in, qmax, NB, q, count, dens, NULL), 0);
            all_pairs(&in, qmax, NB, want);
            double total = 0.0;
            for (int b = 0; b < NB; b++) {
                if (count[b] != want[b])
                    fail_msg("%dD, qmax %g: %g pairs in bin %d, all pairs give %g", dim, qmax,
                             count[b], b, want[b]);
                total += count[b];
            }
            assert_true(total > 1000.0); /* a test with pairs in it */
        }
    }
}

/* Through the sim: walls (dynamic particles) do not count, and the ghosts are never there. */
static void test_sim(void **state)
{
    (void)state;
    for (int ghost = 0; ghost < 2; ghost++) {
        sph_config c = sph_config_default();
        c.dx = 0.01;
        c.h_over_dx = 2.0;
        c.domain = (sph_box){{0, 0, 0}, {0.2, 0.3, 0}};
        c.nfluid = 1;
        c.fluid[0] = (sph_box){{0, 0, 0}, {0.2, 0.1, 0}}; /* 20 x 10 */
        c.boundary = ghost ? SPH_BOUNDARY_GHOST : SPH_BOUNDARY_DYNAMIC;
        c.has_tank = 1;
        c.tank = (sph_box){{0, 0, 0}, {0.2, 0.3, 0}};
        c.t_end = 1.0;
        sph_error err;
        sph_sim *s = sph_sim_create(&c, &err);
        assert_non_null(s);
        double q[NB], count[NB], dens[NB];
        assert_int_equal(sph_sim_rpdf(s, 2.0, NB, q, count, dens, &err), 0);
        if (count[10] != 2.0 * 20 * 10 - 20 - 10)
            fail_msg("%s walls: %g pairs at dx, want %d (the fluid's alone)",
                     ghost ? "ghost" : "dynamic", count[10], 2 * 20 * 10 - 30);
        sph_sim_destroy(s);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_lattice),
        cmocka_unit_test(test_errors),
        cmocka_unit_test(test_all_pairs),
        cmocka_unit_test(test_sim),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
