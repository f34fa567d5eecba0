/*
 * sphd_reflect: the reflection of regular waves in a flume from two or more height gauges, by
 * least squares at the waves' frequency (Mansard & Funke 1980; with two gauges it is Goda &
 * Suzuki's 1976 method at one frequency). Each gauge's series over a window is fitted by
 * eta0 + a cos(omega t) + b sin(omega t), its complex amplitude Z = a - i b; the gauges' amplitudes
 * are then split into an incident wave travelling up x and a reflected one travelling down it,
 * Z_n = A_I exp(-i k x_n) + A_R exp(i k x_n), least squares over the gauges. Kr = |A_R| / |A_I|.
 * The split needs gauges whose spacings are not near a multiple of half a wavelength (the 2x2
 * system singular): its conditioning is reported, and a poor one refused.
 */
#ifndef SPHD_REFLECT_H
#define SPHD_REFLECT_H

/* The least conditioning of the split: two gauges give sin^2(k dl), and Goda & Suzuki's range of
 * spacings, 0.05 < dl / L < 0.45, gives at least sin^2(0.1 pi) = 0.095. */
#define SPHD_REFLECT_MIN_COND 0.09

typedef struct sphd_reflect_out {
    double hi, hr; /* the incident and reflected wave heights, twice their amplitudes [m] */
    double kr;     /* the reflection coefficient hr / hi [-] */
    double cond;   /* 1 - |S|^2 / N^2 of the split (S = sum exp(2 i k x_n)): 1 for gauges a
                      quarter wavelength apart, 0 when the split is impossible [-] */
} sphd_reflect_out;

/* The least squares split of m gauges at x[m] [m] whose series are columns cols[m] of the table
 * g (sample i of gauge j at g[i * stride + cols[j]]; the same times t[n], increasing), read over
 * [t0, t1], for waves of angular frequency omega [rad/s] and wave
 * number k [1/m]. Returns 0 with *out, or -1 when it cannot: fewer than 2 gauges, fewer than 8
 * samples in the window, a window shorter than a period,
 * or a split whose cond is below SPHD_REFLECT_MIN_COND (the gauges too near a multiple of half a
 * wavelength apart); out->cond is set whenever the gauges were read (NaN otherwise). */
int sphd_reflect(const double *t, const double *g, long stride, const long *cols, const double *x,
                 int m, long n, double t0, double t1, double omega, double k,
                 sphd_reflect_out *out);

#endif
