/*
 * sph_mesh: surfaces as plain arrays, and their checks (sph_mesh.h).
 */
#include "sph_mesh.h"

#include <stdlib.h>
#include <string.h>

sph_mesh_limits sph_mesh_limits_default(void)
{
    sph_mesh_limits l = {SPH_MESH_MAX_TRIANGLES_DEFAULT, (size_t)SPH_MESH_MAX_BYTES_DEFAULT};
    return l;
}

void sph_mesh_free(sph_mesh *m)
{
    if (!m)
        return;
    free(m->v);
    free(m->t);
    memset(m, 0, sizeof *m);
}
