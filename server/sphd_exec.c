#include "sphd_exec.h"

#include "sph_events.h"
#include "sph_sim.h"
#include "sph_study.h"
#include "sphd.h"
#include "sphd_ckpt.h"
#include "sphd_outputs.h"
#include "sphd_waves.h"
#include "sph_triggers.h"

#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

struct sphd_exec {
    sph_case c;
    char *outdir;
    int finished;
    sph_sim *sim;             /* a particle simulation (sph_case_is_sim) */
    double wall;              /* wall-clock seconds spent advancing [s] */
    long last_diag;           /* step of the latest diag event, -1 before the first */
    json_t *diag;             /* latest diag body (owned) */
    sphd_outputs *out;        /* result files (with an outdir) */
    double ckpt_interval;     /* wall-clock seconds between checkpoints [s] */
    int ckpt_every_outputs;   /* a checkpoint after every K snapshots [-] */
    double last_ckpt;         /* wall clock of the latest checkpoint [s] */
    int snapshots_since_ckpt; /* [-] */
    json_t *steering;         /* the changes made to the running job (sphd_exec_steer), oldest
                                 first: [{"step", "t", "set"}, ...]; saved with the checkpoint */
    unsigned fired;           /* the triggers that have fired (bit k: trigger k); saved */
    char halt[SPH_TRIGGER_WHEN_MAX + 96]; /* why the latest advance paused or stopped */
    /* a wave flume's gauge series since this run started (sphd_waves.h): wn rows of the time
     * and the gauges' heights [s], [m] */
    double *wt, *wg;
    long wn, wcap;
};

const char *sphd_exec_halt_reason(const sphd_exec *x)
{
    return x->halt;
}

