/*
 * sphd --run: batch mode. One case, in the foreground, no socket. Events go to stdout as JSON
 * Lines (the same objects the stream carries); messages go to stderr; outputs go to the out dir.
 */
#include "sph_case.h"
#include "sph_events.h"
#include "sph_json.h"
#include "sph_study.h"
#include "sphd.h"
#include "sphd_exec.h"

#include <math.h>
#include <errno.h>
#include <omp.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct emitter {
    const char *job;
    const char *outdir;
    long seq;
} emitter;

/* Prints one event (stolen reference) as a line on stdout. */
/* Steps per call of the solver: the run looks for a stop signal between two calls. */
#define SPHD_RUN_CHUNK 100

/* SIGINT or SIGTERM received: the run writes a checkpoint and exits 75. */
static volatile sig_atomic_t run_interrupted;

static void on_stop_signal(int sig)
{
    run_interrupted = sig;
}

static void emit(emitter *em, const char *type, json_t *body)
{
    json_t *ev = sph_event_new(em->job, ++em->seq, type);
    if (body)
        json_object_update(ev, body);
    json_decref(body);
    char *line = json_dumps(ev, JSON_COMPACT | JSON_REAL_PRECISION(10));
    if (line) {
        fputs(line, stdout);
        fputc('\n', stdout);
        fflush(stdout);
        free(line);
    }
    json_decref(ev);
}

static int write_json(const char *dir, const char *name, const json_t *j);

/* sphd_emit_fn for the executor: prints the event; keeps the result in result.json too. */
static void on_event(void *ud, const char *type, json_t *body)
{
    emitter *em = ud;
    if (strcmp(type, "result") == 0)
        write_json(em->outdir, "result.json", body);
    emit(em, type, body);
}

static void emit_state(emitter *em, const char *state, const char *reason)
{
    json_t *b = json_pack("{s:s}", "state", state);
    if (reason)
        json_object_set_new(b, "reason", json_string(reason));
    emit(em, "state", b);
}

/* A run that stops here to go on later (a signal, a trigger's pause): a checkpoint, the last
 * state `paused` with why; SPHD_EX_TEMPFAIL, or SPHD_EX_FAILED when the checkpoint fails. */
static int pause_here(sphd_exec *x, emitter *em, const char *job, const char *why)
{
    sph_error err;
    sph_error_clear(&err);
    if (sphd_exec_checkpoint(x, &err) == 0) {
        emit_state(em, "paused", why);
        fprintf(stderr, "sphd: %s paused (%s); checkpoint written: --resume continues\n", job, why);
        return SPHD_EX_TEMPFAIL;
    }
    char reason[SPH_ERROR_TEXT_MAX + 256];
    snprintf(reason, sizeof reason, "%.160s, and the checkpoint failed: %s: %s", why,
             sph_error_code_name(err.code), err.message);
    emit_state(em, "failed", reason);
    return SPHD_EX_FAILED;
}

static int write_json(const char *dir, const char *name, const json_t *j)
{
    int rc = sphd_write_json(dir, name, j);
    if (rc != 0)
        fprintf(stderr, "sphd: cannot write %s/%s: %s\n", dir, name, strerror(errno));
    return rc;
}

