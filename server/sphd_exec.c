#include "sphd_exec.h"

#include "sph_events.h"
#include "sph_sim.h"
#include "sph_study.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

struct sphd_exec {
    sph_case c;
    char *outdir;
    int finished;
    sph_sim *sim;   /* SPH_METHOD_WCSPH */
    double wall;    /* wall-clock seconds spent advancing [s] */
    long last_diag; /* step of the latest diag event, -1 before the first */
    json_t *diag;   /* latest diag body (owned) */
};

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

sphd_exec *sphd_exec_new(const sph_case *c, const char *outdir, sph_error *err)
{
    sphd_exec *x = calloc(1, sizeof *x);
    if (!x) {
        sph_error_set(err, SPH_ERR_NOMEM, "", "out of memory");
        return NULL;
    }
    x->c = *c;
    x->last_diag = -1;
    if (outdir && !(x->outdir = strdup(outdir))) {
        free(x);
        sph_error_set(err, SPH_ERR_NOMEM, "", "out of memory");
        return NULL;
    }
    switch (c->method) {
    case SPH_METHOD_KERNEL_STUDY:
        if (sph_study_validate(&c->study, err)) {
            sphd_exec_free(x);
            return NULL;
        }
        break;
    case SPH_METHOD_WCSPH:
        if (!(x->sim = sph_sim_create(&c->sim, err))) {
            sphd_exec_free(x);
            return NULL;
        }
        break;
    default:
        sph_error_set(err, SPH_ERR_INVALID, "/method", "method '%s' is not available",
                      sph_method_name(c->method));
        sphd_exec_free(x);
        return NULL;
    }
    return x;
}

static sphd_exec_status advance_study(sphd_exec *x, sphd_emit_fn emit, void *ud, sph_error *err)
{
    sph_study_result *res = calloc(1, sizeof *res);
    if (!res) {
        sph_error_set(err, SPH_ERR_NOMEM, "", "out of memory for the study's results");
        return SPHD_EXEC_FAILED;
    }
    if (sph_study_run(&x->c.study, res, err)) {
        free(res);
        return SPHD_EXEC_FAILED;
    }
    emit(ud, "result", sph_study_result_json(&x->c.study, res));
    free(res);
    x->finished = 1;
    return SPHD_EXEC_DONE;
}

/* A number, or null when it is not finite (no fluid left for a probe, a blow-up). */
static json_t *num(double v)
{
    return isfinite(v) ? json_real(v) : json_null();
}

/* The body of a diag event (new reference). */
static json_t *diag_json(const sph_diag *d, unsigned probes)
{
    json_t *b = json_object();
    json_object_set_new(b, "step", json_integer(d->step));
    json_object_set_new(b, "t", num(d->t));
    json_object_set_new(b, "dt", num(d->dt));
    json_object_set_new(b, "ekin", num(d->ekin));
    json_object_set_new(b, "epot", num(d->epot));
    json_object_set_new(b, "vmax", num(d->vmax));
    json_object_set_new(b, "rho_min", num(d->rho_min));
    json_object_set_new(b, "rho_max", num(d->rho_max));
    json_object_set_new(b, "lost", json_integer(d->lost));
    if (probes & SPH_PROBE_FRONT_X)
        json_object_set_new(b, "front_x", num(d->front_x));
    if (probes & SPH_PROBE_HEIGHT_LEFT)
        json_object_set_new(b, "height_left", num(d->height_left));
    return b;
}

static void emit_diag(sphd_exec *x, sphd_emit_fn emit, void *ud)
{
    const sph_diag *d = sph_sim_diag(x->sim);
    json_decref(x->diag);
    x->diag = diag_json(d, x->c.sim.probes);
    x->last_diag = d->step;
    emit(ud, "diag", json_deep_copy(x->diag));
}

static sphd_exec_status advance_sim(sphd_exec *x, long max_steps, double until, sphd_emit_fn emit,
                                    void *ud, sph_error *err)
{
    const double t_end = x->c.sim.t_end;
    const double t_stop = until < t_end ? until : t_end;
    const long every = x->c.sim.diag_every;
    const double w0 = now();
    if (x->last_diag < 0)
        emit_diag(x, emit, ud); /* the initial state */
    long done = 0;
    int rc = 0;
    while (done < max_steps && sph_sim_time(x->sim) < t_stop) {
        const long step = sph_sim_diag(x->sim)->step;
        long chunk = every - step % every;
        if (chunk > max_steps - done)
            chunk = max_steps - done;
        rc = sph_sim_advance(x->sim, chunk, t_stop, err);
        done += sph_sim_diag(x->sim)->step - step;
        if (rc)
            break;
        if (sph_sim_diag(x->sim)->step % every == 0)
            emit_diag(x, emit, ud);
    }
    x->wall += now() - w0;
    if (rc) {
        if (x->last_diag != sph_sim_diag(x->sim)->step)
            emit_diag(x, emit, ud); /* the state that failed */
        return SPHD_EXEC_FAILED;
    }
    if (sph_sim_time(x->sim) < t_end)
        return SPHD_EXEC_RUNNING;
    const sph_diag *d = sph_sim_diag(x->sim);
    if (x->last_diag != d->step)
        emit_diag(x, emit, ud);
    json_t *res = json_pack("{s:s, s:I, s:o, s:o, s:{s:I, s:I, s:I}, s:O}", "method", "wcsph",
                            "steps", (json_int_t)d->step, "t", num(d->t), "wall_time", num(x->wall),
                            "particles", "fluid", (json_int_t)d->nfluid, "boundary",
                            (json_int_t)d->nboundary, "lost", (json_int_t)d->lost, "diag", x->diag);
    emit(ud, "result", res);
    x->finished = 1;
    return SPHD_EXEC_DONE;
}

