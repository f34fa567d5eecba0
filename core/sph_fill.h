/*
 * sph_fill: the particles of a case at its start, from its shapes. It asks each shape how many
 * particles it has and where (sph_shapes.h, sph_body_shape.h), and writes them into the particle
 * arrays: the fluid boxes' particles first, then the tank's wall particles and the obstacles'
 * (dynamic walls), then a wavemaker's paddle (sph_wavemaker.h), each
 * with its hydrostatic density, the fluid with the initial field's velocity (sph_initial.h), the
 * walls at rest. The rigid bodies' particles come last: sph_bodies_fill() places them from the
 * bodies' state (boundary/sph_body.h), after these.
 *
 * Layer 4 of the set-up pipeline (DESIGN.md section 2: case -> shapes -> particle fill -> sim).
 * May call: the shapes (sph_shapes.h, sph_body_shape.h), the initial fields (sph_initial.h), the
 * lattice (sph_lattice.h), libm. Never the bodies' dynamics or the sim, which call it.
 */
#ifndef SPH_FILL_H
#define SPH_FILL_H

#include "sph_config.h"
#include "sph_error.h"
#include "sph_particles.h"

/* The particles of a case, counted without being built. */
typedef struct sph_fill_counts {
    long fluid; /* fluid particles */
    long wall;  /* boundary particles of the tank's walls (dynamic walls; 0 with ghosts) */
    long body;  /* particles of the rigid bodies */
} sph_fill_counts;

/* A case with a geometry list (sph_scene.h): builds its scene and counts its particles into
 * c's geometry_* fields (sph_config.h), which sph_fill_count and the cell grid then read. A
 * no-op without geometry or once done. SPH_ERR_INVALID (an item's path) when the scene cannot be
 * built or, with mDBC walls, a geometry wall has no wet face (sph_scene_mark_wet), SPH_ERR_NOMEM
 * when its lattice is too large. */
int sph_fill_prepare(sph_config *c, sph_error *err);

/* The config to count and fill with: c itself when it needs no preparing (no scene, or the
 * scene's figures already in it), else *tmp, a copy of c prepared (sph_fill_prepare). NULL (err
 * filled, when not NULL) when the preparing fails. */
const sph_config *sph_fill_prepared(const sph_config *c, sph_config *tmp, sph_error *err);

/* Counts the particles of c. */
void sph_fill_count(const sph_config *c, sph_fill_counts *n);

/* 1 when c's wall particles take their mirror points (mDBC's ghost nodes, sph_mdbc.h) from the
 * fill: mDBC walls with a wall or obstacle item in the geometry list (without one, the built-in
 * boxes' rule, sph_shapes_wall_mirror, is computed where needed). */
int sph_fill_has_mirrors(const sph_config *c);

/* Fills P's first n.fluid + n.wall particles (sph_fill_count; P allocated for at least that):
 * fluid first, then the walls; ids their indices. With mirror not NULL (sph_fill_has_mirrors:
 * dim n.wall doubles), also the walls' mirror points: wall k's (id n.fluid + k) into
 * mirror[dim k ..], across its geometry item's nearest wet face (sph_scene_mirror; its own point
 * where none is wet), or by the built-in boxes' rule for the tank's and the obstacles' particles
 * (sph_shapes_wall_mirror). Returns 0; -1 when the scene cannot be built (a restored state's
 * surfaces are not at hand: the state holds the particles and the mirror points); or, with err,
 * sph_scene_mark_wet's error (a geometry wall with no wet face). */
int sph_fill(const sph_config *c, sph_particles *P, double *mirror, sph_error *err);

/* Ghosts the walls of a ghost-wall tank need for the initial lattice, counted on its geometry:
 * every fluid box's particles within `band` of a wall, one ghost per wall and per corner (2D);
 * per wall in 3D (the edges and corners left to the slack and to growth as needed). */
long sph_fill_ghosts_estimate(const sph_config *c, double band);

#endif
