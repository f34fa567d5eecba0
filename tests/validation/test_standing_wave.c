/*
 * Viscous standing wave (Macia et al., paper 001, section IV): L = lambda = 1 m, H = 0.5 m,
 * eps = 2A/H = 0.1, Re = H sqrt(gH)/nu, ghost (free-slip) walls, Monaghan's viscous term, h = 2
 * dx, c0 = 10 sqrt(gH) rounded up, run for PERIODS periods. The decay rate of the kinetic-energy
 * envelope and the period, fitted over the first 8 periods (sph_sim_wave_fit), against Lighthill's
 * 4 nu k^2 (eq. 8) and 2 pi / omega.
 * Usage: test_standing_wave [--res H/DX] [--re RE] [--kernel NAME] [--periods N]
 *                           [--period-bound F] [--rate-bound F] [--csv FILE] [--rpdf FILE]
 *                           [--delta D]
 * Passes when |T - T_theory| <= period-bound T_theory and |beta - 4 nu k^2| <= rate-bound
 * 4 nu k^2 (defaults 0.02 and 0.15). Writes t, E_kin/E_kin(0) and eq. (8) to the --csv FILE,
 * and the radial particle density function (q = r/h, pairs, density) at the start and at the end
 * to the --rpdf FILE (paper 001 figs. 8, 9, 15).
 */
