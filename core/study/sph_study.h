/*
 * sph_study: the kernel particle-approximation study of Yang, Peng & Liu 2014, section 3.3.
 *
 * N particles evenly spaced on [xmin, xmax] (ends included), spacing dx, volume dx each,
 * h = h_over_dx * dx. For each kernel and test function f, the SPH particle approximations
 *   <f>_a     = sum_b f_b W(x_a - x_b) dx                      (eq. 2)
 *   <df/dx>_a = sum_b f_b dW/dx_a (x_a - x_b) dx               (eq. 3)
 * and their relative errors E = (<g> - g) / g (eqs. 25, 26) at every interior particle (farther
 * than the support radius from both ends), summarised as the maximum |E| and the RMS of E, and at
 * the point `at` (the sums evaluated at x = at). Also each kernel's 1D normalisation integral and
 * second moment (eq. 24) in units of h^2, by quadrature.
 */
#ifndef SPH_STUDY_H
#define SPH_STUDY_H

#include "sph_error.h"
#include "sph_kernel.h"

#define SPH_STUDY_MAX_KERNELS   16
#define SPH_STUDY_MAX_PARTICLES 10000000
#define SPH_STUDY_MIN_PARTICLES 3
#define SPH_STUDY_MAX_H_OVER_DX 10.0

typedef enum {
    SPH_FN_EXP = 0, /* exp(x) */
    SPH_FN_SIN,     /* sin(x) */
    SPH_FN_COS,     /* cos(x) */
    SPH_FN_POLY2,   /* 1 + x + x^2 (never zero, so its relative error is defined everywhere) */
    SPH_FN_COUNT
} sph_function;

typedef struct sph_study_config {
    double xmin, xmax; /* the line [m] */
    long particles;    /* N, ends included */
    double h_over_dx;  /* h = h_over_dx * dx */
    int nkernels;
    sph_kernel_spec kernels[SPH_STUDY_MAX_KERNELS];
    int nfunctions;
    sph_function functions[SPH_FN_COUNT];
    double at; /* point of the pointwise error [m] */
} sph_study_config;

typedef struct sph_error_summary {
    double max; /* max |E| over the interior particles [-] */
    double rms; /* sqrt(mean E^2) over the interior particles [-] */
    double at;  /* E at the point `at` (NaN where g(at) = 0) [-] */
} sph_error_summary;

typedef struct sph_study_kernel_result {
    sph_kernel_spec spec;
    double h;                             /* [m] */
    double support;                       /* [m] */
    double normalisation;                 /* integral of W over the line, by quadrature [-] */
    double second_moment;                 /* integral of x^2 W dx / h^2, by quadrature [-] */
    long interior;                        /* number of interior particles */
    sph_error_summary f[SPH_FN_COUNT];    /* indexed like cfg->functions */
    sph_error_summary dfdx[SPH_FN_COUNT]; /* indexed like cfg->functions */
} sph_study_kernel_result;

typedef struct sph_study_result {
    double dx; /* [m] */
    int nkernels;
    sph_study_kernel_result kernels[SPH_STUDY_MAX_KERNELS];
} sph_study_result;

/* Case-file name of a function ("exp", ...), NULL if invalid; and the reverse (-1 if unknown). */
const char *sph_function_name(sph_function fn);
int sph_function_from_name(const char *name);

/* Checks cfg; returns 0 or SPH_ERR_INVALID with err naming the field (JSON pointer). */
int sph_study_validate(const sph_study_config *cfg, sph_error *err);

/* Runs the study. Returns 0, or an error code with err filled in. */
int sph_study_run(const sph_study_config *cfg, sph_study_result *res, sph_error *err);

/* 1D moment of a kernel by quadrature: integral of |x|^p W(|x|) over the line. */
double sph_kernel_moment_1d(const sph_kernel *k, int p);

#endif
