/*
 * Worker threads: each one runs one job at a time through its executor, in bounded slices, and
 * between slices reads the loop's requests (pause, stop, particle snapshots). Events go to the
 * loop thread over the worker's inproc PAIR; only the loop thread publishes them. Diagnostics are
 * thinned to at most opts.diag_rate per second so that a fast job never floods the stream.
 */
#include "sphd_daemon.h"
#include "sph_sim.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/prctl.h>
#include <zmq.h>
#ifdef _OPENMP
#include <omp.h>
#endif

#define SLICE_MIN_S      0.004 /* a slice shorter than this doubles the next one */
#define SLICE_MAX_S      0.016 /* a slice longer than this halves the next one */
#define PROGRESS_EVERY_S 0.05

typedef struct run_ctx {
    sphd_worker *w;
    sphd_link *link; /* to the loop */
    sphd_job *job;
    double min_diag_gap; /* seconds */
    double last_diag;    /* monotonic time of the last diag sent */
    json_t *held_diag;   /* newest diag not sent (thinned), new ref */
} run_ctx;

static int send_wev(sphd_link *l, sphd_wev *ev)
{
    return sphd_link_send(l, ev); /* takes ev's body and text */
}

static void send_event(run_ctx *r, const char *type, json_t *body)
{
    sphd_wev ev = {.kind = SPHD_WEV_EVENT, .job = r->job, .body = body};
    snprintf(ev.type, sizeof ev.type, "%s", type);
    if (send_wev(r->link, &ev) != 0 && !r->link->wire)
        sphd_log("worker %d: cannot send an event: %s", r->w->index, zmq_strerror(errno));
}

/* sphd_emit_fn: diag events are thinned, the others pass. */
static void on_emit(void *ud, const char *type, json_t *body)
{
    run_ctx *r = ud;
    if (strcmp(type, "diag") == 0) {
        const double now = sphd_mono();
        if (now - r->last_diag < r->min_diag_gap) {
            json_decref(r->held_diag);
            r->held_diag = body;
            return;
        }
        json_decref(r->held_diag);
        r->held_diag = NULL;
        r->last_diag = now;
    }
    send_event(r, type, body);
}

static void flush_diag(run_ctx *r)
{
    if (r->held_diag) {
        send_event(r, "diag", r->held_diag);
        r->held_diag = NULL;
        r->last_diag = sphd_mono();
    }
}

static long progress_step(const json_t *p)
{
    return (long)json_integer_value(json_object_get(p, "step"));
}

static double progress_t(const json_t *p, const char *key)
{
    json_t *v = json_object_get(p, key);
    return json_is_number(v) ? json_number_value(v) : NAN;
}

int sphd_method_available(sph_method m)
{
    return m == SPH_METHOD_KERNEL_STUDY || sph_sim_has_method(m);
}

static void answer_particles(run_ctx *r, sphd_exec *x, sphd_wcmd *cmd)
{
    sphd_wev ev = {.kind = SPHD_WEV_PARTICLES, .job = r->job, .token = cmd->token};
    ev.text = sphd_particles_reply(x, r->job->c, cmd->fields, cmd->max, cmd->status, cmd->id);
    json_decref(cmd->fields);
    send_wev(r->link, &ev);
}

/* A particle query that came after the run ended: the client asks again (the loop then reads the
 * paused job's executor on the files thread). */
static void answer_stale(sphd_link *sock, sphd_wcmd *cmd)
{
    sphd_err e;
    sphd_err_set(&e, SPHD_E_BAD_STATE, NULL,
                 "job %s stopped running while its particles were "
                 "asked for: ask again",
                 cmd->job->id);
    json_t *reply = sphd_reply_new(cmd->id, NULL, &e);
    json_decref(cmd->id);
    json_decref(cmd->status);
    json_decref(cmd->fields);
    sphd_wev ev = {.kind = SPHD_WEV_PARTICLES, .job = cmd->job, .token = cmd->token};
    ev.text = reply ? json_dumps(reply, JSON_COMPACT) : NULL;
    json_decref(reply);
    send_wev(sock, &ev);
}

static void set_omp_threads(sphd_worker *w)
{
#ifdef _OPENMP
    int busy = atomic_load(&w->d->busy);
    int n = w->d->opts.threads / (busy > 0 ? busy : 1);
    omp_set_num_threads(n > 0 ? n : 1);
#else
    (void)w;
#endif
}

