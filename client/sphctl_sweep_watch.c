/*
 * sphctl sweep --watch: every job of a sweep followed to its end, the Clone pattern of
 * sphctl_watch.c over many jobs. The stream is subscribed to the sweep's jobs before the sweep is
 * sent; sphd's reply is the first snapshot (each job's status and seq), the jobs' events update
 * it, and `list` with the sweep takes a fresh one on a jump in a job's seq and every --timeout
 * seconds (a final event lost, or sphd gone). On a TTY a block of lines redrawn on stderr (a
 * summary, then a line per job), else a line per change of state on stdout; with --json one
 * document at the end.
 */
#include "sphctl.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct sweep_watch {
    sphctl *c;
    const char *sweep;
    const json_t *jobs;  /* the reply's statuses (borrowed): each job's params */
    const json_t *paths; /* the varied paths, in order */
    json_t *index;       /* job id -> its index in v */
    sphctl_view *v;      /* the jobs, in the sweep's order */
    size_t n, left;      /* how many; how many not yet final */
    int tty, wid, wpar;  /* the columns' widths */
    int drawn;           /* lines of the block on the screen (TTY) */
    double last_draw, last_refresh;
} sweep_watch;

static const char *const states[] = {"queued", "running", "paused", "done", "failed", "stopped"};
#define NSTATES (sizeof states / sizeof states[0])

/* "sweep S: N jobs: 2 done, 1 running" (the states in the order of states[]). */
static void summary(const sweep_watch *sw, char *buf, size_t size)
{
    size_t count[NSTATES + 1] = {0};
    for (size_t i = 0; i < sw->n; i++) {
        size_t k = 0;
        while (k < NSTATES && strcmp(sw->v[i].state, states[k]) != 0)
            k++;
        count[k]++;
    }
    int len = snprintf(buf, size, "sweep %s: %zu job%s", sw->sweep, sw->n, sw->n == 1 ? "" : "s");
    const char *sep = ": ";
    for (size_t k = 0; k <= NSTATES && len < (int)size; k++) {
        if (count[k]) {
            len += snprintf(buf + len, size - (size_t)len, "%s%zu %s", sep, count[k],
                            k < NSTATES ? states[k] : "other");
            sep = ", ";
        }
    }
}

/* JOB  PARAMS  STATE  progress */
static void job_line(const sweep_watch *sw, size_t i, char *line, size_t size)
{
    const sphctl_view *v = &sw->v[i];
    char params[1024];
    sphctl_fmt_params(json_object_get(json_array_get(sw->jobs, i), "params"), sw->paths, params,
                      sizeof params);
    int n = snprintf(line, size, "%-*s  %-*s  %-8s", sw->wid, v->job, sw->wpar, params, v->state);
    if (n < (int)size)
        sphctl_view_progress(v, 0, line + n, size - (size_t)n);
}

/* Erases the block (the cursor is on the line below it), so that a message can take its place
 * before the next draw. */
static void erase(sweep_watch *sw)
{
    if (sw->drawn)
        fprintf(stderr, "\033[%dA\r\033[J", sw->drawn);
    sw->drawn = 0;
}

/* The block: the summary, then a line per job; when the terminal is too short for all, the
 * running and paused ones first, then the others in order, as many as fit. */
