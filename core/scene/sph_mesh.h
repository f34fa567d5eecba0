/*
 * sph_mesh: a closed surface as plain arrays: triangles in 3D, a polygon's segments in 2D. What a
 * mesh file (protocol/sph_mesh_io.h, assimp) or a case's "polygon" becomes before the scene
 * (sph_scene.h) builds its queries over it. Its checks say what is wrong with a surface that is to
 * have an inside: open edges, non-manifold edges, faces that cross each other.
 *
 * Bottom of the scene's floors. May call: sph_error.h, libc, libm.
 */
#ifndef SPH_MESH_H
#define SPH_MESH_H

#include "sph_error.h"

#include <stddef.h>

/* Default limits on a mesh (a case may not lower them below need; sphd's --mesh-* options). */
#define SPH_MESH_MAX_TRIANGLES_DEFAULT 5000000L
#define SPH_MESH_MAX_BYTES_DEFAULT     (256L << 20)
#define SPH_POLYGON_MAX_POINTS         100000L

typedef struct sph_mesh {
    int dim;         /* 3: triangles; 2: a closed polygon's segments */
    long nv;         /* vertices */
    double *v;       /* 3 nv coordinates [m] (z = 0 in 2D) */
    long nt;         /* triangles (3D) or segments (2D) */
    int *t;          /* 3 nt (3D) or 2 nt (2D) vertex indices, each in [0, nv) */
    long degenerate; /* degenerate triangles (zero area, repeated vertices) dropped on reading */
} sph_mesh;

typedef struct sph_mesh_limits {
    long max_triangles; /* more triangles than this: refused */
    size_t max_bytes;   /* a file larger than this: refused */
} sph_mesh_limits;

/* The default limits. */
sph_mesh_limits sph_mesh_limits_default(void);

/* Frees m's arrays and zeroes it (m may be NULL or zeroed). */
void sph_mesh_free(sph_mesh *m);

/* A 3D mesh from triangle soup: vertices welded (equal coordinates become one vertex), degenerate
 * triangles dropped and counted in m->degenerate. Takes nt triangles as 9 coordinates each.
 * Fails (SPH_ERR_INVALID at path) on non-finite coordinates, no triangle left, or more than
 * lim->max_triangles; SPH_ERR_NOMEM when out of memory. */
int sph_mesh_from_triangles(sph_mesh *m, const double *xyz, long nt, const sph_mesh_limits *lim,
                            const char *path, sph_error *err);

/* A 2D polygon of n points (x, y pairs), closed (the last point joins the first; a repeated last
 * point is dropped), any orientation. Fails (SPH_ERR_INVALID at path) on fewer than 3 distinct
 * points, non-finite coordinates, more than SPH_POLYGON_MAX_POINTS, repeated consecutive points
 * of zero length or two sides that cross or touch (the message names the two sides by index and
 * where they meet). */
int sph_mesh_polygon(sph_mesh *m, const double *xy, long n, const char *path, sph_error *err);

/* Checks that a 3D mesh encloses a volume: closed (every edge shared by exactly two triangles,
 * one each way: the message gives the number of open edges and one of them, by its end points),
 * manifold (no edge in more than two triangles, consistently oriented), and no two triangles
 * crossing each other (self-intersection; found over a grid of the triangles' boxes). 0 or
 * SPH_ERR_INVALID at path. A 2D polygon passes (sph_mesh_polygon checked it). */
int sph_mesh_check_closed(const sph_mesh *m, const char *path, sph_error *err);

/* The mesh's signed volume (3D; area in 2D) [m^3]: positive when its faces wind counter-
 * clockwise seen from outside (outward normals). */
double sph_mesh_volume(const sph_mesh *m);

/* A torus of radii R (the ring) and r (the tube) about the z axis as a closed, outward mesh of
 * nu x nv quads (two triangles each): for tests and benchmarks. 0, or SPH_ERR_NOMEM. */
int sph_mesh_torus(sph_mesh *m, double R, double r, int nu, int nv);

/* Turns every face over (outward normals to inward and back). */
void sph_mesh_flip(sph_mesh *m);

#endif
