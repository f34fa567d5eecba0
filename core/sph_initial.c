/*
 * The table of initial fields (see sph_initial.h). Layer 2 of the set-up pipeline: may call
 * sph_lattice.h, sph_config.h and libm only.
 *
 * Standing wave (Macia et al., paper 001, section IV-B): a tank of length L holding water of
 * depth H, the wave number k = 2 pi / lambda with lambda = 2 L / n so that the side walls are
 * antinodes, omega^2 = g k tanh(k H). With the bottom at y = yb and the left wall at x = xl
 * (the paper's y + H and x),
 *     phi0 = -eps H g / (2 omega) cosh(k (y - yb)) / cosh(k H) cos(k (x - xl))       eq. (7)
 *     u = grad phi0 at t = 0, when the free surface is flat and the pressure hydrostatic.
 * Theory: period 2 pi / omega, kinetic-energy envelope decaying as exp(-4 nu k^2 t), and
 * E_kin(0) = rho0 eps^2 g lambda H^2 / 16 (eq. (8) at t = 0, per unit density in the paper).
 *
 * Solitary wave (Sheu et al., paper 004, section 5.1; the first-order Boussinesq wave): still depth
 * d (the whole rows of particles the fluid box holds: its height rounded down to a multiple of
 * dx, above its bottom yb), crest height H at x0, K = sqrt(3H / (4d^3)),
 *     eta = H sech^2(K (x - x0))                                                       eq. (5.1)
 *     u = sqrt(g d) (H/d) sech^2(K (x - x0))                                           eq. (5.2)
 *     v = sqrt(3 g d) (H/d)^(3/2) ((y - yb)/d) sech^2(K (x - x0)) tanh(K (x - x0)),
 * travelling towards +x at about sqrt(g (d + H)). It has no theory here: its run-up on the right
 * wall is compared with the reference table in the validation. That first-order field adjusts into
 * a wave about 3-4% higher than H (the validation's gauge, 5 depths before the wall).
 *
 * With "order": 3 it is Grimshaw's third-order solitary wave instead (R. Grimshaw 1971, "The
 * solitary wave in water of variable depth. Part 2", J. Fluid Mech. 46, 611-622; J. D. Fenton's
 * ninth-order series, J. Fluid Mech. 53 (1972) 257-271, extends it): with eps = H/d,
 * Y = (y - yb)/d, s = sech(alpha (x - x0)/d), t = tanh(alpha (x - x0)/d),
 *     alpha = sqrt(3 eps / 4) (1 - 5/8 eps + 71/128 eps^2)
 *     eta / d = eps s^2 - 3/4 eps^2 s^2 t^2 + eps^3 (5/8 s^2 t^2 - 101/80 s^4 t^2)
 *     u / sqrt(g d) = eps s^2 - eps^2 (-1/4 s^2 + s^4 + Y^2 (3/2 s^2 - 9/4 s^4))
 *                     - eps^3 (19/40 s^2 + 1/5 s^4 - 6/5 s^6
 *                              + Y^2 (-3/2 s^2 - 15/4 s^4 + 15/2 s^6)
 *                              + Y^4 (-3/8 s^2 + 45/16 s^4 - 45/16 s^6))
 *     v / sqrt(g d) = sqrt(3 eps) Y t (eps s^2 - eps^2 (3/8 s^2 + 2 s^4 + Y^2 (1/2 s^2 - 3/2 s^4))
 *                     - eps^3 (49/640 s^2 - 17/20 s^4 - 18/5 s^6
 *                              + Y^2 (-13/16 s^2 - 25/16 s^4 + 15/2 s^6)
 *                              + Y^4 (-3/40 s^2 + 9/8 s^4 - 27/16 s^6)))
 *     c / sqrt(g d) = 1 + 1/2 eps - 3/20 eps^2 + 3/56 eps^3 (its speed; the field does not use it).
 * The coefficients as in OpenFOAM's IH-Cantabria wave model (openfoam.com's src/waveModels/
 * waveGenerationModels/derived/Grimshaw/GrimshawWaveModel.C: alpha, eta and u the same, its c the
 * same to eps^3; its vertical velocity lacks the factor sqrt(3 eps) Y t and has -9/8 for +9/8,
 * with which div u is only O(eps^3.5)), and checked numerically (a throwaway numpy check,
 * d = g = 1; test_initial repeats it at two heights): div u and the kinematic surface condition
 * (u - c) d eta/dx = v at y = d + eta leave O(eps^4.5), curl u and Bernoulli's condition at the
 * surface O(eps^4) (each residual falls 2^4 to 2^4.5 times as eps halves from 0.2 to 0.0125).
 * Its range: H <= d/3. The exact wave's u (harmonic: div u = curl u = 0) has its maximum along x
 * under the crest at every height, so u_yy = -u_xx >= 0 there and, with u_y = 0 at the bed, u
 * grows from the bed to the surface; the
 * series gives u_y = 3/2 eps^2 Y (1 - eps (3 - Y^2)) at the crest, which turns negative near the
 * bed once eps > 1/3 (and at eps > 0.57 the bed's velocity exceeds the surface's).
 */
