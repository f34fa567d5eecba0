/*
 * sphd_curve: CURVE authentication and encryption of the control and stream sockets
 * (`sphd --curve DIR`). DIR holds the server's secret key (`server.key`, Z85, readable by its
 * owner only) and `clients/`, the authorised clients' public keys, one Z85 file per client (as
 * `sphctl keygen` writes them). The allow-list is enforced by a ZAP handler: a REP socket on
 * inproc://zeromq.zap.01 that the socket loop polls like its other sockets (the loop owns every
 * socket; the list is read and re-read on SIGHUP by that same thread, so it needs no lock).
 */
#ifndef SPHD_CURVE_H
#define SPHD_CURVE_H

#include <stddef.h>

typedef struct sphd_curve sphd_curve;

/* Reads DIR/server.key and DIR/clients/. NULL (reason on stderr) when the secret key is missing,
 * malformed or readable by others, or this libzmq has no CURVE. An empty clients/ is allowed
 * (nobody gets in until a key is added and sphd gets SIGHUP). */
sphd_curve *sphd_curve_load(const char *dir);

/* Binds the ZAP handler in ctx: call before the CURVE sockets bind. Returns 0 or -1 (logged). */
int sphd_curve_start(sphd_curve *cv, void *ctx);

/* The ZAP handler's socket, for the loop's poll. */
void *sphd_curve_zap_socket(const sphd_curve *cv);

/* Makes s a CURVE server with the server's key and the ZAP domain. Returns 0 or -1 (errno). */
int sphd_curve_server(const sphd_curve *cv, void *s);

/* The runners' key pair (sphd --executor slurm): DIR/runner.key (secret), DIR/runner.pub and
 * DIR/server.pub (this daemon's public key), made once in DIR (mode 700) on the shared state
 * directory; the runner key then opens the runners' socket, and only that one. Returns 0 or -1
 * (logged). */
int sphd_curve_runner_keys(sphd_curve *cv, const char *dir);
/* Makes s (the runners' ROUTER) a CURVE server that admits the runner key only. */
int sphd_curve_runners_server(const sphd_curve *cv, void *s);

/* Answers the ZAP requests that are waiting (the loop calls it when the socket is readable). */
void sphd_curve_on_zap(sphd_curve *cv);

/* Re-reads DIR/clients/ (SIGHUP). Returns the number of keys revoked (authorised before, not
 * now), or -1 when the directory cannot be read (the old list is kept). */
int sphd_curve_reload(sphd_curve *cv);

/* 1 when the Z85 public key (a message's "User-Id") is authorised now. */
int sphd_curve_authorised(const sphd_curve *cv, const char *z85);

/* The server's public key, Z85 (40 characters). */
const char *sphd_curve_public(const sphd_curve *cv);

/* Closes the ZAP socket and frees cv; NULL is a no-op. */
void sphd_curve_free(sphd_curve *cv);

#endif
