/*
 * Initial fields (core/sph_initial.c) and the kinetic-energy envelope (core/sph_envelope.c):
 *   - the standing wave's velocity is grad phi0 of paper 001 eq. (7) (checked by central
 *     differences of phi0 written out here), vanishes through the walls, and its kinetic energy
 *     on the lattice is eq. (8)'s at t = 0 within 0.5% (H/dx = 50);
 *   - the solitary wave (paper 004 eqs. (5.1)-(5.2)): its velocity is divergence-free (central
 *     differences), the fill stacks each column up to the raised surface (the crest's column within
 *     dx of d + H, the hump's volume on the lattice within dx^2 + 0.1% of the exact 2H/K, the
 *     count the same as the memory estimate's),
 *     and its particles carry eq. (5.2)'s velocity;
 *   - the solitary wave at "order": 3 (Grimshaw 1971, in Fenton 1972's form): the crest is H high,
 *     u there at the surface and at the bed is the series' value written out at sech = 1,
 *     tanh = 0, v vanishes there and is odd about the crest (u and eta even); div u, curl u and
 *     the kinematic surface condition (u - c) eta_x = v leave residuals that fall at least 2^3.5
 *     times as H/d halves (third order: O(eps^4)); order 1 stays eq. (5.2) bit for bit; an order
 *     other than 1 or 3 is refused at /initial/order, H > d/3 at order 3 at /initial/height; a
 *     state saved before the option (0 in its slot) restores as the first order;
 *   - fields that do not fit the case are refused at the case field's JSON path;
 *   - the envelope fit recovers the decay rate and period of eq. (8) sampled every 2 ms, with
 *     noise, within 0.5%.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "sph_envelope.h"
#include "sph_initial.h"
#include "sph_sim.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void close_to(double got, double want, double tol, const char *what)
{
    if (!(fabs(got - want) <= tol))
        fail_msg("%s: %.17g, expected %.17g within %g", what, got, want, tol);
}

static sph_config wave_config(double res)
{
    const double H = 0.5;
    sph_config c = sph_config_default();
    c.dx = H / res;
    c.h_over_dx = 2.0;
    c.domain = (sph_box){{0, 0, 0}, {1.0, 1.0, 0}};
    c.nfluid = 1;
    c.fluid[0] = (sph_box){{0, 0, 0}, {1.0, H, 0}};
    c.boundary = SPH_BOUNDARY_GHOST;
    c.has_tank = 1;
    c.tank = (sph_box){{0, 0, 0}, {1.0, 1.0, 0}};
    c.c0 = 23.0;
    c.visc = SPH_VISC_MONAGHAN;
    c.nu = H * sqrt(9.81 * H) / 500.0;
    c.initial = sph_initial_default(SPH_INITIAL_STANDING_WAVE);
    c.t_end = 1.0;
    return c;
}

/* Paper 001 eq. (7), with y measured from the bottom (the paper's y + H). */
static double phi0(double x, double y)
{
    const double eps = 0.1, H = 0.5, g = 9.81, k = 2.0 * M_PI;
    const double omega = sqrt(g * k * tanh(k * H));
    return -eps * H * g / (2.0 * omega) * cosh(k * y) / cosh(k * H) * cos(k * x);
}

static void test_velocity(void **state)
{
    (void)state;
    const sph_config c = wave_config(50);
    const double d = 1e-6;
    for (double x = 0.0; x <= 1.0; x += 0.125)
        for (double y = 0.0; y <= 0.5; y += 0.125) {
            const double p[3] = {x, y, 0};
            double v[3];
            sph_initial_velocity(&c, p, v);
            close_to(v[0], (phi0(x + d, y) - phi0(x - d, y)) / (2 * d), 1e-7, "u");
            close_to(v[1], (phi0(x, y + d) - phi0(x, y - d)) / (2 * d), 1e-7, "v");
            if (x == 0.0 || x == 1.0)
                close_to(v[0], 0.0, 1e-15, "u at a wall");
            if (y == 0.0)
                close_to(v[1], 0.0, 1e-15, "v at the bottom");
        }
}

