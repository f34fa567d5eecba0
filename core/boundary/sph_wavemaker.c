/*
 * sph_wavemaker: a wave flume's paddle and damping zone (sph_wavemaker.h).
 *
 * Layer 4 of the set-up pipeline beside the fill (it makes the paddle's particles) and a step
 * helper of the methods. May call: sph_wave_law.h, sph_lattice.h, libm.
 */
#include "sph_wavemaker.h"

#include "sph_lattice.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define PI 3.14159265358979323846

/* The paddle's first-order transfer function H / S at kd (a flap's with its hinge). */
static double transfer(const sph_config *c, double kd, double depth)
{
    return c->wavemaker.type == SPH_WAVEMAKER_FLAP
               ? sph_flap_transfer(kd, c->wavemaker.hinge / depth)
               : sph_piston_transfer(kd);
}

int sph_wave_design_of(const sph_config *c, sph_wave_design *w)
{
    const sph_wavemaker_spec *m = &c->wavemaker;
    const int V = c->dim - 1; /* the vertical axis */
    double top = -INFINITY;
    for (int b = 0; b < c->nfluid; b++)
        top = fmax(top, c->fluid[b].max[V]);
    const double g = -c->gravity[V];
    *w = (sph_wave_design){.depth = top - c->tank.min[V]};
    if (!(w->depth > 0.0) || !(g > 0.0) || !isfinite(w->depth))
        return -1;
    if ((m->waves == SPH_WAVES_REGULAR || m->waves == SPH_WAVES_SOLITARY) && !(m->height > 0.0))
        return -1;
    if (m->waves == SPH_WAVES_SOLITARY) {
        const double d = w->depth, H = m->height;
        w->kappa = sqrt(3.0 * H / (4.0 * d * d * d));
        w->celerity = sqrt(g * (d + H));
        w->stroke = 2.0 * H / (w->kappa * d);
        w->duration = 2.0 * (SPH_SOLITARY_THETA0 + H / d) / (w->kappa * w->celerity);
        w->lag = SPH_SOLITARY_THETA0 / w->kappa;
        return 0;
    }
    if (m->waves == SPH_WAVES_SERIES)
        return 0; /* no theory: the file's motion */
    const double period = m->waves == SPH_WAVES_IRREGULAR ? m->tp : m->period;
    w->omega = 2.0 * PI / period;
    if (!(w->omega > 0.0) || !isfinite(w->omega))
        return -1;
    w->k = sph_wave_number(w->omega, g, w->depth);
    w->length = 2.0 * PI / w->k;
    const double kd = w->k * w->depth;
    w->stroke = (m->waves == SPH_WAVES_IRREGULAR ? m->hs : m->height) / transfer(c, kd, w->depth);
    w->cg = 0.5 * w->omega / w->k * (1.0 + 2.0 * kd / sinh(2.0 * kd));
    return 0;
}

/* The splitmix64 generator (Steele, Lea & Flood 2014): the irregular sea's phases, the same on
 * every platform for a seed. */
