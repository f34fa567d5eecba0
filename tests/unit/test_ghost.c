/*
 * Ghost (mirror) particles for free-slip walls (core/boundary/sph_wall_ghost.c):
 *   - the builder against hand-made mirrors (positions, free-slip velocities, hydrostatic
 *     pressure across the wall, corners as double mirrors, nothing for particles far from walls);
 *   - the configuration errors, at their JSON paths;
 *   - the reflection of a particle that crossed a wall;
 *   - the cell-list force loops with ghosts against the obvious all-pairs sum over the fluid and
 *     explicit mirror images built here, independently of the builder (tolerance 1e-10 of the
 *     largest value), with the artificial, Monaghan and laminar terms and delta-SPH;
 *   - ghosts never reach what a client sees (particle counts, views, diagnostics).
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "sph_wcsph.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* cmocka 1.1 has no assert_double_equal */
static void close_to(double got, double want, double tol, const char *what)
{
    if (!(fabs(got - want) <= tol))
        fail_msg("%s: %.17g, expected %.17g within %g", what, got, want, tol);
}
#define assert_double_equal(a, b, tol) close_to((a), (b), (tol), #a)

static sph_config tank_config(void)
{
    sph_config c = sph_config_default();
    c.dx = 0.01;
    c.h_over_dx = 2.0; /* support 0.04 m */
    c.domain = (sph_box){{0, 0, 0}, {0.2, 0.3, 0}};
    c.nfluid = 1;
    c.fluid[0] = (sph_box){{0, 0, 0}, {0.2, 0.15, 0}}; /* 20 x 15 particles */
    c.boundary = SPH_BOUNDARY_GHOST;
    c.has_tank = 1;
    c.tank = (sph_box){{0, 0, 0}, {0.2, 0.3, 0}};
    c.c0 = 20.0;
    c.t_end = 1.0;
    return c;
}

static void test_builder(void **state)
{
    (void)state;
    sph_config c = tank_config();
    sph_wall_ghost w;
    sph_error err;
    assert_int_equal(sph_wall_ghost_init(&w, &c, 0.04, &err), 0);
    assert_int_equal(w.nwalls, 3);
    /* A near the left wall, B in the bottom-left corner, C far from every wall, D in the
     * bottom-right corner, E near the bottom only, F boundary-typed (never mirrored) */
    double x[32] = {0.005, 0.015, 0.1, 0.19, 0.1, 0.005};
    double y[32] = {0.10, 0.02, 0.10, 0.035, 0.01, 0.10};
    double vx[32] = {0.3, -0.2, 1.0, 0.5, 0.1, 1.0};
    double vy[32] = {0.4, -0.1, 1.0, 0.7, -0.2, 1.0};
    double rho[32] = {1001.0, 1003.0, 1000.0, 1002.0, 1004.0, 1000.0};
    unsigned char type[32] = {SPH_FLUID, SPH_FLUID, SPH_FLUID, SPH_FLUID, SPH_FLUID, SPH_BOUNDARY};
    int id[32] = {10, 11, 12, 13, 14, 15};
    const sph_ghost_arrays a = {{x, y, NULL}, {vx, vy, NULL}, rho, type, id, {NULL}, NULL, 0};
    /* no room: the count alone (nothing written); too little room: nothing written past cap,
     * the count still told */
    assert_int_equal(sph_wall_ghost_build(&w, &c, &a, 6, 6), 1 + 3 + 0 + 3 + 1);
    assert_true(x[6] == 0.0 && rho[6] == 0.0);
    assert_int_equal(sph_wall_ghost_build(&w, &c, &a, 6, 8), 8);
    assert_true(x[8] == 0.0 && rho[8] == 0.0);
    assert_int_equal(sph_wall_ghost_build(&w, &c, &a, 6, 32), 8);
    /* every ghost is an image of its particle across one wall or a corner's two */
    const double g = 9.81, c2 = c.c0 * c.c0;
    int seen_corner = 0;
    for (int k = 6; k < 14; k++) {
        assert_int_equal(type[k], SPH_GHOST);
        const int i = id[k] - 10;
        const int mx = fabs(x[k] - x[i]) > 1e-15, my = fabs(y[k] - y[i]) > 1e-15;
        assert_true(mx || my);
        if (mx) { /* across the left (x = 0) or the right (x = 0.2) wall */
            const double wall = x[i] < 0.1 ? 0.0 : 0.2;
            assert_double_equal(x[k], 2.0 * wall - x[i], 1e-15);
            assert_double_equal(vx[k], -vx[i], 0.0);
        } else {
            assert_double_equal(vx[k], vx[i], 0.0); /* tangential kept */
        }
        if (my) { /* across the bottom */
            assert_double_equal(y[k], -y[i], 1e-15);
            assert_double_equal(vy[k], -vy[i], 0.0);
        } else {
            assert_double_equal(vy[k], vy[i], 0.0);
        }
        seen_corner += mx && my;
        /* p_g = p_f + rho0 g (y_f - y_g): linear EOS, so rho_g - rho_f = rho0 g dy / c0^2 */
        const double want = rho[i] + c.rho0 * g * (y[i] - y[k]) / c2;
        assert_double_equal(rho[k], want, 1e-9);
    }
    assert_int_equal(seen_corner, 2);
    /* the Tait EOS: the ghost's pressure is still the hydrostatic one */
    c.eos = SPH_EOS_TAIT;
    assert_int_equal(sph_wall_ghost_build(&w, &c, &a, 6, 32), 8);
    for (int k = 6; k < 14; k++) {
        const int i = id[k] - 10;
        const double dp = sph_eos_pressure(&c, rho[k]) - sph_eos_pressure(&c, rho[i]);
        assert_double_equal(dp, c.rho0 * g * (y[i] - y[k]), 1e-6);
    }
}