#include "sph_initial.h"

#include "sph_config.h"
#include "sph_lattice.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

typedef struct field {
    const char *name;
    int nparams;
    sph_initial_param params[SPH_INITIAL_MAX_PARAMS];
    int (*check)(const sph_config *c, sph_error *err);
    void (*velocity)(const sph_config *c, const double *x, double *v);
    int (*theory)(const sph_config *c, sph_initial_theory *t);
    double (*elevation)(const sph_config *c, double x); /* NULL: the surface stays flat */
    double (*elevation_max)(const sph_config *c);       /* its largest value over the tank */
} field;

/* ---- rest ---- */

static int rest_check(const sph_config *c, sph_error *err)
{
    (void)c;
    (void)err;
    return 0;
}

static void rest_velocity(const sph_config *c, const double *x, double *v)
{
    (void)x;
    for (int d = 0; d < c->dim; d++)
        v[d] = 0.0;
}

/* ---- standing wave ---- */

enum { SW_EPSILON = 0, SW_WAVELENGTH };

typedef struct wave {
    double eps, H, k, omega, g, xl, yb, lambda;
} wave;

static wave sw_of(const sph_config *c)
{
    wave w;
    w.eps = c->initial.param[SW_EPSILON];
    w.xl = c->tank.min[0];
    w.yb = c->tank.min[1];
    w.H = c->fluid[0].max[1] - w.yb;
    const double L = c->tank.max[0] - c->tank.min[0];
    w.lambda = c->initial.param[SW_WAVELENGTH] > 0.0 ? c->initial.param[SW_WAVELENGTH] : L;
    w.k = 2.0 * M_PI / w.lambda;
    w.g = -c->gravity[1];
    w.omega = sqrt(w.g * w.k * tanh(w.k * w.H));
    return w;
}

/* What the wave fields ask of a case: 2D, a tank whose one fluid box fills it from wall to wall
 * and from its bottom up to the still depth, gravity along -y. `what` names the field. */
static int wave_tank_check(const sph_config *c, const char *what, sph_error *err)
{
    if (c->dim != 2)
        return sph_error_set(err, SPH_ERR_INVALID, "/initial/type",
                             "the %s is a 2D field (dim = 2)", what);
    if (!c->has_tank)
        return sph_error_set(err, SPH_ERR_INVALID, "/initial/type",
                             "the %s needs a tank: its side walls bound the wave (boundary.tank)",
                             what);
    if (!(c->gravity[1] < 0.0) || c->gravity[0] != 0.0)
        return sph_error_set(err, SPH_ERR_INVALID, "/physics/gravity",
                             "the %s needs gravity along -y", what);
    const double tol = 0.5 * c->dx;
    const sph_box *f = &c->fluid[0], *t = &c->tank;
    if (c->nfluid != 1 || fabs(f->min[0] - t->min[0]) > tol || fabs(f->max[0] - t->max[0]) > tol ||
        fabs(f->min[1] - t->min[1]) > tol)
        return sph_error_set(err, SPH_ERR_INVALID, "/fluid",
                             "the %s needs one fluid box filling the tank from wall to wall and "
                             "from its bottom up to the still depth",
                             what);
    return 0;
}

