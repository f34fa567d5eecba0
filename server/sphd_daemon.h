/*
 * sphd daemon mode: the types shared by the socket loop (sphd_daemon.c), the command table
 * (sphd_commands.c), the job manager (sphd_jobs.c) and the worker threads (sphd_worker.c).
 *
 * Threads: the loop thread owns every ZeroMQ socket and all of sphd_daemon and sphd_job except
 * where a field says otherwise; worker threads own the executor of the job they run and talk to
 * the loop over one inproc PAIR each (messages are the structs below, passed by value).
 */
#ifndef SPHD_DAEMON_H
#define SPHD_DAEMON_H

#include "sph_case.h"
#include "sph_endpoint.h"
#include "sph_inputs.h"
#include "sphd_exec.h"

#include <jansson.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stddef.h>

#define SPHD_PROTOCOL_VERSION 1
#define SPHD_JOB_ID_MAX       64
#define SPHD_PATH_MAX         4096
#define SPHD_REASON_MAX       512
#define SPHD_MAX_ENVELOPE     8
#define SPHD_KEEP_FINISHED    1000  /* finished jobs remembered for list/query */
#define SPHD_SWEEP_MAX_LISTS  8     /* fields a sweep varies */
#define SPHD_SWEEP_MAX_JOBS   10000 /* combinations of one sweep */

/* Daemon options (`sphd --listen ... --publish ...`). */
typedef struct sphd_opts {
    char listen[SPH_ENDPOINT_MAX];
    char publish[SPH_ENDPOINT_MAX];
    char state_dir[SPHD_PATH_MAX];
    int threads;          /* worker threads = jobs running at once */
    int max_jobs;         /* queued + running + paused jobs held at once */
    long max_msg_size;    /* bytes; larger requests are dropped by the transport */
    int insecure;         /* allow non-loopback tcp without CURVE */
    int diag_rate;        /* max diag events per second per job */
    double ckpt_interval; /* wall-clock seconds between checkpoints; 0: the default */
    int request_cpu;      /* the CPU of the loop and ZeroMQ threads, or SPHD_CPU_ANY, _AUTO */
    int worker_nice;      /* the solver threads' nice value above sphd's own */
    char curve_dir[SPHD_PATH_MAX]; /* --curve: server.key and clients/ ("": no CURVE) */
    int executor_slurm;            /* --executor slurm: jobs go to Slurm unless they say local */
    char runner_listen[SPH_ENDPOINT_MAX];  /* where runners connect (bind) */
    char runner_connect[SPH_ENDPOINT_MAX]; /* the same, as the nodes reach it */
    char exe[SPHD_PATH_MAX];               /* this sphd binary, for the batch scripts */
    double runner_wait;                    /* a runner waits this long for the daemon (s) */
    char http[256];                        /* --http HOST:PORT: the dashboard ("": none) */
} sphd_opts;

typedef enum {
    SPHD_JOB_QUEUED = 0,
    SPHD_JOB_RUNNING,
    SPHD_JOB_PAUSED,
    SPHD_JOB_DONE,
    SPHD_JOB_FAILED,
    SPHD_JOB_STOPPED
} sphd_job_state;

const char *sphd_job_state_name(sphd_job_state s);
int sphd_job_state_final(sphd_job_state s);

/* Stable error codes of the wire protocol; their names come from sphd_errcode_name only. */
typedef enum {
    SPHD_E_BAD_REQUEST = 0,
    SPHD_E_UNKNOWN_OP,
    SPHD_E_INVALID_CASE,
    SPHD_E_NOT_FOUND,
    SPHD_E_CONFLICT,
    SPHD_E_BAD_STATE,
    SPHD_E_TOO_LARGE,
    SPHD_E_BUSY,
    SPHD_E_INTERNAL,
    SPHD_E_COUNT
} sphd_errcode;

const char *sphd_errcode_name(sphd_errcode c);

