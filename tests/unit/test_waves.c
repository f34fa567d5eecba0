/*
 * The wave flume (issue 45): the physics of boundary/sph_wave_law.h against values computed
 * independently, the paddle and the damping zone in a sim, the bad inputs, and a restart that
 * gives the same bits.
 *
 * - the piston's transfer function at kd = 1: 2 (cosh 2 - 1) / (sinh 2 + 2) = 0.98178930731303
 *   (evaluated in Python's math module), and its limits: 2kd in shallow water (kd -> 0; the
 *   series of both sides to first order), 2 in deep water; the flap's at kd = 1 hinged on the
 *   bottom, 0.528087623589261 (Dean & Dalrymple's closed form in mpmath), and 0.25 d above it,
 *   0.376853729014670 (mpmath's quadrature of the plane-wave solution's integral 4 sinh kd /
 *   (sinh 2kd + 2kd) k int_0^d (z - l) / (d - l) cosh kz dz, not the closed form), its limits kd/2
 *   in shallow water and 2 (1 - 1/kd) in deep water (hinged on the bottom);
 * - Goring's solitary wave law: X(0) = 0, X rising to the stroke sqrt(16 H d / 3) (less the start
 *   X(theta(0))), its velocity dX/dt (a centred difference) and c eta / (d + eta) with eta = H
 *   sech^2(kappa (c t - X) - 3.8) at the paddle (the law's defining equation, to 1e-12);
 * - the flap's placement: rigid (each particle's distance to the hinge kept), its face crossing
 *   the still water level X ahead of rest, its velocity the positions' derivative;
 * - the dispersion solver: kd tanh(kd) = omega^2 d / g to rounding over y from 1e-4 to 50, and
 *   d = 0.4 m, T = 1.27 s -> kd = 1.19803592561098 (Python, bisection to 1e-15);
 * - the ramp: 0 at t = 0, 1/2 half way, 1 from its end on; its rate the derivative (a centred
 *   difference, to 1e-7 relative);
 * - the damping weight: 0 before `from`, 1/4 half way, 1 from `to` on, either way round; the
 *   factor 1 - dt beta f, never negative;
 * - a sim of cases/wave_flume.json at dx = 0.05: the paddle's particles at rest + X(t) with the
 *   velocity dX/dt after some steps (to rounding: the same arithmetic); a fluid particle in the
 *   damping zone's far end slowed by 1 - dt beta; a restart at step 60 continues to the same
 *   bits as the run that went on;
 * - a sim with a flap: its particles turned about the hinge by atan(X / (d - l)); a sim of
 *   cases/wave_solitary.json: the piston at Goring's X(t);
 * - bad inputs: each refused at its field's path;
 * - the wave analysis (server/sphd_waves.c): a sampled sine's height and period by zero
 *   up-crossing; each gauge's window (ramp + 1) T + distance / cg with cg = 1.18939862610825
 *   m/s (Python: kd by bisection, cg = omega / (2k) (1 + 2kd / sinh 2kd)); linear theory's
 *   ramped train at the case's gauges (its envelope moving at cg) measured at H from the
 *   window on, which an analysis from the end of the ramp alone would not (its far gauges'
 *   windows would take in the growing front); a solitary wave's sech^2 passing three gauges at c:
 *   each crest's height and time, and the celerity fitted over them.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "sph_case.h"
#include "sph_json.h"
#include "sph_sim.h"
#include "sph_sim_impl.h"
#include "sph_wave_law.h"
#include "sph_wavemaker.h"
#include "sphd_waves.h"
#include "unit_case.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static void transfer_function(void **state)
{
    (void)state;
    assert_true(fabs(sph_piston_transfer(1.0) - 0.9817893073130344) < 1e-14);
    for (double kd = 1e-3; kd < 2e-2; kd *= 2.0) /* shallow water: H/S -> kd (1 + O(kd^2)) */
        assert_true(fabs(sph_piston_transfer(kd) / kd - 1.0) < kd);
    assert_true(fabs(sph_piston_transfer(20.0) - 2.0) < 1e-12); /* deep water */
    assert_true(fabs(sph_flap_transfer(1.0, 0.0) - 0.528087623589261) < 1e-14);
    assert_true(fabs(sph_flap_transfer(1.0, 0.25) - 0.376853729014670) < 1e-14);
    for (double kd = 1e-3; kd < 2e-2; kd *= 2.0) /* shallow water: H/S -> kd / 2 */
        assert_true(fabs(sph_flap_transfer(kd, 0.0) / (0.5 * kd) - 1.0) < kd);
    assert_true(fabs(sph_flap_transfer(30.0, 0.0) / (2.0 * (1.0 - 1.0 / 30.0)) - 1.0) < 1e-12);
}

/* Goring's law at H/d = 0.2 in d = 0.4 m (cases/wave_solitary.json's wave). */
static sph_paddle_law goring(void)
{
    const double H = 0.08, d = 0.4, g = 9.81;
    sph_paddle_law p = {.solitary = 1, .height = H, .depth = d};
    p.kappa = sqrt(3.0 * H / (4.0 * d * d * d));
    p.celerity = sqrt(g * (d + H));
    p.stroke = sqrt(16.0 * H * d / 3.0);
    p.x0 = H / (p.kappa * d) * (1.0 + tanh(sph_solitary_theta(&p, 0.0)));
    return p;
}

static void solitary_law(void **state)
{
    (void)state;
    const sph_paddle_law p = goring();
    double v, va, vb;
    assert_true(sph_paddle_motion(&p, 0.0, &v) == 0.0);
    assert_true(p.x0 > 0.0 && p.x0 < 1e-3 * p.stroke); /* Goring's start: tanh(-3.8) */
    double last = 0.0;
    for (double t = 0.01; t < 6.0; t += 0.0731) {
        const double X = sph_paddle_motion(&p, t, &v);
        assert_true(X >= last && v >= 0.0); /* forward only */
        last = X;
        const double h = 1e-6;
        const double fd =
            (sph_paddle_motion(&p, t + h, &va) - sph_paddle_motion(&p, t - h, &vb)) / (2 * h);
        assert_true(fabs(fd - v) < 1e-8);
        /* dX/dt = c eta / (d + eta), eta at the paddle (its position X + x0 from theta's origin) */
        const double th = p.kappa * (p.celerity * t - (X + p.x0)) - SPH_SOLITARY_THETA0;
        const double eta = p.height / (cosh(th) * cosh(th));
        assert_true(fabs(v - p.celerity * eta / (p.depth + eta)) < 1e-12);
    }
    /* the stroke done within the paddle's time 2 (3.8 + H/d) / (kappa c) */
    const double dur = 2.0 * (3.8 + p.height / p.depth) / (p.kappa * p.celerity);
    assert_true(fabs(sph_paddle_motion(&p, dur, &v) + p.x0 - p.stroke) < 1e-3 * p.stroke);
    assert_true(fabs(sph_paddle_motion(&p, 1e3, &v) + p.x0 - p.stroke) < 1e-12);
}

