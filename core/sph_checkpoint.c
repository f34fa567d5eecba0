/*
 * sph_sim_save / sph_sim_restore: the whole state a run needs to continue exactly, as bytes (the
 * server puts them in a checkpoint file). Saved: the configuration, the scalars of the time
 * integration (t, step, dt, the latest max acceleration and speed), the latest diagnostics, and
 * every per-particle array that lives from one step to the next, in the particles' current
 * (cell-sorted) order (the method lists them), then the rigid bodies' state, then the geometry
 * walls' mirror points (mDBC; by id: a restored state has no surfaces to find them again), then
 * with a reused neighbour list the cells' starts of its latest build (the particles are still in
 * that build's order: the restored sim builds the list again from them, sph_method_ops.resume).
 * Not saved: what every step rebuilds (the cell list, the probes' histogram, the force loop's
 * scratch arrays) and the neighbour list itself.
 */
#include "sph_sim_impl.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#define SIM_MAGIC "SPHSIM01"
/* 2: sph_config.method; 3: sph_config.mps, sph_diag MPS fields; 4: ghost walls, monaghan
 * viscosity, initial fields, the envelope; 5: rigid bodies (config, diag and state); 6: the
 * walls' viscosity factor; 7: a body's pressure option; 8: sph_mps_config.stabilization; 9: the
 * height gauges (sph_config and sph_diag); 10: 3D (a gauge's y; the third axis's arrays);
 * 11: obstacles; 12: pressure probes (sph_config and sph_diag); 13: sph_config.diag_interval;
 * 14: sph_config.wall_density; 15: sph_config.device; 16: a pressure probe's normal
 * (sph_pressure_spec); 17: sph_config.delta_form; 18: sph_config.precision, float arrays
 * under mixed precision; 19: WCSPH saves no pressure array (derived from the density) */
#define SIM_VERSION                                                                                \
    28u /* 20: the geometry list (sph_config.geometry); 21: polygon bodies                         \
         * (sph_body_spec.corners); 22: geometry walls' mirror points (mDBC);                      \
         * 23: the wavemaker and the damping zone (sph_config.wavemaker,                           \
         * .absorption; the paddle's motion is a function of time, no state);                      \
         * 24: particle shifting (sph_config.shifting; its displacements live within a step);      \
         * 25: the reused neighbour list (sph_config.neighbour_skin; the cells' starts of its      \
         * build and the displacement since); 26: the flap's hinge and solitary waves              \
         * (sph_wavemaker_spec.hinge, SPH_WAVES_SOLITARY); 27: run-up gauges                       \
         * (sph_gauge_spec.to); 28: second-order, irregular and series waves                       \
         * (sph_wavemaker_spec.order, .spectrum, .hs, .tp, .gamma, .duration, .seed, .file,        \
         * .series, .active; a series' rows follow the header; the paddle's state) */

typedef struct {
    char magic[8];
    uint32_t version;
    uint32_t sps; /* 1 if the SPS arrays are present */
    int64_t n;    /* particles */
    int64_t nactive, nfluid, nboundary, step, failed, nbodies;
    int64_t nmirror; /* wall particles with a mirror point in the state (dim doubles each) */
    double t, dt, amax, vmax;
    int64_t nstart; /* the cells' starts saved (a reused neighbour list's build): 0 or ncells + 2 */
    double moved;   /* the neighbour list's displacement bound since its build [m] */
    int64_t nseries;         /* a series wavemaker's rows: their times then displacements follow */
    sph_paddle_state paddle; /* a piston's active absorption */
    sph_config cfg;
    sph_diag diag;
    sph_envelope wave; /* the kinetic-energy peaks so far (initial fields with a theory) */
} sim_header;

