/*
 * sph_mdbc: the density of a fixed wall particle under modified dynamic boundary conditions
 * (mDBC; English, Dominguez, Vacondio, Crespo, Stansby, Lind, Chiapponi & Gomez-Gesteira 2021,
 * Comp. Part. Mech. 9: 1-15). Instead of evolving by continuity (DBC), a wall particle's density
 * is interpolated from the fluid at its ghost node (its mirror point across the wall:
 * sph_shapes_wall_mirror for the built-in boxes, sph_scene_mirror across the nearest wet face of a
 * geometry item's shape, kept in the sim's table) with a first-order consistent correction (Liu &
 * Liu 2006), and carried back to the particle along the density gradient found there:
 *
 *   A = sum_j V_j [ W_j, W_j r_j ; gradW_j, gradW_j (x) r_j ],  b = sum_j m_j [ W_j ; gradW_j ],
 *   A [rho_g ; -grad rho] = b,  rho_wall = rho_g + grad rho . (x_wall - x_g),
 *
 * with r_j = x_g - x_j, V_j = m_j / rho_j and gradW the kernel's gradient at the ghost node.
 * Where A is near singular (|det A| < SPH_MDBC_DETERMINANT: a ghost node at the water's edge)
 * the Shepard value b_0 / A_00 is used, and rho0 where no fluid is within reach. The caller
 * keeps the result at rho0 or above, as the continuity walls do (sph_wcsph.c).
 *
 * The physics of one ghost node, written once for the C loop (sph_wcsph.c) and a device's.
 */
#ifndef SPH_MDBC_H
#define SPH_MDBC_H

#include <math.h>

#define SPH_MDBC_DETERMINANT 1e-3 /* DualSPHysics' limit of the first-order correction */

typedef struct sph_mdbc_sum {
    double a[4][4]; /* A: rows and columns 0 (the value) and 1..D (the gradient) */
    double b[4];
} sph_mdbc_sum;

/* Adds fluid particle j: r = x_g - x_j (D components), w = W(|r|), f = W'(|r|) / |r| (so that
 * gradW = f r), m its mass, rho its density. */
static inline __attribute__((always_inline)) void sph_mdbc_add(const int D, sph_mdbc_sum *s,
                                                               const double *r, double w, double f,
                                                               double m, double rho)
{
    const double v = m / rho;
    double row[4] = {v * w, 0.0, 0.0, 0.0};
    /* (unrolled: the sums stay in registers, not in a loop over memory) */
#pragma GCC unroll 4
    for (int d = 0; d < D; d++)
        row[d + 1] = v * f * r[d];
#pragma GCC unroll 4
    for (int e = 0; e <= D; e++) {
        s->a[e][0] += row[e];
#pragma GCC unroll 4
        for (int d = 0; d < D; d++)
            s->a[e][d + 1] += row[e] * r[d];
    }
    s->b[0] += m * w;
#pragma GCC unroll 4
    for (int d = 0; d < D; d++)
        s->b[d + 1] += m * f * r[d];
}

/* The wall particle's density from the sums of its ghost node; dpos = x_wall - x_g. */
static inline __attribute__((always_inline)) double
sph_mdbc_density(const int D, const sph_mdbc_sum *s, const double *dpos, double rho0)
{
    if (!(s->a[0][0] > 0.0))
        return rho0;
    const int n = D + 1;
    double a[4][5];
    for (int e = 0; e < n; e++) {
        for (int d = 0; d < n; d++)
            a[e][d] = s->a[e][d];
        a[e][n] = s->b[e];
    }
    double det = 1.0;
    for (int col = 0; col < n; col++) { /* Gaussian elimination, partial pivoting */
        int piv = col;
        for (int e = col + 1; e < n; e++)
            if (fabs(a[e][col]) > fabs(a[piv][col]))
                piv = e;
        if (piv != col) {
            for (int d = 0; d <= n; d++) {
                const double t = a[col][d];
                a[col][d] = a[piv][d];
                a[piv][d] = t;
            }
            det = -det;
        }
        det *= a[col][col];
        if (a[col][col] == 0.0)
            break;
        for (int e = col + 1; e < n; e++) {
            const double q = a[e][col] / a[col][col];
            for (int d = col; d <= n; d++)
                a[e][d] -= q * a[col][d];
        }
    }
    if (!(fabs(det) >= SPH_MDBC_DETERMINANT))
        return s->b[0] / s->a[0][0];
    double y[4];
    for (int e = n - 1; e >= 0; e--) {
        double t = a[e][n];
        for (int d = e + 1; d < n; d++)
            t -= a[e][d] * y[d];
        y[e] = t / a[e][e];
    }
    double rho = y[0];
    for (int d = 0; d < D; d++)
        rho -= y[d + 1] * dpos[d]; /* y[1..D] = -grad rho */
    return rho;
}

#endif
