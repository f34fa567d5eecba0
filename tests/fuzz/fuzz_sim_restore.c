/*
 * Fuzz target: sph_sim_restore, the core's reading of a saved simulation state (the "sim" section
 * of a checkpoint). A state that restores is stepped once, so that what restore accepted is also
 * safe to run.
 */
#include "fuzz_util.h"

#include "sph_sim.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    sph_error err;
    sph_sim *s = sph_sim_restore(data, size, &err);
    if (s) {
        (void)sph_sim_diag(s);
        sph_sim_step(s, 1, &err);
        sph_sim_destroy(s);
    }
    return 0;
}
