/*
 * Fuzz target: the mesh path, bytes in, a scene or a clear error out. The first byte chooses:
 * 'o' OBJ, 'p' PLY, 's' STL (binary or ASCII): the rest is a file, read through the guarded
 * reader (protocol/sph_mesh_io.h: assimp in a child process, whose crashes and loops must come
 * back as errors); 't': the rest is a triangle soup (9 floats a triangle), welded and checked in
 * this process (core/scene/sph_mesh.h). A mesh that passes its checks is then filled as fluid on
 * a coarse lattice (core/scene/sph_scene.h), and as an obstacle whose wall points get their mDBC
 * mirror points (its wet faces, then sph_scene_mirror). Small limits: 64 kB, 20000 triangles.
 * May call: sph_mesh_io.h, sph_mesh.h, sph_scene.h.
 */
#include "fuzz_util.h"

#include "sph_mesh.h"
#include "sph_mesh_io.h"
#include "sph_scene.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Fills m as the fluid of a case whose domain is its bounding box grown by a tenth, at a dx of
 * a tenth of its largest extent. */
static void fill(const sph_mesh *m)
{
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (long i = 0; i < m->nv; i++)
        for (int d = 0; d < 3; d++) {
            lo[d] = fmin(lo[d], m->v[3 * i + d]);
            hi[d] = fmax(hi[d], m->v[3 * i + d]);
        }
    double span = 0.0;
    for (int d = 0; d < 3; d++)
        span = fmax(span, hi[d] - lo[d]);
    if (!(span > 0.0) || !isfinite(span) || span > 1e30)
        return;
    sph_config c = sph_config_default();
    c.dim = 3;
    c.dx = span / 10.0;
    for (int d = 0; d < 3; d++) {
        c.domain.min[d] = lo[d] - 0.1 * span;
        c.domain.max[d] = hi[d] + 0.1 * span;
    }
    c.ngeometry = 1;
    c.geometry[0].kind = SPH_GEOM_MESH;
    c.geometry[0].role = SPH_ROLE_FLUID;
    c.geometry[0].transform.scale = 1.0;
    c.geometry[0].layers = 2;
    c.geometry[0].mesh = m;
    sph_error err;
    sph_scene *s = sph_scene_create(&c, &err);
    if (!s)
        return;
    sph_scene_counts n;
    (void)sph_scene_fill(s, &c, &n, NULL, NULL, NULL, &err);
    sph_scene_destroy(s);
    /* as an obstacle (at most 14^3 lattice points), its wall points mirrored */
    c.geometry[0].role = SPH_ROLE_OBSTACLE;
    c.boundary = SPH_BOUNDARY_DYNAMIC;
    c.wall_density = SPH_WALL_MDBC;
    if (!(s = sph_scene_create(&c, &err)))
        return;
    double *x = malloc(3 * 3000 * sizeof *x), *rho = malloc(3000 * sizeof *rho);
    int *owner = malloc(3000 * sizeof *owner);
    double *const pos[3] = {x, x + 3000, x + 6000};
    if (x && rho && owner && sph_scene_fill(s, &c, &n, NULL, NULL, NULL, &err) == 0 &&
        n.fluid + n.wall <= 3000 && sph_scene_fill(s, &c, &n, pos, rho, owner, &err) == 0 &&
        sph_scene_mark_wet(s, &c.domain, &err) == 0)
        for (long k = n.fluid; k < n.fluid + n.wall; k++) {
            const double p[3] = {pos[0][k], pos[1][k], pos[2][k]};
            double g[3];
            (void)sph_scene_mirror(s, owner[k - n.fluid], p, g);
        }
    free(x);
    free(rho);
    free(owner);
    sph_scene_destroy(s);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 1)
        return 0;
    sph_mesh_limits lim = {20000, 65536};
    sph_mesh m;
    sph_error err;
    int rc;
    if (data[0] == 't') {
        const long nt = (long)((size - 1) / 36);
        double *xyz = malloc((size_t)(nt > 0 ? nt : 1) * 9 * sizeof *xyz);
        if (!xyz)
            return 0;
        for (long i = 0; i < 9 * nt; i++) {
            float f;
            memcpy(&f, data + 1 + 4 * i, 4);
            xyz[i] = f;
        }
        rc = sph_mesh_from_triangles(&m, xyz, nt, &lim, "/geometry/0", &err);
        free(xyz);
    } else {
        const char *name = data[0] == 'o' ? "fuzz.obj" : data[0] == 'p' ? "fuzz.ply" : "fuzz.stl";
        rc = sph_mesh_read_memory(data + 1, size - 1, name, &lim, &m, "/geometry/0/mesh", &err);
    }
    if (rc == 0) {
        if (sph_mesh_check_closed(&m, "/geometry/0", &err) == 0)
            fill(&m);
        volatile double v = sph_mesh_volume(&m);
        (void)v;
        sph_mesh_flip(&m);
        sph_mesh_free(&m);
    }
    return 0;
}
