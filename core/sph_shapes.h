/*
 * sph_shapes: the shapes of a case that are not bodies, and what they say about the fluid at
 * rest. A fluid box is the lattice of spacing dx inside it (particles at cell centres), its top
 * raised by the initial field's surface elevation (sph_initial.h: the solitary wave's hump), less
 * the places of rigid bodies (sph_body_shape.h). A tank is `layers` layers of wall particles
 * outside its inner faces (bottom and sides: left and right, and in 3D front and back; the top is
 * open). The hydrostatic density is
 * the one under the deepest fluid column above a point, so that a column at rest starts at rest.
 *
 * Each shape answers "how many, where": its points' coordinates, written to pos[d] (d < dim) from
 * index 0 on, or only counted when pos is NULL. The fill (sph_fill.c) turns them into particles.
 *
 * The vertical axis is the last one (y in 2D; z in 3D): gravity acts along it, the free surface
 * is across it. The initial fields' elevation is a function of the first coordinate alone.
 *
 * Layer 3 of the set-up pipeline (the shapes; DESIGN.md section 2). May call: the bodies' shapes
 * (sph_body_shape.h), the initial fields (sph_initial.h: the surface elevation), the lattice
 * (sph_lattice.h), the equation of state (sph_eos.h), libm. Never the fill, the bodies'
 * dynamics or the sim.
 */
#ifndef SPH_SHAPES_H
#define SPH_SHAPES_H

#include "sph_config.h"

/* The vertical axis of a dim-dimensional case. */
static inline int sph_shapes_up(int dim)
{
    return dim - 1;
}

/* The free surface above the fluid box f at the point x [m]: the box's top, raised by the
 * initial field's elevation at x's abscissa. */
double sph_shapes_fluid_top(const sph_config *c, const sph_box *f, const double *x);

/* The box that the fluid box f's particles lie in: f with its top raised by the initial field's
 * largest elevation. */
sph_box sph_shapes_fluid_bounds(const sph_config *c, const sph_box *f);

/* The fluid box f's points, column by column along the first axis (the vertical axis innermost),
 * each column raised to the surface in whole particles, none where a body is (sph_body_covers).
 * Writes pos[d][0 ..] when pos is not NULL; returns the count. */
long sph_shapes_fluid_points(const sph_config *c, const sph_box *f, double *const *pos);

/* The 2D tank's wall points, `layers` layers outside its bottom and its sides (the top is open):
 * the bottom's rows (the corners with them), from the bottom face down, then the sides' layers,
 * left and right in turn, from the bottom up (a 3D tank of wall particles is the scene's:
 * sph_config_by_scene; 0 here). Writes pos[d][0 ..] when pos is not NULL; returns the count. */
long sph_shapes_tank_points(const sph_config *c, double *const *pos);

/* The obstacle box b's points: a lattice at spacing dx centred in the box, L / dx rounded points
 * along each axis (at least 1), so that its faces lie within dx/4 of the box's (on a box whose
 * sides are whole multiples of dx: the points at the centres of its cells). Writes pos[d][0 ..]
 * when pos is not NULL; returns the count. */
long sph_shapes_obstacle_points(const sph_config *c, const sph_box *b, double *const *pos);

/* The mirror point of the wall particle at x (mDBC, English et al. 2021: its ghost node) into g
 * (dim components; 0 beyond): x reflected across the nearest point of the water's side of the
 * wall it belongs to. For an obstacle's particle, the nearest face of the obstacle that can be
 * wet (not one on the tank's floor or against a tank wall); for a tank wall's particle, the
 * nearest point of the tank's inside, so that a particle in an edge or a corner of the walls is
 * reflected through that edge or corner. The faces are those the particles stand for: dx / 2
 * beyond the outermost particles (on the scene's lattice when the scene filled the case:
 * sph_config_by_scene). g = x for a point that belongs to no wall. (The walls of the geometry
 * list are mirrored across their own shapes' wet faces: sph_scene_mirror, through sph_fill.) */
void sph_shapes_wall_mirror(const sph_config *c, const double *x, double *g);

/* 1 if the point x lies where an obstacle is: within dx of the region of one's lattice (a fluid
 * point there would sit closer than dx to the obstacle's particles). */
int sph_shapes_in_obstacle(const sph_config *c, const double *x);

/* Distance from x to the region of the tank's wall points (2D): `layers` layers of dx outside its
 * bottom, left and right faces [m]. */
double sph_shapes_tank_distance(const sph_config *c, const double *x);

/* The hydrostatic density at x under the deepest fluid box above it [kg/m^3]: a box counts where
 * x lies within `margin` of it across the vertical axis (0: inside it; the walls, which lie
 * outside every box, look within their own thickness). */
double sph_shapes_hydrostatic_density(const sph_config *c, const double *x, double margin);

#endif