/* Runs a job until it ends, is paused or stopped, or reaches its step target. */
void sphd_run_job(sphd_worker *w, sphd_link *sock, sphd_wcmd *cmd)
{
    run_ctx r = {.w = w, .link = sock, .job = cmd->job, .last_diag = -1e9};
    r.min_diag_gap = w->d->opts.diag_rate > 0 ? 1.0 / w->d->opts.diag_rate : 0;
    sphd_exec *x = cmd->exec;
    sphd_wev end = {.kind = SPHD_WEV_END, .job = cmd->job};
    const double t0 = sphd_mono();
    if (!x) {
        /* first run: prepare the job (generate and allocate the particles) */
        sph_error err;
        sph_error_clear(&err);
        if (cmd->job->resume) {
            sphd_continued how;
            x = sphd_exec_continue(cmd->job->c, cmd->job->dir, &how, &err);
            char msg[SPH_ERROR_TEXT_MAX + 160];
            if (how.from == SPHD_FROM_PREVIOUS)
                snprintf(msg, sizeof msg, "resumed from the previous checkpoint: %s",
                         how.why.message);
            else if (how.from == SPHD_FROM_LATEST)
                snprintf(msg, sizeof msg, "resumed from its latest checkpoint");
            else
                snprintf(msg, sizeof msg, "no checkpoint to resume from (%s): starting afresh%s",
                         how.why.message, how.kept ? SPHD_CKPT_KEPT_NOTE : "");
            sphd_log("job %s: %s", cmd->job->id, msg);
            send_event(&r, "log",
                       json_pack("{s:s, s:s}", "level",
                                 how.from == SPHD_FROM_LATEST ? "info" : "warning", "message",
                                 msg));
        } else {
            x = sphd_exec_new(cmd->job->c, cmd->job->dir, &err);
        }
        if (!x) {
            end.end = SPHD_END_FAILED;
            snprintf(end.reason, sizeof end.reason, "%s: %s%s%s", sph_error_code_name(err.code),
                     err.message, err.path[0] ? " at " : "", err.path);
            end.wall = sphd_mono() - t0;
            if (send_wev(sock, &end) != 0)
                sphd_log("worker %d: cannot report the end of a run: %s", w->index,
                         zmq_strerror(errno));
            return;
        }
    }
    if (!cmd->exec && w->d->opts.ckpt_interval > 0)
        sphd_exec_set_checkpoint_policy(x, w->d->opts.ckpt_interval, 1);
    end.exec = x;
    double last_progress = t0;
    json_t *p = sphd_exec_progress(x);
    const long step0 = progress_step(p);
    const double sim0 = progress_t(p, "t");
    json_decref(p);
    long done = 0, slice = 1;
    int ended = 0;
    while (!ended) {
        /* Requests from the loop, between slices. */
        sphd_wcmd in;
        int n;
        while (!ended && (n = sphd_link_recv(sock, &in, 0)) == 1) {
            if (in.kind == SPHD_W_PAUSE) {
                end.end = SPHD_END_PAUSED;
                ended = 1;
            } else if (in.kind == SPHD_W_STEER) {
                end.end = SPHD_END_STEER; /* no checkpoint: the loop writes one once steered */
                ended = 1;
            } else if (in.kind == SPHD_W_STOP || in.kind == SPHD_W_QUIT) {
                /* QUIT while running: a runner the daemon does not want (a stray second run) */
                end.end = SPHD_END_STOPPED;
                ended = 1;
            } else if (in.kind == SPHD_W_PARTICLES) {
                answer_particles(&r, x, &in);
            }
        }
        if (ended)
            break;
        long max = slice;
        if (cmd->max_steps > 0) {
            if (done >= cmd->max_steps) {
                end.end = SPHD_END_TARGET;
                break;
            }
            if (max > cmd->max_steps - done)
                max = cmd->max_steps - done;
        }
        set_omp_threads(w);
        sph_error err;
        sph_error_clear(&err);
        const double s0 = sphd_mono();
        sphd_exec_status st = sphd_exec_advance(x, max, cmd->until, on_emit, &r, &err);
        const double s1 = sphd_mono();
        p = sphd_exec_progress(x);
        const long step = progress_step(p);
        const long did = step - step0 - done;
        done = step - step0;
        if (s1 - s0 < SLICE_MIN_S && slice < (1L << 20))
            slice *= 2;
        else if (s1 - s0 > SLICE_MAX_S && slice > 1)
            slice /= 2;
        if (st == SPHD_EXEC_DONE) {
            end.end = SPHD_END_DONE;
            ended = 1;
        } else if (st == SPHD_EXEC_PAUSE || st == SPHD_EXEC_STOP) { /* a trigger's */
            end.end = st == SPHD_EXEC_PAUSE ? SPHD_END_PAUSED : SPHD_END_STOPPED;
            snprintf(end.reason, sizeof end.reason, "%s", sphd_exec_halt_reason(x));
            ended = 1;
        } else if (st == SPHD_EXEC_FAILED) {
            end.end = SPHD_END_FAILED;
            snprintf(end.reason, sizeof end.reason, "%s: %s%s%s", sph_error_code_name(err.code),
                     err.message, err.path[0] ? " at " : "", err.path);
            ended = 1;
        } else if (isfinite(cmd->until) && (did <= 0 || progress_t(p, "t") >= cmd->until)) {
            end.end = SPHD_END_TARGET; /* reached the time of a `step --until` */
            ended = 1;
        }
        const double wall = s1 - t0;
        double rate = wall > 0 ? done / wall : 0, eta = NAN;
        const double t = progress_t(p, "t"), t_end = progress_t(p, "t_end");
        if (wall > 0 && isfinite(t) && isfinite(sim0) && t > sim0 && isfinite(t_end))
            eta = (t_end - t) / ((t - sim0) / wall);
        if (!ended && s1 - last_progress >= PROGRESS_EVERY_S) {
            sphd_wev pe = {.kind = SPHD_WEV_PROGRESS,
                           .job = cmd->job,
                           .body = p,
                           .wall = wall,
                           .steps_per_s = rate,
                           .eta = eta};
            send_wev(sock, &pe);
            last_progress = s1;
        } else {
            json_decref(p);
        }
    }
    flush_diag(&r);
    if (end.end == SPHD_END_PAUSED || end.end == SPHD_END_TARGET) {
        /* a paused job (on request, at a step target, at shutdown) can be resumed exactly */
        sph_error err;
        sph_error_clear(&err);
        if (sphd_exec_checkpoint(x, &err) != 0)
            send_event(&r, "log",
                       json_pack("{s:s, s:s}", "level", "warning", "message", err.message));
    }
    end.wall = sphd_mono() - t0;
    /* the final progress, whatever ended the run */
    json_t *fp = sphd_exec_progress(x);
    sphd_wev pe = {.kind = SPHD_WEV_PROGRESS, .job = cmd->job, .body = fp, .wall = end.wall};
    if (fp)
        send_wev(sock, &pe);
    if (sock->wire)
        end.exec = NULL; /* a runner's executor ends with it */
    if (send_wev(sock, &end) != 0)
        sphd_log("worker %d: cannot report the end of a run: %s", w->index, zmq_strerror(errno));
    if (sock->wire)
        sphd_exec_free(x);
}

