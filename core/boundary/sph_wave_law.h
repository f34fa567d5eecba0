/*
 * sph_wave_law: the physics of a wave flume written once, as SPH_HD static inline functions that
 * the C loops call and a CUDA kernel can call (sph_hd.h): the linear dispersion relation, the
 * piston's first-order transfer function, the smooth ramp and the piston's law of motion, and the
 * damping zone's weight.
 *
 *   dispersion (Airy):           omega^2 = g k tanh(k d)
 *   piston transfer function:    H / S = 2 (cosh 2kd - 1) / (sinh 2kd + 2kd)
 *                                (Dean & Dalrymple 1991, "Water wave mechanics for engineers and
 *                                scientists", ch. 6, the piston's plane-wave solution)
 *   flap transfer function:      H / S = 4 sinh kd (sinh kd - (cosh kd - 1) / (k (d - l)))
 *                                / (sinh 2kd + 2kd), hinged l above the bottom, S the stroke at
 *                                the still water level (the same solution for the displacement
 *                                profile (z - l) / (d - l); l = 0 is Dean & Dalrymple's flap)
 *   ramp over Tr = ramp T:       r(t) = (1 - cos(pi t / Tr)) / 2 for t < Tr, 1 after
 *   displacement at the still water level: X(t) = r(t) (S/2 sin(omega t) + a2 sin(2 omega t)),
 *                                its velocity dX/dt (a piston moves rigidly by X; a flap turns by
 *                                atan(X / (d - l)) about its hinge); a2 = 0 at first order
 *   second order (Madsen 1971, a piston): a2 = H^2 / (32 d) (3 cosh kd / sinh^3 kd - 2 / m1),
 *                                m1 the piston's H / S: the second harmonic that cancels the
 *                                free one first-order motion makes
 *   irregular waves (JONSWAP, Hasselmann et al. 1973): S(f) ~ f^-5 exp(-5/4 (fp / f)^4)
 *                                gamma^exp(-(f - fp)^2 / (2 sigma^2 fp^2)), sigma 0.07 below fp
 *                                and 0.09 above, scaled so that 4 sqrt(sum S(f_i) df) = Hs over
 *                                the components f_i = i / D in [0.5 fp, 3 fp]; each a wave of
 *                                amplitude sqrt(2 S(f_i) df) and a random phase, made at first
 *                                order: X(t) = r(t) sum A_i sin(omega_i t + phi_i), A_i = that
 *                                amplitude over the transfer function at k_i d
 *   series: X(t) from a table of rows (t_i, X_i) by monotone cubic Hermite interpolation
 *                                (Fritsch & Butland's slopes inside, 0 at both ends: the paddle
 *                                starts and stops at rest and never passes the rows' extremes),
 *                                from an implied row (0, 0) when the first is later, X_n-1
 *                                after the last
 *   solitary wave (Goring 1978): a piston with dX/dt = c eta(X, t) / (d + eta(X, t)), eta = H
 *                                sech^2(theta), theta = kappa (c t - X) - theta0, kappa =
 *                                sqrt(3H / (4 d^3)), c = sqrt(g (d + H)); integrated exactly:
 *                                X = H / (kappa d) (1 + tanh theta), theta from Newton; the
 *                                stroke S = 2H / (kappa d) = sqrt(16 H d / 3) over the time
 *                                2 (theta0 + H/d) / (kappa c), theta0 = 3.8 (Goring's)
 *   damping weight (Altomare et al. 2017, as DualSPHysics' "damping" zones apply it):
 *                                v *= 1 - dt beta f(x), f = s^2, s = (x - from) / (to - from)
 *                                clamped to [0, 1]
 *   breaking limit (Miche 1944): H / L <= 0.142 tanh(kd)
 *
 * Pure functions of their arguments: no state, nothing allocated.
 */
#ifndef SPH_WAVE_LAW_H
#define SPH_WAVE_LAW_H

#include "sph_hd.h"

#include <math.h>

#define SPH_WAVE_BREAKING 0.142 /* Miche's limit of the steepness H / L in deep water [-] */

/* kd from omega^2 d / g = kd tanh(kd) (the linear dispersion relation in terms of y = omega^2
 * d / g > 0), by Newton from Eckart's (1952) approximation; 0 for y <= 0. Converges to rounding
 * in a few iterations for every y (x tanh x is convex and increasing for x > 0). */
