/*
 * sph_sim: the simulation handle (creation, stepping, observation). Method-agnostic: every
 * method-specific call goes through the method's row of the table (sph_method.h).
 */
#include "sph_geometry.h"
#include "sph_sim_impl.h"

#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
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
    return c;
}

/* The box the cell grid covers: the domain and the tank with its walls. */
static void grid_bounds(const sph_config *c, double lo[2], double hi[2])
{
    for (int d = 0; d < 2; d++) {
        lo[d] = c->domain.min[d];
        hi[d] = c->domain.max[d];
        if (c->has_tank && c->boundary == SPH_BOUNDARY_DYNAMIC) {
            const double w = (c->layers + 1) * c->dx;
            lo[d] = fmin(lo[d], c->tank.min[d] - w);
            hi[d] = fmax(hi[d], c->tank.max[d] + w);
        }
    }
}

static double support_of(const sph_config *c)
{
    const sph_kernel_spec *k = &c->kernel;
    double q = 2.0;
    if (k->type == SPH_KERNEL_DOUBLE_COSINE)
        q = k->kappa;
    else if (k->type == SPH_KERNEL_GAUSSIAN)
        q = k->radius;
    return q * c->h_over_dx * c->dx;
}

static long nbins_of(const sph_config *c)
{
    double lo[2], hi[2];
    grid_bounds(c, lo, hi);
    const double span = fmax(hi[0] - lo[0], hi[1] - lo[1]);
    return (long)ceil(span / c->dx) + 2;
}

double sph_sim_estimate_bytes(const sph_config *cfg, long *nfluid, long *nboundary)
{
    long nf = 0, nb = 0;
    if (cfg->dx > 0.0) {
        sph_geometry_count(cfg, &nf, &nb);
        nb += sph_body_count(cfg); /* the bodies' particles are boundary particles that move */
    }
    if (nfluid)
        *nfluid = nf;
    if (nboundary)
        *nboundary = nb;
    if (!(cfg->dx > 0.0))
        return 0.0;
    double lo[2], hi[2];
    grid_bounds(cfg, lo, hi);
    const double cells = sph_cells_count(lo, hi, support_of(cfg));
    const sph_method_ops *ops = sph_method_ops_of(cfg->method);
    const double per = ops ? (double)ops->bytes_per_particle(cfg) : 0.0;
    const double bins = (fmax(hi[0] - lo[0], hi[1] - lo[1]) / cfg->dx + 2.0) * 12.0;
    return (double)(nf + nb) * per + cells * sizeof(int) + bins + sizeof(sph_sim);
}

/* The checks of a configuration that the table of the case parser cannot make. */
int sph_sim_check(const sph_config *c, sph_error *err)
{
    const sph_method_ops *ops = sph_method_ops_of(c->method);
    if (!ops)
        return sph_error_set(err, SPH_ERR_INVALID, "/method",
                             "method %d is not a particle method of this build", (int)c->method);
    if (c->dim != 2)
        return sph_error_set(err, SPH_ERR_INVALID, "/dim", "only 2D simulations are available");
    if (!(c->dx > 0.0) || !isfinite(c->dx))
        return sph_error_set(err, SPH_ERR_INVALID, "/dx", "dx must be a positive number");
    if (!(c->h_over_dx > 0.0))
        return sph_error_set(err, SPH_ERR_INVALID, "/kernel/h_over_dx",
                             "h_over_dx must be positive");
    for (int d = 0; d < 2; d++)
        if (!(c->domain.max[d] > c->domain.min[d]))
            return sph_error_set(err, SPH_ERR_INVALID, "/domain/max",
                                 "the domain's max must exceed its min");
    if (!(c->rho0 > 0.0))
        return sph_error_set(err, SPH_ERR_INVALID, "/physics/rho0", "rho0 must be positive");
    if (!(c->t_end > 0.0))
        return sph_error_set(err, SPH_ERR_INVALID, "/time/end", "the end time must be positive");
    if (!(c->cfl > 0.0) && !(c->dt_fixed > 0.0))
        return sph_error_set(err, SPH_ERR_INVALID, "/time/cfl", "cfl must be positive");
    if (sph_body_check(c, err))
        return err ? err->code : SPH_ERR_INVALID;
    return ops->check(c, err);
}

