/*
 * sphd_outputs: a simulation job's result files in its directory (DESIGN.md section 6):
 *   snap_NNNNNN.h5   particle snapshots at the case's output cadence (particles in creation order),
 *                    each with the fluid's RPDF (group /rpdf) when there is fluid
 *   particles.xmf    the XDMF time series over every snapshot (ParaView, VisIt)
 *   diag.h5          the diagnostics series, extendible datasets, readable while the job runs
 * Its state (the snapshots written so far, the next output time) goes into the job's checkpoints,
 * so a resumed job continues the same series.
 */
#ifndef SPHD_OUTPUTS_H
#define SPHD_OUTPUTS_H

#include "sph_case.h"
#include "sph_sim.h"

#include <jansson.h>

typedef struct sphd_outputs sphd_outputs;

/* Opens the result files of job `job` in dir for the sim s (its method decides the diagnostics
 * series). resume_step < 0 starts afresh; otherwise the diagnostics series keeps its rows up to
 * that step (a resumed job). */
sphd_outputs *sphd_outputs_open(const char *dir, const char *job, const sph_case *c,
                                const sph_sim *s, long resume_step, sph_error *err);

/* Appends the diagnostics row of d. */
int sphd_outputs_diag(sphd_outputs *o, const sph_diag *d, sph_error *err);

/* Simulated time of the next snapshot [s]; INFINITY when the case asks for none. */
double sphd_outputs_next_time(const sphd_outputs *o);

/* Writes the snapshot of s's current state, rewrites the XDMF, and returns the `output` event's
 * body (new reference) or NULL with err. */
json_t *sphd_outputs_snapshot(sphd_outputs *o, const sph_sim *s, sph_error *err);
/* A new period of the snapshots (steering) at time t: the next one at its first multiple after
 * t. */
void sphd_outputs_set_every(sphd_outputs *o, double every, double t);
/* The same out of the schedule (a trigger's): the next scheduled time stays what it was. */
json_t *sphd_outputs_snapshot_extra(sphd_outputs *o, const sph_sim *s, sph_error *err);

/* The state to checkpoint (new reference), and its restoration for a sim at time t [s] (output
 * times already behind t are passed over). */
json_t *sphd_outputs_state(const sphd_outputs *o);
int sphd_outputs_restore(sphd_outputs *o, const json_t *state, double t, sph_error *err);

/* close(NULL) is a no-op. */
void sphd_outputs_close(sphd_outputs *o);

#endif
