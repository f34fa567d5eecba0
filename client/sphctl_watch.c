/*
 * sphctl watch: the Clone pattern. Subscribe to the job's topic first, then ask for a snapshot
 * (query); events up to the snapshot's seq are already in it, later ones update it. A jump in seq
 * is reported as a gap. On a TTY a live progress line, otherwise JSON Lines. The stream, a job's
 * view (its status updated by its events) and its progress text serve sweep --watch too.
 */
#include "sphctl.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/ioctl.h>
#include <time.h>
#include <unistd.h>
#include <zmq.h>

typedef struct watch {
    sphctl *c;
    sphctl_view v;
    int tty;
    double last_draw;
    int drawn;
} watch;

int sphctl_watch_tty(const sphctl *c)
{
    return !c->json && isatty(STDOUT_FILENO);
}

void sphctl_term_size(int *rows, int *cols)
{
    struct winsize ws;
    const int ok = ioctl(STDERR_FILENO, TIOCGWINSZ, &ws) == 0;
    *rows = ok ? ws.ws_row : 0;
    *cols = ok ? ws.ws_col : 0;
}

void sphctl_fit_line(char *line, int cols)
{
    if (cols > 1 && strlen(line) >= (size_t)cols)
        line[cols - 1] = '\0';
}

int sphctl_final_state(const char *s)
{
    return strcmp(s, "done") == 0 || strcmp(s, "failed") == 0 || strcmp(s, "stopped") == 0;
}

int sphctl_state_exit(const char *s)
{
    return strcmp(s, "done") == 0 ? SPHCTL_EX_OK : SPHCTL_EX_FAILED;
}

void sphctl_view_init(sphctl_view *v, const char *job)
{
    memset(v, 0, sizeof *v);
    snprintf(v->job, sizeof v->job, "%s", job);
    v->t = v->t_end = v->rate = v->eta = NAN;
}

void sphctl_view_free(sphctl_view *v)
{
    json_decref(v->diag);
    v->diag = NULL;
}

static void set_state(sphctl_view *v, const json_t *o)
{
    const char *s = json_string_value(json_object_get(o, "state"));
    const char *reason = json_string_value(json_object_get(o, "reason"));
    snprintf(v->state, sizeof v->state, "%s", s ? s : "?");
    snprintf(v->reason, sizeof v->reason, "%s", reason ? reason : "");
}

void sphctl_view_status(sphctl_view *v, const json_t *s)
{
    set_state(v, s);
    v->seq = (long)json_integer_value(json_object_get(s, "seq"));
    json_t *p = json_object_get(s, "progress");
    v->t = sphctl_num(p, "t");
    v->t_end = sphctl_num(p, "t_end");
    v->steps = (long)json_integer_value(json_object_get(p, "steps"));
    v->rate = sphctl_num(p, "steps_per_s");
    v->eta = sphctl_num(p, "eta");
    json_t *d = json_object_get(s, "diag");
    if (json_is_object(d)) {
        json_decref(v->diag);
        v->diag = json_incref(d);
    }
}

void sphctl_view_event(sphctl_view *v, json_t *ev)
{
    const char *type = json_string_value(json_object_get(ev, "type"));
    type = type ? type : "";
    v->seq = (long)json_integer_value(json_object_get(ev, "seq"));
    if (strcmp(type, "state") == 0) {
        set_state(v, ev);
    } else if (strcmp(type, "diag") == 0) {
        json_decref(v->diag);
        v->diag = json_incref(ev);
        double now = sphctl_mono(), t = sphctl_num(ev, "t");
        long step = (long)json_integer_value(json_object_get(ev, "step"));
        if (v->last_diag_wall > 0 && now > v->last_diag_wall && step > v->last_diag_step) {
            v->rate = (double)(step - v->last_diag_step) / (now - v->last_diag_wall);
            if (isfinite(t) && isfinite(v->t_end) && t > v->last_diag_t)
                v->eta = (v->t_end - t) / ((t - v->last_diag_t) / (now - v->last_diag_wall));
        }
        v->last_diag_wall = now;
        v->last_diag_step = step;
        v->last_diag_t = t;
        v->steps = step;
        if (isfinite(t))
            v->t = t;
    }
}

