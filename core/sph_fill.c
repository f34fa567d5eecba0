/*
 * sph_fill: the particles of a case from its shapes (sph_fill.h).
 *
 * Layer 4 of the set-up pipeline. May call: sph_shapes.h, sph_scene.h (a case with a geometry
 * list: every shape, the built-in ones too, on one lattice), sph_body_shape.h, sph_wavemaker.h (the
 * paddle's particles), sph_initial.h (the velocity), sph_lattice.h, libm. Never sph_body.c or
 * sph_sim.c.
 */
#include "sph_fill.h"

#include "sph_body_shape.h"
#include "sph_initial.h"
#include "sph_lattice.h"
#include "sph_scene.h"
#include "sph_shapes.h"
#include "sph_wavemaker.h"

#include <math.h>
#include <stdlib.h>

static int has_walls(const sph_config *c)
{
    return c->has_tank && c->boundary == SPH_BOUNDARY_DYNAMIC;
}

int sph_fill_prepare(sph_config *c, sph_error *err)
{
    if (!sph_config_by_scene(c) || c->geometry_filled)
        return 0;
    sph_scene *sc = sph_scene_create(c, err);
    if (!sc)
        return err ? err->code : SPH_ERR_INVALID;
    sph_scene_counts n;
    int rc = sph_scene_fill(sc, c, &n, NULL, NULL, NULL, err);
    /* the domain's max faces out to the whole lattice cells they cut: a tank whose inside is
     * the domain has its walls on the lattice, up to dx beyond the faces given, and the water
     * between is not lost */
    sph_box domain = c->domain;
    for (int d = 0; d < c->dim; d++) {
        const double o = c->domain.min[d] + 0.5 * c->dx;
        const double cell = o + (floor((c->domain.max[d] - o) / c->dx + 1e-9) + 0.5) * c->dx;
        if (cell > domain.max[d])
            domain.max[d] = cell;
    }
    /* mDBC: every geometry wall has a face to mirror across (found again by sph_fill) */
    if (rc == 0 && sph_fill_has_mirrors(c))
        rc = sph_scene_mark_wet(sc, &domain, err);
    sph_scene_destroy(sc);
    if (rc)
        return rc;
    c->geometry_filled = 1;
    c->domain = domain;
    c->geometry_fluid = n.fluid;
    c->geometry_wall = n.wall;
    for (int d = 0; d < 3; d++) {
        c->geometry_lo[d] = n.lo[d];
        c->geometry_hi[d] = n.hi[d];
    }
    return 0;
}

const sph_config *sph_fill_prepared(const sph_config *c, sph_config *tmp, sph_error *err)
{
    if (!sph_config_by_scene(c) || c->geometry_filled)
        return c;
    *tmp = *c; /* the scene's counts and reach, found once, in the copy */
    return sph_fill_prepare(tmp, err) == 0 ? tmp : NULL;
}

void sph_fill_count(const sph_config *c, sph_fill_counts *n)
{
    if (sph_config_by_scene(c)) { /* the scene holds the built-in shapes too */
        sph_config tmp;
        const sph_config *f = sph_fill_prepared(c, &tmp, NULL);
        n->fluid = f ? f->geometry_fluid : 0;
        n->wall = f ? f->geometry_wall : 0;
        if (has_walls(c)) /* a wavemaker's paddle after the scene's walls */
            n->wall += sph_wavemaker_points(c, NULL);
        n->body = sph_body_count(c);
        return;
    }
    n->fluid = 0;
    for (int b = 0; b < c->nfluid; b++)
        n->fluid += sph_shapes_fluid_points(c, &c->fluid[b], NULL);
    n->wall = has_walls(c) ? sph_shapes_tank_points(c, NULL) : 0;
    if (c->boundary == SPH_BOUNDARY_DYNAMIC)
        for (int k = 0; k < c->nobstacles; k++)
            n->wall += sph_shapes_obstacle_points(c, &c->obstacles[k], NULL);
    if (has_walls(c))
        n->wall += sph_wavemaker_points(c, NULL); /* the paddle: the last wall particles */
    n->body = sph_body_count(c);
}