/* A flap hinged at (1, 0.1) with arm 0.3: rigid, the face X ahead at the still water level. */
static void flap_place(void **state)
{
    (void)state;
    const sph_paddle_law p = {.flap = 1, .hx = 1.0, .hy = 0.1, .arm = 0.3};
    const double rest[4][2] = {{0.99, 0.05}, {0.95, 0.4}, {0.99, 0.65}, {0.93, 0.11}};
    for (double X = -0.05; X <= 0.05; X += 0.0125) {
        const double Xv = 0.7;
        for (int k = 0; k < 4; k++) {
            double x[2], u[2], xa[2], xb[2], w[2];
            sph_paddle_place(&p, rest[k][0], rest[k][1], X, Xv, x, u);
            const double r0 = hypot(rest[k][0] - p.hx, rest[k][1] - p.hy);
            assert_true(fabs(hypot(x[0] - p.hx, x[1] - p.hy) - r0) < 1e-15);
            const double h = 1e-7; /* the velocity: d/dt with X moving at Xv */
            sph_paddle_place(&p, rest[k][0], rest[k][1], X + h * Xv, Xv, xa, w);
            sph_paddle_place(&p, rest[k][0], rest[k][1], X - h * Xv, Xv, xb, w);
            assert_true(fabs((xa[0] - xb[0]) / (2 * h) - u[0]) < 1e-7);
            assert_true(fabs((xa[1] - xb[1]) / (2 * h) - u[1]) < 1e-7);
        }
        /* the face (through the hinge) turned: at the still water level, X ahead */
        double top[2], u[2];
        sph_paddle_place(&p, p.hx, p.hy + 1.0, X, 0.0, top, u);
        const double at = p.hx + (top[0] - p.hx) * p.arm / (top[1] - p.hy);
        assert_true(fabs(at - (p.hx + X)) < 1e-15);
    }
    /* a piston: moved by X */
    const sph_paddle_law q = {0};
    double x[2], u[2];
    sph_paddle_place(&q, 0.5, 0.2, 0.03, 0.4, x, u);
    assert_true(x[0] == 0.5 + 0.03 && x[1] == 0.2 && u[0] == 0.4 && u[1] == 0.0);
}

static void dispersion(void **state)
{
    (void)state;
    for (double y = 1e-4; y < 50.0; y *= 1.7) {
        const double x = sph_wave_kd(y);
        assert_true(fabs(x * tanh(x) - y) <= 1e-13 * y);
    }
    const double g = 9.81, d = 0.4, w = 2.0 * 3.14159265358979323846 / 1.27;
    assert_true(fabs(sph_wave_number(w, g, d) * d - 1.19803592561098) < 1e-12);
    assert_true(sph_wave_kd(0.0) == 0.0);
}

static void ramp(void **state)
{
    (void)state;
    const double tr = 2.5;
    double r, rate;
    assert_true(sph_wave_ramp(0.0, tr, &rate) == 0.0 && rate == 0.0);
    assert_true(fabs(sph_wave_ramp(1.25, tr, &rate) - 0.5) < 1e-15);
    assert_true(sph_wave_ramp(2.5, tr, &rate) == 1.0 && rate == 0.0);
    assert_true(sph_wave_ramp(7.0, tr, &rate) == 1.0);
    assert_true(sph_wave_ramp(0.3, 0.0, &rate) == 1.0); /* none */
    for (double t = 0.1; t < tr; t += 0.3) {
        double a, b;
        r = sph_wave_ramp(t, tr, &rate);
        const double h = 1e-5;
        const double fd = (sph_wave_ramp(t + h, tr, &a) - sph_wave_ramp(t - h, tr, &b)) / (2 * h);
        assert_true(r > 0.0 && r < 1.0);
        assert_true(fabs(fd - rate) <= 1e-7 * fabs(rate) + 1e-9);
    }
    /* the piston's velocity is its displacement's derivative */
    const sph_paddle_law p = {.stroke = 0.04, .omega = 5.0, .tramp = 2.0};
    for (double t = 0.05; t < 4.0; t += 0.37) {
        double v, va, vb;
        sph_paddle_motion(&p, t, &v);
        const double h = 1e-6;
        const double fd =
            (sph_paddle_motion(&p, t + h, &va) - sph_paddle_motion(&p, t - h, &vb)) / (2 * h);
        assert_true(fabs(fd - v) < 1e-8);
    }
}

static void damping_weight(void **state)
{
    (void)state;
    assert_true(sph_damping_weight(1.0, 2.0, 4.0) == 0.0);
    assert_true(fabs(sph_damping_weight(3.0, 2.0, 4.0) - 0.25) < 1e-15);
    assert_true(sph_damping_weight(4.0, 2.0, 4.0) == 1.0);
    assert_true(sph_damping_weight(9.0, 2.0, 4.0) == 1.0);
    assert_true(fabs(sph_damping_weight(1.0, 2.0, 0.0) - 0.25) < 1e-15); /* towards -x */
    assert_true(fabs(sph_damping_factor(9.0, 1e-3, 10.0, 2.0, 4.0) - 0.99) < 1e-15);
    assert_true(sph_damping_factor(9.0, 1.0, 10.0, 2.0, 4.0) == 0.0);
    assert_true(sph_damping_factor(1.0, 1.0, 10.0, 2.0, 4.0) == 1.0);
}

/* dx = 0.05: 3 layers of paddle (the case's 4 and half its stroke would not fit behind the face) */
static const char *const small[] = {"dx=0.05", "wavemaker.layers=3", "time.end=1.0", NULL};

/* After some steps each paddle particle is on its rest lattice (columns dx/2, 3dx/2, ... behind
 * the face, rows dx/2, 3dx/2, ... above the bottom) moved by the paddle's law:
 * cases/wave_flume.json's piston at rest + X(t), moving at dX/dt (kd = 1.19803592561098); a flap
 * hinged 0.1 m above the bottom, turned back about the hinge by phi = atan(X / (d - l)), moving at
 * dphi/dt about it, its stroke from the flap's transfer function. A solitary wave's piston
 * (cases/wave_solitary.json) at Goring's X(t), and the same in cases/wave_runup.json, whose beach
 * is a geometry item (the paddle after the scene's walls). */