static void test_energy(void **state)
{
    (void)state;
    const sph_config c = wave_config(50);
    sph_error err;
    sph_sim *s = sph_sim_create(&c, &err);
    if (!s)
        fail_msg("%s", err.message);
    sph_sim_wave w;
    assert_int_equal(sph_sim_wave_fit(s, 0.0, &w), -1); /* no peaks yet, the theory is there */
    const double e0 = 1000.0 * 0.01 * 9.81 * 1.0 * 0.25 / 16.0; /* rho eps^2 g lambda H^2 / 16 */
    const double ekin = sph_sim_diag(s)->ekin;
    if (fabs(ekin - e0) > 0.005 * e0)
        fail_msg("E_kin(0) %.6f J on the lattice, eq. (8) %.6f J", ekin, e0);
    const double k = 2.0 * M_PI, omega = sqrt(9.81 * k * tanh(k * 0.5));
    sph_sim_destroy(s);
    /* the theory the sim compares with */
    sph_initial_theory t;
    assert_int_equal(sph_initial_theory_of(&c, &t), 0);
    close_to(t.period, 2.0 * M_PI / omega, 1e-12, "period");
    close_to(t.decay_rate, 4.0 * c.nu * k * k, 1e-12, "4 nu k^2");
    close_to(t.ekin0, e0, 1e-12, "ekin0");
    sph_config r = c;
    r.initial = sph_initial_default(SPH_INITIAL_REST);
    assert_int_equal(sph_initial_theory_of(&r, &t), -1);
}

static void expect_error(sph_config c, const char *path)
{
    sph_error err;
    sph_error_clear(&err);
    sph_sim *s = sph_sim_create(&c, &err);
    if (s)
        fail_msg("created, expected an error at %s", path);
    assert_int_equal(err.code, SPH_ERR_INVALID);
    if (strcmp(err.path, path) != 0)
        fail_msg("path %s, expected %s (%s)", err.path, path, err.message);
}

static void test_misfits(void **state)
{
    (void)state;
    sph_config c = wave_config(20);
    c.initial.param[1] = 0.3; /* 1 m is not a whole number of 0.15 m half wavelengths */
    expect_error(c, "/initial/wavelength");
    c = wave_config(20);
    c.initial.param[1] = 2.0; /* half a wavelength: fits (the walls are antinodes) */
    sph_error err;
    sph_sim *s = sph_sim_create(&c, &err);
    assert_non_null(s);
    sph_sim_destroy(s);
    c = wave_config(20);
    c.initial.param[0] = 0.9;
    expect_error(c, "/initial/epsilon");
    c = wave_config(20);
    c.fluid[0].max[0] = 0.5; /* water in half the tank */
    expect_error(c, "/fluid");
    c = wave_config(20);
    c.gravity[1] = 0.0;
    expect_error(c, "/physics/gravity");
    c = wave_config(20);
    c.boundary = SPH_BOUNDARY_NONE;
    c.has_tank = 0;
    expect_error(c, "/initial/type");
}

/* Paper 004's set-up at half scale: d = 5 m (dx 0.4 m: 12 whole rows hold 4.8 m), H = 1 m. */
static sph_config solitary_config(void)
{
    sph_config c = sph_config_default();
    c.method = SPH_METHOD_MPS;
    c.kernel = sph_kernel_spec_default(SPH_KERNEL_KOSHIZUKA);
    c.dx = 0.4;
    c.domain = (sph_box){{0, 0, 0}, {80.0, 10.0, 0}};
    c.nfluid = 1;
    c.fluid[0] = (sph_box){{0, 0, 0}, {80.0, 5.0, 0}};
    c.boundary = SPH_BOUNDARY_DYNAMIC;
    c.layers = 4;
    c.has_tank = 1;
    c.tank = (sph_box){{0, 0, 0}, {80.0, 8.0, 0}};
    c.visc = SPH_VISC_LAMINAR;
    c.nu = 1e-6;
    c.initial = sph_initial_default(SPH_INITIAL_SOLITARY_WAVE);
    c.initial.param[0] = 1.0;  /* H */
    c.initial.param[1] = 30.0; /* x0 */
    c.t_end = 1.0;
    return c;
}

