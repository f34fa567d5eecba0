/*
 * sph_kernel: the kernel library. Each kernel is a closed form W(r, h) = norm * f(q), q = r / h,
 * with norm = sigma_d / h^d, in 1, 2 and 3 dimensions, with value and radial derivative.
 *
 * Kernels are data: sph_kernel_init() derives every constant once (the normalisation of each
 * kernel in each dimension is derived in closed form here, not copied from the papers, and checked
 * by quadrature in tests/unit/test_kernel.c). Evaluation is `static inline`.
 *
 * Selecting a kernel per job without a function-pointer call per pair:
 *   - sph_kernel_w() / sph_kernel_dwdr() switch on k->type. Fine outside hot loops.
 *   - Hot loops are written once as a `static inline` function taking the kernel type as an
 *     argument and calling sph_kernel_eval_t(TYPE, ...). The loop is instantiated per kernel
 * through SPH_KERNEL_DISPATCH(k->type, CALL), which switches once, outside the loop, and passes a
 *     compile-time constant; the compiler then folds the switch inside sph_kernel_eval_t away and
 *     inlines the one closed form into the loop body.
 *
 * Sources (equation numbers are the papers', see ../shared/papers/README.md):
 *   cubic spline        Yang, Peng & Liu 2014, eq. (22); support 2h
 *   gaussian            Yang, Peng & Liu 2014, eq. (21); truncated at `radius` h (default 3) and
 *                       renormalised so that the truncated kernel integrates to exactly 1
 *   double cosine       Yang, Peng & Liu 2014, eq. (20); support kappa h, kappa in [2, 3]
 *   wendland c2         Macia et al., eq. (4), (2 - q)^4 (1 + 2q); support 2h
 *   renormalized gauss  Macia et al., eq. (5), alpha = 3/2, m = exp(-9); support 2h
 *   koshizuka (MPS)     Koshizuka & Oka 1996, w = re/r - 1 for r < re; not normalised
 *   sheu quartic (MPS)  Sheu et al. 2011, eq. (4.8); normalised in 1D (eq. 4.10)
 * MPS kernels use the effective radius re = 2h (Sheu et al.: "re = 2h, h the grid size").
 */
#ifndef SPH_KERNEL_H
#define SPH_KERNEL_H

#include "sph_error.h"
#include "sph_hd.h"

#include <math.h>

typedef enum {
    SPH_KERNEL_CUBIC_SPLINE = 0,
    SPH_KERNEL_GAUSSIAN,
    SPH_KERNEL_DOUBLE_COSINE,
    SPH_KERNEL_WENDLAND_C2,
    SPH_KERNEL_RENORMALIZED_GAUSSIAN,
    SPH_KERNEL_KOSHIZUKA,
    SPH_KERNEL_SHEU_QUARTIC,
    SPH_KERNEL_COUNT
} sph_kernel_type;

/* What a case file says about a kernel. */
typedef struct sph_kernel_spec {
    sph_kernel_type type;
    double kappa;  /* double cosine: support radius in units of h, [2, 3]; default 2 */
    double radius; /* gaussian: truncation radius in units of h, [2, 6]; default 3 */
} sph_kernel_spec;

#define SPH_KERNEL_KAPPA_DEFAULT    2.0
#define SPH_KERNEL_KAPPA_MIN        2.0
#define SPH_KERNEL_KAPPA_MAX        3.0
#define SPH_KERNEL_GAUSS_RADIUS     3.0
#define SPH_KERNEL_GAUSS_RADIUS_MIN 2.0
#define SPH_KERNEL_GAUSS_RADIUS_MAX 6.0
#define SPH_KERNEL_RGK_ALPHA        1.5 /* Macia et al.: alpha = 3/2 */

/* An initialised kernel: everything a pair evaluation needs. */
typedef struct sph_kernel {
    sph_kernel_type type;
    int dim;        /* 1, 2 or 3 */
    double h;       /* smoothing length [m] */
    double inv_h;   /* 1 / h [1/m] */
    double qmax;    /* support radius in units of h [-] */
    double support; /* support radius qmax * h [m] */
    double norm;    /* sigma_d / h^d: W = norm * f(q) [1/m^d]; MPS kernels: see above */
    double c1;      /* gaussian: -; double cosine: pi / kappa; RGK: alpha^2; quartic: a */
    double c2;      /* RGK: m_alpha = exp(-4 alpha^2); quartic: c */
    double c3;      /* quartic: d */
    double c4;      /* quartic: e */
} sph_kernel;

/* The spec a kernel type gets when a case names it without parameters. */
sph_kernel_spec sph_kernel_spec_default(sph_kernel_type type);

/* Initialises k for dimension dim (1..3) and smoothing length h > 0. Returns 0, or an SPH_ERR_*
 * code with err filled in (path relative to the kernel object, e.g. "/kappa"). */
int sph_kernel_init(sph_kernel *k, const sph_kernel_spec *spec, int dim, double h, sph_error *err);

/* Case-file name of a type ("cubic_spline", ...); NULL for an invalid type. */
const char *sph_kernel_type_name(sph_kernel_type type);
/* Type from its case-file name; returns -1 if unknown. */
int sph_kernel_type_from_name(const char *name);
/* True for the MPS weight functions (koshizuka, sheu_quartic). */
int sph_kernel_is_mps(sph_kernel_type type);
/* The sigma_d of a type and dimension (norm * h^d), derived in closed form. */
double sph_kernel_sigma(const sph_kernel_spec *spec, int dim);

/* The quartic kernel's coefficients (Sheu et al. eq. 4.8, with the misprint in e corrected):
 * w(s) = (a + c s^2 + d s^3 + e s^4) / re, s = r / re. */
void sph_kernel_sheu_coefficients(double *a, double *c, double *d, double *e);

