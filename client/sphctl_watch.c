/*
 * sphctl watch: the Clone pattern. Subscribe to the job's topic first, then ask for a snapshot
 * (query); events up to the snapshot's seq are already in it, later ones update it. A jump in seq
 * is reported as a gap. On a TTY a live progress line, otherwise JSON Lines.
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
    const char *job;
    int tty;
    long seq; /* last seq seen (snapshot or event) */
    char state[16];
    double t, t_end, rate, eta;
    long steps;
    json_t *diag;
    double last_draw, last_diag_wall;
    long last_diag_step;
    double last_diag_t;
    int drawn;
} watch;

static double mono(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void take_status(watch *w, const json_t *s)
{
    snprintf(w->state, sizeof w->state, "%s",
             json_string_value(json_object_get(s, "state"))
                 ? json_string_value(json_object_get(s, "state"))
                 : "?");
    w->seq = (long)json_integer_value(json_object_get(s, "seq"));
    json_t *p = json_object_get(s, "progress");
    w->t = sphctl_num(p, "t");
    w->t_end = sphctl_num(p, "t_end");
    w->steps = (long)json_integer_value(json_object_get(p, "steps"));
    w->rate = sphctl_num(p, "steps_per_s");
    w->eta = sphctl_num(p, "eta");
    json_t *d = json_object_get(s, "diag");
    if (json_is_object(d)) {
        json_decref(w->diag);
        w->diag = json_incref(d);
    }
}

static int final_state(const char *s)
{
    return strcmp(s, "done") == 0 || strcmp(s, "failed") == 0 || strcmp(s, "stopped") == 0;
}

static void draw(watch *w, int force)
{
    if (!w->tty)
        return;
    double now = mono();
    if (!force && now - w->last_draw < 0.1)
        return;
    w->last_draw = now;
    char line[512];
    int n = snprintf(line, sizeof line, "%s %-8s", w->job, w->state);
    if (isfinite(w->t) && isfinite(w->t_end) && w->t_end > 0) {
        double f = w->t / w->t_end;
        f = f < 0 ? 0 : f > 1 ? 1 : f;
        char bar[21];
        int k = (int)(f * 20 + 0.5);
        for (int i = 0; i < 20; i++)
            bar[i] = i < k ? '#' : '.';
        bar[20] = '\0';
        n += snprintf(line + n, sizeof line - (size_t)n, " [%s] %5.1f%% t %.4g/%.4g s", bar,
                      100 * f, w->t, w->t_end);
    }
    n += snprintf(line + n, sizeof line - (size_t)n, " step %ld", w->steps);
    if (isfinite(w->rate) && w->rate > 0)
        n += snprintf(line + n, sizeof line - (size_t)n, " %.0f steps/s", w->rate);
    if (isfinite(w->eta) && strcmp(w->state, "running") == 0) {
        char eta[32];
        sphctl_fmt_duration(w->eta, eta, sizeof eta);
        n += snprintf(line + n, sizeof line - (size_t)n, " ETA %s", eta);
    }
    static const char *const keys[] = {"front_x", "height_left", "penetration", "runup",
                                       "ekin",    "vmax",        NULL};
    for (int i = 0; keys[i] && n < (int)sizeof line - 40; i++) {
        double v = sphctl_num(w->diag, keys[i]);
        if (isfinite(v))
            n += snprintf(line + n, sizeof line - (size_t)n, " %s %.4g", keys[i], v);
    }
    /* one line: cut to the terminal's width, or a redraw would wrap and scroll */
    struct winsize ws;
    if (ioctl(STDERR_FILENO, TIOCGWINSZ, &ws) == 0 && ws.ws_col > 1 && ws.ws_col <= sizeof line &&
        strlen(line) >= ws.ws_col)
        line[ws.ws_col - 1] = '\0';
    fprintf(stderr, "\r%s\033[K", line);
    fflush(stderr);
    w->drawn = 1;
}

static void on_event(watch *w, json_t *ev)
{
    const char *type = json_string_value(json_object_get(ev, "type"));
    type = type ? type : "";
    if (!w->tty)
        sphctl_print_json(ev, 1);
    if (strcmp(type, "state") == 0) {
        const char *s = json_string_value(json_object_get(ev, "state"));
        snprintf(w->state, sizeof w->state, "%s", s ? s : "?");
        if (w->tty) {
            const char *reason = json_string_value(json_object_get(ev, "reason"));
            draw(w, 1);
            if (reason)
                fprintf(stderr, "\n%s: %s", w->job, reason);
        }
    } else if (strcmp(type, "diag") == 0) {
        json_decref(w->diag);
        w->diag = json_incref(ev);
        double now = mono(), t = sphctl_num(ev, "t");
        long step = (long)json_integer_value(json_object_get(ev, "step"));
        if (w->last_diag_wall > 0 && now > w->last_diag_wall && step > w->last_diag_step) {
            w->rate = (double)(step - w->last_diag_step) / (now - w->last_diag_wall);
            if (isfinite(t) && isfinite(w->t_end) && t > w->last_diag_t)
                w->eta = (w->t_end - t) / ((t - w->last_diag_t) / (now - w->last_diag_wall));
        }
        w->last_diag_wall = now;
        w->last_diag_step = step;
        w->last_diag_t = t;
        w->steps = step;
        if (isfinite(t))
            w->t = t;
        draw(w, 0);
    } else if (strcmp(type, "log") == 0 && w->tty) {
        const char *m = json_string_value(json_object_get(ev, "message"));
        fprintf(stderr, "%s%s: %s\n", w->drawn ? "\r\033[K" : "", w->job, m ? m : "");
        draw(w, 1);
    } else if (strcmp(type, "output") == 0 && w->tty) {
        const char *f = json_string_value(json_object_get(ev, "file"));
        fprintf(stderr, "%s%s: wrote %s\n", w->drawn ? "\r\033[K" : "", w->job, f ? f : "?");
        draw(w, 1);
    }
}

static void report_gap(watch *w, long from, long to)
{
    fprintf(stderr, "%ssphctl: %s: missed events %ld..%ld (the stream dropped them)\n",
            w->tty && w->drawn ? "\r\033[K" : "", w->job, from, to);
    if (!w->tty) {
        json_t *g = json_pack("{s:s, s:s, s:I, s:I}", "job", w->job, "type", "gap", "from",
                              (json_int_t)from, "to", (json_int_t)to);
        sphctl_print_json(g, 1);
        json_decref(g);
    }
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
    int rc = sphctl_request(w->c, "query", json_pack("{s:s}", "job", w->job), &r, NULL, 0);
    if (rc)
        return rc;
    take_status(w, r);
    if (!w->tty) {
        json_t *snap = json_pack("{s:s, s:I, s:s, s:O}", "job", w->job, "seq", (json_int_t)w->seq,
                                 "type", "snapshot", "status", r);
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
    return strcmp(w->state, "done") == 0 ? SPHCTL_EX_OK : SPHCTL_EX_FAILED;
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
    const double until = mono() + c->timeout;
    int connected = 0;
    while (!connected) {
        const double left = until - mono();
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
    watch w = {.c = c,
               .job = job,
               .tty = !c->json && isatty(STDOUT_FILENO),
               .t = NAN,
               .t_end = NAN,
               .rate = NAN,
               .eta = NAN};
    int rc;
    void *sub = st->sub, *mon = st->mon;
    const char *ep = st->ep;
    if (strcmp(st->topic, job) != 0) {
        /* subscribed to every job before the id was known: narrow it (the new subscription
         * goes out before the old one's cancellation, so nothing of this job is missed) */
        if (zmq_setsockopt(sub, ZMQ_SUBSCRIBE, job, strlen(job)) != 0 ||
            zmq_setsockopt(sub, ZMQ_UNSUBSCRIBE, st->topic, strlen(st->topic)) != 0) {
            fprintf(stderr, "sphctl: cannot subscribe to %s: %s\n", ep, zmq_strerror(errno));
            sphctl_stream_close(st);
            return SPHCTL_EX_UNAVAILABLE;
        }
        snprintf(st->topic, sizeof st->topic, "%s", job);
    }
    if (from_start && st->connected) {
        /* listening since before the job existed: its events from the first on are the whole
         * story (a jump in seq still takes a snapshot, below); a quiet query gives the end
         * time for the progress line */
        json_t *r;
        if ((rc = sphctl_request(c, "query", json_pack("{s:s}", "job", job), &r, NULL, 0)) != 0)
            goto out;
        w.t_end = sphctl_num(json_object_get(r, "progress"), "t_end");
        json_decref(r);
    } else if ((rc = snapshot(&w)) != 0) { /* subscribed first, then the snapshot */
        goto out;
    }
    int first = 1;
    double last_heard = mono();
    while (!final_state(w.state)) {
        zmq_pollitem_t it[2] = {{.socket = sub, .events = ZMQ_POLLIN},
                                {.socket = mon, .events = ZMQ_POLLIN}};
        int n = zmq_poll(it, 2, 500);
        if (n < 0) {
            if (errno == EINTR)
                continue;
            rc = SPHCTL_EX_SOFTWARE;
            goto out;
        }
        if ((it[1].revents & ZMQ_POLLIN) && sphctl_refused(c, mon, ep)) {
            rc = SPHCTL_EX_NOPERM; /* the stream refused us (a key revoked meanwhile) */
            goto out;
        }
        if (n > 0 && !(it[0].revents & ZMQ_POLLIN))
            continue;
        if (n == 0) {
            /* quiet: is the server still there? (a query also refreshes the progress) */
            if (mono() - last_heard >= c->timeout) {
                long seen = w.seq;
                if ((rc = snapshot(&w)) != 0)
                    goto out;
                if (w.seq > seen + 1 && !first)
                    report_gap(&w, seen + 1, w.seq);
                last_heard = mono();
            }
            continue;
        }
        char topic[256];
        int tn = zmq_recv(sub, topic, sizeof topic - 1, 0);
        if (tn < 0)
            continue;
        int more = 0;
        size_t ml = sizeof more;
        zmq_getsockopt(sub, ZMQ_RCVMORE, &more, &ml);
        if (!more)
            continue;
        zmq_msg_t m;
        zmq_msg_init(&m);
        if (zmq_msg_recv(&m, sub, 0) < 0) {
            zmq_msg_close(&m);
            continue;
        }
        json_t *ev = json_loadb(zmq_msg_data(&m), zmq_msg_size(&m), 0, NULL);
        zmq_msg_close(&m);
        last_heard = mono();
        /* the topic is a prefix match: keep our job only */
        const char *ej = json_string_value(json_object_get(ev, "job"));
        if (!ev || !ej || strcmp(ej, job) != 0) {
            json_decref(ev);
            continue;
        }
        long seq = (long)json_integer_value(json_object_get(ev, "seq"));
        if (seq <= w.seq) {
            json_decref(ev); /* already in the snapshot */
            continue;
        }
        if (seq > w.seq + 1) {
            if (first) {
                /* the subscription took effect after the snapshot: take a fresh one */
                long seen = w.seq;
                if ((rc = snapshot(&w)) != 0) {
                    json_decref(ev);
                    goto out;
                }
                if (seq > w.seq + 1)
                    report_gap(&w, seen + 1, seq - 1);
                if (seq <= w.seq) {
                    json_decref(ev);
                    first = 0;
                    continue;
                }
            } else {
                report_gap(&w, w.seq + 1, seq - 1);
            }
        }
        first = 0;
        w.seq = seq;
        on_event(&w, ev);
        json_decref(ev);
    }
    rc = finish(&w);
out:
    json_decref(w.diag);
    sphctl_stream_close(st);
    return rc;
}