static void test_solitary(void **state)
{
    (void)state;
    sph_config c = solitary_config();
    const double H = 1.0, d = 4.8, x0 = 30.0, g = 9.81, K = sqrt(3.0 * H / (4.0 * d * d * d));
    close_to(sph_initial_elevation(&c, x0), H, 1e-12, "crest height");
    close_to(sph_initial_elevation(&c, x0 + 1.0 / K), H / pow(cosh(1.0), 2), 1e-12,
             "eta at x0 + 1/K");
    close_to(sph_initial_elevation_max(&c), H, 1e-12, "largest elevation");
    /* u(x) at the surface and divergence-free */
    const double e = 1e-4;
    for (double x = 10.0; x < 60.0; x += 3.7)
        for (double y = 0.5; y < d; y += 1.1) {
            double v[2], vxp[2], vxm[2], vyp[2], vym[2];
            sph_initial_velocity(&c, (double[]){x, y}, v);
            close_to(v[0], sqrt(g * d) * sph_initial_elevation(&c, x) / d, 1e-12, "u, eq. (5.2)");
            sph_initial_velocity(&c, (double[]){x + e, y}, vxp);
            sph_initial_velocity(&c, (double[]){x - e, y}, vxm);
            sph_initial_velocity(&c, (double[]){x, y + e}, vyp);
            sph_initial_velocity(&c, (double[]){x, y - e}, vym);
            const double div = (vxp[0] - vxm[0] + vyp[1] - vym[1]) / (2.0 * e);
            close_to(div, 0.0, 1e-7, "div u");
        }
    /* the fill: the still water's whole rows plus the hump, column by column */
    sph_error err;
    sph_sim *s = sph_sim_create(&c, &err);
    assert_non_null(s);
    sph_particle_view pv;
    sph_sim_particles(s, &pv);
    long nf = 0, ncol = (long)(80.0 / c.dx + 1e-6);
    double ytop_crest = 0.0, vmax_err = 0.0;
    for (long i = 0; i < pv.n; i++) {
        if (pv.type[i] != 0)
            continue;
        nf++;
        if (fabs(pv.pos[0][i] - x0) < c.dx)
            ytop_crest = fmax(ytop_crest, pv.pos[1][i]);
        double v[2];
        sph_initial_velocity(&c, (double[]){pv.pos[0][i], pv.pos[1][i]}, v);
        vmax_err = fmax(vmax_err, fabs(pv.vel[0][i] - v[0]) + fabs(pv.vel[1][i] - v[1]));
    }
    close_to(vmax_err, 0.0, 1e-12, "particle velocities against eq. (5.2)");
    close_to(ytop_crest + 0.5 * c.dx, d + H, c.dx, "the crest column's top");
    long n0 = 12 * ncol;
    /* the hump's volume over the tank (2H/K for a crest far from both walls) */
    const double hump = H / K * (tanh(K * (80.0 - x0)) + tanh(K * x0));
    const double lattice = (double)(nf - n0) * c.dx * c.dx;
    printf("hump volume %.4f m^2 on the lattice, %.4f exact\n", lattice, hump);
    if (!(fabs(lattice - hump) <= 0.001 * hump + c.dx * c.dx))
        fail_msg("hump volume %.3f m^2 on the lattice, %.3f exact", lattice, hump);
    long nfe, nbe;
    sph_sim_estimate_bytes(&c, &nfe, &nbe);
    assert_int_equal(nfe, nf);
    sph_sim_destroy(s);
    /* misfits */
    c = solitary_config();
    c.initial.param[0] = 4.0; /* H/d > 0.7 */
    expect_error(c, "/initial/height");
    c = solitary_config();
    c.initial.param[0] = 0.2; /* below dx */
    expect_error(c, "/initial/height");
    c = solitary_config();
    c.initial.param[1] = 90.0;
    expect_error(c, "/initial/crest");
    c = solitary_config();
    c.tank.max[1] = 6.0; /* below d + 2H */
    expect_error(c, "/boundary/tank/max/1");
}