/* Particles [i0, i1) of P, whose positions a shape wrote: their type, id, velocity (the initial
 * field's for the fluid, rest for walls) and density: rho[i - i0] where rho is given (the scene's),
 * else the hydrostatic one of the fluid boxes (looking `margin` across). */
static void settle(const sph_config *c, sph_particles *P, long i0, long i1, int type, double margin,
                   const double *rho)
{
    for (long i = i0; i < i1; i++) {
        const double x[3] = {P->x[i], P->y[i], P->z ? P->z[i] : 0.0};
        double v[3] = {0.0, 0.0, 0.0};
        if (type == SPH_FLUID)
            sph_initial_velocity(c, x, v);
        const int M = P->mixed;
        SPH_SET(M, P, vx, i, v[0]);
        SPH_SET(M, P, vy, i, v[1]);
        if (P->dim == 3)
            SPH_SET(M, P, vz, i, v[2]);
        SPH_SET(M, P, rho, i, rho ? rho[i - i0] : sph_shapes_hydrostatic_density(c, x, margin));
        P->type[i] = (unsigned char)type;
        P->id[i] = (int)i;
    }
}

int sph_fill_has_mirrors(const sph_config *c)
{
    if (c->wall_density != SPH_WALL_MDBC || c->boundary != SPH_BOUNDARY_DYNAMIC)
        return 0;
    for (int k = 0; k < c->ngeometry; k++)
        if (c->geometry[k].role == SPH_ROLE_WALL || c->geometry[k].role == SPH_ROLE_OBSTACLE)
            return 1;
    return 0;
}

/* The walls' mirror points (sph_fill): wall k of the scene at P's particle i0 + k, of shape
 * owner[k], into mirror[dim k ..]. */
static int mirrors(sph_scene *sc, const sph_config *c, const sph_particles *P, long i0, long nwall,
                   const int *owner, double *mirror, sph_error *err)
{
    const int rc = sph_scene_mark_wet(sc, &c->domain, err);
    if (rc)
        return rc;
    const int dim = c->dim;
#pragma omp parallel for schedule(dynamic, 256)
    for (long k = 0; k < nwall; k++) {
        const long i = i0 + k;
        const double x[3] = {P->x[i], P->y[i], P->z ? P->z[i] : 0.0};
        double g[3];
        if (sph_scene_item(sc, owner[k]) < 0)
            sph_shapes_wall_mirror(c, x, g);
        else
            sph_scene_mirror(sc, owner[k], x, g);
        for (int d = 0; d < dim; d++)
            mirror[(size_t)dim * (size_t)k + (size_t)d] = g[d];
    }
    return 0;
}

/* A wavemaker's paddle (sph_wavemaker.h), the last wall particles, from P's particle i on:
 * their count (0 without one). */
static long fill_paddle(const sph_config *c, sph_particles *P, long i)
{
    if (!has_walls(c))
        return 0;
    double *const at[3] = {P->x + i, P->y + i, P->z ? P->z + i : NULL};
    const long n = sph_wavemaker_points(c, at);
    settle(c, P, i, i + n, SPH_BOUNDARY, (c->wavemaker.layers + 0.5) * c->dx, NULL);
    return n;
}

/* The geometry's particles (the built-in shapes among them) from its scene, and the walls'
 * mirror points with mirror not NULL; 0, -1 when the scene cannot be built or filled (a restored
 * state's surfaces are not at hand: its particles come from the state), or sph_scene_mark_wet's
 * error. */
static int fill_scene(const sph_config *c, sph_particles *P, double *mirror, sph_error *err)
{
    sph_scene *sc = sph_scene_create(c, NULL);
    if (!sc)
        return -1;
    const long n = c->geometry_fluid + c->geometry_wall;
    double *rho = malloc((size_t)(n > 0 ? n : 1) * sizeof *rho);
    const long nw = c->geometry_wall > 0 ? c->geometry_wall : 1;
    int *owner = mirror ? malloc((size_t)nw * sizeof *owner) : NULL;
    double *const at[3] = {P->x, P->y, P->z};
    sph_scene_counts cnt;
    int rc = rho && (owner || !mirror) ? sph_scene_fill(sc, c, &cnt, at, rho, owner, NULL) : -1;
    if (rc == 0 && (cnt.fluid != c->geometry_fluid || cnt.wall != c->geometry_wall))
        rc = -1;
    if (rc == 0) {
        settle(c, P, 0, cnt.fluid, SPH_FLUID, 0.0, rho);
        settle(c, P, cnt.fluid, n, SPH_BOUNDARY, 0.0, rho + cnt.fluid);
        if (mirror)
            rc = mirrors(sc, c, P, cnt.fluid, cnt.wall, owner, mirror, err);
    }
    if (rc == 0)
        fill_paddle(c, P, n);
    sph_scene_destroy(sc);
    free(owner);
    free(rho);
    return rc;
}

