/*
 * Particle shifting, written once for the C loops (core/wcsph/sph_wcsph.c) and a CUDA kernel
 * later: Lind, Xu, Stansby & Rogers (2012, J. Comput. Phys. 231, 1499-1523)'s Fickian
 * displacement down the gradient of the particle concentration C,
 *
 *     dr_a = A h |v_a| dt grad C_a,     grad C_a = sum_b V_b grad_a W_ab,     V_b = m / rho_b,
 *
 * with the diffusion coefficient D = -A h |v_a| dt of Skillen et al. (2013) and the free-surface
 * treatment as DualSPHysics 5.4 applies them (JSphShifting::RunCpu, JSphCpu::InteractionForcesFluid
 * "Shifting correction"; its "full" mode: walls, ghosts and bodies count in C as fluid does):
 * the divergence of position
 *
 *     div r_a = -sum_b V_b (x_a - x_b).grad_a W_ab     (D in the fluid's bulk: 2 or 3)
 *
 * marks the free surface: a particle with div r_a below the threshold T (DualSPHysics'
 * fsthreshold, 1.5 in 2D and 2.75 in 3D) is not shifted at all, so nothing moves it across the
 * surface (its normal, where grad C points, included); above it the displacement is scaled by
 * (div r_a - T) / (D - T), which fades it in towards the bulk. Each component is capped at
 * 0.1 dx, as DualSPHysics caps it. A is negative (DualSPHysics' default -2): the shift goes
 * from crowded towards sparse regions.
 * Off by default: at A = -2 and T = 1.5 the 2D dam break keeps its bounds, but the standing wave
 * at H/dx = 50 decays 2.2 times too fast (docs/status.md has the figures).
 */
#ifndef SPH_SHIFTING_H
#define SPH_SHIFTING_H

#include "sph_hd.h"

#include <math.h>

/* Particle a's sums over its neighbours. */
typedef struct sph_shift_sum {
    double g[3]; /* grad C_a = sum_b V_b grad_a W_ab [1/m] */
    double div;  /* div r_a = -sum_b V_b (x_a - x_b).grad_a W_ab [-] */
} sph_shift_sum;

/* The constants of a shifting pass. */
typedef struct sph_shift_const {
    double ahdt; /* A h dt [m s] (A < 0) */
    double tfs;  /* the free-surface threshold of div r (0: no free-surface treatment) [-] */
    double maxd; /* cap on each component of the displacement, 0.1 dx [m] */
} sph_shift_const;

/* The pair (a, b) into a's sums: d = x_a - x_b, r2 = |d|^2, fw = (dW/dr) / r (grad_a W_ab =
 * fw d), vb = m / rho_b, b's volume. */
SPH_HD static inline __attribute__((always_inline)) void
sph_shifting_pair(const int D, const double *SPH_RESTRICT d, double r2, double fw, double vb,
                  sph_shift_sum *SPH_RESTRICT s)
{
    const double f = vb * fw;
    s->g[0] += f * d[0];
    s->g[1] += f * d[1];
    if (D == 3)
        s->g[2] += f * d[2];
    s->div -= f * r2;
}

/* Particle a's displacement dr (D components) from its sums s and its speed |v_a| [m/s]. */
SPH_HD static inline __attribute__((always_inline)) void
sph_shifting_displacement(const int D, const sph_shift_const *SPH_RESTRICT k,
                          const sph_shift_sum *SPH_RESTRICT s, double speed,
                          double *SPH_RESTRICT dr)
{
    double u = k->ahdt * speed;
    if (k->tfs > 0.0) /* the free surface: no shift; fading in below the bulk's D */
        u = s->div < k->tfs ? 0.0 : u * (s->div - k->tfs) / ((double)D - k->tfs);
    for (int c = 0; c < D; c++) {
        const double v = s->g[c] * u;
        dr[c] = fabs(v) < k->maxd ? v : (v >= 0.0 ? k->maxd : -k->maxd);
    }
}

#endif
