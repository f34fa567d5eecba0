/*
 * sphd_http: the web dashboard (sphd_http.h): libmicrohttpd in its threads, one per connection;
 * the page from sphd_web_files; requests and events bridged to sphd's own ZeroMQ sockets.
 */
#include "sphd_http.h"

#include "sph_fileio.h"
#include "sph_json.h"
#include "sphd_web.h"

#include <arpa/inet.h>
#include <errno.h>
#include <fcntl.h>
#include <jansson.h>
#include <microhttpd.h>
#include <netdb.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/random.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>
#include <zmq.h>

#define REQUEST_TIMEOUT_MS 120000 /* a deferred reply (pause, set) comes at a step boundary */
#define EVENT_POLL_MS      250    /* how often an event stream looks at sphd_http_stop */
#define HEARTBEAT_S                                                                                \
    10.0 /* a comment line on a quiet stream keeps it open (the                                    \
            connections time out after 60 s without traffic) */
#define TOKEN_BYTES 24

struct sphd_http {
    struct MHD_Daemon *mhd;
    void *ctx;
    char control[256], stream[256];
    char token[2 * TOKEN_BYTES + 1]; /* "" when none is needed (loopback) */
    char hosts[2][300];              /* loopback: the Host values that are this server */
    long max_body;
    atomic_int stopping;
};

/* ---- addresses and the token ---- */

static int parse_addr(const char *addr, char *host, size_t hn, char *port, size_t pn)
{
    const char *colon = strrchr(addr, ':');
    if (!colon || colon == addr || !colon[1] || strlen(colon + 1) >= pn)
        return -1;
    const char *h = addr, *e = colon;
    if (*h == '[') { /* [v6]:port */
        if (e[-1] != ']')
            return -1;
        h++;
        e--;
    }
    if ((size_t)(e - h) >= hn || e == h)
        return -1;
    snprintf(host, hn, "%.*s", (int)(e - h), h);
    snprintf(port, pn, "%s", colon + 1);
    for (const char *p = port; *p; p++)
        if (*p < '0' || *p > '9')
            return -1;
    return 0;
}

static int is_loopback(const struct sockaddr *sa)
{
    if (sa->sa_family == AF_INET)
        return (ntohl(((const struct sockaddr_in *)sa)->sin_addr.s_addr) >> 24) == 127;
    if (sa->sa_family == AF_INET6)
        return IN6_IS_ADDR_LOOPBACK(&((const struct sockaddr_in6 *)sa)->sin6_addr);
    return 0;
}