static void paddle_moves(void **state)
{
    (void)state;
    static const char *const flap[] = {"dx=0.05",
                                       "wavemaker.layers=3",
                                       "wavemaker.type=flap",
                                       "wavemaker.hinge=0.1",
                                       "wavemaker.x=0.3",
                                       "fluid.0.box.min.0=0.3",
                                       NULL};
    static const char *const sol[] = {"dx=0.05", "wavemaker.layers=3", NULL};
    static const char *const rsets[] = {"dx=0.05", "wavemaker.layers=3",
                                        "wavemaker.waves.height=0.08", NULL};
    /* the 3D flume (0.4 m wide: 10 particles across at its dx = 0.04 m) cut to 2 m, no ramp, a
     * piston and a flap */
#define SHORT3                                                                                     \
    "domain.max.0=2", "boundary.tank.max.0=2", "fluid.0.box.max.0=2", "absorption.from=1.5",       \
        "absorption.to=2", "wavemaker.ramp=0", "diagnostics.gauges.0.x=1",                         \
        "diagnostics.gauges.1.x=1.2"
    static const char *const small3[] = {SHORT3, NULL};
    static const char *const flap3[] = {SHORT3,
                                        "wavemaker.type=flap",
                                        "wavemaker.hinge=0.1",
                                        "wavemaker.x=0.4",
                                        "fluid.0.box.min.0=0.4",
                                        NULL};
#undef SHORT3
    static const struct {
        const char *file;
        const char *const *sets;
    } runs[] = {{"wave_flume.json", small},    {"wave_flume.json", flap},
                {"wave_solitary.json", sol},   {"wave_runup.json", rsets},
                {"wave_flume3d.json", small3}, {"wave_flume3d.json", flap3}};
    for (int run = 0; run < 6; run++) {
        const int solitary = run == 2 || run == 3;
        /* the whole case: wave_runup.json's beach is a surface it owns (sph_case_clear) */
        sph_case *cs = calloc(1, sizeof *cs);
        assert_non_null(cs);
        sph_error err;
        if (parse_full_case(runs[run].file, runs[run].sets, cs, &err))
            fail_msg("%s: %s: %s", runs[run].file, err.path, err.message);
        const sph_config cfg = cs->sim;
        sph_sim *s = sph_sim_create(&cfg, &err);
        if (!s)
            fail_msg("%s: %s", err.path, err.message);
        sph_wave_design w;
        assert_int_equal(sph_sim_wave_design(&cfg, &w), 0);
        const double d = w.depth, l = cfg.wavemaker.hinge, H = cfg.wavemaker.height;
        sph_paddle_law law;
        if (solitary) {
            law = goring(); /* the same wave: H 0.08 m in 0.4 m */
            assert_true(fabs(w.stroke - law.stroke) < 1e-15 && d == law.depth && H == law.height);
        } else if (run == 0 || run == 4) {
            assert_true(run == 4 || fabs(w.k * d - 1.19803592561098) < 1e-12);
            assert_true(fabs(w.stroke - H / sph_piston_transfer(w.k * d)) < 1e-15);
        } else {
            assert_true(fabs(w.stroke - H / sph_flap_transfer(w.k * d, l / d)) < 1e-15);
        }
        if (!solitary)
            law = (sph_paddle_law){.stroke = w.stroke,
                                   .omega = w.omega,
                                   .tramp = cfg.wavemaker.ramp * cfg.wavemaker.period};
        assert_int_equal(sph_sim_advance(s, run >= 4 ? 50 : 400, INFINITY, &err), 0);
        double v;
        const double X = sph_paddle_motion(&law, sph_sim_time(s), &v);
        assert_true(fabs(X) > 1e-4); /* it has moved */
        const int V = cfg.dim - 1;   /* the vertical axis; in 3D y stays */
        const double hx = cfg.wavemaker.x, hy = cfg.tank.min[V] + l, arm = d - l;
        const int flapped = run == 1 || run == 5;
        const double phi = flapped ? atan2(X, arm) : 0.0;
        const double dphi = flapped ? arm * v / (arm * arm + X * X) : 0.0;
        sph_particle_view pv;
        sph_sim_particles(s, &pv);
        long np = 0;
        const double dx = cfg.dx;
        for (long i = 0; i < pv.n; i++) {
            if (pv.type[i] != 1 || pv.pos[V][i] < 0.0 || pv.pos[0][i] < cfg.tank.min[0] ||
                pv.pos[0][i] > 1.0 ||
                (V == 2 && (pv.pos[1][i] < 0.0 || pv.pos[1][i] > cfg.tank.max[1])))
                continue; /* the paddle: wall particles inside the tank, above its bottom */
            double rx = pv.pos[0][i] - X, ry = pv.pos[V][i], ux = v, uy = 0.0;
            if (flapped) { /* turned back about the hinge */
                const double px = pv.pos[0][i] - hx, py = pv.pos[V][i] - hy;
                rx = hx + px * cos(phi) - py * sin(phi);
                ry = hy + px * sin(phi) + py * cos(phi);
                ux = dphi * py;
                uy = -dphi * px;
            }
            const double k = (hx - rx) / dx - 0.5, r = (ry - cfg.tank.min[V]) / dx - 0.5;
            assert_true(fabs(k - round(k)) < 1e-9 && k >= -1e-9 && k < cfg.wavemaker.layers);
            assert_true(fabs(r - round(r)) < 1e-9 && r >= -1e-9);
            assert_true(fabs(pv.vel[0][i] - ux) < 1e-12 && fabs(pv.vel[V][i] - uy) < 1e-12);
            assert_true(V == 1 || pv.vel[1][i] == 0.0);
            np++;
        }
        const long rows = lround((cfg.tank.max[V] - cfg.tank.min[V]) / dx);
        const long across = V == 2 ? lround((cfg.tank.max[1] - cfg.tank.min[1]) / dx) : 1;
        assert_int_equal(np, cfg.wavemaker.layers * rows * across);
        sph_sim_destroy(s);
        sph_case_clear(cs);
        free(cs);
    }
}

/* A restart in the ramp continues to the same bits (the paddle's law a function of time). */
static void restart_same_bits(void **state)
{
    (void)state;
    const sph_config cfg = load_case("wave_flume.json", small);
    sph_error err;
    sph_sim *a = sph_sim_create(&cfg, &err);
    assert_non_null(a);
    assert_int_equal(sph_sim_advance(a, 60, INFINITY, &err), 0);
    void *buf;
    size_t len;
    assert_int_equal(sph_sim_save(a, &buf, &len, &err), 0);
    sph_sim *b = sph_sim_restore(buf, len, &err);
    if (!b)
        fail_msg("%s: %s", err.path, err.message);
    free(buf);
    assert_int_equal(sph_sim_advance(a, 120, INFINITY, &err), 0);
    assert_int_equal(sph_sim_advance(b, 120, INFINITY, &err), 0);
    unit_same_bits(a, b);
    sph_sim_destroy(a);
    sph_sim_destroy(b);
}

/* A fluid particle beyond the damping zone's end keeps 1 - dt beta of its velocity each step:
 * with the zone over the whole flume and beta 1/dt, the fluid stops after one step. */
static void damping_stops(void **state)
{
    (void)state;
    static const char *const sets[] = {"dx=0.05",
                                       "wavemaker.layers=3",
                                       "wavemaker.ramp=0",
                                       "absorption.from=0.3",
                                       "absorption.to=0.31",
                                       "absorption.beta=1e4",
                                       NULL};
    const sph_config cfg = load_case("wave_flume.json", sets);
    sph_error err;
    sph_sim *s = sph_sim_create(&cfg, &err);
    if (!s)
        fail_msg("%s: %s", err.path, err.message);
    assert_int_equal(sph_sim_advance(s, 3, INFINITY, &err), 0);
    sph_particle_view pv;
    sph_sim_particles(s, &pv);
    long nz = 0;
    for (long i = 0; i < pv.n; i++)
        if (pv.type[i] == 0 && pv.pos[0][i] > 0.31) {
            assert_true(pv.vel[0][i] == 0.0 && pv.vel[1][i] == 0.0);
            nz++;
        }
    assert_true(nz > 1000);
    sph_sim_destroy(s);
}

/* cases/wave_flume.json with sets: refused at path (by the parser or sph_sim_check). */
static void refused(const char *const *sets, const char *path)
{
    sph_config cfg;
    sph_error err;
    int rc = parse_case("wave_flume.json", sets, &cfg, &err);
    if (rc == 0)
        rc = sph_sim_check(&cfg, &err);
    if (rc == 0)
        fail_msg("accepted; expected an error at %s", path);
    if (strcmp(err.path, path) != 0)
        fail_msg("error at %s (%s), expected at %s", err.path, err.message, path);
}

static void bad_inputs(void **state)
{
    (void)state;
    /* steeper than 0.142 tanh(kd) (0.118 here): H/L = 0.3 / 2.1 */
    refused((const char *const[]){"wavemaker.waves.height=0.3", NULL}, "/wavemaker/waves/height");
    /* the stroke takes the paddle's back through the tank's wall */
    refused((const char *const[]){"wavemaker.x=0.07", "fluid.0.box.min.0=0.07", NULL},
            "/wavemaker/x");
    /* fluid behind the paddle's face */
    refused((const char *const[]){"fluid.0.box.min.0=0.1", NULL}, "/fluid/0/box/min");
    /* the face would pass the fluid's far end (a long period's stroke in a short flume) */
    refused((const char *const[]){"fluid.0.box.max.0=0.22", "absorption.from=0.5", NULL},
            "/wavemaker/waves/height");
    /* damping zone outside the domain, or over the paddle's travel */
    refused((const char *const[]){"absorption.to=12", NULL}, "/absorption/to");
    refused((const char *const[]){"absorption.from=0.15", NULL}, "/absorption/from");
    /* a flap's hinge out of the water column (d = 0.4 m), a hinge for a piston */
    refused((const char *const[]){"wavemaker.type=flap", "wavemaker.hinge=0.4", NULL},
            "/wavemaker/hinge");
    refused((const char *const[]){"wavemaker.type=flap", "wavemaker.hinge=-0.01", NULL},
            "/wavemaker/hinge");
    refused((const char *const[]){"wavemaker.hinge=0.1", NULL}, "/wavemaker/hinge");
    /* a flap's top swings back (0.7 - 0) / 0.4 times its stroke at the still water level: with
     * the face 0.095 m from the wall, 3 layers (0.06 m) and the piston's S/2 (0.0216 m) fit, the
     * flap's (0.047 m at the level, 0.082 m at the top) do not */
    refused((const char *const[]){"wavemaker.type=flap", "wavemaker.x=0.095", "wavemaker.layers=3",
                                  "fluid.0.box.min.0=0.095", NULL},
            "/wavemaker/x");
    /* a solitary wave: with a period, from a flap, beyond H/d = 0.6, a reflection of it; regular
     * waves without a period */
    static const char *const flap_sol[] = {"wavemaker.type=flap", NULL};
    static const char *const high[] = {"wavemaker.waves.height=0.25", NULL};
    static const char *const refl[] = {"diagnostics.reflection=[\"g5d\",\"g10d\"]", NULL};
    static const char *const noperiod[] = {"wavemaker.waves.type=regular", NULL};
    static const char *const period[] = {"wavemaker.waves.period=1.5", NULL};
    const struct {
        const char *const *sets;
        const char *path;
    } sol[] = {{flap_sol, "/wavemaker/type"},
               {high, "/wavemaker/waves/height"},
               {refl, "/diagnostics/reflection"},
               {noperiod, "/wavemaker/waves/period"},
               {period, "/wavemaker/waves/period"}};
    /* with a wavemaker the water is the fluid boxes: a geometry fluid item is refused */
    sph_case *cs = calloc(1, sizeof *cs);
    assert_non_null(cs);
    sph_error err;
    int rc = parse_full_case("wave_runup.json",
                             (const char *const[]){"geometry.0.role=fluid", NULL}, cs, &err);
    if (rc == 0)
        rc = sph_sim_check(&cs->sim, &err);
    sph_case_clear(cs);
    free(cs);
    if (rc == 0 || strcmp(err.path, "/geometry/0/role") != 0)
        fail_msg("a fluid item with a wavemaker: %s (%s)", rc ? err.path : "accepted",
                 rc ? err.message : "");
    for (size_t k = 0; k < sizeof sol / sizeof *sol; k++) {
        sph_config cfg;
        sph_error err;
        int rc = parse_case("wave_solitary.json", sol[k].sets, &cfg, &err);
        if (rc == 0)
            rc = sph_sim_check(&cfg, &err);
        if (rc == 0 || strcmp(err.path, sol[k].path) != 0)
            fail_msg("case %zu: %s (%s), expected an error at %s", k, rc ? err.path : "accepted",
                     rc ? err.message : "", sol[k].path);
    }
    /* mDBC: not in this version */
    refused((const char *const[]){"boundary.density=mdbc", NULL}, "/boundary/density");
}