static void expect_error(sph_config c, const char *path)
{
    sph_error err;
    sph_error_clear(&err);
    sph_sim *s = sph_sim_create(&c, &err);
    assert_null(s);
    assert_int_equal(err.code, SPH_ERR_INVALID);
    if (strcmp(err.path, path) != 0)
        fail_msg("path %s, expected %s (%s)", err.path, path, err.message);
}

static void test_errors(void **state)
{
    (void)state;
    sph_config c = tank_config();
    c.has_tank = 0;
    expect_error(c, "/boundary/tank");
    c = tank_config();
    c.tank.max[0] = c.tank.min[0];
    expect_error(c, "/boundary/tank/max");
    c = tank_config();
    c.gravity[0] = 1.0;
    expect_error(c, "/physics/gravity");
    c = tank_config();
    c.fluid[0].max[0] = 0.3;
    expect_error(c, "/fluid/0/box");
}

static void test_reflect(void **state)
{
    (void)state;
    sph_config c = tank_config();
    sph_wall_ghost w;
    assert_int_equal(sph_wall_ghost_init(&w, &c, 0.04, NULL), 0);
    double x[2] = {-0.001, -0.002}, v[2] = {-1.0, -2.0};
    sph_wall_ghost_reflect(&w, x, v);
    assert_double_equal(x[0], 0.001, 1e-15);
    assert_double_equal(x[1], 0.002, 1e-15);
    assert_double_equal(v[0], 1.0, 0.0);
    assert_double_equal(v[1], 2.0, 0.0);
    double x2[2] = {0.203, 0.1}, v2[2] = {0.5, 0.0};
    sph_wall_ghost_reflect(&w, x2, v2);
    assert_double_equal(x2[0], 0.197, 1e-15);
    assert_double_equal(v2[0], -0.5, 0.0);
    double x3[2] = {0.1, 0.1}, v3[2] = {-3.0, -3.0}; /* inside: untouched */
    sph_wall_ghost_reflect(&w, x3, v3);
    assert_double_equal(x3[0], 0.1, 0.0);
    assert_double_equal(v3[0], -3.0, 0.0);
}

static double urand(unsigned *s)
{
    *s = *s * 1103515245u + 12345u;
    return ((*s >> 8) & 0xffffff) / (double)0x1000000;
}

#define NMAX 2048

/* The reference: fluid particles (creation order) and their mirrors, built here. */
typedef struct cloud {
    long n, nf;
    double x[NMAX], y[NMAX], vx[NMAX], vy[NMAX], rho[NMAX];
    double ax[NMAX], ay[NMAX], drho[NMAX];
} cloud;

