/* The symmetric pair loop's instantiations for the cubic spline kernel (sph_wcsph_strips.h). */
#include "sph_wcsph_strips.h"

SPH_STRIPS_OF(SPH_KERNEL_CUBIC_SPLINE)