/* The largest residuals over a patch around the crest (|x - x0| < 3 d, the column below the
 * surface) of Grimshaw's field of height H over the half-scale depth d = 4.8 m, as multiples of
 * sqrt(g d) / d: div u, curl u, and (u - c) eta_x - v at the surface with the third-order c. */
static void grimshaw_residuals(double H, double r[3])
{
    sph_config c = solitary_config();
    c.initial.param[0] = H;
    c.initial.param[2] = 3.0;
    const double d = 4.8, g = 9.81, x0 = 30.0, e = H / d, h = 1e-4;
    const double cw = sqrt(g * d) * (1.0 + 0.5 * e - 0.15 * e * e + 3.0 / 56.0 * e * e * e);
    r[0] = r[1] = r[2] = 0.0;
    for (double x = x0 - 3.0 * d; x <= x0 + 3.0 * d; x += 0.37 * d) {
        const double top = d + sph_initial_elevation(&c, x);
        for (double y = 0.05 * d; y < top; y += 0.15 * d) {
            double vxp[2], vxm[2], vyp[2], vym[2];
            sph_initial_velocity(&c, (double[]){x + h, y}, vxp);
            sph_initial_velocity(&c, (double[]){x - h, y}, vxm);
            sph_initial_velocity(&c, (double[]){x, y + h}, vyp);
            sph_initial_velocity(&c, (double[]){x, y - h}, vym);
            r[0] = fmax(r[0], fabs(vxp[0] - vxm[0] + vyp[1] - vym[1]) / (2.0 * h));
            r[1] = fmax(r[1], fabs(vyp[0] - vym[0] - vxp[1] + vxm[1]) / (2.0 * h));
        }
        double v[2];
        sph_initial_velocity(&c, (double[]){x, top}, v);
        const double ex =
            (sph_initial_elevation(&c, x + h) - sph_initial_elevation(&c, x - h)) / (2.0 * h);
        r[2] = fmax(r[2], fabs((v[0] - cw) * ex - v[1]));
    }
    r[0] *= d / sqrt(g * d);
    r[1] *= d / sqrt(g * d);
    r[2] /= sqrt(g * d);
}

