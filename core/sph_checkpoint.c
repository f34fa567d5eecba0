/*
 * sph_sim_save / sph_sim_restore: the whole state a run needs to continue exactly, as bytes (the
 * server puts them in a checkpoint file). Saved: the configuration, the scalars of the time
 * integration (t, step, dt, the latest max acceleration and speed), the latest diagnostics, and
 * every per-particle array that lives from one step to the next, in the particles' current
 * (cell-sorted) order (the method lists them), then the rigid bodies' state. Not saved: what every
 * step rebuilds (the cell list, the probes' histogram, the force loop's scratch arrays).
 */
#include "sph_sim_impl.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#define SIM_MAGIC   "SPHSIM01"
#define SIM_VERSION 4u /* 2: sph_config.method; 4: rigid bodies (config and state) */

typedef struct {
    char magic[8];
    uint32_t version;
    uint32_t sps; /* 1 if the SPS arrays are present */
    int64_t n;    /* particles */
    int64_t nactive, nfluid, nboundary, step, failed, nbodies;
    double t, dt, amax, vmax;
    sph_config cfg;
    sph_diag diag;
} sim_header;

/* The per-particle arrays that persist across steps, in the method's fixed order. */
static int persistent_arrays(const sph_sim *s, double **d, int maxd)
{
    return s->ops->arrays(s, d, maxd);
}

int sph_sim_save(const sph_sim *s, void **buf, size_t *len, sph_error *err)
{
    double *arrays[32];
    const int na = persistent_arrays(s, arrays, 32);
    const size_t n = (size_t)s->P.n;
    const size_t nbs = (size_t)s->bodies.n;
    const size_t size = sizeof(sim_header) + (size_t)na * n * sizeof(double) +
                        n * (1 + sizeof(int)) + nbs * sizeof(sph_body_state);
    unsigned char *b = malloc(size);
    if (!b)
        return sph_error_set(err, SPH_ERR_NOMEM, "", "out of memory for a %zu-byte checkpoint",
                             size);
    sim_header h;
    memset(&h, 0, sizeof h);
    memcpy(h.magic, SIM_MAGIC, 8);
    h.version = SIM_VERSION;
    h.sps = s->P.txx != NULL;
    h.n = s->P.n;
    h.nactive = s->nactive;
    h.nfluid = s->nfluid;
    h.nboundary = s->nboundary;
    h.nbodies = s->bodies.n;
    h.step = s->step;
    h.failed = s->failed;
    h.t = s->t;
    h.dt = s->dt;
    h.amax = s->amax;
    h.vmax = s->vmax;
    h.cfg = s->cfg;
    h.diag = s->diag;
    unsigned char *p = b;
    memcpy(p, &h, sizeof h);
    p += sizeof h;
    for (int i = 0; i < na; i++) {
        memcpy(p, arrays[i], n * sizeof(double));
        p += n * sizeof(double);
    }
    memcpy(p, s->P.type, n);
    p += n;
    memcpy(p, s->P.id, n * sizeof(int));
    p += n * sizeof(int);
    for (size_t k = 0; k < nbs; k++) {
        memcpy(p, &s->bodies.b[k].s, sizeof(sph_body_state));
        p += sizeof(sph_body_state);
    }
    *buf = b;
    *len = size;
    return 0;
}

sph_sim *sph_sim_restore(const void *buf, size_t len, sph_error *err)
{
    sim_header h;
    if (len < sizeof h) {
        sph_error_set(err, SPH_ERR_IO, "", "simulation state truncated (%zu bytes)", len);
        return NULL;
    }
    memcpy(&h, buf, sizeof h);
    if (memcmp(h.magic, SIM_MAGIC, 8) != 0 || h.version != SIM_VERSION) {
        sph_error_set(err, SPH_ERR_IO, "", "not a simulation state of this version of sphd");
        return NULL;
    }
    sph_sim *s = sph_sim_create(&h.cfg, err);
    if (!s)
        return NULL;
    double *arrays[32];
    const int na = persistent_arrays(s, arrays, 32);
    const size_t n = (size_t)s->P.n;
    const size_t nbs = (size_t)s->bodies.n;
    if (h.n != s->P.n || (s->P.txx != NULL) != (h.sps != 0) || h.nbodies != s->bodies.n ||
        len != sizeof h + (size_t)na * n * sizeof(double) + n * (1 + sizeof(int)) +
                   nbs * sizeof(sph_body_state)) {
        sph_sim_destroy(s);
        sph_error_set(err, SPH_ERR_IO, "", "simulation state does not match its configuration");
        return NULL;
    }
    const unsigned char *p = (const unsigned char *)buf + sizeof h;
    for (int i = 0; i < na; i++) {
        memcpy(arrays[i], p, n * sizeof(double));
        p += n * sizeof(double);
    }
    memcpy(s->P.type, p, n);
    p += n;
    memcpy(s->P.id, p, n * sizeof(int));
    p += n * sizeof(int);
    for (size_t k = 0; k < nbs; k++) {
        memcpy(&s->bodies.b[k].s, p, sizeof(sph_body_state));
        p += sizeof(sph_body_state);
    }
    s->nactive = h.nactive;
    s->step = h.step;
    s->failed = (int)h.failed;
    s->t = h.t;
    s->dt = h.dt;
    s->amax = h.amax;
    s->vmax = h.vmax;
    s->diag = h.diag;
    return s;
}