static int sw_check(const sph_config *c, sph_error *err)
{
    if (wave_tank_check(c, "standing wave", err))
        return SPH_ERR_INVALID;
    const sph_box *f = &c->fluid[0], *t = &c->tank;
    const double L = t->max[0] - t->min[0];
    const double lambda =
        c->initial.param[SW_WAVELENGTH] > 0.0 ? c->initial.param[SW_WAVELENGTH] : L;
    const double halves = 2.0 * L / lambda;
    if (fabs(halves - nearbyint(halves)) > 1e-6 * halves || nearbyint(halves) < 1.0)
        return sph_error_set(err, SPH_ERR_INVALID, "/initial/wavelength",
                             "the wavelength %g m does not fit the tank: the walls must be "
                             "antinodes, so the tank length %g m must be a whole number of half "
                             "wavelengths",
                             lambda, L);
    const wave w = sw_of(c);
    if (!(w.eps * w.H / 2.0 < 0.5 * (f->max[1] - f->min[1])))
        return sph_error_set(err, SPH_ERR_INVALID, "/initial/epsilon",
                             "epsilon %g is too large for linear theory", w.eps);
    return 0;
}

static void sw_velocity(const sph_config *c, const double *x, double *v)
{
    const wave w = sw_of(c);
    const double a = w.eps * w.H * w.g * w.k / (2.0 * w.omega * cosh(w.k * w.H));
    const double ky = w.k * (x[1] - w.yb), kx = w.k * (x[0] - w.xl);
    /* u = d phi0/dx, v = d phi0/dy of eq. (7) */
    v[0] = a * cosh(ky) * sin(kx);
    v[1] = -a * sinh(ky) * cos(kx);
}

static int sw_theory(const sph_config *c, sph_initial_theory *t)
{
    const wave w = sw_of(c);
    t->omega = w.omega;
    t->period = 2.0 * M_PI / w.omega;
    t->decay_rate = 4.0 * sph_config_viscosity_nu(c) * w.k * w.k; /* Lighthill, eq. (8) */
    t->ekin0 = c->rho0 * w.eps * w.eps * w.g * w.lambda * w.H * w.H / 16.0;
    return 0;
}

/* ---- solitary wave ---- */

enum { SOL_HEIGHT = 0, SOL_CREST, SOL_ORDER };

typedef struct solitary {
    double H, d, K, x0, yb, g;
    int order; /* 1 or 3 */
} solitary;

static solitary sol_of(const sph_config *c)
{
    solitary w;
    w.H = c->initial.param[SOL_HEIGHT];
    w.x0 = c->initial.param[SOL_CREST];
    w.order = c->initial.param[SOL_ORDER] == 3.0 ? 3 : 1;
    w.yb = c->fluid[0].min[1];
    w.d = (double)sph_lattice_axis_count(w.yb, c->fluid[0].max[1], c->dx) * c->dx;
    w.g = -c->gravity[1];
    if (!(w.d > 0.0))
        w.K = 0.0;
    else if (w.order == 1)
        w.K = sqrt(3.0 * w.H / (4.0 * w.d * w.d * w.d));
    else { /* alpha / d */
        const double e = w.H / w.d;
        w.K = sqrt(0.75 * e) * (1.0 - 0.625 * e + 71.0 / 128.0 * e * e) / w.d;
    }
    return w;
}

static int sol_check(const sph_config *c, sph_error *err)
{
    if (wave_tank_check(c, "solitary wave", err))
        return SPH_ERR_INVALID;
    const double order = c->initial.param[SOL_ORDER];
    if (order != 1.0 && order != 3.0)
        return sph_error_set(err, SPH_ERR_INVALID, "/initial/order",
                             "the solitary wave's order must be 1 (paper 004's first-order field) "
                             "or 3 (Grimshaw's third order), got %g",
                             order);
    const solitary w = sol_of(c);
    if (!(w.H <= SPH_SOL_HEIGHT_RATIO * w.d))
        return sph_error_set(err, SPH_ERR_INVALID, "/initial/height",
                             "the wave height %g m is more than %g times the still depth %g m: "
                             "such a wave breaks",
                             w.H, SPH_SOL_HEIGHT_RATIO, w.d);
    if (w.order == 3 && !(w.H <= SPH_SOL_HEIGHT_RATIO_3 * w.d))
        return sph_error_set(err, SPH_ERR_INVALID, "/initial/height",
                             "the wave height %g m is more than a third of the still depth %g m, "
                             "beyond the third-order field's range: its velocity under the crest "
                             "no longer grows from the bed to the surface (order 1 allows %g d)",
                             w.H, w.d, SPH_SOL_HEIGHT_RATIO);
    if (!(w.H >= c->dx))
        return sph_error_set(err, SPH_ERR_INVALID, "/initial/height",
                             "the wave height %g m is below the particle spacing dx = %g m: the "
                             "lattice cannot resolve it",
                             w.H, c->dx);
    if (!(w.x0 > c->tank.min[0] && w.x0 < c->tank.max[0]))
        return sph_error_set(err, SPH_ERR_INVALID, "/initial/crest",
                             "the crest x = %g m must lie inside the tank (%g to %g m)", w.x0,
                             c->tank.min[0], c->tank.max[0]);
    if (!(c->tank.max[1] - w.yb >= w.d + 2.0 * w.H))
        return sph_error_set(err, SPH_ERR_INVALID, "/boundary/tank/max/1",
                             "the tank's walls (%g m high) must reach the still depth plus twice "
                             "the wave height (%g m): the wave runs up a wall to about d + 2H",
                             c->tank.max[1] - w.yb, w.d + 2.0 * w.H);
    if (!(c->domain.max[1] >= c->tank.max[1]))
        return sph_error_set(err, SPH_ERR_INVALID, "/domain/max/1",
                             "the domain must reach the top of the tank's walls (%g m)",
                             c->tank.max[1]);
    return 0;
}