#define PI 3.14159265358979323846

/* A sine sampled every 0.02 s: its zero-up-crossing height and period. */
static void analysis_zero_up(void **state)
{
    (void)state;
    enum { N = 500 };
    double t[N], eta[N];
    const double a = 0.025, T = 1.27;
    for (int i = 0; i < N; i++) {
        t[i] = 0.02 * i;
        eta[i] = 0.4 + a * sin(2.0 * PI * t[i] / T + 0.3);
    }
    double H, P;
    const int count = sphd_waves_zero_up(t, eta, 1, N, 2.0, &H, &P);
    assert_int_equal(count, 5); /* up-crossings at 2.48, 3.75, ..., 8.83 s: five whole waves */
    assert_true(fabs(H / (2.0 * a) - 1.0) < 2e-3); /* 63 samples a period: the crest's sample */
    assert_true(fabs(P / T - 1.0) < 1e-4);
    assert_int_equal(sphd_waves_zero_up(t, eta, 1, N, 9.9, &H, &P), 0);
    assert_true(isnan(H) && isnan(P));
}

/* Each gauge's window: (ramp + 1) T + its distance from the paddle / cg. */
static void analysis_window(void **state)
{
    (void)state;
    const sph_config cfg = load_case("wave_flume.json", (const char *const[]){NULL});
    const double cg = 1.1893986261082539, T = cfg.wavemaker.period;
    assert_true(cfg.ngauges >= 3);
    for (int k = 0; k < cfg.ngauges; k++) {
        const double want =
            (cfg.wavemaker.ramp + 1.0) * T + (cfg.gauges[k].x - cfg.wavemaker.x) / cg;
        assert_true(fabs(sphd_waves_window(&cfg, k) - want) < 1e-9);
    }
}

/* Linear theory's train from cfg's paddle at each gauge, n samples 0.02 s apart into new arrays
 * *t and *g (row-major, a column per gauge): the ramped envelope moving at cg, and a reflected
 * wave of kr times its height travelling back from the far wall, phase-locked to the incident one
 * there, under the same envelope (a developed pattern; kr 0: none). */
static void train(const sph_config *cfg, const sph_wave_design *w, double kr, long n, double **t,
                  double **g)
{
    const int ng = cfg->ngauges;
    *t = malloc((size_t)n * sizeof **t);
    *g = malloc((size_t)(n * ng) * sizeof **g);
    assert_non_null(*t);
    assert_non_null(*g);
    const double H = cfg->wavemaker.height, tr = cfg->wavemaker.ramp * cfg->wavemaker.period;
    const double xw = cfg->domain.max[0];
    for (long i = 0; i < n; i++) {
        const double ti = (*t)[i] = 0.02 * (double)i;
        for (int k = 0; k < ng; k++) {
            const double x = cfg->gauges[k].x - cfg->wavemaker.x, back = xw - cfg->gauges[k].x;
            double rate;
            const double r = sph_wave_ramp(ti - x / w->cg, tr, &rate);
            double eta = w->depth + 0.5 * H * r * sin(w->omega * ti - w->k * x);
            if (kr > 0.0)
                eta += 0.5 * kr * H * r *
                       sin(w->omega * ti - w->k * (xw - cfg->wavemaker.x) - w->k * back);
            (*g)[i * ng + k] = eta;
        }
    }
}

/* Linear theory's train from the case's paddle, its ramped envelope moving at cg, at each
 * gauge: the analysis gives H (and T) at every gauge, the farthest too. */
static void analysis_developed_train(void **state)
{
    (void)state;
    const sph_config cfg = load_case("wave_flume.json", (const char *const[]){NULL});
    sph_wave_design w;
    assert_int_equal(sph_sim_wave_design(&cfg, &w), 0);
    const int ng = cfg.ngauges;
    const long n = 800; /* 16 s at 0.02 s */
    double *t, *g;
    train(&cfg, &w, 0.0, n, &t, &g);
    const double H = cfg.wavemaker.height, T = cfg.wavemaker.period;
    json_t *out = sphd_waves_json(&cfg, t, g, n);
    assert_non_null(out);
    for (int k = 0; k < ng; k++) {
        json_t *o = json_object_get(out, cfg.gauges[k].name);
        assert_non_null(o);
        assert_true(json_integer_value(json_object_get(o, "count")) >= 3);
        const double h = json_real_value(json_object_get(o, "height"));
        const double p = json_real_value(json_object_get(o, "period"));
        assert_true(fabs(h / H - 1.0) < 3e-3);
        assert_true(fabs(p / T - 1.0) < 1e-3);
    }
    json_decref(out);
    free(t);
    free(g);
}

/* The same train with a reflected one of 0.15 its height travelling back from the far wall (as
 * developed as the incident one):
 * the result's reflection (diagnostics.reflection: g2L, r1, r2) gives Kr = 0.15 and the incident
 * height H within 1%; a case whose reflection gauges are half a wavelength apart says why it
 * cannot split them. */