void sphctl_view_progress(const sphctl_view *v, int diag, char *line, size_t size)
{
    int n = 0;
    line[0] = '\0';
    if (isfinite(v->t) && isfinite(v->t_end) && v->t_end > 0) {
        double f = v->t / v->t_end;
        f = f < 0 ? 0 : f > 1 ? 1 : f;
        char bar[21];
        int k = (int)(f * 20 + 0.5);
        for (int i = 0; i < 20; i++)
            bar[i] = i < k ? '#' : '.';
        bar[20] = '\0';
        n += snprintf(line + n, size - (size_t)n, " [%s] %5.1f%% t %.4g/%.4g s", bar, 100 * f, v->t,
                      v->t_end);
    }
    n += snprintf(line + n, size - (size_t)n, " step %ld", v->steps);
    if (isfinite(v->rate) && v->rate > 0)
        n += snprintf(line + n, size - (size_t)n, " %.0f steps/s", v->rate);
    if (isfinite(v->eta) && strcmp(v->state, "running") == 0) {
        char eta[32];
        sphctl_fmt_duration(v->eta, eta, sizeof eta);
        n += snprintf(line + n, size - (size_t)n, " ETA %s", eta);
    }
    static const char *const keys[] = {"front_x", "height_left", "penetration", "runup",
                                       "ekin",    "vmax",        NULL};
    for (int i = 0; diag && keys[i] && n < (int)size - 40; i++) {
        double x = sphctl_num(v->diag, keys[i]);
        if (isfinite(x))
            n += snprintf(line + n, size - (size_t)n, " %s %.4g", keys[i], x);
    }
}

static void draw(watch *w, int force)
{
    if (!w->tty)
        return;
    double now = sphctl_mono();
    if (!force && now - w->last_draw < 0.1)
        return;
    w->last_draw = now;
    char line[512];
    int n = snprintf(line, sizeof line, "%s %-8s", w->v.job, w->v.state);
    sphctl_view_progress(&w->v, 1, line + n, sizeof line - (size_t)n);
    /* one line: cut to the terminal's width, or a redraw would wrap and scroll */
    int rows, cols;
    sphctl_term_size(&rows, &cols);
    sphctl_fit_line(line, cols);
    fprintf(stderr, "\r%s\033[K", line);
    fflush(stderr);
    w->drawn = 1;
}

static void on_event(watch *w, json_t *ev)
{
    const char *type = json_string_value(json_object_get(ev, "type"));
    type = type ? type : "";
    sphctl_view_event(&w->v, ev);
    if (!w->tty)
        sphctl_print_json(ev, 1);
    if (strcmp(type, "state") == 0) {
        if (w->tty) {
            const char *reason = json_string_value(json_object_get(ev, "reason"));
            draw(w, 1);
            if (reason)
                fprintf(stderr, "\n%s: %s", w->v.job, reason);
        }
    } else if (strcmp(type, "diag") == 0) {
        draw(w, 0);
    } else if (strcmp(type, "log") == 0 && w->tty) {
        const char *m = json_string_value(json_object_get(ev, "message"));
        fprintf(stderr, "%s%s: %s\n", w->drawn ? "\r\033[K" : "", w->v.job, m ? m : "");
        draw(w, 1);
    } else if (strcmp(type, "output") == 0 && w->tty) {
        const char *f = json_string_value(json_object_get(ev, "file"));
        fprintf(stderr, "%s%s: wrote %s\n", w->drawn ? "\r\033[K" : "", w->v.job, f ? f : "?");
        draw(w, 1);
    }
}

void sphctl_report_gap(const char *job, long from, long to, int clear, int json_line)
{
    fprintf(stderr, "%ssphctl: %s: missed events %ld..%ld (the stream dropped them)\n",
            clear ? "\r\033[K" : "", job, from, to);
    if (json_line) {
        json_t *g = json_pack("{s:s, s:s, s:I, s:I}", "job", job, "type", "gap", "from",
                              (json_int_t)from, "to", (json_int_t)to);
        sphctl_print_json(g, 1);
        json_decref(g);
    }
}

static void report_gap(watch *w, long from, long to)
{
    sphctl_report_gap(w->v.job, from, to, w->tty && w->drawn, !w->tty);
}

