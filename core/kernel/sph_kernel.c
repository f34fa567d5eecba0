/*
 * Kernel constants, derived in closed form. The papers' printed constants are not trusted: Yang et
 * al. print alpha_2 = 15/(14 pi h^2) for the cubic spline of eq. (22), which integrates to 3; the
 * value that normalises it is 5/(14 pi h^2). tests/unit/test_kernel.c checks every sigma below by
 * quadrature in 1D, 2D and 3D.
 */
#include "sph_kernel.h"

#include <string.h>

static const char *const kernel_names[SPH_KERNEL_COUNT] = {
    [SPH_KERNEL_CUBIC_SPLINE] = "cubic_spline",
    [SPH_KERNEL_GAUSSIAN] = "gaussian",
    [SPH_KERNEL_DOUBLE_COSINE] = "double_cosine",
    [SPH_KERNEL_WENDLAND_C2] = "wendland_c2",
    [SPH_KERNEL_RENORMALIZED_GAUSSIAN] = "renormalized_gaussian",
    [SPH_KERNEL_KOSHIZUKA] = "koshizuka",
    [SPH_KERNEL_SHEU_QUARTIC] = "sheu_quartic",
};

const char *sph_kernel_type_name(sph_kernel_type type)
{
    if ((int)type < 0 || type >= SPH_KERNEL_COUNT)
        return NULL;
    return kernel_names[type];
}

int sph_kernel_type_from_name(const char *name)
{
    for (int i = 0; i < SPH_KERNEL_COUNT; i++)
        if (name && strcmp(name, kernel_names[i]) == 0)
            return i;
    return -1;
}

int sph_kernel_is_mps(sph_kernel_type type)
{
    return type == SPH_KERNEL_KOSHIZUKA || type == SPH_KERNEL_SHEU_QUARTIC;
}

sph_kernel_spec sph_kernel_spec_default(sph_kernel_type type)
{
    sph_kernel_spec s = {
        .type = type, .kappa = SPH_KERNEL_KAPPA_DEFAULT, .radius = SPH_KERNEL_GAUSS_RADIUS};
    return s;
}

void sph_kernel_sheu_coefficients(double *a, double *c, double *d, double *e)
{
    /* Sheu et al. 2011 below eq. (4.7). The paper prints e = 480(sqrt2 - 600)/(...); the value
     * consistent with a = 1 - e/15 and the other constraints is (480 sqrt2 - 600)/(...). */
    const double s2 = sqrt(2.0);
    const double den = 512.0 * s2 - 745.0;
    *a = (480.0 * s2 - 705.0) / den;
    *c = (-960.0 * s2 + 1515.0) / den;
    *d = -210.0 / den;
    *e = (480.0 * s2 - 600.0) / den;
}

/* Integral of q^(d-1) exp(-a q^2) over [0, R], for d = 1, 2, 3. */
static double gauss_radial_moment(int d, double a, double R)
{
    const double sa = sqrt(a);
    switch (d) {
    case 1:
        return sqrt(M_PI) * erf(sa * R) / (2.0 * sa);
    case 2:
        return (1.0 - exp(-a * R * R)) / (2.0 * a);
    default:
        return sqrt(M_PI) * erf(sa * R) / (4.0 * a * sa) - R * exp(-a * R * R) / (2.0 * a);
    }
}

/* Measure of the unit sphere's surface in d dimensions, with the 1D "sphere" {-1, 1}: 2. */
static double sphere_measure(int d)
{
    return d == 1 ? 2.0 : d == 2 ? 2.0 * M_PI : 4.0 * M_PI;
}

