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
 *   ramp over Tr = ramp T:       r(t) = (1 - cos(pi t / Tr)) / 2 for t < Tr, 1 after
 *   piston displacement:         X(t) = r(t) S/2 sin(omega t), its velocity dX/dt
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

/* A piston's law of motion: what sph_piston_motion needs. */
typedef struct sph_piston_law {
    double stroke; /* S: twice the amplitude of the displacement [m] */
    double omega;  /* 2 pi / T [rad/s] */
    double tramp;  /* the ramp's duration [s] */
} sph_piston_law;

/* The piston's displacement X(t) from rest [m] and its velocity dX/dt [m/s] at time t. */
SPH_HD static inline double sph_piston_motion(const sph_piston_law *p, double t, double *v)
{
    double rate;
    const double r = sph_wave_ramp(t, p->tramp, &rate);
    const double a = 0.5 * p->stroke;
    const double s = sin(p->omega * t), c = cos(p->omega * t);
    *v = a * (rate * s + r * p->omega * c);
    return a * r * s;
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