/* STATE_DIR/http.token: read, or made (random, mode 600) when there is none. */
static int load_token(const char *state_dir, char *tok, size_t n, sph_error *err)
{
    char path[4096];
    snprintf(path, sizeof path, "%s/http.token", state_dir);
    FILE *f = fopen(path, "r");
    if (f) {
        struct stat st;
        const int ok =
            fstat(fileno(f), &st) == 0 && (st.st_mode & 077) == 0 && fgets(tok, (int)n, f) != NULL;
        fclose(f);
        tok[strcspn(tok, "\r\n")] = '\0';
        if (!ok || strlen(tok) < 16)
            return sph_error_set(err, SPH_ERR_IO, "",
                                 "%s must hold a token of at least 16 characters and be readable "
                                 "by its owner only (chmod 600)",
                                 path);
        return 0;
    }
    unsigned char raw[TOKEN_BYTES];
    if (getrandom(raw, sizeof raw, 0) != (ssize_t)sizeof raw)
        return sph_error_set(err, SPH_ERR_IO, "", "cannot make a token: %s", strerror(errno));
    for (int i = 0; i < TOKEN_BYTES; i++)
        snprintf(tok + 2 * i, 3, "%02x", raw[i]);
    const int fd = open(path, O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
    if (fd < 0 || sph_write_all(fd, tok, strlen(tok)) != 0 || sph_write_all(fd, "\n", 1) != 0) {
        const int e = errno;
        if (fd >= 0)
            close(fd);
        return sph_error_set(err, SPH_ERR_IO, "", "cannot write %s: %s", path, strerror(e));
    }
    close(fd);
    return 0;
}

/* Compares in a time that does not depend on where they differ. */
static int same_secret(const char *a, const char *b)
{
    const size_t n = strlen(b);
    if (!a || strlen(a) != n)
        return 0;
    unsigned char d = 0;
    for (size_t i = 0; i < n; i++)
        d |= (unsigned char)(a[i] ^ b[i]);
    return d == 0;
}

/* ---- responses ---- */

static enum MHD_Result send_buf(struct MHD_Connection *c, unsigned status, const char *type,
                                const void *data, size_t len, int copy)
{
    struct MHD_Response *r = MHD_create_response_from_buffer(
        len, (void *)data, copy ? MHD_RESPMEM_MUST_COPY : MHD_RESPMEM_PERSISTENT);
    if (!r)
        return MHD_NO;
    MHD_add_response_header(r, "Content-Type", type);
    MHD_add_response_header(r, "Cache-Control", "no-store");
    MHD_add_response_header(r, "X-Content-Type-Options", "nosniff");
    MHD_add_response_header(r, "X-Frame-Options", "DENY");
    MHD_add_response_header(r, "Referrer-Policy", "no-referrer");
    MHD_add_response_header(r, "Content-Security-Policy",
                            "default-src 'self'; style-src 'self' 'unsafe-inline'; "
                            "img-src 'self' data:; frame-ancestors 'none'");
    const enum MHD_Result rc = MHD_queue_response(c, status, r);
    MHD_destroy_response(r);
    return rc;
}

/* {"error": {"code", "message"}}: the dashboard's own refusals (the wire's are sphd's). */
static enum MHD_Result send_error(struct MHD_Connection *c, unsigned status, const char *code,
                                  const char *msg)
{
    json_t *j = json_pack("{s:b, s:{s:s, s:s}}", "ok", 0, "error", "code", code, "message", msg);
    char *text = j ? json_dumps(j, JSON_COMPACT) : NULL;
    json_decref(j);
    if (!text)
        return MHD_NO;
    const enum MHD_Result rc = send_buf(c, status, "application/json", text, strlen(text), 1);
    free(text);
    return rc;
}

static const char *content_type(const char *path)
{
    const char *dot = strrchr(path, '.');
    if (dot && strcmp(dot, ".html") == 0)
        return "text/html; charset=utf-8";
    if (dot && strcmp(dot, ".js") == 0)
        return "text/javascript; charset=utf-8";
    if (dot && strcmp(dot, ".css") == 0)
        return "text/css; charset=utf-8";
    return "application/octet-stream";
}

/* ---- the bridge ---- */

/* One request sent to sphd's control socket; its reply (new string) or NULL on a timeout. */
static char *forward(sphd_http *h, const char *body, size_t len)
{
    void *s = zmq_socket(h->ctx, ZMQ_DEALER);
    if (!s)
        return NULL;
    const int zero = 0;
    zmq_setsockopt(s, ZMQ_LINGER, &zero, sizeof zero);
    char *reply = NULL;
    if (zmq_connect(s, h->control) == 0 && zmq_send(s, body, len, 0) == (int)len) {
        zmq_pollitem_t it = {.socket = s, .events = ZMQ_POLLIN};
        if (zmq_poll(&it, 1, REQUEST_TIMEOUT_MS) == 1) {
            zmq_msg_t m;
            zmq_msg_init(&m);
            if (zmq_msg_recv(&m, s, 0) >= 0 && (reply = malloc(zmq_msg_size(&m) + 1))) {
                memcpy(reply, zmq_msg_data(&m), zmq_msg_size(&m));
                reply[zmq_msg_size(&m)] = '\0';
            }
            zmq_msg_close(&m);
        }
    }
    zmq_close(s);
    return reply;
}

typedef struct upload {
    char *buf;
    size_t len;
    int too_large;
} upload;

static enum MHD_Result do_request(sphd_http *h, struct MHD_Connection *c, upload *u)
{
    if (u->too_large) {
        char msg[128];
        snprintf(msg, sizeof msg, "a request may hold at most %ld bytes (--max-msg-size)",
                 h->max_body);
        return send_error(c, MHD_HTTP_CONTENT_TOO_LARGE, "too_large", msg);
    }
    json_error_t je;
    json_t *req = u->buf ? json_loadb(u->buf, u->len, 0, &je) : NULL;
    if (!json_is_object(req) || !json_is_string(json_object_get(req, "op"))) {
        json_decref(req);
        return send_error(c, MHD_HTTP_BAD_REQUEST, "bad_request",
                          "the body is one request of the wire protocol: {\"op\": ..., "
                          "\"args\": {...}}");
    }
    if (!json_object_get(req, "v"))
        json_object_set_new(req, "v", json_integer(1));
    if (!json_object_get(req, "id"))
        json_object_set_new(req, "id", json_string("http"));
    char *text = json_dumps(req, JSON_COMPACT);
    json_decref(req);
    char *reply = text ? forward(h, text, strlen(text)) : NULL;
    free(text);
    if (!reply)
        return send_error(c, MHD_HTTP_GATEWAY_TIMEOUT, "timeout",
                          "sphd did not answer in time; ask again");
    const enum MHD_Result rc =
        send_buf(c, MHD_HTTP_OK, "application/json", reply, strlen(reply), 1);
    free(reply);
    return rc;
}

/* An event stream: sphd's PUB, subscribed in the connection's thread. */
typedef struct events {
    sphd_http *h;
    void *sub;
    char topic[80];
    char *pending; /* what is left of the latest message to send */
    size_t off, len;
    double last;
} events;

static double mono(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static ssize_t events_read(void *cls, uint64_t pos, char *buf, size_t max)
{
    (void)pos;
    events *ev = cls;
    if (!ev->sub) {
        ev->sub = zmq_socket(ev->h->ctx, ZMQ_SUB);
        const int zero = 0;
        if (!ev->sub)
            return MHD_CONTENT_READER_END_WITH_ERROR;
        zmq_setsockopt(ev->sub, ZMQ_LINGER, &zero, sizeof zero);
        zmq_setsockopt(ev->sub, ZMQ_SUBSCRIBE, ev->topic, strlen(ev->topic));
        if (zmq_connect(ev->sub, ev->h->stream) != 0)
            return MHD_CONTENT_READER_END_WITH_ERROR;
        ev->last = mono();
        static const char hello[] = ": sphd events\n\n";
        memcpy(buf, hello, sizeof hello - 1 < max ? sizeof hello - 1 : max);
        return (ssize_t)(sizeof hello - 1 < max ? sizeof hello - 1 : max);
    }
    while (!ev->pending) {
        if (atomic_load(&ev->h->stopping))
            return MHD_CONTENT_READER_END_OF_STREAM;
        zmq_pollitem_t it = {.socket = ev->sub, .events = ZMQ_POLLIN};
        if (zmq_poll(&it, 1, EVENT_POLL_MS) == 1) {
            /* [topic, body]: the body (the last part) becomes one SSE message */
            zmq_msg_t m;
            int more = 1;
            zmq_msg_init(&m);
            while (more) {
                if (zmq_msg_recv(&m, ev->sub, 0) < 0) {
                    zmq_msg_close(&m);
                    return MHD_CONTENT_READER_END_WITH_ERROR;
                }
                more = zmq_msg_more(&m);
            }
            const size_t n = zmq_msg_size(&m);
            ev->pending = malloc(n + 9);
            if (!ev->pending) {
                zmq_msg_close(&m);
                return MHD_CONTENT_READER_END_WITH_ERROR;
            }
            memcpy(ev->pending, "data: ", 6);
            memcpy(ev->pending + 6, zmq_msg_data(&m), n);
            /* a JSON body holds no raw newline: one data line */
            for (size_t i = 6; i < 6 + n; i++)
                if (ev->pending[i] == '\n' || ev->pending[i] == '\r')
                    ev->pending[i] = ' ';
            memcpy(ev->pending + 6 + n, "\n\n", 2);
            ev->len = n + 8;
            ev->off = 0;
            zmq_msg_close(&m);
        } else if (mono() - ev->last > HEARTBEAT_S) {
            ev->last = mono();
            static const char beat[] = ": .\n\n";
            const size_t k = sizeof beat - 1 < max ? sizeof beat - 1 : max;
            memcpy(buf, beat, k);
            return (ssize_t)k;
        }
    }
    const size_t k = ev->len - ev->off < max ? ev->len - ev->off : max;
    memcpy(buf, ev->pending + ev->off, k);
    ev->off += k;
    if (ev->off == ev->len) {
        free(ev->pending);
        ev->pending = NULL;
    }
    ev->last = mono();
    return (ssize_t)k;
}

static void events_free(void *cls)
{
    events *ev = cls;
    if (ev->sub)
        zmq_close(ev->sub);
    free(ev->pending);
    free(ev);
}

static enum MHD_Result do_events(sphd_http *h, struct MHD_Connection *c)
{
    events *ev = calloc(1, sizeof *ev);
    if (!ev)
        return MHD_NO;
    ev->h = h;
    const char *job = MHD_lookup_connection_value(c, MHD_GET_ARGUMENT_KIND, "job");
    if (job)
        snprintf(ev->topic, sizeof ev->topic, "%s", job);
    struct MHD_Response *r =
        MHD_create_response_from_callback(MHD_SIZE_UNKNOWN, 4096, events_read, ev, events_free);
    if (!r) {
        free(ev);
        return MHD_NO;
    }
    MHD_add_response_header(r, "Content-Type", "text/event-stream");
    MHD_add_response_header(r, "Cache-Control", "no-store");
    MHD_add_response_header(r, "X-Content-Type-Options", "nosniff");
    const enum MHD_Result rc = MHD_queue_response(c, MHD_HTTP_OK, r);
    MHD_destroy_response(r);
    return rc;
}

/* ---- the handler ---- */

/* The checks every request passes: Host (loopback), Origin, the token for /api/. 0, or the
 * refusal already queued (*rc). */
static int refused(sphd_http *h, struct MHD_Connection *c, const char *url, enum MHD_Result *rc)
{
    const char *host = MHD_lookup_connection_value(c, MHD_HEADER_KIND, "Host");
    if (!h->token[0]) {
        int ok = 0;
        for (int i = 0; i < 2 && host; i++)
            ok |= strcmp(host, h->hosts[i]) == 0;
        if (!ok) {
            *rc = send_error(c, MHD_HTTP_FORBIDDEN, "forbidden",
                             "this dashboard answers to its own address only (the Host header)");
            return 1;
        }
    }
    const char *origin = MHD_lookup_connection_value(c, MHD_HEADER_KIND, "Origin");
    if (origin) {
        char own[320];
        snprintf(own, sizeof own, "http://%s", host ? host : "");
        if (strcmp(origin, own) != 0) {
            *rc = send_error(c, MHD_HTTP_FORBIDDEN, "forbidden",
                             "a request from another origin is refused");
            return 1;
        }
    }
    if (h->token[0] && strncmp(url, "/api/", 5) == 0 &&
        !same_secret(MHD_lookup_connection_value(c, MHD_HEADER_KIND, "X-Sphd-Token"), h->token)) {
        *rc = send_error(c, MHD_HTTP_UNAUTHORIZED, "unauthorized",
                         "this dashboard needs its token (the file http.token in sphd's state "
                         "directory) in the header X-Sphd-Token");
        return 1;
    }
    return 0;
}

static enum MHD_Result handler(void *cls, struct MHD_Connection *c, const char *url,
                               const char *method, const char *version, const char *data,
                               size_t *size, void **con_cls)
{
    (void)version;
    sphd_http *h = cls;
    const int post = strcmp(method, "POST") == 0;
    if (!*con_cls) { /* the headers: the checks, before any body is read */
        enum MHD_Result rc;
        if (refused(h, c, url, &rc))
            return rc;
        if (post) {
            if (strcmp(url, "/api/request") != 0)
                return send_error(c, MHD_HTTP_NOT_FOUND, "not_found", "POST /api/request only");
            const char *ct = MHD_lookup_connection_value(c, MHD_HEADER_KIND, "Content-Type");
            if (!ct || strncmp(ct, "application/json", 16) != 0)
                return send_error(c, MHD_HTTP_UNSUPPORTED_MEDIA_TYPE, "bad_request",
                                  "the body must be JSON (Content-Type: application/json)");
            upload *u = calloc(1, sizeof *u);
            if (!u)
                return MHD_NO;
            *con_cls = u;
            return MHD_YES;
        }
        *con_cls = h; /* a GET: nothing to keep */
    }
    if (post) {
        upload *u = *con_cls;
        if (*size) {
            if (!u->too_large && u->len + *size <= (size_t)h->max_body) {
                char *b = realloc(u->buf, u->len + *size + 1);
                if (!b)
                    return MHD_NO;
                u->buf = b;
                memcpy(u->buf + u->len, data, *size);
                u->len += *size;
            } else {
                u->too_large = 1;
            }
            *size = 0;
            return MHD_YES;
        }
        return do_request(h, c, u);
    }
    if (strcmp(method, "GET") != 0 && strcmp(method, "HEAD") != 0)
        return send_error(c, MHD_HTTP_METHOD_NOT_ALLOWED, "bad_request", "GET or POST");
    if (strcmp(url, "/api/events") == 0)
        return do_events(h, c);
    const char *path = strcmp(url, "/") == 0 ? "/index.html" : url;
    for (const sphd_web_file *f = sphd_web_files; f->path; f++)
        if (strcmp(f->path, path) == 0)
            return send_buf(c, MHD_HTTP_OK, content_type(path), f->data, f->len, 0);
    return send_error(c, MHD_HTTP_NOT_FOUND, "not_found", "no such page");
}

static void completed(void *cls, struct MHD_Connection *c, void **con_cls,
                      enum MHD_RequestTerminationCode toe)
{
    (void)c;
    (void)toe;
    if (*con_cls && *con_cls != cls) {
        upload *u = *con_cls;
        free(u->buf);
        free(u);
    }
    *con_cls = NULL;
}

sphd_http *sphd_http_start(const char *addr, void *ctx, const char *control, const char *stream,
                           const char *state_dir, long max_body, char *url, size_t url_len,
                           sph_error *err)
{
    char host[256], port[16];
    if (parse_addr(addr, host, sizeof host, port, sizeof port) != 0) {
        sph_error_set(err, SPH_ERR_INVALID, "",
                      "--http takes HOST:PORT (127.0.0.1:8080, [::1]:8080, 0.0.0.0:8080), not "
                      "'%s'",
                      addr);
        return NULL;
    }
    struct addrinfo hints = {.ai_flags = AI_NUMERICSERV | AI_PASSIVE, .ai_socktype = SOCK_STREAM};
    struct addrinfo *ai = NULL;
    const int g = getaddrinfo(host, port, &hints, &ai);
    if (g != 0 || !ai) {
        sph_error_set(err, SPH_ERR_INVALID, "", "--http %s: %s", addr, gai_strerror(g));
        return NULL;
    }
    sphd_http *h = calloc(1, sizeof *h);
    if (!h) {
        freeaddrinfo(ai);
        sph_error_set(err, SPH_ERR_NOMEM, "", "out of memory");
        return NULL;
    }
    h->ctx = ctx;
    h->max_body = max_body;
    snprintf(h->control, sizeof h->control, "%s", control);
    snprintf(h->stream, sizeof h->stream, "%s", stream);
    const int loop = is_loopback(ai->ai_addr);
    if (!loop && load_token(state_dir, h->token, sizeof h->token, err) != 0) {
        freeaddrinfo(ai);
        free(h);
        return NULL;
    }
    h->mhd =
        MHD_start_daemon(MHD_USE_THREAD_PER_CONNECTION | MHD_USE_INTERNAL_POLLING_THREAD |
                             (ai->ai_family == AF_INET6 ? MHD_USE_IPv6 : 0),
                         0, NULL, NULL, handler, h, MHD_OPTION_SOCK_ADDR, ai->ai_addr,
                         MHD_OPTION_NOTIFY_COMPLETED, completed, h, MHD_OPTION_CONNECTION_LIMIT,
                         64u, MHD_OPTION_CONNECTION_TIMEOUT, 60u, MHD_OPTION_END);
    freeaddrinfo(ai);
    if (!h->mhd) {
        sph_error_set(err, SPH_ERR_IO, "", "--http %s: cannot serve there (in use?)", addr);
        free(h);
        return NULL;
    }
    const union MHD_DaemonInfo *di = MHD_get_daemon_info(h->mhd, MHD_DAEMON_INFO_BIND_PORT);
    const unsigned p = di ? di->port : (unsigned)atoi(port);
    const int v6 = strchr(host, ':') != NULL;
    snprintf(url, url_len, "http://%s%s%s:%u/", v6 ? "[" : "", host, v6 ? "]" : "", p);
    snprintf(h->hosts[0], sizeof h->hosts[0], "%s%s%s:%u", v6 ? "[" : "", host, v6 ? "]" : "", p);
    snprintf(h->hosts[1], sizeof h->hosts[1], "localhost:%u", p);
    return h;
}

int sphd_http_needs_token(const sphd_http *h)
{
    return h && h->token[0];
}

void sphd_http_stop(sphd_http *h)
{
    if (!h)
        return;
    atomic_store(&h->stopping, 1);
    MHD_stop_daemon(h->mhd);
    free(h);
}
