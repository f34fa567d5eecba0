/*
 * The physics of one WCSPH pair (Yang, Peng & Liu 2014, section 2.2; Macia et al. for the
 * artificial viscosity), written once for 2D and 3D: the dimension D and the option flags F are
 * compile-time constants of the loops that call it (core/wcsph/sph_wcsph.c; a GPU kernel
 * later), which fold every test on them away. The function reads the pair's geometry and state
 * and returns what the pair adds to each of its particles; the caller decides which particles
 * take it (a symmetric CPU loop adds to both a and b, a gather loop to a alone) and in which
 * order, and keeps the sums. In 2D the arithmetic is exactly the 2D code's of before the 3D
 * core, operation for operation (tests/regress/golden.py checks it bit for bit).
 */
#ifndef SPH_WCSPH_PAIR_H
#define SPH_WCSPH_PAIR_H

#include "sph_hd.h"

#include <math.h>

/* Option flags, instantiated as constants. GHOST: the walls are ghost particles (free slip,
 * boundary/sph_wall_ghost.c), which take part in every term like fluid neighbours, delta-SPH
 * included; only ghost-ghost pairs are skipped. MONAGHAN: Monaghan's viscous term on every
 * pair, approaching or not, as a physical viscosity (Macia et al.). BODY: the case has rigid
 * bodies (boundary/sph_body.h), whose particles interact with everything but their own body. */
enum {
    SPH_WF_LAMINAR = 1,
    SPH_WF_SPS = 2,
    SPH_WF_DELTA = 4,
    SPH_WF_GHOST = 8,
    SPH_WF_MONAGHAN = 16,
    SPH_WF_BODY = 32,
    SPH_WF_COUNT = 64
};

/* The constants of a force evaluation. */
typedef struct sph_wcsph_pair_const {
    double m;        /* particle mass [kg] */
    double h;        /* smoothing length [m] */
    double eta2;     /* 0.01 h^2 [m^2] */
    double alpha_c0; /* Monaghan's term (artificial or physical): alpha c0 [m/s] */
    double mu8;      /* laminar: 8 mu = 8 rho0 nu [Pa s] */
    double dcoef;    /* delta-SPH: 2 delta h c0 m [kg m^2/s] */
    double dgh[3];   /* delta-SPH, Fourtakas et al.'s form: the hydrostatic density's gradient
                        rho0 g / c0^2 (0 in Molteni & Colagrossi's) [kg/m^4] */
} sph_wcsph_pair_const;

/* What a pair adds: a gets +f, b gets -f; both get dd (continuity, eq. 12); delta-SPH: a gets
 * +dwa, b gets -dwb; SPS: a gets ga, b gets gb (the velocity gradients xx, xy, yy, and in 3D
 * zz, xz, yz). */
typedef struct sph_wcsph_pair_out {
    double f[3];
    double dd;
    double dwa, dwb;
    double ga[6], gb[6];
} sph_wcsph_pair_out;

/* The pair a (position, velocity, density, p / rho^2: pri) and b, d = x_a - x_b, r2 = |d|^2,
 * fw = (dW/dr) / r (grad_a W_ab = fw d), dv = v_a - v_b. vf: the factor on the viscous terms
 * (the walls' viscosity factor on fluid-wall pairs, else 1). ta, tb (SPS): the sub-particle
 * stresses / rho of a and b (xx, xy, yy, and in 3D zz, xz, yz). delta: whether delta-SPH acts on
 * this pair. */
