/*
 * Rigid bodies (core/boundary/sph_body.c) against exact answers:
 *  - a body falling in an empty domain follows y0 - g t^2/2 and -g t to round-off, rigidly, and
 *    the adaptive time step respects its speed;
 *  - a body with only rotation free spins up at the rate a prescribed torque gives
 *    (alpha = T / I), and in water its angular velocity follows the torque the solver reports;
 *  - a prescribed-velocity body moves exactly as prescribed through water;
 *  - the moment of inertia (analytic, of the uniform solid) against the sum over a fine solid
 *    filling of particles; the particle counts and the fluid carved around a body;
 *  - momentum: without gravity or walls, fluid plus body keeps its momentum to round-off;
 *  - a run with a body saved and restored continues bitwise (1 and 2 threads);
 *  - bad bodies are refused at their JSON path.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "sph_body.h"
#include "sph_fill.h"
#include "sph_sim.h"

#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define PI 3.14159265358979323846

/* An empty domain 2 m x 3 m, no walls, one circle of D = 0.1 m at (0, 0), density 500. */
static sph_config empty_domain(void)
{
    sph_config c = sph_config_default();
    c.dx = 0.01;
    c.domain = (sph_box){{-1.0, -2.5, 0}, {1.0, 0.5, 0}};
    c.boundary = SPH_BOUNDARY_NONE;
    c.c0 = 20.0;
    c.t_end = 1.0;
    c.nbodies = 1;
    sph_body_spec *b = &c.bodies[0];
    snprintf(b->name, sizeof b->name, "cyl");
    b->shape = SPH_SHAPE_CIRCLE;
    b->diameter = 0.1;
    b->density = 500.0;
    b->free = SPH_DOF_ALL;
    return c;
}

/* Still water 0.4 m x 0.2 m in a tank, a body above or in it. */
static sph_config tank(void)
{
    sph_config c = empty_domain();
    c.domain = (sph_box){{-0.3, -0.1, 0}, {0.3, 0.6, 0}};
    c.boundary = SPH_BOUNDARY_DYNAMIC;
    c.has_tank = 1;
    c.tank = (sph_box){{-0.2, 0.0, 0}, {0.2, 0.5, 0}};
    c.nfluid = 1;
    c.fluid[0] = (sph_box){{-0.2, 0.0, 0}, {0.2, 0.2, 0}};
    c.bodies[0].center[1] = 0.2;
    return c;
}

static void test_free_fall(void **state)
{
    (void)state;
    sph_config c = empty_domain();
    c.bodies[0].velocity[0] = 0.25; /* and a horizontal drift, exact too */
    sph_error err;
    sph_sim *s = sph_sim_create(&c, &err);
    assert_non_null(s);
    const double g = 9.81, h = c.h_over_dx * c.dx;
    const sph_diag *d = sph_sim_diag(s);
    assert_int_equal(d->nbodies, 1);
    assert_int_equal(d->nfluid, 0);
    const long np = d->nbody;
    assert_true(np > 50);
    while (sph_sim_time(s) < 0.5) {
        assert_int_equal(sph_sim_advance(s, 50, 0.5, &err), 0);
        d = sph_sim_diag(s);
        const double t = d->t, y = -0.5 * g * t * t, v = -g * t;
        assert_true(fabs(d->body[0].x[1] - y) <= 1e-12);
        assert_true(fabs(d->body[0].v[1] - v) <= 1e-12);
        assert_true(fabs(d->body[0].x[0] - 0.25 * t) <= 1e-12);
        assert_true(d->body[0].v[0] == 0.25);
        assert_true(d->body[0].omega == 0.0 && d->body[0].angle == 0.0);
        /* the time step respects the body's speed (at the start of the step) */
        const double v0 = g * (t - d->dt);
        assert_true(d->dt <= c.cfl * h / (c.c0 + sqrt(v0 * v0 + 0.0625)) * (1.0 + 1e-12));
    }
    d = sph_sim_diag(s);
    printf("free fall to t = %g s in %ld steps: y = %.17g (exact %.17g), v = %.17g\n", d->t,
           d->step, d->body[0].x[1], -0.5 * g * d->t * d->t, d->body[0].v[1]);
    /* rigid: every particle sits where its body puts it, with the body's velocity */
    sph_particle_view pv;
    sph_sim_particles(s, &pv);
    long nb = 0;
    for (long i = 0; i < pv.n; i++)
        if (pv.type[i] == SPH_BODY) {
            const double rx = pv.pos[0][i] - d->body[0].x[0], ry = pv.pos[1][i] - d->body[0].x[1];
            assert_true(sqrt(rx * rx + ry * ry) < 0.05);
            assert_true(fabs(pv.vel[1][i] - d->body[0].v[1]) < 1e-12);
            nb++;
        }
    assert_int_equal(nb, np);
    sph_sim_destroy(s);
}