int sphd_run(const sphd_run_opts *o)
{
    sph_error err;
    sph_error_clear(&err);
    json_t *root = NULL;
    if (sph_case_load(o->case_file, &root, &err)) {
        fprintf(stderr, "sphd: %s\n", err.message);
        return err.code == SPH_ERR_IO ? SPHD_EX_NOINPUT : SPHD_EX_DATAERR;
    }
    for (int i = 0; i < o->nsets; i++) {
        if (sph_json_apply_set(root, o->sets[i], &err)) {
            fprintf(stderr, "sphd: %s: %s\n", o->case_file, err.message);
            json_decref(root);
            return SPHD_EX_DATAERR;
        }
    }
    sph_case *c = calloc(1, sizeof *c);
    if (!c) {
        json_decref(root);
        return SPHD_EX_SOFTWARE;
    }
    if (sph_case_from_json(root, c, &err)) {
        if (err.path[0])
            fprintf(stderr, "sphd: %s: invalid case: %s (at %s)\n", o->case_file, err.message,
                    err.path);
        else
            fprintf(stderr, "sphd: %s: invalid case: %s\n", o->case_file, err.message);
        free(c);
        json_decref(root);
        return SPHD_EX_DATAERR;
    }
    /* the files the case names: relative to the case file's directory */
    char casedir[4096];
    const char *slash = strrchr(o->case_file, '/');
    snprintf(casedir, sizeof casedir, "%.*s", slash ? (int)(slash - o->case_file) : 1,
             slash ? o->case_file : ".");
    if (!casedir[0])
        snprintf(casedir, sizeof casedir, "/");
    if (sph_case_load_files(c, casedir, NULL, &err)) {
        fprintf(stderr, "sphd: %s: invalid case: %s (at %s)\n", o->case_file, err.message,
                err.path);
        sph_case_clear(c);
        free(c);
        json_decref(root);
        return SPHD_EX_DATAERR;
    }
    const char *job = o->job ? o->job : c->name;
    if (!sphd_job_id_ok(job)) {
        fprintf(stderr,
                "sphd: job id '%s' is not usable as a file name: use 1-63 letters, digits, '.', "
                "'_' or '-' (set one with --id)\n",
                job);
        sph_case_clear(c);
        free(c);
        json_decref(root);
        return SPHD_EX_USAGE;
    }
    char outdir[4096];
    if (o->out_dir)
        snprintf(outdir, sizeof outdir, "%s", o->out_dir);
    else
        snprintf(outdir, sizeof outdir, "out/%s", job);
    if (sphd_mkdirs(outdir) != 0) {
        fprintf(stderr, "sphd: cannot create output directory '%s': %s\n", outdir, strerror(errno));
        sph_case_clear(c);
        free(c);
        json_decref(root);
        return SPHD_EX_CANTCREAT;
    }
    if (o->threads > 0)
        omp_set_num_threads(o->threads);

    emitter em = {.job = job, .seq = 0, .outdir = outdir};
    int rc = SPHD_EX_OK;
    write_json(outdir, "case.json", root);
    sphd_exec *x = NULL;
    if (o->resume && sph_case_is_sim(c)) {
        sphd_continued how;
        x = sphd_exec_continue(c, outdir, &how, &err);
        if (how.from == SPHD_FROM_PREVIOUS)
            fprintf(stderr, "sphd: %s\n", how.why.message);
        else if (how.from == SPHD_FROM_LATEST)
            fprintf(stderr, "sphd: %s: resuming from its checkpoint\n", job);
        else
            fprintf(stderr, "sphd: %s: no checkpoint to resume from (%s); starting afresh%s\n", job,
                    how.why.message, how.kept ? SPHD_CKPT_KEPT_NOTE : "");
    } else {
        x = sphd_exec_new(c, outdir, &err);
    }
    if (!x) {
        fprintf(stderr, "sphd: %s: %s: %s\n", o->case_file, sph_error_code_name(err.code),
                err.message);
        sph_case_clear(c);
        free(c);
        json_decref(root);
        return err.code == SPH_ERR_INVALID || err.code == SPH_ERR_NOMEM ? SPHD_EX_DATAERR
                                                                        : SPHD_EX_SOFTWARE;
    }
    if (o->ckpt_interval > 0)
        sphd_exec_set_checkpoint_policy(x, o->ckpt_interval, 1);
    emit_state(&em, "running", NULL);
    for (int k = 0; sph_case_is_sim(c) && k < c->sim.ngeometry; k++) { /* what each mesh held */
        char note[256];
        int warn = 0;
        if (sph_case_mesh_note(c, k, note, sizeof note, &warn) == 0)
            emit(&em, "log",
                 json_pack("{s:s, s:s}", "level", warn ? "warning" : "info", "message", note));
    }
    /* SIGINT, SIGTERM: stop between two chunks of steps, with a checkpoint (--resume) */
    struct sigaction sa = {0};
    sa.sa_handler = on_stop_signal;
    sa.sa_flags = SA_RESETHAND; /* a second signal stops it at once */
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, NULL);
    sigaction(SIGTERM, &sa, NULL);
    sphd_exec_status st = SPHD_EXEC_RUNNING;
    while (!run_interrupted && (st = sphd_exec_advance(x, SPHD_RUN_CHUNK, INFINITY, on_event, &em,
                                                       &err)) == SPHD_EXEC_RUNNING)
        ;
    if (run_interrupted && st == SPHD_EXEC_RUNNING) {
        const int sig = (int)run_interrupted;
        rc = pause_here(x, &em, job,
                        sig == SIGINT ? "interrupted by SIGINT" : "interrupted by SIGTERM");
    } else if (st == SPHD_EXEC_DONE) {
        emit_state(&em, "done", NULL);
    } else if (st == SPHD_EXEC_PAUSE) { /* a trigger's: resumable, as an interrupted run */
        rc = pause_here(x, &em, job, sphd_exec_halt_reason(x));
    } else if (st == SPHD_EXEC_STOP) {
        emit_state(&em, "stopped", sphd_exec_halt_reason(x));
        rc = SPHD_EX_FAILED;
    } else {
        char reason[SPH_ERROR_TEXT_MAX + 32];
        snprintf(reason, sizeof reason, "%s: %s", sph_error_code_name(err.code), err.message);
        emit_state(&em, "failed", reason);
        rc = SPHD_EX_FAILED;
    }
    sphd_exec_free(x);
    if (rc != SPHD_EX_TEMPFAIL)
        fprintf(stderr, "sphd: %s %s; outputs in %s\n", job,
                rc == 0                ? "done"
                : st == SPHD_EXEC_STOP ? "stopped"
                                       : "failed",
                outdir);
    sph_case_clear(c);
    free(c);
    json_decref(root);
    return rc;
}
