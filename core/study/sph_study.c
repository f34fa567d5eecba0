#include "sph_study.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char *const function_names[SPH_FN_COUNT] = {
    [SPH_FN_EXP] = "exp", [SPH_FN_SIN] = "sin", [SPH_FN_COS] = "cos", [SPH_FN_POLY2] = "poly2"};

const char *sph_function_name(sph_function fn)
{
    if ((int)fn < 0 || fn >= SPH_FN_COUNT)
        return NULL;
    return function_names[fn];
}

int sph_function_from_name(const char *name)
{
    for (int i = 0; i < SPH_FN_COUNT; i++)
        if (name && strcmp(name, function_names[i]) == 0)
            return i;
    return -1;
}

/* f(x) and f'(x) */
static double fn_eval(sph_function fn, double x, double *dfdx)
{
    switch (fn) {
    case SPH_FN_EXP:
        *dfdx = exp(x);
        return *dfdx;
    case SPH_FN_SIN:
        *dfdx = cos(x);
        return sin(x);
    case SPH_FN_COS:
        *dfdx = -sin(x);
        return cos(x);
    case SPH_FN_POLY2:
    default:
        *dfdx = 1.0 + 2.0 * x;
        return 1.0 + x + x * x;
    }
}

/* Composite Simpson of |x|^p W over [0, R], split at q = 1 where the cubic spline changes piece. */
static double simpson_piece(const sph_kernel *k, int p, double a, double b, int n)
{
    const double step = (b - a) / n;
    double s = 0.0;
    for (int i = 0; i <= n; i++) {
        const double x = a + i * step;
        const double w = (i == 0 || i == n) ? 1.0 : (i % 2 ? 4.0 : 2.0);
        s += w * pow(x, p) * sph_kernel_w(k, x);
    }
    return s * step / 3.0;
}

double sph_kernel_moment_1d(const sph_kernel *k, int p)
{
    const double R = k->support;
    const double b = k->h < R ? k->h : R;
    /* W is zero at and beyond R; integrate [0, h] and [h, R) on each side (W is even) */
    double s = simpson_piece(k, p, 0.0, b, 4000);
    if (R > b)
        s += simpson_piece(k, p, b, R * (1.0 - 1e-15), 8000);
    return 2.0 * s;
}

static int is_interior(const sph_study_config *cfg, double x, double support)
{
    return x - cfg->xmin > support && cfg->xmax - x > support;
}

static long count_interior(const sph_study_config *cfg, double dx, double support)
{
    long count = 0;
    for (long a = 0; a < cfg->particles; a++)
        count += is_interior(cfg, cfg->xmin + (double)a * dx, support);
    return count;
}

int sph_study_validate(const sph_study_config *cfg, sph_error *err)
{
    if (!isfinite(cfg->xmin) || !isfinite(cfg->xmax) || !(cfg->xmax > cfg->xmin))
        return sph_error_set(err, SPH_ERR_INVALID, "/domain",
                             "the domain must have max > min (got [%g, %g])", cfg->xmin, cfg->xmax);
    if (cfg->particles < SPH_STUDY_MIN_PARTICLES || cfg->particles > SPH_STUDY_MAX_PARTICLES)
        return sph_error_set(err, SPH_ERR_INVALID, "/particles",
                             "particles must be between %d and %d, got %ld",
                             SPH_STUDY_MIN_PARTICLES, SPH_STUDY_MAX_PARTICLES, cfg->particles);
    if (!(cfg->h_over_dx > 0.0) || cfg->h_over_dx > SPH_STUDY_MAX_H_OVER_DX)
        return sph_error_set(err, SPH_ERR_INVALID, "/h_over_dx",
                             "h_over_dx must be in (0, %g], got %g", SPH_STUDY_MAX_H_OVER_DX,
                             cfg->h_over_dx);
    if (cfg->nkernels < 1 || cfg->nkernels > SPH_STUDY_MAX_KERNELS)
        return sph_error_set(err, SPH_ERR_INVALID, "/kernels",
                             "list between 1 and %d kernels (got %d)", SPH_STUDY_MAX_KERNELS,
                             cfg->nkernels);
    if (cfg->nfunctions < 1 || cfg->nfunctions > SPH_FN_COUNT)
        return sph_error_set(err, SPH_ERR_INVALID, "/functions",
                             "list between 1 and %d functions (got %d)", SPH_FN_COUNT,
                             cfg->nfunctions);
    if (!(cfg->at >= cfg->xmin && cfg->at <= cfg->xmax))
        return sph_error_set(err, SPH_ERR_INVALID, "/at",
                             "at = %g lies outside the domain [%g, %g]", cfg->at, cfg->xmin,
                             cfg->xmax);
    const double dx = (cfg->xmax - cfg->xmin) / (double)(cfg->particles - 1);
    for (int i = 0; i < cfg->nkernels; i++) {
        char path[SPH_ERROR_PATH_MAX + 32];
        sph_kernel k;
        sph_error kerr;
        if (cfg->kernels[i].type == SPH_KERNEL_KOSHIZUKA)
            return sph_error_set(err, SPH_ERR_INVALID, "/kernels",
                                 "kernels/%d: koshizuka is singular at r = 0 and has no 1D "
                                 "normalisation; a kernel study needs a normalised kernel",
                                 i);
        if (sph_kernel_init(&k, &cfg->kernels[i], 1, cfg->h_over_dx * dx, &kerr)) {
            snprintf(path, sizeof path, "/kernels/%d%s", i, kerr.path);
            return sph_error_set(err, kerr.code, path, "%s", kerr.message);
        }
        if (count_interior(cfg, dx, k.support) == 0) {
            snprintf(path, sizeof path, "/kernels/%d", i);
            return sph_error_set(err, SPH_ERR_INVALID, path,
                                 "no interior particles: the support radius %g is at least half "
                                 "the domain; use a longer domain or a smaller h_over_dx",
                                 k.support);
        }
    }
    return 0;
}