/* An error reply in the making (caller-owned, never allocates). */
typedef struct sphd_err {
    sphd_errcode code;
    char path[SPH_ERROR_PATH_MAX + 16];
    char message[SPH_ERROR_TEXT_MAX + 64];
} sphd_err;

int sphd_err_set(sphd_err *e, sphd_errcode code, const char *path, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));

/* A request kept for a later reply (pause/stop of a running job, shutdown, particle queries):
 * the routing envelope and the request id. */
typedef struct sphd_pending {
    int nframes;
    size_t len[SPHD_MAX_ENVELOPE];
    unsigned char *frame[SPHD_MAX_ENVELOPE];
    json_t *id; /* the request's "id" (new ref; json null when absent) */
    const char *op;
    long token;                /* for particle queries answered by a worker */
    char job[SPHD_JOB_ID_MAX]; /* the job a particle query is about */
    struct sphd_pending *next;
} sphd_pending;

typedef struct sphd_job {
    char id[SPHD_JOB_ID_MAX];
    char dir[SPHD_PATH_MAX];
    json_t *case_json;           /* the case as run (after `set`), for idempotent submit */
    char sweep[SPHD_JOB_ID_MAX]; /* the sweep it belongs to, or "" */
    json_t *params;              /* a sweep's job: {"dotted.path": value} (new ref), else NULL */
    sph_case *c;
    sphd_exec *exec; /* NULL until the first run and once finished; the worker's while running */
    sphd_job_state state;
    char reason[SPHD_REASON_MAX];
    long seq;          /* last published event's seq */
    long seq_on_disk;  /* the largest seq its journal holds (written before it is published) */
    int seq_unwritten; /* a seq could not be journaled (said once) */
    int started;       /* has ever been queued to run */
    int resume;        /* the next run continues from the checkpoint in dir (recovered job) */
    int worker;        /* worker index while running, else -1 */
    long step_n;       /* pending `step`: steps to do (0: none) */
    double step_until; /* pending `step`: time to reach (INFINITY: none) */
    int stepping;      /* the current run ends paused (a `step`) */
    int pause_requested, stop_requested; /* journaled (sphd_job_journal_requests) */
    int requests_unsent; /* recovered with a pause/stop pending: told to its runner when back */
    int slurm;           /* runs on the Slurm executor */
    json_t *resources;   /* the job's `resources` (new ref) or NULL */
    char slurm_id[48];   /* its current (or last) Slurm job, "" before the first */
    int held;            /* a sweep's job waiting for its array's sbatch */
    int runner_seen;     /* the runner of the current Slurm job said hello */
    int retries;         /* Slurm jobs resubmitted after one ended without a result */
    double gone_since;   /* monotonic time Slurm first reported its job ended, or 0 */
    long run_max_steps;  /* the current remote run's step target (0: none) */
    double run_until;    /* ... its time target (INFINITY: none) */
    int readers;         /* requests the files thread serves on this job: not forgotten meanwhile */
    int exec_readers; /* of which particle queries: its executor is not run nor freed meanwhile */
    json_t *progress; /* latest executor progress (new ref) */
    json_t *diag;     /* latest diag event body (new ref) */
    json_t *result;   /* result event body, when done (new ref) */
    double submitted; /* unix time */
    double wall;      /* seconds spent running, finished runs */
    double run_wall;  /* seconds into the current run */
    double steps_per_s, eta; /* from the worker, while running */
    sphd_pending *waiters;   /* replies due when the current run ends */
    /* steering (op `set`, PROTOCOL.md 3.12) */
    json_t *case_now;     /* the case with every change in effect (NULL: case_json) */
    json_t *steering;     /* the changes in effect, oldest first: [{"step", "t", "set"}] */
    json_t *steer_set;    /* a change waiting for the run's next step boundary, or NULL */
    json_t *steer_case;   /* the case it makes (case_now with it) */
    sph_case *steer_next; /* that case parsed (op set checked it), used when it is made */
    char steer_error[SPH_ERROR_TEXT_MAX + SPH_ERROR_PATH_MAX +
                     8]; /* why the latest change was not made ("" when it was) */
    char *query_text;    /* the encoded `query` result until the job changes (sphd_job_touch) */
    char *status_text;   /* the encoded job status, likewise (for `list`) */
    struct sphd_job *next;
} sphd_job;