static void test_solitary_order3(void **state)
{
    (void)state;
    sph_config c = solitary_config();
    c.initial.param[2] = 3.0;
    const double H = 1.0, d = 4.8, x0 = 30.0, g = 9.81, e = H / d, cg = sqrt(g * d);
    close_to(sph_initial_elevation(&c, x0), H, 1e-12, "crest height");
    close_to(sph_initial_elevation_max(&c), H, 1e-12, "largest elevation");
    /* u at the crest (sech = 1, tanh = 0): sqrt(g d) (eps - eps^2 (3/4 - 3/4 Y^2)
     * - eps^3 (-21/40 + 9/4 Y^2 - 3/8 Y^4)), Y = y/d; at the bed Y = 0, at the surface 1 + eps */
    double v[2];
    sph_initial_velocity(&c, (double[]){x0, 0.0}, v);
    close_to(v[0], cg * (e - 0.75 * e * e + 21.0 / 40.0 * e * e * e), 1e-12, "u at the bed");
    close_to(v[1], 0.0, 1e-15, "v at the bed");
    const double Y = 1.0 + e, Y2 = Y * Y;
    sph_initial_velocity(&c, (double[]){x0, d + H}, v);
    close_to(v[0],
             cg * (e - e * e * (0.75 - 0.75 * Y2) -
                   e * e * e * (-21.0 / 40.0 + 9.0 / 4.0 * Y2 - 0.375 * Y2 * Y2)),
             1e-12, "u at the crest's surface");
    close_to(v[1], 0.0, 1e-15, "v at the crest");
    /* about the crest: eta and u even, v odd (and v > 0 ahead of the crest: the water rises) */
    for (double dxc = 0.7; dxc < 40.0; dxc += 3.1) {
        close_to(sph_initial_elevation(&c, x0 + dxc), sph_initial_elevation(&c, x0 - dxc), 1e-12,
                 "eta even about the crest");
        for (double y = 0.3; y < d; y += 1.1) {
            double a[2], b[2];
            sph_initial_velocity(&c, (double[]){x0 + dxc, y}, a);
            sph_initial_velocity(&c, (double[]){x0 - dxc, y}, b);
            close_to(a[0], b[0], 1e-12, "u even about the crest");
            close_to(a[1], -b[1], 1e-12, "v odd about the crest");
            if (!(a[1] > 0.0))
                fail_msg("v = %g ahead of the crest at x0 + %g, y = %g", a[1], dxc, y);
        }
    }
    /* third order: the residuals are below 5 eps^4 and fall as eps^4 (eps^4.5 for div u and the
     * surface condition) */
    double r1[3], r2[3];
    grimshaw_residuals(1.0, r1);
    grimshaw_residuals(0.5, r2);
    const char *what[3] = {"div u", "curl u", "kinematic surface condition"};
    for (int k = 0; k < 3; k++) {
        printf("%s: %.3e at H/d = %.4f, %.3e at half of it (ratio %.1f)\n", what[k], r1[k], 1.0 / d,
               r2[k], r1[k] / r2[k]);
        if (!(r1[k] < 5.0 * pow(1.0 / d, 4.0) && r1[k] / r2[k] > pow(2.0, 3.5)))
            fail_msg("%s: %.3e at H/d = %.3f, %.3e at half of it: not third order", what[k], r1[k],
                     1.0 / d, r2[k]);
    }
    /* it fills like the first order: the crest's column reaches d + H */
    sph_error err;
    sph_sim *s = sph_sim_create(&c, &err);
    if (!s)
        fail_msg("%s", err.message);
    sph_particle_view pv;
    sph_sim_particles(s, &pv);
    double ytop = 0.0;
    for (long i = 0; i < pv.n; i++)
        if (pv.type[i] == 0 && fabs(pv.pos[0][i] - x0) < c.dx)
            ytop = fmax(ytop, pv.pos[1][i]);
    close_to(ytop + 0.5 * c.dx, d + H, c.dx, "the crest column's top");
    sph_sim_destroy(s);
    /* order 1 (the default) is eq. (5.2) as before, to the bit (d as the code forms it: 12 dx) */
    c = solitary_config();
    assert_true(c.initial.param[2] == 1.0);
    const double d1 = 12.0 * c.dx, e1 = H / d1, K = sqrt(3.0 * H / (4.0 * d1 * d1 * d1));
    const double xa = x0 + 2.3, ya = 1.7, s2 = 1.0 / (cosh(K * (xa - x0)) * cosh(K * (xa - x0)));
    sph_initial_velocity(&c, (double[]){xa, ya}, v);
    assert_true(v[0] == sqrt(g * d1) * e1 * s2);
    assert_true(v[1] == sqrt(3.0 * g * d1) * e1 * sqrt(e1) * (ya / d1) * s2 * tanh(K * (xa - x0)));
    assert_true(sph_initial_elevation(&c, xa) == H * s2);
    /* a state saved before the option (0 in its slot) restores as the first order */
    c = solitary_config();
    s = sph_sim_create(&c, &err);
    assert_non_null(s);
    void *buf;
    size_t len;
    assert_int_equal(sph_sim_save(s, &buf, &len, &err), 0);
    sph_sim_destroy(s);
    const double slots[3] = {c.initial.param[0], c.initial.param[1], 1.0};
    unsigned char *hit = NULL;
    for (size_t k = 0; k + sizeof slots <= len && !hit; k++)
        if (memcmp((unsigned char *)buf + k, slots, sizeof slots) == 0)
            hit = (unsigned char *)buf + k;
    assert_non_null(hit);
    memset(hit + 2 * sizeof(double), 0, sizeof(double));
    s = sph_sim_restore(buf, len, &err);
    free(buf);
    if (!s)
        fail_msg("an old state: %s", err.message);
    assert_true(sph_sim_config(s)->initial.param[2] == 1.0);
    sph_sim_destroy(s);
    /* refusals */
    c = solitary_config();
    c.initial.param[2] = 2.0;
    expect_error(c, "/initial/order");
    c.initial.param[2] = 0.0;
    expect_error(c, "/initial/order");
    c = solitary_config();
    c.initial.param[2] = 3.0;
    c.initial.param[0] = 1.7; /* H/d = 0.354 > 1/3, within order 1's 0.7 */
    c.tank.max[1] = 9.0;
    expect_error(c, "/initial/height");
    c.initial.param[2] = 1.0;
    s = sph_sim_create(&c, &err);
    if (!s)
        fail_msg("order 1 at H/d = 0.354: %s", err.message);
    sph_sim_destroy(s);
}

