/*
 * sph_method: the table of the particle methods of this build (sph_method.h).
 */
#include "sph_method.h"
#include "sph_sim.h"
#include "sph_mps.h"
#include "sph_wcsph.h"

const sph_method_ops *sph_method_ops_of(sph_method m)
{
    switch (m) {
    case SPH_METHOD_WCSPH:
        return &sph_wcsph_ops;
    case SPH_METHOD_MPS:
        return &sph_mps_ops;
    default:
        return NULL;
    }
}

const sph_method_ops *sph_method_ops_for(const sph_config *c)
{
    if (c->device == SPH_DEVICE_GPU)
        return c->method == SPH_METHOD_WCSPH ? &sph_wcsph_gpu_ops : NULL;
    return sph_method_ops_of(c->method);
}

int sph_sim_has_method(sph_method m)
{
    return sph_method_ops_of(m) != NULL;
}

void sph_core_init(void)
{
#ifdef SPH_HYPRE /* MPS's AMG solves (sph_mps_amg.c) */
    sph_mps_amg_process_init();
#endif
}