/* The body module alone: a couple of tangential forces on a rotation-only body gives
 * alpha = T / I, and the scheme integrates it exactly (omega = alpha t, theta = alpha t^2 / 2). */
static void test_spin_up_prescribed_torque(void **state)
{
    (void)state;
    sph_config c = empty_domain();
    c.bodies[0].free = SPH_DOF_ROTATION;
    sph_bodies B;
    assert_int_equal(sph_bodies_init(&B, &c, 0), 0);
    sph_particles P;
    assert_int_equal(sph_particles_alloc(&P, B.np, 2, 0), 0);
    sph_bodies_fill(&B, &c, &P);
    const double m = c.rho0 * c.dx * c.dx, a0 = 0.3; /* tangential acceleration [m/s^2] */
    const double R = 0.05, M = 500.0 * PI * R * R, I = 0.5 * M * R * R;
    assert_true(fabs(B.b[0].mass - M) <= 1e-14 * M);
    assert_true(fabs(B.b[0].inertia - I) <= 1e-14 * I);
    double T = 0.0; /* the torque of the couple, summed independently */
    for (long i = 0; i < P.n; i++) {
        const double rx = P.x[i] - 0.0, ry = P.y[i] - 0.0, r = sqrt(rx * rx + ry * ry);
        T += r * m * a0;
    }
    const double alpha = T / I, dt = 1e-3;
    double t = 0.0;
    for (int k = 0; k <= 400; k++) {
        if (k > 0) { /* step 0 is the evaluation before the first step, as the solver's */
            assert_true(sph_bodies_predict(&B, dt, &c.domain) < 0);
            sph_bodies_move(&B, &P, P.n);
        }
        for (long i = 0; i < P.n; i++) { /* the couple, turning with the body */
            const double rx = P.x[i] - B.b[0].s.x[0], ry = P.y[i] - B.b[0].s.x[1];
            const double r = sqrt(rx * rx + ry * ry);
            P.ax[i] = r > 0.0 ? -a0 * ry / r : 0.0;
            P.ay[i] = r > 0.0 ? a0 * rx / r : 0.0;
        }
        sph_bodies_gather(&B, &P, P.n, m);
        if (k == 0)
            continue;
        sph_bodies_correct(&B, dt);
        t += dt;
        assert_true(fabs(B.b[0].s.alpha - alpha) <= 1e-12 * alpha);
        assert_true(fabs(B.b[0].s.omega - alpha * t) <= 1e-12 * alpha);
        assert_true(fabs(B.b[0].s.theta - 0.5 * alpha * t * t) <= 1e-12 * alpha);
        /* translation is not free: the net force (zero for a couple) and gravity do nothing */
        assert_true(B.b[0].s.x[0] == 0.0 && B.b[0].s.x[1] == 0.0);
    }
    printf("spin-up: T = %.6g N m, I = %.6g kg m^2, omega(%g s) = %.15g (alpha t = %.15g)\n", T, I,
           t, B.b[0].s.omega, alpha * t);
    sph_particles_free(&P);
    sph_bodies_free(&B);
}

/* The whole solver: a rotation-only box half in water, turned by 0.3 rad; its angular velocity
 * follows the torque the diagnostics report: omega(n+1) = omega(n) + dt/2 (T(n) + T(n+1)) / I. */
