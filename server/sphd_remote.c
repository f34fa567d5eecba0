/*
 * Jobs on the Slurm executor, seen from the loop: the runners' messages (sphd_link.c's wire)
 * handed to the job manager as a local worker's would be, and a look at Slurm's queue every
 * few seconds for jobs whose Slurm job ended without a word from their runner (a node that
 * failed, a time limit, scancel, a runner killed): those continue from their checkpoint in a
 * new Slurm job, up to their retry limit, or are paused when someone cancelled them.
 */
#include "sphd.h"
#include "sphd_daemon.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define POLL_EVERY_S 2.0
#define GONE_GRACE_S 3.0 /* an ended Slurm job's last messages may still be on their way */

/* A line in the daemon's log and a `log` event on the job's stream, printf-style. */
static void say(sphd_daemon *d, sphd_job *j, const char *level, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));
static void say(sphd_daemon *d, sphd_job *j, const char *level, const char *fmt, ...)
{
    char msg[512];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    sphd_log("job %s: %s", j->id, msg);
    sphd_publish(d, j, "log", json_pack("{s:s, s:s}", "level", level, "message", msg));
}

/* A runner's routing id is JOB@SLURMJOB: its job, if that job runs in that Slurm job now (a
 * job whose sbatch has not answered yet takes the Slurm job its runner names). */
static sphd_job *runner_job(sphd_daemon *d, const char *runner, const char **sid)
{
    const char *at = strrchr(runner, '@');
    if (!at)
        return NULL;
    char id[SPHD_JOB_ID_MAX];
    snprintf(id, sizeof id, "%.*s", (int)(at - runner), runner);
    *sid = at + 1;
    sphd_job *j = sphd_job_find(d, id);
    if (!j || j->worker != SPHD_WORKER_REMOTE || j->state != SPHD_JOB_RUNNING)
        return NULL;
    if (j->slurm_id[0] && strcmp(j->slurm_id, *sid) != 0)
        return NULL;
    if (!j->slurm_id[0])
        snprintf(j->slurm_id, sizeof j->slurm_id, "%s", *sid);
    return j;
}

/* A runner that has no job here (stopped, paused, forgotten, or a stray second run): it quits,
 * and its Slurm job goes. */
static void send_away(sphd_daemon *d, const char *runner, const char *sid)
{
    static char last[SPHD_JOB_ID_MAX + 64]; /* the loop thread's: one word per stray runner */
    if (strcmp(last, runner) == 0)
        return;
    snprintf(last, sizeof last, "%s", runner);
    sphd_wcmd q = {.kind = SPHD_W_QUIT};
    sphd_wire_send_cmd(d->runners, runner, &q);
    sphd_log("runner %s has no job to run here: told to quit", runner);
    if (sid && *sid) {
        sphd_scmd c = {.kind = SPHD_S_CANCEL, .arg = strdup(sid)};
        if (c.arg)
            sphd_slurm_send(d, &c);
    }
}

/* A pause or stop journaled before a restart and not carried out yet: told to the runner (a
 * second word to a runner that had it already is dropped when its run has ended). */
static void send_requests(sphd_daemon *d, sphd_job *j)
{
    if (!j->requests_unsent)
        return;
    j->requests_unsent = 0;
    sphd_wcmd cmd = {.kind = j->stop_requested ? SPHD_W_STOP : SPHD_W_PAUSE, .job = j};
    if (!j->pause_requested && !j->stop_requested)
        return;
    if (sphd_jobs_send(d, j, &cmd) != 0) {
        sphd_log("job %s: cannot reach its runner", j->id);
        return;
    }
    say(d, j, "info", "its %s, requested before sphd restarted, is sent to its runner",
        j->stop_requested ? "stop" : "pause");
}

static void on_hello(sphd_daemon *d, const char *runner, json_t *hello)
{
    const char *sid = "";
    sphd_job *j = runner_job(d, runner, &sid);
    if (!j) {
        send_away(d, runner, sid);
        return;
    }
    j->runner_seen = 1;
    j->gone_since = 0;
    /* a remote run always looks for a checkpoint first (Slurm may have requeued it after a
     * node failure); the runner starts afresh when there is none */
    j->resume = 1;
    sphd_wcmd run = {
        .kind = SPHD_W_RUN, .job = j, .max_steps = j->run_max_steps, .until = j->run_until};
    if (sphd_wire_send_cmd(d->runners, runner, &run) != 0) {
        sphd_log("job %s: cannot reach its runner", j->id);
        return;
    }
    say(d, j, "info", "running on %s (Slurm job %s)",
        json_string_value(json_object_get(hello, "host")) ?: "?", j->slurm_id);
    send_requests(d, j);
}