int sph_fill(const sph_config *c, sph_particles *P, double *mirror, sph_error *err)
{
    if (sph_config_by_scene(c))
        return fill_scene(c, P, mirror, err);
    long i = 0;
    for (int b = 0; b < c->nfluid; b++) {
        double *const at[3] = {P->x + i, P->y + i, P->z ? P->z + i : NULL};
        const long n = sph_shapes_fluid_points(c, &c->fluid[b], at);
        settle(c, P, i, i + n, SPH_FLUID, 0.0, NULL);
        i += n;
    }
    if (has_walls(c)) {
        double *const at[3] = {P->x + i, P->y + i, P->z ? P->z + i : NULL};
        const long n = sph_shapes_tank_points(c, at);
        settle(c, P, i, i + n, SPH_BOUNDARY, (c->layers + 0.5) * c->dx, NULL);
        i += n;
    }
    if (c->boundary != SPH_BOUNDARY_DYNAMIC)
        return 0;
    for (int k = 0; k < c->nobstacles; k++) { /* the obstacles, after the tank's walls */
        double *const at[3] = {P->x + i, P->y + i, P->z ? P->z + i : NULL};
        const long n = sph_shapes_obstacle_points(c, &c->obstacles[k], at);
        settle(c, P, i, i + n, SPH_BOUNDARY, 0.0, NULL);
        i += n;
    }
    i += fill_paddle(c, P, i);
    return 0;
}

long sph_fill_ghosts_estimate(const sph_config *c, double band)
{
    if (c->boundary != SPH_BOUNDARY_GHOST || !c->has_tank)
        return 0;
    const double dx = c->dx;
    long n = 0;
    if (c->dim == 3) { /* per wall: the fluid within the band times the wall's extent */
        for (int b = 0; b < c->nfluid; b++) {
            const sph_box *f = &c->fluid[b];
            const sph_box r = sph_shapes_fluid_bounds(c, f);
            double nn[3], e = 0.0;
            for (int d = 0; d < 3; d++)
                nn[d] = (double)sph_lattice_axis_count(r.min[d], r.max[d], dx);
            for (int d = 0; d < 3; d++) {
                const double k = fmin(nn[d], ceil(band / dx));
                const double face = nn[(d + 1) % 3] * nn[(d + 2) % 3];
                const int lo = f->min[d] < c->tank.min[d] + band;
                const int hi = d < 2 && f->max[d] > c->tank.max[d] - band; /* open top */
                e += (lo + hi) * k * face;
            }
            if (e > 0.0)
                n += e < 1e15 ? (long)e : (long)1e15;
        }
        return n;
    }
    for (int b = 0; b < c->nfluid; b++) {
        const sph_box *f = &c->fluid[b];
        const sph_box r = sph_shapes_fluid_bounds(c, f);
        const double nx = (double)sph_lattice_axis_count(r.min[0], r.max[0], dx);
        const double ny = (double)sph_lattice_axis_count(r.min[1], r.max[1], dx);
        const double kx = fmin(nx, ceil(band / dx)), ky = fmin(ny, ceil(band / dx));
        const int left = f->min[0] < c->tank.min[0] + band;
        const int right = f->max[0] > c->tank.max[0] - band;
        const int bottom = f->min[1] < c->tank.min[1] + band;
        const double e =
            (left + right) * kx * ny + bottom * ky * nx + (left + right) * bottom * kx * ky;
        if (e > 0.0) /* false for NaN: a config no check has seen yet (a saved state) */
            n += e < 1e15 ? (long)e : (long)1e15;
    }
    return n;
}
