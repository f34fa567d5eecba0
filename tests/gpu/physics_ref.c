/* The reference side of ctest gpu_physics: the shared physics (physics_cases.h) compiled by the
 * project's C compiler, as the CPU solver compiles it. */
#include "physics_cases.h"

void pc_reference(const sph_kernel *kern, const sph_config *lin, const sph_config *tait,
                  double *out)
{
    for (int i = 0; i < PC_SAMPLES; i++)
        pc_eval(i, kern, lin, tait, out + (long)i * PC_OUT);
}