SPH_HD static inline double sph_wave_kd(double y)
{
    if (!(y > 0.0))
        return 0.0;
    double x = y / sqrt(tanh(y)); /* Eckart: within 5% everywhere */
    for (int it = 0; it < 50; it++) {
        const double t = tanh(x);
        const double f = x * t - y;
        const double fp = t + x * (1.0 - t * t);
        const double dx = f / fp;
        x -= dx;
        if (fabs(dx) <= 1e-15 * x)
            break;
    }
    return x;
}

/* The wave number k [1/m] of waves of angular frequency omega [rad/s] in water of depth d [m]
 * under gravity g [m/s^2]. */
SPH_HD static inline double sph_wave_number(double omega, double g, double d)
{
    return sph_wave_kd(omega * omega * d / g) / d;
}

/* The piston's first-order transfer function H / S of kd (Dean & Dalrymple, ch. 6). */
SPH_HD static inline double sph_piston_transfer(double kd)
{
    return 2.0 * (cosh(2.0 * kd) - 1.0) / (sinh(2.0 * kd) + 2.0 * kd);
}

/* A flap's first-order transfer function H / S of kd, hinged at lh = l / d of the depth above the
 * bottom (0 <= lh < 1; S the stroke at the still water level). */
SPH_HD static inline double sph_flap_transfer(double kd, double lh)
{
    const double sh = sinh(kd);
    return 4.0 * sh * (sh - (cosh(kd) - 1.0) / (kd * (1.0 - lh))) / (sinh(2.0 * kd) + 2.0 * kd);
}

/* The ramp r(t) over tr seconds (0 or less: none) and its rate dr/dt [1/s]. */
SPH_HD static inline double sph_wave_ramp(double t, double tr, double *rate)
{
    if (!(tr > 0.0) || t >= tr) {
        *rate = 0.0;
        return 1.0;
    }
    if (t <= 0.0) {
        *rate = 0.0;
        return 0.0;
    }
    const double a = 3.14159265358979323846 * t / tr;
    *rate = 0.5 * 3.14159265358979323846 / tr * sin(a);
    return 0.5 * (1.0 - cos(a));
}

#define SPH_SOLITARY_THETA0 3.8 /* Goring's start: the wave's sech^2 at 2e-3 of its crest [-] */
#define SPH_SOLITARY_MAX    0.6 /* the highest H/d a solitary wave's law takes [-] */

/* Madsen's (1971) second harmonic of a piston's displacement a2 [m] (X = S/2 sin(omega t) + a2
 * sin(2 omega t)) for waves of height H [m] in water of depth d [m] at kd. */
SPH_HD static inline double sph_madsen_second(double kd, double H, double d)
{
    const double sh = sinh(kd);
    return H * H / (32.0 * d) * (3.0 * cosh(kd) / (sh * sh * sh) - 2.0 / sph_piston_transfer(kd));
}

/* The JONSWAP spectrum's shape at frequency f [Hz] for the peak fp [Hz] and enhancement gamma
 * (unscaled: the caller scales it to the significant height). */
SPH_HD static inline double sph_jonswap_shape(double f, double fp, double gamma)
{
    if (!(f > 0.0))
        return 0.0;
    const double sigma = f <= fp ? 0.07 : 0.09, q = fp / f, e = (f - fp) / (sigma * fp);
    return pow(f, -5.0) * exp(-1.25 * q * q * q * q) * pow(gamma, exp(-0.5 * e * e));
}

/* The slope of a series' interpolant at row i of n (sph_series_motion): 0 at both ends and
 * where the neighbouring chords differ in sign or one is flat, else their weighted harmonic mean
 * (Fritsch & Butland 1984, Brodlie's weights: monotone between rows, no overshoot). */
SPH_HD static inline double sph_series_slope(const double *ts, const double *xs, long n, long i)
{
    if (i <= 0 || i >= n - 1)
        return 0.0;
    const double h0 = ts[i] - ts[i - 1], h1 = ts[i + 1] - ts[i];
    const double d0 = (xs[i] - xs[i - 1]) / h0, d1 = (xs[i + 1] - xs[i]) / h1;
    if (!(d0 * d1 > 0.0))
        return 0.0;
    return 3.0 * (h0 + h1) / ((2.0 * h1 + h0) / d0 + (h1 + 2.0 * h0) / d1);
}

/* X(t) of a series of n >= 1 rows (t increasing) and its rate (sph_paddle_motion's series):
 * the cubic Hermite piece between the rows around t with sph_series_slope's slopes. */
