/*
 * The WCSPH method's private interface (core/wcsph/ only): the pair loops (sph_wcsph.c) and the
 * integrator and table row (sph_wcsph_step.c).
 */
#ifndef SPH_WCSPH_H
#define SPH_WCSPH_H

#include "sph_eos.h"
#include "sph_sim_impl.h"

/* sph_wcsph.c: builds the ghosts of free-slip walls, sorts the particles by cell, computes p,
 * then the accelerations (gravity included, zero for boundary particles) and density rates into
 * P.ax, P.ay, P.drho, and removes the ghosts again. Returns 0, or -1 when out of memory for the
 * ghosts (or for a kernel without a pair loop, the MPS weights, which wcsph_check refuses). */
int sph_wcsph_forces(sph_sim *s);

/* The same forces by the gather loop: each particle against every neighbour, its own side alone
 * (the GPU's scheduling; the sums run in another order, so the results agree to rounding, not
 * bit for bit). The C reference of the GPU kernels, for tests/unit/test_wcsph_gather.c. */
int sph_wcsph_forces_gather(sph_sim *s);

/* sph_wcsph_step.c: the method's row of the table. */
extern const sph_method_ops sph_wcsph_ops;

#endif
