/*
 * sphd_exec: runs one job's computation, whatever its method, in bounded slices, so that the
 * batch mode (`sphd --run`) and the daemon's worker threads drive jobs the same way:
 *
 *     sphd_exec *x = sphd_exec_new(&case, job, outdir, &err);
 *     while ((st = sphd_exec_advance(x, 100, INFINITY, emit, ud)) == SPHD_EXEC_RUNNING)
 *         ... check for pause/stop requests between slices ...
 *     sphd_exec_free(x);
 *
 * The executor emits `diag`, `log`, `output` and `result` events through the callback; the caller
 * adds `job` and `seq` and emits the `state` events (it owns the job's state machine).
 * Not thread-safe: one thread drives an executor at a time.
 */
#ifndef SPHD_EXEC_H
#define SPHD_EXEC_H

#include "sph_case.h"
#include "sph_error.h"

#include <jansson.h>

typedef enum {
    SPHD_EXEC_RUNNING = 0, /* more to do */
    SPHD_EXEC_DONE,        /* finished; the result event was emitted */
    SPHD_EXEC_FAILED,      /* failed; err says why (e.g. unstable: NaN at step N) */
    SPHD_EXEC_PAUSE,       /* a trigger asks to pause here (sphd_exec_halt_reason says which) */
    SPHD_EXEC_STOP         /* a trigger asks to stop here */
} sphd_exec_status;

/* Receives one event body (type + fields; stolen reference). */
typedef void (*sphd_emit_fn)(void *ud, const char *type, json_t *body);

typedef struct sphd_exec sphd_exec;

/* Prepares the job (allocates the particles for a simulation). The case is copied. outdir may be
 * NULL (no files written). Returns NULL with err filled in (invalid_case, too_large, ...). */
sphd_exec *sphd_exec_new(const sph_case *c, const char *outdir, sph_error *err);

/* Advances by at most max_steps solver steps and not past time `until` (INFINITY: no bound).
 * One-shot methods (kernel_study) finish in one call. */
sphd_exec_status sphd_exec_advance(sphd_exec *x, long max_steps, double until, sphd_emit_fn emit,
                                   void *ud, sph_error *err);

/* Why the latest advance returned SPHD_EXEC_PAUSE or SPHD_EXEC_STOP: "trigger 'P1 > 5000'
 * at t = 0.41 s" (the case's triggers, sph_triggers.h: each fires once, at the first diag event
 * that meets it, with a `trigger` event; the checkpoints keep which have fired). */
const char *sphd_exec_halt_reason(const sphd_exec *x);

/* Progress for status/query: {"t", "t_end", "step", "finished", "diag": {...latest diag...}}
 * (new ref; a kernel study has only step and finished). */
json_t *sphd_exec_progress(const sphd_exec *x);

/* Particle fields of a simulation job ("pos", "vel", "rho", "p", "type", "id"; at most 8),
 * downsampled evenly over the particles' creation order to at most max_particles:
 * {"total": N, "count": n, "fields": {"pos": [[x, y], ...], "rho": [...], ...}} (new ref).
 * NULL with err for a job without particles or an unknown field. */
json_t *sphd_exec_particles(const sphd_exec *x, const char *const *fields, int nfields,
                            long max_particles, sph_error *err);

/* Checkpoints (simulations with an outdir): written after every `every_outputs` snapshots and
 * whenever `interval` wall-clock seconds have passed since the latest (checked between steps).
 * Defaults: 60 s, 1. */
#define SPHD_CKPT_INTERVAL_DEFAULT 60.0
void sphd_exec_set_checkpoint_policy(sphd_exec *x, double interval, int every_outputs);

/* Writes a checkpoint now (the daemon calls it on pause and on shutdown). Returns 0 (also for
 * jobs with nothing to checkpoint) or an error code (io_error: disk full...). */
int sphd_exec_checkpoint(sphd_exec *x, sph_error *err);

/* Steering (op `set`, PROTOCOL.md 3.12), between two runs of the executor: next's steerable
 * parameters (sph_sim_steer) take effect from the next step; `set` (the assignments, an array of
 * strings) is recorded with the step and time into the job's steering history, which the
 * checkpoints keep (write one after this to commit it) and the result event carries. *record gets
 * the history's new entry (a new reference). The case's triggers become next's (those unchanged
 * keep whether they fired). SPH_ERR_INVALID (nothing changed) for an end time not
 * past the job's time, a job without a simulation, or what sph_sim_steer refuses. */
int sphd_exec_steer(sphd_exec *x, const sph_case *next, const json_t *set, json_t **record,
                    sph_error *err);
/* The steering history (borrowed; NULL when never steered). */
const json_t *sphd_exec_steering(const sphd_exec *x);

/* Continues a simulation from the latest valid checkpoint in outdir (the case must be the one the
 * job was submitted with). *fell_back is set when the latest checkpoint was damaged and the
 * previous one used; err->message then says why (code SPH_OK). NULL with err when there is no
 * valid checkpoint. */
sphd_exec *sphd_exec_resume(const sph_case *c, const char *outdir, int *fell_back, sph_error *err);

/* How sphd_exec_continue went: from the latest checkpoint, from the previous one (why: what was
 * wrong with the latest), or afresh (why: no checkpoint could be read; kept: how many checkpoint
 * files it could not read were set aside as NAME.unreadable, SPHD_CKPT_KEPT_NOTE). */
typedef struct sphd_continued {
    enum { SPHD_FROM_LATEST, SPHD_FROM_PREVIOUS, SPHD_AFRESH } from;
    int kept;
    sph_error why;
} sphd_continued;
#define SPHD_CKPT_KEPT_NOTE                                                                        \
    " (the checkpoint that could not be read is kept as checkpoint.unreadable)"

/* Continues a simulation from its checkpoint in outdir (sphd_exec_resume) or, when none can be
 * read, starts it afresh (sphd_exec_new) with the checkpoint files it could not read (another
 * version's state, or damaged) kept aside, not overwritten by the fresh run's first checkpoint.
 * *how says which. NULL with err when the fresh start fails. */
sphd_exec *sphd_exec_continue(const sph_case *c, const char *outdir, sphd_continued *how,
                              sph_error *err);

/* destroy(NULL) is a no-op. */
void sphd_exec_free(sphd_exec *x);

#endif