sphd_exec_status sphd_exec_advance(sphd_exec *x, long max_steps, double until, sphd_emit_fn emit,
                                   void *ud, sph_error *err)
{
    if (x->finished)
        return SPHD_EXEC_DONE;
    switch (x->c.method) {
    case SPH_METHOD_KERNEL_STUDY:
        return advance_study(x, emit, ud, err);
    case SPH_METHOD_WCSPH:
        return advance_sim(x, max_steps, until, emit, ud, err);
    default:
        sph_error_set(err, SPH_ERR_INTERNAL, "", "method not implemented");
        return SPHD_EXEC_FAILED;
    }
}

json_t *sphd_exec_progress(const sphd_exec *x)
{
    if (!x->sim)
        return json_pack("{s:I, s:b}", "step", (json_int_t)0, "finished", x->finished);
    const sph_diag *d = sph_sim_diag(x->sim);
    json_t *diag = x->diag ? json_deep_copy(x->diag) : diag_json(d, x->c.sim.probes);
    return json_pack("{s:o, s:o, s:I, s:b, s:o}", "t", num(d->t), "t_end", num(x->c.sim.t_end),
                     "step", (json_int_t)d->step, "finished", x->finished, "diag", diag);
}

json_t *sphd_exec_particles(const sphd_exec *x, const char *const *fields, int nfields,
                            long max_particles, sph_error *err)
{
    static const char *const known[] = {"pos", "vel", "rho", "p", "type", "id", NULL};
    if (!x->sim) {
        sph_error_set(err, SPH_ERR_INVALID, "", "this job has no particles (method '%s')",
                      sph_method_name(x->c.method));
        return NULL;
    }
    for (int f = 0; f < nfields; f++) {
        int ok = 0;
        for (int k = 0; known[k]; k++)
            ok |= strcmp(fields[f], known[k]) == 0;
        if (!ok) {
            sph_error_set(err, SPH_ERR_INVALID, "/fields",
                          "unknown particle field '%s' (known: pos, vel, rho, p, type, id)",
                          fields[f]);
            return NULL;
        }
    }
    if (nfields < 1 || nfields > 8) {
        sph_error_set(err, SPH_ERR_INVALID, "/fields", "ask for 1 to 8 particle fields");
        return NULL;
    }
    if (max_particles < 1) {
        sph_error_set(err, SPH_ERR_INVALID, "/max_particles", "max_particles must be >= 1");
        return NULL;
    }
    sph_particle_view v;
    sph_sim_particles(x->sim, &v);
    /* evenly over the creation order (fluid first, then walls): index by id */
    long *where = malloc((size_t)(v.n > 0 ? v.n : 1) * sizeof *where);
    if (!where) {
        sph_error_set(err, SPH_ERR_NOMEM, "", "out of memory");
        return NULL;
    }
    for (long i = 0; i < v.n; i++)
        where[v.id[i]] = i;
    const long count = v.n < max_particles ? v.n : max_particles;
    json_t *out = json_object();
    json_t *arr[8] = {0};
    for (int f = 0; f < nfields; f++) {
        arr[f] = json_array();
        json_object_set_new(out, fields[f], arr[f]);
    }
    for (long k = 0; k < count; k++) {
        const long i = where[(long)((double)k * (double)v.n / (double)count)];
        for (int f = 0; f < nfields && f < 8; f++) {
            const char *name = fields[f];
            json_t *val;
            if (strcmp(name, "pos") == 0)
                val = json_pack("[o, o]", num(v.pos[0][i]), num(v.pos[1][i]));
            else if (strcmp(name, "vel") == 0)
                val = json_pack("[o, o]", num(v.vel[0][i]), num(v.vel[1][i]));
            else if (strcmp(name, "rho") == 0)
                val = num(v.rho[i]);
            else if (strcmp(name, "p") == 0)
                val = num(v.p[i]);
            else if (strcmp(name, "type") == 0)
                val = json_string(v.type[i] == 0 ? "fluid" : v.type[i] == 1 ? "boundary" : "lost");
            else
                val = json_integer(v.id[i]);
            json_array_append_new(arr[f], val);
        }
    }
    free(where);
    return json_pack("{s:I, s:I, s:o}", "total", (json_int_t)v.n, "count", (json_int_t)count,
                     "fields", out);
}

void sphd_exec_free(sphd_exec *x)
{
    if (!x)
        return;
    sph_sim_destroy(x->sim);
    json_decref(x->diag);
    free(x->outdir);
    free(x);
}