static void analysis_reflection(void **state)
{
    (void)state;
    sph_case *cs = calloc(1, sizeof *cs);
    assert_non_null(cs);
    sph_error err;
    assert_int_equal(parse_full_case("wave_flume.json", (const char *const[]){NULL}, cs, &err), 0);
    assert_int_equal(cs->output.nreflect, 3);
    const sph_config cfg = cs->sim;
    sph_wave_design w;
    assert_int_equal(sph_sim_wave_design(&cfg, &w), 0);
    const long n = 800;
    const double H = cfg.wavemaker.height, kr = 0.15;
    double *t, *g;
    train(&cfg, &w, kr, n, &t, &g);
    json_t *o = sphd_waves_reflection_json(&cs->sim, &cs->output, t, g, n);
    assert_non_null(o);
    const double c = json_real_value(json_object_get(o, "coefficient"));
    const double hi = json_real_value(json_object_get(o, "incident_height"));
    printf("reflection: Kr %.4f (0.15), Hi %.5f (%.5f), conditioning %.3f, from %.2f s\n", c, hi, H,
           json_real_value(json_object_get(o, "conditioning")),
           json_real_value(json_object_get(o, "from")));
    assert_true(fabs(c - kr) < 0.005);
    assert_true(fabs(hi / H - 1.0) < 0.01);
    assert_int_equal(json_array_size(json_object_get(o, "gauges")), 3);
    json_decref(o);
    /* gauges half a wavelength apart: no split, and why */
    cs->sim.gauges[cs->output.reflect[1]].x =
        cs->sim.gauges[cs->output.reflect[0]].x + 0.5 * w.length;
    cs->sim.gauges[cs->output.reflect[2]].x = cs->sim.gauges[cs->output.reflect[0]].x + w.length;
    o = sphd_waves_reflection_json(&cs->sim, &cs->output, t, g, n);
    assert_non_null(o);
    assert_true(json_is_null(json_object_get(o, "coefficient")));
    assert_non_null(strstr(json_string_value(json_object_get(o, "why")), "half a wavelength"));
    json_decref(o);
    sph_case_clear(cs);
    free(cs);
    free(t);
    free(g);
}

/* A solitary wave of Goring's theory, eta = H sech^2(kappa (c t - x) - 3.8) with x from the
 * paddle, passing cases/wave_solitary.json's gauges (sampled every 0.02 s, a level of 0.4 m
 * under it): each crest's height within 0.2% of H and time within 2 ms of the theory's, the
 * celerity within 0.1% of c; a run that ends before the last window closes fits the others. */
static void analysis_solitary(void **state)
{
    (void)state;
    const sph_config cfg = load_case("wave_solitary.json", (const char *const[]){NULL});
    sph_wave_design w;
    assert_int_equal(sph_sim_wave_design(&cfg, &w), 0);
    const int ng = cfg.ngauges;
    const long n = 300; /* 6 s */
    double *t = malloc(n * sizeof *t), *g = malloc(n * ng * sizeof *g);
    assert_non_null(t);
    assert_non_null(g);
    const double H = cfg.wavemaker.height;
    for (long i = 0; i < n; i++) {
        t[i] = 0.02 * (double)i;
        for (int k = 0; k < ng; k++) {
            const double x = cfg.gauges[k].x - cfg.wavemaker.x;
            const double s = 1.0 / cosh(w.kappa * (w.celerity * t[i] - x) - 3.8);
            g[i * ng + k] = w.depth + H * s * s;
        }
    }
    json_t *o = sphd_waves_solitary_json(&cfg, t, g, n);
    assert_non_null(o);
    assert_true(fabs(json_real_value(json_object_get(o, "celerity")) / w.celerity - 1.0) < 1e-3);
    assert_true(json_real_value(json_object_get(o, "theory")) == w.celerity);
    for (int k = 0; k < ng; k++) {
        json_t *gk = json_object_get(json_object_get(o, "gauges"), cfg.gauges[k].name);
        const double x = cfg.gauges[k].x - cfg.wavemaker.x;
        const double tc = (x + 3.8 / w.kappa) / w.celerity;
        assert_true(fabs(json_real_value(json_object_get(gk, "height")) / H - 1.0) < 2e-3);
        assert_true(fabs(json_real_value(json_object_get(gk, "time")) - tc) < 2e-3);
        assert_true(fabs(json_real_value(json_object_get(gk, "level")) - w.depth) < 1e-4);
    }
    json_decref(o);
    /* the run ends at 4.2 s, before the last gauge's window closes (4.6 s): the others' fit */
    o = sphd_waves_solitary_json(&cfg, t, g, 211);
    printf("celerity over two gauges: %.5f m/s (%.5f)\n",
           json_real_value(json_object_get(o, "celerity")), w.celerity);
    assert_true(fabs(json_real_value(json_object_get(o, "celerity")) / w.celerity - 1.0) < 5e-3);
    json_decref(o);
    /* no regular analysis of a solitary wave, and no solitary one of regular waves */
    assert_null(sphd_waves_json(&cfg, t, g, n));
    const sph_config reg = load_case("wave_flume.json", (const char *const[]){NULL});
    assert_null(sphd_waves_solitary_json(&reg, t, g, n));
    free(t);
    free(g);
}

/* diagnostics.reflection: refused without a wavemaker, for an unknown gauge, one named twice. */
static void reflection_refused(void **state)
{
    (void)state;
    const char *const unknown[] = {"diagnostics.reflection=[\"g1L\",\"nope\"]", NULL};
    const char *const twice[] = {"diagnostics.reflection=[\"g1L\",\"g1L\"]", NULL};
    const char *const one[] = {"diagnostics.reflection=[\"g1L\"]", NULL};
    refused(unknown, "/diagnostics/reflection/1");
    refused(twice, "/diagnostics/reflection/1");
    refused(one, "/diagnostics/reflection");
    const char *const nowave[] = {"diagnostics.reflection=[\"a\",\"b\"]", NULL};
    sph_config cfg;
    sph_error err;
    assert_int_not_equal(parse_case("dambreak.json", nowave, &cfg, &err), 0);
    assert_non_null(strstr(err.message, "wavemaker"));
}

/* ---- second order, irregular seas, series (issue 45) ------------------------------------- */

/* Madsen's second harmonic at kd = 0.6, H = 0.05 m, d = 0.4 m: 0.00203892942146992 m (mpmath,
 * H^2 / (32 d) (3 cosh kd / sinh^3 kd - 2 / m1), m1 the piston's H/S); the law at order 2
 * r(t) (S/2 sin(omega t) + a2 sin(2 omega t)), its rate a centred difference. */
static void second_order_law(void **state)
{
    (void)state;
    assert_true(fabs(sph_madsen_second(0.6, 0.05, 0.4) / 0.00203892942146992 - 1.0) < 1e-13);
    const sph_paddle_law p = {.stroke = 0.1, .omega = 2.0, .tramp = 3.0, .second = 0.004};
    for (double t = 0.1; t < 8.0; t += 0.37) {
        double v, vp, vm, rate;
        const double X = sph_paddle_motion(&p, t, &v);
        const double r = sph_wave_ramp(t, p.tramp, &rate);
        assert_true(fabs(X - r * (0.05 * sin(2.0 * t) + 0.004 * sin(4.0 * t))) < 1e-15);
        const double h = 1e-6;
        const double d =
            (sph_paddle_motion(&p, t + h, &vp) - sph_paddle_motion(&p, t - h, &vm)) / (2.0 * h);
        assert_true(fabs(v - d) < 1e-8);
    }
}

/* cases/wave_flume.json with waves (a JSON object) and sets, without its reflection (of regular
 * waves only), parsed into the whole case *c: 0 or the parser's error. */
static int flume(const char *waves, const char *const *sets, sph_case *c, sph_error *err)
{
    char path[4096];
    const char *src = getenv("SPH_SOURCE_DIR");
    snprintf(path, sizeof path, "%s/cases/wave_flume.json", src ? src : ".");
    json_t *root;
    assert_int_equal(sph_case_load(path, &root, err), 0);
    json_object_del(json_object_get(root, "diagnostics"), "reflection");
    json_t *w = json_loads(waves, 0, NULL);
    assert_non_null(w);
    json_object_set_new(json_object_get(root, "wavemaker"), "waves", w);
    for (; sets && *sets; sets++)
        if (sph_json_apply_set(root, *sets, err) != 0)
            fail_msg("--set %s: %s", *sets, err->message);
    const int rc = sph_case_from_json(root, c, err);
    json_decref(root);
    return rc;
}

static const char *const IRREGULAR =
    "{\"type\": \"irregular\", \"hs\": 0.04, \"tp\": 1.27, \"duration\": 1000, \"seed\": 7}";