/* The job id: the last component of the output directory. */
static const char *job_of(const char *outdir)
{
    const char *slash = strrchr(outdir, '/');
    return slash ? slash + 1 : outdir;
}

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
    x->ckpt_interval = SPHD_CKPT_INTERVAL_DEFAULT;
    x->ckpt_every_outputs = 1;
    x->last_ckpt = now();
    if (outdir && !(x->outdir = strdup(outdir))) {
        free(x);
        sph_error_set(err, SPH_ERR_NOMEM, "", "out of memory");
        return NULL;
    }
    if (!sph_case_is_sim(c)) {
        if (sph_study_validate(&c->study, err)) {
            sphd_exec_free(x);
            return NULL;
        }
    } else if (!(x->sim = sph_sim_create(&c->sim, err)) ||
               (outdir &&
                !(x->out = sphd_outputs_open(outdir, job_of(outdir), c, x->sim, -1, err)))) {
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

/* [v0, v1] of a 2D vector (new reference). */
static json_t *vec2(const double *v)
{
    return json_pack("[o, o]", num(v[0]), num(v[1]));
}

/* The rigid bodies of a diag, under their names (new reference). */
static json_t *bodies_json(const sph_diag *d, const sph_config *c)
{
    json_t *all = json_object();
    for (int k = 0; k < d->nbodies && k < c->nbodies; k++) {
        const sph_body_diag *b = &d->body[k];
        json_object_set_new(all, c->bodies[k].name,
                            json_pack("{s:o, s:o, s:o, s:o, s:o, s:o, s:o}", "x", vec2(b->x), "v",
                                      vec2(b->v), "angle", num(b->angle), "omega", num(b->omega),
                                      "force", vec2(b->force), "torque", num(b->torque),
                                      "penetration", num(b->penetration)));
    }
    return all;
}

/* The body of a diag event (new reference). */
static json_t *diag_json(const sph_diag *d, const sph_config *c, int solves_pressure)
{
    const unsigned probes = c->probes;
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
    if (probes & SPH_PROBE_PENETRATION)
        json_object_set_new(b, "penetration", num(d->penetration));
    if (probes & SPH_PROBE_RUNUP)
        json_object_set_new(b, "runup", num(d->runup));
    if (d->nbodies > 0)
        json_object_set_new(b, "bodies", bodies_json(d, c));
    if (d->ngauges > 0) {
        json_t *g = json_object();
        for (int k = 0; k < d->ngauges && k < c->ngauges; k++)
            json_object_set_new(g, c->gauges[k].name, num(d->gauge[k]));
        json_object_set_new(b, "gauges", g);
    }
    if (d->npressure > 0) {
        json_t *g = json_object();
        for (int k = 0; k < d->npressure && k < c->npressure; k++)
            json_object_set_new(g, c->pressure[k].name, num(d->pressure[k]));
        json_object_set_new(b, "pressure", g);
    }
    if (solves_pressure) { /* the pressure solve of the latest step */
        json_object_set_new(b, "cg_iterations", json_integer(d->cg_iterations));
        json_object_set_new(b, "cg_residual", num(d->cg_residual));
        json_object_set_new(b, "free_surface", json_integer(d->free_surface));
    }
    return b;
}

/* What a simulation's result adds for the physics its case asked for: the viscous term (with
 * the alpha Monaghan's term used), and for an initial field with a theory the kinetic-energy
 * envelope's decay rate and the period fitted over the first 8 periods beside the theory's. */
static void result_physics(json_t *res, const sph_sim *s)
{
    const sph_config *c = sph_sim_config(s);
    json_t *v = json_pack("{s:s}", "type", sph_visc_name(c->visc));
    if (c->visc != SPH_VISC_LAMINAR)
        json_object_set_new(
            v, "alpha",
            num(c->visc == SPH_VISC_MONAGHAN ? sph_config_monaghan_alpha(c) : c->alpha));
    if (c->visc != SPH_VISC_ARTIFICIAL)
        json_object_set_new(v, "nu", num(c->nu));
    json_object_set_new(res, "viscosity", v);
    sph_sim_wave w;
    sph_sim_wave_fit(s, INFINITY, &w); /* the theory's period, for the fit's span */
    if (w.period_theory > 0.0 && sph_sim_wave_fit(s, 8.0 * w.period_theory, &w) == 0)
        json_object_set_new(res, "wave",
                            json_pack("{s:o, s:i, s:o, s:o, s:o, s:o}", "fit_until", num(w.t_fit),
                                      "peaks", w.peaks, "period", num(w.period), "period_theory",
                                      num(w.period_theory), "decay_rate", num(w.decay_rate),
                                      "decay_rate_theory", num(w.decay_rate_theory)));
}

/* A wave flume's gauges into the series of its wave analysis (dropped when out of memory: the
 * analysis then covers less). */
static void keep_gauges(sphd_exec *x, const sph_diag *d)
{
    const sph_config *c = &x->c.sim;
    const int ng = c->ngauges;
    if (c->wavemaker.type == SPH_WAVEMAKER_NONE || ng == 0 || d->ngauges < ng)
        return;
    if (x->wn == x->wcap) {
        const long cap = x->wcap ? 2 * x->wcap : 1024;
        double *t = realloc(x->wt, (size_t)cap * sizeof *t);
        if (t)
            x->wt = t;
        double *g = t ? realloc(x->wg, (size_t)cap * (size_t)ng * sizeof *g) : NULL;
        if (!g)
            return;
        x->wg = g;
        x->wcap = cap;
    }
    x->wt[x->wn] = d->t;
    for (int k = 0; k < ng; k++)
        x->wg[x->wn * ng + k] = d->gauge[k];
    x->wn++;
}

static int emit_diag(sphd_exec *x, sphd_emit_fn emit, void *ud, sph_error *err)
{
    const sph_diag *d = sph_sim_diag(x->sim);
    json_decref(x->diag);
    x->diag = diag_json(d, &x->c.sim, sph_sim_solves_pressure(x->sim));
    x->last_diag = d->step;
    emit(ud, "diag", json_deep_copy(x->diag));
    keep_gauges(x, d);
    return x->out ? sphd_outputs_diag(x->out, d, err) : 0;
}

/* A snapshot when the time has come (and at the end), then a checkpoint when due. */
static int outputs_due(sphd_exec *x, int at_end, sphd_emit_fn emit, void *ud, sph_error *err)
{
    if (!x->out)
        return 0;
    const double t = sph_sim_time(x->sim);
    const double next = sphd_outputs_next_time(x->out);
    if (t >= next - 1e-12 * (1.0 + fabs(next)) || (at_end && isfinite(next))) {
        json_t *ev = sphd_outputs_snapshot(x->out, x->sim, err);
        if (!ev)
            return err ? (int)err->code : SPH_ERR_IO;
        emit(ud, "output", ev);
        x->snapshots_since_ckpt++;
    }
    if (!at_end && (x->snapshots_since_ckpt >= x->ckpt_every_outputs ||
                    now() - x->last_ckpt >= x->ckpt_interval))
        return sphd_exec_checkpoint(x, err);
    return 0;
}

/* The triggers that the latest diag meets, each once: a `trigger` event, then its action (a
 * checkpoint or a snapshot now; pause and stop are returned: SPHD_EXEC_PAUSE or _STOP, the
 * first of them in the list, with x->halt). SPHD_EXEC_RUNNING when the run goes on,
 * SPHD_EXEC_FAILED on a write that failed (err). */
static sphd_exec_status run_triggers(sphd_exec *x, sphd_emit_fn emit, void *ud, sph_error *err)
{
    sphd_exec_status halt = SPHD_EXEC_RUNNING;
    const sph_output_config *o = &x->c.output;
    for (int k = 0; k < o->ntriggers && k < 32; k++) {
        const sph_trigger *t = &o->triggers[k];
        if ((x->fired >> k & 1u) || !sph_trigger_holds(t, x->diag))
            continue;
        x->fired |= 1u << k;
        const sph_diag *d = sph_sim_diag(x->sim);
        emit(ud, "trigger",
             json_pack("{s:s, s:s, s:I, s:o}", "when", t->when, "do",
                       sph_trigger_action_name(t->action), "step", (json_int_t)d->step, "t",
                       num(d->t)));
        int rc = 0;
        if (t->action == SPH_TRIGGER_CHECKPOINT) {
            rc = sphd_exec_checkpoint(x, err);
        } else if (t->action == SPH_TRIGGER_SNAPSHOT && x->out) {
            json_t *ev = sphd_outputs_snapshot_extra(x->out, x->sim, err);
            if (ev) {
                emit(ud, "output", ev);
                x->snapshots_since_ckpt++;
            }
            rc = ev ? 0 : SPH_ERR_IO;
        } else if ((t->action == SPH_TRIGGER_PAUSE || t->action == SPH_TRIGGER_STOP) &&
                   halt == SPHD_EXEC_RUNNING) {
            halt = t->action == SPH_TRIGGER_PAUSE ? SPHD_EXEC_PAUSE : SPHD_EXEC_STOP;
            snprintf(x->halt, sizeof x->halt, "trigger '%s' at t = %.6g s (step %ld)", t->when,
                     d->t, d->step);
        }
        if (rc)
            return SPHD_EXEC_FAILED;
    }
    return halt;
}

/* The first multiple of interval after t (t itself when it lies on one, within rounding, is
 * passed): where the next diag of a case with diagnostics.interval lands. */
static double next_multiple(double t, double interval)
{
    const double k = floor(t / interval + 1e-9);
    double next = (k + 1.0) * interval;
    if (next <= t)
        next = (k + 2.0) * interval;
    return next;
}

static sphd_exec_status advance_sim(sphd_exec *x, long max_steps, double until, sphd_emit_fn emit,
                                    void *ud, sph_error *err)
{
    const double t_end = x->c.sim.t_end;
    const double interval = x->c.sim.diag_interval;
    const long every = interval > 0.0 ? LONG_MAX : x->c.sim.diag_every;
    const double w0 = now();
    int rc = 0;
    sphd_exec_status halt = SPHD_EXEC_RUNNING;
    x->halt[0] = '\0';
    if (x->last_diag < 0) { /* the initial state */
        rc = emit_diag(x, emit, ud, err) || outputs_due(x, 0, emit, ud, err);
        if (rc == 0 && (halt = run_triggers(x, emit, ud, err)) == SPHD_EXEC_FAILED)
            rc = -1;
    }
    long done = 0;
    while (rc == 0 && halt == SPHD_EXEC_RUNNING && done < max_steps) {
        double t_stop = until < t_end ? until : t_end;
        if (x->out && sphd_outputs_next_time(x->out) < t_stop)
            t_stop = sphd_outputs_next_time(x->out); /* land on the output time */
        const double t_diag =
            interval > 0.0 ? next_multiple(sph_sim_time(x->sim), interval) : INFINITY;
        if (t_diag < t_stop)
            t_stop = t_diag; /* land on the diag time */
        if (sph_sim_time(x->sim) >= t_stop)
            break;
        const long step = sph_sim_diag(x->sim)->step;
        long chunk = every - step % every;
        if (chunk > max_steps - done)
            chunk = max_steps - done;
        rc = sph_sim_advance(x->sim, chunk, t_stop, err);
        done += sph_sim_diag(x->sim)->step - step;
        if (rc)
            break;
        const int diag_now = interval > 0.0 ? sph_sim_time(x->sim) >= t_diag
                                            : sph_sim_diag(x->sim)->step % every == 0;
        if (diag_now)
            rc = emit_diag(x, emit, ud, err);
        if (rc == 0 && sph_sim_time(x->sim) < t_end)
            rc = outputs_due(x, 0, emit, ud, err);
        /* after the outputs of this step: a paused run goes on from the next one */
        if (rc == 0 && diag_now && (halt = run_triggers(x, emit, ud, err)) == SPHD_EXEC_FAILED)
            rc = -1;
    }
    x->wall += now() - w0;
    if (rc) {
        if (x->last_diag != sph_sim_diag(x->sim)->step) {
            sph_error ignored;
            emit_diag(x, emit, ud, &ignored); /* the state that failed */
        }
        return SPHD_EXEC_FAILED;
    }
    if (halt != SPHD_EXEC_RUNNING && sph_sim_time(x->sim) < t_end)
        return halt;
    if (sph_sim_time(x->sim) < t_end)
        return SPHD_EXEC_RUNNING;
    const sph_diag *d = sph_sim_diag(x->sim);
    if ((x->last_diag != d->step && emit_diag(x, emit, ud, err)) ||
        outputs_due(x, 1, emit, ud, err))
        return SPHD_EXEC_FAILED;
    json_t *res = json_pack("{s:s, s:I, s:o, s:o, s:{s:I, s:I, s:I}, s:O}", "method",
                            sph_method_name(x->c.method), "steps", (json_int_t)d->step, "t",
                            num(d->t), "wall_time", num(x->wall), "particles", "fluid",
                            (json_int_t)d->nfluid, "boundary", (json_int_t)d->nboundary, "lost",
                            (json_int_t)d->lost, "diag", x->diag);
    if (res && d->nbody > 0) /* the bodies' particles, when there are bodies */
        json_object_set_new(json_object_get(res, "particles"), "body", json_integer(d->nbody));
    result_physics(res, x->sim);
    json_t *waves = res ? sphd_waves_json(&x->c.sim, x->wt, x->wg, x->wn) : NULL;
    if (waves)
        json_object_set_new(res, "waves", waves);
    json_t *sol = res ? sphd_waves_solitary_json(&x->c.sim, x->wt, x->wg, x->wn) : NULL;
    if (sol)
        json_object_set_new(res, "solitary", sol);
    json_t *refl =
        res ? sphd_waves_reflection_json(&x->c.sim, &x->c.output, x->wt, x->wg, x->wn) : NULL;
    if (refl)
        json_object_set_new(res, "reflection", refl);
    if (res && x->steering)
        json_object_set(res, "steering", x->steering);
    emit(ud, "result", res);
    x->finished = 1;
    return SPHD_EXEC_DONE;
}

sphd_exec_status sphd_exec_advance(sphd_exec *x, long max_steps, double until, sphd_emit_fn emit,
                                   void *ud, sph_error *err)
{
    if (x->finished)
        return SPHD_EXEC_DONE;
    if (!sph_case_is_sim(&x->c))
        return advance_study(x, emit, ud, err);
    return advance_sim(x, max_steps, until, emit, ud, err);
}

json_t *sphd_exec_progress(const sphd_exec *x)
{
    if (!x->sim)
        return json_pack("{s:I, s:b}", "step", (json_int_t)0, "finished", x->finished);
    const sph_diag *d = sph_sim_diag(x->sim);
    json_t *diag = x->diag ? json_deep_copy(x->diag)
                           : diag_json(d, &x->c.sim, sph_sim_solves_pressure(x->sim));
    return json_pack("{s:o, s:o, s:I, s:b, s:o}", "t", num(d->t), "t_end", num(x->c.sim.t_end),
                     "step", (json_int_t)d->step, "finished", x->finished, "diag", diag);
}

/* The radial particle density function of the fluid now (sph_rpdf.h): SPH_SIM_RPDF_BINS bins of
 * q = r/h over [0, SPH_SIM_RPDF_QMAX), as in the snapshots. New reference, or NULL with err. */
static json_t *rpdf_json(const sph_sim *s, sph_error *err)
{
    enum { NB = SPH_SIM_RPDF_BINS };
    double q[NB], count[NB], dens[NB];
    if (sph_sim_rpdf(s, SPH_SIM_RPDF_QMAX, NB, q, count, dens, err))
        return NULL;
    json_t *jq = json_array(), *jc = json_array(), *jd = json_array();
    for (int b = 0; b < NB; b++) {
        json_array_append_new(jq, num(q[b]));
        json_array_append_new(jc, json_integer((json_int_t)count[b]));
        json_array_append_new(jd, num(dens[b]));
    }
    return json_pack("{s:o, s:o, s:o}", "q", jq, "count", jc, "density", jd);
}

json_t *sphd_exec_particles(const sphd_exec *x, const char *const *fields, int nfields,
                            long max_particles, sph_error *err)
{
    static const char *const known[] = {"pos", "vel", "rho", "p", "type", "id", "rpdf", NULL};
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
                          "unknown particle field '%s' (known: pos, vel, rho, p, type, id, rpdf)",
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
        if (strcmp(fields[f], "rpdf") == 0) { /* not per particle: the whole fluid's */
            json_t *r = rpdf_json(x->sim, err);
            if (!r) {
                free(where);
                json_decref(out);
                return NULL;
            }
            json_object_set_new(out, "rpdf", r);
            continue;
        }
        arr[f] = json_array();
        json_object_set_new(out, fields[f], arr[f]);
    }
    for (long k = 0; k < count; k++) {
        const long i = where[(long)((double)k * (double)v.n / (double)count)];
        for (int f = 0; f < nfields && f < 8; f++) {
            const char *name = fields[f];
            if (!arr[f])
                continue;
            json_t *val;
            if (strcmp(name, "pos") == 0 || strcmp(name, "vel") == 0) {
                const double *const *c = name[0] == 'p' ? v.pos : v.vel;
                const float *const *c32 = name[0] == 'p' ? NULL : v.vel32;
                val = json_array(); /* [x, y], and z in 3D */
                for (int d = 0; d < v.dim; d++)
                    json_array_append_new(val, num(sph_view_get(c[d], c32 ? c32[d] : NULL, i)));
            } else if (strcmp(name, "rho") == 0)
                val = num(sph_view_get(v.rho, v.rho32, i));
            else if (strcmp(name, "p") == 0)
                val = num(sph_view_get(v.p, v.p32, i));
            else if (strcmp(name, "type") == 0) {
                const char *tn = sph_particle_type_name(v.type[i]);
                val = json_string(tn ? tn : "unknown");
            } else
                val = json_integer(v.id[i]);
            json_array_append_new(arr[f], val);
        }
    }
    free(where);
    return json_pack("{s:I, s:I, s:o}", "total", (json_int_t)v.n, "count", (json_int_t)count,
                     "fields", out);
}

