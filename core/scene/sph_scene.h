/*
 * sph_scene: the shapes of a case's "geometry" list, with their roles and transforms, and the
 * two questions a shape answers: "is this point inside?" and "how far is the surface?"
 * (DESIGN.md section 2, "the set-up as a scene"). A shape is a primitive (box, cylinder,
 * sphere), a 2D polygon or a 3D mesh (sph_mesh.h); each is placed by its transform (scale,
 * rotations about x, y then z, translation). Meshes answer over Embree's bounding-volume
 * hierarchy (closest points: rtcPointQuery; inside tests at any point: rays).
 *
 * The fill (sph_scene_fill) puts particles on one lattice of spacing dx for the whole list,
 * anchored at the domain's min corner (points at its cell centres, as DualSPHysics' GenCase
 * does), so that the items' particles never come closer than dx to one another. Along each
 * lattice row (x) a shape's inside is found exactly: a mesh's triangles (a polygon's sides) that
 * the row crosses, found in the plane across the row with a symbolic perturbation of the row
 * (simulation of simplicity), so that a row through an edge or a vertex crosses the surface
 * once, never twice or not at all; the row's points inside are those of non-zero winding number.
 * Each lattice point takes the role of the last item that holds it: fluid, or a wall's shell
 * (`layers` rows from its surface inwards); a void, and an obstacle's inside past its shell, take
 * the fluid out (never a wall particle); a wall's inside past its shell leaves the point as it
 * was.
 *
 * mDBC walls (sph_mdbc.h) take each wall particle's ghost node, its mirror point g = 2 s - x,
 * across the nearest point s of its shape's wet surface (sph_scene_mirror). A face is wet when
 * water can stand on its outer side: its outside point (a point of the face moved dx/2 out along
 * its normal) lies inside the domain and inside no other wall or obstacle shape of the scene (the
 * built-in tank's walls and obstacles among them). The points tried are a face's centroid and the
 * points half way from it to its corners (a mesh's triangle, a polygon's side, a box's face, a 3D
 * cylinder's cap; the face is wet when one of them is, so that a large face partly under another
 * wall stays wet); a round surface (a sphere, a circle, a cylinder's side) at the nearest point
 * itself. So the outer faces of a tank's walls (outside the domain), an obstacle's face on the
 * floor (inside the floor) and a floor under the obstacle (inside it) are dry, the faces towards
 * the water wet. Shells are walls' solids: a container is given as the solid of its walls (as
 * scripts/make-meshes.py --only test2 writes Test 2's tank: an open-top cup), not as a shape that
 * holds the water, whose faces point away from it.
 *
 * Rigid bodies (sph_body_shape.h: circles, boxes, polygons) keep their own rings of particles;
 * the scene leaves their places to them (sph_body_covers).
 *
 * Layer 3 of the set-up pipeline, beside sph_shapes (the built-in boxes). May call: sph_mesh.h,
 * sph_lattice.h, sph_eos.h, Embree, libm. Never the fill of the built-in shapes or the sim.
 */
#ifndef SPH_SCENE_H
#define SPH_SCENE_H

#include "sph_config.h"
#include "sph_error.h"

typedef struct sph_scene sph_scene;

/* Builds the scene of c's geometry list (with the built-in fluid boxes, tank and obstacles as
 * its first shapes: one lattice for all, when the list is not empty). Checks each item: a zero
 * or negative scale, a polygon in 3D or a mesh in 2D, a missing surface, a surface that does
 * not enclose a volume (sph_mesh_check_closed), a fluid item outside the domain, a wall item
 * that lies wholly outside it; SPH_ERR_INVALID at the item's path (/geometry/K...). NULL on
 * error (err filled). */
sph_scene *sph_scene_create(const sph_config *c, sph_error *err);
void sph_scene_destroy(sph_scene *s);

/* Shapes in the scene (the built-in ones first). */
int sph_scene_count(const sph_scene *s);

/* 1 if x (3 components; z = 0 in 2D) is inside shape k. */
int sph_scene_inside(const sph_scene *s, int k, const double *x);

/* The distance from x to shape k's surface [m]; its nearest point into near (may be NULL). */
double sph_scene_distance(const sph_scene *s, int k, const double *x, double *near);

/* Bytes the scene holds: its surfaces' copies and Embree's hierarchies. */
double sph_scene_bytes(const sph_scene *s);

/* Shape k's bounding box in the world [m]. */
void sph_scene_bounds(const sph_scene *s, int k, double *lo, double *hi);

/* The particles of the scene on its lattice. */
typedef struct sph_scene_counts {
    long fluid, wall;
    double lo[3], hi[3]; /* the box their points lie in (nothing: lo > hi) [m] */
} sph_scene_counts;

/* Classifies the lattice (SPH_ERR_NOMEM when the lattice it must walk is larger than max_bytes
 * allows, before anything is allocated for it) and counts the particles into *n. With pos and
 * rho not NULL, also writes the fluid's points, then the walls' (pos[d][0 ..], lattice order: x
 * slowest, the vertical axis fastest), and each one's hydrostatic density into rho[0 ..] (the
 * depth below the top of the water above it in its lattice column); with owner not NULL too,
 * each wall point's shape (the last wall or obstacle that put it there) into owner[0 .. n->wall),
 * in the walls' order. */
int sph_scene_fill(const sph_scene *s, const sph_config *c, sph_scene_counts *n, double *const *pos,
                   double *rho, int *owner, sph_error *err);

/* The geometry item shape k is (its index in c's "geometry" list), or -1 for a built-in shape
 * (a fluid box, one of the tank's walls, an obstacle: sph_shapes.h mirrors those). */
int sph_scene_item(const sph_scene *s, int k);

/* Marks the wet faces of the geometry's walls and obstacles (above) in the domain given, for
 * sph_scene_mirror. SPH_ERR_INVALID at the item's path (/geometry/K) for a mesh, polygon or box
 * wall with no wet face (nothing to mirror across: its faces point away from the water, or lie
 * outside the domain); SPH_ERR_NOMEM. */
int sph_scene_mark_wet(sph_scene *s, const sph_box *domain, sph_error *err);

/* The mirror point g = 2 s - x (3 components; 0 beyond dim) of the wall point x of shape k (a
 * geometry item's, after sph_scene_mark_wet), s the nearest point of the shape's wet surface.
 * Returns 0, or -1 with g = x when no part of it is wet (a sphere whose surface near x is under
 * another wall). Safe from several threads at once. */
int sph_scene_mirror(const sph_scene *s, int k, const double *x, double *g);

#endif
