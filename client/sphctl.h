/*
 * sphctl: the client of sphd. Internal interfaces of its files.
 *
 * The files call each other downwards only; floors, bottom up:
 *   sphctl_util.c                   shared helpers (command-line parsing, printing)
 *   sphctl_curve.c                  settings, CURVE keys, socket monitor, keygen
 *   sphctl_conn.c                   the control connection: requests
 *   sphctl_watch.c, sphctl_files.c, the event stream; the result-file commands; parameter
 *   sphctl_sweep.c                  sweeps
 *   sphctl.c                        main and the command table
 */
#ifndef SPHCTL_H
#define SPHCTL_H

#include "sph_endpoint.h"

#include <getopt.h>
#include <jansson.h>

/* sysexits.h codes (DESIGN.md section 3). */
#define SPHCTL_EX_OK          0
#define SPHCTL_EX_FAILED      1
#define SPHCTL_EX_USAGE       64
#define SPHCTL_EX_DATAERR     65
#define SPHCTL_EX_NOINPUT     66
#define SPHCTL_EX_UNAVAILABLE 69
#define SPHCTL_EX_SOFTWARE    70
#define SPHCTL_EX_CANTCREAT   73
#define SPHCTL_EX_TEMPFAIL    75
#define SPHCTL_EX_NOPERM      77
#define SPHCTL_EX_CONFIG      78

#define SPHCTL_MAX_REQUEST (16L << 20) /* sphd's default --max-msg-size */

typedef struct sphctl {
    char endpoint[SPH_ENDPOINT_MAX];
    int json;       /* --json */
    double timeout; /* seconds per request */
    void *ctx;
    void *sock; /* DEALER to the control endpoint, NULL until the first request */
    void *mon;  /* its socket monitor (handshake failures), or NULL */
    int curve;  /* CURVE on: the three keys below are set (Z85) */
    char server_key[41], public_key[41], secret_key[41];
    long next_id;
    const char *file; /* for messages about a case file */
} sphctl;

/* ---- sphctl_util.c: the command line of one command, JSON and human formatting ---- */

/* Prints "sphctl: " fmt (with arg) and a pointer to 'sphctl CMD --help' to stderr; returns 64. */
int sphctl_usage(const char *cmd, const char *fmt, const char *arg);

#define SPHCTL_RUN (-1) /* sphctl_args: go on and run the command */

typedef struct sphctl_argspec {
    const char *help;          /* printed on stdout for --help */
    const char *optstring;     /* getopt_long's: "h", or "+h" to stop at the first positional */
    const struct option *opts; /* the long options, --help included; NULL: --help only */
    const char *bad_option;    /* the message for an unknown option; NULL: "bad option for CMD" */
    int min_args, max_args;    /* how many positionals */
    const char *bad_count;     /* the message for another count; NULL: "CMD takes N argument(s)"
                                  and the help, on stderr */
} sphctl_argspec;

/* Parses argv (argv[0] is the command's name) from optind = 0. Every option but --help goes to
 * on_opt(ud, o, optarg) (may be NULL), which returns 0 or an exit code that ends the parse.
 * Returns SPHCTL_RUN with the positionals from argv[optind], else the exit code to return: 0
 * after --help, 64 on a usage error, or on_opt's. */
int sphctl_args(const sphctl_argspec *spec, int argc, char **argv,
                int (*on_opt)(void *ud, int o, const char *arg), void *ud);

/* --resources JSON (submit, sweep): *out gets the object (replacing what it held), or returns
 * the usage error (64). */
int sphctl_resources_opt(const char *cmd, const char *arg, json_t **out);

/* An on_opt for sphctl_args: ud is an array of const char *, indexed by the option's val (from
 * 0), that gets the option's value ("" for an option without one). */
int sphctl_store_opt(void *ud, int o, const char *arg);

/* Prints a JSON value as one line (compact) or indented, to stdout. */
void sphctl_print_json(const json_t *v, int compact);

/* Human formatting helpers. */
void sphctl_fmt_duration(double s, char *buf, size_t n);

/* The number o[k], NaN when it is not a number. */
double sphctl_num(const json_t *o, const char *k);

/* A sweep job's params ({"dotted.path": value}) as "path=value path=value" (strings bare, other
 * values as compact JSON) into buf (truncated to n); the paths in order (an array of strings,
 * may be NULL) first, then the others in the object's order. Returns buf. */