/* An irregular sea's components: the JONSWAP shape against mpmath at three frequencies (f = 0.5,
 * fp, 1.2 Hz for Tp = 1.27 s, gamma 3.3); the frequencies i / D from 0.5 to 3 fp; the surface
 * they make, sum a_i sin(omega_i t + phi_i) with a_i = A_i times the piston's H / S, sampled over
 * the duration D: 4 sqrt(m0) = Hs (the components are orthogonal over D: to 1e-9) and its H1/3
 * by zero up-crossing (sphd_waves_sea) within [0.85, 1.0] Hs (Rayleigh's 1.0 less the spectrum's
 * width: about 0.95 for JONSWAP, Goda 2000); the largest component at the peak; the same seed
 * the same phases, another seed others. */
static void irregular_sea(void **state)
{
    (void)state;
    const double fp = 1.0 / 1.27;
    assert_true(fabs(sph_jonswap_shape(0.5, fp, 3.3) / 0.0146649738472036702 - 1.0) < 1e-12);
    assert_true(fabs(sph_jonswap_shape(fp, fp, 3.3) / 3.12366493412966990 - 1.0) < 1e-12);
    assert_true(fabs(sph_jonswap_shape(1.2, fp, 3.3) / 0.318755391902221371 - 1.0) < 1e-12);
    sph_case *cs = calloc(1, sizeof *cs);
    assert_non_null(cs);
    sph_error err;
    if (flume(IRREGULAR, NULL, cs, &err))
        fail_msg("%s: %s", err.path, err.message);
    const sph_config *c = &cs->sim;
    const double D = 1000.0, g = 9.81;
    sph_wave_design w;
    assert_int_equal(sph_sim_wave_design(c, &w), 0);
    double *comp;
    const int n = sph_wave_components(c, w.depth, &comp, NULL);
    const long lo = (long)ceil(0.5 * fp * D), hi = (long)floor(3.0 * fp * D);
    assert_int_equal(n, hi - lo + 1);
    int peak = 0;
    for (int i = 0; i < n; i++) {
        assert_true(fabs(comp[3 * i + 1] - 2.0 * PI * (double)(lo + i) / D) < 1e-12);
        assert_true(comp[3 * i + 2] >= 0.0 && comp[3 * i + 2] < 2.0 * PI);
        const double kd = sph_wave_number(comp[3 * i + 1], g, w.depth) * w.depth;
        comp[3 * i] *= sph_piston_transfer(kd); /* the wave's amplitude */
        if (comp[3 * i] > comp[3 * peak])
            peak = i;
    }
    assert_true(fabs(comp[3 * peak + 1] / (2.0 * PI) - fp) <= 1.0 / D);
    const long ns = 20000;
    double *t = malloc(ns * sizeof *t), *eta = malloc(ns * sizeof *eta);
    assert_true(t && eta);
    double m0 = 0.0;
    for (long j = 0; j < ns; j++) {
        t[j] = D * (double)j / (double)ns;
        eta[j] = 0.0;
        for (int i = 0; i < n; i++)
            eta[j] += comp[3 * i] * sin(comp[3 * i + 1] * t[j] + comp[3 * i + 2]);
        m0 += eta[j] * eta[j] / (double)ns;
    }
    assert_true(fabs(4.0 * sqrt(m0) / 0.04 - 1.0) < 1e-9);
    double hm0, h13;
    const int waves = sphd_waves_sea(t, eta, 1, ns, 0.0, &hm0, &h13);
    assert_true(waves > 500 && fabs(hm0 / 0.04 - 1.0) < 1e-3);
    if (!(h13 / 0.04 >= 0.85 && h13 / 0.04 <= 1.0))
        fail_msg("H1/3 = %g Hs", h13 / 0.04);
    /* the same seed: the same phases; another: others */
    double *again, *other;
    assert_int_equal(sph_wave_components(c, w.depth, &again, NULL), n);
    cs->sim.wavemaker.seed = 8;
    assert_int_equal(sph_wave_components(c, w.depth, &other, NULL), n);
    int same = 0;
    for (int i = 0; i < n; i++) {
        assert_true(again[3 * i + 2] == comp[3 * i + 2]);
        same += other[3 * i + 2] == comp[3 * i + 2];
    }
    assert_int_equal(same, 0);
    free(again);
    free(other);
    free(comp);
    free(t);
    free(eta);
    sph_case_clear(cs);
    free(cs);
}

/* A series' law: the rows' displacements at the rows, at rest (0 rate) at both ends and before
 * and after them, Fritsch & Butland's slope at the inner rows (0 at a turn, as at every inner
 * row here; the weighted harmonic mean of the chords where they agree, computed by hand), its
 * rate continuous across each row (the Hermite pieces meet) and the derivative of X (a centred
 * difference); next to a step (rows 0, 0, 1.5, 1.5 a second apart) it stays within the rows'
 * extremes, where centred slopes overshoot by 0.11 m. */
static void series_law(void **state)
{
    (void)state;
    const double ts[] = {0.0, 0.5, 1.0, 1.7, 2.0}, xs[] = {0.0, 0.01, -0.02, 0.005, 0.0};
    const long n = 5;
    double v;
    for (long i = 0; i < n; i++) {
        assert_true(fabs(sph_series_motion(ts, xs, n, ts[i], &v) - xs[i]) < 1e-15);
        const double h = 1e-7;
        double vl, vr;
        const double xl = sph_series_motion(ts, xs, n, ts[i] - h, &vl);
        const double xr = sph_series_motion(ts, xs, n, ts[i] + h, &vr);
        assert_true(fabs(xl - xr) < 1e-8 && fabs(vl - vr) < 1e-5);
        assert_true(fabs(0.5 * (vl + vr)) < 1e-6 && sph_series_slope(ts, xs, n, i) == 0.0);
    }
    {
        const double t2[] = {0.0, 1.0, 3.0}, x2[] = {0.0, 0.02, 0.03};
        /* chords 0.02 and 0.005, h0 = 1, h1 = 2: 3 (1 + 2) / ((2 2 + 1) / 0.02 + (2 + 2 1) /
         * 0.005) = 9 / (250 + 800) */
        assert_true(fabs(sph_series_slope(t2, x2, 3, 1) - 9.0 / 1050.0) < 1e-15);
    }
    const double t3[] = {0.0, 1.0, 2.0, 3.0}, x3[] = {0.0, 0.0, 1.5, 1.5};
    for (double t = 0.0; t <= 3.0; t += 0.01) {
        const double X = sph_series_motion(t3, x3, 4, t, &v);
        assert_true(X >= -1e-15 && X <= 1.5 + 1e-15);
    }
    assert_true(sph_series_motion(ts, xs, n, -1.0, &v) == 0.0 && v == 0.0);
    assert_true(sph_series_motion(ts, xs, n, 9.0, &v) == 0.0 && v == 0.0);
    for (double t = 0.05; t < 2.0; t += 0.0731) {
        double vp, vm;
        const double h = 1e-6;
        sph_series_motion(ts, xs, n, t, &v);
        const double d =
            (sph_series_motion(ts, xs, n, t + h, &vp) - sph_series_motion(ts, xs, n, t - h, &vm)) /
            (2.0 * h);
        assert_true(fabs(v - d) < 1e-7);
    }
}

/* The series' text: a header, comments, blank lines and separators; its errors at
 * /wavemaker/waves/file naming the line. */
