/*
 * sph_sim: the simulation handle (creation, stepping, observation). Method-agnostic: every
 * method-specific call goes through the method's row of the table (sph_method.h).
 */
#include "sph_gpu.h"
#include "sph_fill.h"
#include "sph_initial.h"
#include "sph_rpdf.h"
#include "sph_sim_impl.h"

#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The box the cell grid covers: the domain and the tank with its walls (dynamic particles or
 * the band of ghosts, one support plus a spacing wide). */
static void grid_bounds(const sph_config *c, double lo[3], double hi[3])
{
    lo[2] = hi[2] = 0.0;
    for (int d = 0; d < c->dim; d++) {
        lo[d] = c->domain.min[d];
        hi[d] = c->domain.max[d];
        if (c->has_tank && c->boundary != SPH_BOUNDARY_NONE && !c->geometry_filled) {
            const double w = c->boundary == SPH_BOUNDARY_DYNAMIC ? (c->layers + 1) * c->dx
                                                                 : sph_config_support(c) + c->dx;
            lo[d] = fmin(lo[d], c->tank.min[d] - w);
            hi[d] = fmax(hi[d], c->tank.max[d] + w);
        }
        if (c->geometry_filled && c->geometry_lo[d] <= c->geometry_hi[d]) {
            lo[d] = fmin(lo[d], c->geometry_lo[d] - c->dx);
            hi[d] = fmax(hi[d], c->geometry_hi[d] + c->dx);
        }
    }
}

/* Ghosts the walls need for the initial lattice (a ghost-wall tank; 0 otherwise). */
static long ghosts_estimate(const sph_config *c)
{
    return sph_fill_ghosts_estimate(c, sph_config_support(c));
}

static long nbins_of(const sph_config *c)
{
    double lo[3], hi[3];
    grid_bounds(c, lo, hi);
    double span = fmax(hi[0] - lo[0], hi[1] - lo[1]);
    if (c->dim == 3)
        span = fmax(span, hi[2] - lo[2]);
    return (long)ceil(span / c->dx) + 2;
}

double sph_sim_estimate_bytes(const sph_config *cfg_in, long *nfluid, long *nboundary)
{
    sph_config prepared;
    const sph_config *cfg = cfg_in->dx > 0.0 ? sph_fill_prepared(cfg_in, &prepared, NULL) : NULL;
    if (!cfg)
        cfg = cfg_in;
    long nf = 0, nb = 0;
    if (cfg->dx > 0.0) {
        sph_fill_counts n;
        sph_fill_count(cfg, &n);
        nf = n.fluid;
        nb = n.wall + n.body; /* the bodies' particles are boundary particles that move */
    }
    if (nfluid)
        *nfluid = nf;
    if (nboundary)
        *nboundary = nb;
    if (!(cfg->dx > 0.0))
        return 0.0;
    double lo[3], hi[3];
    grid_bounds(cfg, lo, hi);
    const double cells = sph_cells_count(cfg->dim, lo, hi, sph_config_cell_size(cfg));
    const sph_method_ops *ops = sph_method_ops_for(cfg);
    const double per = ops ? (double)ops->bytes_per_particle(cfg) : 0.0;
    double span = fmax(hi[0] - lo[0], hi[1] - lo[1]);
    if (cfg->dim == 3)
        span = fmax(span, hi[2] - lo[2]);
    const double bins = (span / cfg->dx + 2.0) * 12.0;
    const double ghosts = 1.25 * (double)ghosts_estimate(cfg);
    /* the geometry walls' mirror points (mDBC) */
    const double mirrors =
        sph_fill_has_mirrors(cfg) ? (double)cfg->geometry_wall * cfg->dim * sizeof(double) : 0.0;
    /* per cell: its start, and with mDBC its wet flag */
    return (double)(nf + nb + ghosts) * per + cells * (sizeof(int) + 1) + bins + mirrors +
           sizeof(sph_sim);
}

/* The names that a gauge may not take: the diag series' own and diag.h5's tables (PROTOCOL.md
 * section 4), and the diag events' members. */
static const char *const reserved_names[] = {
    "step",         "t",           "dt",      "ekin",          "epot",
    "vmax",         "rho_min",     "rho_max", "front_x",       "height_left",
    "lost",         "penetration", "runup",   "cg_iterations", "cg_residual",
    "free_surface", "bodies",      "gauges",  "pressure",      "job",
    "seq",          "type",        "diag",    "rows",          NULL};

