/*
 * sph_geometry: builders that fill the particle arrays from a configuration's geometry: fluid
 * boxes at spacing dx (particles at cell centres), and the walls of a tank as `layers` layers of
 * dynamic boundary particles outside its inner faces (bottom, left and right; the top is open).
 * Fluid leaves the places of rigid bodies (boundary/sph_body.h) to them; the bodies' particles
 * are built by sph_body.c.
 */
#ifndef SPH_GEOMETRY_H
#define SPH_GEOMETRY_H

#include "sph_config.h"
#include "sph_particles.h"

/* Whole particles of spacing dx between lo and hi (floor((hi - lo) / dx) with a 1e-6 tolerance
 * for rounding; 0 for an empty or inverted range, capped so that products of counts cannot
 * overflow). */
long sph_geometry_axis_count(double lo, double hi, double dx);

/* Particles a box holds at spacing dx (0 if thinner than dx along an axis). */
long sph_geometry_box_count(const sph_box *b, int dim, double dx);

/* Counts the particles of a configuration without building them. */
void sph_geometry_count(const sph_config *c, long *nfluid, long *nboundary);

/* Fills P (allocated for nfluid + nboundary particles): fluid first, then boundary; velocity
 * zero; density hydrostatic under each fluid box (so that a column at rest starts at rest). */
void sph_geometry_fill(const sph_config *c, sph_particles *P);

/* The hydrostatic density at (x, y) under the deepest fluid box above it [kg/m^3]. */
double sph_geometry_hydrostatic_density(const sph_config *c, double x, double y);

#endif