static uint64_t splitmix64(uint64_t *state)
{
    uint64_t z = (*state += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
}

/* The frequency indices [lo, hi] of c's irregular sea's components, f_i = i / duration in [0.5,
 * 3] times the peak's; their count. */
static long component_range(const sph_wavemaker_spec *m, long *lo, long *hi)
{
    const double fp = 1.0 / m->tp;
    *lo = (long)ceil(0.5 * fp * m->duration - 1e-9);
    *hi = (long)floor(3.0 * fp * m->duration + 1e-9);
    if (*lo < 1)
        *lo = 1;
    return *hi >= *lo ? *hi - *lo + 1 : 0;
}

int sph_wave_components(const sph_config *c, double depth, double **comp, double **tf)
{
    const sph_wavemaker_spec *m = &c->wavemaker;
    const double g = -c->gravity[c->dim - 1];
    long lo, hi;
    const long n = component_range(m, &lo, &hi);
    *comp = NULL;
    if (tf)
        *tf = NULL;
    if (n < 1 || n > SPH_IRREGULAR_COMPONENTS || !(depth > 0.0) || !(g > 0.0))
        return 0;
    double *a = malloc((size_t)n * 3 * sizeof *a), *h = tf ? malloc((size_t)n * sizeof *h) : NULL;
    if (!a || (tf && !h)) {
        free(a);
        free(h);
        return -1;
    }
    const double fp = 1.0 / m->tp, df = 1.0 / m->duration;
    double sum = 0.0;
    for (long i = 0; i < n; i++) {
        a[3 * i] = sph_jonswap_shape((double)(lo + i) * df, fp, m->gamma);
        sum += a[3 * i] * df;
    }
    const double scale = m->hs * m->hs / 16.0 / sum; /* 4 sqrt(m0) = Hs */
    uint64_t state = (uint64_t)m->seed;
    for (long i = 0; i < n; i++) {
        const double f = (double)(lo + i) * df, omega = 2.0 * PI * f;
        const double amp = sqrt(2.0 * scale * a[3 * i] * df); /* the wave's amplitude */
        const double kd = sph_wave_number(omega, g, depth) * depth, hs = transfer(c, kd, depth);
        a[3 * i] = amp / hs;
        if (h)
            h[i] = hs;
        a[3 * i + 1] = omega;
        a[3 * i + 2] = 2.0 * PI * (double)(splitmix64(&state) >> 11) * 0x1.0p-53;
    }
    *comp = a;
    if (tf)
        *tf = h;
    return (int)n;
}

/* The paddle's excursion at the still water level: how far forward (*fwd) and back (*bwd) of
 * rest its face goes over the whole motion; 0, or -1 out of memory. */
static int excursion(const sph_config *c, const sph_wave_design *d, double *fwd, double *bwd)
{
    const sph_wavemaker_spec *m = &c->wavemaker;
    *fwd = *bwd = 0.0;
    switch (m->waves) {
    case SPH_WAVES_SOLITARY:
        *fwd = d->stroke;
        return 0;
    case SPH_WAVES_REGULAR: {
        const double a2 =
            m->order == 2 ? fabs(sph_madsen_second(d->k * d->depth, m->height, d->depth)) : 0.0;
        *fwd = *bwd = 0.5 * d->stroke + a2;
        return 0;
    }
    case SPH_WAVES_SERIES:
        for (long i = 0; m->series && i < m->series->n; i++) {
            *fwd = fmax(*fwd, m->series->x[i]);
            *bwd = fmax(*bwd, -m->series->x[i]);
        }
        return 0;
    case SPH_WAVES_IRREGULAR: { /* sampled 8 times a period of the highest component, each
                                 * component's phase turned by rotation, not sin and cos */
        double *comp;
        const int n = sph_wave_components(c, d->depth, &comp, NULL);
        if (n < 0)
            return -1;
        double *rot = n > 0 ? malloc((size_t)n * 4 * sizeof *rot) : NULL;
        if (n > 0 && !rot) {
            free(comp);
            return -1;
        }
        const double wmax = n > 0 ? comp[3 * (n - 1) + 1] : 1.0;
        const long ns = (long)ceil(8.0 * m->duration * wmax / (2.0 * PI));
        const double step = m->duration / (double)(ns > 0 ? ns : 1);
        for (int i = 0; i < n; i++) { /* (cos, sin) of the phase, and of its step */
            rot[4 * i] = cos(comp[3 * i + 2]);
            rot[4 * i + 1] = sin(comp[3 * i + 2]);
            rot[4 * i + 2] = cos(comp[3 * i + 1] * step);
            rot[4 * i + 3] = sin(comp[3 * i + 1] * step);
        }
        for (long j = 0; j < ns && n > 0; j++) {
            double X = 0.0;
            for (int i = 0; i < n; i++) {
                double *q = rot + 4 * i;
                X += comp[3 * i] * q[1];
                const double cj = q[0] * q[2] - q[1] * q[3], sj = q[1] * q[2] + q[0] * q[3];
                q[0] = cj;
                q[1] = sj;
            }
            *fwd = fmax(*fwd, X);
            *bwd = fmax(*bwd, -X);
        }
        free(rot);
        free(comp);
        return 0;
    }
    default:
        return 0;
    }
}

static int absorption_check(const sph_config *c, double lo, double hi, sph_error *err)
{
    const sph_absorption_spec *a = &c->absorption;
    if (a->type == 0)
        return 0;
    if (a->type != 1)
        return sph_error_set(err, SPH_ERR_INVALID, "/absorption/type",
                             "unknown absorption: \"damping\"");
    if (c->method != SPH_METHOD_WCSPH)
        return sph_error_set(err, SPH_ERR_INVALID, "/absorption",
                             "a damping zone needs the wcsph method in this version");
    if (!(a->beta >= 0.0) || !isfinite(a->beta))
        return sph_error_set(err, SPH_ERR_INVALID, "/absorption/beta",
                             "beta must be a number >= 0 [1/s]");
    const double *dom = NULL;
    const char *path = NULL;
    if (!(a->from >= c->domain.min[0] && a->from <= c->domain.max[0]))
        dom = &a->from, path = "/absorption/from";
    else if (!(a->to >= c->domain.min[0] && a->to <= c->domain.max[0]))
        dom = &a->to, path = "/absorption/to";
    if (dom)
        return sph_error_set(err, SPH_ERR_INVALID, path,
                             "the damping zone's end %g m is outside the domain ([%g, %g] m)", *dom,
                             c->domain.min[0], c->domain.max[0]);
    if (!(a->to != a->from))
        return sph_error_set(err, SPH_ERR_INVALID, "/absorption/to",
                             "the damping zone needs 'to' different from 'from'");
    const double zlo = fmin(a->from, a->to), zhi = fmax(a->from, a->to);
    if (lo < hi && zlo < hi && zhi > lo)
        return sph_error_set(err, SPH_ERR_INVALID, "/absorption/from",
                             "the damping zone [%g, %g] m overlaps the paddle's travel [%g, %g] "
                             "m: put it at the flume's far end",
                             zlo, zhi, lo, hi);
    return 0;
}

int sph_wavemaker_check(const sph_config *c, sph_error *err)
{
    const sph_wavemaker_spec *w = &c->wavemaker;
    if (w->type == SPH_WAVEMAKER_NONE)
        return absorption_check(c, 0.0, 0.0, err);
    if ((unsigned)w->type >= SPH_WAVEMAKER_COUNT || (unsigned)w->waves >= SPH_WAVES_COUNT)
        return sph_error_set(err, SPH_ERR_INVALID, "/wavemaker/type",
                             "unknown wavemaker or waves type");
    if (c->method != SPH_METHOD_WCSPH)
        return sph_error_set(err, SPH_ERR_INVALID, "/wavemaker",
                             "a wavemaker needs the wcsph method in this version");
    if (c->boundary != SPH_BOUNDARY_DYNAMIC || !c->has_tank)
        return sph_error_set(err, SPH_ERR_INVALID, "/wavemaker",
                             "a paddle is made of dynamic wall particles: it needs a tank with "
                             "\"type\": \"dynamic\" walls");
    for (int k = 0; k < c->ngeometry; k++)
        if (c->geometry[k].role == SPH_ROLE_FLUID) {
            char path[64];
            snprintf(path, sizeof path, "/geometry/%d/role", k);
            return sph_error_set(err, SPH_ERR_INVALID, path,
                                 "with a wavemaker the water is the fluid boxes (its depth and "
                                 "its place in front of the paddle are theirs): give structures "
                                 "and beaches as wall, obstacle or void items");
        }
    if (c->wall_density != SPH_WALL_CONTINUITY)
        return sph_error_set(err, SPH_ERR_INVALID, "/boundary/density",
                             "mDBC walls do not move in this version: a wavemaker needs "
                             "\"continuity\" walls");
    if (!(w->layers >= 1 && w->layers <= 8))
        return sph_error_set(err, SPH_ERR_INVALID, "/wavemaker/layers",
                             "layers must be from 1 to 8");
    const int solitary = w->waves == SPH_WAVES_SOLITARY;
    const int irregular = w->waves == SPH_WAVES_IRREGULAR, series = w->waves == SPH_WAVES_SERIES;
    if ((w->waves == SPH_WAVES_REGULAR || solitary) && (!(w->height > 0.0) || !isfinite(w->height)))
        return sph_error_set(err, SPH_ERR_INVALID, "/wavemaker/waves/height",
                             "the wave height must be positive");
    if (irregular) {
        if (!(w->hs > 0.0) || !isfinite(w->hs))
            return sph_error_set(err, SPH_ERR_INVALID, "/wavemaker/waves/hs",
                                 "the significant wave height must be positive");
        if (!(w->tp > 0.0) || !isfinite(w->tp))
            return sph_error_set(err, SPH_ERR_INVALID, "/wavemaker/waves/tp",
                                 "the peak period must be positive [s]");
        if (!(w->gamma >= 1.0 && w->gamma <= 10.0))
            return sph_error_set(err, SPH_ERR_INVALID, "/wavemaker/waves/gamma",
                                 "the peak enhancement factor must be from 1 (Pierson-Moskowitz) "
                                 "to 10");
        if (!(w->duration <= 1e5) || !(w->duration <= 1e6 * w->tp))
            return sph_error_set(err, SPH_ERR_INVALID, "/wavemaker/waves/duration",
                                 "the irregular sea's duration must be at most 1e5 s and a "
                                 "million peak periods");
        if (!(w->ramp > 0.0))
            return sph_error_set(err, SPH_ERR_INVALID, "/wavemaker/ramp",
                                 "an irregular sea starts at a random displacement: give it a "
                                 "ramp (more than 0 peak periods; 2 is the default)");
        long lo, hi;
        const long nc = component_range(w, &lo, &hi);
        if (!(w->duration >= 10.0 * w->tp) || !isfinite(w->duration))
            return sph_error_set(err, SPH_ERR_INVALID, "/wavemaker/waves/duration",
                                 "the irregular sea's duration (%g s) must be at least 10 peak "
                                 "periods (%g s): its components are 1 / duration apart",
                                 w->duration, 10.0 * w->tp);
        if (nc > SPH_IRREGULAR_COMPONENTS)
            return sph_error_set(err, SPH_ERR_INVALID, "/wavemaker/waves/duration",
                                 "a duration of %g s makes %ld components (1 / duration apart "
                                 "from 0.5 to 3 times the peak frequency), more than %d: "
                                 "shorten it (the motion repeats after it)",
                                 w->duration, nc, SPH_IRREGULAR_COMPONENTS);
    }
    if (w->order != 1 && w->order != 2)
        return sph_error_set(err, SPH_ERR_INVALID, "/wavemaker/waves/order", "the order is 1 or 2");
    if (w->active) {
        const char *why = w->type != SPH_WAVEMAKER_PISTON ? "it moves a piston: use \"piston\""
                          : series        ? "a series gives no level to aim at at the paddle"
                          : w->order == 2 ? "its target is first-order theory's: use order 1"
                          : c->device == SPH_DEVICE_GPU
                              ? "it reads the water level at the paddle on the host after every "
                                "step, which the GPU's step keeps on the device: run it on the "
                                "CPU"
                              : NULL;
        if (why)
            return sph_error_set(err, SPH_ERR_INVALID, "/wavemaker/absorption",
                                 "active absorption: %s", why);
        int wet = 0; /* it reads the level over [x + dx, x + 3 dx] */
        for (int b = 0; b < c->nfluid; b++)
            wet |= c->fluid[b].min[0] <= w->x + c->dx && c->fluid[b].max[0] >= w->x + 3.0 * c->dx;
        if (!wet)
            return sph_error_set(err, SPH_ERR_INVALID, "/wavemaker/absorption",
                                 "active absorption reads the water level just in front of the "
                                 "piston: a fluid box must start at its face (x = %g m)",
                                 w->x);
    }
    if (w->order == 2 && (w->waves != SPH_WAVES_REGULAR || w->type != SPH_WAVEMAKER_PISTON))
        return sph_error_set(err, SPH_ERR_INVALID, "/wavemaker/waves/order",
                             "second order (Madsen 1971) is for regular waves from a piston");
    if (solitary && w->type == SPH_WAVEMAKER_FLAP)
        return sph_error_set(err, SPH_ERR_INVALID, "/wavemaker/type",
                             "a solitary wave comes from a piston (Goring's law): use "
                             "\"piston\"");
    if (w->waves == SPH_WAVES_REGULAR && (!(w->period > 0.0) || !isfinite(w->period)))
        return sph_error_set(err, SPH_ERR_INVALID, "/wavemaker/waves/period",
                             "regular waves need a positive period [s]");
    if (solitary && w->period != 0.0)
        return sph_error_set(err, SPH_ERR_INVALID, "/wavemaker/waves/period",
                             "a solitary wave has no period: leave it out");
    if (!(w->ramp >= 0.0) || !isfinite(w->ramp))
        return sph_error_set(err, SPH_ERR_INVALID, "/wavemaker/ramp",
                             "the ramp must be 0 or more periods");
    if (!(w->x > c->tank.min[0] && w->x < c->tank.max[0]))
        return sph_error_set(err, SPH_ERR_INVALID, "/wavemaker/x",
                             "the paddle's face (x = %g m) must be inside the tank ((%g, %g) m)",
                             w->x, c->tank.min[0], c->tank.max[0]);
    double far = -INFINITY;
    for (int b = 0; b < c->nfluid; b++) {
        if (c->fluid[b].min[0] < w->x - 1e-9 * c->dx) {
            char path[64];
            snprintf(path, sizeof path, "/fluid/%d/box/min", b);
            return sph_error_set(err, SPH_ERR_INVALID, path,
                                 "the fluid must lie in front of the paddle: its box starts at "
                                 "x = %g m, behind the paddle's face at %g m",
                                 c->fluid[b].min[0], w->x);
        }
        far = fmax(far, c->fluid[b].max[0]);
    }
    sph_wave_design d;
    if (c->nfluid < 1 || sph_wave_design_of(c, &d))
        return sph_error_set(err, SPH_ERR_INVALID, "/wavemaker",
                             "a wavemaker needs fluid above the tank's bottom and gravity "
                             "along -y");
    if (w->type == SPH_WAVEMAKER_FLAP) {
        if (!(w->hinge >= 0.0 && w->hinge < d.depth))
            return sph_error_set(err, SPH_ERR_INVALID, "/wavemaker/hinge",
                                 "the flap's hinge (%g m above the bottom) must lie in the water "
                                 "column, from the bottom up to below the still water level "
                                 "(%g m)",
                                 w->hinge, d.depth);
    } else if (w->hinge != 0.0) {
        return sph_error_set(err, SPH_ERR_INVALID, "/wavemaker/hinge",
                             "only a flap has a hinge: leave it out for a piston");
    }
    if (solitary) {
        if (w->height > SPH_SOLITARY_MAX * d.depth)
            return sph_error_set(err, SPH_ERR_INVALID, "/wavemaker/waves/height",
                                 "a solitary wave of H/d = %.3g is beyond Goring's law: its "
                                 "first-order theory holds up to H/d = %.2g (d = %.4g m; the "
                                 "highest solitary wave is 0.78 d)",
                                 w->height / d.depth, SPH_SOLITARY_MAX, d.depth);
    } else if (!series) {
        const double H = irregular ? w->hs : w->height;
        const char *hp = irregular ? "/wavemaker/waves/hs" : "/wavemaker/waves/height";
        const double steep = H / d.length, limit = SPH_WAVE_BREAKING * tanh(d.k * d.depth);
        if (steep > limit)
            return sph_error_set(err, SPH_ERR_INVALID, hp,
                                 "the wave would break: H/L = %.4g (L = %.4g m at d = %.4g m%s) "
                                 "exceeds the breaking limit 0.142 tanh(kd) = %.4g: lower the "
                                 "height or lengthen the period",
                                 steep, d.length, d.depth,
                                 irregular ? ", Hs over the peak's L" : "", limit);
        const double ursell = w->height * d.length * d.length / (d.depth * d.depth * d.depth);
        if (w->order == 2 && ursell >= 8.0 * PI * PI / 3.0)
            return sph_error_set(err, SPH_ERR_INVALID, "/wavemaker/waves/order",
                                 "second-order theory holds for an Ursell number H L^2 / d^3 "
                                 "below 8 pi^2 / 3 = 26.3; these waves' is %.3g: lower the height "
                                 "or shorten the period",
                                 ursell);
    }
    if (series && w->series) { /* checked once read (sph_case_load_files) */
        const sph_wave_series *q = w->series;
        const double vmax = sqrt(-c->gravity[c->dim - 1] * d.depth);
        if (q->n < 2)
            return sph_error_set(err, SPH_ERR_INVALID, "/wavemaker/waves/file",
                                 "the series needs at least 2 rows");
        for (long i = 0; i < q->n; i++) {
            const double t0 = i > 0 ? q->t[i - 1] : 0.0, x0 = i > 0 ? q->x[i - 1] : 0.0;
            if (i > 0 && !(q->t[i] > t0))
                return sph_error_set(err, SPH_ERR_INVALID, "/wavemaker/waves/file",
                                     "the series' time does not increase at row %ld (t = %g s "
                                     "after %g s)",
                                     i + 1, q->t[i], t0);
            if (i == 0 && !(q->t[0] >= 0.0))
                return sph_error_set(err, SPH_ERR_INVALID, "/wavemaker/waves/file",
                                     "the series starts at t = %g s, before 0", q->t[0]);
            const double dt = q->t[i] - t0, dxs = fabs(q->x[i] - x0);
            if (!isfinite(q->x[i]) || (dxs > 0.0 && !(dxs <= vmax * dt)))
                return sph_error_set(err, SPH_ERR_INVALID, "/wavemaker/waves/file",
                                     "the series jumps at row %ld (t = %g s): the paddle would "
                                     "move %g m in %g s, faster than the long waves' speed "
                                     "sqrt(g d) = %.3g m/s (the paddle rests at 0 until the "
                                     "first row): smooth the motion or sample it finer",
                                     i + 1, q->t[i], dxs, dt, vmax);
        }
    }
    /* how far the paddle's particles travel back (behind the face) and forward (the face at the
     * still water level): a piston's regular motion +-S/2 (+ the second harmonic), a solitary
     * wave's 0 to S, an irregular sea's and a series' extremes; a flap's back at the tank's top
     * turns (top - hinge) / (d - l) times as far as the face */
    double fwd, bwd;
    if (excursion(c, &d, &fwd, &bwd))
        return sph_error_set(err, SPH_ERR_NOMEM, "/wavemaker", "out of memory");
    if (w->type == SPH_WAVEMAKER_FLAP)
        bwd *= fmax(c->tank.max[c->dim - 1] - c->tank.min[c->dim - 1] - w->hinge, 0.0) /
               (d.depth - w->hinge);
    const double back = w->x - w->layers * c->dx - bwd;
    if (back < c->tank.min[0] || back < c->domain.min[0])
        return sph_error_set(err, SPH_ERR_INVALID, "/wavemaker/x",
                             "the paddle's stroke (%.4g m back) takes its back to x = %.4g m, "
                             "beyond the tank's wall at %g m: move the paddle's face at least "
                             "%.4g m from the wall",
                             bwd, back, fmax(c->tank.min[0], c->domain.min[0]),
                             w->layers * c->dx + bwd);
    if (w->x + fwd >= far)
        return sph_error_set(err, SPH_ERR_INVALID, "/wavemaker/waves/height",
                             "the paddle's stroke (%.4g m forward) takes its face to x = %.4g m, "
                             "past the fluid's far end at %g m",
                             fwd, w->x + fwd, far);
    return absorption_check(c, back, w->x + fwd, err);
}

long sph_wavemaker_points(const sph_config *c, double *const *pos)
{
    if (c->wavemaker.type == SPH_WAVEMAKER_NONE || !c->has_tank)
        return 0;
    const double dx = c->dx;
    const int V = c->dim - 1;
    const long L = c->wavemaker.layers;
    /* the tank's height in rows (along V) and, in 3D, its width across (along y) */
    const long nv = sph_lattice_axis_count(c->tank.min[V], c->tank.max[V], dx);
    const long ny = V == 2 ? sph_lattice_axis_count(c->tank.min[1], c->tank.max[1], dx) : 1;
    if (!pos)
        return L * nv * ny;
    long i = 0;
    for (long k = 0; k < L; k++)
        for (long iy = 0; iy < ny; iy++)
            for (long iv = 0; iv < nv; iv++, i++) {
                pos[0][i] = c->wavemaker.x - (k + 0.5) * dx;
                pos[V][i] = c->tank.min[V] + (iv + 0.5) * dx;
                if (V == 2)
                    pos[1][i] = c->tank.min[1] + (iy + 0.5) * dx;
            }
    return i;
}

/* The water's top among P's first n fluid particles with x in [lo, hi] above bottom (-INFINITY:
 * none there). */
static double level_at(const sph_particles *P, long n, double lo, double hi, double bottom)
{
    const double *vert = P->dim == 3 ? P->z : P->y;
    double top = -INFINITY;
#pragma omp parallel for schedule(static) reduction(max : top) if (n >= SPH_OMP_MIN)
    for (long i = 0; i < n; i++)
        if (P->type[i] == SPH_FLUID && P->x[i] >= lo && P->x[i] <= hi && vert[i] > top)
            top = vert[i];
    return top - bottom;
}

/* Sets up active absorption for c's paddle over P as the fill left it: 0, or -1 out of memory. */
static int active_init(sph_paddle *p, const sph_config *c, const sph_wave_design *d,
                       const sph_particles *P)
{
    const sph_wavemaker_spec *m = &c->wavemaker;
    p->active = 1;
    p->face = m->x;
    p->dx = c->dx;
    p->bottom = c->tank.min[c->dim - 1];
    p->sgd = sqrt(-c->gravity[c->dim - 1] / d->depth);
    p->hs = m->waves == SPH_WAVES_REGULAR ? transfer(c, d->k * d->depth, d->depth) : 0.0;
    p->tau = 10.0 * (m->waves == SPH_WAVES_SOLITARY    ? d->duration
                     : m->waves == SPH_WAVES_IRREGULAR ? m->tp
                                                       : m->period);
    p->st.level0 = level_at(P, P->n, p->face + p->dx, p->face + 3.0 * p->dx, p->bottom);
    return 0;
}

void sph_paddle_absorb(sph_paddle *p, const sph_particles *P, long n, double t, double dt)
{
    if (!p->active || !(dt > 0.0))
        return;
    double v;
    const double face = p->face + sph_paddle_motion(&p->law, t, &v) + p->st.xc;
    const double level = level_at(P, n, face + p->dx, face + 3.0 * p->dx, p->bottom);
    const double eta =
        isfinite(level) && isfinite(p->st.level0) ? level - p->st.level0 : 0.0; /* dry: none */
    const double e = eta - sph_paddle_target(&p->law, t, p->hs, p->tf);
    const double a = fmin(dt / p->tau, 1.0);
    p->st.ebar += a * (e - p->st.ebar);
    p->st.vc = -p->sgd * (e - p->st.ebar) - p->st.xc / p->tau;
    p->st.xc += p->st.vc * dt;
}

int sph_paddle_init(sph_paddle *p, const sph_config *c, const sph_particles *P, long first)
{
    *p = (sph_paddle){.first = first, .np = sph_wavemaker_points(c, NULL)};
    if (p->np == 0)
        return 0;
    /* in 2D (x, y), in 3D (x, z): the plane the paddle moves in (y stays) */
    const double *vert = c->dim == 3 ? P->z : P->y;
    p->rest = malloc((size_t)p->np * 2 * sizeof *p->rest);
    if (!p->rest)
        return -1;
    for (long q = 0; q < p->np; q++) {
        p->rest[2 * q] = P->x[first + q];
        p->rest[2 * q + 1] = vert[first + q];
    }
    sph_wave_design d;
    if (sph_wave_design_of(c, &d) == 0) /* checked: always */
        sph_paddle_law_of(c, &d, &p->law);
    const sph_wavemaker_spec *m = &c->wavemaker;
    if (m->waves == SPH_WAVES_IRREGULAR) { /* with active absorption, their transfer functions */
        const int n = sph_wave_components(c, d.depth, &p->comp, m->active ? &p->tf : NULL);
        if (n < 0)
            return -1;
        p->law.ncomp = n;
        p->law.comp = p->comp;
    } else if (m->waves == SPH_WAVES_SERIES && m->series && m->series->n > 0) {
        /* at rest at 0 until the first row: an implied row (0, 0) before a later one */
        const long k = m->series->t[0] > 0.0 ? 1 : 0, n = m->series->n + k;
        p->rows.t = malloc((size_t)n * sizeof *p->rows.t);
        p->rows.x = malloc((size_t)n * sizeof *p->rows.x);
        if (!p->rows.t || !p->rows.x)
            return -1;
        p->rows.t[0] = p->rows.x[0] = 0.0;
        memcpy(p->rows.t + k, m->series->t, (size_t)m->series->n * sizeof *p->rows.t);
        memcpy(p->rows.x + k, m->series->x, (size_t)m->series->n * sizeof *p->rows.x);
        p->rows.n = p->law.nseries = n;
        p->law.st = p->rows.t;
        p->law.sx = p->rows.x;
    } else if (m->waves == SPH_WAVES_SERIES) {
        return -2;
    }
    if (m->active && active_init(p, c, &d, P))
        return -1;
    return 0;
}

void sph_paddle_law_of(const sph_config *c, const sph_wave_design *d, sph_paddle_law *law)
{
    const sph_wavemaker_spec *m = &c->wavemaker;
    const double period = m->waves == SPH_WAVES_IRREGULAR ? m->tp : m->period;
    *law = (sph_paddle_law){.stroke = d->stroke, .omega = d->omega, .tramp = m->ramp * period};
    if (m->waves == SPH_WAVES_REGULAR && m->order == 2)
        law->second = sph_madsen_second(d->k * d->depth, m->height, d->depth);
    if (m->waves == SPH_WAVES_SOLITARY) {
        law->solitary = 1;
        law->height = m->height;
        law->depth = d->depth;
        law->kappa = d->kappa;
        law->celerity = d->celerity;
        law->x0 = m->height / (d->kappa * d->depth) * (1.0 + tanh(sph_solitary_theta(law, 0.0)));
    }
    if (m->type == SPH_WAVEMAKER_FLAP) {
        law->flap = 1;
        law->hx = m->x;
        law->hy = c->tank.min[c->dim - 1] + m->hinge;
        law->arm = d->depth - m->hinge;
    }
}

void sph_paddle_free(sph_paddle *p)
{
    free(p->rest);
    free(p->comp);
    free(p->tf);
    free(p->rows.t);
    free(p->rows.x);
    *p = (sph_paddle){0};
}

void sph_paddle_move(const sph_paddle *p, sph_particles *P, long n, double t)
{
    if (p->np == 0)
        return;
    double v;
    double X = sph_paddle_motion(&p->law, t, &v);
    if (p->active) {
        X += p->st.xc;
        v += p->st.vc;
    }
    const int M = P->mixed;
#pragma omp parallel for schedule(static) if (n >= SPH_OMP_MIN)
    for (long i = 0; i < n; i++)
        sph_paddle_particle(&p->law, p->rest, p->first, p->np, P, M, i, X, v);
}

void sph_damping_apply(const sph_config *c, sph_particles *P, long n, double dt)
{
    const sph_absorption_spec *a = &c->absorption;
    if (a->type == 0)
        return;
    const int M = P->mixed;
#pragma omp parallel for schedule(static) if (n >= SPH_OMP_MIN)
    for (long i = 0; i < n; i++)
        sph_damping_particle(P, M, i, dt, a->beta, a->from, a->to);
}
