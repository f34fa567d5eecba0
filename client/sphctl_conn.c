/* sphctl's connection: one DEALER socket, one request at a time, a timeout on every reply;
 * sphctl_show prints a reply for a command. */
#include "sphctl.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <zmq.h>

double sphctl_mono(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int connect_control(sphctl *c)
{
    const char *path = sph_ipc_path(c->endpoint);
    struct stat st;
    if (path && stat(path, &st) != 0) {
        fprintf(stderr,
                "sphctl: sphd is not running at %s (no socket there); start it with 'sphd'\n",
                c->endpoint);
        return SPHCTL_EX_UNAVAILABLE;
    }
    if (!c->ctx && !(c->ctx = zmq_ctx_new())) {
        fprintf(stderr, "sphctl: cannot create a ZeroMQ context: %s\n", zmq_strerror(errno));
        return SPHCTL_EX_SOFTWARE;
    }
    c->sock = zmq_socket(c->ctx, ZMQ_DEALER);
    int zero = 0;
    if (!c->sock || zmq_setsockopt(c->sock, ZMQ_LINGER, &zero, sizeof zero) != 0) {
        fprintf(stderr, "sphctl: cannot create a socket: %s\n", zmq_strerror(errno));
        return SPHCTL_EX_SOFTWARE;
    }
    if (sphctl_secure(c, c->sock) != 0)
        return SPHCTL_EX_SOFTWARE;
    /* a refused handshake is told apart from a server that does not answer */
    c->mon = sphctl_monitor(c, c->sock, "control");
    if (zmq_connect(c->sock, c->endpoint) != 0) {
        fprintf(stderr, "sphctl: cannot connect to %s: %s\n", c->endpoint, zmq_strerror(errno));
        return errno == EINVAL || errno == EPROTONOSUPPORT ? SPHCTL_EX_USAGE
                                                           : SPHCTL_EX_UNAVAILABLE;
    }
    return 0;
}

static void close_control(sphctl *c)
{
    if (c->mon)
        zmq_close(c->mon);
    c->mon = NULL;
    if (c->sock)
        zmq_close(c->sock);
    c->sock = NULL;
}

void sphctl_close(sphctl *c)
{
    close_control(c);
    if (c->ctx)
        zmq_ctx_term(c->ctx);
    c->ctx = NULL;
}

/* Sends one request. zmq_send waits while the socket has no pipe to the server, as when a
 * handshake was refused and the connection torn down (a plain client meeting a CURVE server):
 * the wait watches the monitor, so that a refusal is told at once, and ends at the timeout. */
static int send_request(sphctl *c, const char *text, size_t len)
{
    const double until = sphctl_mono() + c->timeout;
    for (;;) {
        if (zmq_send(c->sock, text, len, ZMQ_DONTWAIT) >= 0)
            return 0;
        if (errno == EINTR)
            continue;
        if (errno != EAGAIN) {
            fprintf(stderr, "sphctl: cannot send to %s: %s\n", c->endpoint, zmq_strerror(errno));
            return SPHCTL_EX_UNAVAILABLE;
        }
        if (c->mon && sphctl_refused(c, c->mon, c->endpoint)) {
            close_control(c);
            return SPHCTL_EX_NOPERM;
        }
        const double left = until - sphctl_mono();
        if (left <= 0) {
            fprintf(stderr, "sphctl: no connection to sphd at %s within %g s (is it running?)\n",
                    c->endpoint, c->timeout);
            close_control(c);
            return SPHCTL_EX_UNAVAILABLE;
        }
        zmq_pollitem_t it[2] = {{.socket = c->sock, .events = ZMQ_POLLOUT},
                                {.socket = c->mon, .events = ZMQ_POLLIN}};
        if (zmq_poll(it, c->mon ? 2 : 1, (long)(left * 1000) + 1) < 0 && errno != EINTR) {
            fprintf(stderr, "sphctl: cannot send to %s: %s\n", c->endpoint, zmq_strerror(errno));
            return SPHCTL_EX_SOFTWARE;
        }
    }
}

static int exit_code_for(const char *code)
{
    if (strcmp(code, "invalid_case") == 0)
        return SPHCTL_EX_DATAERR;
    if (strcmp(code, "busy") == 0)
        return SPHCTL_EX_TEMPFAIL;
    if (strcmp(code, "not_authorised") == 0)
        return SPHCTL_EX_NOPERM;
    return SPHCTL_EX_FAILED;
}

int sphctl_request(sphctl *c, const char *op, json_t *args, json_t **result, char *errcode,
                   size_t errcode_len)
{
    *result = NULL;
    if (errcode && errcode_len)
        errcode[0] = '\0';
    char id[32];
    snprintf(id, sizeof id, "sphctl-%ld", ++c->next_id);
    json_t *req = json_pack("{s:i, s:s, s:s, s:o}", "v", 1, "id", id, "op", op, "args",
                            args ? args : json_object());
    char *text = req ? json_dumps(req, JSON_COMPACT) : NULL;
    json_decref(req);
    if (!text) {
        fprintf(stderr, "sphctl: out of memory\n");
        return SPHCTL_EX_SOFTWARE;
    }
    size_t len = strlen(text);
    if ((long)len > SPHCTL_MAX_REQUEST) {
        fprintf(stderr, "sphctl: the request is %zu bytes, more than sphd accepts (%ld)\n", len,
                SPHCTL_MAX_REQUEST);
        free(text);
        return SPHCTL_EX_DATAERR;
    }
    int rc;
    if (!c->sock && (rc = connect_control(c)) != 0) {
        free(text);
        return rc;
    }
    rc = send_request(c, text, len);
    free(text);
    if (rc)
        return rc;
    long wait_ms = (long)(c->timeout * 1000);
    for (;;) {
        zmq_pollitem_t it[2] = {{.socket = c->sock, .events = ZMQ_POLLIN},
                                {.socket = c->mon, .events = ZMQ_POLLIN}};
        int n = zmq_poll(it, c->mon ? 2 : 1, wait_ms);
        if (n < 0 && errno == EINTR)
            continue;
        if (c->mon && (n == 0 || (it[1].revents & ZMQ_POLLIN)) &&
            sphctl_refused(c, c->mon, c->endpoint)) {
            close_control(c);
            return SPHCTL_EX_NOPERM;
        }
        if (n > 0 && !(it[0].revents & ZMQ_POLLIN))
            continue; /* a monitor event that is no refusal (the wait starts again) */
        if (n <= 0) {
            fprintf(stderr, "sphctl: no reply from sphd at %s within %g s (is it running?)\n",
                    c->endpoint, c->timeout);
            /* a late reply must not be taken for the next request's */
            close_control(c);
            return SPHCTL_EX_UNAVAILABLE;
        }
        zmq_msg_t m;
        zmq_msg_init(&m);
        if (zmq_msg_recv(&m, c->sock, 0) < 0) {
            zmq_msg_close(&m);
            continue;
        }
        json_error_t jerr;
        json_t *reply = json_loadb(zmq_msg_data(&m), zmq_msg_size(&m), 0, &jerr);
        int more = zmq_msg_more(&m);
        zmq_msg_close(&m);
        while (more) { /* replies are one frame; drain anything else */
            zmq_msg_init(&m);
            if (zmq_msg_recv(&m, c->sock, 0) < 0)
                more = 0;
            else
                more = zmq_msg_more(&m);
            zmq_msg_close(&m);
        }
        if (!reply) {
            fprintf(stderr, "sphctl: sphd sent a reply that is not JSON: %s\n", jerr.text);
            return SPHCTL_EX_SOFTWARE;
        }
        const char *rid = json_string_value(json_object_get(reply, "id"));
        if (!rid || strcmp(rid, id) != 0) {
            json_decref(reply);
            continue; /* a reply to an earlier request */
        }
        if (json_is_true(json_object_get(reply, "ok"))) {
            *result = json_incref(json_object_get(reply, "result"));
            json_decref(reply);
            return 0;
        }
        json_t *err = json_object_get(reply, "error");
        const char *code = json_string_value(json_object_get(err, "code"));
        const char *msg = json_string_value(json_object_get(err, "message"));
        const char *path = json_string_value(json_object_get(err, "path"));
        code = code ? code : "internal";
        if (errcode && errcode_len)
            snprintf(errcode, errcode_len, "%s", code);
        if (strcmp(code, "invalid_case") == 0 && c->file)
            fprintf(stderr, "sphctl: %s: invalid case: %s%s%s%s\n", c->file, msg ? msg : "",
                    path && *path ? " (at " : "", path && *path ? path : "",
                    path && *path ? ")" : "");
        else
            fprintf(stderr, "sphctl: %s: %s%s%s%s\n", code, msg ? msg : "",
                    path && *path ? " (at " : "", path && *path ? path : "",
                    path && *path ? ")" : "");
        if (c->json)
            sphctl_print_json(reply, 1);
        rc = exit_code_for(code);
        json_decref(reply);
        return rc;
    }
}

int sphctl_show(sphctl *c, const char *op, json_t *args,
                void (*human)(const json_t *r, const void *ud), const void *ud)
{
    json_t *r;
    int rc = sphctl_request(c, op, args, &r, NULL, 0);
    if (rc)
        return rc;
    if (c->json || !human)
        sphctl_print_json(r, c->json);
    else
        human(r, ud);
    json_decref(r);
    return 0;
}