static void *worker_main(void *arg)
{
    sphd_worker *w = arg;
    char ep[64];
    snprintf(ep, sizeof ep, "sphd-worker-%d", w->index);
    prctl(PR_SET_NAME, ep, 0, 0, 0); /* the solver threads by name in top -H and /proc */
    /* below the socket loop, so that requests preempt the solver at once (sphd_sched.c); the
     * OpenMP threads this thread starts inherit it */
    if (sphd_sched_lower_self(w->d->opts.worker_nice) != 0)
        sphd_log("worker %d: cannot lower its priority: %s", w->index, strerror(errno));
    snprintf(ep, sizeof ep, "inproc://sphd-worker-%d", w->index);
    void *pair = sphd_pair_open(w->d->ctx, ep, 0);
    if (!pair)
        return NULL;
    sphd_link link = {.sock = pair}, *sock = &link;
    for (;;) {
        sphd_wcmd cmd;
        int n = sphd_link_recv(sock, &cmd, 1);
        if (n < 0)
            break; /* ETERM: the context is going away */
        if (n == 0)
            continue;
        if (cmd.kind == SPHD_W_QUIT)
            break;
        if (cmd.kind == SPHD_W_RUN)
            sphd_run_job(w, sock, &cmd);
        else if (cmd.kind == SPHD_W_PARTICLES)
            answer_stale(sock, &cmd); /* the run ended before it was read */
        /* stale PAUSE/STOP/STEER (the run ended first) are dropped */
    }
    zmq_close(pair);
    return NULL;
}

int sphd_worker_send(sphd_worker *w, const sphd_wcmd *cmd)
{
    return sphd_pair_send(w->pair, cmd, sizeof *cmd);
}

int sphd_workers_start(sphd_daemon *d)
{
    d->workers = calloc((size_t)d->opts.threads, sizeof *d->workers);
    if (!d->workers)
        return -1;
    d->nworkers = d->opts.threads;
    for (int i = 0; i < d->nworkers; i++) {
        sphd_worker *w = &d->workers[i];
        w->d = d;
        w->index = i;
        char ep[64];
        snprintf(ep, sizeof ep, "inproc://sphd-worker-%d", i);
        w->pair = sphd_pair_open(d->ctx, ep, 1);
        if (!w->pair)
            return -1;
        int rc = pthread_create(&w->thread, NULL, worker_main, w);
        if (rc != 0) {
            sphd_log("cannot start worker thread %d: %s", i, strerror(rc));
            return -1;
        }
        w->started = 1;
    }
    return 0;
}

void sphd_workers_stop(sphd_daemon *d)
{
    for (int i = 0; i < d->nworkers; i++) {
        sphd_worker *w = &d->workers[i];
        if (w->started) {
            sphd_wcmd q = {.kind = SPHD_W_QUIT};
            if (sphd_worker_send(w, &q) != 0)
                sphd_log("worker %d: cannot send quit: %s", i, zmq_strerror(errno));
        }
    }
    for (int i = 0; i < d->nworkers; i++) {
        sphd_worker *w = &d->workers[i];
        if (w->started)
            pthread_join(w->thread, NULL);
        if (w->pair)
            zmq_close(w->pair);
    }
    free(d->workers);
    d->workers = NULL;
    d->nworkers = 0;
}