/* The stream endpoint of hello, with a wildcard host replaced by the control endpoint's. */
static int stream_endpoint(sphctl *c, char *out, size_t n)
{
    json_t *hello;
    int rc = sphctl_request(c, "hello", NULL, &hello, NULL, 0);
    if (rc)
        return rc;
    const char *s = json_string_value(json_object_get(hello, "stream"));
    if (!s) {
        json_decref(hello);
        fprintf(stderr, "sphctl: sphd's hello names no stream endpoint\n");
        return SPHCTL_EX_SOFTWARE;
    }
    const char *star = strstr(s, "://*:");
    const char *any = strstr(s, "://0.0.0.0:");
    if ((star || any) && strncmp(c->endpoint, "tcp://", 6) == 0) {
        char host[256];
        snprintf(host, sizeof host, "%s", c->endpoint + 6);
        char *colon = strrchr(host, ':');
        if (colon)
            *colon = '\0';
        snprintf(out, n, "tcp://%s%s", host, strrchr(s, ':'));
    } else {
        snprintf(out, n, "%s", s);
    }
    json_decref(hello);
    return 0;
}

static int snapshot(watch *w)
{
    json_t *r;
    int rc = sphctl_request(w->c, "query", json_pack("{s:s}", "job", w->v.job), &r, NULL, 0);
    if (rc)
        return rc;
    sphctl_view_status(&w->v, r);
    if (!w->tty) {
        json_t *snap = json_pack("{s:s, s:I, s:s, s:O}", "job", w->v.job, "seq",
                                 (json_int_t)w->v.seq, "type", "snapshot", "status", r);
        sphctl_print_json(snap, 1);
        json_decref(snap);
    }
    json_decref(r);
    draw(w, 1);
    return 0;
}

static int finish(watch *w)
{
    if (w->tty) {
        draw(w, 1);
        fputc('\n', stderr);
    }
    return sphctl_state_exit(w->v.state);
}

int sphctl_stream_open(sphctl *c, const char *topic, sphctl_stream *st)
{
    memset(st, 0, sizeof *st);
    snprintf(st->topic, sizeof st->topic, "%s", topic);
    int rc = stream_endpoint(c, st->ep, sizeof st->ep);
    if (rc)
        return rc;
    st->sub = zmq_socket(c->ctx, ZMQ_SUB);
    int zero = 0;
    if (!st->sub || zmq_setsockopt(st->sub, ZMQ_LINGER, &zero, sizeof zero) != 0 ||
        sphctl_secure(c, st->sub) != 0 || !(st->mon = sphctl_monitor(c, st->sub, "stream")) ||
        zmq_setsockopt(st->sub, ZMQ_SUBSCRIBE, topic, strlen(topic)) != 0 ||
        zmq_connect(st->sub, st->ep) != 0) {
        fprintf(stderr, "sphctl: cannot subscribe to %s: %s\n", st->ep, zmq_strerror(errno));
        sphctl_stream_close(st);
        return SPHCTL_EX_UNAVAILABLE;
    }
    /* The subscription goes out right after the handshake: wait for it, so that a job started
     * after this returns cannot publish before we listen (a short job could otherwise end
     * unseen). A stream that does not answer in time is no error: the watch loop's snapshots
     * still follow the job. */
    const double until = sphctl_mono() + c->timeout;
    int connected = 0;
    while (!connected) {
        const double left = until - sphctl_mono();
        if (left <= 0)
            break;
        zmq_pollitem_t it = {.socket = st->mon, .events = ZMQ_POLLIN};
        int n = zmq_poll(&it, 1, (long)(left * 1000) + 1);
        if (n < 0 && errno == EINTR)
            continue;
        if (n <= 0)
            break;
        if (sphctl_monitor_read(c, st->mon, st->ep, &connected)) {
            sphctl_stream_close(st);
            return SPHCTL_EX_NOPERM;
        }
    }
    st->connected = connected;
    return 0;
}

int sphctl_stream_topic(sphctl_stream *st, const char *topic)
{
    if (strcmp(st->topic, topic) == 0)
        return 0;
    /* the new subscription goes out before the old one's cancellation, so nothing under both
     * is missed */
    if (zmq_setsockopt(st->sub, ZMQ_SUBSCRIBE, topic, strlen(topic)) != 0 ||
        zmq_setsockopt(st->sub, ZMQ_UNSUBSCRIBE, st->topic, strlen(st->topic)) != 0) {
        fprintf(stderr, "sphctl: cannot subscribe to %s: %s\n", st->ep, zmq_strerror(errno));
        sphctl_stream_close(st);
        return SPHCTL_EX_UNAVAILABLE;
    }
    snprintf(st->topic, sizeof st->topic, "%s", topic);
    return 0;
}

