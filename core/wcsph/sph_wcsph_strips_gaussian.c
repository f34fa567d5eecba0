/* The symmetric pair loop's instantiations for the gaussian kernel (sph_wcsph_strips.h). */
#include "sph_wcsph_strips.h"

SPH_STRIPS_OF(SPH_KERNEL_GAUSSIAN)
