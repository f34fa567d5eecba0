/*
 * The WCSPH per-particle updates, written once for the C loops (core/wcsph/) and the CUDA kernels
 * (core/gpu/): the preparation before a force evaluation (EOS, p / rho^2, SPS stresses), gravity,
 * and the integrator's predictor and corrector (sph_wcsph_step.c says the scheme). Each reads and
 * writes particle i of an sph_particles whose arrays live where the caller runs (host or device);
 * a loop, an OpenMP loop or a kernel launch around them is the backend's, the arithmetic is here.
 * The dimension D is a constant at every call (the loops are written once per dimension).
 */
#ifndef SPH_WCSPH_PARTICLE_H
#define SPH_WCSPH_PARTICLE_H

#include "sph_eos.h"
#include "sph_hd.h"
#include "sph_particles.h"
#include "sph_wall_ghost.h"
#include "sph_wcsph_pair.h"

#include <math.h>

/* Particle i before a force evaluation: EOS, p / rho^2 (the pressure itself is not stored), SPS
 * stresses from the previous velocity gradients; its accumulators zeroed. The loops over the
 * particles here are written once per dimension, the dimension a literal there (an OpenMP loop in a
 * function that takes D outlines its body before D is known, and tests D per particle). */
SPH_HD static inline __attribute__((always_inline)) void prepare_one(const int D, const int M,
                                                                     const sph_config *cfg,
                                                                     sph_particles *P, double smag,
                                                                     double blin, long i)
{
    const double rho = SPH_GET(M, P, rho, i);
    const double p = sph_eos_pressure(cfg, rho);
    SPH_SET(M, P, pr, i, p / (rho * rho));
    SPH_SET(M, P, ax, i, 0.0);
    SPH_SET(M, P, ay, i, 0.0);
    if (D == 3)
        SPH_SET(M, P, az, i, 0.0);
    SPH_SET(M, P, drho, i, 0.0);
    if (P->gxx) {
        /* stored as R / rho as eq. (15) uses it; boundary particles carry none */
        double *const gs[6] = {P->gxx, P->gxy, P->gyy, P->gzz, P->gxz, P->gyz};
        double *const ts[6] = {P->txx, P->txy, P->tyy, P->tzz, P->txz, P->tyz};
        const int ng = D == 3 ? 6 : 3;
        double g[6] = {0}, t[6] = {0};
        for (int q = 0; q < ng; q++)
            g[q] = gs[q][i];
        if (P->type[i] == SPH_FLUID)
            sph_wcsph_sps_stress(D, g, rho, smag, blin, t);
        for (int q = 0; q < ng; q++) {
            ts[q][i] = t[q];
            gs[q][i] = 0.0;
        }
    }
}

/* Gravity on particle i if it is fluid (g: the gravity vector), else its acceleration zeroed;
 * returns its |a|^2 (0 for the others; under mixed precision, of the stored float values). */
SPH_HD static inline __attribute__((always_inline)) double
gravity_one(const int D, const int M, const double *g, sph_particles *P, long i)
{
    if (P->type[i] == SPH_FLUID) {
        SPH_SET(M, P, ax, i, SPH_GET(M, P, ax, i) + g[0]);
        SPH_SET(M, P, ay, i, SPH_GET(M, P, ay, i) + g[1]);
        const double ax = SPH_GET(M, P, ax, i), ay = SPH_GET(M, P, ay, i);
        double a2 = ax * ax + ay * ay;
        if (D == 3) {
            SPH_SET(M, P, az, i, SPH_GET(M, P, az, i) + g[2]);
            const double az = SPH_GET(M, P, az, i);
            a2 += az * az;
        }
        return a2;
    }
    SPH_SET(M, P, ax, i, 0.0);
    SPH_SET(M, P, ay, i, 0.0);
    if (D == 3)
        SPH_SET(M, P, az, i, 0.0);
    return 0.0;
}

/* What the predictor and the corrector read of a sim: copied into each thread (firstprivate), so
 * that the loops hold it in registers (a store to a particle's type, a char, may alias anything
 * the loop would otherwise reload from memory). */
typedef struct step_ctx {
    sph_particles *P;
    const sph_wall_ghost *ghost;
    double lo[3], hi[3]; /* the domain */
    double rho0;
    int ghosts; /* free-slip ghost walls */
} step_ctx;

/* The predictor of particle i: fluid moved (or lost when it leaves the domain; with ghost walls,
 * reflected back first), the density advanced. Returns 1 when its new position is not finite.
 * Written per component (z under D == 3) as the 2D loop was: a loop over arrays of component
 * pointers made the 2D integration 55% slower. The loops over the particles are written once per
 * dimension (predict2, predict3), the dimension a literal there: an OpenMP loop in a function
 * that takes D outlines its body before D is known, and tests D per particle. */
