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
#ifdef SPH_EXPERIMENTAL_MPS
    case SPH_METHOD_MPS: /* not validated yet (issue 12): only in -DSPH_EXPERIMENTAL_MPS=ON builds
                          */
        return &sph_mps_ops;
#endif
    default:
        return NULL;
    }
}

int sph_sim_has_method(sph_method m)
{
    return sph_method_ops_of(m) != NULL;
}