SPH_HD static inline double sph_series_motion(const double *ts, const double *xs, long n, double t,
                                              double *v)
{
    *v = 0.0;
    if (t <= ts[0])
        return xs[0];
    if (t >= ts[n - 1])
        return xs[n - 1];
    long lo = 0, hi = n - 1; /* ts[lo] < t < ts[hi] */
    while (hi - lo > 1) {
        const long mid = lo + (hi - lo) / 2;
        if (ts[mid] <= t)
            lo = mid;
        else
            hi = mid;
    }
    const double h = ts[hi] - ts[lo], s = (t - ts[lo]) / h;
    const double m0 = sph_series_slope(ts, xs, n, lo), m1 = sph_series_slope(ts, xs, n, hi);
    const double s2 = s * s, s3 = s2 * s;
    const double h00 = 2.0 * s3 - 3.0 * s2 + 1.0, h10 = s3 - 2.0 * s2 + s;
    const double h01 = -2.0 * s3 + 3.0 * s2, h11 = s3 - s2;
    *v = ((6.0 * s2 - 6.0 * s) * (xs[lo] - xs[hi]) / h + (3.0 * s2 - 4.0 * s + 1.0) * m0 +
          (3.0 * s2 - 2.0 * s) * m1);
    return h00 * xs[lo] + h10 * h * m0 + h01 * xs[hi] + h11 * h * m1;
}

/* A paddle's law of motion: what sph_paddle_motion and sph_paddle_place need. The arrays of
 * irregular waves and of a series are host memory: sph_paddle_motion runs on the host, a GPU
 * kernel takes X and its rate (sph_paddle_place reads none of them). */
typedef struct sph_paddle_law {
    int solitary;  /* 0: regular waves (stroke, omega, tramp), 1: Goring's solitary wave */
    double stroke; /* S: twice the amplitude of the displacement (solitary: its whole travel) [m] */
    double omega;  /* 2 pi / T [rad/s] */
    double tramp;  /* the ramp's duration [s] */
    double second; /* regular, order 2: the second harmonic's amplitude a2 [m] */
    int ncomp;     /* irregular: its components, 3 a component in comp: A_i [m], omega_i
                    * [rad/s], phi_i [rad] (0: not irregular) */
    const double *comp;
    long nseries; /* a series: its rows (0: no series) */
    const double *st, *sx;
    double height, depth, kappa, celerity; /* solitary: H, d [m], kappa [1/m], c [m/s] */
    double x0;     /* solitary: H / (kappa d) (1 + tanh theta(0)), taken off so that X(0) = 0 [m] */
    int flap;      /* 0: a piston, moved rigidly by X; 1: a flap turned about (hx, hy) */
    double hx, hy; /* flap: its hinge [m] */
    double arm;    /* flap: the hinge's depth below the still water level d - l [m] */
} sph_paddle_law;

/* Goring's theta(t) of a solitary wave's law: the root of theta + kappa X(theta) = kappa c t -
 * theta0, X(theta) = H / (kappa d) (1 + tanh theta), by Newton (the left side's slope lies in
 * [1, 1 + H/d], so it converges from any start). */
SPH_HD static inline double sph_solitary_theta(const sph_paddle_law *p, double t)
{
    const double a = p->height / p->depth; /* kappa X = a (1 + tanh theta) */
    const double rhs = p->kappa * p->celerity * t - SPH_SOLITARY_THETA0;
    double th = rhs - a;
    for (int it = 0; it < 60; it++) {
        const double th2 = tanh(th);
        const double f = th + a * (1.0 + th2) - rhs;
        const double d = f / (1.0 + a * (1.0 - th2 * th2));
        th -= d;
        if (fabs(d) <= 1e-14 * (1.0 + fabs(th)))
            break;
    }
    return th;
}

/* The paddle's displacement X(t) at the still water level from rest [m] and its velocity dX/dt
 * [m/s] at time t. */