int sphctl_stream_next(sphctl *c, sphctl_stream *st, long ms, json_t **ev)
{
    *ev = NULL;
    zmq_pollitem_t it[2] = {{.socket = st->sub, .events = ZMQ_POLLIN},
                            {.socket = st->mon, .events = ZMQ_POLLIN}};
    int n = zmq_poll(it, 2, ms);
    if (n < 0)
        return errno == EINTR ? 0 : SPHCTL_EX_SOFTWARE;
    if ((it[1].revents & ZMQ_POLLIN) && sphctl_refused(c, st->mon, st->ep))
        return SPHCTL_EX_NOPERM; /* the stream refused us (a key revoked meanwhile) */
    if (!(it[0].revents & ZMQ_POLLIN))
        return 0;
    char topic[256];
    if (zmq_recv(st->sub, topic, sizeof topic - 1, 0) < 0)
        return 0;
    int more = 0;
    size_t ml = sizeof more;
    zmq_getsockopt(st->sub, ZMQ_RCVMORE, &more, &ml);
    if (!more)
        return 0;
    zmq_msg_t m;
    zmq_msg_init(&m);
    if (zmq_msg_recv(&m, st->sub, 0) >= 0)
        *ev = json_loadb(zmq_msg_data(&m), zmq_msg_size(&m), 0, NULL);
    zmq_msg_close(&m);
    return 0;
}

void sphctl_stream_close(sphctl_stream *st)
{
    if (st->mon)
        zmq_close(st->mon);
    if (st->sub)
        zmq_close(st->sub);
    st->mon = st->sub = NULL;
}

int sphctl_watch(sphctl *c, const char *job)
{
    sphctl_stream st;
    int rc = sphctl_stream_open(c, job, &st);
    if (rc)
        return rc;
    return sphctl_watch_stream(c, &st, job, 0);
}

int sphctl_watch_stream(sphctl *c, sphctl_stream *st, const char *job, int from_start)
{
    watch w = {.c = c, .tty = sphctl_watch_tty(c)};
    sphctl_view_init(&w.v, job);
    /* subscribed to every job before the id was known: narrow it */
    int rc = sphctl_stream_topic(st, job);
    if (rc)
        return rc;
    if (from_start && st->connected) {
        /* listening since before the job existed: its events from the first on are the whole
         * story (a jump in seq still takes a snapshot, below); a quiet query gives the end
         * time for the progress line */
        json_t *r;
        if ((rc = sphctl_request(c, "query", json_pack("{s:s}", "job", job), &r, NULL, 0)) != 0)
            goto out;
        w.v.t_end = sphctl_num(json_object_get(r, "progress"), "t_end");
        json_decref(r);
    } else if ((rc = snapshot(&w)) != 0) { /* subscribed first, then the snapshot */
        goto out;
    }
    int first = 1;
    double last_heard = sphctl_mono();
    while (!sphctl_final_state(w.v.state)) {
        json_t *ev;
        if ((rc = sphctl_stream_next(c, st, 500, &ev)) != 0)
            goto out;
        if (!ev) {
            /* quiet: is the server still there? (a query also refreshes the progress) */
            if (sphctl_mono() - last_heard >= c->timeout) {
                long seen = w.v.seq;
                if ((rc = snapshot(&w)) != 0)
                    goto out;
                if (w.v.seq > seen + 1 && !first)
                    report_gap(&w, seen + 1, w.v.seq);
                last_heard = sphctl_mono();
            }
            continue;
        }
        last_heard = sphctl_mono();
        /* the topic is a prefix match: keep our job only */
        const char *ej = json_string_value(json_object_get(ev, "job"));
        if (!ej || strcmp(ej, job) != 0) {
            json_decref(ev);
            continue;
        }
        long seq = (long)json_integer_value(json_object_get(ev, "seq"));
        if (seq <= w.v.seq) {
            json_decref(ev); /* already in the snapshot */
            continue;
        }
        if (seq > w.v.seq + 1) {
            if (first) {
                /* the subscription took effect after the snapshot: take a fresh one */
                long seen = w.v.seq;
                if ((rc = snapshot(&w)) != 0) {
                    json_decref(ev);
                    goto out;
                }
                if (seq > w.v.seq + 1)
                    report_gap(&w, seen + 1, seq - 1);
                if (seq <= w.v.seq) {
                    json_decref(ev);
                    first = 0;
                    continue;
                }
            } else {
                report_gap(&w, w.v.seq + 1, seq - 1);
            }
        }
        first = 0;
        on_event(&w, ev);
        json_decref(ev);
    }
    rc = finish(&w);
out:
    sphctl_view_free(&w.v);
    sphctl_stream_close(st);
    return rc;
}
