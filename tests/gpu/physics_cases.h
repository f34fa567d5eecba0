/*
 * The shared physics of sphd (kernels, EOS, the WCSPH pair, the SPS stress: the SPH_HD headers
 * of core/) evaluated on a fixed set of inputs, by one function that a C file (gcc), a CUDA
 * file's host code (nvcc + g++) and its device code (nvcc) all call: tests/gpu/. The inputs are
 * made from the sample index alone, so every caller sees the same ones.
 */
#ifndef PHYSICS_CASES_H
#define PHYSICS_CASES_H

#include "sph_eos.h"
#include "sph_hd.h"
#include "sph_kernel.h"
#include "sph_wcsph_pair.h"

#define PC_SAMPLES 256
#define PC_KERNELS 5 /* cubic spline, Gaussian, double cosine, Wendland C2, renormalised Gaussian  \
                      */
#define PC_PAIRS 8   /* 2D and 3D, 4 option sets each */
#define PC_OUT   (PC_KERNELS * 2 + 4 + PC_PAIRS * 18 + 9)

/* A number in [0, 1) from (i, j): a fixed hash, the same everywhere. */
SPH_HD static inline double pc_u(int i, int j)
{
    unsigned x = (unsigned)i * 2654435761u ^ ((unsigned)j + 0x9e3779b9u) * 40503u;
    x ^= x >> 15;
    x *= 2246822519u;
    x ^= x >> 13;
    x *= 3266489917u;
    x ^= x >> 16;
    return (double)(x & 0xffffffu) / 16777216.0;
}

/* The option sets of the pairs: 0, laminar, SPS + delta-SPH (Molteni's form), Monaghan +
 * delta-SPH (Fourtakas' form: the hydrostatic gradient rho0 g / c0^2 along the last axis). */
SPH_HD static inline void pc_pair(int D, unsigned F, int i, double h, const sph_kernel *kern,
                                  double *out)
{
    sph_wcsph_pair_const k;
    k.m = 0.5 + pc_u(i, 1);
    k.h = h;
    k.eta2 = 0.01 * h * h;
    k.alpha_c0 = 0.1 * 25.0;
    k.mu8 = 8.0e-3;
    k.dcoef = 2.0 * 0.1 * h * 25.0 * k.m;
    for (int c = 0; c < 3; c++)
        k.dgh[c] = (F & SPH_WF_MONAGHAN) && c == D - 1 ? 1000.0 * -9.81 / (25.0 * 25.0) : 0.0;
    double d[3], dv[3], ta[6], tb[6];
    for (int c = 0; c < 3; c++) {
        d[c] = (c < D ? 1.0 : 0.0) * (pc_u(i, 2 + c) - 0.5) * 1.2 * h;
        dv[c] = (c < D ? 1.0 : 0.0) * (pc_u(i, 5 + c) - 0.5);
    }
    for (int c = 0; c < 6; c++) {
        ta[c] = pc_u(i, 8 + c) - 0.5;
        tb[c] = pc_u(i, 14 + c) - 0.5;
    }
    const double r2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2] + 1e-12 * h * h;
    const double r = sqrt(r2);
    const double fw = sph_kernel_dwdr(kern, r) / r;
    const double rhoi = 1000.0 * (1.0 + 0.01 * pc_u(i, 20)),
                 rhoj = 1000.0 * (1.0 + 0.01 * pc_u(i, 21));
    sph_wcsph_pair_out o;
    sph_wcsph_pair(D, F, &k, d, r2, fw, dv, rhoi, rhoj, 600.0 * pc_u(i, 22) / (rhoi * rhoi),
                   600.0 * pc_u(i, 23) / (rhoj * rhoj), 1.0, ta, tb, (F & SPH_WF_DELTA) != 0, &o);
    out[0] = o.f[0];
    out[1] = o.f[1];
    out[2] = D == 3 ? o.f[2] : 0.0;
    out[3] = o.dd;
    out[4] = (F & SPH_WF_DELTA) ? o.dwa : 0.0;
    out[5] = (F & SPH_WF_DELTA) ? o.dwb : 0.0;
    for (int c = 0; c < 6; c++) {
        const int used = (F & SPH_WF_SPS) && c < (D == 3 ? 6 : 3);
        out[6 + c] = used ? o.ga[c] : 0.0;
        out[12 + c] = used ? o.gb[c] : 0.0;
    }
}

/* Sample i: every function's values, into out[PC_OUT]. kern: the PC_KERNELS kernels (h as
 * initialised); cfg_lin, cfg_tait: linear and Tait equations of state. */
SPH_HD static inline void pc_eval(int i, const sph_kernel *kern, const sph_config *cfg_lin,
                                  const sph_config *cfg_tait, double *out)
{
    int n = 0;
    const double h = kern[0].h;
    for (int t = 0; t < PC_KERNELS; t++) {
        const double r = pc_u(i, 30 + t) * kern[t].support * 1.05;
        double dw;
        out[n++] = sph_kernel_eval_t(kern[t].type, &kern[t], r, &dw);
        out[n++] = dw;
    }
    const double rho = 1000.0 * (0.95 + 0.1 * pc_u(i, 40));
    out[n++] = sph_eos_pressure(cfg_lin, rho);
    out[n++] = sph_eos_pressure(cfg_tait, rho);
    out[n++] = sph_eos_density(cfg_lin, 1000.0 * (pc_u(i, 41) - 0.3));
    out[n++] = sph_eos_density(cfg_tait, 1000.0 * (pc_u(i, 41) - 0.3));
    const unsigned flags[4] = {0u, SPH_WF_LAMINAR, SPH_WF_SPS | SPH_WF_DELTA,
                               SPH_WF_MONAGHAN | SPH_WF_DELTA};
    for (int p = 0; p < PC_PAIRS; p++) {
        pc_pair(p < 4 ? 2 : 3, flags[p % 4], i, h, &kern[3], out + n);
        n += 18;
    }
    double g[6], t[6];
    for (int c = 0; c < 6; c++)
        g[c] = pc_u(i, 50 + c) - 0.5;
    sph_wcsph_sps_stress(2, g, 1000.0, 1e-6, 1e-7, t);
    for (int c = 0; c < 3; c++)
        out[n++] = t[c];
    sph_wcsph_sps_stress(3, g, 1000.0, 1e-6, 1e-7, t);
    for (int c = 0; c < 6; c++)
        out[n++] = t[c];
}

#endif
