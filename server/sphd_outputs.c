#include "sphd_outputs.h"

#include "sphd.h"
#include "sphd_h5.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The diagnostics series' columns, after "step" (PROTOCOL.md section 4); the energies are per
 * metre in 2D. */
static const sphd_diag_column diag_columns_2d[] = {{"t", "s", 0},
                                                   {"dt", "s", 0},
                                                   {"ekin", "J/m", 0},
                                                   {"epot", "J/m", 0},
                                                   {"vmax", "m/s", 0},
                                                   {"rho_min", "kg/m^3", 0},
                                                   {"rho_max", "kg/m^3", 0},
                                                   {"front_x", "m", 0},
                                                   {"height_left", "m", 0},
                                                   {"lost", "1", 1},
                                                   {"penetration", "m", 0},
                                                   {"runup", "m", 0}};
#define NDIAG ((int)(sizeof diag_columns_2d / sizeof diag_columns_2d[0]))

/* The pressure solve's series, after the fixed ones, for a method that solves one (MPS). */
static const sphd_diag_column solve_columns[] = {
    {"cg_iterations", "1", 1}, {"cg_residual", "1", 0}, {"free_surface", "1", 1}};
#define NSOLVECOL ((int)(sizeof solve_columns / sizeof solve_columns[0]))

/* Each rigid body's series, as "<name>.<member>" after the fixed ones, in the order of the
 * case's bodies (the members of sph_body_diag; 2D). */
static const sphd_diag_column body_columns_2d[] = {
    {"x", "m", 0},       {"y", "m", 0},          {"vx", "m/s", 0}, {"vy", "m/s", 0},
    {"angle", "rad", 0}, {"omega", "rad/s", 0},  {"fx", "N/m", 0}, {"fy", "N/m", 0},
    {"torque", "N", 0},  {"penetration", "m", 0}};
#define NBODYCOL ((int)(sizeof body_columns_2d / sizeof body_columns_2d[0]))
/* Then each height gauge's series, under the gauge's name, in the order of the case's gauges,
 * then each pressure probe's likewise. */
#define NCOLUMNS_MAX                                                                               \
    (NDIAG + NSOLVECOL + SPH_CONFIG_MAX_BODIES * NBODYCOL + 2 * SPH_CONFIG_MAX_GAUGES)

struct sphd_outputs {
    char dir[4096];
    char job[64];
    sph_output_config cfg;
    int dim;
    double dx;   /* [m] */
    double mass; /* particle mass [kg] (per metre in 2D) */
    char kernel[32];
    sphd_diagfile *diag;
    int ncolumns;  /* the diag series after "step" */
    int nsolve;    /* the pressure solve's series (NSOLVECOL or 0) */
    int nbodies;   /* bodies with series in diag.h5 */
    int ngauges;   /* height gauges with series in diag.h5 */
    int npressure; /* pressure probes with series in diag.h5 */
    char body_names[SPH_CONFIG_MAX_BODIES * NBODYCOL][SPH_BODY_NAME_MAX + 16];
    sphd_xdmf_entry *entries; /* snapshots written */
    int nentries, capentries;
    long skip; /* output times passed over: a run resumed past them (its output.every changed) */
};

