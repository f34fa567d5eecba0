/*
 * sphd_http: the web dashboard (sphd --http HOST:PORT; PROTOCOL.md 3.13), served with
 * libmicrohttpd. It is a bridge, not a second way into a job:
 *
 *   GET  /, /app.js, ...   the page and its scripts, built into sphd (sphd_web.h)
 *   POST /api/request      one request of the wire protocol ({"op", "args"}), sent to sphd's
 *                          control socket as any client's and its reply returned as it is: the
 *                          same command table as sphctl's
 *   GET  /api/events       the event stream (sphd's PUB socket) as Server-Sent Events; ?job=ID
 *                          for one job's
 *
 * Security: a loopback address serves without a token, but only to requests whose Host is that
 * address (a page elsewhere cannot reach it through DNS rebinding); any other address needs the
 * token that sphd keeps in STATE_DIR/http.token (made at the first start, mode 600), sent in the
 * header X-Sphd-Token (never in a URL): without it every /api/ request is answered 401. A request
 * with an Origin other than the page's own is refused (403), and sphd sends no CORS header; a
 * request must be JSON (415) and no larger than --max-msg-size (413).
 *
 * Threads: libmicrohttpd's, one per connection; each makes its own ZeroMQ sockets in sphd's
 * context, and closes them before sphd_http_stop returns.
 */
#ifndef SPHD_HTTP_H
#define SPHD_HTTP_H

#include "sph_error.h"

#include <stddef.h>

typedef struct sphd_http sphd_http;

/* Serves the dashboard on addr ("127.0.0.1:8080", "[::1]:8080", "0.0.0.0:8080"; port 0: any
 * free one) for the sphd whose control and stream endpoints are given, in ZeroMQ context ctx.
 * state_dir holds the token; max_body bounds a request. url gets the dashboard's address. NULL
 * with err (SPH_ERR_INVALID: a bad address; SPH_ERR_IO: it cannot bind, or the token cannot be
 * made). */
sphd_http *sphd_http_start(const char *addr, void *ctx, const char *control, const char *stream,
                           const char *state_dir, long max_body, char *url, size_t url_len,
                           sph_error *err);

/* 1 if the dashboard asks for its token (a non-loopback address). */
int sphd_http_needs_token(const sphd_http *h);

/* Stops serving: the open event streams end, every connection's sockets are closed. */
void sphd_http_stop(sphd_http *h);

#endif