static void series_parse(void **state)
{
    (void)state;
    sph_wave_series q;
    sph_error err;
    const char *ok =
        "\xef\xbb\xbftime,displacement\n# a comment\n0, 0\n\n0.5;0.01\n"
        "1.0\t-0.02\r\n 1.5   0\n# a long comment ......................................"
        "............................................................................"
        "............................................................................"
        "............................................................................\n";
    assert_int_equal(sph_wave_series_parse(ok, strlen(ok), "m.csv", &q, &err), 0);
    assert_int_equal(q.n, 4);
    assert_true(q.t[2] == 1.0 && q.x[2] == -0.02 && q.t[3] == 1.5 && q.x[1] == 0.01);
    sph_wave_series_free(&q);
    const struct {
        const char *text, *needle;
    } bad[] = {{"0,0\n1,0\n1,0.01\n", "line 3"},
               {"0,0\n1,0\n0.5,0.01\n", "does not increase"},
               {"0,0\n1,abc\n", "line 2"},
               {"0,0\n1,0,3\n", "line 2"},
               {"0,abc\n0,0\n1,0\n", "line 1"},
               {"t,x\n0,0\n", "at least 2 rows"},
               {"0,0\n1,0                                                                    "
                "                                                                             "
                "                                                                             "
                "                  x\n",
                "line 2"},
               {"", "at least 2 rows"}};
    for (size_t k = 0; k < sizeof bad / sizeof *bad; k++) {
        if (sph_wave_series_parse(bad[k].text, strlen(bad[k].text), "m.csv", &q, &err) == 0)
            fail_msg("series %zu accepted", k);
        assert_string_equal(err.path, "/wavemaker/waves/file");
        if (!strstr(err.message, bad[k].needle) || !strstr(err.message, "m.csv"))
            fail_msg("series %zu: \"%s\" lacks \"%s\"", k, err.message, bad[k].needle);
        assert_true(q.n == 0 && q.t == NULL);
    }
}

/* A series flume: cases/wave_flume.json's piston moved by rows (a ramped sine sampled every
 * 0.01 s) written to a file next to a case that names it, read by sph_case_load_files; the
 * paddle at rest + the law's X(t) after 300 steps; a checkpoint at step 100 (which carries the
 * rows) continues to the same bits. A second-order piston and an irregular sea (their own
 * laws) restart to the same bits too. */
static void series_flume(void **state)
{
    (void)state;
    char dir[] = "/tmp/sph_series_XXXXXX";
    assert_non_null(mkdtemp(dir));
    char file[256];
    snprintf(file, sizeof file, "%s/motion.csv", dir);
    FILE *f = fopen(file, "w");
    assert_non_null(f);
    fprintf(f, "time,displacement\n");
    for (int i = 0; i <= 300; i++) {
        const double t = 0.01 * i, r = t < 2.54 ? t / 2.54 : 1.0;
        fprintf(f, "%.17g,%.17g\n", t, 0.02 * r * r * sin(2.0 * PI * t / 1.27));
    }
    fclose(f);
    const char *const sets[] = {"dx=0.05", "wavemaker.layers=3", NULL};
    sph_case *cs = calloc(1, sizeof *cs);
    assert_non_null(cs);
    sph_error err;
    assert_int_equal(flume("{\"type\": \"series\", \"file\": \"motion.csv\"}", sets, cs, &err), 0);
    assert_null(cs->sim.wavemaker.series);
    /* sph_sim_create refuses a series not read */
    assert_null(sph_sim_create(&cs->sim, &err));
    assert_string_equal(err.path, "/wavemaker/waves/file");
    if (sph_case_load_files(cs, dir, NULL, &err))
        fail_msg("%s: %s", err.path, err.message);
    assert_non_null(cs->sim.wavemaker.series);
    assert_int_equal(cs->sim.wavemaker.series->n, 301);
    sph_sim *a = sph_sim_create(&cs->sim, &err);
    assert_non_null(a);
    const sph_wave_series *q = cs->sim.wavemaker.series;
    assert_true(q->t[300] == 3.0);
    assert_int_equal(sph_sim_advance(a, 100, INFINITY, &err), 0);
    void *buf;
    size_t len;
    assert_int_equal(sph_sim_save(a, &buf, &len, &err), 0);
    sph_case_clear(cs); /* the restored sim needs nothing of the case */
    sph_sim *b = sph_sim_restore(buf, len, &err);
    if (!b)
        fail_msg("%s: %s", err.path, err.message);
    free(buf);
    assert_int_equal(sph_sim_advance(a, 200, INFINITY, &err), 0);
    assert_int_equal(sph_sim_advance(b, 200, INFINITY, &err), 0);
    unit_same_bits(a, b);
    /* the paddle at rest + X(t), X from the file's rows (read again here) */
    sph_wave_series rows;
    {
        FILE *g = fopen(file, "rb");
        static char text[65536];
        const size_t got = fread(text, 1, sizeof text, g);
        fclose(g);
        assert_int_equal(sph_wave_series_parse(text, got, "motion.csv", &rows, &err), 0);
    }
    double v;
    const double X = sph_series_motion(rows.t, rows.x, rows.n, sph_sim_time(b), &v);
    assert_true(fabs(X) > 1e-4); /* 0.3 s into the ramp */
    sph_particle_view pv;
    sph_sim_particles(b, &pv);
    long np = 0;
    for (long i = 0; i < pv.n; i++) {
        if (pv.type[i] != 1 || pv.pos[1][i] < 0.0 || pv.pos[0][i] < 0.0 || pv.pos[0][i] > 0.3)
            continue;
        const double k = (0.2 - (pv.pos[0][i] - X)) / 0.05 - 0.5;
        assert_true(fabs(k - round(k)) < 1e-9 && fabs(pv.vel[0][i] - v) < 1e-12);
        np++;
    }
    assert_int_equal(np, 3 * 14);
    sph_wave_series_free(&rows);
    sph_sim_destroy(a);
    sph_sim_destroy(b);
    unlink(file);
    rmdir(dir);
    /* second order and an irregular sea: a restart to the same bits */
    const char *waves[] = {
        "{\"type\": \"regular\", \"height\": 0.05, \"period\": 1.27, \"order\": 2}",
        "{\"type\": \"irregular\", \"hs\": 0.04, \"tp\": 1.27, \"duration\": 60}",
        "{\"type\": \"regular\", \"height\": 0.05, \"period\": 1.27}"};
    const char *const active[] = {"dx=0.05", "wavemaker.layers=3", "wavemaker.absorption=active",
                                  "wavemaker.ramp=0.5", NULL};
    for (int k = 0; k < 3; k++) {
        assert_int_equal(flume(waves[k], k == 2 ? active : sets, cs, &err), 0);
        a = sph_sim_create(&cs->sim, &err);
        assert_non_null(a);
        assert_int_equal(sph_sim_advance(a, 60, INFINITY, &err), 0);
        assert_int_equal(sph_sim_save(a, &buf, &len, &err), 0);
        b = sph_sim_restore(buf, len, &err);
        assert_non_null(b);
        free(buf);
        assert_int_equal(sph_sim_advance(a, 120, INFINITY, &err), 0);
        assert_int_equal(sph_sim_advance(b, 120, INFINITY, &err), 0);
        unit_same_bits(a, b);
        if (k == 2) { /* the correction has moved the piston off its law */
            assert_true(fabs(a->paddle.st.xc) > 0.0 && a->paddle.st.xc == b->paddle.st.xc);
            assert_true(a->paddle.st.level0 > 0.35 && a->paddle.st.level0 < 0.41);
        }
        sph_sim_destroy(a);
        sph_sim_destroy(b);
        sph_case_clear(cs);
    }
    free(cs);
}