void sphd_remote_on_message(sphd_daemon *d)
{
    for (int k = 0; k < 1000; k++) { /* then the other sockets get their turn */
        char runner[SPHD_JOB_ID_MAX + 64];
        sphd_wev ev;
        json_t *hello = NULL;
        const int n = sphd_wire_recv_wev(d->runners, runner, sizeof runner, &ev, &hello);
        if (n == 0)
            return;
        if (n < 0) {
            sphd_log("a runner sent a message sphd cannot read; ignored");
            continue;
        }
        if (hello) {
            on_hello(d, runner, hello);
            json_decref(hello);
            continue;
        }
        const char *sid = "";
        sphd_job *j = runner_job(d, runner, &sid);
        if (!j) { /* a runner that outlived its run here */
            json_decref(ev.body);
            free(ev.text);
            if (ev.kind == SPHD_WEV_END)
                continue; /* it ends anyway */
            send_away(d, runner, sid);
            continue;
        }
        if (!j->runner_seen) { /* sphd was restarted while the runner ran: it is back */
            j->runner_seen = 1;
            say(d, j, "info", "its runner (Slurm job %s) is back", j->slurm_id);
            if (ev.kind != SPHD_WEV_END) /* else its run ended: what it says is the answer */
                send_requests(d, j);
        }
        j->gone_since = 0;
        ev.job = j;
        sphd_jobs_on_worker(d, NULL, &ev);
    }
}

/* The last line the Slurm job wrote to its output file (the runner's last words), or "". */
static void last_words(const sphd_job *j, const char *slurm_id, char *out, size_t n)
{
    out[0] = '\0';
    char path[SPHD_PATH_MAX + 96];
    snprintf(path, sizeof path, "%s/slurm-%s.out", j->dir, slurm_id);
    FILE *f = fopen(path, "r");
    if (!f)
        return;
    char line[512];
    while (fgets(line, sizeof line, f)) {
        size_t k = strlen(line);
        while (k > 0 && (line[k - 1] == '\n' || line[k - 1] == ' '))
            line[--k] = '\0';
        if (k > 0)
            snprintf(out, n, "%s", line);
    }
    fclose(f);
}

/* Slurm's word on one of our jobs: 1 while it may still run, 0 ended (state in st). */
static int still_there(const char *lines, const char *id, char *st, size_t n)
{
    snprintf(st, n, "gone from Slurm's queue");
    const size_t len = strlen(id);
    for (const char *p = lines; p && *p;) {
        const char *nl = strchr(p, '\n');
        if (strncmp(p, id, len) == 0 && p[len] == ' ') {
            const char *s = p + len + 1;
            const size_t sl = nl ? (size_t)(nl - s) : strlen(s);
            snprintf(st, n, "%.*s", (int)sl, s);
            return strncmp(s, "PENDING", 7) == 0 || strncmp(s, "RUNNING", 7) == 0 ||
                   strncmp(s, "CONFIGURING", 11) == 0 || strncmp(s, "COMPLETING", 10) == 0 ||
                   strncmp(s, "SUSPENDED", 9) == 0 || strncmp(s, "REQUEUED", 8) == 0 ||
                   strncmp(s, "RESIZING", 8) == 0;
        }
        p = nl ? nl + 1 : NULL;
    }
    return 0;
}