/* Loop -> worker. */
typedef enum {
    SPHD_W_RUN,
    SPHD_W_PAUSE,
    SPHD_W_STOP,
    SPHD_W_PARTICLES,
    SPHD_W_QUIT,
    SPHD_W_STEER /* end the run at the next step boundary: the loop steers the job and runs it on */
} sphd_wcmd_kind;
typedef struct sphd_wcmd {
    sphd_wcmd_kind kind;
    sphd_job *job;
    sphd_exec *exec; /* RUN: the executor, owned by the worker until END */
    long max_steps;  /* RUN: 0 no bound */
    double until;    /* RUN: INFINITY no bound */
    json_t *fields;  /* PARTICLES: array of names (stolen) */
    long max;        /* PARTICLES: at most this many particles */
    long token;      /* PARTICLES */
    json_t *status;  /* PARTICLES: the job's status for the reply (stolen; a deep copy) */
    json_t *id;      /* PARTICLES: the request's id (stolen; a deep copy) */
} sphd_wcmd;

/* Worker -> loop. */
typedef enum { SPHD_WEV_EVENT, SPHD_WEV_PROGRESS, SPHD_WEV_END, SPHD_WEV_PARTICLES } sphd_wev_kind;
typedef enum {
    SPHD_END_DONE,
    SPHD_END_FAILED,
    SPHD_END_PAUSED,  /* paused on request */
    SPHD_END_STOPPED, /* stopped on request */
    SPHD_END_TARGET,  /* a `step` reached its target */
    SPHD_END_STEER    /* ended to be steered (SPHD_W_STEER): the loop runs it on */
} sphd_end_kind;
typedef struct sphd_wev {
    sphd_wev_kind kind;
    sphd_job *job;
    char type[16];     /* EVENT: the event type */
    json_t *body;      /* EVENT body, PROGRESS progress, PARTICLES result (stolen) */
    sphd_end_kind end; /* END */
    sphd_exec *exec;   /* END: the executor, handed back (NULL if it could not be created) */
    char reason[SPHD_REASON_MAX];
    double wall; /* END/PROGRESS: seconds run in this run */
    double steps_per_s, eta;
    long token; /* PARTICLES */
    char *text; /* PARTICLES: the encoded reply (malloc'ed), NULL when out of memory */
} sphd_wev;

/* The line between the loop and what runs a job (sphd_link.c): the messages above as structs
 * over an inproc PAIR (a local worker, wire 0) or as frames over tcp (a runner, wire 1). */
typedef struct sphd_link {
    void *sock;
    int wire;
    sphd_job *job; /* a runner's own job (wire) */
} sphd_link;

#define SPHD_WORKER_REMOTE (-2) /* sphd_job.worker: the job runs in a runner on the cluster */
#define SPHD_SLURM_RETRIES 3    /* resubmissions of a job whose Slurm job ended without a result */

typedef struct sphd_worker {
    struct sphd_daemon *d;
    int index;
    void *pair; /* loop side: owned by the loop thread */
    pthread_t thread;
    int started;
    sphd_job *job; /* the job it runs, or NULL */
} sphd_worker;

/* Loop -> files thread (sphd_files.c). */
typedef enum {
    SPHD_F_LIST = 1,
    SPHD_F_FETCH,
    SPHD_F_EXPORT,
    SPHD_F_PARTICLES, /* `query` with fields of a paused job (its idle executor) */
    SPHD_F_QUIT
} sphd_fkind;

