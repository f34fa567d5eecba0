/*
 * sph_body_shape: the shapes of rigid bodies (a circle of diameter D, a box of edges w x h at an
 * angle, or a polygon given by its corners), as the case gives them, at their initial place: what a
 * shape contains, the points of its particles in its own frame, its area, moment of inertia, extent
 * and bounding radius. Nothing here moves: the bodies' dynamics is sph_body.c.
 *
 * Layer 3 of the set-up pipeline (the shapes; DESIGN.md section 2). May call: libm and the plain
 * configuration (sph_config.h) only. Called by the other shapes (sph_shapes.c: fluid leaves the
 * bodies' places), the fill (sph_fill.c: how many) and the bodies' dynamics (sph_body.c).
 */
#ifndef SPH_BODY_SHAPE_H
#define SPH_BODY_SHAPE_H

#include "sph_config.h"

/* Rounding slack of the geometric tests, in units of dx. */
#define SPH_BODY_EPS 1e-9

/* Counting stops past this many particles: more than any simulation may hold (2e9). */
#define SPH_BODY_COUNT_CAP 2100000000L

/* Area of the uniform solid shape [m^2]. */
double sph_body_shape_area(const sph_body_spec *b);

/* Moment of inertia of the uniform solid shape of mass m about its centre [kg m^2]. */
double sph_body_shape_inertia(const sph_body_spec *b, double m);

/* A polygon whose rings' lengths fall short of a circle's by at most this fraction still gets
 * the circle's rings: a polygon within dx/100 of a circle places its particles as the circle
 * would (sph_body_shape_points). */
#define SPH_BODY_POLYGON_TOL 0.02

/* The shape's extent at angle th from its centre: x from lo[0] to hi[0], y from lo[1] to hi[1]
 * [m] (a circle's and a box's are symmetric: lo = -hi). */
void sph_body_shape_extent(const sph_body_spec *b, double th, double lo[2], double hi[2]);

/* Radius of the circle about the centre that holds the shape [m]. */
double sph_body_shape_radius(const sph_body_spec *b);

/* 1 if x lies inside the shape grown by `grow`, the body at its initial place. */
int sph_body_shape_contains(const sph_body_spec *b, const double *x, double grow);

/* The body's particles in its own frame (angle 0) at spacing dx: rings of radius
 * R - (k + 1/2) dx for the circle (ring k has round(2 pi r / dx) particles, every other ring
 * turned by half a spacing; what is left at the centre, less than dx across, gets one particle), a
 * lattice centred in the box for the box; all of it or the outer `layers`. The outermost particles
 * sit dx/2 inside the surface. A polygon's rings are placed as the circle's, on its inward offsets
 * at d = (k + 1/2) dx (its sides moved in by d, meeting at mitres at convex corners and joined by
 * arcs of radius d about concave ones), each starting at the first corner's offset: ring k has
 * round(L / dx) particles evenly along the offset's length L, while L is at least pi dx (within
 * SPH_BODY_POLYGON_TOL); a point closer than d to another part of the surface (where a side has
 * vanished at that depth) is dropped; one particle at the last ring's centroid when that lies
 * farther than k dx inside. Writes xy (2 per particle) when not NULL; returns the count (a count
 * alone stops past SPH_BODY_COUNT_CAP). */
long sph_body_shape_points(const sph_body_spec *b, double dx, double *xy);

/* The points of body b at its initial place, as a new array (2 per point, *np of them); NULL
 * when out of memory. */
double *sph_body_shape_world_points(const sph_body_spec *b, double dx, long *np);

/* Body particles of all of c's bodies. */
long sph_body_count(const sph_config *c);

/* 1 if a fluid particle at x would fall inside a body of c (its shape grown by dx/2): the fluid
 * lattice leaves that place to the body. */
int sph_body_covers(const sph_config *c, const double *x);

#endif