static void test_envelope(void **state)
{
    (void)state;
    const double T = 0.8, beta = 0.35, omega = 2.0 * M_PI / T;
    sph_envelope e;
    sph_envelope_init(&e, 0.97 * T); /* the expected period a little off */
    unsigned seed = 1;
    for (double t = 0.0; t < 10.0 * T; t += 0.002) {
        seed = seed * 1103515245u + 12345u;
        const double noise = 1e-4 * (((seed >> 8) & 0xffff) / 65536.0 - 0.5);
        sph_envelope_add(&e, t, 0.5 * exp(-beta * t) * (1.0 + cos(2.0 * omega * t)) + noise);
    }
    sph_envelope_fit f;
    assert_int_equal(sph_envelope_fit_peaks(&e, 8.0 * T, &f), 0);
    assert_int_equal(f.npeaks, 17); /* t = 0, T/2, ..., 8T */
    close_to(f.decay_rate, beta, 0.005 * beta, "decay rate");
    close_to(f.period, T, 0.005 * T, "period");
    assert_int_equal(sph_envelope_fit_peaks(&e, 0.6 * T, &f), -1); /* 2 peaks: no fit */
}

/* A ghost-walled standing wave saved and restored continues bitwise, its envelope included. */
static void test_restore(void **state)
{
    (void)state;
    const sph_config c = wave_config(10);
    sph_error err;
    sph_sim *a = sph_sim_create(&c, &err);
    assert_non_null(a);
    assert_int_equal(sph_sim_advance(a, 400, 0.3, &err), 0); /* past the first window */
    void *buf;
    size_t len;
    assert_int_equal(sph_sim_save(a, &buf, &len, &err), 0);
    sph_sim *b = sph_sim_restore(buf, len, &err);
    free(buf);
    if (!b)
        fail_msg("%s", err.message);
    assert_int_equal(sph_sim_advance(a, 4000, 1.1, &err), 0);
    assert_int_equal(sph_sim_advance(b, 4000, 1.1, &err), 0);
    sph_particle_view va, vb;
    sph_sim_particles(a, &va);
    sph_sim_particles(b, &vb);
    assert_int_equal(va.n, vb.n);
    assert_memory_equal(va.pos[0], vb.pos[0], (size_t)va.n * sizeof(double));
    assert_memory_equal(va.vel[1], vb.vel[1], (size_t)va.n * sizeof(double));
    sph_sim_wave wa, wb;
    assert_int_equal(sph_sim_wave_fit(a, INFINITY, &wa), 0);
    assert_int_equal(sph_sim_wave_fit(b, INFINITY, &wb), 0);
    assert_int_equal(wa.peaks, 3);
    assert_memory_equal(&wa, &wb, sizeof wa);
    sph_sim_destroy(a);
    sph_sim_destroy(b);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_velocity),        cmocka_unit_test(test_energy),
        cmocka_unit_test(test_misfits),         cmocka_unit_test(test_solitary),
        cmocka_unit_test(test_solitary_order3), cmocka_unit_test(test_envelope),
        cmocka_unit_test(test_restore),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
