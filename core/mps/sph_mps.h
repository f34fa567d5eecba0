/*
 * The MPS method's private interface (core/mps/ and the MPS benchmarks): its row of the method
 * table, and the latest pressure equation for benchmarks.
 * The numerics are in sph_mps_ops.h (interaction models), sph_mps_nbr.h (neighbour lists) and
 * sph_mps_ppe.h (the Poisson equation and its solve); the algorithm in sph_mps.c.
 */
#ifndef SPH_MPS_H
#define SPH_MPS_H

#include "sph_method.h"
#include "sph_mps_ppe.h"
#include "sph_sim.h"

extern const sph_method_ops sph_mps_ops;

/* The pressure equation of s's latest step, for benchmarks that solve it again with other
 * solvers (bench/bench_mps_amg.c): the assembled matrix (borrowed: the sim's own workspace, valid
 * until the next step or destroy; solving with it between steps is harmless, the next step
 * assembles anew) and in *rhs its right-hand side per particle, in the order of the particle view
 * (sph_sim_particles). NULL when s is no MPS sim or has not stepped since it was created or
 * restored. */
sph_mps_ppe *sph_mps_latest_system(sph_sim *s, const double **rhs);

#endif