static void test_spin_up_in_water(void **state)
{
    (void)state;
    sph_config c = tank();
    sph_body_spec *b = &c.bodies[0];
    b->shape = SPH_SHAPE_BOX;
    b->size[0] = 0.12;
    b->size[1] = 0.06;
    b->angle = 0.3;
    b->free = SPH_DOF_ROTATION;
    sph_error err;
    sph_sim *s = sph_sim_create(&c, &err);
    assert_non_null(s);
    const double M = 500.0 * 0.12 * 0.06, I = M * (0.12 * 0.12 + 0.06 * 0.06) / 12.0;
    sph_diag prev = *sph_sim_diag(s);
    double tmax = 0.0;
    for (int k = 0; k < 300; k++) {
        assert_int_equal(sph_sim_step(s, 1, &err), 0);
        const sph_diag *d = sph_sim_diag(s);
        const double dw = 0.5 * d->dt * (prev.body[0].torque + d->body[0].torque) / I;
        assert_true(fabs(d->body[0].omega - (prev.body[0].omega + dw)) <=
                    1e-12 * (fabs(d->body[0].omega) + 1e-9));
        assert_true(d->body[0].x[0] == 0.0 && d->body[0].x[1] == 0.2);
        tmax = fmax(tmax, fabs(d->body[0].torque));
        prev = *d;
    }
    assert_true(tmax > 0.0);
    printf("spin-up in water: largest torque %.4g N m, omega = %.6g rad/s after %ld steps\n", tmax,
           prev.body[0].omega, prev.step);
    sph_sim_destroy(s);
}

static void test_prescribed_velocity(void **state)
{
    (void)state;
    sph_config c = tank();
    sph_body_spec *b = &c.bodies[0];
    b->center[1] = 0.25; /* above the water, moving into it */
    b->velocity[0] = 0.3;
    b->velocity[1] = -0.4;
    b->omega = 2.0;
    b->free = 0;
    sph_error err;
    sph_sim *s = sph_sim_create(&c, &err);
    assert_non_null(s);
    double fmax_ = 0.0;
    while (sph_sim_time(s) < 0.15) {
        assert_int_equal(sph_sim_advance(s, 25, 0.15, &err), 0);
        const sph_diag *d = sph_sim_diag(s);
        assert_true(fabs(d->body[0].x[0] - 0.3 * d->t) <= 1e-12);
        assert_true(fabs(d->body[0].x[1] - (0.25 - 0.4 * d->t)) <= 1e-12);
        assert_true(fabs(d->body[0].angle - 2.0 * d->t) <= 1e-12);
        assert_true(d->body[0].v[0] == 0.3 && d->body[0].v[1] == -0.4 && d->body[0].omega == 2.0);
        fmax_ = fmax(fmax_, fabs(d->body[0].force[1]));
    }
    assert_true(fmax_ > 0.0); /* the water pushed, and the body did not care */
    printf("prescribed: t = %g s, x = %.15g, y = %.15g, angle = %.15g; largest |Fy| %.3g N\n",
           sph_sim_time(s), sph_sim_diag(s)->body[0].x[0], sph_sim_diag(s)->body[0].x[1],
           sph_sim_diag(s)->body[0].angle, fmax_);
    sph_sim_destroy(s);
}

/* I of the uniform solid (what the bodies use) against sum m r^2 over a fine solid filling. */
static void test_inertia(void **state)
{
    (void)state;
    sph_config c = empty_domain();
    c.dx = 0.1 / 80;
    c.nbodies = 2;
    c.bodies[1] = c.bodies[0];
    snprintf(c.bodies[1].name, sizeof c.bodies[1].name, "box");
    c.bodies[1].shape = SPH_SHAPE_BOX;
    c.bodies[1].size[0] = 0.2;
    c.bodies[1].size[1] = 0.1;
    c.bodies[1].center[1] = -0.5;
    c.bodies[1].density = 0.0;
    c.bodies[1].mass = 7.0;
    sph_bodies B;
    assert_int_equal(sph_bodies_init(&B, &c, 0), 0);
    assert_int_equal(B.np, sph_body_count(&c));
    for (int k = 0; k < 2; k++) {
        double sum = 0.0;
        long n = 0;
        for (long q = 0; q < B.np; q++)
            if (B.owner[q] == k) {
                sum += B.local[2 * q] * B.local[2 * q] + B.local[2 * q + 1] * B.local[2 * q + 1];
                n++;
            }
        const double Ip = B.b[k].mass * sum / (double)n;
        const double rel = fabs(Ip - B.b[k].inertia) / B.b[k].inertia;
        printf("inertia of %s: analytic %.6g, from %ld particles %.6g (%.3g%%)\n", c.bodies[k].name,
               B.b[k].inertia, n, Ip, 100.0 * rel);
        assert_true(rel < 0.01);
    }
    assert_true(fabs(B.b[1].mass - 7.0) == 0.0);
    assert_true(fabs(B.b[1].inertia - 7.0 * (0.04 + 0.01) / 12.0) <= 1e-15);
    sph_bodies_free(&B);

    /* hollow: `layers` layers; the box's count in closed form matches its lattice */
    c.dx = 0.01;
    c.bodies[0].layers = 2;
    c.bodies[1].layers = 3;
    assert_int_equal(sph_bodies_init(&B, &c, 0), 0);
    assert_int_equal(B.np, sph_body_count(&c));
    assert_int_equal(B.b[1].np, 20 * 10 - 14 * 4);
    assert_int_equal(B.b[0].np, lround(2 * PI * 0.045 / 0.01) + lround(2 * PI * 0.035 / 0.01));
    sph_bodies_free(&B);
}