#include "sph_initial.h"
#include "sph_sim.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int main(int argc, char **argv)
{
    double res = 50, re = 500, periods = 10, period_bound = 0.02, rate_bound = 0.15, delta = 0.0;
    const char *kernel = "wendland_c2", *csv = NULL, *rpdf = NULL;
    for (int i = 1; i + 1 < argc; i += 2) {
        if (!strcmp(argv[i], "--res"))
            res = atof(argv[i + 1]);
        else if (!strcmp(argv[i], "--re"))
            re = atof(argv[i + 1]);
        else if (!strcmp(argv[i], "--delta"))
            delta = atof(argv[i + 1]);
        else if (!strcmp(argv[i], "--kernel"))
            kernel = argv[i + 1];
        else if (!strcmp(argv[i], "--periods"))
            periods = atof(argv[i + 1]);
        else if (!strcmp(argv[i], "--period-bound"))
            period_bound = atof(argv[i + 1]);
        else if (!strcmp(argv[i], "--rate-bound"))
            rate_bound = atof(argv[i + 1]);
        else if (!strcmp(argv[i], "--csv"))
            csv = argv[i + 1];
        else if (!strcmp(argv[i], "--rpdf"))
            rpdf = argv[i + 1];
        else {
            fprintf(stderr, "usage: see the file's header\n");
            return 64;
        }
    }
    const double L = 1.0, H = 0.5, g = 9.81, dx = H / res;
    sph_config c = sph_config_default();
    const int kt = sph_kernel_type_from_name(kernel);
    if (kt < 0) {
        fprintf(stderr, "unknown kernel %s\n", kernel);
        return 64;
    }
    c.kernel = sph_kernel_spec_default((sph_kernel_type)kt);
    c.h_over_dx = 2.0;
    c.dx = dx;
    c.domain = (sph_box){{0, 0, 0}, {L, 2.0 * H, 0}};
    c.nfluid = 1;
    c.fluid[0] = (sph_box){{0, 0, 0}, {L, H, 0}};
    c.boundary = SPH_BOUNDARY_GHOST;
    c.has_tank = 1;
    c.tank = (sph_box){{0, 0, 0}, {L, 2.0 * H, 0}};
    c.c0 = ceil(10.0 * sqrt(g * H));
    c.visc = SPH_VISC_MONAGHAN;
    c.nu = H * sqrt(g * H) / re;
    c.initial = sph_initial_default(SPH_INITIAL_STANDING_WAVE);
    c.delta_sph = delta;
    c.t_end = 1.0; /* set below from the theory's period */
    sph_error err;
    sph_sim *s = sph_sim_create(&c, &err);
    if (!s) {
        fprintf(stderr, "FAIL: %s (%s)\n", err.message, err.path);
        return 1;
    }
    sph_sim_wave w;
    sph_sim_wave_fit(s, 0.0, &w); /* the theory only, for the end time */
    c.t_end = periods * w.period_theory;
    enum { NB = SPH_SIM_RPDF_BINS };
    double q[NB], c0[NB], d0[NB], c1[NB], d1[NB];
    if (sph_sim_rpdf(s, SPH_SIM_RPDF_QMAX, NB, q, c0, d0, &err)) {
        fprintf(stderr, "FAIL: %s\n", err.message);
        return 1;
    }
    FILE *f = csv ? fopen(csv, "w") : NULL;
    const double e0 = sph_sim_diag(s)->ekin;
    if (f)
        fprintf(f, "# standing wave, %s, Re %g, H/dx %g: t [s], Ekin/Ekin(0), eq. (8)\n", kernel,
                re, res);
    while (sph_sim_time(s) < c.t_end) {
        const double t = sph_sim_time(s);
        if (f)
            fprintf(f, "%.6f %.6e %.6e\n", t, sph_sim_diag(s)->ekin / e0,
                    0.5 * exp(-w.decay_rate_theory * t) *
                        (1.0 + cos(4.0 * M_PI * t / w.period_theory)));
        if (sph_sim_advance(s, 20, c.t_end, &err)) {
            fprintf(stderr, "FAIL: %s\n", err.message);
            return 1;
        }
    }
    if (f)
        fclose(f);
    if (rpdf && (f = fopen(rpdf, "w")) != NULL) {
        if (sph_sim_rpdf(s, SPH_SIM_RPDF_QMAX, NB, q, c1, d1, &err)) {
            fprintf(stderr, "FAIL: %s\n", err.message);
            return 1;
        }
        fprintf(f,
                "# RPDF, %s, Re %g, H/dx %g, at t = 0 and t = %g s: q = r/h, pairs(0), "
                "density(0), pairs(t), density(t)\n",
                kernel, re, res, sph_sim_time(s));
        for (int b = 0; b < NB; b++)
            fprintf(f, "%.4f %g %.5f %g %.5f\n", q[b], c0[b], d0[b], c1[b], d1[b]);
        fclose(f);
    }
    if (sph_sim_wave_fit(s, 8.0 * w.period_theory, &w)) {
        fprintf(stderr, "FAIL: fewer than 3 kinetic-energy peaks\n");
        return 1;
    }
    const sph_diag *d = sph_sim_diag(s);
    const double perr = (w.period - w.period_theory) / w.period_theory;
    const double rerr = (w.decay_rate - w.decay_rate_theory) / w.decay_rate_theory;
    printf("standing wave: %s, Re %g, H/dx %g, %ld particles, %ld steps, alpha %.5f, nu %.4g "
           "m^2/s\n",
           kernel, re, res, d->nfluid, d->step, w.alpha, w.nu);
    printf("standing wave: Ekin(0) %.4f J (theory %.4f), %d peaks up to t = %.3f s\n", e0,
           w.ekin0_theory, w.peaks, w.t_fit);
    printf("standing wave: period %.4f s, theory %.4f s, error %+.2f%% (bound %g%%)\n", w.period,
           w.period_theory, 100.0 * perr, 100.0 * period_bound);
    printf("standing wave: decay rate %.4f 1/s, theory 4 nu k^2 = %.4f 1/s, error %+.1f%% (bound "
           "%g%%)\n",
           w.decay_rate, w.decay_rate_theory, 100.0 * rerr, 100.0 * rate_bound);
    const int ok = fabs(perr) <= period_bound && fabs(rerr) <= rate_bound;
    printf("%s\n", ok ? "PASS" : "FAIL");
    sph_sim_destroy(s);
    return ok ? 0 : 1;
}
