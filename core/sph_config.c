/*
 * sph_config: the plain configuration's defaults and the viscosities it implies (sph_config.h).
 *
 * Layer 0 of the set-up pipeline (DESIGN.md section 2): the configuration every layer reads. May
 * call: the kernels' and the MPS method's defaults (sph_kernel_spec_default,
 * sph_mps_config_default) and the kernels' support parameters (sph_kernel.h), libm.
 */
#include "sph_config.h"

#include <math.h>
#include <string.h>

sph_config sph_config_default(void)
{
    sph_config c;
    memset(&c, 0, sizeof c);
    c.method = SPH_METHOD_WCSPH;
    c.dim = 2;
    c.kernel = sph_kernel_spec_default(SPH_KERNEL_WENDLAND_C2);
    c.h_over_dx = 1.414; /* sqrt(2): what the shipped cases are validated with */
    c.boundary = SPH_BOUNDARY_DYNAMIC;
    c.layers = 3;
    c.wall_viscosity = 1.0;
    c.rho0 = 1000.0;
    c.gravity[1] = -9.81;
    c.eos = SPH_EOS_LINEAR;
    c.c0 = 20.0;
    c.visc = SPH_VISC_ARTIFICIAL;
    c.alpha = 0.01;
    c.turb = SPH_TURB_NONE;
    c.cfl = 0.2;
    c.diag_every = 100;
    c.probes = SPH_PROBE_FRONT_X | SPH_PROBE_HEIGHT_LEFT;
    c.max_bytes = SPH_CONFIG_DEFAULT_MAX_BYTES;
    c.mps = sph_mps_config_default();
    for (int k = 0; k < SPH_CONFIG_MAX_GAUGES; k++)
        c.gauges[k].to = NAN; /* a line, unless the case gives `to` */
    c.wavemaker.layers = 3;
    c.wavemaker.ramp = SPH_WAVEMAKER_RAMP_DEFAULT;
    c.wavemaker.order = 1;
    c.wavemaker.gamma = SPH_JONSWAP_GAMMA_DEFAULT;
    c.wavemaker.seed = 1;
    c.absorption.beta = SPH_DAMPING_BETA_DEFAULT;
    c.shifting.coefficient = SPH_SHIFT_COEFFICIENT_DEFAULT;
    /* at rest; the standing wave's parameters and the solitary wave's order (the third slot) at
     * the defaults the case table gives them */
    c.initial.type = SPH_INITIAL_REST;
    c.initial.param[0] = SPH_SW_EPSILON_DEFAULT;
    c.initial.param[1] = SPH_SW_WAVELENGTH_DEFAULT;
    c.initial.param[2] = SPH_SOL_ORDER_DEFAULT;
    return c;
}

double sph_config_monaghan_alpha(const sph_config *c)
{
    return 2.0 * (c->dim + 2) * c->nu / (c->h_over_dx * c->dx * c->c0);
}

double sph_config_viscosity_nu(const sph_config *c)
{
    if (c->visc == SPH_VISC_ARTIFICIAL)
        return c->alpha * c->h_over_dx * c->dx * c->c0 / (2.0 * (c->dim + 2));
    return c->nu;
}

double sph_config_support(const sph_config *c)
{
    const sph_kernel_spec *k = &c->kernel;
    if (sph_kernel_is_mps(k->type)) /* MPS weights: the larger of the two effective radii */
        return (c->mps.re > c->mps.re_grad ? c->mps.re : c->mps.re_grad) * c->dx;
    double q = 2.0;
    if (k->type == SPH_KERNEL_DOUBLE_COSINE)
        q = k->kappa;
    else if (k->type == SPH_KERNEL_GAUSSIAN)
        q = k->radius;
    return q * c->h_over_dx * c->dx;
}

double sph_config_cell_size(const sph_config *c)
{
    return sph_config_support(c) * (1.0 + c->neighbour_skin);
}

double sph_config_nlist_bytes(const sph_config *c)
{
    if (!(c->neighbour_skin > 0.0))
        return 0.0;
    const double r = sph_config_cell_size(c) / c->dx;
    const double ball = c->dim == 3 ? 4.0 / 3.0 * M_PI * r * r * r : M_PI * r * r;
    return (double)sizeof(long) + 2.0 * ceil(0.5 * ball) * (double)sizeof(int);
}

double sph_config_h(const sph_config *c)
{
    return sph_kernel_is_mps(c->kernel.type) ? 0.5 * sph_config_support(c) : c->h_over_dx * c->dx;
}

void sph_config_pressure_point(const sph_config *c, const sph_pressure_spec *q, double x[3])
{
    double n2 = 0.0;
    for (int d = 0; d < c->dim; d++)
        n2 += q->normal[d] * q->normal[d];
    const double f = n2 > 0.0 ? SPH_PROBE_OFFSET_H * sph_config_h(c) / sqrt(n2) : 0.0;
    for (int d = 0; d < 3; d++)
        x[d] = d < c->dim ? q->at[d] + f * q->normal[d] : 0.0;
}

int sph_config_by_scene(const sph_config *c)
{
    return c->ngeometry > 0 ||
           (c->dim == 3 && c->boundary != SPH_BOUNDARY_GHOST && c->method == SPH_METHOD_WCSPH);
}

void sph_config_steer(sph_config *c, const sph_config *from)
{
    c->alpha = from->alpha;
    c->nu = from->nu;
    c->delta_sph = from->delta_sph;
    c->cfl = from->cfl;
    c->t_end = from->t_end;
    c->diag_every = from->diag_every; /* (the caller's schedule; kept for a restore) */
    c->diag_interval = from->diag_interval;
    memcpy(c->gravity, from->gravity, sizeof c->gravity);
}