/* Approximations of f and f' at the point x from the particles within the support. */
static void approximate(const sph_kernel *k, const double *fv, double xmin, double dx, long n,
                        double x, double *fa, double *da)
{
    long lo = (long)floor((x - k->support - xmin) / dx);
    long hi = (long)ceil((x + k->support - xmin) / dx);
    if (lo < 0)
        lo = 0;
    if (hi > n - 1)
        hi = n - 1;
    double s = 0.0, g = 0.0;
    for (long b = lo; b <= hi; b++) {
        const double xb = xmin + (double)b * dx;
        const double rx = x - xb;
        double dwdr;
        const double w = sph_kernel_eval_t(k->type, k, fabs(rx), &dwdr);
        s += fv[b] * w * dx;
        g += fv[b] * (rx > 0 ? dwdr : rx < 0 ? -dwdr : 0.0) * dx;
    }
    *fa = s;
    *da = g;
}

int sph_study_run(const sph_study_config *cfg, sph_study_result *res, sph_error *err)
{
    if (sph_study_validate(cfg, err))
        return err ? (int)err->code : SPH_ERR_INVALID;
    memset(res, 0, sizeof *res);
    const long n = cfg->particles;
    const double dx = (cfg->xmax - cfg->xmin) / (double)(n - 1);
    res->dx = dx;
    res->nkernels = cfg->nkernels;

    double *fv = malloc((size_t)n * sizeof *fv);
    if (!fv)
        return sph_error_set(err, SPH_ERR_NOMEM, "/particles", "cannot allocate %ld particles", n);

    for (int ki = 0; ki < cfg->nkernels; ki++) {
        sph_study_kernel_result *kr = &res->kernels[ki];
        sph_kernel k;
        sph_kernel_init(&k, &cfg->kernels[ki], 1, cfg->h_over_dx * dx, NULL);
        kr->spec = cfg->kernels[ki];
        kr->h = k.h;
        kr->support = k.support;
        kr->normalisation = sph_kernel_moment_1d(&k, 0);
        kr->second_moment = sph_kernel_moment_1d(&k, 2) / (k.h * k.h);

        for (int fi = 0; fi < cfg->nfunctions; fi++) {
            const sph_function fn = cfg->functions[fi];
            for (long i = 0; i < n; i++) {
                double d;
                fv[i] = fn_eval(fn, cfg->xmin + (double)i * dx, &d);
            }
            double fmax = 0.0, dmax = 0.0, fsum = 0.0, dsum = 0.0;
            long count = 0;
            for (long a = 0; a < n; a++) {
                const double x = cfg->xmin + (double)a * dx;
                if (!is_interior(cfg, x, k.support))
                    continue;
                double fa, da, dexact;
                approximate(&k, fv, cfg->xmin, dx, n, x, &fa, &da);
                const double fexact = fn_eval(fn, x, &dexact);
                const double ef = (fa - fexact) / fexact;
                const double ed = (da - dexact) / dexact;
                fmax = fmax > fabs(ef) ? fmax : fabs(ef);
                dmax = dmax > fabs(ed) ? dmax : fabs(ed);
                fsum += ef * ef;
                dsum += ed * ed;
                count++;
            }
            kr->interior = count;
            kr->f[fi].max = fmax;
            kr->dfdx[fi].max = dmax;
            kr->f[fi].rms = count ? sqrt(fsum / (double)count) : NAN;
            kr->dfdx[fi].rms = count ? sqrt(dsum / (double)count) : NAN;
            double fa, da, dexact;
            approximate(&k, fv, cfg->xmin, dx, n, cfg->at, &fa, &da);
            const double fexact = fn_eval(fn, cfg->at, &dexact);
            kr->f[fi].at = fexact != 0.0 ? (fa - fexact) / fexact : NAN;
            kr->dfdx[fi].at = dexact != 0.0 ? (da - dexact) / dexact : NAN;
        }
    }
    free(fv);
    return 0;
}