/* The height gauges: distinct names of letters, digits, '_' and '-' (they name diag.h5's
 * series) that are not the diag series' own, each line inside the tank (the domain without one). */
/* A probe's name at path (`kind`: "gauge" or "pressure probe"): 1 to 31 letters, digits, '_'
 * and '-' (it names the probe's series in diag.h5), not the diag series' own, and distinct from
 * the first ng gauges' and the first np pressure probes' (those checked before it). */
static int probe_name_check(const sph_config *c, const char *name, const char *kind, int ng, int np,
                            const char *path, sph_error *err)
{
    const size_t len = strnlen(name, SPH_GAUGE_NAME_MAX);
    if (len == 0 || len >= SPH_GAUGE_NAME_MAX)
        return sph_error_set(err, SPH_ERR_INVALID, path, "a %s needs a name of 1 to %d characters",
                             kind, SPH_GAUGE_NAME_MAX - 1);
    if (name[strspn(name, "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789_-")])
        return sph_error_set(err, SPH_ERR_INVALID, path,
                             "the %s name '%s' may hold only letters, digits, '_' and '-' (it "
                             "names the %s's series in diag.h5)",
                             kind, name, kind);
    for (int r = 0; reserved_names[r]; r++)
        if (strcmp(name, reserved_names[r]) == 0)
            return sph_error_set(err, SPH_ERR_INVALID, path,
                                 "the %s name '%s' is taken by the diagnostics' own series: "
                                 "choose another",
                                 kind, name);
    for (int j = 0; j < ng + np; j++)
        if (strcmp(j < ng ? c->gauges[j].name : c->pressure[j - ng].name, name) == 0)
            return sph_error_set(err, SPH_ERR_INVALID, path, "two %s are named '%s'",
                                 strcmp(kind, "gauge") == 0 ? "gauges"
                                 : j < ng                   ? "probes"
                                                            : "pressure probes",
                                 name);
    return 0;
}

/* The height gauges and the pressure probes: their names (probe_name_check), each gauge's line
 * inside the tank (the domain without one), each pressure probe's point inside the domain. */
