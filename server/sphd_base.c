/*
 * The bottom floor of the daemon: what every other floor shares and nothing here calls up.
 * Errors and replies, the job states' names, the event stream, requests kept for a later reply,
 * the inproc PAIRs between threads, the log and the clocks. The types are in sphd_daemon.h.
 */
#include "sphd_daemon.h"
#include "sphd_journal.h"

#include "sph_events.h"

#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>
#include <zmq.h>

static const char *const errcode_names[SPHD_E_COUNT] = {
    [SPHD_E_BAD_REQUEST] = "bad_request",   [SPHD_E_UNKNOWN_OP] = "unknown_op",
    [SPHD_E_INVALID_CASE] = "invalid_case", [SPHD_E_NOT_FOUND] = "not_found",
    [SPHD_E_CONFLICT] = "conflict",         [SPHD_E_BAD_STATE] = "bad_state",
    [SPHD_E_TOO_LARGE] = "too_large",       [SPHD_E_BUSY] = "busy",
    [SPHD_E_INTERNAL] = "internal",
};

const char *sphd_errcode_name(sphd_errcode c)
{
    return (unsigned)c < SPHD_E_COUNT ? errcode_names[c] : "internal";
}

int sphd_err_set(sphd_err *e, sphd_errcode code, const char *path, const char *fmt, ...)
{
    e->code = code;
    snprintf(e->path, sizeof e->path, "%s", path ? path : "");
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(e->message, sizeof e->message, fmt, ap);
    va_end(ap);
    return -1;
}

json_t *sphd_reply_new(json_t *id, json_t *result, const sphd_err *e)
{
    json_t *r = json_pack("{s:i, s:O}", "v", SPHD_PROTOCOL_VERSION, "id", id ? id : json_null());
    if (!r) {
        json_decref(result);
        return NULL;
    }
    if (!e) {
        json_object_set_new(r, "ok", json_true());
        json_object_set_new(r, "result", result ? result : json_object());
        return r;
    }
    json_decref(result);
    json_t *err =
        json_pack("{s:s, s:s}", "code", sphd_errcode_name(e->code), "message", e->message);
    if (err && e->path[0])
        json_object_set_new(err, "path", json_string(e->path));
    json_object_set_new(r, "ok", json_false());
    json_object_set_new(r, "error", err);
    return r;
}

/* ---- job states ---- */

static const char *const state_names[] = {
    [SPHD_JOB_QUEUED] = "queued", [SPHD_JOB_RUNNING] = "running", [SPHD_JOB_PAUSED] = "paused",
    [SPHD_JOB_DONE] = "done",     [SPHD_JOB_FAILED] = "failed",   [SPHD_JOB_STOPPED] = "stopped",
};

const char *sphd_job_state_name(sphd_job_state s)
{
    return (unsigned)s < sizeof state_names / sizeof state_names[0] ? state_names[s] : "unknown";
}

int sphd_job_state_final(sphd_job_state s)
{
    return s == SPHD_JOB_DONE || s == SPHD_JOB_FAILED || s == SPHD_JOB_STOPPED;
}

void sphd_job_touch(sphd_job *j)
{
    free(j->query_text);
    j->query_text = NULL;
    free(j->status_text);
    j->status_text = NULL;
}

/* ---- clocks, log, kept requests, PAIRs, replies and events ---- */

double sphd_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_REALTIME, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