/* The fluid leaves the body's place: particles within dx/2 of its surface are not built. */
static void test_carving(void **state)
{
    (void)state;
    sph_config c = tank();
    sph_fill_counts n;
    sph_fill_count(&c, &n);
    long inside = 0;
    for (int i = 0; i < 40; i++)
        for (int j = 0; j < 20; j++) {
            const double x = -0.2 + (i + 0.5) * 0.01, y = (j + 0.5) * 0.01;
            inside += hypot(x, y - 0.2) < 0.055;
        }
    assert_true(inside > 0);
    assert_int_equal(n.fluid, 800 - inside);
    sph_error err;
    sph_sim *s = sph_sim_create(&c, &err);
    assert_non_null(s);
    assert_int_equal(sph_sim_diag(s)->nfluid, n.fluid);
    sph_sim_destroy(s);
}

/* No gravity, no walls: a body thrown into a block of water. What the fluid gains the body
 * loses: sum m v + M V stays what it was, to round-off. */
static void test_momentum(void **state)
{
    (void)state;
    sph_config c = empty_domain();
    c.gravity[1] = 0.0;
    c.nfluid = 1;
    c.fluid[0] = (sph_box){{-0.2, -0.3, 0}, {0.2, -0.1, 0}};
    c.bodies[0].center[1] = -0.04;
    c.bodies[0].velocity[1] = -1.0;
    c.bodies[0].omega = 3.0;
    sph_error err;
    sph_sim *s = sph_sim_create(&c, &err);
    assert_non_null(s);
    const double m = c.rho0 * c.dx * c.dx, M = 500.0 * PI * 0.05 * 0.05;
    double p0[2] = {0.0, -M}, fmax_ = 0.0;
    for (int k = 0; k < 6; k++) {
        assert_int_equal(sph_sim_step(s, 50, &err), 0);
        sph_particle_view v;
        sph_sim_particles(s, &v);
        double p[2] = {0.0, 0.0};
        for (long i = 0; i < v.n; i++)
            if (v.type[i] == SPH_FLUID) {
                p[0] += m * v.vel[0][i];
                p[1] += m * v.vel[1][i];
            }
        const sph_diag *d = sph_sim_diag(s);
        assert_int_equal(d->lost, 0);
        p[0] += M * d->body[0].v[0];
        p[1] += M * d->body[0].v[1];
        fmax_ = fmax(fmax_, fabs(d->body[0].force[1]));
        printf("momentum at t = %.4f s: (%.3e, %.15f) kg m/s, body v = %.6f m/s\n", d->t,
               p[0] - p0[0], p[1], d->body[0].v[1]);
        assert_true(fabs(p[0] - p0[0]) < 1e-12 && fabs(p[1] - p0[1]) < 1e-12);
    }
    assert_true(fmax_ > 1.0); /* the body did hit the water */
    sph_sim_destroy(s);
}