void sphd_exec_set_checkpoint_policy(sphd_exec *x, double interval, int every_outputs)
{
    x->ckpt_interval = interval;
    x->ckpt_every_outputs = every_outputs;
}

int sphd_exec_checkpoint(sphd_exec *x, sph_error *err)
{
    if (!x->sim || !x->outdir)
        return 0; /* nothing to continue: one-shot jobs, or no place to write */
    void *state;
    size_t len;
    if (sph_sim_save(x->sim, &state, &len, err))
        return err ? (int)err->code : SPH_ERR_NOMEM;
    json_t *ex =
        json_pack("{s:o, s:f, s:I}", "outputs", x->out ? sphd_outputs_state(x->out) : json_object(),
                  "wall", x->wall, "last_diag", (json_int_t)x->last_diag);
    if (ex && x->steering) { /* with the triggers and the snapshots' period as steered */
        json_object_set(ex, "steering", x->steering);
        json_object_set_new(ex, "triggers", sph_triggers_json(&x->c.output));
        json_object_set_new(ex, "output_every", json_real(x->c.output.every));
    }
    if (ex && x->fired)
        json_object_set_new(ex, "fired", json_integer((json_int_t)x->fired));
    char *text = json_dumps(ex, JSON_COMPACT | JSON_REAL_PRECISION(17));
    json_decref(ex);
    if (!text) {
        free(state);
        return sph_error_set(err, SPH_ERR_NOMEM, "", "out of memory");
    }
    const sphd_ckpt_section sections[] = {{"sim", state, len}, {"exec", text, strlen(text)}};
    int rc = sphd_ckpt_write(x->outdir, sections, 2, err);
    free(state);
    free(text);
    if (rc == 0) {
        x->last_ckpt = now();
        x->snapshots_since_ckpt = 0;
    }
    return rc;
}