int sph_sim_save(const sph_sim *s, void **buf, size_t *len, sph_error *err)
{
    sph_array arrays[40];
    const int na = s->ops->arrays(s, arrays, 40);
    const size_t n = (size_t)s->P.n;
    const size_t nbs = (size_t)s->bodies.n;
    const size_t nm = (size_t)s->nmirror * (size_t)s->cfg.dim;
    const size_t ns = s->cfg.neighbour_skin > 0.0 ? (size_t)s->cells.ncells + 2 : 0;
    const size_t nq = (size_t)s->paddle.rows.n;
    const size_t size = sizeof(sim_header) + 2 * nq * sizeof(double) +
                        sph_method_arrays_size(arrays, na) * n + n * (1 + sizeof(int)) +
                        nbs * sizeof(sph_body_state) + nm * sizeof(double) + ns * sizeof(int);
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
    h.nmirror = s->nmirror;
    h.step = s->step;
    h.failed = s->failed;
    h.t = s->t;
    h.dt = s->dt;
    h.amax = s->amax;
    h.vmax = s->vmax;
    h.nstart = (int64_t)ns;
    h.moved = s->nlist.moved;
    h.nseries = (int64_t)nq;
    h.paddle = s->paddle.st;
    h.cfg = s->cfg;
    h.cfg.wavemaker.series = NULL; /* an address: the rows follow */
    h.diag = s->diag;
    h.wave = s->wave;
    unsigned char *p = b;
    memcpy(p, &h, sizeof h);
    p += sizeof h;
    if (nq) {
        memcpy(p, s->paddle.rows.t, nq * sizeof(double));
        memcpy(p + nq * sizeof(double), s->paddle.rows.x, nq * sizeof(double));
    }
    p += 2 * nq * sizeof(double);
    for (int i = 0; i < na; i++) {
        memcpy(p, arrays[i].p, n * arrays[i].size);
        p += n * arrays[i].size;
    }
    memcpy(p, s->P.type, n);
    p += n;
    memcpy(p, s->P.id, n * sizeof(int));
    p += n * sizeof(int);
    for (size_t k = 0; k < nbs; k++) {
        memcpy(p, &s->bodies.b[k].s, sizeof(sph_body_state));
        p += sizeof(sph_body_state);
    }
    if (nm)
        memcpy(p, s->mirror, nm * sizeof(double));
    p += nm * sizeof(double);
    if (ns)
        memcpy(p, s->cells.start, ns * sizeof(int));
    *buf = b;
    *len = size;
    return 0;
}

static sph_sim *restore(const void *buf, size_t len, int device, sph_error *err);

sph_sim *sph_sim_restore(const void *buf, size_t len, sph_error *err)
{
    return restore(buf, len, -1, err);
}

sph_sim *sph_sim_restore_on(const void *buf, size_t len, sph_device device, sph_error *err)
{
    return restore(buf, len, (int)device, err);
}

/* device: the device to run on, or -1 for the saved configuration's */
static sph_sim *restore(const void *buf, size_t len, int device, sph_error *err)
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
    /* a solitary wave saved before its "order" option has 0 in that slot: the first order it ran */
    if (h.cfg.initial.type == SPH_INITIAL_SOLITARY_WAVE && h.cfg.initial.param[2] == 0.0)
        h.cfg.initial.param[2] = SPH_SOL_ORDER_DEFAULT;
    for (int k = 0; k < SPH_CONFIG_MAX_GEOMETRY; k++) /* a saved address means nothing here */
        h.cfg.geometry[k].mesh = NULL;
    if (device >= 0) /* the state's layout is the same on every device */
        h.cfg.device = (sph_device)device;
    /* a series wavemaker's rows, right after the header */
    const size_t nq = (size_t)h.nseries;
    if (h.nseries < 0 || h.nseries > SPH_WAVE_SERIES_MAX ||
        (len - sizeof h) / (2 * sizeof(double)) < nq) {
        sph_error_set(err, SPH_ERR_IO, "", "simulation state has a bad wave series");
        return NULL;
    }
    sph_wave_series q = {.n = (long)nq};
    if (nq) {
        q.t = malloc(nq * sizeof(double));
        q.x = malloc(nq * sizeof(double));
        if (!q.t || !q.x) {
            free(q.t);
            free(q.x);
            sph_error_set(err, SPH_ERR_NOMEM, "", "out of memory for the wave series");
            return NULL;
        }
        memcpy(q.t, (const unsigned char *)buf + sizeof h, nq * sizeof(double));
        memcpy(q.x, (const unsigned char *)buf + sizeof h + nq * sizeof(double),
               nq * sizeof(double));
    }
    h.cfg.wavemaker.series = nq ? &q : NULL;
    const size_t hq = sizeof h + 2 * nq * sizeof(double); /* the header and the rows */
    /* the configuration's particles are the state's: checked before they are allocated */
    long nf = 0, nb = 0;
    sph_sim *s = NULL;
    if (sph_sim_check(&h.cfg, err))
        goto done;
    sph_sim_estimate_bytes(&h.cfg, &nf, &nb);
    if (h.n != nf + nb || (size_t)h.n > (len - hq) / (1 + sizeof(int))) {
        sph_error_set(err, SPH_ERR_IO, "", "simulation state does not match its configuration");
        goto done;
    }
    if (!isfinite(h.paddle.xc) || !isfinite(h.paddle.vc) || !isfinite(h.paddle.ebar) ||
        (!isfinite(h.paddle.level0) && !isinf(h.paddle.level0)) ||
        (!h.cfg.wavemaker.active &&
         (h.paddle.xc != 0.0 || h.paddle.vc != 0.0 || h.paddle.ebar != 0.0))) {
        sph_error_set(err, SPH_ERR_IO, "", "simulation state has a bad paddle state");
        goto done;
    }
    s = sph_sim_create(&h.cfg, err); /* its paddle copies the rows */
    if (s)
        s->paddle.st = h.paddle;