SPH_HD static inline double sph_paddle_motion(const sph_paddle_law *p, double t, double *v)
{
    if (p->solitary) {
        if (t <= 0.0) {
            *v = 0.0;
            return 0.0;
        }
        const double th = sph_solitary_theta(p, t);
        const double sech = 1.0 / cosh(th), eta = p->height * sech * sech;
        *v = p->celerity * eta / (p->depth + eta);
        return p->height / (p->kappa * p->depth) * (1.0 + tanh(th)) - p->x0;
    }
    if (p->nseries > 0)
        return sph_series_motion(p->st, p->sx, p->nseries, t, v);
    double rate;
    const double r = sph_wave_ramp(t, p->tramp, &rate);
    if (p->ncomp > 0) {
        double X = 0.0, V = 0.0;
        for (int i = 0; i < p->ncomp; i++) {
            const double A = p->comp[3 * i], w = p->comp[3 * i + 1],
                         ph = w * t + p->comp[3 * i + 2];
            X += A * sin(ph);
            V += A * w * cos(ph);
        }
        *v = rate * X + r * V;
        return r * X;
    }
    const double a = 0.5 * p->stroke;
    const double s = sin(p->omega * t), c = cos(p->omega * t);
    if (p->second != 0.0) {
        const double w = p->omega, a2 = p->second, s2 = 2.0 * s * c, c2 = c * c - s * s;
        const double X = a * s + a2 * s2, V = a * w * c + 2.0 * w * a2 * c2;
        *v = rate * X + r * V;
        return r * X;
    }
    *v = a * (rate * s + r * p->omega * c);
    return a * r * s;
}

/* The surface elevation [m] the law's waves make at the paddle's face at time t (linear
 * theory's progressive wave, in phase with the paddle's velocity): regular waves r(t) H/2
 * cos(omega t) (first order, H = S times the transfer function hs); an irregular sea the sum of
 * its components' a_i cos(omega_i t + phi_i) (comp's A_i times their transfer functions in tf);
 * a solitary wave H sech^2(theta(t)). Active absorption's target (sph_wavemaker.h). */
SPH_HD static inline double sph_paddle_target(const sph_paddle_law *p, double t, double hs,
                                              const double *tf)
{
    if (p->solitary) {
        if (t <= 0.0)
            return 0.0;
        const double sech = 1.0 / cosh(sph_solitary_theta(p, t));
        return p->height * sech * sech;
    }
    double rate;
    const double r = sph_wave_ramp(t, p->tramp, &rate);
    if (p->ncomp > 0) {
        double e = 0.0;
        for (int i = 0; i < p->ncomp; i++)
            e += p->comp[3 * i] * tf[i] * cos(p->comp[3 * i + 1] * t + p->comp[3 * i + 2]);
        return r * e;
    }
    return r * 0.5 * p->stroke * hs * cos(p->omega * t);
}

/* Where a paddle particle resting at (rx, ry) is when the paddle's displacement at the still
 * water level is X with the rate Xv (sph_paddle_motion): its position into x[2], its velocity
 * into u[2]. A piston moves it by X; a flap turns it rigidly about the hinge by phi =
 * atan(X / arm) (the face at the still water level then X ahead of rest), at the rate dphi/dt. */
SPH_HD static inline void sph_paddle_place(const sph_paddle_law *p, double rx, double ry, double X,
                                           double Xv, double *x, double *u)
{
    if (!p->flap) {
        x[0] = rx + X;
        x[1] = ry;
        u[0] = Xv;
        u[1] = 0.0;
        return;
    }
    const double phi = atan2(X, p->arm), w = p->arm * Xv / (p->arm * p->arm + X * X);
    const double c = cos(phi), s = sin(phi), ax = rx - p->hx, ay = ry - p->hy;
    const double px = ax * c + ay * s, py = -ax * s + ay * c; /* turned clockwise by phi */
    x[0] = p->hx + px;
    x[1] = p->hy + py;
    u[0] = w * py;
    u[1] = -w * px;
}

/* The damping zone's weight f(x) in [0, 1]: 0 up to `from`, (x - from)^2 / (to - from)^2 across,
 * 1 beyond `to` (either way round: from > to puts the zone towards -x). */
SPH_HD static inline double sph_damping_weight(double x, double from, double to)
{
    double s = (x - from) / (to - from);
    s = s < 0.0 ? 0.0 : (s > 1.0 ? 1.0 : s);
    return s * s;
}

/* The factor a fluid particle's velocity at x is multiplied by after a step of dt [s] with the
 * relaxation rate beta [1/s]: 1 - dt beta f(x), never below 0. */
SPH_HD static inline double sph_damping_factor(double x, double dt, double beta, double from,
                                               double to)
{
    const double k = 1.0 - dt * beta * sph_damping_weight(x, from, to);
    return k > 0.0 ? k : 0.0;
}

#endif