int sphd_exec_steer(sphd_exec *x, const sph_case *next_case, const json_t *set, json_t **record,
                    sph_error *err)
{
    const sph_config *next = &next_case->sim;
    *record = NULL;
    if (!x->sim || x->finished)
        return sph_error_set(err, SPH_ERR_INVALID, "",
                             "the job has no running simulation to steer");
    const sph_diag *d = sph_sim_diag(x->sim);
    if (!(next->t_end > d->t))
        return sph_error_set(err, SPH_ERR_INVALID, "/time/end",
                             "the job is at t = %.9g s already: the end time must be later", d->t);
    if (sph_sim_steer(x->sim, next, err))
        return (int)err->code;
    sph_config_steer(&x->c.sim, next);
    /* the triggers: those that stay as they were keep whether they have fired */
    const sph_output_config *o = &x->c.output, *n = &next_case->output;
    unsigned fired = 0;
    for (int k = 0; k < n->ntriggers && k < o->ntriggers; k++)
        if ((x->fired >> k & 1u) && strcmp(o->triggers[k].when, n->triggers[k].when) == 0 &&
            o->triggers[k].action == n->triggers[k].action)
            fired |= 1u << k;
    x->fired = fired;
    x->c.output.ntriggers = n->ntriggers;
    memcpy(x->c.output.triggers, n->triggers, sizeof n->triggers);
    if (n->every != o->every) { /* the snapshots: the first multiple of the new period after t */
        x->c.output.every = n->every;
        if (x->out)
            sphd_outputs_set_every(x->out, n->every, d->t);
    }
    json_t *rec =
        json_pack("{s:I, s:o, s:O}", "step", (json_int_t)d->step, "t", num(d->t), "set", set);
    if (!x->steering)
        x->steering = json_array();
    if (!rec || !x->steering || json_array_append(x->steering, rec))
        return sph_error_set(err, SPH_ERR_NOMEM, "", "out of memory");
    *record = rec;
    return 0;
}

