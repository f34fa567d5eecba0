/*
 * WCSPH on the GPU: the method table's row for a case with "device": "gpu" (core/gpu/sph_gpu.h
 * runs the step). It shares everything but the step with the CPU's row (sph_wcsph_step.c): the
 * checks, dt, the blow-up messages, the arrays a checkpoint saves (so a GPU job's checkpoint
 * restores on the CPU and the other way round). The set-up and the first force evaluation run
 * on the CPU (init); the particles go to the device at the first step and come back when the
 * host reads them (sync: diagnostics, outputs, checkpoints, queries).
 * The GPU runs dynamic walls (DBC, continuity density) without rigid bodies, with a wavemaker's
 * paddle and a damping zone: ghost walls, mDBC and bodies are refused at their paths.
 */
#include "sph_gpu.h"
#include "sph_wcsph.h"

#include <math.h>
#include <stdlib.h>

typedef struct gpu_state {
    sph_gpu *g;
    int stale; /* the host's particles are older than the device's */
} gpu_state;

static int gpu_check(const sph_config *c, sph_error *err)
{
    if (sph_gpu_count() < 1)
        return sph_error_set(err, SPH_ERR_INVALID, "/device",
#ifdef SPH_CUDA
                             "\"gpu\": no GPU is visible to this sphd; use \"device\": \"cpu\""
#else
                             "\"gpu\": this sphd was built without CUDA (cmake -DSPH_CUDA=ON "
                             "builds the GPU backend); use \"device\": \"cpu\", the default"
#endif
        );
    if (c->boundary != SPH_BOUNDARY_DYNAMIC)
        return sph_error_set(err, SPH_ERR_INVALID, "/boundary/type",
                             "the GPU runs dynamic walls only (\"type\": \"dynamic\"); ghost walls "
                             "run on the CPU (\"device\": \"cpu\")");
    /* TODO(issue 23): mDBC on the device (a thread per wall particle running mdbc_one's fit,
     * sph_mdbc.h, and one per fluid particle running nopen_one; the geometry walls' mirror
     * table, s->mirror, up with the particles), for Test 2's report with mDBC walls at 30 over
     * the depth, about 4 hours to 6 s on this project's 2-core machine */
    if (c->wall_density != SPH_WALL_CONTINUITY)
        return sph_error_set(err, SPH_ERR_INVALID, "/boundary/density",
                             "the GPU runs the walls' density by continuity only; mdbc runs on "
                             "the CPU (\"device\": \"cpu\")");
    if (c->nbodies > 0)
        return sph_error_set(err, SPH_ERR_INVALID, "/bodies",
                             "rigid bodies run on the CPU only (\"device\": \"cpu\")");
    /* TODO(issue 46): shifting on the device, a thread per fluid particle running shift_one
     * (sph_wcsph_loop.h) and sph_shifting_displacement, then one adding the displacements */
    if (c->shifting.type != SPH_SHIFT_NONE)
        return sph_error_set(err, SPH_ERR_INVALID, "/physics/shifting",
                             "shifting runs on the CPU only in this version (\"device\": "
                             "\"cpu\")");
    return sph_wcsph_ops.check(c, err);
}

static int gpu_init(sph_sim *s, sph_error *err)
{
    gpu_state *gs = calloc(1, sizeof *gs);
    if (!gs)
        return sph_error_set(err, SPH_ERR_NOMEM, "", "out of memory");
    s->mstate = gs;
    return sph_wcsph_ops.init(s, err); /* the first forces on the CPU */
}

/* The device's particles back on the host, in the host's cell order (the host's readers, the
 * probes among them, use its cells). */
static int gpu_sync(sph_sim *s, sph_error *err)
{
    gpu_state *gs = s->mstate;
    if (!gs || !gs->g || !gs->stale)
        return 0;
    if (sph_gpu_download(gs->g, &s->P, err))
        return -1;
    s->nactive = sph_cells_sort(&s->cells, &s->P);
    gs->stale = 0;
    return 0;
}

static int gpu_step(sph_sim *s, double dt_cap, sph_error *err)
{
    gpu_state *gs = s->mstate;
    if (!gs->g) { /* the first step: the particles (made, or restored) go to the device */
        sph_gpu_setup su = {.cfg = s->cfg, .kernel = s->kernel, .grid = s->cells};
        sph_wcsph_consts_of(s, &su.k);
        su.nactive = s->nactive;
        su.paddle = s->paddle; /* a wavemaker's (np 0: none) */
        if (!(gs->g = sph_gpu_create(&su, &s->P, err)))
            return err ? err->code : SPH_ERR_NOMEM;
    }
    const long step = s->step + 1;
    double dt;
    int rc = sph_wcsph_step_dt(s, dt_cap, &dt, err);
    if (rc)
        return rc;
    sph_gpu_step_out o;
    if (sph_gpu_step(gs->g, s->t, dt, &o, err))
        return err ? err->code : SPH_ERR_IO;
    gs->stale = 1;
    s->timing.neighbours += o.t_neighbours;
    s->timing.interactions += o.t_interactions;
    s->timing.integration += o.t_integration;
    s->timing.pairs = o.pairs;
    s->timing.active = o.nactive;
    if (o.bad_predict)
        return sph_wcsph_predict_failed(s, step, dt, o.bad_predict, err);
    s->nactive = o.nactive;
    s->amax = sqrt(o.amax2);
    s->vmax = sqrt(o.vmax2);
    s->t += dt;
    s->step = step;
    if (o.bad_correct || o.rho_lo < 0.5 * s->cfg.rho0 || o.rho_hi > 2.0 * s->cfg.rho0) {
        if ((rc = gpu_sync(s, err)) != 0) /* the message names a particle */
            return rc;
    }
    return sph_wcsph_step_checks(s, step, dt, o.bad_correct, o.rho_lo, o.rho_hi, err);
}

static void gpu_destroy(sph_sim *s)
{
    gpu_state *gs = s->mstate;
    if (gs)
        sph_gpu_destroy(gs->g);
    free(gs);
    s->mstate = NULL;
}

static double gpu_device_bytes(const sph_sim *s)
{
    const gpu_state *gs = s->mstate;
    return gs ? sph_gpu_bytes(gs->g) : 0.0;
}

const sph_method_ops sph_wcsph_gpu_ops = {
    .name = "wcsph",
    .check = gpu_check,
    .bytes_per_particle = sph_wcsph_bytes_per_particle,
    .init = gpu_init,
    .dt = sph_wcsph_dt,
    .step = gpu_step,
    .pressure = sph_wcsph_pressure,
    .diag = NULL,
    .arrays = sph_wcsph_arrays,
    .destroy = gpu_destroy,
    .sync = gpu_sync,
    .device_bytes = gpu_device_bytes,
};
