/*
 * sph_method: the per-method table behind the sim handle. sph_sim.c knows each method only as a
 * row of this table; a method's files (wcsph/, mps/) know the handle through sph_sim_impl.h.
 * Nothing outside this table branches on the method.
 *
 * The handle owns what every method shares: the configuration, the particles (positions,
 * velocities, density or number density, pressure, type, id), the cell list, time, step, dt,
 * the diagnostics and the timers. A method keeps anything else in s->mstate.
 */
#ifndef SPH_METHOD_H
#define SPH_METHOD_H

#include "sph_config.h"
#include "sph_error.h"

#include <stddef.h>

typedef struct sph_sim sph_sim;

/* A per-particle array and the bytes of one of its elements. */
typedef struct sph_array {
    void *p;
    size_t size;
} sph_array;

typedef struct sph_method_ops {
    const char *name;    /* the case file's "method" */
    int solves_pressure; /* 1: a pressure equation per step, its figures in sph_diag (cg_*,
                            free_surface) */
    /* Checks the configuration fields the method reads (err->path names the case field).
     * Called by sph_sim_create() after the shared checks. */
    int (*check)(const sph_config *cfg, sph_error *err);
    /* Bytes per particle of the particle storage the method needs. */
    size_t (*bytes_per_particle)(const sph_config *cfg);
    /* Particles are built: allocate s->mstate, evaluate what the first step needs. */
    int (*init)(sph_sim *s, sph_error *err);
    /* The time step the next step would take, before any cap [s]. */
    double (*dt)(const sph_sim *s);
    /* One step of at most dt_cap [s]; updates s->t, s->step, s->dt. Returns 0 or
     * SPH_ERR_UNSTABLE (message with the step and the quantity). */
    int (*step)(sph_sim *s, double dt_cap, sph_error *err);
    /* The pressure for a particle view, into *p (double) or, under mixed precision, *p32
     * (float; the other NULL): the method's stored pressure, or one it derives into the
     * particles' scratch array, which holds nothing between two steps (so the sim stays const:
     * no state is written). */
    void (*pressure)(const sph_sim *s, const double **p, const float **p32);
    /* Fills the method's own diagnostics into s->diag after the shared ones; may be NULL. */
    void (*diag)(sph_sim *s);
    /* The per-particle arrays that live from one step to the next, in a fixed order (what a
     * checkpoint saves besides type and id), with their element sizes (double, or float under
     * mixed precision); returns how many (at most maxd). */
    int (*arrays)(const sph_sim *s, sph_array *d, int maxd);
    /* After a restore (the state's particles in their saved order, s->cells.start as the state
     * saved it with a reused neighbour list): rebuilds what the next step reads besides them.
     * Returns 0 or an error code with err set; may be NULL. */
    int (*resume)(sph_sim *s, sph_error *err);
    /* Frees s->mstate; may be NULL. */
    void (*destroy)(sph_sim *s);
    /* A device backend: brings the host's particles up to date with the device's (called
     * before the host reads them: diagnostics, outputs, checkpoints, queries). Returns 0 or an
     * error code with err set. NULL for the CPU's rows. */
    int (*sync)(sph_sim *s, sph_error *err);
    /* A device backend: the bytes the simulation holds on the device. NULL for the CPU's. */
    double (*device_bytes)(const sph_sim *s);
} sph_method_ops;

/* For a method's `arrays`: copies the non-NULL arrays of all[0..nall) to d (at most maxd, in
 * order) and returns how many. */
static inline int sph_method_arrays(const sph_array *all, int nall, sph_array *d, int maxd)
{
    int n = 0;
    for (int i = 0; i < nall && n < maxd; i++)
        if (all[i].p)
            d[n++] = all[i];
    return n;
}

/* The bytes per particle of arrays a[0..na). */
static inline size_t sph_method_arrays_size(const sph_array *a, int na)
{
    size_t b = 0;
    for (int i = 0; i < na; i++)
        b += a[i].size;
    return b;
}

/* The row of method m, or NULL when m is not a particle simulation of this build. */
const sph_method_ops *sph_method_ops_of(sph_method m);

/* The row that runs configuration c: its method's, on its device (NULL: no such row; WCSPH is
 * the one method with a GPU row). */
const sph_method_ops *sph_method_ops_for(const sph_config *c);

#endif