static int gauge_check(const sph_config *c, sph_error *err)
{
    if (c->ngauges < 0 || c->ngauges > SPH_CONFIG_MAX_GAUGES)
        return sph_error_set(err, SPH_ERR_INVALID, "/diagnostics/gauges", "at most %d gauges",
                             SPH_CONFIG_MAX_GAUGES);
    if (c->npressure < 0 || c->npressure > SPH_CONFIG_MAX_GAUGES)
        return sph_error_set(err, SPH_ERR_INVALID, "/diagnostics/pressure",
                             "at most %d pressure probes", SPH_CONFIG_MAX_GAUGES);
    char path[64];
    for (int k = 0; k < c->ngauges; k++) {
        const sph_gauge_spec *g = &c->gauges[k];
        snprintf(path, sizeof path, "/diagnostics/gauges/%d/name", k);
        if (probe_name_check(c, g->name, "gauge", k, 0, path, err))
            return SPH_ERR_INVALID;
        /* the line's horizontal coordinates: x, and y in 3D */
        for (int d = 0; d < c->dim - 1; d++) {
            const double lo = c->has_tank ? c->tank.min[d] : c->domain.min[d];
            const double hi = c->has_tank ? c->tank.max[d] : c->domain.max[d];
            const double v = d == 0 ? g->x : g->y;
            const char *ax = d == 0 ? "x" : "y";
            snprintf(path, sizeof path, "/diagnostics/gauges/%d/%s", k, ax);
            if (!(v > lo && v < hi))
                return sph_error_set(err, SPH_ERR_INVALID, path,
                                     "the gauge '%s' at %s = %g m must lie inside the %s (%s in "
                                     "(%g, %g) m)",
                                     g->name, ax, v, c->has_tank ? "tank" : "domain", ax, lo, hi);
        }
        if (!isnan(g->to)) { /* a run-up gauge: [x, to] inside the tank */
            const double hi = c->has_tank ? c->tank.max[0] : c->domain.max[0];
            snprintf(path, sizeof path, "/diagnostics/gauges/%d/to", k);
            if (!(g->to > g->x && g->to <= hi))
                return sph_error_set(err, SPH_ERR_INVALID, path,
                                     "the run-up gauge '%s' reads x in [x, to]: 'to' (%g m) must "
                                     "lie past x (%g m) and inside the %s (up to %g m)",
                                     g->name, g->to, g->x, c->has_tank ? "tank" : "domain", hi);
        }
    }
    for (int k = 0; k < c->npressure; k++) {
        const sph_pressure_spec *q = &c->pressure[k];
        snprintf(path, sizeof path, "/diagnostics/pressure/%d/name", k);
        if (probe_name_check(c, q->name, "pressure probe", c->ngauges, k, path, err))
            return SPH_ERR_INVALID;
        for (int d = 0; d < c->dim; d++)
            if (!(q->at[d] >= c->domain.min[d] && q->at[d] <= c->domain.max[d])) {
                snprintf(path, sizeof path, "/diagnostics/pressure/%d/at/%d", k, d);
                return sph_error_set(err, SPH_ERR_INVALID, path,
                                     "the pressure probe '%s' must lie inside the domain "
                                     "([%g, %g] m on this axis)",
                                     q->name, c->domain.min[d], c->domain.max[d]);
            }
        static const char axis[] = "xyz";
        double x[3];
        sph_config_pressure_point(c, q, x);
        for (int d = 0; d < c->dim; d++)
            if (!(x[d] >= c->domain.min[d] && x[d] <= c->domain.max[d])) {
                snprintf(path, sizeof path, "/diagnostics/pressure/%d/normal", k);
                return sph_error_set(err, SPH_ERR_INVALID, path,
                                     "the pressure probe '%s' reads %g smoothing lengths along "
                                     "its normal, at %c = %g m, outside the domain ([%g, %g] "
                                     "m): the normal must point into the fluid",
                                     q->name, SPH_PROBE_OFFSET_H, axis[d], x[d], c->domain.min[d],
                                     c->domain.max[d]);
            }
    }
    return 0;
}

/* The checks of a configuration that the table of the case parser cannot make, and the ones it
 * makes repeated for direct API users and for a configuration read back from a saved state
 * (sph_checkpoint.c), which no parser has seen. */
/* The geometry list's rules that need no surface (the scene checks the rest when it is built). */
static int geometry_check(const sph_config *c, sph_error *err)
{
    if (c->ngeometry < 0 || c->ngeometry > SPH_CONFIG_MAX_GEOMETRY)
        return sph_error_set(err, SPH_ERR_INVALID, "/geometry", "at most %d geometry items",
                             SPH_CONFIG_MAX_GEOMETRY);
    if (c->ngeometry == 0)
        return 0;
    if (c->method != SPH_METHOD_WCSPH)
        return sph_error_set(err, SPH_ERR_INVALID, "/geometry",
                             "a geometry list needs the wcsph method in this version");
    if (c->boundary == SPH_BOUNDARY_GHOST)
        return sph_error_set(err, SPH_ERR_INVALID, "/geometry",
                             "a geometry list needs \"dynamic\" walls (or none): ghost walls "
                             "mirror a tank's box only");
    if (c->initial.type != SPH_INITIAL_REST && sph_initial_elevation_max(c) > 0.0)
        return sph_error_set(err, SPH_ERR_INVALID, "/geometry",
                             "an initial field that raises the surface (the solitary wave) is "
                             "not filled through a geometry list in this version");
    for (int k = 0; k < c->ngeometry; k++) {
        const sph_geometry_spec *g = &c->geometry[k];
        char path[64];
        snprintf(path, sizeof path, "/geometry/%d", k);
        if ((unsigned)g->kind >= SPH_GEOM_KIND_COUNT || (unsigned)g->role >= SPH_ROLE_COUNT)
            return sph_error_set(err, SPH_ERR_INVALID, path, "unknown kind or role");
        const int walls = g->role == SPH_ROLE_WALL || g->role == SPH_ROLE_OBSTACLE;
        if (walls && c->boundary != SPH_BOUNDARY_DYNAMIC)
            return sph_error_set(err, SPH_ERR_INVALID, path,
                                 "a wall or obstacle is made of dynamic wall particles: it needs "
                                 "boundary.type \"dynamic\"");
        if (walls && !(g->layers >= 1))
            return sph_error_set(err, SPH_ERR_INVALID, path, "a wall needs at least one layer");
        if (!(g->transform.scale > 0.0) || !isfinite(g->transform.scale)) {
            snprintf(path, sizeof path, "/geometry/%d/transform/scale", k);
            return sph_error_set(err, SPH_ERR_INVALID, path, "the scale must be positive");
        }
    }
    return 0;
}