static double sech2(double a)
{
    const double ch = cosh(a);
    return isfinite(ch) ? 1.0 / (ch * ch) : 0.0;
}

/* Grimshaw's third order (the header's formulas) at a = alpha (x - x0) / d, Y = (y - yb) / d:
 * u and v over sqrt(g d). */
static void sol_velocity3(double e, double a, double Y, double *u, double *v)
{
    const double s2 = sech2(a), s4 = s2 * s2, s6 = s4 * s2, t = tanh(a);
    const double Y2 = Y * Y, Y4 = Y2 * Y2;
    *u = e * s2 - e * e * (-0.25 * s2 + s4 + Y2 * (1.5 * s2 - 2.25 * s4)) -
         e * e * e *
             (19.0 / 40.0 * s2 + 0.2 * s4 - 1.2 * s6 + Y2 * (-1.5 * s2 - 3.75 * s4 + 7.5 * s6) +
              Y4 * (-0.375 * s2 + 45.0 / 16.0 * s4 - 45.0 / 16.0 * s6));
    *v = sqrt(3.0 * e) * Y * t *
         (e * s2 - e * e * (0.375 * s2 + 2.0 * s4 + Y2 * (0.5 * s2 - 1.5 * s4)) -
          e * e * e *
              (49.0 / 640.0 * s2 - 0.85 * s4 - 3.6 * s6 +
               Y2 * (-13.0 / 16.0 * s2 - 25.0 / 16.0 * s4 + 7.5 * s6) +
               Y4 * (-0.075 * s2 + 1.125 * s4 - 27.0 / 16.0 * s6)));
}

static void sol_velocity(const sph_config *c, const double *x, double *v)
{
    const solitary w = sol_of(c);
    const double a = w.K * (x[0] - w.x0), e = w.H / w.d;
    if (w.order == 3) {
        const double cg = sqrt(w.g * w.d);
        sol_velocity3(e, a, (x[1] - w.yb) / w.d, &v[0], &v[1]);
        v[0] *= cg;
        v[1] *= cg;
        return;
    }
    const double s = sech2(a);
    v[0] = sqrt(w.g * w.d) * e * s;
    v[1] = sqrt(3.0 * w.g * w.d) * e * sqrt(e) * ((x[1] - w.yb) / w.d) * s * tanh(a);
}

static double sol_elevation(const sph_config *c, double x)
{
    const solitary w = sol_of(c);
    if (w.order == 3) {
        const double e = w.H / w.d, a = w.K * (x - w.x0);
        const double s2 = sech2(a), t2 = tanh(a) * tanh(a);
        return w.d * (e * s2 - 0.75 * e * e * s2 * t2 +
                      e * e * e * (0.625 * s2 * t2 - 101.0 / 80.0 * s2 * s2 * t2));
    }
    return w.H * sech2(w.K * (x - w.x0));
}

/* the crest's height where it lies inside the tank, else the higher wall's elevation (the
 * surface falls off monotonically on each side of the crest, at the third order too up to
 * H/d = 0.85) */
static double sol_elevation_max(const sph_config *c)
{
    const solitary w = sol_of(c);
    if (w.x0 > c->tank.min[0] && w.x0 < c->tank.max[0])
        return w.H;
    return fmax(sol_elevation(c, c->tank.min[0]), sol_elevation(c, c->tank.max[0]));
}

