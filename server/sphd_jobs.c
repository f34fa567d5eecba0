/*
 * The job manager: the job table, the state machine (queued, running, paused, done, failed,
 * stopped), the scheduler that hands runnable jobs to idle workers, and the job records in
 * STATE_DIR/jobs/JOB/. Runs on the loop thread only.
 */
#include "sphd.h"
#include "sphd_daemon.h"

#include "sph_events.h"
#include "sph_json.h"
#include "sph_sim.h"
#include "sphd_journal.h"

#include <dirent.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

int sphd_job_id_ok(const char *id)
{
    size_t n = strlen(id);
    if (n == 0 || n >= SPHD_JOB_ID_MAX || id[0] == '.')
        return 0;
    for (size_t i = 0; i < n; i++) {
        char c = id[i];
        if (!((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
              c == '.' || c == '_' || c == '-'))
            return 0;
    }
    return 1;
}

sphd_job *sphd_job_find(sphd_daemon *d, const char *id)
{
    for (sphd_job *j = d->jobs; j; j = j->next)
        if (strcmp(j->id, id) == 0)
            return j;
    return NULL;
}

/* A job's JSON file, written atomically; a failure is logged (the job carries on). */
static int write_json(const char *dir, const char *name, const json_t *j)
{
    int rc = sphd_write_json(dir, name, j);
    if (rc != 0)
        sphd_log("cannot write %s/%s: %s", dir, name, strerror(errno));
    return rc;
}

static json_t *num_or_null(double x)
{
    return sph_json_real_or_null(x);
}

/* ---- steering ---- */

json_t *sphd_job_steering(const sphd_job *j)
{
    /* the values in effect: each path's latest assignment */
    json_t *values = json_object();
    size_t k, i;
    const json_t *rec, *a;
    json_array_foreach(j->steering, k, rec)
    {
        json_array_foreach(json_object_get(rec, "set"), i, a)
        {
            const char *text = json_string_value(a), *eq = text ? strchr(text, '=') : NULL;
            if (!eq)
                continue;
            char path[256];
            snprintf(path, sizeof path, "%.*s", (int)(eq - text), text);
            json_t *v = json_loads(eq + 1, JSON_DECODE_ANY, NULL);
            json_object_set_new(values, path, v ? v : json_string(eq + 1));
        }
    }
    json_t *o = json_pack("{s:o, s:O}", "values", values, "history",
                          j->steering ? j->steering : json_array());
    if (o && j->steer_set)
        json_object_set(o, "pending", j->steer_set);
    if (o && j->steer_error[0])
        json_object_set_new(o, "error", json_string(j->steer_error));
    return o;
}

void sphd_job_steer_drop(sphd_job *j)
{
    json_decref(j->steer_set);
    json_decref(j->steer_case);
    if (j->steer_next) {
        sph_case_clear(j->steer_next);
        free(j->steer_next);
    }
    j->steer_set = j->steer_case = NULL;
    j->steer_next = NULL;
}

int sphd_job_steer_apply(sphd_daemon *d, sphd_job *j, sphd_err *e)
{
    json_t *set = json_incref(j->steer_set), *next_json = json_incref(j->steer_case);
    sph_case *next = j->steer_next;
    j->steer_next = NULL;
    sphd_job_steer_drop(j);
    sph_error err;
    sph_error_clear(&err);
    json_t *rec = NULL;
    int rc = -1;
    if (!j->exec)
        sph_error_set(&err, SPH_ERR_INVALID, "", "the job has no simulation in memory to steer");
    else if (sphd_exec_steer(j->exec, next, set, &rec, &err) == 0)
        rc = 0;
    sph_case_clear(next);
    free(next);
    if (rc != 0) {
        snprintf(j->steer_error, sizeof j->steer_error, "%s%s%s", err.message,
                 err.path[0] ? " at " : "", err.path);
        sphd_err_set(e, SPHD_E_INVALID_CASE, err.path[0] ? err.path : NULL, "%s", err.message);
        json_decref(set);
        json_decref(next_json);
        return -1;
    }
    j->steer_error[0] = '\0';
    /* committed by the checkpoint, whose history holds it (a crash before it: never made) */
    sph_error_clear(&err);
    if (sphd_exec_checkpoint(j->exec, &err) != 0)
        sphd_log("job %s: the checkpoint after a change failed: %s", j->id, err.message);
    json_decref(j->steering);
    j->steering = json_deep_copy(sphd_exec_steering(j->exec));
    json_decref(j->case_now);
    j->case_now = next_json;
    /* case.json records the history (its "steering", which a case parses and ignores); the
     * job's identity (j->case_json) stays the case as submitted */
    json_t *rec_case = json_deep_copy(j->case_json);
    if (rec_case && json_object_set(rec_case, "steering", j->steering) == 0)
        write_json(j->dir, "case.json", rec_case);
    json_decref(rec_case);
    json_t *jr = json_pack("{s:f, s:O, s:O, s:O, s:I}", "t", sphd_now(), "steer", set, "step",
                           json_object_get(rec, "step"), "sim_t", json_object_get(rec, "t"), "seq",
                           (json_int_t)j->seq);
    if (jr && sphd_journal_append(j->dir, jr, &err) != 0)
        sphd_log("job %s: %s", j->id, err.message);
    json_decref(jr);
    json_decref(set);
    sphd_publish(d, j, "steer", rec);
    sphd_job_record(d, j, 0);
    return 0;
}

json_t *sphd_job_status(const sphd_job *j)
{
    json_t *s =
        json_pack("{s:s, s:s, s:s, s:s, s:I, s:f, s:s}", "job", j->id, "name", j->c->name, "method",
                  sph_method_name(j->c->method), "state", sphd_job_state_name(j->state), "seq",
                  (json_int_t)j->seq, "submitted", j->submitted, "dir", j->dir);
    if (!s)
        return NULL;
    if (j->state == SPHD_JOB_FAILED || j->reason[0])
        json_object_set_new(s, "reason", json_string(j->reason));
    if (j->slurm) {
        json_object_set_new(s, "executor", json_string("slurm"));
        if (j->slurm_id[0])
            json_object_set_new(s, "slurm_job", json_string(j->slurm_id));
        if (j->retries)
            json_object_set_new(s, "retries", json_integer(j->retries));
    }
    if (j->resources)
        json_object_set(s, "resources", j->resources);
    if (j->sweep[0]) {
        json_object_set_new(s, "sweep", json_string(j->sweep));
        json_object_set(s, "params", j->params ? j->params : json_null());
    }
    const json_t *p = j->progress;
    json_t *t = json_object_get(p, "t"), *t_end = json_object_get(p, "t_end");
    json_t *prog =
        json_pack("{s:O?, s:O?, s:I, s:f, s:o, s:o}", "t", t, "t_end", t_end, "steps",
                  (json_int_t)json_integer_value(json_object_get(p, "step")), "wall",
                  j->wall + (j->state == SPHD_JOB_RUNNING ? j->run_wall : 0.0), "steps_per_s",
                  num_or_null(j->state == SPHD_JOB_RUNNING ? j->steps_per_s : 0.0), "eta",
                  num_or_null(j->state == SPHD_JOB_RUNNING ? j->eta : NAN));
    if (prog) {
        json_t *np = json_object_get(p, "particles");
        if (np)
            json_object_set(prog, "particles", np);
        json_object_set_new(s, "progress", prog);
    }
    if (j->steering || j->steer_set || j->steer_error[0])
        json_object_set_new(s, "steering", sphd_job_steering(j));
    if (j->step_n > 0 || isfinite(j->step_until)) {
        json_t *st = json_object();
        if (j->step_n > 0)
            json_object_set_new(st, "n", json_integer(j->step_n));
        if (isfinite(j->step_until))
            json_object_set_new(st, "until", json_real(j->step_until));
        json_object_set_new(s, "pending_step", st);
    }
    return s;
}

/* job.json: what a later sphd needs to resume or report the job (issue 5 reads it). */
void sphd_job_record(sphd_daemon *d, sphd_job *j, int interrupted)
{
    (void)d;
    json_t *rec = sphd_job_status(j);
    if (!rec)
        return;
    json_object_set_new(rec, "resumable", json_boolean(!sphd_job_state_final(j->state)));
    json_object_set_new(rec, "interrupted_by_shutdown", json_boolean(interrupted));
    write_json(j->dir, "job.json", rec);
    json_decref(rec);
}

void sphd_job_set_state(sphd_daemon *d, sphd_job *j, sphd_job_state s, const char *reason)
{
    const int was_final = sphd_job_state_final(j->state);
    j->state = s;
    snprintf(j->reason, sizeof j->reason, "%s", reason ? reason : "");
    if (sphd_job_state_final(s) && !was_final) {
        d->njobs_active--;
        d->njobs_final++;
        if (j->exec_readers == 0) { /* else the files thread reads it: freed when done */
            sphd_exec_free(j->exec);
            j->exec = NULL;
        }
        j->step_n = 0;
        j->step_until = INFINITY;
    }
    json_t *b = json_pack("{s:s}", "state", sphd_job_state_name(s));
    if (b && j->reason[0]) /* failed, or paused or stopped by a trigger */
        json_object_set_new(b, "reason", json_string(j->reason));
    /* the journal: every state change, appended and fsync'd before anyone hears of it, with
     * the seq of its `state` event */
    json_t *rec = json_pack("{s:f, s:s, s:I, s:I}", "t", sphd_now(), "state",
                            sphd_job_state_name(s), "seq", (json_int_t)(j->seq + 1), "step",
                            (json_int_t)json_integer_value(json_object_get(j->progress, "step")));
    if (rec && j->reason[0])
        json_object_set_new(rec, "reason", json_string(j->reason));
    if (rec && s == SPHD_JOB_RUNNING && j->pause_requested)
        json_object_set_new(rec, "pause", json_true()); /* still pending (a recovered job) */
    if (rec && s == SPHD_JOB_RUNNING && j->stop_requested)
        json_object_set_new(rec, "stop", json_true());
    sph_error err;
    if (rec && sphd_journal_append(j->dir, rec, &err) != 0)
        sphd_log("job %s: %s", j->id, err.message);
    else if (rec && j->seq + 1 > j->seq_on_disk)
        j->seq_on_disk = j->seq + 1;
    json_decref(rec);
    sphd_publish(d, j, "state", b);
    sphd_job_record(d, j, 0);
}

void sphd_job_journal_requests(sphd_daemon *d, sphd_job *j)
{
    (void)d;
    json_t *rec = json_pack("{s:f, s:b, s:b, s:I}", "t", sphd_now(), "pause", j->pause_requested,
                            "stop", j->stop_requested, "seq", (json_int_t)j->seq);
    sph_error err;
    if (rec && sphd_journal_append(j->dir, rec, &err) != 0)
        sphd_log("job %s: %s", j->id, err.message);
    json_decref(rec);
}

static void job_free(sphd_job *j)
{
    if (!j)
        return;
    sphd_job_touch(j);
    sphd_exec_free(j->exec);
    json_decref(j->case_json);
    json_decref(j->params);
    json_decref(j->resources);
    json_decref(j->progress);
    json_decref(j->diag);
    json_decref(j->result);
    json_decref(j->case_now);
    json_decref(j->steering);
    sphd_job_steer_drop(j);
    while (j->waiters) {
        sphd_pending *n = j->waiters->next;
        sphd_pending_free(j->waiters);
        j->waiters = n;
    }
    sph_case_clear(j->c);
    free(j->c);
    free(j);
}

/* Forgets the oldest finished jobs beyond SPHD_KEEP_FINISHED (their files stay). */
static void prune(sphd_daemon *d)
{
    sphd_job **pp = &d->jobs;
    while (*pp && d->njobs_final > SPHD_KEEP_FINISHED) {
        sphd_job *j = *pp;
        if (sphd_job_state_final(j->state) && j->readers == 0) {
            *pp = j->next;
            d->njobs_final--;
            job_free(j);
        } else {
            pp = &j->next;
        }
    }
}

sphd_job *sphd_job_submit(sphd_daemon *d, const char *id, json_t *case_json, int start,
                          const char *sweep, json_t *params, json_t *resources,
                          const sphd_inputs *in, sphd_err *e)
{
    if (d->njobs_active >= d->opts.max_jobs) {
        sphd_err_set(e, SPHD_E_BUSY, NULL,
                     "sphd holds %d jobs (--max-jobs); retry when one has finished",
                     d->njobs_active);
        return NULL;
    }
    sphd_job *j = calloc(1, sizeof *j);
    if (!j || !(j->c = calloc(1, sizeof *j->c))) {
        free(j);
        sphd_err_set(e, SPHD_E_INTERNAL, NULL, "out of memory");
        return NULL;
    }
    sph_error err;
    sph_error_clear(&err);
    if (sph_case_from_json(case_json, j->c, &err)) {
        sphd_err_set(e, SPHD_E_INVALID_CASE, err.path, "%s", err.message);
        job_free(j);
        return NULL;
    }
    if (id) {
        snprintf(j->id, sizeof j->id, "%s", id);
    } else {
        /* NAME-N, unique in memory and on disk. */
        for (;;) {
            snprintf(j->id, sizeof j->id, "%.40s-%ld", j->c->name, ++d->next_job_number);
            char dir[SPHD_PATH_MAX + 128];
            snprintf(dir, sizeof dir, "%s/jobs/%s", d->opts.state_dir, j->id);
            if (sphd_job_id_ok(j->id) && !sphd_job_find(d, j->id) && access(dir, F_OK) != 0)
                break;
            if (!sphd_job_id_ok(j->id)) {
                snprintf(j->id, sizeof j->id, "job-%ld", d->next_job_number);
                if (!sphd_job_find(d, j->id))
                    break;
            }
        }
    }
    if ((size_t)snprintf(j->dir, sizeof j->dir, "%s/jobs/%s", d->opts.state_dir, j->id) >=
        sizeof j->dir) {
        sphd_err_set(e, SPHD_E_BAD_REQUEST, NULL, "the state directory path is too long");
        job_free(j);
        return NULL;
    }
    /* The executor (particle generation, allocation) is solver work: the worker creates it
     * when the job first runs. Here only the cheap check of its size. */
    if (sph_case_is_sim(j->c)) {
        long nf = 0, nb = 0;
        const double bytes = sph_sim_estimate_bytes(&j->c->sim, &nf, &nb);
        if (bytes > j->c->sim.max_bytes) {
            sphd_err_set(e, SPHD_E_TOO_LARGE, "/dx",
                         "the case needs about %.0f MB (%ld fluid and %ld boundary particles), "
                         "more than the %.0f MB allowed: use a larger dx",
                         bytes / 1e6, nf, nb, j->c->sim.max_bytes / 1e6);
            job_free(j);
            return NULL;
        }
    }
    if (sphd_mkdirs(j->dir) != 0) {
        sphd_err_set(e, SPHD_E_INTERNAL, NULL, "cannot create %s: %s", j->dir, strerror(errno));
        job_free(j);
        return NULL;
    }
    /* the files the case names, kept before the job is accepted, then its meshes read from
     * there (as a restarted sphd or a runner reads them) */
    static const sphd_inputs none = {0};
    char files[SPHD_PATH_MAX + 16];
    if (sphd_inputs_write(j->dir, case_json, in ? in : &none, e) != 0) {
        sphd_inputs_remove(j->dir, case_json);
        job_free(j);
        return NULL;
    }
    if (sphd_inputs_dir(j->dir, files, sizeof files) != 0 ||
        sph_case_load_files(j->c, files, NULL, &err) != 0) {
        sphd_err_set(e, SPHD_E_INVALID_CASE, err.path, "%s", err.message);
        sphd_inputs_remove(j->dir, case_json);
        rmdir(j->dir); /* when nothing else is there */
        job_free(j);
        return NULL;
    }
    if (write_json(j->dir, "case.json", case_json) != 0) {
        sphd_err_set(e, SPHD_E_INTERNAL, NULL, "cannot write %s/case.json", j->dir);
        sphd_inputs_remove(j->dir, case_json);
        job_free(j);
        return NULL;
    }
    j->case_json = json_incref(case_json);
    if (sweep) {
        snprintf(j->sweep, sizeof j->sweep, "%s", sweep);
        j->params = json_incref(params);
    }
    j->resources = json_incref(resources);
    const char *ex = json_string_value(json_object_get(resources, "executor"));
    j->slurm = ex ? strcmp(ex, "slurm") == 0 : d->opts.executor_slurm;
    j->run_until = INFINITY;
    j->worker = -1;
    j->step_until = INFINITY;
    j->eta = NAN;
    j->submitted = sphd_now();
    if (sph_case_is_sim(j->c))
        j->progress = json_pack("{s:f, s:f, s:i}", "t", 0.0, "t_end", j->c->sim.t_end, "step", 0);
    else
        j->progress = json_pack("{s:i}", "step", 0);
    j->state = start ? SPHD_JOB_QUEUED : SPHD_JOB_PAUSED;
    j->started = start;
    /* append: the scheduler runs jobs in submission order */
    sphd_job **pp = &d->jobs;
    while (*pp)
        pp = &(*pp)->next;
    *pp = j;
    d->njobs_active++;
    sphd_publish(d, j, "log",
                 json_pack("{s:s, s:s}", "level", "info", "message",
                           start ? "submitted" : "submitted, not started"));
    for (int k = 0; sph_case_is_sim(j->c) && k < j->c->sim.ngeometry; k++) {
        char note[256];
        int warn = 0;
        if (sph_case_mesh_note(j->c, k, note, sizeof note, &warn) == 0)
            sphd_publish(
                d, j, "log",
                json_pack("{s:s, s:s}", "level", warn ? "warning" : "info", "message", note));
    }
    sphd_job_set_state(d, j, j->state, NULL);
    sphd_log("job %s submitted (%s, %s)", j->id, sph_method_name(j->c->method),
             sphd_job_state_name(j->state));
    prune(d);
    return j;
}

static int runnable(const sphd_job *j)
{
    if (j->worker != -1 || j->held || j->exec_readers > 0 || sphd_job_state_final(j->state))
        return 0;
    return j->state == SPHD_JOB_QUEUED ||
           (j->state == SPHD_JOB_PAUSED && (j->step_n > 0 || isfinite(j->step_until)));
}

/* The run's targets (a pending `step`), taken from the job. */
static void take_targets(sphd_job *j, long *max_steps, double *until)
{
    *max_steps = 0;
    *until = INFINITY;
    j->stepping = 0;
    if (j->step_n > 0 || isfinite(j->step_until)) {
        *max_steps = j->step_n;
        *until = j->step_until;
        j->stepping = 1;
    }
    j->step_n = 0;
    j->step_until = INFINITY;
}

/* An sbatch out on the Slurm thread: the jobs it is for (task i of an array is jobs[i]). */
typedef struct sphd_submit {
    long token;
    int array;
    size_t n;
    char (*ids)[SPHD_JOB_ID_MAX];
    size_t *tasks; /* an array's task of each job (its index in the sweep) */
    struct sphd_submit *next;
} sphd_submit;

/* The job waits for sbatch (on the Slurm thread), then for its runner: running from now on. */
static void remote_submitting(sphd_daemon *d, sphd_job *j)
{
    sphd_job_touch(j);
    j->worker = SPHD_WORKER_REMOTE;
    j->slurm_id[0] = '\0';
    j->runner_seen = 0;
    j->gone_since = 0;
    j->started = 1;
    j->run_wall = 0;
    take_targets(j, &j->run_max_steps, &j->run_until);
    sphd_job_set_state(d, j, SPHD_JOB_RUNNING, NULL);
}

/* sbatch's --array for tasks (ascending): runs joined, "0-3,7,9-12". NULL when out of memory. */
static char *array_spec(const size_t *tasks, size_t n)
{
    char *s = malloc(n * 44 + 1);
    if (!s)
        return NULL;
    size_t len = 0;
    for (size_t i = 0; i < n;) {
        size_t k = i;
        while (k + 1 < n && tasks[k + 1] == tasks[k] + 1)
            k++;
        len += (size_t)sprintf(s + len, len ? ",%zu" : "%zu", tasks[i]);
        if (k > i)
            len += (size_t)sprintf(s + len, "-%zu", tasks[k]);
        i = k + 1;
    }
    return s;
}

/* Sends the sbatch of a script for jobs (one, or a sweep's array of n: task tasks[i] is
 * jobs[i]); 0 or -1 with why. */
static int send_submit(sphd_daemon *d, sphd_job **jobs, size_t n, const size_t *tasks,
                       const char *script, const char *name, const char *out, char *why,
                       size_t whyn)
{
    const int array = tasks != NULL;
    sphd_submit *s = calloc(1, sizeof *s);
    sphd_scmd cmd = {.kind = SPHD_S_SUBMIT,
                     .arg = strdup(script),
                     .name = strdup(name),
                     .out = strdup(out),
                     .array = array ? array_spec(tasks, n) : NULL,
                     .res = jobs[0]->resources ? json_deep_copy(jobs[0]->resources) : NULL};
    if (!s || !(s->ids = calloc(n, sizeof *s->ids)) || !(s->tasks = calloc(n, sizeof *s->tasks)) ||
        !cmd.arg || !cmd.name || !cmd.out || (array && !cmd.array)) {
        if (s) {
            free(s->ids);
            free(s->tasks);
        }
        free(s);
        free(cmd.arg);
        free(cmd.name);
        free(cmd.out);
        free(cmd.array);
        json_decref(cmd.res);
        snprintf(why, whyn, "out of memory");
        return -1;
    }
    if ((s->token = sphd_slurm_send(d, &cmd)) < 0) {
        free(s->ids);
        free(s->tasks);
        free(s);
        snprintf(why, whyn, "the Slurm thread does not answer");
        return -1;
    }
    s->array = array;
    s->n = n;
    for (size_t i = 0; i < n; i++) {
        snprintf(s->ids[i], sizeof s->ids[i], "%s", jobs[i]->id);
        s->tasks[i] = array ? tasks[i] : 0;
    }
    s->next = d->submits;
    d->submits = s;
    return 0;
}

static void fail_remote(sphd_daemon *d, sphd_job *j, const char *why)
{
    char reason[SPHD_REASON_MAX];
    snprintf(reason, sizeof reason, "slurm: %.480s", why);
    sphd_log("job %s: %s", j->id, reason);
    j->worker = -1;
    sphd_job_set_state(d, j, SPHD_JOB_FAILED, reason);
    sphd_jobs_answer_waiters(d, j);
}

/* A job on the Slurm executor: its batch script, and its sbatch sent to the Slurm thread. */
static void start_remote(sphd_daemon *d, sphd_job *j)
{
    char script[SPHD_PATH_MAX + 32], out[SPHD_PATH_MAX + 32], why[400];
    snprintf(script, sizeof script, "%s/slurm.sh", j->dir);
    snprintf(out, sizeof out, "%s/slurm-%%j.out", j->dir);
    remote_submitting(d, j);
    if (sphd_slurm_script(d, script, j->dir, NULL, why, sizeof why) != 0 ||
        send_submit(d, &j, 1, NULL, script, j->id, out, why, sizeof why) != 0)
        fail_remote(d, j, why);
}

int sphd_jobs_start_array(sphd_daemon *d, sphd_job **jobs, size_t n, const char *sweep, sphd_err *e)
{
    char script[SPHD_PATH_MAX + 128], out[SPHD_PATH_MAX + 128], why[400];
    snprintf(script, sizeof script, "%s/sweeps", d->opts.state_dir);
    sphd_mkdirs(script);
    snprintf(script, sizeof script, "%s/sweeps/%s.sh", d->opts.state_dir, sweep);
    snprintf(out, sizeof out, "%s/jobs/%s-%%a/slurm-%%A_%%a.out", d->opts.state_dir, sweep);
    /* the task of job SWEEP-K is K (the script runs the job of its task), ascending */
    size_t *tasks = calloc(n, sizeof *tasks);
    if (!tasks)
        return sphd_err_set(e, SPHD_E_INTERNAL, NULL, "out of memory");
    const size_t pre = strlen(sweep) + 1;
    for (size_t i = 0; i < n; i++) {
        jobs[i]->held = 0;
        remote_submitting(d, jobs[i]);
        tasks[i] = (size_t)strtoul(jobs[i]->id + pre, NULL, 10);
    }
    int rc = sphd_slurm_script(d, script, NULL, sweep, why, sizeof why);
    if (rc == 0)
        rc = send_submit(d, jobs, n, tasks, script, sweep, out, why, sizeof why);
    free(tasks);
    if (rc != 0) {
        for (size_t i = 0; i < n; i++)
            fail_remote(d, jobs[i], why);
        return sphd_err_set(e, SPHD_E_INTERNAL, NULL, "slurm: %s", why);
    }
    return 0;
}

void sphd_jobs_on_submitted(sphd_daemon *d, const sphd_sev *ev)
{
    sphd_submit **pp = &d->submits;
    while (*pp && (*pp)->token != ev->token)
        pp = &(*pp)->next;
    sphd_submit *s = *pp;
    if (!s)
        return;
    *pp = s->next;
    if (ev->rc == 0)
        sphd_log("%s %s: Slurm %sjob %s", s->array ? "sweep of" : "job", s->ids[0],
                 s->array ? "array " : "", ev->id);
    for (size_t i = 0; i < s->n; i++) {
        char sid[sizeof((sphd_job *)0)->slurm_id];
        if (s->array)
            snprintf(sid, sizeof sid, "%.23s_%zu", ev->id, s->tasks[i]);
        else
            snprintf(sid, sizeof sid, "%s", ev->id);
        sphd_job *j = sphd_job_find(d, s->ids[i]);
        /* (its runner may have said hello first and named the Slurm job already) */
        const int wanted = j && j->worker == SPHD_WORKER_REMOTE && j->state == SPHD_JOB_RUNNING &&
                           (!j->slurm_id[0] || strcmp(j->slurm_id, sid) == 0);
        if (!wanted) { /* paused or stopped meanwhile: its Slurm job goes too */
            if (ev->rc == 0) {
                sphd_scmd c = {.kind = SPHD_S_CANCEL, .arg = strdup(sid)};
                if (c.arg)
                    sphd_slurm_send(d, &c);
            }
            continue;
        }
        if (ev->rc != 0) {
            fail_remote(d, j, ev->why);
            continue;
        }
        snprintf(j->slurm_id, sizeof j->slurm_id, "%s", sid);
        sphd_job_touch(j);
        json_t *rec = json_pack("{s:f, s:s, s:s, s:I}", "t", sphd_now(), "state", "running",
                                "slurm_job", j->slurm_id, "seq", (json_int_t)j->seq);
        sph_error err;
        if (rec && sphd_journal_append(j->dir, rec, &err) != 0)
            sphd_log("job %s: %s", j->id, err.message);
        json_decref(rec);
        sphd_job_record(d, j, 0);
        char msg[128];
        snprintf(msg, sizeof msg, "submitted to Slurm (job %s): waiting for its runner",
                 j->slurm_id);
        sphd_publish(d, j, "log", json_pack("{s:s, s:s}", "level", "info", "message", msg));
    }
    free(s->ids);
    free(s->tasks);
    free(s);
}

int sphd_jobs_send(sphd_daemon *d, sphd_job *j, sphd_wcmd *cmd)
{
    if (j->worker >= 0)
        return sphd_worker_send(&d->workers[j->worker], cmd);
    if (j->worker == SPHD_WORKER_REMOTE && j->runner_seen && d->runners) {
        char runner[SPHD_JOB_ID_MAX + 64];
        snprintf(runner, sizeof runner, "%s@%s", j->id, j->slurm_id);
        return sphd_wire_send_cmd(d->runners, runner, cmd);
    }
    errno = ENOTCONN;
    return -1;
}

/* Runs j on at once on worker w, which has just ended a run of it to steer it: the job stays
 * running (no state event). 0, or -1 when the worker cannot be reached. */
static int rerun(sphd_daemon *d, sphd_worker *w, sphd_job *j)
{
    sphd_wcmd cmd = {.kind = SPHD_W_RUN, .job = j, .exec = j->exec, .until = INFINITY};
    if (sphd_worker_send(w, &cmd) != 0)
        return -1;
    j->worker = w->index;
    j->run_wall = 0;
    w->job = j;
    atomic_fetch_add(&d->busy, 1);
    return 0;
}

void sphd_jobs_schedule(sphd_daemon *d)
{
    if (d->stopping)
        return;
    for (sphd_job *j = d->jobs; j; j = j->next)
        if (j->slurm && runnable(j))
            start_remote(d, j);
    for (int i = 0; i < d->nworkers; i++) {
        sphd_worker *w = &d->workers[i];
        if (w->job)
            continue;
        sphd_job *j = d->jobs;
        while (j && (j->slurm || !runnable(j)))
            j = j->next;
        if (!j)
            return;
        sphd_wcmd cmd = {.kind = SPHD_W_RUN, .job = j, .exec = j->exec, .until = INFINITY};
        if (j->step_n > 0 || isfinite(j->step_until)) {
            cmd.max_steps = j->step_n;
            cmd.until = j->step_until;
            j->stepping = 1;
        } else {
            j->stepping = 0;
        }
        if (sphd_worker_send(w, &cmd) != 0) {
            sphd_log("cannot hand job %s to worker %d: %s", j->id, i, strerror(errno));
            return;
        }
        j->step_n = 0;
        j->step_until = INFINITY;
        sphd_job_touch(j);
        j->worker = i;
        j->started = 1;
        j->run_wall = 0;
        w->job = j;
        atomic_fetch_add(&d->busy, 1);
        sphd_job_set_state(d, j, SPHD_JOB_RUNNING, NULL);
    }
}

void sphd_jobs_answer_waiters(sphd_daemon *d, sphd_job *j)
{
    while (j->waiters) {
        sphd_pending *p = j->waiters;
        j->waiters = p->next;
        sphd_reply(d, p, sphd_job_status(j), NULL);
        sphd_pending_free(p);
    }
    /* particle queries that the worker will not answer any more */
    sphd_pending **pp = &d->particle_waits;
    while (*pp) {
        sphd_pending *p = *pp;
        if (strcmp(p->job, j->id) != 0) {
            pp = &p->next;
            continue;
        }
        *pp = p->next;
        sphd_err e;
        sphd_err_set(&e, SPHD_E_BUSY, NULL, "job %s stopped running meanwhile; ask again", j->id);
        sphd_reply(d, p, NULL, &e);
        sphd_pending_free(p);
    }
}

void sphd_jobs_on_worker(sphd_daemon *d, sphd_worker *w, sphd_wev *ev)
{
    sphd_job *j = ev->job;
    switch (ev->kind) {
    case SPHD_WEV_EVENT:
        if (strcmp(ev->type, "diag") == 0) {
            json_decref(j->diag);
            j->diag = json_incref(ev->body);
        } else if (strcmp(ev->type, "result") == 0) {
            json_decref(j->result);
            j->result = json_incref(ev->body);
            write_json(j->dir, "result.json", ev->body);
        } else if (strcmp(ev->type, "trigger") == 0) {
            json_t *jr =
                json_pack("{s:f, s:O, s:O, s:O, s:I}", "t", sphd_now(), "trigger",
                          json_object_get(ev->body, "when"), "do", json_object_get(ev->body, "do"),
                          "step", json_object_get(ev->body, "step"), "seq", (json_int_t)j->seq);
            sph_error jerr;
            if (jr && sphd_journal_append(j->dir, jr, &jerr) != 0)
                sphd_log("job %s: %s", j->id, jerr.message);
            json_decref(jr);
        }
        sphd_publish(d, j, ev->type, ev->body);
        return;
    case SPHD_WEV_PROGRESS:
        sphd_job_touch(j);
        json_decref(j->progress);
        j->progress = ev->body;
        j->steps_per_s = ev->steps_per_s;
        j->eta = ev->eta;
        j->run_wall = ev->wall;
        return;
    case SPHD_WEV_PARTICLES: {
        /* the worker encoded the whole reply: the loop only sends it */
        sphd_pending *p = sphd_pending_take(&d->particle_waits, ev->token);
        if (p)
            sphd_reply_text(d, p, ev->text);
        else
            free(ev->text);
        sphd_pending_free(p);
        return;
    }
    case SPHD_WEV_END:
        break;
    }
    /* The run ended: the worker gave the executor back (the one it created on a first run);
     * a runner keeps none (it wrote a checkpoint if the job can go on). */
    sphd_job_touch(j);
    if (w) {
        if (!j->exec)
            j->exec = ev->exec;
        w->job = NULL;
        atomic_fetch_sub(&d->busy, 1);
    } else {
        j->resume = 1;
        j->runner_seen = 0;
    }
    j->worker = -1;
    j->wall += ev->wall;
    j->run_wall = 0;
    j->steps_per_s = 0;
    j->eta = NAN;
    const int stepping = j->stepping;
    j->stepping = 0;
    /* a change waiting for this boundary: made now, while no worker holds the executor */
    if (j->steer_set) {
        if (ev->end == SPHD_END_PAUSED || ev->end == SPHD_END_TARGET || ev->end == SPHD_END_STEER) {
            sphd_err se;
            sphd_job_steer_apply(d, j, &se); /* a refusal is in steer_error */
        } else {
            snprintf(j->steer_error, sizeof j->steer_error,
                     "the job ended (%s) before the change took effect",
                     ev->end == SPHD_END_DONE     ? "done"
                     : ev->end == SPHD_END_FAILED ? "failed"
                                                  : "stopped");
            sphd_job_steer_drop(j);
        }
    }
    switch (ev->end) {
    case SPHD_END_STEER:
        if (j->stop_requested) {
            sphd_job_set_state(d, j, SPHD_JOB_STOPPED, NULL);
        } else if (d->stopping || j->pause_requested) {
            sphd_job_set_state(d, j, SPHD_JOB_PAUSED, NULL);
            if (d->stopping)
                sphd_job_record(d, j, 1);
        } else if (!w || rerun(d, w, j) != 0) {
            sphd_job_set_state(d, j, SPHD_JOB_QUEUED, NULL);
        }
        break;
    case SPHD_END_DONE:
        sphd_job_set_state(d, j, SPHD_JOB_DONE, NULL);
        break;
    case SPHD_END_FAILED:
        sphd_log("job %s failed: %s", j->id, ev->reason);
        sphd_job_set_state(d, j, SPHD_JOB_FAILED, ev->reason);
        break;
    case SPHD_END_STOPPED: /* on request, or by a trigger (its reason) */
        sphd_job_set_state(d, j, SPHD_JOB_STOPPED, ev->reason[0] ? ev->reason : NULL);
        break;
    case SPHD_END_PAUSED:
    case SPHD_END_TARGET:
        if (j->stop_requested) {
            sphd_job_set_state(d, j, SPHD_JOB_STOPPED, NULL);
        } else if (d->stopping || j->pause_requested || stepping || ev->reason[0]) {
            if (d->stopping)
                sphd_publish(d, j, "log",
                             json_pack("{s:s, s:s}", "level", "info", "message",
                                       "paused: sphd is shutting down; the job is recorded for "
                                       "a later resume"));
            /* a trigger's pause says which (ev->reason) */
            sphd_job_set_state(d, j, SPHD_JOB_PAUSED, ev->reason[0] ? ev->reason : NULL);
            if (d->stopping)
                sphd_job_record(d, j, 1);
        } else {
            /* a stale pause (resumed meanwhile): back in the queue */
            sphd_job_set_state(d, j, SPHD_JOB_QUEUED, NULL);
        }
        break;
    }
    j->pause_requested = j->stop_requested = j->requests_unsent = 0;
    sphd_jobs_answer_waiters(d, j);
    sphd_log("job %s %s after %.3f s", j->id, sphd_job_state_name(j->state), ev->wall);
}

void sphd_jobs_free(sphd_daemon *d)
{
    while (d->submits) {
        sphd_submit *s = d->submits;
        d->submits = s->next;
        free(s->ids);
        free(s->tasks);
        free(s);
    }
    while (d->jobs) {
        sphd_job *n = d->jobs->next;
        job_free(d->jobs);
        d->jobs = n;
    }
}

/* ---- recovery ---- */

typedef struct {
    json_t *last;    /* the latest state record (new ref) */
    long seq;        /* the largest seq in any record */
    int pause, stop; /* a pause or stop requested since it, not yet carried out */
} replay_ctx;

static void keep_last(void *ud, const json_t *rec)
{
    replay_ctx *r = ud;
    const json_t *seq = json_object_get(rec, "seq");
    if (json_is_integer(seq) && json_integer_value(seq) > r->seq)
        r->seq = (long)json_integer_value(seq);
    const json_t *pause = json_object_get(rec, "pause"), *stop = json_object_get(rec, "stop");
    /* a state change: what was pending is done with (a change's record, steering or a trigger,
     * leaves the state to the latest state record) */
    if (json_object_get(rec, "state")) {
        json_decref(r->last);
        r->last = json_deep_copy(rec);
        r->pause = json_is_true(pause);
        r->stop = json_is_true(stop);
    } else if (json_is_boolean(pause) || json_is_boolean(stop)) { /* `pause`, `resume`, `stop` */
        r->pause = json_is_true(pause);
        r->stop = json_is_true(stop);
    }
}

static json_t *load_json(const char *dir, const char *name)
{
    char path[SPHD_PATH_MAX + 64];
    snprintf(path, sizeof path, "%s/%s", dir, name);
    return json_load_file(path, 0, NULL);
}

static int state_from_name(const char *name)
{
    for (int s = SPHD_JOB_QUEUED; s <= SPHD_JOB_STOPPED; s++)
        if (name && strcmp(name, sphd_job_state_name((sphd_job_state)s)) == 0)
            return s;
    return -1;
}

static int by_submitted(const void *a, const void *b)
{
    const sphd_job *x = *(sphd_job *const *)a, *y = *(sphd_job *const *)b;
    return x->submitted < y->submitted   ? -1
           : x->submitted > y->submitted ? 1
                                         : strcmp(x->id, y->id);
}

/* One job directory: its case, and its state from the journal (job.json when the journal is
 * missing). A job that was running or queued is queued again and continues from its checkpoint;
 * a paused one stays paused; finished ones stay visible. */
static sphd_job *recover_one(sphd_daemon *d, const char *id)
{
    sphd_job *j = calloc(1, sizeof *j);
    if (!j || !(j->c = calloc(1, sizeof *j->c))) {
        free(j);
        return NULL;
    }
    if (snprintf(j->id, sizeof j->id, "%.*s", (int)sizeof j->id - 1, id) >= (int)sizeof j->id ||
        snprintf(j->dir, sizeof j->dir, "%.3000s/jobs/%.63s", d->opts.state_dir, id) >=
            (int)sizeof j->dir) {
        job_free(j);
        return NULL;
    }
    json_t *case_json = load_json(j->dir, "case.json");
    sph_error err;
    sph_error_clear(&err);
    char files[SPHD_PATH_MAX + 16];
    if (!case_json || sph_case_from_json(case_json, j->c, &err) ||
        (sphd_inputs_dir(j->dir, files, sizeof files) == 0 &&
         sph_case_load_files(j->c, files, NULL, &err) != 0)) {
        sphd_log("job %s: cannot take it up again: %s", id,
                 case_json ? err.message : "case.json is missing or unreadable");
        json_decref(case_json);
        job_free(j);
        return NULL;
    }
    j->case_json = case_json;
    replay_ctx r = {0};
    int torn = 0;
    sphd_journal_replay(j->dir, keep_last, &r, &torn, &err);
    json_t *rec = load_json(j->dir, "job.json");
    const json_t *src = r.last ? r.last : rec;
    int st = src ? state_from_name(json_string_value(json_object_get(src, "state"))) : -1;
    const char *reason = src ? json_string_value(json_object_get(src, "reason")) : NULL;
    /* every published seq was journaled first: the next event follows the last one */
    j->seq = (long)json_integer_value(json_object_get(rec, "seq"));
    if (r.seq > j->seq)
        j->seq = r.seq;
    if (j->seq < 0)
        j->seq = 0;
    j->seq_on_disk = j->seq;
    j->submitted = json_number_value(json_object_get(rec, "submitted"));
    j->slurm = json_is_string(json_object_get(rec, "executor")) &&
               strcmp(json_string_value(json_object_get(rec, "executor")), "slurm") == 0;
    if (json_is_object(json_object_get(rec, "resources")))
        j->resources = json_incref(json_object_get(rec, "resources"));
    j->retries = (int)json_integer_value(json_object_get(rec, "retries"));
    j->run_until = INFINITY;
    const char *sweep = json_string_value(json_object_get(rec, "sweep"));
    if (sweep && json_is_object(json_object_get(rec, "params"))) {
        snprintf(j->sweep, sizeof j->sweep, "%s", sweep);
        j->params = json_incref(json_object_get(rec, "params"));
    }
    j->wall = json_number_value(json_object_get(json_object_get(rec, "progress"), "wall"));
    json_t *prog = json_object_get(rec, "progress");
    j->worker = -1;
    j->step_until = INFINITY;
    j->eta = NAN;
    j->started = 1;
    if (sph_case_is_sim(j->c))
        j->progress =
            json_pack("{s:O?, s:f, s:I}", "t", json_object_get(prog, "t"), "t_end", j->c->sim.t_end,
                      "step", (json_int_t)json_integer_value(json_object_get(prog, "steps")));
    else
        j->progress = json_pack("{s:i}", "step", 0);
    char ck[SPHD_PATH_MAX + 32];
    snprintf(ck, sizeof ck, "%s/checkpoint", j->dir);
    char prev[SPHD_PATH_MAX + 32];
    snprintf(prev, sizeof prev, "%s/checkpoint.prev", j->dir);
    const int has_ckpt = access(ck, F_OK) == 0 || access(prev, F_OK) == 0;
    const char *sid = json_string_value(json_object_get(r.last, "slurm_job"));
    if (!sid)
        sid = json_string_value(json_object_get(rec, "slurm_job"));
    if (j->slurm && sid && sid[0] && st == SPHD_JOB_RUNNING) {
        /* its Slurm job may still run: its runner reconnects, or the poll finds it ended */
        snprintf(j->slurm_id, sizeof j->slurm_id, "%s", sid);
        j->state = SPHD_JOB_RUNNING;
        j->worker = SPHD_WORKER_REMOTE;
        j->resume = 1;
        /* a pause or stop its runner may not have carried out: told again when it is back
         * (or the job ends so when its Slurm job is found gone) */
        j->pause_requested = r.pause;
        j->stop_requested = r.stop;
        j->requests_unsent = r.pause || r.stop;
    } else if (st == SPHD_JOB_RUNNING && r.pause && !r.stop) {
        j->state = SPHD_JOB_PAUSED; /* it was pausing: paused, at its latest checkpoint */
        j->resume = has_ckpt;
    } else if (st < 0 || st == SPHD_JOB_RUNNING || st == SPHD_JOB_QUEUED) {
        j->state = SPHD_JOB_QUEUED;
        j->resume = has_ckpt;
    } else if (st == SPHD_JOB_PAUSED) {
        j->state = SPHD_JOB_PAUSED;
        j->resume = has_ckpt;
    } else {
        j->state = (sphd_job_state)st;
        snprintf(j->reason, sizeof j->reason, "%s", reason ? reason : "");
        j->result = load_json(j->dir, "result.json");
    }
    json_t *steering = json_incref(json_object_get(case_json, "steering"));
    json_object_del(case_json, "steering"); /* the job's identity: the case as submitted */
    if (json_array_size(steering) > 0) {    /* a steered job: its case as steered */
        j->steering = steering;
        j->case_now = json_deep_copy(case_json);
        size_t k, i;
        const json_t *sr, *a;
        json_array_foreach(steering, k, sr)
        {
            json_array_foreach(json_object_get(sr, "set"), i, a)
            {
                if (json_is_string(a) && j->case_now)
                    sph_json_apply_set(j->case_now, json_string_value(a), &err);
            }
        }
    } else {
        json_decref(steering);
    }
    if (torn)
        sphd_log("job %s: the last line of its journal was torn by a crash; ignored", id);
    json_decref(r.last);
    json_decref(rec);
    return j;
}

void sphd_jobs_recover(sphd_daemon *d)
{
    char dir[SPHD_PATH_MAX + 8];
    snprintf(dir, sizeof dir, "%s/jobs", d->opts.state_dir);
    DIR *dd = opendir(dir);
    if (!dd)
        return;
    sphd_job **found = NULL;
    size_t n = 0, cap = 0;
    struct dirent *e;
    while ((e = readdir(dd))) {
        if (!sphd_job_id_ok(e->d_name) || sphd_job_find(d, e->d_name))
            continue;
        sphd_job *j = recover_one(d, e->d_name);
        if (!j)
            continue;
        if (n == cap) {
            cap = cap ? 2 * cap : 16;
            sphd_job **f = realloc(found, cap * sizeof *f);
            if (!f) {
                job_free(j);
                break;
            }
            found = f;
        }
        found[n++] = j;
    }
    closedir(dd);
    if (n)
        qsort(found, n, sizeof *found, by_submitted);
    sphd_job **pp = &d->jobs;
    while (*pp)
        pp = &(*pp)->next;
    long resumed = 0, finished = 0;
    for (size_t i = 0; i < n; i++) {
        sphd_job *j = found[i];
        *pp = j;
        pp = &j->next;
        if (sphd_job_state_final(j->state)) {
            d->njobs_final++;
            finished++;
        } else {
            d->njobs_active++;
            resumed += j->resume;
            sphd_publish(d, j, "log",
                         json_pack("{s:s, s:s}", "level", "info", "message",
                                   j->resume ? "taken up after a restart; continues from its "
                                               "checkpoint"
                                             : "taken up after a restart"));
            sphd_job_set_state(d, j, j->state, NULL);
        }
    }
    free(found);
    if (n)
        sphd_log("took up %zu jobs from %s: %ld to continue from checkpoints, %ld finished", n, dir,
                 resumed, finished);
    prune(d);
}