double sph_kernel_sigma(const sph_kernel_spec *spec, int dim)
{
    const double pi = M_PI;
    switch (spec->type) {
    case SPH_KERNEL_CUBIC_SPLINE: {
        /* Integral of f over R^d: 6 (1D), 14 pi / 5 (2D), 4 pi (3D). */
        static const double sigma[4] = {0, 1.0 / 6.0, 5.0 / (14.0 * M_PI), 1.0 / (4.0 * M_PI)};
        return sigma[dim];
    }
    case SPH_KERNEL_GAUSSIAN:
        return 1.0 / (sphere_measure(dim) * gauss_radial_moment(dim, 1.0, spec->radius));
    case SPH_KERNEL_DOUBLE_COSINE: {
        const double k = spec->kappa;
        if (dim == 1)
            return 1.0 / (6.0 * k);
        if (dim == 2)
            return pi / ((3.0 * pi * pi - 16.0) * k * k);
        return pi / ((4.0 * pi * pi - 30.0) * k * k * k);
    }
    case SPH_KERNEL_WENDLAND_C2: {
        /* Integral of (2-q)^4 (1+2q) q^(d-1) over [0,2]: 32/3, 32/7, 64/21 (times the sphere). */
        static const double sigma[4] = {0, 3.0 / 64.0, 7.0 / (64.0 * M_PI), 21.0 / (256.0 * M_PI)};
        return sigma[dim];
    }
    case SPH_KERNEL_RENORMALIZED_GAUSSIAN: {
        const double a = SPH_KERNEL_RGK_ALPHA * SPH_KERNEL_RGK_ALPHA;
        const double m = exp(-4.0 * a);
        const double shift = m * pow(2.0, dim) / dim; /* integral of m q^(d-1) over [0, 2] */
        return 1.0 / (sphere_measure(dim) * (gauss_radial_moment(dim, a, 2.0) - shift));
    }
    case SPH_KERNEL_KOSHIZUKA:
        return 1.0;
    case SPH_KERNEL_SHEU_QUARTIC:
        return 0.5; /* 1 / re with re = 2h: norm = 1/(2h), in every dimension (MPS divides by n0) */
    default:
        return 0.0;
    }
}

int sph_kernel_init(sph_kernel *k, const sph_kernel_spec *spec, int dim, double h, sph_error *err)
{
    memset(k, 0, sizeof *k);
    if ((int)spec->type < 0 || spec->type >= SPH_KERNEL_COUNT)
        return sph_error_set(err, SPH_ERR_INVALID, "/type", "unknown kernel type %d",
                             (int)spec->type);
    if (dim < 1 || dim > 3)
        return sph_error_set(err, SPH_ERR_INVALID, "/dim", "dim must be 1, 2 or 3, not %d", dim);
    if (!(h > 0.0) || !isfinite(h))
        return sph_error_set(err, SPH_ERR_INVALID, "/h_over_dx",
                             "the smoothing length must be positive and finite (got %g)", h);
    if (spec->type == SPH_KERNEL_DOUBLE_COSINE &&
        !(spec->kappa >= SPH_KERNEL_KAPPA_MIN && spec->kappa <= SPH_KERNEL_KAPPA_MAX))
        return sph_error_set(err, SPH_ERR_INVALID, "/kappa",
                             "kappa must be in [%g, %g] (Yang et al. 2014), got %g",
                             SPH_KERNEL_KAPPA_MIN, SPH_KERNEL_KAPPA_MAX, spec->kappa);
    if (spec->type == SPH_KERNEL_GAUSSIAN && !(spec->radius >= SPH_KERNEL_GAUSS_RADIUS_MIN &&
                                               spec->radius <= SPH_KERNEL_GAUSS_RADIUS_MAX))
        return sph_error_set(err, SPH_ERR_INVALID, "/radius",
                             "the gaussian truncation radius must be in [%g, %g] h, got %g",
                             SPH_KERNEL_GAUSS_RADIUS_MIN, SPH_KERNEL_GAUSS_RADIUS_MAX,
                             spec->radius);

    k->type = spec->type;
    k->dim = dim;
    k->h = h;
    k->inv_h = 1.0 / h;
    const double sigma = sph_kernel_sigma(spec, dim);
    switch (spec->type) {
    case SPH_KERNEL_GAUSSIAN:
        k->qmax = spec->radius;
        break;
    case SPH_KERNEL_DOUBLE_COSINE:
        k->qmax = spec->kappa;
        k->c1 = M_PI / spec->kappa;
        break;
    case SPH_KERNEL_RENORMALIZED_GAUSSIAN:
        k->qmax = 2.0;
        k->c1 = SPH_KERNEL_RGK_ALPHA * SPH_KERNEL_RGK_ALPHA;
        k->c2 = exp(-4.0 * k->c1);
        break;
    case SPH_KERNEL_SHEU_QUARTIC:
        k->qmax = 2.0;
        sph_kernel_sheu_coefficients(&k->c1, &k->c2, &k->c3, &k->c4);
        break;
    default:
        k->qmax = 2.0;
        break;
    }
    k->support = k->qmax * h;
    if (sph_kernel_is_mps(spec->type))
        k->norm = spec->type == SPH_KERNEL_SHEU_QUARTIC ? sigma / h : sigma;
    else
        k->norm = sigma / pow(h, dim);
    return 0;
}
