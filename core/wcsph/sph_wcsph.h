/*
 * The WCSPH method's private interface (core/wcsph/ only): the pair loops (sph_wcsph.c) and the
 * integrator and table row (sph_wcsph_step.c).
 */
#ifndef SPH_WCSPH_H
#define SPH_WCSPH_H

#include "sph_eos.h"
#include "sph_sim_impl.h"
#include "sph_wcsph_loop.h"

/* sph_wcsph.c: builds the ghosts of free-slip walls, sorts the particles by cell, computes p,
 * then the accelerations (gravity included, zero for boundary particles) and density rates into
 * P.ax, P.ay, P.drho, and removes the ghosts again. Returns 0, or -1 when out of memory for the
 * ghosts (or for a kernel without a pair loop, the MPS weights, which wcsph_check refuses). */
int sph_wcsph_forces(sph_sim *s);

/* The same within a step of length dt: with the case's particle shifting
 * (physics.shifting, sph_shifting.h), the fluid particles shifted after the pair loop. */
int sph_wcsph_forces_step(sph_sim *s, double dt);

/* The same forces by the gather loop: each particle against every neighbour, its own side alone
 * (the GPU's scheduling; the sums run in another order, so the results agree to rounding, not
 * bit for bit). The C reference of the GPU kernels, for tests/unit/test_wcsph_gather.c. */
int sph_wcsph_forces_gather(sph_sim *s);

/* mDBC's no-penetration control after the corrector: the fluid particles moving into the first
 * layer of wall particles lose (or reverse) that part of their velocity. Returns 0, or -1 when
 * out of memory for the cells' wall map. */
int sph_wcsph_no_penetration(sph_sim *s);

void sph_wcsph_consts_of(const sph_sim *s, sph_wcsph_consts *k);

/* The symmetric pair loop over strip `strip` of the force context c (sph_wcsph_strips.h);
 * returns its pairs. */
typedef long (*sph_strip_fn)(const fctx *c, int strip);

/* sph_wcsph_strips_<type>.c: the pair loop's instantiation for kernel type T, dimension D and
 * the options flags (SPH_WF_* and F_MIXED), NULL for a combination sph_sim_check refuses. */
sph_strip_fn sph_wcsph_strip_SPH_KERNEL_CUBIC_SPLINE(int D, unsigned flags);
sph_strip_fn sph_wcsph_strip_SPH_KERNEL_GAUSSIAN(int D, unsigned flags);
sph_strip_fn sph_wcsph_strip_SPH_KERNEL_DOUBLE_COSINE(int D, unsigned flags);
sph_strip_fn sph_wcsph_strip_SPH_KERNEL_WENDLAND_C2(int D, unsigned flags);
sph_strip_fn sph_wcsph_strip_SPH_KERNEL_RENORMALIZED_GAUSSIAN(int D, unsigned flags);

/* A reused neighbour list (neighbours.skin): the largest displacement the predictor is about to
 * give a fluid particle of [0, n) over dt, from the velocities and the previous rates (ax0 ...);
 * the step adds it to s->nlist.moved before the force evaluation. */
double sph_wcsph_nlist_moved(const sph_sim *s, double dt, long n);

/* The method's `resume` entry: after a restore, the neighbour list built anew from the state's
 * order and cells (the same pairs in the same order as the list the state was saved with). */
int sph_wcsph_resume(sph_sim *s, sph_error *err);

/* sph_wcsph_step.c, shared by the CPU's step and the GPU's: the step's dt (at most dt_cap; a
 * collapsed dt is a blow-up: SPH_ERR_UNSTABLE), and the checks after it (bad: particles with a
 * non-finite velocity or density; rlo, rhi: the density range; then the lost particles). */
int sph_wcsph_step_dt(sph_sim *s, double dt_cap, double *dt, sph_error *err);
int sph_wcsph_predict_failed(const sph_sim *s, long step, double dt, long bad, sph_error *err);
int sph_wcsph_step_checks(sph_sim *s, long step, double dt, long bad, double rlo, double rhi,
                          sph_error *err);

/* sph_wcsph.c: the pressure of the current density (not stored) into the particles' scratch
 * array, *p in double or *p32 in float (mixed precision), the other NULL: the method's
 * `pressure` entry (sph_method_ops), and the bodies' pressure's source after the sort. */
void sph_wcsph_pressure(const sph_sim *s, const double **p, const float **p32);

/* sph_wcsph_step.c: the entries of the method's row that its GPU row shares (sph_method_ops
 * says what each does). */
size_t sph_wcsph_bytes_per_particle(const sph_config *c);
double sph_wcsph_dt(const sph_sim *s);
int sph_wcsph_arrays(const sph_sim *s, sph_array *d, int maxd);

/* sph_wcsph_step.c: the method's row of the table; sph_wcsph_gpu.c: its row on a GPU. */
extern const sph_method_ops sph_wcsph_ops;
extern const sph_method_ops sph_wcsph_gpu_ops;

#endif