static void draw(sweep_watch *sw, int force)
{
    if (!sw->tty)
        return;
    double now = sphctl_mono();
    if (!force && now - sw->last_draw < 0.1)
        return;
    sw->last_draw = now;
    int rows, cols;
    sphctl_term_size(&rows, &cols);
    size_t fit = rows > 2 ? (size_t)rows - 2 : sw->n, shown = 0;
    char *show = calloc(sw->n ? sw->n : 1, 1);
    for (int pass = 0; pass < 2 && show; pass++)
        for (size_t i = 0; i < sw->n && shown < fit; i++) {
            const char *s = sw->v[i].state;
            const int active = strcmp(s, "running") == 0 || strcmp(s, "paused") == 0;
            if (!show[i] && (pass == 1 || active)) {
                show[i] = 1;
                shown++;
            }
        }
    char line[1536];
    summary(sw, line, sizeof line);
    if (shown < sw->n)
        snprintf(line + strlen(line), sizeof line - strlen(line), " (%zu shown)", shown);
    erase(sw);
    sphctl_fit_line(line, cols);
    fprintf(stderr, "%s\033[K\n", line);
    sw->drawn = 1;
    for (size_t i = 0; i < sw->n && show; i++) {
        if (!show[i])
            continue;
        job_line(sw, i, line, sizeof line);
        sphctl_fit_line(line, cols);
        fprintf(stderr, "%s\033[K\n", line);
        sw->drawn++;
    }
    free(show);
    fflush(stderr);
}

/* Job i's state went from old to its view's: the count of the unfinished, and the news (a redraw
 * on a TTY, with a failure's reason above the block; else a line on stdout). */
static void changed(sweep_watch *sw, size_t i, const char *old)
{
    const sphctl_view *v = &sw->v[i];
    if (!sphctl_final_state(old) && sphctl_final_state(v->state))
        sw->left--;
    if (sw->tty) {
        if (*v->reason) {
            erase(sw);
            fprintf(stderr, "%s: %s\n", v->job, v->reason);
        }
        draw(sw, 1);
    } else if (!sw->c->json) {
        char line[1536];
        job_line(sw, i, line, sizeof line);
        printf("%s%s%s%s\n", line, *v->reason ? " (" : "", v->reason, *v->reason ? ")" : "");
        fflush(stdout);
    }
}

static long find(const sweep_watch *sw, const char *job)
{
    const json_t *k = job ? json_object_get(sw->index, job) : NULL;
    return k ? (long)json_integer_value(k) : -1;
}

/* A fresh snapshot of every job: `list` with the sweep. Returns 0 or the exit code. */
static int refresh(sweep_watch *sw)
{
    json_t *r;
    int rc = sphctl_request(sw->c, "list", json_pack("{s:s}", "sweep", sw->sweep), &r, NULL, 0);
    sw->last_refresh = sphctl_mono();
    if (rc)
        return rc;
    size_t k;
    json_t *s;
    json_array_foreach(json_object_get(r, "jobs"), k, s)
    {
        long i = find(sw, json_string_value(json_object_get(s, "job")));
        if (i < 0 || json_integer_value(json_object_get(s, "seq")) < sw->v[i].seq)
            continue;
        char old[sizeof sw->v[i].state];
        memcpy(old, sw->v[i].state, sizeof old);
        sphctl_view_status(&sw->v[i], s);
        if (strcmp(old, sw->v[i].state) != 0)
            changed(sw, (size_t)i, old);
    }
    json_decref(r);
    draw(sw, 0);
    return 0;
}

static void gap(sweep_watch *sw, size_t i, long from, long to)
{
    erase(sw);
    sphctl_report_gap(sw->v[i].job, from, to, 0, 0);
    draw(sw, 1);
}

/* One event from the stream. Returns 0 or the exit code. */
static int on_event(sweep_watch *sw, json_t *ev)
{
    long i = find(sw, json_string_value(json_object_get(ev, "job")));
    if (i < 0)
        return 0; /* the topic is a prefix: another sweep's job, or another job */
    sphctl_view *v = &sw->v[i];
    long seq = (long)json_integer_value(json_object_get(ev, "seq"));
    if (seq <= v->seq)
        return 0; /* already in the snapshot */
    if (seq > v->seq + 1) {
        /* events went missing (or the subscription took effect after the reply): a fresh
         * snapshot, at most one a second, and what it does not cover is a gap */
        long seen = v->seq;
        int rc = sphctl_mono() - sw->last_refresh >= 1.0 ? refresh(sw) : 0;
        if (rc)
            return rc;
        if (seq <= v->seq)
            return 0;
        if (seq > v->seq + 1)
            gap(sw, (size_t)i, seen + 1, seq - 1);
    }
    char old[sizeof v->state];
    memcpy(old, v->state, sizeof old);
    sphctl_view_event(v, ev);
    if (strcmp(old, v->state) != 0)
        changed(sw, (size_t)i, old);
    else
        draw(sw, 0);
    return 0;
}

