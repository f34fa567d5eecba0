/*
 * sph_mesh_io: mesh files (STL binary and ASCII, OBJ, PLY) read into an sph_mesh through
 * assimp's C API. The format comes from the file name's extension; every mesh of the file is
 * triangulated, its node transforms applied, points and lines ignored, and the triangles welded
 * by sph_mesh_from_triangles. Nothing is printed (assimp's logger is never attached).
 *
 * May call: sph_mesh.h, sph_error.h, assimp (cimport.h), libc.
 */
#ifndef SPH_MESH_IO_H
#define SPH_MESH_IO_H

#include "sph_error.h"
#include "sph_mesh.h"

#include <stddef.h>

/* The reader runs in a child process (fork) with at most SPH_MESH_READ_SECONDS of CPU and of
 * wall time: assimp 5.2 is not safe on hostile files (fuzz_mesh found an abort, a read past the
 * end and an endless loop in it), and a broken mesh must never take sphd down with it. A crash,
 * a time out or an abort in the child is a clear SPH_ERR_INVALID naming the file. */
#define SPH_MESH_READ_SECONDS 30

/* A mesh from a file's bytes; name is the file's name (its extension picks the format, and the
 * messages name it). More than lim->max_bytes is refused before parsing (lim NULL: the
 * defaults). 0, or SPH_ERR_INVALID at path (unknown format, empty or unparsable file, no
 * triangle, too many), SPH_ERR_NOMEM. On failure *out is zeroed. */
int sph_mesh_read_memory(const void *bytes, size_t len, const char *name,
                         const sph_mesh_limits *lim, sph_mesh *out, const char *path,
                         sph_error *err);

/* The same in this process, unguarded (the child's half of sph_mesh_read_memory; the fuzz target
 * runs it on the inputs that pass the checks before assimp). */
int sph_mesh_read_unguarded(const void *bytes, size_t len, const char *name,
                            const sph_mesh_limits *lim, sph_mesh *out, const char *path,
                            sph_error *err);

/* A mesh from a file: its size checked against lim->max_bytes first, then read whole and given
 * to sph_mesh_read_memory with name (NULL: file). SPH_ERR_IO when it cannot be read. */
int sph_mesh_read_file(const char *file, const char *name, const sph_mesh_limits *lim,
                       sph_mesh *out, const char *path, sph_error *err);

#endif