SPH_HD static inline __attribute__((always_inline)) void
sph_wcsph_pair(const int D, const unsigned F, const sph_wcsph_pair_const *SPH_RESTRICT k,
               const double *SPH_RESTRICT d, double r2, double fw, const double *SPH_RESTRICT dv,
               double rhoi, double rhoj, double pri, double prj, double vf,
               const double *SPH_RESTRICT ta, const double *SPH_RESTRICT tb, int delta,
               sph_wcsph_pair_out *SPH_RESTRICT o)
{
    const double m = k->m;
    const double vr =
        D == 3 ? dv[0] * d[0] + dv[1] * d[1] + dv[2] * d[2] : dv[0] * d[0] + dv[1] * d[1];

    /* eq. (12): continuity */
    o->dd = m * vr * fw;

    /* eq. (13): pressure, with Monaghan's viscous term Pi_ab (Macia et al.): artificial
     * (approaching pairs only) or physical (every pair, alpha from nu) */
    double pt = pri + prj;
    if ((F & SPH_WF_MONAGHAN) || (!(F & SPH_WF_LAMINAR) && vr < 0.0)) {
        const double mu = k->h * vr / (r2 + k->eta2);
        pt -= vf * k->alpha_c0 * mu * 2.0 / (rhoi + rhoj);
    }
    for (int c = 0; c < D; c++)
        o->f[c] = -m * pt * fw * d[c];

    if (F & SPH_WF_LAMINAR) { /* eq. (14) (Morris: the Laplacian in any dimension) */
        const double rs = rhoi + rhoj;
        const double lc = vf * k->mu8 * m * fw * r2 / (rs * rs * (r2 + k->eta2));
        for (int c = 0; c < D; c++)
            o->f[c] += lc * dv[c];
    }
    if (F & SPH_WF_SPS) { /* eq. (15): sub-particle stress; velocity gradients for eq. (9) */
        const double sxx = ta[0] + tb[0], sxy = ta[1] + tb[1], syy = ta[2] + tb[2];
        const double gx = fw * d[0], gy = fw * d[1];
        const double vi = -m / rhoj, vj = -m / rhoi;
        if (D == 3) {
            const double szz = ta[3] + tb[3], sxz = ta[4] + tb[4], syz = ta[5] + tb[5];
            o->f[0] += m * fw * (sxx * d[0] + sxy * d[1] + sxz * d[2]);
            o->f[1] += m * fw * (sxy * d[0] + syy * d[1] + syz * d[2]);
            o->f[2] += m * fw * (sxz * d[0] + syz * d[1] + szz * d[2]);
        } else {
            o->f[0] += m * fw * (sxx * d[0] + sxy * d[1]);
            o->f[1] += m * fw * (sxy * d[0] + syy * d[1]);
        }
        o->ga[0] = vi * dv[0] * gx;
        o->ga[1] = vi * (dv[0] * gy + dv[1] * gx);
        o->ga[2] = vi * dv[1] * gy;
        o->gb[0] = vj * dv[0] * gx;
        o->gb[1] = vj * (dv[0] * gy + dv[1] * gx);
        o->gb[2] = vj * dv[1] * gy;
        if (D == 3) {
            const double gz = fw * d[2];
            o->ga[3] = vi * dv[2] * gz;
            o->ga[4] = vi * (dv[0] * gz + dv[2] * gx);
            o->ga[5] = vi * (dv[1] * gz + dv[2] * gy);
            o->gb[3] = vj * dv[2] * gz;
            o->gb[4] = vj * (dv[0] * gz + dv[2] * gx);
            o->gb[5] = vj * (dv[1] * gz + dv[2] * gy);
        }
    }
    if ((F & SPH_WF_DELTA) && delta) {
        /* delta-SPH (Molteni & Colagrossi 2009): 2 delta h c0 sum (rho_b - rho_a)
         * (x_b - x_a).grad_a W / (r^2 + eta^2) V_b; in Fourtakas et al.'s (2019) form the
         * hydrostatic part of rho_b - rho_a, rho0 g.(x_b - x_a) / c0^2 = -dgh.d, taken off
         * (with dgh = 0, Molteni's: the same bits) */
        double gd = k->dgh[0] * d[0] + k->dgh[1] * d[1];
        if (D == 3)
            gd += k->dgh[2] * d[2];
        const double w = k->dcoef * ((rhoj - rhoi) + gd) * (-fw * r2) / (r2 + k->eta2);
        o->dwa = w / rhoj;
        o->dwb = w / rhoi;
    } else {
        o->dwa = o->dwb = 0.0;
    }
}

/* The sub-particle stress / rho of a fluid particle from its velocity gradients g (xx, xy, yy,
 * and in 3D zz, xz, yz; the off-diagonal ones are du_i/dx_j + du_j/dx_i), into t (the same
 * components): Yang et al. eqs. (7)-(9), Smagorinsky's eddy viscosity nut = smag |S| sqrt 2
 * (smag = (Cs dx)^2), the isotropic part after Dalrymple & Rogers 2006 (blin = 2/3 CI dx^2). */
SPH_HD static inline __attribute__((always_inline)) void
sph_wcsph_sps_stress(const int D, const double *SPH_RESTRICT g, double rho, double smag,
                     double blin, double *SPH_RESTRICT t)
{
    if (D == 3) {
        const double dudx = g[0], sxy = g[1], dvdy = g[2], dwdz = g[3], sxz = g[4], syz = g[5];
        const double s2 = 2.0 * (dudx * dudx + dvdy * dvdy + dwdz * dwdz) + sxy * sxy + sxz * sxz +
                          syz * syz;        /* 2 S:S */
        const double nut = smag * sqrt(s2); /* eq. (8) */
        const double iso = -(2.0 / 3.0 * nut * (dudx + dvdy + dwdz) + blin * s2);
        t[0] = (2.0 * nut * dudx + iso) / rho;
        t[1] = nut * sxy / rho;
        t[2] = (2.0 * nut * dvdy + iso) / rho;
        t[3] = (2.0 * nut * dwdz + iso) / rho;
        t[4] = nut * sxz / rho;
        t[5] = nut * syz / rho;
        return;
    }
    const double dudx = g[0], sxy = g[1], dvdy = g[2];
    const double s2 = 2.0 * (dudx * dudx + dvdy * dvdy) + sxy * sxy; /* 2 S:S */
    const double nut = smag * sqrt(s2);                              /* eq. (8) */
    const double iso = -(2.0 / 3.0 * nut * (dudx + dvdy) + blin * s2);
    t[0] = (2.0 * nut * dudx + iso) / rho;
    t[1] = nut * sxy / rho;
    t[2] = (2.0 * nut * dvdy + iso) / rho;
}

#endif
