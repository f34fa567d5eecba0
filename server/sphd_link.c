/*
 * The line between the loop and whatever runs a job: one set of messages (sphd_wcmd to the
 * runner of a job, sphd_wev back), in two encodings. A local worker thread passes the structs
 * over its inproc PAIR (pointers included: the executor is handed back and forth). A runner on
 * a cluster node (`sphd --runner`, started by Slurm) sends frames over tcp on a DEALER whose
 * routing id is its job's id:
 *
 *   runner -> daemon   [kind] [JSON] ([text])   kind: hello, event, progress, end, particles
 *   daemon -> runner   [job id] [kind] [JSON]   kind: run, pause, stop, particles, quit
 *
 *   hello      {"job", "slurm_job", "host", "pid"}
 *   event      {"type", "body"}                          (diag, log, output, result)
 *   progress   {"body", "wall", "steps_per_s", "eta"}
 *   end        {"end": done|failed|paused|stopped|target, "reason", "wall"}
 *   particles  {"token"} [the encoded reply]
 *   run        {"max_steps", "until", "resume"}
 *   particles  {"token", "fields", "max", "status", "id"}
 *
 * Numbers go with 17 significant digits, so a remote job's results are bit for bit a local one's.
 */
#include "sphd_daemon.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <zmq.h>

#define WIRE_FLAGS (JSON_COMPACT | JSON_REAL_PRECISION(17))

static const char *const end_names[] = {
    [SPHD_END_DONE] = "done",       [SPHD_END_FAILED] = "failed", [SPHD_END_PAUSED] = "paused",
    [SPHD_END_STOPPED] = "stopped", [SPHD_END_TARGET] = "target", [SPHD_END_STEER] = "steer"};

static json_t *num_or_null(double v)
{
    return isfinite(v) ? json_real(v) : json_null();
}

static double num_or_nan(const json_t *v)
{
    return json_is_number(v) ? json_number_value(v) : NAN;
}

/* Sends frames (NULL-terminated texts; the last may be given with its length). */
static int send_frames(void *sock, int flags, const char *const *parts, int n, size_t last_len)
{
    for (int i = 0; i < n; i++) {
        const size_t len = i == n - 1 && last_len != (size_t)-1 ? last_len : strlen(parts[i]);
        int rc;
        do
            rc = zmq_send(sock, parts[i], len, (i < n - 1 ? ZMQ_SNDMORE : 0) | flags);
        while (rc < 0 && errno == EINTR);
        if (rc < 0)
            return -1;
    }
    return 0;
}

int sphd_link_send(sphd_link *l, sphd_wev *ev)
{
    if (!l->wire) {
        if (sphd_pair_send(l->sock, ev, sizeof *ev) == 0)
            return 0;
        json_decref(ev->body);
        free(ev->text);
        return -1;
    }
    json_t *m = NULL;
    const char *kind = "event";
    switch (ev->kind) {
    case SPHD_WEV_EVENT:
        m = json_pack("{s:s, s:o}", "type", ev->type, "body", ev->body ? ev->body : json_null());
        ev->body = NULL;
        break;
    case SPHD_WEV_PROGRESS:
        kind = "progress";
        m = json_pack("{s:o, s:o, s:o, s:o}", "body", ev->body ? ev->body : json_null(), "wall",
                      num_or_null(ev->wall), "steps_per_s", num_or_null(ev->steps_per_s), "eta",
                      num_or_null(ev->eta));
        ev->body = NULL;
        break;
    case SPHD_WEV_END:
        kind = "end";
        m = json_pack("{s:s, s:s, s:o}", "end", end_names[ev->end], "reason", ev->reason, "wall",
                      num_or_null(ev->wall));
        break;
    case SPHD_WEV_PARTICLES:
        kind = "particles";
        m = json_pack("{s:I}", "token", (json_int_t)ev->token);
        break;
    }
    char *text = m ? json_dumps(m, WIRE_FLAGS) : NULL;
    json_decref(m);
    int rc = -1;
    if (text) {
        /* the end and a query's answer wait for the daemon (it may be restarting); the stream
         * of events does not: past the high-water mark they are dropped (a seq gap) */
        const int flags =
            ev->kind == SPHD_WEV_END || ev->kind == SPHD_WEV_PARTICLES ? 0 : ZMQ_DONTWAIT;
        if (ev->kind == SPHD_WEV_PARTICLES) {
            const char *parts[] = {kind, text, ev->text ? ev->text : ""};
            rc = send_frames(l->sock, flags, parts, 3, (size_t)-1);
        } else {
            const char *parts[] = {kind, text};
            rc = send_frames(l->sock, flags, parts, 2, (size_t)-1);
        }
    }
    free(text);
    free(ev->text);
    ev->text = NULL;
    return rc;
}

