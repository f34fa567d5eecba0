/*
 * The wave flume (issue 45): the physics of boundary/sph_wave_law.h against values computed
 * independently, the paddle and the damping zone in a sim, the bad inputs, and a restart that
 * gives the same bits.
 *
 * - the piston's transfer function at kd = 1: 2 (cosh 2 - 1) / (sinh 2 + 2) = 0.98178930731303
 *   (evaluated in Python's math module), and its limits: 2kd in shallow water (kd -> 0; the
 *   series of both sides to first order), 2 in deep water;
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
 * - bad inputs: each refused at its field's path;
 * - the wave analysis (server/sphd_waves.c): a sampled sine's height and period by zero
 *   up-crossing; each gauge's window (ramp + 1) T + distance / cg with cg = 1.18939862610825
 *   m/s (Python: kd by bisection, cg = omega / (2k) (1 + 2kd / sinh 2kd)); linear theory's
 *   ramped train at the case's gauges (its envelope moving at cg) measured at H from the
 *   window on, which an analysis from the end of the ramp alone would not (its far gauges'
 *   windows would take in the growing front).
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "sph_case.h"
#include "sph_json.h"
#include "sph_sim.h"
#include "sph_wave_law.h"
#include "sphd_waves.h"
#include "unit_case.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void transfer_function(void **state)
{
    (void)state;
    assert_true(fabs(sph_piston_transfer(1.0) - 0.9817893073130344) < 1e-14);
    for (double kd = 1e-3; kd < 2e-2; kd *= 2.0) /* shallow water: H/S -> kd (1 + O(kd^2)) */
        assert_true(fabs(sph_piston_transfer(kd) / kd - 1.0) < kd);
    assert_true(fabs(sph_piston_transfer(20.0) - 2.0) < 1e-12); /* deep water */
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
    const sph_piston_law p = {.stroke = 0.04, .omega = 5.0, .tramp = 2.0};
    for (double t = 0.05; t < 4.0; t += 0.37) {
        double v, va, vb;
        sph_piston_motion(&p, t, &v);
        const double h = 1e-6;
        const double fd =
            (sph_piston_motion(&p, t + h, &va) - sph_piston_motion(&p, t - h, &vb)) / (2 * h);
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

/* The paddle's particles (boundary particles behind the face at x, within the stroke) at rest +
 * X(t), moving at dX/dt. */
static void paddle_moves(void **state)
{
    (void)state;
    const sph_config cfg = load_case("wave_flume.json", small);
    sph_error err;
    sph_sim *s = sph_sim_create(&cfg, &err);
    if (!s)
        fail_msg("%s: %s", err.path, err.message);
    sph_wave_design w;
    assert_int_equal(sph_sim_wave_design(&cfg, &w), 0);
    assert_true(fabs(w.k * w.depth - 1.19803592561098) < 1e-12);
    assert_int_equal(sph_sim_advance(s, 400, INFINITY, &err), 0);
    const sph_piston_law law = {
        .stroke = w.stroke, .omega = w.omega, .tramp = cfg.wavemaker.ramp * cfg.wavemaker.period};
    double v;
    const double X = sph_piston_motion(&law, sph_sim_time(s), &v);
    assert_true(fabs(X) > 1e-4); /* it has moved */
    sph_particle_view pv;
    sph_sim_particles(s, &pv);
    long np = 0;
    const double dx = cfg.dx, x0 = cfg.wavemaker.x;
    for (long i = 0; i < pv.n; i++) {
        if (pv.type[i] != 1 || pv.pos[1][i] < 0.0 || pv.pos[0][i] < cfg.tank.min[0] ||
            pv.pos[0][i] > 1.0)
            continue; /* the paddle: wall particles inside the tank, above its bottom */
        const double rest = pv.pos[0][i] - X;
        const double k = (x0 - rest) / dx - 0.5; /* its column behind the face */
        assert_true(fabs(k - round(k)) < 1e-9 && k >= -1e-9 && k < cfg.wavemaker.layers);
        assert_true(fabs(pv.vel[0][i] - v) < 1e-15 && pv.vel[1][i] == 0.0);
        np++;
    }
    assert_int_equal(np, cfg.wavemaker.layers * 14); /* 0.7 m of tank at dx = 0.05 */
    sph_sim_destroy(s);
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
    /* a flap, the GPU, mDBC: not in this version */
    refused((const char *const[]){"wavemaker.type=flap", NULL}, "/wavemaker/type");
    refused((const char *const[]){"device=gpu", NULL}, "/wavemaker");
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

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(transfer_function),
        cmocka_unit_test(dispersion),
        cmocka_unit_test(ramp),
        cmocka_unit_test(damping_weight),
        cmocka_unit_test(paddle_moves),
        cmocka_unit_test(restart_same_bits),
        cmocka_unit_test(damping_stops),
        cmocka_unit_test(bad_inputs),
        cmocka_unit_test(analysis_zero_up),
        cmocka_unit_test(analysis_window),
        cmocka_unit_test(analysis_developed_train),
        cmocka_unit_test(analysis_reflection),
        cmocka_unit_test(reflection_refused),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
