/*
 * sph_geometry: builders that fill the particle arrays from a configuration's geometry: fluid
 * boxes at spacing dx (particles at cell centres), and the walls of a tank as `layers` layers of
 * dynamic boundary particles outside its inner faces (bottom, left and right; the top is open).
 * Fluid leaves the places of rigid bodies (boundary/sph_body.h) to them; the bodies' particles
 * are built by sph_body.c. The lattice counts are sph_lattice.h's.
 */
#ifndef SPH_GEOMETRY_H
#define SPH_GEOMETRY_H

#include "sph_config.h"
#include "sph_particles.h"

/* Counts the particles of a configuration without building them. */
void sph_geometry_count(const sph_config *c, long *nfluid, long *nboundary);

/* Fills P (allocated for nfluid + nboundary particles): fluid first, then boundary; velocity
 * zero; density hydrostatic under each fluid box (so that a column at rest starts at rest). */
void sph_geometry_fill(const sph_config *c, sph_particles *P);

/* The hydrostatic density at (x, y) under the deepest fluid box above it [kg/m^3]. */
double sph_geometry_hydrostatic_density(const sph_config *c, double x, double y);

#endif