void sphd_remote_poll(sphd_daemon *d)
{
    const double now = sphd_mono();
    if (now < d->next_slurm_poll || d->slurm_polling)
        return;
    d->next_slurm_poll = now + POLL_EVERY_S;
    size_t len = 0, cap = 0;
    char *ids = NULL;
    for (sphd_job *j = d->jobs; j; j = j->next) {
        if (j->worker != SPHD_WORKER_REMOTE || !j->slurm_id[0])
            continue;
        const size_t need = len + strlen(j->slurm_id) + 2;
        if (need > cap) {
            cap = need * 2;
            char *n = realloc(ids, cap);
            if (!n) {
                free(ids);
                return;
            }
            ids = n;
        }
        len += (size_t)sprintf(ids + len, "%s%s", len ? "," : "", j->slurm_id);
    }
    if (!ids)
        return;
    sphd_scmd cmd = {.kind = SPHD_S_STATES, .arg = ids};
    if (sphd_slurm_send(d, &cmd) >= 0)
        d->slurm_polling = 1;
}

/* squeue's answer: the jobs whose Slurm job ended without a word from their runner. */
static void on_states(sphd_daemon *d, const char *lines)
{
    const double now = sphd_mono();
    for (sphd_job *j = d->jobs; j; j = j->next) {
        if (j->worker != SPHD_WORKER_REMOTE || !j->slurm_id[0])
            continue;
        char st[64];
        if (still_there(lines, j->slurm_id, st, sizeof st)) {
            j->gone_since = 0;
            continue;
        }
        if (j->gone_since == 0) {
            j->gone_since = now;
            continue;
        }
        if (now - j->gone_since < GONE_GRACE_S)
            continue;
        /* it ended and its runner said nothing */
        char reason[SPHD_REASON_MAX], slurm_id[sizeof j->slurm_id], words[200], said[256] = "";
        snprintf(slurm_id, sizeof slurm_id, "%s", j->slurm_id);
        last_words(j, slurm_id, words, sizeof words);
        if (words[0])
            snprintf(said, sizeof said, "; its last output: %s", words);
        j->worker = -1;
        j->runner_seen = 0;
        j->gone_since = 0;
        j->resume = 1;
        j->run_wall = 0;
        sphd_job_touch(j);
        const json_t *r = json_object_get(j->resources, "retries");
        const int limit = r ? (int)json_integer_value(r) : SPHD_SLURM_RETRIES;
        const int stop = j->stop_requested, pause = j->pause_requested;
        if (j->stepping) { /* the retry goes on to the same target (from the checkpoint) */
            j->step_n = j->run_max_steps;
            j->step_until = j->run_until;
        }
        j->pause_requested = j->stop_requested = j->stepping = j->requests_unsent = 0;
        if (stop) {
            sphd_job_set_state(d, j, SPHD_JOB_STOPPED, NULL);
        } else if (pause) {
            snprintf(reason, sizeof reason, "Slurm job %s ended (%s) while pausing%s", slurm_id, st,
                     said);
            sphd_job_set_state(d, j, SPHD_JOB_PAUSED, reason);
        } else if (strncmp(st, "CANCELLED", 9) == 0) {
            snprintf(reason, sizeof reason,
                     "Slurm job %s was cancelled (scancel): resume continues from the checkpoint",
                     slurm_id);
            say(d, j, "warning", "%s", reason);
            sphd_job_set_state(d, j, SPHD_JOB_PAUSED, reason);
        } else if (j->retries < limit) {
            j->retries++;
            snprintf(reason, sizeof reason,
                     "Slurm job %s ended (%s) without a result%s: submitted again from the "
                     "checkpoint (retry %d of %d)",
                     slurm_id, st, said, j->retries, limit);
            say(d, j, "warning", "%s", reason);
            sphd_job_set_state(d, j, SPHD_JOB_QUEUED, reason);
        } else {
            snprintf(reason, sizeof reason,
                     "Slurm job %s ended (%s) without a result%s (after %d %s)", slurm_id, st, said,
                     j->retries, j->retries == 1 ? "retry" : "retries");
            sphd_job_set_state(d, j, SPHD_JOB_FAILED, reason);
        }
        sphd_jobs_answer_waiters(d, j);
    }
}

void sphd_remote_on_slurm(sphd_daemon *d)
{
    sphd_sev ev;
    while (sphd_slurm_recv(d, &ev)) {
        if (ev.kind == SPHD_S_SUBMIT) {
            sphd_jobs_on_submitted(d, &ev);
        } else if (ev.kind == SPHD_S_STATES) {
            d->slurm_polling = 0;
            if (ev.lines) /* else squeue failed (said in the log): asked again later */
                on_states(d, ev.lines);
            free(ev.lines);
        }
    }
}