const char *sphctl_fmt_params(const json_t *params, const json_t *order, char *buf, size_t n);

/* ---- sphctl_curve.c: settings, CURVE keys, the socket monitor, keygen ---- */

/* The endpoint and the CURVE keys from the options given (NULL: not given), the environment or
 * the config file. Returns 0 or an exit code (said on stderr). */
int sphctl_settings(sphctl *c, const char *endpoint, const char *server_key, const char *key);
/* $XDG_CONFIG_HOME/sphctl or ~/.config/sphctl. Returns 0 or -1. */
int sphctl_config_dir(char *out, size_t n);
/* Sets the CURVE client keys on sock when CURVE is on. Returns 0 or -1 (said). */
int sphctl_secure(sphctl *c, void *sock);
/* A PAIR receiving sock's handshake events (name: unique per socket), or NULL. */
void *sphctl_monitor(sphctl *c, void *sock, const char *name);
/* Reads what mon has; 1 when it reports that sphd refused the handshake (said on stderr, with
 * why: key not authorised, CURVE required, ...), else 0. */
int sphctl_refused(sphctl *c, void *mon, const char *endpoint);
/* The same, and sets *connected (when not NULL) if a handshake succeeded. */
int sphctl_monitor_read(sphctl *c, void *mon, const char *endpoint, int *connected);
int sphctl_cmd_keygen(sphctl *c, int argc, char **argv);

/* ---- sphctl_conn.c: the control connection, one request at a time ---- */

/* Sends {"v":1,"id":..,"op":op,"args":args} (args stolen, may be NULL) and waits for the reply,
 * at most c->timeout seconds. On success returns 0 and *result (new ref). On a refusal prints the
 * error to stderr and returns its exit code (65 invalid_case, 75 busy, 1 otherwise); 69 when the
 * server does not answer. *errcode gets the error code name when not NULL (static storage). */
int sphctl_request(sphctl *c, const char *op, json_t *args, json_t **result, char *errcode,
                   size_t errcode_len);

void sphctl_close(sphctl *c);

/* Sends op with args (stolen, may be NULL); on success prints the result, with --json as one
 * compact line, else with human(r, ud) (NULL: indented JSON). Returns the exit code. */
int sphctl_show(sphctl *c, const char *op, json_t *args,
                void (*human)(const json_t *r, const void *ud), const void *ud);

/* ---- sphctl_watch.c: the event stream, subscribed and connected ---- */

typedef struct sphctl_stream {
    void *sub;                 /* SUB socket */
    void *mon;                 /* its monitor */
    char topic[128];           /* what it is subscribed to ("" = every job) */
    char ep[SPH_ENDPOINT_MAX]; /* the stream endpoint */
    int connected;             /* its handshake was seen before sphctl_stream_open returned */
} sphctl_stream;
/* Subscribes to topic (a job id, or "" for every job, when the id is not known yet) and waits
 * up to c->timeout for the connection's handshake, so that events published after it returns
 * reach it. Returns 0 or the exit code (said). */
int sphctl_stream_open(sphctl *c, const char *topic, sphctl_stream *st);
void sphctl_stream_close(sphctl_stream *st);
/* Follows job to its end on an open stream (subscribe, then snapshot), and closes it; with
 * from_start (the stream was connected before the job was created) every event of the job is
 * on the stream, so it is followed from its first event, without a snapshot. Returns the exit
 * code: 0 done, 1 failed or stopped, 69 server gone. */
int sphctl_watch_stream(sphctl *c, sphctl_stream *st, const char *job, int from_start);
/* Both: watch JOB. */
int sphctl_watch(sphctl *c, const char *job);

/* ---- sphctl_files.c: results, fetch and export (argv[0] is the command's name) ---- */

int sphctl_cmd_results(sphctl *c, int argc, char **argv);
int sphctl_cmd_fetch(sphctl *c, int argc, char **argv);
int sphctl_cmd_export(sphctl *c, int argc, char **argv);

/* ---- sphctl_sweep.c: sweep, one job per combination of values (argv[0] is "sweep") ---- */

int sphctl_cmd_sweep(sphctl *c, int argc, char **argv);

/* sphctl.c (main and the command table) is the top floor: it declares nothing here. */

#endif