done:
    free(q.t);
    free(q.x);
    if (!s)
        return NULL;
    sph_array arrays[40];
    const int na = s->ops->arrays(s, arrays, 40);
    const size_t n = (size_t)s->P.n;
    const size_t nbs = (size_t)s->bodies.n;
    const size_t per = sph_method_arrays_size(arrays, na);
    const size_t nm = (size_t)s->nmirror * (size_t)s->cfg.dim;
    const size_t ns = s->cfg.neighbour_skin > 0.0 ? (size_t)s->cells.ncells + 2 : 0;
    if (h.n != s->P.n || (s->P.txx != NULL) != (h.sps != 0) || h.nbodies != s->bodies.n ||
        h.nmirror != s->nmirror || h.nstart != (int64_t)ns ||
        len != hq + per * n + n * (1 + sizeof(int)) + nbs * sizeof(sph_body_state) +
                   nm * sizeof(double) + ns * sizeof(int)) {
        sph_sim_destroy(s);
        sph_error_set(err, SPH_ERR_IO, "", "simulation state does not match its configuration");
        return NULL;
    }
    if (h.nactive < 0 || h.nactive > h.n || h.step < 0 || (h.failed != 0 && h.failed != 1) ||
        !isfinite(h.t) || !(h.dt >= 0 && isfinite(h.dt))) {
        sph_sim_destroy(s);
        sph_error_set(err, SPH_ERR_IO, "", "simulation state has impossible counters or times");
        return NULL;
    }
    const unsigned char *p = (const unsigned char *)buf + hq;
    /* types are SPH_FLUID, SPH_BOUNDARY, SPH_LOST or SPH_BODY (ghosts live only inside a force
     * evaluation), the ids a permutation of 0..n-1 (the server indexes by id), and a particle is
     * a body's exactly when its id is one of the bodies' (the pair loop and the bodies index
     * their tables by id - first): checked before anything is taken */
    const unsigned char *types = p + per * n;
    const unsigned char *ids = types + n;
    unsigned char *seen = calloc(n ? n : 1, 1);
    int bad = !seen;
    for (size_t i = 0; i < n && !bad; i++) {
        int id;
        memcpy(&id, ids + i * sizeof(int), sizeof id);
        const int body_id = s->bodies.n > 0 && (long)id >= s->bodies.first;
        bad = (types[i] > SPH_LOST && types[i] != SPH_BODY) || id < 0 || (size_t)id >= n ||
              seen[id]++ || (types[i] == SPH_BODY) != body_id;
    }
    free(seen);
    if (bad) {
        sph_sim_destroy(s);
        sph_error_set(err, SPH_ERR_IO, "", "simulation state has bad particle types or ids");
        return NULL;
    }
    for (int i = 0; i < na; i++) {
        memcpy(arrays[i].p, p, n * arrays[i].size);
        p += n * arrays[i].size;
    }
    memcpy(s->P.type, p, n);
    p += n;
    memcpy(s->P.id, p, n * sizeof(int));
    p += n * sizeof(int);
    for (size_t k = 0; k < nbs; k++) {
        memcpy(&s->bodies.b[k].s, p, sizeof(sph_body_state));
        p += sizeof(sph_body_state);
    }
    if (nm) {
        memcpy(s->mirror, p, nm * sizeof(double));
        for (size_t k = 0; k < nm; k++)
            if (!isfinite(s->mirror[k])) {
                sph_sim_destroy(s);
                sph_error_set(err, SPH_ERR_IO, "",
                              "simulation state has a mirror point that is not a number");
                return NULL;
            }
    }
    if (ns) { /* the list's cells: ascending from 0 to the active particles, then all of them */
        const unsigned char *st = p + nm * sizeof(double);
        int ok = isfinite(h.moved) && h.moved >= 0.0;
        int v = 0, prev = 0;
        for (size_t k = 0; k + 1 < ns && ok; k++) {
            memcpy(&v, st + k * sizeof v, sizeof v);
            ok = v >= prev && v <= h.nactive && (k > 0 || v == 0);
            prev = v;
        }
        int all;
        memcpy(&all, st + (ns - 1) * sizeof all, sizeof all);
        if (!ok || v != h.nactive || all != h.n) {
            sph_sim_destroy(s);
            sph_error_set(err, SPH_ERR_IO, "", "simulation state has a bad cell list");
            return NULL;
        }
        memcpy(s->cells.start, st, ns * sizeof(int));
    }
    s->nactive = h.nactive;
    s->step = h.step;
    s->failed = (int)h.failed;
    s->t = h.t;
    s->dt = h.dt;
    s->amax = h.amax;
    s->vmax = h.vmax;
    s->diag = h.diag;
    s->wave = h.wave;
    s->nlist.moved = h.moved;
    if (s->ops->resume && s->ops->resume(s, err)) {
        sph_sim_destroy(s);
        return NULL;
    }
    return s;
}