SPH_HD static inline __attribute__((always_inline)) long
predict_one(const int D, const int M, const step_ctx *k, double dt, long i)
{
    sph_particles *P = k->P;
    long bad = 0;
    if (P->type[i] == SPH_FLUID) {
        const double ax = SPH_GET(M, P, ax0, i), ay = SPH_GET(M, P, ay0, i),
                     az = D == 3 ? SPH_GET(M, P, az0, i) : 0.0;
        const double vx = SPH_GET(M, P, vx, i), vy = SPH_GET(M, P, vy, i),
                     vz = D == 3 ? SPH_GET(M, P, vz, i) : 0.0;
        double x[3] = {P->x[i] + dt * (vx + 0.5 * dt * ax), P->y[i] + dt * (vy + 0.5 * dt * ay),
                       0.0};
        double v[3] = {vx + dt * ax, vy + dt * ay, 0.0};
        if (D == 3) {
            x[2] = P->z[i] + dt * (vz + 0.5 * dt * az);
            v[2] = vz + dt * az;
        }
        bad = !isfinite(x[0]) || !isfinite(x[1]) || (D == 3 && !isfinite(x[2]));
        if (k->ghosts) /* a particle that crossed a free-slip wall comes back, before the domain
                          check: a tank may fill the domain */
            sph_wall_ghost_reflect(k->ghost, x, v);
        if (x[0] >= k->lo[0] && x[0] <= k->hi[0] && x[1] >= k->lo[1] && x[1] <= k->hi[1] &&
            (D == 2 || (x[2] >= k->lo[2] && x[2] <= k->hi[2]))) {
            P->x[i] = x[0];
            P->y[i] = x[1];
            SPH_SET(M, P, vx, i, v[0]);
            SPH_SET(M, P, vy, i, v[1]);
            if (D == 3) {
                P->z[i] = x[2];
                SPH_SET(M, P, vz, i, v[2]);
            }
        } else {
            P->type[i] = SPH_LOST; /* frozen where it left */
            SPH_SET(M, P, vx, i, 0.0);
            SPH_SET(M, P, vy, i, 0.0);
            if (D == 3)
                SPH_SET(M, P, vz, i, 0.0);
        }
    }
    SPH_SET(M, P, rho, i, SPH_GET(M, P, rho, i) + dt * SPH_GET(M, P, drho0, i));
    return bad;
}

/* The corrector of particle i: a fluid particle's velocity, every density (walls never below
 * rho0); its speed squared and density into the running maxima and minimum. Returns 1 when one
 * is not finite. */
SPH_HD static inline __attribute__((always_inline)) long correct_one(const int D, const int M,
                                                                     const step_ctx *k, double dt,
                                                                     long i, double *vmax2,
                                                                     double *rlo, double *rhi)
{
    sph_particles *P = k->P;
    long bad = 0;
    double rho =
        SPH_GET(M, P, rho, i) + 0.5 * dt * (SPH_GET(M, P, drho, i) - SPH_GET(M, P, drho0, i));
    if (P->type[i] == SPH_FLUID) {
        const double vx =
            SPH_GET(M, P, vx, i) + 0.5 * dt * (SPH_GET(M, P, ax, i) - SPH_GET(M, P, ax0, i));
        const double vy =
            SPH_GET(M, P, vy, i) + 0.5 * dt * (SPH_GET(M, P, ay, i) - SPH_GET(M, P, ay0, i));
        SPH_SET(M, P, vx, i, vx);
        SPH_SET(M, P, vy, i, vy);
        double v2 = vx * vx + vy * vy;
        if (D == 3) {
            const double vz =
                SPH_GET(M, P, vz, i) + 0.5 * dt * (SPH_GET(M, P, az, i) - SPH_GET(M, P, az0, i));
            SPH_SET(M, P, vz, i, vz);
            v2 += vz * vz;
        }
        *vmax2 = v2 > *vmax2 ? v2 : *vmax2;
        bad += !isfinite(v2);
    } else if (rho < k->rho0) {
        rho = k->rho0; /* walls do not pull fluid in (as DualSPHysics does) */
    }
    SPH_SET(M, P, rho, i, rho);
    bad += !isfinite(rho);
    *rlo = rho < *rlo ? rho : *rlo;
    *rhi = rho > *rhi ? rho : *rhi;
    return bad;
}

#endif