double sphd_mono(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

void sphd_log(const char *fmt, ...)
{
    char buf[1024];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(buf, sizeof buf, fmt, ap);
    va_end(ap);
    time_t t = time(NULL);
    struct tm tm;
    char stamp[32];
    strftime(stamp, sizeof stamp, "%Y-%m-%dT%H:%M:%SZ", gmtime_r(&t, &tm));
    fprintf(stderr, "%s sphd: %s\n", stamp, buf);
}

sphd_pending *sphd_pending_copy(const sphd_pending *p)
{
    sphd_pending *c = calloc(1, sizeof *c);
    if (!c)
        return NULL;
    c->nframes = p->nframes;
    c->op = p->op;
    c->token = p->token;
    snprintf(c->job, sizeof c->job, "%s", p->job);
    c->id = json_incref(p->id ? p->id : json_null());
    for (int i = 0; i < p->nframes; i++) {
        c->len[i] = p->len[i];
        c->frame[i] = malloc(p->len[i] ? p->len[i] : 1);
        if (!c->frame[i]) {
            sphd_pending_free(c);
            return NULL;
        }
        memcpy(c->frame[i], p->frame[i], p->len[i]);
    }
    return c;
}

void sphd_pending_free(sphd_pending *p)
{
    if (!p)
        return;
    for (int i = 0; i < p->nframes; i++)
        free(p->frame[i]);
    json_decref(p->id);
    free(p);
}

sphd_pending *sphd_pending_take(sphd_pending **list, long token)
{
    for (sphd_pending **pp = list; *pp; pp = &(*pp)->next) {
        if ((*pp)->token == token) {
            sphd_pending *p = *pp;
            *pp = p->next;
            return p;
        }
    }
    return NULL;
}

void *sphd_pair_open(void *ctx, const char *endpoint, int bind)
{
    void *s = zmq_socket(ctx, ZMQ_PAIR);
    int zero = 0;
    if (!s || zmq_setsockopt(s, ZMQ_LINGER, &zero, sizeof zero) != 0 ||
        (bind ? zmq_bind(s, endpoint) : zmq_connect(s, endpoint)) != 0) {
        sphd_log("cannot %s %s: %s", bind ? "bind" : "connect", endpoint, zmq_strerror(errno));
        if (s)
            zmq_close(s);
        return NULL;
    }
    return s;
}

int sphd_pair_send(void *sock, const void *msg, size_t len)
{
    for (;;) {
        if (zmq_send(sock, msg, len, 0) == (int)len)
            return 0;
        if (errno != EINTR)
            return -1;
    }
}

static void free_text(void *data, void *hint)
{
    (void)hint;
    free(data);
}

void sphd_reply_text(sphd_daemon *d, const sphd_pending *to, char *text)
{
    if (!text) {
        sphd_log("cannot encode a reply (out of memory)");
        return;
    }
    for (int i = 0; i < to->nframes; i++) {
        if (zmq_send(d->router, to->frame[i], to->len[i], ZMQ_SNDMORE | ZMQ_DONTWAIT) < 0) {
            /* EHOSTUNREACH: the client went away (ROUTER_MANDATORY); EAGAIN: it does not read */
            if (i == 0) {
                sphd_log("reply dropped: %s", zmq_strerror(errno));
                free(text);
                return;
            }
        }
    }
    /* the text is handed to ZeroMQ, not copied: a reply of a million particles costs the loop
     * nothing */
    zmq_msg_t m;
    if (zmq_msg_init_data(&m, text, strlen(text), free_text, NULL) != 0) {
        free(text);
        return;
    }
    if (zmq_msg_send(&m, d->router, ZMQ_DONTWAIT) < 0) {
        sphd_log("reply dropped: %s", zmq_strerror(errno));
        zmq_msg_close(&m);
    }
}

static void send_reply_json(sphd_daemon *d, const sphd_pending *to, json_t *reply)
{
    char *text = reply ? json_dumps(reply, JSON_COMPACT | JSON_REAL_PRECISION(12)) : NULL;
    json_decref(reply);
    sphd_reply_text(d, to, text);
}

void sphd_reply(sphd_daemon *d, const sphd_pending *to, json_t *result, const sphd_err *e)
{
    send_reply_json(d, to, sphd_reply_new(to->id, result, e));
}

void sphd_publish(sphd_daemon *d, sphd_job *j, const char *type, json_t *body)
{
    sphd_job_touch(j); /* its seq changes */
    ++j->seq;
    if (j->seq > j->seq_on_disk) {
        /* the seq in the journal before anyone sees it: a restarted sphd (kill -9 included)
         * goes on from it, with no gap and no repeat (a state change wrote it already) */
        json_t *rec = json_pack("{s:I}", "seq", (json_int_t)j->seq);
        sph_error err;
        if (rec && sphd_journal_note(j->dir, rec, &err) == 0)
            j->seq_on_disk = j->seq;
        else if (rec && !j->seq_unwritten++) /* said once per job */
            sphd_log("job %s: %s", j->id, err.message);
        json_decref(rec);
    }
    json_t *ev = sph_event_new(j->id, j->seq, type);
    if (ev && body)
        json_object_update_missing(ev, body); /* job, seq and type are ours */
    json_decref(body);
    char *text = ev ? json_dumps(ev, JSON_COMPACT | JSON_REAL_PRECISION(12)) : NULL;
    json_decref(ev);
    if (!text) {
        sphd_log("job %s: event %ld lost (out of memory)", j->id, j->seq);
        return;
    }
    /* PUB never blocks: past the HWM a slow subscriber loses events (and sees the gap in seq). */
    if (zmq_send(d->pub, j->id, strlen(j->id), ZMQ_SNDMORE | ZMQ_DONTWAIT) < 0 ||
        zmq_send(d->pub, text, strlen(text), ZMQ_DONTWAIT) < 0)
        sphd_log("job %s: event %ld not published: %s", j->id, j->seq, zmq_strerror(errno));
    free(text);
}