/* Reads one message of up to 4 frames; returns the number of frames, 0 when none is there
 * (without wait), -1 on error. Each frame is malloc'ed and NUL-terminated. */
static int recv_frames(void *sock, int wait, char **f, size_t *len, int max)
{
    int n = 0, more = 1;
    while (more) {
        zmq_msg_t m;
        zmq_msg_init(&m);
        int rc;
        do
            rc = zmq_msg_recv(&m, sock, n == 0 && !wait ? ZMQ_DONTWAIT : 0);
        while (rc < 0 && errno == EINTR);
        if (rc < 0) {
            zmq_msg_close(&m);
            for (int i = 0; i < n; i++)
                free(f[i]);
            return errno == EAGAIN ? 0 : -1;
        }
        more = zmq_msg_more(&m);
        if (n < max) {
            len[n] = zmq_msg_size(&m);
            f[n] = malloc(len[n] + 1);
            if (f[n]) {
                memcpy(f[n], zmq_msg_data(&m), len[n]);
                f[n][len[n]] = '\0';
                n++;
            }
        }
        zmq_msg_close(&m);
    }
    return n;
}

static void free_frames(char **f, int n)
{
    for (int i = 0; i < n; i++)
        free(f[i]);
}

int sphd_link_recv(sphd_link *l, sphd_wcmd *cmd, int wait)
{
    if (!l->wire) {
        int n;
        do
            n = zmq_recv(l->sock, cmd, sizeof *cmd, wait ? 0 : ZMQ_DONTWAIT);
        while (n < 0 && errno == EINTR);
        if (n < 0)
            return errno == EAGAIN ? 0 : -1;
        return n == (int)sizeof *cmd ? 1 : 0;
    }
    for (;;) {
        char *f[4];
        size_t len[4];
        int n = recv_frames(l->sock, wait, f, len, 4);
        if (n <= 0)
            return n;
        memset(cmd, 0, sizeof *cmd);
        cmd->job = l->job;
        cmd->until = INFINITY;
        json_t *m = n >= 2 ? json_loadb(f[1], len[1], 0, NULL) : NULL;
        int ok = 1;
        if (strcmp(f[0], "run") == 0) {
            cmd->kind = SPHD_W_RUN;
            cmd->max_steps = (long)json_integer_value(json_object_get(m, "max_steps"));
            const double u = num_or_nan(json_object_get(m, "until"));
            cmd->until = isfinite(u) ? u : INFINITY;
            if (l->job)
                l->job->resume = json_is_true(json_object_get(m, "resume"));
        } else if (strcmp(f[0], "pause") == 0) {
            cmd->kind = SPHD_W_PAUSE;
        } else if (strcmp(f[0], "stop") == 0) {
            cmd->kind = SPHD_W_STOP;
        } else if (strcmp(f[0], "quit") == 0) {
            cmd->kind = SPHD_W_QUIT;
        } else if (strcmp(f[0], "steer") == 0) {
            cmd->kind = SPHD_W_STEER;
        } else if (strcmp(f[0], "particles") == 0 && m) {
            cmd->kind = SPHD_W_PARTICLES;
            cmd->token = (long)json_integer_value(json_object_get(m, "token"));
            cmd->max = (long)json_integer_value(json_object_get(m, "max"));
            cmd->fields = json_incref(json_object_get(m, "fields"));
            cmd->status = json_incref(json_object_get(m, "status"));
            cmd->id = json_incref(json_object_get(m, "id"));
        } else {
            ok = 0;
        }
        json_decref(m);
        free_frames(f, n);
        if (ok)
            return 1;
        sphd_log("runner: an unknown message from the daemon; ignored");
        if (!wait)
            return 0;
    }
}

