/*
 * Fuzz target: mesh files (protocol/sph_mesh_io.h, assimp) and the checks on what they give
 * (core/scene/sph_mesh.h). Input: one byte choosing the format ('o': OBJ, 'p': PLY, anything
 * else: STL, binary or ASCII), then the file's bytes. Read with small limits (64 kB, 20000
 * triangles), then checked for being closed, its volume taken, and freed.
 * May call: sph_mesh_io.h, sph_mesh.h.
 */
#include "fuzz_util.h"

#include "sph_mesh.h"
#include "sph_mesh_io.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 1)
        return 0;
    const char *name = data[0] == 'o' ? "fuzz.obj" : data[0] == 'p' ? "fuzz.ply" : "fuzz.stl";
    sph_mesh_limits lim = {20000, 65536};
    sph_mesh m;
    sph_error err;
    if (sph_mesh_read_memory(data + 1, size - 1, name, &lim, &m, "/geometry/0/mesh", &err) == 0) {
        (void)sph_mesh_check_closed(&m, "/geometry/0", &err);
        volatile double v = sph_mesh_volume(&m);
        (void)v;
        sph_mesh_flip(&m);
        sph_mesh_free(&m);
    }
    return 0;
}
