/*
 * sphctl: the client of sphd. Internal interfaces of its files.
 *
 * The files call each other downwards only; floors, bottom up:
 *   sphctl_util.c                   shared helpers (command-line parsing, printing)
 *   sphctl_curve.c                  settings, CURVE keys, socket monitor, keygen
 *   sphctl_conn.c                   the control connection: requests
 *   sphctl_watch.c, sphctl_files.c  the event stream and watch; the result-file commands
 *   sphctl_inputs.c                 the files a case names, sent with it
 *   sphctl_sweep_watch.c            following a sweep's jobs (sweep --watch)
 *   sphctl_sweep.c                  parameter sweeps
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
/* The widths of the columns of a sweep's jobs (statuses): the ids, and their params as
 * sphctl_fmt_params writes them. */
void sphctl_sweep_widths(const json_t *jobs, const json_t *order, int *wid, int *wpar);

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

/* ---- sphctl_watch.c: the event stream; a job's view; watch ---- */

typedef struct sphctl_stream {
    void *sub;                 /* SUB socket */
    void *mon;                 /* its monitor */
    char topic[128];           /* what it is subscribed to ("" = every job) */
    char ep[SPH_ENDPOINT_MAX]; /* the stream endpoint */
    int connected;             /* its handshake was seen before sphctl_stream_open returned */
} sphctl_stream;
/* Subscribes to topic (a job id, a prefix of job ids, or "" for every job, when the id is not
 * known yet) and waits up to c->timeout for the connection's handshake, so that events
 * published after it returns reach it. Returns 0 or the exit code (said). */
int sphctl_stream_open(sphctl *c, const char *topic, sphctl_stream *st);
/* Moves the subscription to topic (the new one goes out before the old one's cancellation:
 * nothing under both is missed). Returns 0, or 69 (said; the stream is closed). */
int sphctl_stream_topic(sphctl_stream *st, const char *topic);
/* Waits up to ms milliseconds for the next event. Returns 0 with *ev (new ref; NULL when none
 * came: quiet, a signal, or a message that is not JSON), or the exit code: 77 the stream refused
 * us (said), 70 the poll failed. Events of any job under the topic (a prefix): check "job". */
int sphctl_stream_next(sphctl *c, sphctl_stream *st, long ms, json_t **ev);
void sphctl_stream_close(sphctl_stream *st);

/* One job as a watch sees it: a status (query, list, sweep's reply), then its events. */
typedef struct sphctl_view {
    char job[128];
    char state[16];   /* queued, running, paused, done, failed, stopped; "" before any */
    char reason[256]; /* why it failed, or "" */
    long seq;         /* the last seq applied (status or event) */
    double t, t_end;  /* simulated time and end time [s]; NaN unknown */
    double rate, eta; /* steps/s, wall seconds to t_end; NaN unknown */
    long steps;
    json_t *diag; /* the latest diagnostics (owned), or NULL */
    double last_diag_wall, last_diag_t;
    long last_diag_step;
} sphctl_view;
void sphctl_view_init(sphctl_view *v, const char *job);
void sphctl_view_free(sphctl_view *v); /* its diag; the struct is the caller's */
/* Takes a job status (PROTOCOL.md 3.3): state, seq, progress, diag. */
void sphctl_view_status(sphctl_view *v, const json_t *status);
/* Applies an event of the job (seq, and a state or diag event's fields; the others leave the
 * view as it is); the steps/s and ETA from the diag events' pace. */
void sphctl_view_event(sphctl_view *v, json_t *ev);
/* The progress text (" [####....] 40.0% t T/T_END s step N R steps/s ETA E", with diag a few
 * key diagnostics) into line (size bytes). */
void sphctl_view_progress(const sphctl_view *v, int diag, char *line, size_t size);
/* done, failed or stopped: no event follows. */
int sphctl_final_state(const char *state);
/* The exit code of a watch whose job ended in state: 0 done, 1 failed or stopped. */
int sphctl_state_exit(const char *state);
/* A watch draws live on stderr when this is true (stdout a terminal, no --json), else prints
 * lines on stdout. */
int sphctl_watch_tty(const sphctl *c);
/* stderr's terminal size (0 and 0 when it is none); cuts line to cols - 1 characters, so that
 * a redraw does not wrap and scroll. */
void sphctl_term_size(int *rows, int *cols);
void sphctl_fit_line(char *line, int cols);
/* "sphctl: JOB: missed events FROM..TO" on stderr (clear: erase the live line first); with
 * json_line also a {"job", "type": "gap", "from", "to"} line on stdout. */
void sphctl_report_gap(const char *job, long from, long to, int clear, int json_line);
/* Seconds on the monotonic clock. */
double sphctl_mono(void);
/* Follows job to its end on an open stream (subscribe, then snapshot), and closes it; with
 * from_start (the stream was connected before the job was created) every event of the job is
 * on the stream, so it is followed from its first event, without a snapshot. Returns the exit
 * code: 0 done, 1 failed or stopped, 69 server gone. */
int sphctl_watch_stream(sphctl *c, sphctl_stream *st, const char *job, int from_start);
/* Both: watch JOB. */
int sphctl_watch(sphctl *c, const char *job);

/* ---- sphctl_sweep_watch.c: sweep --watch, every job of a sweep to its end ---- */

/* Follows the jobs of sphd's sweep reply (borrowed) on st, subscribed before the sweep was
 * sent, and closes st; paths: the varied paths in order, for the parameters' text. On a TTY a
 * block of lines redrawn on stderr; else a line per state change on stdout; with --json one
 * line at the end, {"sweep", "count", "jobs": [STATUS, ...]} as list gives them. Returns the
 * worst of the jobs' sphctl_state_exit (0 all done, 1 one failed or stopped), or the exit
 * code that ended the watch (69 sphd gone, 77 refused). */
int sphctl_sweep_watch(sphctl *c, sphctl_stream *st, const json_t *reply, const json_t *paths);

/* ---- sphctl_files.c: results, fetch and export (argv[0] is the command's name) ---- */

int sphctl_cmd_results(sphctl *c, int argc, char **argv);
int sphctl_cmd_fetch(sphctl *c, int argc, char **argv);
int sphctl_cmd_export(sphctl *c, int argc, char **argv);

/* ---- sphctl_inputs.c: the files a case names, sent with submit and sweep ---- */

/* Adds args.files ({NAME: {"data": BASE64, "crc32": HEX, "size": N}}, PROTOCOL.md 3.11) for
 * the files that the case root names (each geometry item's "mesh"; root with sets applied, and
 * for a sweep in any combination of vary's values; both may be NULL), read relative to the
 * directory of c->file. Nothing is added when it names none. Returns 0, or the exit code (said
 * on stderr): 65 a name that is not a relative path below that directory or a file over the
 * limits, 66 a file that cannot be read. */
int sphctl_attach_files(sphctl *c, const json_t *root, const json_t *sets, const json_t *vary,
                        json_t *args);

/* ---- sphctl_sweep.c: sweep, one job per combination of values (argv[0] is "sweep") ---- */

int sphctl_cmd_sweep(sphctl *c, int argc, char **argv);

/* sphctl.c (main and the command table) is the top floor: it declares nothing here. */

#endif
