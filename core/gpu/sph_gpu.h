/*
 * sph_gpu: the WCSPH step on an NVIDIA GPU (CUDA; built with -DSPH_CUDA=ON, sph_gpu.cu). The whole
 * step stays on the device: the cell sort (keys, a stable radix sort, the cells' starts), the
 * per-particle preparation, the gather pair loop, gravity, the predictor and the corrector, a
 * wavemaker's paddle and a damping zone (core/boundary/sph_wavemaker.h's SPH_HD functions). The
 * physics is the C loops' own: every kernel calls the SPH_HD functions of
 * core/wcsph/sph_wcsph_particle.h, sph_wcsph_loop.h and sph_cells.h; this file adds the
 * scheduling, the reductions and the transfers only.
 *
 * The particles come back (sph_gpu_download) only when the host reads them: diagnostics,
 * outputs, checkpoints, queries (the method row, core/wcsph/sph_wcsph_gpu.c, decides when). In a
 * build without CUDA (sph_gpu_none.c) there are no devices and sph_gpu_create says so.
 * Several simulations may share one GPU: each owns its device arrays and its stream.
 */
#ifndef SPH_GPU_H
#define SPH_GPU_H

#include "sph_cells.h"
#include "sph_config.h"
#include "sph_error.h"
#include "sph_kernel.h"
#include "sph_particles.h"
#include "sph_wavemaker.h"
#include "sph_wcsph_loop.h"

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct sph_gpu sph_gpu;

/* What the device needs besides the particles: all copied at creation. */
typedef struct sph_gpu_setup {
    sph_config cfg;     /* EOS, gravity, domain, the options */
    sph_kernel kernel;  /* the kernel as initialised for the run */
    sph_cells grid;     /* the grid's shape (its arrays are not read) */
    sph_wcsph_consts k; /* the force constants (no ghosts, no bodies among the options) */
    long nactive;       /* the particles in cells (the rest, lost, at the end) */
    sph_paddle paddle;  /* a wavemaker's (np 0: none); its rest table the host's, copied */
} sph_gpu_setup;

/* What a step found: the active count after the sort, the predictor's and corrector's non-finite
 * counts, the largest fluid speed and acceleration squared, the density range, the pairs, and
 * the device time of each phase [s]. */
typedef struct sph_gpu_step_out {
    long nactive, bad_predict, bad_correct, pairs;
    double vmax2, amax2, rho_lo, rho_hi;
    double t_neighbours, t_interactions, t_integration;
} sph_gpu_step_out;

/* The visible GPUs: their count (0 without CUDA or without a device); the name and memory of
 * device k into name (len bytes) and *bytes when asked. */
int sph_gpu_count(void);
int sph_gpu_describe(int k, char *name, size_t len, double *bytes);

/* Allocates the device arrays for P's particles and copies them, with the setup, to the device.
 * NULL with err set (SPH_ERR_INVALID without a GPU, SPH_ERR_NOMEM when it does not fit). */
sph_gpu *sph_gpu_create(const sph_gpu_setup *su, const sph_particles *P, sph_error *err);

/* One step of dt from time t: predictor (and a paddle placed at t + dt), sort, forces, corrector
 * (and a damping zone). Returns 0, or -1 with err set when the device fails (the step's figures
 * in *o either way). */
int sph_gpu_step(sph_gpu *g, double t, double dt, sph_gpu_step_out *o, sph_error *err);

/* Copies the particles back into P (which must hold as many); the device order, which is the
 * cell order of the latest sort. Returns 0 or -1 with err set. */
int sph_gpu_download(sph_gpu *g, sph_particles *P, sph_error *err);

/* Device bytes the simulation holds. */
double sph_gpu_bytes(const sph_gpu *g);

void sph_gpu_destroy(sph_gpu *g);

#ifdef __cplusplus
}
#endif

#endif