sphd_outputs *sphd_outputs_open(const char *dir, const char *job, const sph_case *c,
                                const sph_sim *s, long resume_step, sph_error *err)
{
    sphd_outputs *o = calloc(1, sizeof *o);
    if (!o) {
        sph_error_set(err, SPH_ERR_NOMEM, "", "out of memory");
        return NULL;
    }
    snprintf(o->dir, sizeof o->dir, "%s", dir);
    snprintf(o->job, sizeof o->job, "%s", job);
    snprintf(o->kernel, sizeof o->kernel, "%s", sph_kernel_type_name(c->sim.kernel.type));
    o->cfg = c->output;
    o->dim = c->sim.dim;
    o->dx = c->sim.dx;
    o->mass = c->sim.rho0 * pow(c->sim.dx, c->sim.dim);
    sphd_remove_stale_temps(dir); /* left by a crashed run in this directory */
    char path[4200];
    snprintf(path, sizeof path, "%s/diag.h5", dir);
    sphd_diag_column cols[NCOLUMNS_MAX];
    memcpy(cols, diag_columns_2d, sizeof diag_columns_2d);
    if (c->sim.dim != 2) /* energies [J] in 3D */
        cols[2].units = cols[3].units = "J";
    o->nsolve = sph_sim_solves_pressure(s) ? NSOLVECOL : 0;
    memcpy(cols + NDIAG, solve_columns, (size_t)o->nsolve * sizeof solve_columns[0]);
    o->nbodies = c->sim.nbodies;
    o->ngauges = c->sim.ngauges;
    o->npressure = c->sim.npressure;
    o->ncolumns = NDIAG + o->nsolve + o->nbodies * NBODYCOL + o->ngauges + o->npressure;
    for (int b = 0; b < o->nbodies; b++)
        for (int m = 0; m < NBODYCOL; m++) {
            const int k = b * NBODYCOL + m;
            snprintf(o->body_names[k], sizeof o->body_names[k], "%s.%s", c->sim.bodies[b].name,
                     body_columns_2d[m].name);
            cols[NDIAG + o->nsolve + k] = body_columns_2d[m];
            cols[NDIAG + o->nsolve + k].name = o->body_names[k];
        }
    for (int k = 0; k < o->ngauges; k++) {
        sphd_diag_column *g = &cols[NDIAG + o->nsolve + o->nbodies * NBODYCOL + k];
        g->name = c->sim.gauges[k].name; /* read by the open only */
        g->units = "m";
        g->integer = 0;
    }
    for (int k = 0; k < o->npressure; k++) {
        sphd_diag_column *g = &cols[NDIAG + o->nsolve + o->nbodies * NBODYCOL + o->ngauges + k];
        g->name = c->sim.pressure[k].name;
        g->units = "Pa";
        g->integer = 0;
    }
    o->diag = sphd_diagfile_open(path, cols, o->ncolumns, resume_step, err);
    if (!o->diag) {
        free(o);
        return NULL;
    }
    return o;
}

int sphd_outputs_diag(sphd_outputs *o, const sph_diag *d, sph_error *err)
{
    double v[NCOLUMNS_MAX] = {d->t,           d->dt,           d->ekin,        d->epot,
                              d->vmax,        d->rho_min,      d->rho_max,     d->front_x,
                              d->height_left, (double)d->lost, d->penetration, d->runup};
    if (o->nsolve) {
        v[NDIAG] = (double)d->cg_iterations;
        v[NDIAG + 1] = d->cg_residual;
        v[NDIAG + 2] = (double)d->free_surface;
    }
    double *vb = v + NDIAG + o->nsolve;
    for (int k = 0; k < o->nbodies; k++) {
        const sph_body_diag *b = &d->body[k];
        const int have = k < d->nbodies;
        const double m[NBODYCOL] = {b->x[0],  b->x[1],     b->v[0],     b->v[1],   b->angle,
                                    b->omega, b->force[0], b->force[1], b->torque, b->penetration};
        for (int j = 0; j < NBODYCOL; j++)
            vb[k * NBODYCOL + j] = have ? m[j] : NAN;
    }
    double *vg = vb + o->nbodies * NBODYCOL;
    for (int k = 0; k < o->ngauges; k++)
        vg[k] = k < d->ngauges ? d->gauge[k] : NAN;
    for (int k = 0; k < o->npressure; k++)
        vg[o->ngauges + k] = k < d->npressure ? d->pressure[k] : NAN;
    return sphd_diagfile_append(o->diag, d->step, v, err);
}

double sphd_outputs_next_time(const sphd_outputs *o)
{
    if (!(o->cfg.every > 0.0))
        return INFINITY;
    return (double)(o->nentries + o->skip) * o->cfg.every;
}

/* Gathers src[where[k]] for k in creation order into dst (elements of size es). */
static void gather(void *dst, const void *src, const long *where, long n, size_t es)
{
    for (long k = 0; k < n; k++)
        memcpy((char *)dst + (size_t)k * es, (const char *)src + (size_t)where[k] * es, es);
}

/* A view's field (double d, or float f under mixed precision) gathered into doubles. */
static void gather_field(double *dst, const double *d, const float *f, const long *where, long n)
{
    if (d)
        gather(dst, d, where, n, sizeof(double));
    else
        for (long k = 0; k < n; k++)
            dst[k] = (double)f[where[k]];
}

/* The fluid's RPDF with the query's binning into *r (arrays of SPH_SIM_RPDF_BINS) for a sim of
 * nactive fluid particles (lost ones not counted). Returns 1 when there is one, 0 when there is
 * none to write (no fluid particle, or the sim has none to give: SPH_ERR_INVALID), or -1 with
 * err (out of memory). */