int sph_sim_check(const sph_config *c, sph_error *err)
{
    const sph_method_ops *ops = sph_method_ops_for(c);
    if (!ops && c->device == SPH_DEVICE_GPU && sph_method_ops_of(c->method))
        return sph_error_set(err, SPH_ERR_INVALID, "/device",
                             "\"gpu\": the GPU runs WCSPH only; use \"device\": \"cpu\"");
    if (!ops)
        return sph_error_set(err, SPH_ERR_INVALID, "/method",
                             "method %d is not a particle method of this build", (int)c->method);
    if (c->dim != 2 && c->dim != 3)
        return sph_error_set(err, SPH_ERR_INVALID, "/dim", "dim must be 2 or 3");
    if ((unsigned)c->precision >= SPH_PRECISION_COUNT)
        return sph_error_set(err, SPH_ERR_INVALID, "/precision",
                             "unknown precision: \"double\" or \"mixed\"");
    if (c->precision == SPH_PRECISION_MIXED) {
        const char *why = c->method != SPH_METHOD_WCSPH ? "the MPS method"
                          : c->device != SPH_DEVICE_CPU ? "the GPU"
                          : c->turb == SPH_TURB_SPS     ? "the SPS turbulence model"
                          : c->nbodies > 0              ? "rigid bodies"
                                                        : NULL;
        if (why)
            return sph_error_set(err, SPH_ERR_INVALID, "/precision",
                                 "\"mixed\" is for WCSPH on the CPU without SPS or rigid bodies; "
                                 "%s stores in double only: remove \"precision\" or set it to "
                                 "\"double\"",
                                 why);
    }
    if (c->neighbour_skin != 0.0) {
        if (!(c->neighbour_skin > 0.0 && c->neighbour_skin <= SPH_NEIGHBOUR_SKIN_MAX))
            return sph_error_set(err, SPH_ERR_INVALID, "/neighbours/skin",
                                 "the skin must be in [0, %g] (a fraction of the support)",
                                 SPH_NEIGHBOUR_SKIN_MAX);
        /* what a list reused over steps cannot follow: particles added every step (ghosts),
         * walls that move (bodies, a paddle), passes that search the cells in their current
         * order (mDBC, shifting), another device or method */
        const char *why = c->method != SPH_METHOD_WCSPH             ? "the MPS method"
                          : c->device != SPH_DEVICE_CPU             ? "the GPU"
                          : c->boundary == SPH_BOUNDARY_GHOST       ? "ghost walls"
                          : c->wall_density == SPH_WALL_MDBC        ? "mDBC walls"
                          : c->nbodies > 0                          ? "rigid bodies"
                          : c->wavemaker.type != SPH_WAVEMAKER_NONE ? "a wavemaker"
                          : c->shifting.type != SPH_SHIFT_NONE      ? "particle shifting"
                                                                    : NULL;
        if (why)
            return sph_error_set(err, SPH_ERR_INVALID, "/neighbours/skin",
                                 "a reused neighbour list is for WCSPH on the CPU with dynamic "
                                 "walls of continuity density, without bodies, a wavemaker or "
                                 "shifting; with %s the cells are searched every step: remove "
                                 "\"neighbours\" or set its skin to 0",
                                 why);
    }
    if (c->dim == 3 && c->method != SPH_METHOD_WCSPH)
        return sph_error_set(err, SPH_ERR_INVALID, "/dim",
                             "the %s method runs in 2D only: 3D cases take \"method\": \"wcsph\"",
                             c->method == SPH_METHOD_MPS ? "MPS" : "chosen");
    if (!(c->dx > 0.0) || !isfinite(c->dx))
        return sph_error_set(err, SPH_ERR_INVALID, "/dx", "dx must be a positive number");
    if (!(c->h_over_dx >= SPH_H_OVER_DX_MIN && c->h_over_dx <= SPH_H_OVER_DX_MAX))
        return sph_error_set(err, SPH_ERR_INVALID, "/kernel/h_over_dx",
                             "h_over_dx must be in [%g, %g]", SPH_H_OVER_DX_MIN, SPH_H_OVER_DX_MAX);
    if ((unsigned)c->kernel.type >= SPH_KERNEL_COUNT)
        return sph_error_set(err, SPH_ERR_INVALID, "/kernel/type", "unknown kernel");
    if (c->nfluid < 0 || c->nfluid > SPH_CONFIG_MAX_BOXES)
        return sph_error_set(err, SPH_ERR_INVALID, "/fluid", "at most %d fluid boxes",
                             SPH_CONFIG_MAX_BOXES);
    if ((unsigned)c->boundary >= SPH_BOUNDARY_COUNT || (unsigned)c->eos >= SPH_EOS_COUNT ||
        (unsigned)c->visc >= SPH_VISC_COUNT || (unsigned)c->turb >= SPH_TURB_COUNT)
        return sph_error_set(err, SPH_ERR_INVALID, "", "unknown boundary, EOS or viscosity type");
    if (!(c->wall_viscosity >= 0.0 && c->wall_viscosity <= 1.0))
        return sph_error_set(err, SPH_ERR_INVALID, "/boundary/viscosity_factor",
                             "viscosity_factor must be in [0, 1]");
    if ((unsigned)c->wall_density >= SPH_WALL_COUNT)
        return sph_error_set(err, SPH_ERR_INVALID, "/boundary/density",
                             "unknown wall density: continuity or mdbc");
    if (c->wall_density == SPH_WALL_MDBC &&
        (c->boundary != SPH_BOUNDARY_DYNAMIC || c->method != SPH_METHOD_WCSPH))
        return sph_error_set(err, SPH_ERR_INVALID, "/boundary/density",
                             "mdbc is for the dynamic walls of wcsph: remove boundary.density");
    if (c->boundary == SPH_BOUNDARY_DYNAMIC && (c->layers < 1 || c->layers > 8))
        return sph_error_set(err, SPH_ERR_INVALID, "/boundary/layers",
                             "layers must be from 1 to 8");
    for (int d = 0; d < c->dim; d++)
        if (!(c->domain.max[d] > c->domain.min[d]))
            return sph_error_set(err, SPH_ERR_INVALID, "/domain/max",
                                 "the domain's max must exceed its min");
    if (!(c->rho0 > 0.0))
        return sph_error_set(err, SPH_ERR_INVALID, "/physics/rho0", "rho0 must be positive");
    if (c->boundary == SPH_BOUNDARY_GHOST) {
        sph_wall_ghost w;
        if (sph_wall_ghost_init(&w, c, sph_config_support(c), err))
            return err ? err->code : SPH_ERR_INVALID;
    }
    if (c->visc == SPH_VISC_MONAGHAN && c->method != SPH_METHOD_WCSPH)
        return sph_error_set(err, SPH_ERR_INVALID, "/physics/viscosity/type",
                             "Monaghan's viscous term is a WCSPH term (method wcsph)");
    if (sph_initial_check(c, err))
        return err ? err->code : SPH_ERR_INVALID;
    if (!(c->t_end > 0.0))
        return sph_error_set(err, SPH_ERR_INVALID, "/time/end", "the end time must be positive");
    if (!(c->cfl > 0.0) && !(c->dt_fixed > 0.0))
        return sph_error_set(err, SPH_ERR_INVALID, "/time/cfl", "cfl must be positive");
    if (c->nobstacles < 0 || c->nobstacles > SPH_CONFIG_MAX_BOXES)
        return sph_error_set(err, SPH_ERR_INVALID, "/boundary/obstacles", "at most %d obstacles",
                             SPH_CONFIG_MAX_BOXES);
    if (c->nobstacles > 0 && (c->boundary != SPH_BOUNDARY_DYNAMIC || c->method != SPH_METHOD_WCSPH))
        return sph_error_set(err, SPH_ERR_INVALID, "/boundary/obstacles",
                             "obstacles are boxes of dynamic wall particles: they need "
                             "\"type\": \"dynamic\" walls and the wcsph method");
    for (int k = 0; k < c->nobstacles; k++)
        for (int d = 0; d < c->dim; d++)
            if (!(c->obstacles[k].max[d] > c->obstacles[k].min[d])) {
                char path[64];
                snprintf(path, sizeof path, "/boundary/obstacles/%d/box/max", k);
                return sph_error_set(err, SPH_ERR_INVALID, path,
                                     "an obstacle's max must exceed its min");
            }
    if (geometry_check(c, err))
        return SPH_ERR_INVALID;
    if (c->dim == 3 && c->nbodies > 0)
        return sph_error_set(err, SPH_ERR_INVALID, "/bodies",
                             "rigid bodies are available in 2D only in this version (dim = 2)");
    if (sph_body_check(c, err))
        return err ? err->code : SPH_ERR_INVALID;
    if (gauge_check(c, err))
        return SPH_ERR_INVALID;
    if (sph_wavemaker_check(c, err))
        return err ? err->code : SPH_ERR_INVALID;
    return ops->check(c, err);
}

