/* The symmetric pair loop's instantiations for the double cosine kernel (sph_wcsph_strips.h). */
#include "sph_wcsph_strips.h"

SPH_STRIPS_OF(SPH_KERNEL_DOUBLE_COSINE)
