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
    SPHD_EXEC_FAILED       /* failed; err says why (e.g. unstable: NaN at step N) */
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

/* Progress for status/query: {"t", "t_end", "step", "finished", "diag": {...latest diag...}}
 * (new ref; a kernel study has only step and finished). */
json_t *sphd_exec_progress(const sphd_exec *x);

/* Particle fields of a simulation job ("pos", "vel", "rho", "p", "type", "id"; at most 8),
 * downsampled evenly over the particles' creation order to at most max_particles:
 * {"total": N, "count": n, "fields": {"pos": [[x, y], ...], "rho": [...], ...}} (new ref).
 * NULL with err for a job without particles or an unknown field. */
json_t *sphd_exec_particles(const sphd_exec *x, const char *const *fields, int nfields,
                            long max_particles, sph_error *err);

/* destroy(NULL) is a no-op. */
void sphd_exec_free(sphd_exec *x);

#endif