typedef struct sphd_fcmd {
    sphd_fkind kind;
    sphd_job *job;
    int checksums;    /* LIST */
    char *file;       /* FETCH: malloc'ed, freed by whoever ends the request */
    long long offset; /* FETCH */
    long length;      /* FETCH */
    sphd_exec *exec;  /* PARTICLES: the paused job's executor (read only) */
    json_t *fields;   /* PARTICLES: names; status and id as sphd_wcmd's (all three stolen) */
    json_t *status, *id;
    long max;
    long token;
} sphd_fcmd;

/* Files thread -> loop: the answer to the request with the same token (token -1: the last). */
typedef struct sphd_fev {
    long token;
    json_t *body; /* the result, or NULL with err set (text NULL) */
    char *text;   /* PARTICLES: the encoded reply (NULL: out of memory, err set) */
    sphd_job *job;
    int exec_read; /* a PARTICLES answer */
    sphd_err err;
} sphd_fev;

typedef struct sphd_daemon {
    sphd_opts opts;
    void *ctx;
    void *router;             /* control */
    void *pub;                /* stream */
    struct sphd_curve *curve; /* --curve: keys and the ZAP handler, or NULL */
    int sigfd;                /* read end of the signal self-pipe */
    int lockfd;
    char lockpath[SPHD_PATH_MAX];
    sphd_worker *workers;
    int nworkers;
    atomic_int busy; /* workers running a job (read by workers for OpenMP threads) */
    sphd_job *jobs;  /* oldest first */
    int njobs_active, njobs_final;
    long next_job_number;
    long next_token;
    sphd_pending *particle_waits;
    sphd_pending *shutdown_waits;
    void *files; /* PAIR to the files thread */
    pthread_t files_thread;
    int files_started;
    sphd_pending *file_waits; /* results/fetch/export being read by the files thread */
    void *runners;            /* ROUTER the runners on the cluster connect to, or NULL */
    void *slurm;              /* PAIR to the Slurm thread (sphd_slurm.c) */
    pthread_t slurm_thread;
    int slurm_started;
    int slurm_polling;           /* a squeue is out */
    struct sphd_submit *submits; /* sbatch calls out: which jobs each is for */
    double next_slurm_poll;      /* monotonic time of the next squeue */
    int stopping;                /* shutting down: pause everything, then exit */
    double started_at;
    /* counters */
    long requests, errors;
} sphd_daemon;

/* ---- floor 0, sphd_base.c: shared by every floor (also sphd_errcode_name, sphd_err_set and
 * sphd_job_state_name above). ---- */