sph_sim *sph_sim_create(const sph_config *cfg, sph_error *err)
{
    if (sph_sim_check(cfg, err))
        return NULL;
    long nf, nb;
    const double bytes = sph_sim_estimate_bytes(cfg, &nf, &nb);
    if (nf <= 0 && cfg->nbodies == 0) {
        sph_error_set(err, SPH_ERR_INVALID, "/fluid",
                      "the case has no fluid particles (every fluid box is thinner than dx)");
        return NULL;
    }
    if (bytes > cfg->max_bytes) {
        sph_error_set(err, SPH_ERR_NOMEM, "/dx",
                      "the case needs about %.0f MB (%ld fluid and %ld boundary particles at dx "
                      "= %g m), more than the %.0f MB allowed: use a larger dx",
                      bytes / 1e6, nf, nb, cfg->dx, cfg->max_bytes / 1e6);
        return NULL;
    }
    if (nf + nb > 2000000000L) {
        sph_error_set(err, SPH_ERR_NOMEM, "/dx", "more than 2e9 particles: use a larger dx");
        return NULL;
    }
    sph_sim *s = calloc(1, sizeof *s);
    if (!s) {
        sph_error_set(err, SPH_ERR_NOMEM, "", "out of memory");
        return NULL;
    }
    s->cfg = *cfg;
    s->ops = sph_method_ops_of(cfg->method);
    s->h = cfg->h_over_dx * cfg->dx;
    s->mass = cfg->rho0 * cfg->dx * cfg->dx;
    const long nbody = sph_body_count(cfg);
    s->nfluid = nf;
    s->nboundary = nb - nbody;
    s->max_lost = 10 + nf / 100;
    if (sph_kernel_init(&s->kernel, &cfg->kernel, 2, s->h, err)) {
        if (err) {
            char path[SPH_ERROR_PATH_MAX];
            memcpy(path, err->path, sizeof path);
            path[sizeof path - 8] = '\0';
            memcpy(err->path, "/kernel", 7);
            memcpy(err->path + 7, path, sizeof path - 7);
        }
        free(s);
        return NULL;
    }
    double lo[2], hi[2];
    grid_bounds(cfg, lo, hi);
    s->nbins = nbins_of(cfg);
    s->bin_count = calloc((size_t)s->nbins, sizeof *s->bin_count);
    s->bin_max = calloc((size_t)s->nbins, sizeof *s->bin_max);
    if (!s->bin_count || !s->bin_max ||
        sph_particles_alloc(&s->P, nf + nb, cfg->turb == SPH_TURB_SPS) ||
        sph_cells_alloc(&s->cells, lo, hi, s->kernel.support, nf + nb) ||
        sph_bodies_init(&s->bodies, cfg, nf + nb - nbody)) {
        sph_sim_destroy(s);
        sph_error_set(err, SPH_ERR_NOMEM, "", "out of memory for %ld particles", nf + nb);
        return NULL;
    }
    sph_geometry_fill(cfg, &s->P);
    sph_bodies_fill(&s->bodies, cfg, &s->P);
    s->vmax = sph_bodies_vmax(&s->bodies); /* the first step respects the bodies' speed */
    if (s->ops->init(s, err)) {
        sph_sim_destroy(s);
        return NULL;
    }
    sph_diag_compute(s);
    return s;
}

int sph_sim_advance(sph_sim *s, long max_steps, double t_until, sph_error *err)
{
    if (s->failed)
        return sph_error_set(err, SPH_ERR_UNSTABLE, "", "the simulation has failed");
    int rc = 0;
    for (long k = 0; k < max_steps && s->t < t_until; k++) {
        /* land on t_until: shorten the last step, and the one before if the last would be tiny */
        double cap = t_until - s->t;
        const double dt = s->ops->dt(s);
        if (cap > dt && cap < 1.5 * dt)
            cap = 0.5 * cap;
        if ((rc = s->ops->step(s, cap, err)) != 0) {
            s->failed = 1;
            break;
        }
        if (t_until - s->t < 1e-12 * (fabs(t_until) + 1.0))
            s->t = t_until;
    }
    const double t0 = omp_get_wtime();
    sph_diag_compute(s);
    s->timing.integration += omp_get_wtime() - t0;
    return rc;
}

int sph_sim_step(sph_sim *s, long nsteps, sph_error *err)
{
    return sph_sim_advance(s, nsteps, INFINITY, err);
}

const sph_diag *sph_sim_diag(const sph_sim *s)
{
    return &s->diag;
}
double sph_sim_time(const sph_sim *s)
{
    return s->t;
}
const sph_config *sph_sim_config(const sph_sim *s)
{
    return &s->cfg;
}
void sph_sim_timing(const sph_sim *s, sph_timing *timing)
{
    *timing = s->timing;
}

void sph_sim_particles(const sph_sim *s, sph_particle_view *v)
{
    s->ops->pressure(s); /* a derived field: brought up to date for the view */
    memset(v, 0, sizeof *v);
    v->n = s->P.n;
    v->dim = 2;
    v->pos[0] = s->P.x;
    v->pos[1] = s->P.y;
    v->vel[0] = s->P.vx;
    v->vel[1] = s->P.vy;
    v->rho = s->P.rho;
    v->p = s->P.p;
    v->type = s->P.type;
    v->id = s->P.id;
}

double sph_sim_bytes(const sph_sim *s)
{
    const double n = (double)s->P.n;
    return n * (double)s->ops->bytes_per_particle(&s->cfg) +
           (double)(s->cells.ncells + 4) * sizeof(int) + (double)s->nbins * 12.0 + sizeof *s;
}

void sph_sim_destroy(sph_sim *s)
{
    if (!s)
        return;
    if (s->ops && s->ops->destroy)
        s->ops->destroy(s);
    sph_particles_free(&s->P);
    sph_cells_free(&s->cells);
    sph_bodies_free(&s->bodies);
    free(s->bin_count);
    free(s->bin_max);
    free(s);
}