static int fluid_rpdf(const sph_sim *s, long nactive, sphd_h5_rpdf *r, double *q, double *count,
                      double *density, sph_error *err)
{
    if (nactive == 0)
        return 0;
    sph_error e;
    const int rc = sph_sim_rpdf(s, SPH_SIM_RPDF_QMAX, SPH_SIM_RPDF_BINS, q, count, density, &e);
    if (rc == SPH_ERR_INVALID)
        return 0;
    if (rc) {
        if (err)
            *err = e;
        return -1;
    }
    *r = (sphd_h5_rpdf){SPH_SIM_RPDF_BINS, SPH_SIM_RPDF_QMAX, q, count, density};
    return 1;
}

json_t *sphd_outputs_snapshot(sphd_outputs *o, const sph_sim *s, sph_error *err)
{
    sph_particle_view v;
    sph_sim_particles(s, &v);
    const sph_diag *d = sph_sim_diag(s);
    const long n = v.n;
    long nfluid = 0, nactive = 0, nboundary = 0, nbody = 0;
    for (long i = 0; i < n; i++) { /* SPH_PARTICLE_TYPES_DOC */
        nfluid += v.type[i] == 0 || v.type[i] == 2;
        nactive += v.type[i] == 0;
        nboundary += v.type[i] == 1;
        nbody += v.type[i] == 4;
    }
    /* before the snapshot's buffers: the RPDF's cell grid is freed by then */
    double rq[SPH_SIM_RPDF_BINS], rcount[SPH_SIM_RPDF_BINS], rdensity[SPH_SIM_RPDF_BINS];
    sphd_h5_rpdf rpdf = {0};
    const int has_rpdf = fluid_rpdf(s, nactive, &rpdf, rq, rcount, rdensity, err);
    if (has_rpdf < 0)
        return NULL;
    const size_t nn = (size_t)(n > 0 ? n : 1);
    long *where = malloc(nn * sizeof *where);
    double *buf = malloc(nn * sizeof(double) * 9);
    unsigned char *type = malloc(nn);
    int32_t *id = malloc(nn * sizeof *id);
    if (!where || !buf || !type || !id) {
        free(where), free(buf), free(type), free(id);
        sph_error_set(err, SPH_ERR_NOMEM, "", "out of memory for a snapshot of %ld particles", n);
        return NULL;
    }
    for (long i = 0; i < n; i++)
        where[v.id[i]] = i;
    double *col[9];
    for (int k = 0; k < 9; k++)
        col[k] = buf + (size_t)k * nn;
    sphd_h5_field f[8];
    int nf = 0;
    const unsigned want = o->cfg.fields;
    int c = 0;
    sphd_h5_field pos = {"pos", "m", SPHD_H5_F64, v.dim, {0}};
    for (int k = 0; k < v.dim; k++) {
        gather(col[c], v.pos[k], where, n, sizeof(double));
        pos.comp[k] = col[c++];
    }
    f[nf++] = pos;
    if (want & SPH_FIELD_VEL) {
        sphd_h5_field vel = {"vel", "m/s", SPHD_H5_F64, v.dim, {0}};
        for (int k = 0; k < v.dim; k++) {
            gather_field(col[c], v.vel[k], v.vel32[k], where, n);
            vel.comp[k] = col[c++];
        }
        f[nf++] = vel;
    }
    if (want & SPH_FIELD_RHO) {
        gather_field(col[c], v.rho, v.rho32, where, n);
        f[nf++] = (sphd_h5_field){"rho", "kg/m^3", SPHD_H5_F64, 1, {col[c++]}};
    }
    if (want & SPH_FIELD_P) {
        gather_field(col[c], v.p, v.p32, where, n);
        f[nf++] = (sphd_h5_field){"p", "Pa", SPHD_H5_F64, 1, {col[c++]}};
    }
    if (want & SPH_FIELD_MASS) {
        for (long k = 0; k < n; k++)
            col[c][k] = o->mass;
        f[nf++] = (sphd_h5_field){"mass", o->dim == 2 ? "kg/m" : "kg", SPHD_H5_F64, 1, {col[c++]}};
    }
    if (want & SPH_FIELD_TYPE) {
        gather(type, v.type, where, n, 1);
        f[nf++] = (sphd_h5_field){"type", SPH_PARTICLE_TYPES_DOC, SPHD_H5_I8, 1, {type}};
    }
    /* always: the XDMF's and VTKHDF's connectivity (ids are creation order = file order) */
    for (long k = 0; k < n; k++)
        id[k] = (int32_t)k;
    f[nf++] = (sphd_h5_field){"id", "1", SPHD_H5_I32, 1, {id}};

    if (o->nentries == o->capentries) {
        int cap = o->capentries ? 2 * o->capentries : 64;
        sphd_xdmf_entry *e = realloc(o->entries, (size_t)cap * sizeof *e);
        if (!e) {
            free(where), free(buf), free(type), free(id);
            sph_error_set(err, SPH_ERR_NOMEM, "", "out of memory");
            return NULL;
        }
        o->entries = e;
        o->capentries = cap;
    }
    sphd_xdmf_entry *e = &o->entries[o->nentries];
    snprintf(e->file, sizeof e->file, "snap_%06d.h5", o->nentries);
    e->t = d->t;
    e->step = d->step;
    e->n = n;
    sphd_h5_header h = {.t = d->t,
                        .step = d->step,
                        .dim = o->dim,
                        .dx = o->dx,
                        .kernel = o->kernel,
                        .job = o->job,
                        .n = n,
                        .n_fluid = nfluid,
                        .n_boundary = nboundary,
                        .n_body = nbody,
                        .mass = o->mass,
                        .h = sph_sim_h(s),
                        .rpdf = has_rpdf ? &rpdf : NULL};
    char path[4400], xmf[4200];
    snprintf(path, sizeof path, "%s/%s", o->dir, e->file);
    snprintf(xmf, sizeof xmf, "%s/particles.xmf", o->dir);
    int rc = sphd_h5_write_snapshot(path, &h, f, nf, o->cfg.compress, err);
    if (rc == 0)
        rc = sphd_xdmf_write(xmf, o->entries, o->nentries + 1, f, nf, err);
    free(where), free(buf), free(type), free(id);
    if (rc)
        return NULL;
    o->nentries++;
    return json_pack("{s:s, s:f, s:I}", "file", e->file, "t", e->t, "step", (json_int_t)e->step);
}