int sphd_wire_send_cmd(void *router, const char *runner, sphd_wcmd *cmd)
{
    json_t *m = NULL;
    const char *kind = "run";
    switch (cmd->kind) {
    case SPHD_W_RUN:
        m = json_pack("{s:I, s:o, s:b}", "max_steps", (json_int_t)cmd->max_steps, "until",
                      num_or_null(cmd->until), "resume", cmd->job && cmd->job->resume);
        break;
    case SPHD_W_PAUSE:
        kind = "pause";
        m = json_object();
        break;
    case SPHD_W_STOP:
        kind = "stop";
        m = json_object();
        break;
    case SPHD_W_QUIT:
        kind = "quit";
        m = json_object();
        break;
    case SPHD_W_STEER:
        kind = "steer";
        m = json_object();
        break;
    case SPHD_W_PARTICLES:
        kind = "particles";
        m = json_pack("{s:I, s:I, s:o, s:o, s:o}", "token", (json_int_t)cmd->token, "max",
                      (json_int_t)cmd->max, "fields", cmd->fields ? cmd->fields : json_null(),
                      "status", cmd->status ? cmd->status : json_null(), "id",
                      cmd->id ? cmd->id : json_null());
        cmd->fields = cmd->status = cmd->id = NULL;
        break;
    }
    char *text = m ? json_dumps(m, WIRE_FLAGS) : NULL;
    json_decref(m);
    if (!text)
        return -1;
    const char *parts[] = {runner, kind, text};
    const int rc = send_frames(router, ZMQ_DONTWAIT, parts, 3, (size_t)-1);
    free(text);
    return rc;
}

int sphd_wire_recv_wev(void *router, char *runner, size_t runner_len, sphd_wev *ev, json_t **hello)
{
    char *f[4];
    size_t len[4];
    int n = recv_frames(router, 0, f, len, 4);
    if (n <= 0)
        return n;
    memset(ev, 0, sizeof *ev);
    *hello = NULL;
    int rc = -1;
    json_t *m = n >= 3 ? json_loadb(f[2], len[2], 0, NULL) : NULL;
    if (m && len[0] < runner_len) {
        memcpy(runner, f[0], len[0]);
        runner[len[0]] = '\0';
        const char *kind = f[1];
        rc = 1;
        if (strcmp(kind, "hello") == 0) {
            *hello = json_incref(m);
        } else if (strcmp(kind, "event") == 0) {
            ev->kind = SPHD_WEV_EVENT;
            snprintf(ev->type, sizeof ev->type, "%s",
                     json_string_value(json_object_get(m, "type")) ?: "log");
            ev->body = json_incref(json_object_get(m, "body"));
        } else if (strcmp(kind, "progress") == 0) {
            ev->kind = SPHD_WEV_PROGRESS;
            ev->body = json_incref(json_object_get(m, "body"));
            ev->wall = num_or_nan(json_object_get(m, "wall"));
            ev->steps_per_s = num_or_nan(json_object_get(m, "steps_per_s"));
            ev->eta = num_or_nan(json_object_get(m, "eta"));
        } else if (strcmp(kind, "end") == 0) {
            ev->kind = SPHD_WEV_END;
            const char *e = json_string_value(json_object_get(m, "end"));
            ev->end = SPHD_END_FAILED;
            for (int i = 0; i < (int)(sizeof end_names / sizeof end_names[0]); i++)
                if (e && strcmp(e, end_names[i]) == 0)
                    ev->end = (sphd_end_kind)i;
            snprintf(ev->reason, sizeof ev->reason, "%s",
                     json_string_value(json_object_get(m, "reason")) ?: "");
            ev->wall = num_or_nan(json_object_get(m, "wall"));
            if (!isfinite(ev->wall))
                ev->wall = 0;
        } else if (strcmp(kind, "particles") == 0 && n >= 4) {
            ev->kind = SPHD_WEV_PARTICLES;
            ev->token = (long)json_integer_value(json_object_get(m, "token"));
            ev->text = f[3];
            f[3] = NULL;
        } else {
            rc = -1;
        }
    }
    json_decref(m);
    free_frames(f, n);
    return rc;
}