static const field fields[SPH_INITIAL_COUNT] = {
    [SPH_INITIAL_REST] = {"rest", 0, {{0}}, rest_check, rest_velocity, NULL, NULL, NULL},
    [SPH_INITIAL_STANDING_WAVE] =
        {"standing_wave",
         2,
         {[SW_EPSILON] = {"epsilon", "-", SPH_SW_EPSILON_DEFAULT, SPH_SW_EPSILON_MIN,
                          SPH_SW_EPSILON_MAX,
                          "2A/H: twice the wave amplitude over the still depth"},
          [SW_WAVELENGTH] = {"wavelength", "m", SPH_SW_WAVELENGTH_DEFAULT, SPH_SW_WAVELENGTH_MIN,
                             SPH_SW_WAVELENGTH_MAX, "lambda; 0 (the default): the tank's length"}},
         sw_check,
         sw_velocity,
         sw_theory,
         NULL,
         NULL},
    [SPH_INITIAL_SOLITARY_WAVE] =
        {"solitary_wave",
         3,
         {[SOL_HEIGHT] = {"height", "m", 0.0, 0.0, SPH_SOL_HEIGHT_MAX,
                          "H: the crest's height above the still water (at most 0.7 d; d/3 at "
                          "order 3)"},
          [SOL_CREST] = {"crest", "m", 0.0, -SPH_SOL_CREST_MAX, SPH_SOL_CREST_MAX,
                         "x0: the crest's initial abscissa, inside the tank"},
          [SOL_ORDER] = {"order", "-", SPH_SOL_ORDER_DEFAULT, SPH_SOL_ORDER_MIN, SPH_SOL_ORDER_MAX,
                         "1: paper 004's first-order field (the default); 3: Grimshaw's (1971) "
                         "third order"}},
         sol_check,
         sol_velocity,
         NULL,
         sol_elevation,
         sol_elevation_max},
};

const char *sph_initial_name(sph_initial_type type)
{
    if ((int)type < 0 || type >= SPH_INITIAL_COUNT)
        return NULL;
    return fields[type].name;
}

int sph_initial_from_name(const char *name)
{
    for (int i = 0; i < SPH_INITIAL_COUNT; i++)
        if (name && strcmp(name, fields[i].name) == 0)
            return i;
    return -1;
}

const sph_initial_param *sph_initial_params(sph_initial_type type, int *n)
{
    *n = 0;
    if ((int)type < 0 || type >= SPH_INITIAL_COUNT)
        return NULL;
    *n = fields[type].nparams;
    return fields[type].params;
}

sph_initial_spec sph_initial_default(sph_initial_type type)
{
    sph_initial_spec s;
    memset(&s, 0, sizeof s);
    s.type = type;
    int n;
    const sph_initial_param *p = sph_initial_params(type, &n);
    for (int i = 0; i < n; i++)
        s.param[i] = p[i].def;
    return s;
}

int sph_initial_check(const sph_config *c, sph_error *err)
{
    const sph_initial_type t = c->initial.type;
    if ((int)t < 0 || t >= SPH_INITIAL_COUNT)
        return sph_error_set(err, SPH_ERR_INVALID, "/initial/type", "unknown initial field %d",
                             (int)t);
    const field *f = &fields[t];
    for (int i = 0; i < f->nparams; i++) {
        const sph_initial_param *p = &f->params[i];
        const double v = c->initial.param[i];
        if (!(v >= p->min && v <= p->max)) {
            char path[64];
            snprintf(path, sizeof path, "/initial/%s", p->name);
            return sph_error_set(err, SPH_ERR_INVALID, path, "%s must be in [%g, %g] %s, got %g",
                                 p->name, p->min, p->max, p->unit, v);
        }
    }
    return f->check(c, err);
}

void sph_initial_velocity(const sph_config *c, const double *x, double *v)
{
    fields[c->initial.type].velocity(c, x, v);
}

double sph_initial_elevation(const sph_config *c, double x)
{
    const field *f = &fields[c->initial.type];
    return f->elevation ? f->elevation(c, x) : 0.0;
}

double sph_initial_elevation_max(const sph_config *c)
{
    const field *f = &fields[c->initial.type];
    return f->elevation_max && c->has_tank ? f->elevation_max(c) : 0.0;
}

int sph_initial_theory_of(const sph_config *c, sph_initial_theory *t)
{
    memset(t, 0, sizeof *t);
    const field *f = &fields[c->initial.type];
    return f->theory ? f->theory(c, t) : -1;
}