double sphd_now(void);  /* unix time, seconds */
double sphd_mono(void); /* monotonic seconds */
void sphd_log(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
/* {"v","id","ok","result"|"error"} (result stolen). */
json_t *sphd_reply_new(json_t *id, json_t *result, const sphd_err *e);
/* Replies to a request (the result or the error; result stolen). */
void sphd_reply(sphd_daemon *d, const sphd_pending *to, json_t *result, const sphd_err *e);
/* Sends an encoded reply (taken: handed to ZeroMQ without a copy) with the request's envelope. */
void sphd_reply_text(sphd_daemon *d, const sphd_pending *to, char *text);
void sphd_publish(sphd_daemon *d, sphd_job *j, const char *type, json_t *body);
/* Forgets what was cached about j (call on every change to a job). */
void sphd_job_touch(sphd_job *j);
sphd_pending *sphd_pending_copy(const sphd_pending *p);
void sphd_pending_free(sphd_pending *p);
/* Unlinks and returns the request of `list` kept under token, or NULL. */
sphd_pending *sphd_pending_take(sphd_pending **list, long token);
/* An inproc PAIR between the loop (bind) and one of its threads (connect), LINGER 0; NULL (logged)
 * on failure. */
void *sphd_pair_open(void *ctx, const char *endpoint, int bind);
/* Sends one fixed-size message (a command or an event struct) over a PAIR, retrying on EINTR.
 * Returns 0 or -1 (errno). */
int sphd_pair_send(void *sock, const void *msg, size_t len);

/* ---- top floor, sphd_daemon.c: the socket loop ---- */
int sphd_daemon_main(const sphd_opts *opts);

/* sphd_commands.c: parses and dispatches one request; returns the encoded reply to send now
 * (malloc'ed) or NULL when the reply is deferred (the handler kept a copy of `req`). */
char *sphd_dispatch(sphd_daemon *d, const sphd_pending *req, const char *body, size_t len);
/* The name of the i-th op of the table, NULL past the end (for the tests). */
const char *sphd_op_name(size_t i);

/* sphd_inputs.c: the files a case names, sent in args.files and kept in JOBDIR/files/ */
typedef struct sphd_input {
    char name[SPH_INPUT_NAME_MAX + 1];
    unsigned char *data; /* owned */
    size_t len;
} sphd_input;
typedef struct sphd_inputs {
    int n;
    sphd_input f[SPH_INPUT_MAX_COUNT];
} sphd_inputs;
/* Decodes args.files (borrowed; NULL: none) into out: names usable, base64 valid, size and
 * crc32 as given, within the limits. 0, or -1 with e (bad_request or too_large at
 * /args/files/NAME) and out empty. */
int sphd_inputs_decode(const json_t *files, sphd_inputs *out, sphd_err *e);
void sphd_inputs_free(sphd_inputs *in);
const sphd_input *sphd_inputs_get(const sphd_inputs *in, const char *name);
/* Every file case_json names is in in (used[i] set for each, when used is not NULL). 0, or -1
 * with e: invalid_case at /geometry/K/mesh for a name that is not usable, bad_request at
 * /args/files/NAME for a file in lacks. */
int sphd_inputs_match(const json_t *case_json, const sphd_inputs *in, unsigned char *used,
                      sphd_err *e);
/* -1 with e (bad_request at /args/files/NAME) when a file of in was not used. */
int sphd_inputs_unused(const sphd_inputs *in, const unsigned char *used, sphd_err *e);
/* Writes the files case_json names into dir/files/ (atomically). 0 or -1 with e (internal). */
int sphd_inputs_write(const char *dir, const json_t *case_json, const sphd_inputs *in, sphd_err *e);
/* Removes what sphd_inputs_write wrote (a job refused after it). */
void sphd_inputs_remove(const char *dir, const json_t *case_json);
/* 1 when dir/files/ holds the files case_json names with in's bytes. */
int sphd_inputs_same(const char *dir, const json_t *case_json, const sphd_inputs *in);
/* dir/files into buf: 0, or -1 when it does not fit. */
int sphd_inputs_dir(const char *dir, char *buf, size_t n);

/* sphd_jobs.c */
sphd_job *sphd_job_find(sphd_daemon *d, const char *id);
/* Creates a job from a validated submit; NULL with e filled in. */
/* sweep and params: a sweep's job (params taken as a new ref), else NULL. in: the files the
 * case names (matched; may be NULL when it names none), written to the job's files/ before
 * the job is accepted and its meshes read from there. */
sphd_job *sphd_job_submit(sphd_daemon *d, const char *id, json_t *case_json, int start,
                          const char *sweep, json_t *params, json_t *resources,
                          const sphd_inputs *in, sphd_err *e);
/* The Slurm thread's answer to an sbatch: the jobs it was for get their Slurm ids (or fail with
 * sbatch's message; a job paused or stopped meanwhile has its new Slurm job cancelled). */
struct sphd_sev;
void sphd_jobs_on_submitted(sphd_daemon *d, const struct sphd_sev *ev);
/* Replies to the requests waiting for j's run to end (pause, stop, particle queries). */
void sphd_jobs_answer_waiters(sphd_daemon *d, sphd_job *j);
/* Sends cmd to whatever runs j (its worker, or its runner on the cluster): 0 or -1 (errno). */
int sphd_jobs_send(sphd_daemon *d, sphd_job *j, sphd_wcmd *cmd);
/* A sweep's held jobs to Slurm as one array job (task i is jobs[i]). 0, or -1 with e (the jobs
 * failed with sbatch's message). */
int sphd_jobs_start_array(sphd_daemon *d, sphd_job **jobs, size_t n, const char *sweep,
                          sphd_err *e);
json_t *sphd_job_status(const sphd_job *j);
void sphd_job_set_state(sphd_daemon *d, sphd_job *j, sphd_job_state s, const char *reason);
/* Steering: the job's "steering" object for its status ({"values": {path: value}, "history",
 * "pending", "error"}; new ref). */
json_t *sphd_job_steering(const sphd_job *j);
/* Makes the change waiting in j->steer_set on j->exec (no worker holding it): the executor
 * steered and checkpointed, steering.json and the journal written, a `steer` event published.
 * 0, or -1 with e (and j->steer_error) when it is refused; the change is no longer pending. */
int sphd_job_steer_apply(sphd_daemon *d, sphd_job *j, sphd_err *e);
/* Forgets the change waiting in j (steer_set, steer_case, steer_next). */
void sphd_job_steer_drop(sphd_job *j);
void sphd_job_record(sphd_daemon *d, sphd_job *j, int interrupted);
/* Journals the job's pending pause and stop (fsync'd): a restarted sphd still carries them out. */
void sphd_job_journal_requests(sphd_daemon *d, sphd_job *j);
void sphd_jobs_schedule(sphd_daemon *d);
void sphd_jobs_on_worker(sphd_daemon *d, sphd_worker *w, sphd_wev *ev);
void sphd_jobs_free(sphd_daemon *d);
/* On start: takes up the jobs found in STATE_DIR/jobs (see sphd_jobs.c). */
void sphd_jobs_recover(sphd_daemon *d);

/* sphd_sweep.c: parameter sweeps. */
/* Applies `set` ("PATH=VALUE" strings, as sphd --run --set) to the case c. 0, or -1 with e at
 * /args/set/i (not a string) or the field's path (invalid_case). */
int sphd_apply_sets(json_t *c, const json_t *sets, sphd_err *e);
/* The cases of a sweep: case_in with `sets` ("PATH=VALUE" strings) applied, then one case per
 * combination of vary's lists ([{"path", "values"}], the last varying fastest). Returns the
 * array of cases and *params ({"path": value} per case), or NULL with e set. */
json_t *sphd_sweep_expand(const json_t *case_in, const json_t *sets, const json_t *vary,
                          json_t **params, sphd_err *e);
/* The table of a sweep's jobs: {"sweep","params","columns","count","format", "rows" (json) or
 * "csv"}: per job its id, state, parameters and result summary (scalars, dotted names). */
json_t *sphd_sweep_table(sphd_daemon *d, const char *sweep, int csv, sphd_err *e);

/* sphd_remote.c: jobs on the Slurm executor, for the loop. */
/* Takes the runners' messages that have come. */
void sphd_remote_on_message(sphd_daemon *d);
/* Every few seconds: asks Slurm (on the Slurm thread) about the jobs out there. */
void sphd_remote_poll(sphd_daemon *d);
/* The Slurm thread's answers: sbatch's job ids; squeue's states (jobs whose Slurm job ended
 * without a word continue from their checkpoint, pause or fail). */
void sphd_remote_on_slurm(sphd_daemon *d);
/* sphd --runner: one job on a cluster node (sphd_runner.c). Returns an exit code. */
int sphd_runner_main(const char *endpoint, const char *dir, const char *keys, int threads,
                     double ckpt_interval, int diag_rate, double wait_s);

/* sphd_results.c: a job's result files (`results`, `fetch`, `export`); NULL with e set. */
#define SPHD_FETCH_DEFAULT (1L << 20)
#define SPHD_FETCH_MAX     (4L << 20)
/* The kind of a job file from its name: case, record, journal, result, diagnostics, snapshot,
 * xdmf, checkpoint or other. */
const char *sphd_results_kind(const char *name);
/* {"job","dir","files":[{"name","size","kind"[,"crc32"]}]}: regular files sorted by name,
 * without the temporaries of atomic writes. */
json_t *sphd_results_list(const sphd_job *j, int checksums, sphd_err *e);
/* One chunk of one listed file: {"file","offset","length","size","eof","crc32","data"}. */
json_t *sphd_results_fetch(const sphd_job *j, const char *file, long long offset, long length,
                           sphd_err *e);
/* The diagnostics series as CSV: {"format":"csv","rows","csv"}; bad_state without diag.h5. */
json_t *sphd_results_export_csv(const sphd_job *j, sphd_err *e);

/* sphd_link.c */
/* Sends one worker message (its body and text are taken). Returns 0 or -1. */
int sphd_link_send(sphd_link *l, sphd_wev *ev);
/* Receives one command: 1, 0 when there is none (without wait), -1 on error. */
int sphd_link_recv(sphd_link *l, sphd_wcmd *cmd, int wait);
/* The daemon's side of the wire: a command to the runner of job `runner` (its json taken), and
 * a runner's message: 1 with *ev (ev->job NULL: the caller finds it by runner) or *hello set, 0
 * when none is there, -1 for a message it cannot read. */
int sphd_wire_send_cmd(void *router, const char *runner, sphd_wcmd *cmd);
int sphd_wire_recv_wev(void *router, char *runner, size_t runner_len, sphd_wev *ev, json_t **hello);

/* sphd_slurm.c: calls to Slurm's commands. */
typedef enum { SPHD_S_SUBMIT = 1, SPHD_S_CANCEL, SPHD_S_STATES, SPHD_S_QUIT } sphd_skind;
/* Loop -> Slurm thread; the strings and res are the thread's (malloc'ed, a deep copy). */
typedef struct sphd_scmd {
    sphd_skind kind;
    long token;
    char *arg;                /* SUBMIT: the script; CANCEL: the Slurm id; STATES: the ids */
    char *name, *out, *array; /* SUBMIT: job name, output pattern, array range or NULL */
    json_t *res;              /* SUBMIT: the resources or NULL */
} sphd_scmd;
/* Slurm thread -> loop (no answer to CANCEL). */
typedef struct sphd_sev {
    int kind; /* sphd_skind */
    long token;
    int rc;        /* 0, or -1: why (SUBMIT) / lines NULL (STATES) */
    char id[48];   /* SUBMIT: Slurm's job id */
    char why[400]; /* SUBMIT: sbatch's message */
    char *lines;   /* STATES: squeue's "ID STATE" lines (malloc'ed) */
} sphd_sev;
int sphd_slurm_start(sphd_daemon *d);
/* Sends cmd (its strings taken); returns its token, or -1. */
long sphd_slurm_send(sphd_daemon *d, sphd_scmd *cmd);
/* 1 with an answer in *ev, 0 when none is there. */
int sphd_slurm_recv(sphd_daemon *d, sphd_sev *ev);
void sphd_slurm_stop(sphd_daemon *d);
/* Runs argv[0] (found on PATH) with its stdout and stderr into out and err (NUL-terminated,
 * truncated). Returns its exit status, or -1 (errno) when it could not start. */
int sphd_slurm_call(char *const argv[], char *out, size_t outn, char *err, size_t errn);
/* 0 when sbatch runs here, else -1 with why. */
int sphd_slurm_available(char *why, size_t n);
/* Checks a `resources` object (where: its JSON path). Returns 0 or -1 with e set. */
int sphd_resources_check(const json_t *res, const char *where, sphd_err *e);
/* sbatch SCRIPT with the job's resources (array: "0-N" or NULL); id gets Slurm's job id.
 * Returns 0, or -1 with why (sbatch's own message). */
int sphd_slurm_submit(const sphd_daemon *d, const char *script, const char *name,
                      const char *out_pattern, const json_t *res, const char *array, char *id,
                      size_t idn, char *why, size_t whyn);
void sphd_slurm_cancel(const char *id);
/* squeue's "ID STATE" lines for the comma-separated ids (malloc'ed), or NULL. */
char *sphd_slurm_states(const char *ids);
/* Writes the batch script that runs `sphd --runner` for a job (dir) or a sweep's array (dir
 * NULL: STATE/jobs/SWEEP-$SLURM_ARRAY_TASK_ID) at path. Returns 0 or -1 with why. */
int sphd_slurm_script(const sphd_daemon *d, const char *path, const char *dir, const char *sweep,
                      char *why, size_t whyn);

/* sphd_query.c: particle queries, answered by the thread that may read the executor (a running
 * job's worker, the files thread for a paused job), never by the loop. */
/* Particle fields of an executor: new ref or NULL with e set. */
json_t *sphd_particles(sphd_exec *x, const sph_case *c, json_t *fields, long max, sphd_err *e);
/* The whole encoded reply to a particle query: status (stolen) with "particles" added, or the
 * error; id stolen. NULL when out of memory. */
char *sphd_particles_reply(sphd_exec *x, const sph_case *c, json_t *fields, long max,
                           json_t *status, json_t *id);

/* sphd_files.c: the thread that reads job files for `results`, `fetch` and `export`. */
int sphd_files_start(sphd_daemon *d);
/* Sends cmd (its file now owned) and keeps from for the answer: 1 (deferred), or -1 with e. */
int sphd_files_send(sphd_daemon *d, sphd_fcmd *cmd, const sphd_pending *from, sphd_err *e);
/* Does cmd's work in the calling thread: the result, or NULL with e set. */
json_t *sphd_files_do(const sphd_fcmd *cmd, sphd_err *e);
/* Replies to the answers that have come (the loop calls it when the files socket is readable). */
void sphd_files_on_answer(sphd_daemon *d);
/* Answers what was sent, ends the thread, frees what is left. */
void sphd_files_stop(sphd_daemon *d);

/* sphd_worker.c */
int sphd_workers_start(sphd_daemon *d);
void sphd_workers_stop(sphd_daemon *d);
int sphd_worker_send(sphd_worker *w, const sphd_wcmd *cmd);
/* Runs a job until it ends, is paused or stopped, or reaches its step target, talking to the
 * loop over l (a worker thread's PAIR, or a runner's tcp line to the daemon). */
void sphd_run_job(sphd_worker *w, sphd_link *l, sphd_wcmd *cmd);
/* 1 when this build's executor runs jobs of method m (hello's "methods"). */
int sphd_method_available(sph_method m);

/* sphd_sched.c: where the request threads (the socket loop, the ZeroMQ threads) run. */
#define SPHD_CPU_ANY  (-1) /* not pinned */
#define SPHD_CPU_AUTO (-2) /* the last CPU the process may use */
/* 1 when this process may run on CPU cpu. */
int sphd_sched_cpu_usable(int cpu);
/* The CPU for want (a CPU number, SPHD_CPU_AUTO or SPHD_CPU_ANY), or SPHD_CPU_ANY (errno
 * EINVAL when want was a CPU this process may not use). */
int sphd_sched_pick_cpu(int want);
/* The threads that ctx starts from now on (call it before the first socket) run on cpu (>= 0;
 * a negative cpu changes nothing). Returns 0 or -1 (errno). */
int sphd_sched_zmq_threads(void *ctx, int cpu);
/* The calling thread runs on cpu from now on (threads it starts later inherit that; a negative
 * cpu changes nothing). Returns 0 or -1 (errno). */
int sphd_sched_pin_self(int cpu);
/* The calling thread's nice value goes up by `by` (at most to 19); threads it starts later
 * inherit it. Returns 0 or -1 (errno). */
int sphd_sched_lower_self(int by);

#endif