static void mirror(cloud *C, const sph_config *c, double support)
{
    const double g = -c->gravity[1];
    const long nf = C->nf;
    long n = nf;
    for (long i = 0; i < nf; i++) {
        const double dl = C->x[i] - c->tank.min[0], dr = c->tank.max[0] - C->x[i];
        const double db = C->y[i] - c->tank.min[1];
        const int nx = dl < support ? -1 : dr < support ? 1 : 0; /* the tank is > 2 supports */
        const int ny = db < support;
        for (int kx = 0; kx <= (nx != 0); kx++)
            for (int ky = 0; ky <= ny; ky++) {
                if (!kx && !ky)
                    continue;
                double x = C->x[i], y = C->y[i], vx = C->vx[i], vy = C->vy[i];
                if (kx) {
                    x = nx < 0 ? 2.0 * c->tank.min[0] - x : 2.0 * c->tank.max[0] - x;
                    vx = -vx;
                }
                if (ky) {
                    y = 2.0 * c->tank.min[1] - y;
                    vy = -vy;
                }
                const double p =
                    c->c0 * c->c0 * (C->rho[i] - c->rho0) + c->rho0 * g * (C->y[i] - y);
                assert_true(n < NMAX);
                C->x[n] = x;
                C->y[n] = y;
                C->vx[n] = vx;
                C->vy[n] = vy;
                C->rho[n] = c->rho0 + p / (c->c0 * c->c0);
                n++;
            }
    }
    C->n = n;
}

/* Accelerations and density rates of the fluid particles by the obvious sum over every fluid
 * particle and mirror. */
static void all_pairs(cloud *C, const sph_sim *s)
{
    const sph_config *c = &s->cfg;
    const double m = s->mass, h = s->h, eta2 = 0.01 * h * h;
    for (long a = 0; a < C->nf; a++) {
        C->ax[a] = C->ay[a] = C->drho[a] = 0.0;
        const double ra = C->rho[a], pa = c->c0 * c->c0 * (ra - c->rho0);
        for (long b = 0; b < C->n; b++) {
            const double rv[2] = {C->x[a] - C->x[b], C->y[a] - C->y[b]};
            const double r2 = rv[0] * rv[0] + rv[1] * rv[1];
            if (b == a || r2 >= s->kernel.support * s->kernel.support)
                continue;
            double gr[2];
            sph_kernel_grad(&s->kernel, rv, gr);
            const double rb = C->rho[b], pb = c->c0 * c->c0 * (rb - c->rho0);
            const double v[2] = {C->vx[a] - C->vx[b], C->vy[a] - C->vy[b]};
            const double vr = v[0] * rv[0] + v[1] * rv[1];
            C->drho[a] += m * (v[0] * gr[0] + v[1] * gr[1]);
            double pt = pa / (ra * ra) + pb / (rb * rb);
            if (c->visc == SPH_VISC_MONAGHAN || (c->visc == SPH_VISC_ARTIFICIAL && vr < 0.0))
                pt += -(c->visc == SPH_VISC_MONAGHAN ? sph_config_monaghan_alpha(c) : c->alpha) *
                      c->c0 * (h * vr / (r2 + eta2)) / (0.5 * (ra + rb));
            for (int d = 0; d < 2; d++) {
                double acc = -m * pt * gr[d];
                if (c->visc == SPH_VISC_LAMINAR)
                    acc += 8.0 * c->rho0 * c->nu * m * (rv[0] * gr[0] + rv[1] * gr[1]) /
                           ((ra + rb) * (ra + rb) * (r2 + eta2)) * v[d];
                if (d == 0)
                    C->ax[a] += acc;
                else
                    C->ay[a] += acc;
            }
            if (c->delta_sph > 0.0)
                C->drho[a] += c->delta_sph * h * c->c0 * 2.0 * (rb - ra) *
                              -(rv[0] * gr[0] + rv[1] * gr[1]) / (r2 + eta2) * m / rb;
        }
        C->ax[a] += c->gravity[0];
        C->ay[a] += c->gravity[1];
    }
}