void sphd_outputs_set_every(sphd_outputs *o, double every, double t)
{
    o->cfg.every = every;
    if (every > 0.0) {
        const double k = floor(t / every + 1e-9) + 1.0; /* the first time after t */
        if (k < 1e15)
            o->skip = (long)k - o->nentries;
    }
}

json_t *sphd_outputs_snapshot_extra(sphd_outputs *o, const sph_sim *s, sph_error *err)
{
    json_t *ev = sphd_outputs_snapshot(o, s, err);
    if (ev)
        o->skip--; /* (nentries + skip) every: the next time is the one it was */
    return ev;
}

json_t *sphd_outputs_state(const sphd_outputs *o)
{
    json_t *list = json_array();
    for (int i = 0; i < o->nentries; i++)
        json_array_append_new(list,
                              json_pack("{s:s, s:f, s:I, s:I}", "file", o->entries[i].file, "t",
                                        o->entries[i].t, "step", (json_int_t)o->entries[i].step,
                                        "n", (json_int_t)o->entries[i].n));
    return json_pack("{s:o, s:I}", "snapshots", list, "skip", (json_int_t)o->skip);
}

int sphd_outputs_restore(sphd_outputs *o, const json_t *state, double t, sph_error *err)
{
    json_t *list = json_object_get(state, "snapshots");
    if (!json_is_array(list))
        return sph_error_set(err, SPH_ERR_IO, "", "checkpoint lacks the outputs' state");
    size_t n = json_array_size(list);
    sphd_xdmf_entry *e = calloc(n ? n : 1, sizeof *e);
    if (!e)
        return sph_error_set(err, SPH_ERR_NOMEM, "", "out of memory");
    for (size_t i = 0; i < n; i++) {
        json_t *it = json_array_get(list, i);
        const char *file = json_string_value(json_object_get(it, "file"));
        snprintf(e[i].file, sizeof e[i].file, "%s", file ? file : "");
        e[i].t = json_number_value(json_object_get(it, "t"));
        e[i].step = (long)json_integer_value(json_object_get(it, "step"));
        e[i].n = (long)json_integer_value(json_object_get(it, "n"));
    }
    free(o->entries);
    o->entries = e;
    o->nentries = o->capentries = (int)n;
    o->skip = (long)json_integer_value(json_object_get(state, "skip")); /* trigger snapshots */
    /* a schedule the state is already past (the case's output.every made shorter before the
     * resume): the next output is the first time due from t on, not a burst of late ones */
    if (o->cfg.every > 0.0 && (double)(o->nentries + o->skip) * o->cfg.every <= t) {
        const double k = floor(t / o->cfg.every + 1e-9) + 1.0; /* the first time after t */
        if (k < 1e15)
            o->skip = (long)k - o->nentries;
    }
    return 0;
}

void sphd_outputs_close(sphd_outputs *o)
{
    if (!o)
        return;
    sphd_diagfile_close(o->diag);
    free(o->entries);
    free(o);
}