const json_t *sphd_exec_steering(const sphd_exec *x)
{
    return x ? x->steering : NULL;
}

sphd_exec *sphd_exec_resume(const sph_case *c, const char *outdir, int *fell_back, sph_error *err)
{
    if (!sph_case_is_sim(c)) {
        sph_error_set(err, SPH_ERR_INVALID, "", "only simulations resume from checkpoints");
        return NULL;
    }
    sph_error why;
    sph_error_clear(&why);
    sphd_ckpt *ck = sphd_ckpt_load(outdir, fell_back, &why);
    if (!ck) {
        sph_error_set(err, SPH_ERR_IO, "", "%s", why.message);
        return NULL;
    }
    if (err && fell_back && *fell_back)
        *err = why; /* says which checkpoint was damaged; code SPH_OK */
    size_t len = 0, tlen = 0;
    const void *state = sphd_ckpt_get(ck, "sim", &len);
    const char *text = sphd_ckpt_get(ck, "exec", &tlen);
    json_t *ex = text ? json_loadb(text, tlen, 0, NULL) : NULL;
    sphd_exec *x = calloc(1, sizeof *x);
    if (!state || !ex || !x) {
        json_decref(ex);
        sphd_ckpt_free(ck);
        free(x);
        sph_error_set(err, SPH_ERR_IO, "", "checkpoint in '%s' lacks the job's state", outdir);
        return NULL;
    }
    x->c = *c;
    x->ckpt_interval = SPHD_CKPT_INTERVAL_DEFAULT;
    x->ckpt_every_outputs = 1;
    x->last_ckpt = now();
    x->wall = json_number_value(json_object_get(ex, "wall"));
    x->last_diag = (long)json_integer_value(json_object_get(ex, "last_diag"));
    x->fired = (unsigned)json_integer_value(json_object_get(ex, "fired"));
    x->outdir = strdup(outdir);
    x->sim = x->outdir ? sph_sim_restore(state, len, err) : NULL;
    sphd_ckpt_free(ck);
    const json_t *steering = json_object_get(ex, "steering");
    if (x->sim && json_array_size(steering) > 0) {
        /* a steered job goes on with the values it had at the checkpoint, not the case's */
        x->steering = json_deep_copy(steering);
        sph_config_steer(&x->c.sim, sph_sim_config(x->sim));
        sph_error terr;
        const json_t *tr = json_object_get(ex, "triggers");
        if (tr && sph_triggers_parse(tr, "/triggers", &x->c.sim, &x->c.output, &terr) != 0)
            x->c.output.ntriggers = 0; /* (they parsed when they were set) */
        const double every = json_number_value(json_object_get(ex, "output_every"));
        if (every > 0.0)
            x->c.output.every = every;
    }
    if (x->sim) {
        const sph_diag *d = sph_sim_diag(x->sim);
        x->diag = diag_json(d, &x->c.sim, sph_sim_solves_pressure(x->sim));
        x->out = sphd_outputs_open(outdir, job_of(outdir), &x->c, x->sim, d->step, err);
        if (x->out && sphd_outputs_restore(x->out, json_object_get(ex, "outputs"), d->t, err)) {
            sphd_outputs_close(x->out);
            x->out = NULL;
        }
    }
    json_decref(ex);
    if (!x->sim || !x->out) {
        sphd_exec_free(x);
        return NULL;
    }
    return x;
}

sphd_exec *sphd_exec_continue(const sph_case *c, const char *outdir, sphd_continued *how,
                              sph_error *err)
{
    memset(how, 0, sizeof *how);
    sph_error_clear(&how->why);
    int fell_back = 0;
    sphd_exec *x = sphd_exec_resume(c, outdir, &fell_back, &how->why);
    if (x) {
        how->from = fell_back ? SPHD_FROM_PREVIOUS : SPHD_FROM_LATEST;
        return x;
    }
    how->from = SPHD_AFRESH;
    how->kept = sphd_ckpt_set_aside(outdir);
    return sphd_exec_new(c, outdir, err);
}

void sphd_exec_free(sphd_exec *x)
{
    if (!x)
        return;
    sphd_outputs_close(x->out);
    sph_sim_destroy(x->sim);
    json_decref(x->diag);
    json_decref(x->steering);
    free(x->wt);
    free(x->wg);
    free(x->outdir);
    free(x);
}