/* The new kinds' bad inputs, each at its path. */
static void bad_new_inputs(void **state)
{
    (void)state;
    const struct {
        const char *waves;
        const char *const *sets;
        const char *path;
    } bad[] = {
        /* second order: a flap; an Ursell number past 8 pi^2 / 3 (kd 0.34: T = 4 s) */
        {"{\"type\": \"regular\", \"height\": 0.05, \"period\": 1.27, \"order\": 2}",
         (const char *const[]){"wavemaker.type=flap", NULL}, "/wavemaker/waves/order"},
        {"{\"type\": \"regular\", \"height\": 0.05, \"period\": 4, \"order\": 2}", NULL,
         "/wavemaker/waves/order"},
        {"{\"type\": \"regular\", \"height\": 0.05, \"period\": 1.27, \"order\": 3}", NULL,
         "/wavemaker/waves/order"},
        /* irregular: too short, too many components, too steep, a height instead of hs, an
         * order, gamma out of range, no hs */
        {"{\"type\": \"irregular\", \"hs\": 0.04, \"tp\": 1.27, \"duration\": 12}", NULL,
         "/wavemaker/waves/duration"},
        {"{\"type\": \"irregular\", \"hs\": 0.04, \"tp\": 1.27, \"duration\": 2000}", NULL,
         "/wavemaker/waves/duration"},
        {"{\"type\": \"irregular\", \"hs\": 0.3, \"tp\": 1.27, \"duration\": 60}", NULL,
         "/wavemaker/waves/hs"},
        {"{\"type\": \"irregular\", \"height\": 0.04, \"hs\": 0.04, \"tp\": 1.27, "
         "\"duration\": 60}",
         NULL, "/wavemaker/waves/height"},
        {"{\"type\": \"irregular\", \"hs\": 0.04, \"tp\": 1.27, \"duration\": 60, \"order\": 1}",
         NULL, "/wavemaker/waves/order"},
        {"{\"type\": \"irregular\", \"hs\": 0.04, \"tp\": 1.27, \"duration\": 60, \"gamma\": 0.5}",
         NULL, "/wavemaker/waves/gamma"},
        {"{\"type\": \"irregular\", \"tp\": 1.27, \"duration\": 60}", NULL, "/wavemaker/waves/hs"},
        /* active absorption from a flap, with a series, with second order; an unknown kind */
        {"{\"type\": \"regular\", \"height\": 0.05, \"period\": 1.27}",
         (const char *const[]){"wavemaker.absorption=active", "wavemaker.type=flap", NULL},
         "/wavemaker/absorption"},
        {"{\"type\": \"series\", \"file\": \"m.csv\"}",
         (const char *const[]){"wavemaker.absorption=active", NULL}, "/wavemaker/absorption"},
        {"{\"type\": \"regular\", \"height\": 0.05, \"period\": 1.27, \"order\": 2}",
         (const char *const[]){"wavemaker.absorption=active", NULL}, "/wavemaker/absorption"},
        {"{\"type\": \"regular\", \"height\": 0.05, \"period\": 1.27}",
         (const char *const[]){"wavemaker.absorption=passive", NULL}, "/wavemaker/absorption"},
        /* an irregular sea without a ramp (it starts at a random displacement) */
        {"{\"type\": \"irregular\", \"hs\": 0.04, \"tp\": 1.27, \"duration\": 60}",
         (const char *const[]){"wavemaker.ramp=0", NULL}, "/wavemaker/ramp"},
        /* active absorption with no water at the face to read */
        {"{\"type\": \"regular\", \"height\": 0.05, \"period\": 1.27}",
         (const char *const[]){"wavemaker.absorption=active", "fluid.0.box.min.0=0.3", NULL},
         "/wavemaker/absorption"},
        /* a series without its file, with a height */
        {"{\"type\": \"series\"}", NULL, "/wavemaker/waves/file"},
        {"{\"type\": \"series\", \"file\": \"m.csv\", \"height\": 0.1}", NULL,
         "/wavemaker/waves/height"},
    };
    for (size_t k = 0; k < sizeof bad / sizeof *bad; k++) {
        sph_case *cs = calloc(1, sizeof *cs);
        assert_non_null(cs);
        sph_error err;
        const int rc = flume(bad[k].waves, bad[k].sets, cs, &err);
        sph_case_clear(cs);
        free(cs);
        if (rc == 0 || strcmp(err.path, bad[k].path) != 0)
            fail_msg("case %zu: %s (%s), expected an error at %s", k, rc ? err.path : "accepted",
                     rc ? err.message : "", bad[k].path);
    }
    /* active absorption on the GPU (the wavemaker's own check: a build without CUDA refuses the
     * device first) */
    {
        sph_case *cs = calloc(1, sizeof *cs);
        assert_non_null(cs);
        sph_error err;
        assert_int_equal(flume("{\"type\": \"regular\", \"height\": 0.05, \"period\": 1.27}",
                               (const char *const[]){"wavemaker.absorption=active", NULL}, cs,
                               &err),
                         0);
        cs->sim.device = SPH_DEVICE_GPU;
        assert_int_not_equal(sph_wavemaker_check(&cs->sim, &err), 0);
        assert_string_equal(err.path, "/wavemaker/absorption");
        sph_case_clear(cs);
        free(cs);
    }
    /* a series whose first row comes later than 0 starts from rest at 0 (an implied row),
     * however far its first row lies (0.1 m at 2 s: 0.05 m/s, no jump) */
    {
        sph_case *cs = calloc(1, sizeof *cs);
        assert_non_null(cs);
        sph_error err;
        assert_int_equal(flume("{\"type\": \"series\", \"file\": \"m.csv\"}",
                               (const char *const[]){"dx=0.05", "wavemaker.layers=3", NULL}, cs,
                               &err),
                         0);
        double t[] = {2.0, 3.0}, x[] = {0.1, 0.1};
        sph_wave_series q = {.n = 2, .t = t, .x = x};
        cs->sim.wavemaker.series = &q;
        sph_sim *s = sph_sim_create(&cs->sim, &err);
        if (!s)
            fail_msg("%s: %s", err.path, err.message);
        double v;
        assert_int_equal(s->paddle.rows.n, 3);
        assert_true(sph_paddle_motion(&s->paddle.law, 0.0, &v) == 0.0 && v == 0.0);
        assert_true(sph_paddle_motion(&s->paddle.law, 2.0, &v) == 0.1);
        const double X1 = sph_paddle_motion(&s->paddle.law, 1.0, &v);
        assert_true(X1 > 0.0 && X1 < 0.1 && v > 0.0);
        sph_sim_destroy(s);
        cs->sim.wavemaker.series = NULL;
        sph_case_clear(cs);
        free(cs);
    }
    /* a series' rows: a jump (from rest at t = 0 to 5 mm; 0.5 m in 0.1 s, faster than sqrt(g d)
     * = 1.98 m/s), a stroke through the tank's wall */
    const struct {
        double t[3], x[3];
        const char *path, *needle;
    } rows[] = {{{0.0, 1.0, 2.0}, {0.005, 0.0, 0.0}, "/wavemaker/waves/file", "row 1"},
                {{0.0, 0.1, 2.0}, {0.0, 0.5, 0.0}, "/wavemaker/waves/file", "row 2"},
                {{0.0, 1.0, 2.0}, {0.0, -0.15, 0.0}, "/wavemaker/x", "back"}};
    for (size_t k = 0; k < sizeof rows / sizeof *rows; k++) {
        sph_case *cs = calloc(1, sizeof *cs);
        assert_non_null(cs);
        sph_error err;
        assert_int_equal(flume("{\"type\": \"series\", \"file\": \"m.csv\"}", NULL, cs, &err), 0);
        sph_wave_series q = {.n = 3, .t = (double *)rows[k].t, .x = (double *)rows[k].x};
        cs->sim.wavemaker.series = &q;
        const int rc = sph_sim_check(&cs->sim, &err);
        cs->sim.wavemaker.series = NULL;
        sph_case_clear(cs);
        free(cs);
        if (rc == 0 || strcmp(err.path, rows[k].path) != 0 || !strstr(err.message, rows[k].needle))
            fail_msg("rows %zu: %s (%s), expected an error at %s", k, rc ? err.path : "accepted",
                     rc ? err.message : "", rows[k].path);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(transfer_function),
        cmocka_unit_test(dispersion),
        cmocka_unit_test(ramp),
        cmocka_unit_test(damping_weight),
        cmocka_unit_test(solitary_law),
        cmocka_unit_test(flap_place),
        cmocka_unit_test(paddle_moves),
        cmocka_unit_test(restart_same_bits),
        cmocka_unit_test(damping_stops),
        cmocka_unit_test(bad_inputs),
        cmocka_unit_test(analysis_zero_up),
        cmocka_unit_test(analysis_window),
        cmocka_unit_test(analysis_developed_train),
        cmocka_unit_test(analysis_reflection),
        cmocka_unit_test(analysis_solitary),
        cmocka_unit_test(reflection_refused),
        cmocka_unit_test(second_order_law),
        cmocka_unit_test(irregular_sea),
        cmocka_unit_test(series_law),
        cmocka_unit_test(series_parse),
        cmocka_unit_test(series_flume),
        cmocka_unit_test(bad_new_inputs),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