/*
 * Evaluation. sph_kernel_eval_t() returns W(r) and stores dW/dr in *dwdr, for 0 <= r; both are
 * zero for r >= support. `type` should be a compile-time constant in hot loops (see above).
 */
SPH_HD static inline __attribute__((always_inline)) double
sph_kernel_eval_t(sph_kernel_type type, const sph_kernel *k, double r, double *dwdr)
{
    const double q = r * k->inv_h;
    if (q >= k->qmax) {
        *dwdr = 0.0;
        return 0.0;
    }
    double f, fq; /* shape f(q) and df/dq */
    switch (type) {
    case SPH_KERNEL_CUBIC_SPLINE: {
        const double a = 2.0 - q;
        if (q < 1.0) {
            const double b = 1.0 - q;
            f = a * a * a - 4.0 * b * b * b;
            fq = -3.0 * a * a + 12.0 * b * b;
        } else {
            f = a * a * a;
            fq = -3.0 * a * a;
        }
        break;
    }
    case SPH_KERNEL_GAUSSIAN:
        f = exp(-q * q);
        fq = -2.0 * q * f;
        break;
    case SPH_KERNEL_DOUBLE_COSINE: {
        const double x = k->c1 * q; /* pi q / kappa */
        const double s1 = sin(x), c1 = cos(x);
        /* cos 2x = 2 cos^2 x - 1, sin 2x = 2 sin x cos x: one sin and one cos per pair */
        f = 4.0 * c1 + (2.0 * c1 * c1 - 1.0) + 3.0;
        fq = -k->c1 * (4.0 * s1 + 4.0 * s1 * c1);
        break;
    }
    case SPH_KERNEL_WENDLAND_C2: {
        const double a = 2.0 - q;
        const double a3 = a * a * a;
        f = a3 * a * (1.0 + 2.0 * q);
        fq = -10.0 * q * a3;
        break;
    }
    case SPH_KERNEL_RENORMALIZED_GAUSSIAN: {
        const double e = exp(-k->c1 * q * q);
        f = e - k->c2;
        fq = -2.0 * k->c1 * q * e;
        break;
    }
    case SPH_KERNEL_KOSHIZUKA:
        /* w = re/r - 1 = qmax/q - 1; singular at r = 0 (MPS sums exclude the particle itself) */
        f = k->qmax / q - 1.0;
        fq = -k->qmax / (q * q);
        break;
    case SPH_KERNEL_SHEU_QUARTIC: {
        const double s = q / k->qmax; /* r / re */
        f = k->c1 + s * s * (k->c2 + s * (k->c3 + s * k->c4));
        fq = s * (2.0 * k->c2 + s * (3.0 * k->c3 + s * 4.0 * k->c4)) / k->qmax;
        break;
    }
    default:
        f = 0.0;
        fq = 0.0;
        break;
    }
    *dwdr = k->norm * fq * k->inv_h;
    return k->norm * f;
}

/* Generic evaluation (switches on k->type): W(r), dW/dr, and both. */
SPH_HD static inline double sph_kernel_w(const sph_kernel *k, double r)
{
    double d;
    return sph_kernel_eval_t(k->type, k, r, &d);
}

SPH_HD static inline double sph_kernel_dwdr(const sph_kernel *k, double r)
{
    double d;
    (void)sph_kernel_eval_t(k->type, k, r, &d);
    return d;
}

/* Gradient with respect to the first particle's position: dW/dr * rvec / r, rvec = x_a - x_b
 * (k->dim components). Zero at r = 0. Returns W. */
SPH_HD static inline double sph_kernel_grad(const sph_kernel *k, const double *rvec, double *grad)
{
    double r2 = 0.0;
    for (int i = 0; i < k->dim; i++)
        r2 += rvec[i] * rvec[i];
    const double r = sqrt(r2);
    double dwdr;
    const double w = sph_kernel_eval_t(k->type, k, r, &dwdr);
    const double s = r > 0.0 ? dwdr / r : 0.0;
    for (int i = 0; i < k->dim; i++)
        grad[i] = s * rvec[i];
    return w;
}

/* Instantiates a hot loop per kernel type: CALL(T) is expanded once per type with T a constant. */
#define SPH_KERNEL_DISPATCH(type, CALL)                                                            \
    do {                                                                                           \
        switch (type) {                                                                            \
        case SPH_KERNEL_CUBIC_SPLINE:                                                              \
            CALL(SPH_KERNEL_CUBIC_SPLINE);                                                         \
            break;                                                                                 \
        case SPH_KERNEL_GAUSSIAN:                                                                  \
            CALL(SPH_KERNEL_GAUSSIAN);                                                             \
            break;                                                                                 \
        case SPH_KERNEL_DOUBLE_COSINE:                                                             \
            CALL(SPH_KERNEL_DOUBLE_COSINE);                                                        \
            break;                                                                                 \
        case SPH_KERNEL_WENDLAND_C2:                                                               \
            CALL(SPH_KERNEL_WENDLAND_C2);                                                          \
            break;                                                                                 \
        case SPH_KERNEL_RENORMALIZED_GAUSSIAN:                                                     \
            CALL(SPH_KERNEL_RENORMALIZED_GAUSSIAN);                                                \
            break;                                                                                 \
        case SPH_KERNEL_KOSHIZUKA:                                                                 \
            CALL(SPH_KERNEL_KOSHIZUKA);                                                            \
            break;                                                                                 \
        case SPH_KERNEL_SHEU_QUARTIC:                                                              \
            CALL(SPH_KERNEL_SHEU_QUARTIC);                                                         \
            break;                                                                                 \
        default:                                                                                   \
            break;                                                                                 \
        }                                                                                          \
    } while (0)

#endif
