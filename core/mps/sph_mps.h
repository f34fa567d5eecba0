/*
 * The MPS method's private interface (core/mps/ only): its row of the method table.
 * The numerics are in sph_mps_ops.h (interaction models), sph_mps_nbr.h (neighbour lists) and
 * sph_mps_ppe.h (the Poisson equation and its solve); the algorithm in sph_mps.c.
 */
#ifndef SPH_MPS_H
#define SPH_MPS_H

#include "sph_method.h"

extern const sph_method_ops sph_mps_ops;

#endif