static void restore_with_bodies(int threads)
{
    omp_set_num_threads(threads);
    sph_config c = tank();
    c.bodies[0].center[1] = 0.26;
    c.bodies[0].velocity[1] = -1.0;
    c.nbodies = 2;
    c.bodies[1] = c.bodies[0];
    snprintf(c.bodies[1].name, sizeof c.bodies[1].name, "box");
    c.bodies[1].shape = SPH_SHAPE_BOX;
    c.bodies[1].size[0] = c.bodies[1].size[1] = 0.06;
    c.bodies[1].center[0] = 0.12;
    c.bodies[1].center[1] = 0.2;
    sph_error err;
    sph_sim *a = sph_sim_create(&c, &err);
    assert_non_null(a);
    assert_int_equal(sph_sim_step(a, 150, &err), 0);
    void *buf;
    size_t len;
    assert_int_equal(sph_sim_save(a, &buf, &len, &err), 0);
    assert_int_equal(sph_sim_step(a, 150, &err), 0);
    sph_sim *b = sph_sim_restore(buf, len, &err);
    assert_non_null(b);
    assert_int_equal(sph_sim_step(b, 150, &err), 0);
    sph_particle_view va, vb;
    sph_sim_particles(a, &va);
    sph_sim_particles(b, &vb);
    assert_int_equal(va.n, vb.n);
    for (int d = 0; d < 2; d++) {
        assert_memory_equal(va.pos[d], vb.pos[d], (size_t)va.n * sizeof(double));
        assert_memory_equal(va.vel[d], vb.vel[d], (size_t)va.n * sizeof(double));
    }
    assert_memory_equal(va.rho, vb.rho, (size_t)va.n * sizeof(double));
    assert_memory_equal(sph_sim_diag(a)->body, sph_sim_diag(b)->body, 2 * sizeof(sph_body_diag));
    assert_true(sph_sim_diag(a)->body[0].v[1] != -1.0); /* the water did something */
    free(buf);
    sph_sim_destroy(a);
    sph_sim_destroy(b);
}

static void test_restore_one_thread(void **state)
{
    (void)state;
    restore_with_bodies(1);
}

static void test_restore_two_threads(void **state)
{
    (void)state;
    restore_with_bodies(2);
}

/* Bad bodies, each at its path. */
static void expect_invalid(const sph_config *c, const char *path)
{
    sph_error err;
    sph_error_clear(&err);
    assert_int_not_equal(sph_sim_check(c, &err), 0);
    printf("  %-22s %s\n", err.path, err.message);
    assert_string_equal(err.path, path);
}

static void test_invalid(void **state)
{
    (void)state;
    sph_config c = tank(), d;
    assert_int_equal(sph_sim_check(&c, NULL), 0);
    d = c;
    d.bodies[0].center[0] = 0.29; /* past the domain's right edge */
    expect_invalid(&d, "/bodies/0/center");
    d = c;
    d.bodies[0].center[0] = -0.23; /* into the left wall */
    expect_invalid(&d, "/bodies/0/center");
    d = c;
    d.bodies[0].center[1] = 0.03; /* into the bottom */
    expect_invalid(&d, "/bodies/0/center");
    d = c;
    d.bodies[0].density = 0.0;
    expect_invalid(&d, "/bodies/0/density");
    d = c;
    d.bodies[0].density = -3.0;
    expect_invalid(&d, "/bodies/0/density");
    d = c;
    d.bodies[0].mass = 2.0;
    expect_invalid(&d, "/bodies/0/mass");
    d = c;
    d.bodies[0].diameter = 0.015; /* less than 2 dx */
    expect_invalid(&d, "/bodies/0/diameter");
    d = c;
    d.nbodies = 2;
    d.bodies[1] = d.bodies[0];
    snprintf(d.bodies[1].name, sizeof d.bodies[1].name, "other");
    d.bodies[1].shape = SPH_SHAPE_BOX;
    d.bodies[1].size[0] = 0.1;
    d.bodies[1].size[1] = 0.015;
    d.bodies[1].center[0] = 0.12;
    expect_invalid(&d, "/bodies/1/size/1");
    d.bodies[1].size[1] = 0.05;
    assert_int_equal(sph_sim_check(&d, NULL), 0); /* 0.12 - 0.05 - 0.05 = 0.02 apart */
    d.bodies[1].center[0] = 0.09;                 /* 0.09 - 0.05 - 0.05: overlaps */
    expect_invalid(&d, "/bodies/1/center");
    d.bodies[1].center[0] = 0.12;
    snprintf(d.bodies[1].name, sizeof d.bodies[1].name, "cyl");
    expect_invalid(&d, "/bodies/1/name");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_free_fall),
        cmocka_unit_test(test_spin_up_prescribed_torque),
        cmocka_unit_test(test_spin_up_in_water),
        cmocka_unit_test(test_prescribed_velocity),
        cmocka_unit_test(test_inertia),
        cmocka_unit_test(test_carving),
        cmocka_unit_test(test_momentum),
        cmocka_unit_test(test_restore_one_thread),
        cmocka_unit_test(test_restore_two_threads),
        cmocka_unit_test(test_invalid),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