static void check_forces(sph_visc_type visc, double delta)
{
    sph_config c = tank_config();
    c.visc = visc;
    c.alpha = 0.1;
    c.nu = 1e-3;
    c.delta_sph = delta;
    sph_error err;
    sph_sim *s = sph_sim_create(&c, &err);
    assert_non_null(s);
    sph_particles *P = &s->P;
    cloud *C = calloc(1, sizeof *C);
    assert_non_null(C);
    C->nf = P->n;
    unsigned seed = 777u + (unsigned)visc;
    for (long i = 0; i < P->n; i++) { /* a shaken lattice, inside the tank */
        P->x[i] += 0.004 * (urand(&seed) - 0.5);
        P->y[i] += 0.004 * (urand(&seed) - 0.5);
        P->vx[i] = urand(&seed) - 0.5;
        P->vy[i] = urand(&seed) - 0.5;
        P->rho[i] = 995.0 + 10.0 * urand(&seed);
        const int k = P->id[i];
        C->x[k] = P->x[i];
        C->y[k] = P->y[i];
        C->vx[k] = P->vx[i];
        C->vy[k] = P->vy[i];
        C->rho[k] = P->rho[i];
    }
    mirror(C, &c, s->kernel.support);
    all_pairs(C, s);
    assert_int_equal(sph_wcsph_forces(s), 0);
    assert_int_equal(s->nghost, C->n - C->nf);
    assert_int_equal(P->n, C->nf); /* the ghosts are gone again */
    assert_int_equal(s->nactive, C->nf);
    double scale[3] = {0, 0, 0};
    for (long a = 0; a < C->nf; a++) {
        scale[0] = fmax(scale[0], fabs(C->ax[a]));
        scale[1] = fmax(scale[1], fabs(C->ay[a]));
        scale[2] = fmax(scale[2], fabs(C->drho[a]));
    }
    for (long i = 0; i < P->n; i++) {
        const int k = P->id[i];
        assert_int_equal(P->type[i], SPH_FLUID);
        const double got[3] = {P->ax[i], P->ay[i], P->drho[i]},
                     want[3] = {C->ax[k], C->ay[k], C->drho[k]};
        for (int f = 0; f < 3; f++)
            if (fabs(got[f] - want[f]) > 1e-10 * scale[f])
                fail_msg("visc %d delta %g: field %d of particle %d: cell list %.17g, all pairs "
                         "with mirrors %.17g",
                         (int)visc, delta, f, k, got[f], want[f]);
        /* the positions the loop saw are the particle's own (the ghosts' were dropped) */
        assert_double_equal(P->x[i], C->x[k], 0.0);
        assert_double_equal(P->vy[i], C->vy[k], 0.0);
    }
    free(C);
    sph_sim_destroy(s);
}

static void test_forces_artificial(void **state)
{
    (void)state;
    check_forces(SPH_VISC_ARTIFICIAL, 0.0);
}

static void test_forces_monaghan_delta(void **state)
{
    (void)state;
    check_forces(SPH_VISC_MONAGHAN, 0.1);
}

static void test_forces_laminar(void **state)
{
    (void)state;
    check_forces(SPH_VISC_LAMINAR, 0.0);
}

/* Stepping: ghosts never reach the particle view or the diagnostics. */
static void test_invisible(void **state)
{
    (void)state;
    sph_config c = tank_config();
    sph_error err;
    sph_sim *s = sph_sim_create(&c, &err);
    assert_non_null(s);
    assert_int_equal(sph_sim_step(s, 20, &err), 0);
    assert_true(s->nghost > 0);
    sph_particle_view v;
    sph_sim_particles(s, &v);
    assert_int_equal(v.n, 300);
    for (long i = 0; i < v.n; i++)
        assert_int_equal(v.type[i], SPH_FLUID);
    const sph_diag *d = sph_sim_diag(s);
    assert_int_equal(d->nfluid, 300);
    assert_int_equal(d->nboundary, 0);
    assert_int_equal(d->lost, 0);
    sph_sim_destroy(s);
}

/* A particle the predictor takes across a wall of a tank that fills the domain comes back
 * (reflected before the domain check): it is not lost. */
static void test_crossing(void **state)
{
    (void)state;
    sph_config c = tank_config(); /* domain and tank share the walls */
    sph_error err;
    sph_sim *s = sph_sim_create(&c, &err);
    assert_non_null(s);
    sph_particles *P = &s->P;
    long k = -1;
    for (long i = 0; i < P->n; i++)
        if (P->id[i] == 0) /* the bottom-left corner particle, at (dx/2, dx/2) */
            k = i;
    assert_true(k >= 0);
    P->vx[k] = -100.0; /* 2 cm in a step of 2e-4 s: through the left wall */
    assert_int_equal(sph_sim_step(s, 1, &err), 0);
    assert_int_equal(sph_sim_diag(s)->lost, 0);
    for (long i = 0; i < P->n; i++)
        if (P->id[i] == 0) {
            assert_true(P->x[i] > 0.0 && P->vx[i] > 0.0);
            assert_int_equal(P->type[i], SPH_FLUID);
        }
    sph_sim_destroy(s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_builder),
        cmocka_unit_test(test_errors),
        cmocka_unit_test(test_reflect),
        cmocka_unit_test(test_forces_artificial),
        cmocka_unit_test(test_forces_monaghan_delta),
        cmocka_unit_test(test_forces_laminar),
        cmocka_unit_test(test_invisible),
        cmocka_unit_test(test_crossing),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
