/*
 * sph_lattice: particles on a lattice of spacing dx (particles at cell centres), counted. Pure
 * functions of numbers: the bottom of the set-up pipeline (DESIGN.md section 2, "the set-up as a
 * pipeline": lattice -> initial fields -> shapes -> fill -> sim).
 *
 * Layer 1 of the set-up. May call: nothing but libm (sph_config.h for the box type only).
 */
#ifndef SPH_LATTICE_H
#define SPH_LATTICE_H

#include "sph_config.h"

/* Particles along one axis, capped at SPH_LATTICE_AXIS_MAX so that products of counts never
 * overflow (a case that large is refused as too large anyway). */
#define SPH_LATTICE_AXIS_MAX 10000000L

/* Whole particles of spacing dx between lo and hi (floor((hi - lo) / dx) with a 1e-6 tolerance
 * for rounding; 0 for an empty or inverted range, capped so that products of counts cannot
 * overflow). */
long sph_lattice_axis_count(double lo, double hi, double dx);

/* Particles a box holds at spacing dx (0 if thinner than dx along an axis): the product of its
 * first dim axes' counts. */
long sph_lattice_box_count(const sph_box *b, int dim, double dx);

#endif