/* The end: the block's last draw, the summary line, or the final statuses (--json). Returns the
 * worst job's exit code, or the request's. */
static int finish(sweep_watch *sw)
{
    char line[1536];
    int rc = SPHCTL_EX_OK;
    for (size_t i = 0; i < sw->n; i++) {
        const int e = sphctl_state_exit(sw->v[i].state);
        rc = e > rc ? e : rc;
    }
    if (sw->tty) {
        draw(sw, 1);
    } else if (!sw->c->json) {
        summary(sw, line, sizeof line);
        printf("%s\n", line);
    } else {
        json_t *r;
        int e = sphctl_request(sw->c, "list", json_pack("{s:s}", "sweep", sw->sweep), &r, NULL, 0);
        if (e)
            return e;
        json_t *out = json_pack("{s:s, s:I, s:O}", "sweep", sw->sweep, "count",
                                (json_int_t)json_array_size(json_object_get(r, "jobs")), "jobs",
                                json_object_get(r, "jobs"));
        sphctl_print_json(out, 1);
        json_decref(out);
        json_decref(r);
    }
    return rc;
}

int sphctl_sweep_watch(sphctl *c, sphctl_stream *st, const json_t *reply, const json_t *paths)
{
    sweep_watch sw = {.c = c,
                      .sweep = json_string_value(json_object_get(reply, "sweep")),
                      .jobs = json_object_get(reply, "jobs"),
                      .paths = paths,
                      .index = json_object(),
                      .tty = sphctl_watch_tty(c)};
    sw.n = json_array_size(sw.jobs);
    sw.v = calloc(sw.n ? sw.n : 1, sizeof *sw.v);
    int rc = SPHCTL_EX_SOFTWARE;
    char topic[sizeof st->topic];
    if (!sw.sweep || !sw.index || !sw.v) {
        fprintf(stderr, "sphctl: out of memory, or a sweep reply without its id\n");
        goto out;
    }
    sphctl_sweep_widths(sw.jobs, paths, &sw.wid, &sw.wpar);
    for (size_t i = 0; i < sw.n; i++) {
        const json_t *s = json_array_get(sw.jobs, i);
        const char *job = json_string_value(json_object_get(s, "job"));
        sphctl_view_init(&sw.v[i], job ? job : "?");
        sphctl_view_status(&sw.v[i], s);
        json_object_set_new(sw.index, sw.v[i].job, json_integer((json_int_t)i));
        sw.left += !sphctl_final_state(sw.v[i].state);
    }
    /* subscribed to every job before the sweep's id was known: narrow it to its jobs */
    snprintf(topic, sizeof topic, "%s-", sw.sweep);
    if ((rc = sphctl_stream_topic(st, topic)) != 0)
        goto out;
    sw.last_refresh = sphctl_mono();
    draw(&sw, 1);
    while (sw.left > 0) {
        json_t *ev;
        if ((rc = sphctl_stream_next(c, st, 500, &ev)) != 0)
            goto out;
        if (ev) {
            rc = on_event(&sw, ev);
            json_decref(ev);
            if (rc)
                goto out;
        }
        if (sphctl_mono() - sw.last_refresh >= c->timeout && (rc = refresh(&sw)) != 0)
            goto out;
    }
    rc = finish(&sw);
out:
    for (size_t i = 0; sw.v && i < sw.n; i++)
        sphctl_view_free(&sw.v[i]);
    free(sw.v);
    json_decref(sw.index);
    sphctl_stream_close(st);
    return rc;
}
