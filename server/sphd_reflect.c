/*
 * sphd_reflect: the incident and reflected regular waves of a flume from its gauges, by least
 * squares (sphd_reflect.h).
 */
#include "sphd_reflect.h"

#include <complex.h>
#include <math.h>
#include <string.h>

/* The determinant of the 3 x 3 matrix s with its column `col` replaced by r (col -1: none). */
static double det3(const double s[3][3], int col, const double r[3])
{
    double c[3][3];
    for (int p = 0; p < 3; p++)
        for (int q = 0; q < 3; q++)
            c[p][q] = q == col ? r[p] : s[p][q];
    return c[0][0] * (c[1][1] * c[2][2] - c[1][2] * c[2][1]) -
           c[0][1] * (c[1][0] * c[2][2] - c[1][2] * c[2][0]) +
           c[0][2] * (c[1][0] * c[2][1] - c[1][1] * c[2][0]);
}

/* The least squares fit of eta (sample i at eta[i * stride]) over the samples of [t0, t1] by e0 +
 * a cos(omega t) + b sin(omega t) (a 3 x 3 system, solved by Cramer's rule): its complex
 * amplitude a - i b into *z. Returns the samples used, or -1 for a singular system. */
static long fit(const double *t, const double *eta, long stride, long n, double t0, double t1,
                double omega, double complex *z)
{
    double s[3][3], r[3];
    memset(s, 0, sizeof s);
    memset(r, 0, sizeof r);
    long used = 0;
    for (long i = 0; i < n; i++) {
        const double e = eta[i * stride];
        if (!(t[i] >= t0 && t[i] <= t1) || !isfinite(e))
            continue;
        const double f[3] = {1.0, cos(omega * t[i]), sin(omega * t[i])};
        for (int p = 0; p < 3; p++) {
            for (int q = 0; q < 3; q++)
                s[p][q] += f[p] * f[q];
            r[p] += f[p] * e;
        }
        used++;
    }
    const double det = det3(s, -1, r);
    if (!(fabs(det) > 1e-12 * (double)used * (double)used * (double)used))
        return -1;
    *z = det3(s, 1, r) / det - I * (det3(s, 2, r) / det);
    return used;
}

int sphd_reflect(const double *t, const double *g, long stride, const long *cols, const double *x,
                 int m, long n, double t0, double t1, double omega, double k, sphd_reflect_out *out)
{
    out->hi = out->hr = out->kr = out->cond = NAN;
    if (m < 2 || !(omega > 0.0) || !(k > 0.0) || !(t1 - t0 >= 2.0 * M_PI / omega))
        return -1;
    /* normal equations of Z_n = A_I u_n + A_R conj(u_n), u_n = exp(-i k x_n):
     * [N S; conj(S) N] [A_I; A_R] = [sum conj(u) Z; sum u Z], S = sum conj(u_n)^2 */
    double complex S = 0.0, bi = 0.0, br = 0.0;
    for (int j = 0; j < m; j++) {
        double complex z;
        if (fit(t, g + cols[j], stride, n, t0, t1, omega, &z) < 8)
            return -1;
        const double complex u = cexp(-I * k * x[j]);
        S += conj(u) * conj(u);
        bi += conj(u) * z;
        br += u * z;
    }
    const double N = (double)m;
    out->cond = 1.0 - creal(S * conj(S)) / (N * N);
    if (!(out->cond >= SPHD_REFLECT_MIN_COND))
        return -1;
    const double complex det = N * N - S * conj(S);
    const double complex ai = (N * bi - S * br) / det, ar = (N * br - conj(S) * bi) / det;
    out->hi = 2.0 * cabs(ai);
    out->hr = 2.0 * cabs(ar);
    out->kr = out->hr / out->hi;
    return 0;
}