sph_sim *sph_sim_create(const sph_config *cfg_in, sph_error *err)
{
    if (sph_sim_check(cfg_in, err))
        return NULL;
    sph_config prepared; /* the scene's counts and reach, in the sim's copy of the config */
    const sph_config *cfg = sph_fill_prepared(cfg_in, &prepared, err);
    if (!cfg)
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
    s->ops = sph_method_ops_for(cfg);
    s->h = sph_config_h(cfg);
    s->mass = cfg->rho0 * cfg->dx * cfg->dx;
    if (cfg->dim == 3)
        s->mass *= cfg->dx;
    const long nbody = sph_body_count(cfg);
    s->nfluid = nf;
    s->nboundary = nb - nbody;
    s->max_lost = 10 + nf / 100;
    if (sph_kernel_init(&s->kernel, &cfg->kernel, cfg->dim, s->h, err)) {
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
    if (cfg->boundary == SPH_BOUNDARY_GHOST)
        sph_wall_ghost_init(&s->ghost, cfg, s->kernel.support, NULL); /* checked above */
    const long cap = nf + nb + (long)(1.25 * (double)ghosts_estimate(cfg));
    double lo[3], hi[3];
    grid_bounds(cfg, lo, hi);
    s->nbins = nbins_of(cfg);
    s->bin_count = calloc((size_t)s->nbins, sizeof *s->bin_count);
    s->bin_max = calloc((size_t)s->nbins, sizeof *s->bin_max);
    if (sph_fill_has_mirrors(cfg)) { /* the geometry walls' mirror points, by id (mDBC) */
        s->mirror_first = nf;
        s->nmirror = cfg->geometry_wall;
        s->mirror =
            calloc((size_t)(s->nmirror > 0 ? s->nmirror : 1) * (size_t)cfg->dim, sizeof *s->mirror);
    }
    if (!s->bin_count || !s->bin_max || (sph_fill_has_mirrors(cfg) && !s->mirror) ||
        sph_particles_alloc(&s->P, nf + nb, cfg->dim, sph_sim_particle_opts(cfg)) ||
        sph_particles_reserve(&s->P, cap) ||
        sph_cells_alloc(&s->cells, cfg->dim, lo, hi,
                        s->kernel.support * (1.0 + cfg->neighbour_skin), cap) ||
        sph_bodies_init(&s->bodies, cfg, nf + nb - nbody)) {
        sph_sim_destroy(s);
        sph_error_set(err, SPH_ERR_NOMEM, "", "out of memory for %ld particles", nf + nb);
        return NULL;
    }
    /* fluid and walls (a restored state's come from it: -1 here), then the bodies' particles from
     * their state */
    if (sph_fill(cfg, &s->P, s->mirror, err) > 0) {
        sph_sim_destroy(s);
        return NULL;
    }
    for (int k = 0; k < SPH_CONFIG_MAX_GEOMETRY; k++) /* the case's surfaces, not the sim's */
        s->cfg.geometry[k].mesh = NULL;
    /* a wavemaker's paddle: the last wall particles, before the bodies' (a restored state's
     * particles overwrite these, its paddle where the state left it) */
    const int prc =
        sph_paddle_init(&s->paddle, cfg, &s->P, nf + nb - nbody - sph_wavemaker_points(cfg, NULL));
    s->cfg.wavemaker.series = s->paddle.rows.n > 0 ? &s->paddle.rows : NULL; /* the sim's copy */
    if (prc) {
        sph_sim_destroy(s);
        if (prc == -2)
            sph_error_set(err, SPH_ERR_INVALID, "/wavemaker/waves/file",
                          "the wavemaker's series was not read (sph_case_load_files)");
        else
            sph_error_set(err, SPH_ERR_NOMEM, "", "out of memory for the paddle");
        return NULL;
    }
    sph_paddle_move(&s->paddle, &s->P, nf + nb, 0.0);
    sph_bodies_fill(&s->bodies, cfg, &s->P);
    s->vmax = sph_bodies_vmax(&s->bodies); /* the first step respects the bodies' speed */
    if (s->ops->init(s, err)) {
        sph_sim_destroy(s);
        return NULL;
    }
    sph_diag_compute(s);
    s->has_theory = sph_initial_theory_of(cfg, &s->theory) == 0;
    if (s->has_theory) {
        sph_envelope_init(&s->wave, s->theory.period);
        sph_envelope_add(&s->wave, s->t, s->diag.ekin);
    }
    return s;
}

int sph_sim_rpdf(const sph_sim *s, double qmax, int nbins, double *q, double *count,
                 double *density, sph_error *err)
{
    const sph_rpdf_input in = {.dim = s->cfg.dim,
                               .n = s->nactive,
                               .pos = {s->P.x, s->P.y, s->P.z},
                               .type = s->P.type,
                               .h = s->h,
                               .dx = s->cfg.dx};
    return sph_rpdf_compute(&in, qmax, nbins, q, count, density, err);
}

/* Kinetic energy of the fluid [J], a serial sum in the particles' order (0.5 m sum v^2: the
 * same value as sph_diag's ekin up to rounding). */
static double fluid_ekin(const sph_sim *s)
{
    const sph_particles *P = &s->P;
    double e = 0.0;
    const int M = P->mixed;
    for (long i = 0; i < s->nactive; i++)
        if (P->type[i] == SPH_FLUID) {
            const double vx = SPH_GET(M, P, vx, i), vy = SPH_GET(M, P, vy, i);
            double v2 = vx * vx + vy * vy;
            if (P->dim == 3) {
                const double vz = SPH_GET(M, P, vz, i);
                v2 += vz * vz;
            }
            e += v2;
        }
    return 0.5 * s->mass * e;
}

int sph_sim_wave_fit(const sph_sim *s, double t_fit, sph_sim_wave *w)
{
    memset(w, 0, sizeof *w);
    if (!s->has_theory)
        return -1;
    const sph_config *c = &s->cfg;
    w->t_fit = fmin(t_fit, s->t);
    w->decay_rate_theory = s->theory.decay_rate;
    w->period_theory = s->theory.period;
    w->ekin0_theory = s->theory.ekin0;
    w->nu = sph_config_viscosity_nu(c);
    w->alpha = c->visc == SPH_VISC_MONAGHAN  ? sph_config_monaghan_alpha(c)
               : c->visc == SPH_VISC_LAMINAR ? 0.0
                                             : c->alpha;
    sph_envelope_fit f;
    if (sph_envelope_fit_peaks(&s->wave, w->t_fit, &f))
        return -1;
    w->peaks = f.npeaks;
    w->decay_rate = f.decay_rate;
    w->period = f.period;
    return 0;
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
        if (s->has_theory) { /* (a device backend's particles come back every step then) */
            if (s->ops->sync && (rc = s->ops->sync(s, err)) != 0) {
                s->failed = 1;
                break;
            }
            sph_envelope_add(&s->wave, s->t, fluid_ekin(s));
        }
        if (t_until - s->t < 1e-12 * (fabs(t_until) + 1.0))
            s->t = t_until;
    }
    const double t0 = omp_get_wtime();
    if (s->ops->sync) { /* after a failure too: the diagnostics show the state it failed in */
        sph_error late;
        const int src = s->ops->sync(s, rc ? &late : err);
        if (src && !rc) {
            rc = src;
            s->failed = 1;
        }
    }
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
int sph_sim_wave_design(const sph_config *c, sph_wave_design *w)
{
    if (c->wavemaker.type == SPH_WAVEMAKER_NONE)
        return -1;
    return sph_wave_design_of(c, w);
}

double sph_sim_time(const sph_sim *s)
{
    return s->t;
}
int sph_sim_solves_pressure(const sph_sim *s)
{
    return s->ops->solves_pressure;
}
double sph_sim_h(const sph_sim *s)
{
    return s->h;
}
const sph_config *sph_sim_config(const sph_sim *s)
{
    return &s->cfg;
}

int sph_sim_steer(sph_sim *s, const sph_config *next, sph_error *err)
{
    sph_config *c = &s->cfg;
    if (c->device != SPH_DEVICE_CPU)
        return sph_error_set(err, SPH_ERR_INVALID, "/device",
                             "a job on the GPU is not steered in this version (the device's copy "
                             "of the parameters is made once): run it on the CPU");
    const int new_gravity = memcmp(c->gravity, next->gravity, sizeof c->gravity) != 0;
    if (new_gravity && c->boundary == SPH_BOUNDARY_GHOST)
        return sph_error_set(err, SPH_ERR_INVALID, "/physics/gravity",
                             "ghost walls keep the gravity they were made with (their pressure's "
                             "hydrostatic part): not steered");
    sph_config_steer(c, next);
    for (int d = 0; d < 3; d++)
        s->bodies.gravity[d] = next->gravity[d];
    return 0;
}
void sph_sim_timing(const sph_sim *s, sph_timing *timing)
{
    *timing = s->timing;
}

void sph_sim_particles(const sph_sim *s, sph_particle_view *v)
{
    memset(v, 0, sizeof *v);
    v->n = s->P.n;
    v->dim = s->cfg.dim;
    v->pos[0] = s->P.x;
    v->pos[1] = s->P.y;
    v->pos[2] = s->P.z;
    v->vel[0] = s->P.vx;
    v->vel[1] = s->P.vy;
    v->vel[2] = s->P.vz;
    v->rho = s->P.rho;
    v->vel32[0] = s->P.f32.vx;
    v->vel32[1] = s->P.f32.vy;
    v->vel32[2] = s->P.f32.vz;
    v->rho32 = s->P.f32.rho;
    s->ops->pressure(s, &v->p, &v->p32); /* stored, or derived for the view */
    v->type = s->P.type;
    v->id = s->P.id;
}

double sph_sim_bytes(const sph_sim *s)
{
    const double n = (double)s->P.n;
    /* a reused neighbour list: what it holds, not the estimate's share */
    double list = (double)s->nlist.off_cap * sizeof(long) +
                  (double)s->nlist.ncol * (sizeof(long) + sizeof(int *)) -
                  n * ceil(sph_config_nlist_bytes(&s->cfg));
    for (int t = 0; t < s->nlist.ntb; t++) /* the threads' lists, kept between builds */
        list += (double)s->nlist.tb[t].cap * sizeof(int);
    return n * (double)s->ops->bytes_per_particle(&s->cfg) + list +
           (double)(s->cells.ncells + 4) * sizeof(int) + (double)s->nbins * 12.0 +
           (double)s->nmirror * s->cfg.dim * sizeof(double) + sizeof *s;
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
    sph_paddle_free(&s->paddle);
    free(s->bin_count);
    free(s->bin_max);
    free(s->mirror);
    free(s->shift);
    free(s->nlist.off);
    free(s->nlist.cb);
    free(s->nlist.ca);
    for (int t = 0; t < s->nlist.ntb; t++)
        free(s->nlist.tb[t].b);
    free(s->nlist.tb);
    free(s);
}

const char *sph_particle_type_name(int type)
{
    switch (type) {
    case SPH_FLUID:
        return "fluid";
    case SPH_BOUNDARY:
        return "boundary";
    case SPH_LOST:
        return "lost";
    case SPH_BODY:
        return "body";
    default:
        return NULL;
    }
}

double sph_sim_device_bytes(const sph_sim *s)
{
    return s->ops->device_bytes ? s->ops->device_bytes(s) : 0.0;
}

int sph_sim_gpu_count(void)
{
    return sph_gpu_count();
}

int sph_sim_gpu_describe(int k, char *name, size_t len, double *bytes)
{
    return sph_gpu_describe(k, name, len, bytes);
}
