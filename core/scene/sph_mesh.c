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

/* TEMPORARY (replaced by the mesh branch's checks): accepts every surface. */
int sph_mesh_check_closed(const sph_mesh *m, const char *path, sph_error *err)
{
    (void)m;
    (void)path;
    (void)err;
    return 0;
}

int sph_mesh_polygon(sph_mesh *m, const double *xy, long n, const char *path, sph_error *err)
{
    memset(m, 0, sizeof *m);
    if (n < 3)
        return sph_error_set(err, SPH_ERR_INVALID, path, "a polygon needs at least 3 points");
    m->dim = 2;
    m->nv = n;
    m->nt = n;
    m->v = calloc(3 * (size_t)n, sizeof *m->v);
    m->t = malloc(2 * (size_t)n * sizeof *m->t);
    if (!m->v || !m->t) {
        sph_mesh_free(m);
        return sph_error_set(err, SPH_ERR_NOMEM, path, "out of memory");
    }
    for (long i = 0; i < n; i++) {
        m->v[3 * i] = xy[2 * i];
        m->v[3 * i + 1] = xy[2 * i + 1];
        m->t[2 * i] = (int)i;
        m->t[2 * i + 1] = (int)((i + 1) % n);
    }
    return 0;
}

double sph_mesh_volume(const sph_mesh *m)
{
    double v = 0.0;
    for (long f = 0; f < m->nt; f++) {
        const double *a = m->v + 3 * (size_t)m->t[3 * f], *b = m->v + 3 * (size_t)m->t[3 * f + 1],
                     *c = m->v + 3 * (size_t)m->t[3 * f + 2];
        v += a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
             a[2] * (b[0] * c[1] - b[1] * c[0]);
    }
    return v / 6.0;
}

void sph_mesh_flip(sph_mesh *m)
{
    for (long f = 0; f < m->nt; f++) {
        const int t = m->t[3 * f + 1];
        m->t[3 * f + 1] = m->t[3 * f + 2];
        m->t[3 * f + 2] = t;
    }
}
