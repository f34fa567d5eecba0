/*
 * Ghost (mirror) particles for free-slip tank walls; see sph_wall_ghost.h.
 */
#include "sph_wall_ghost.h"

#include "sph_eos.h"
#include "sph_particles.h"

#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <string.h>

int sph_wall_ghost_init(sph_wall_ghost *w, const sph_config *c, double support, sph_error *err)
{
    memset(w, 0, sizeof *w);
    const int dim = c->dim, up = dim - 1;
    if (!c->has_tank)
        return sph_error_set(err, SPH_ERR_INVALID, "/boundary/tank",
                             "ghost walls need a tank: give boundary.tank {min, max}, the inner "
                             "faces of its walls");
    for (int a = 0; a < dim; a++)
        if (!(c->tank.max[a] > c->tank.min[a]))
            return sph_error_set(err, SPH_ERR_INVALID, "/boundary/tank/max",
                                 "the tank's max must exceed its min along every axis");
    for (int a = 0; a < dim; a++)
        if (a != up && c->gravity[a] != 0.0)
            return sph_error_set(err, SPH_ERR_INVALID, "/physics/gravity",
                                 "ghost walls need gravity along the vertical axis only: their "
                                 "tank is axis-aligned, with its bottom normal to gravity and its "
                                 "top open (a tilted tank is not available)");
    const double tol = 1e-9 * (1.0 + fabs(c->dx));
    for (int b = 0; b < c->nfluid; b++)
        for (int a = 0; a < dim; a++)
            if (c->fluid[b].min[a] < c->tank.min[a] - tol ||
                (a != up && c->fluid[b].max[a] > c->tank.max[a] + tol)) {
                char path[32];
                snprintf(path, sizeof path, "/fluid/%d/box", b);
                return sph_error_set(err, SPH_ERR_INVALID, path,
                                     "fluid box %d reaches outside the ghost-walled tank", b);
            }
    w->dim = dim;
    w->band = support;
    for (int a = 0; a < dim; a++) {
        w->wall[w->nwalls++] = (sph_ghost_plane){a, c->tank.min[a], +1};
        if (a != up)
            w->wall[w->nwalls++] = (sph_ghost_plane){a, c->tank.max[a], -1};
        w->rho0g[a] = c->rho0 * c->gravity[a];
    }
    return 0;
}

void sph_wall_ghost_bounds(const sph_wall_ghost *w, double *lo, double *hi)
{
    for (int k = 0; k < w->nwalls; k++) {
        const sph_ghost_plane *p = &w->wall[k];
        if (p->dir > 0)
            lo[p->axis] = fmin(lo[p->axis], p->pos - w->band);
        else
            hi[p->axis] = fmax(hi[p->axis], p->pos + w->band);
    }
}

/* The walls particle i is near (bit k: wall k), 0 for particles that are not fluid. */
static unsigned near_walls(const sph_wall_ghost *w, const sph_ghost_arrays *a, long i)
{
    if (a->type[i] != SPH_FLUID)
        return 0;
    unsigned m = 0;
    for (int k = 0; k < w->nwalls; k++) {
        const sph_ghost_plane *p = &w->wall[k];
        const double d = (a->pos[p->axis][i] - p->pos) * p->dir;
        if (d >= 0.0 && d < w->band)
            m |= 1u << k;
    }
    return m;
}

/* True when the walls of mask `sub` have distinct normal axes (a mirror, or a corner's double
 * or triple mirror; two parallel walls at once are no image of anything). */
static int distinct_axes(const sph_wall_ghost *w, unsigned sub)
{
    unsigned axes = 0;
    for (int k = 0; k < w->nwalls; k++)
        if (sub & (1u << k)) {
            const unsigned bit = 1u << w->wall[k].axis;
            if (axes & bit)
                return 0;
            axes |= bit;
        }
    return 1;
}

/* The ghosts of particles [lo, hi), written from index g on while below cap; returns g after
 * them. */
static long ghosts_of(const sph_wall_ghost *w, const sph_config *c, const sph_ghost_arrays *a,
                      long lo, long hi, long g, long cap)
{
    const int dim = w->dim;
    double *const *pos = a->pos, *const *vel = a->vel;
    float *const *vel32 = a->vel32;
    double *restrict rho = a->rho;
    float *restrict rho32 = a->rho32;
    const int mixed = a->mixed;
    unsigned char *restrict type = a->type;
    int *restrict id = a->id;
    for (long i = lo; i < hi; i++) {
        const unsigned m = near_walls(w, a, i);
        if (!m)
            continue;
        for (unsigned sub = m; sub; sub = (sub - 1) & m) {
            if (!distinct_axes(w, sub))
                continue;
            if (g < cap) {
                double x[3], v[3];
                for (int d = 0; d < dim; d++) {
                    x[d] = pos[d][i];
                    v[d] = mixed ? (double)vel32[d][i] : vel[d][i];
                }
                for (int k = 0; k < w->nwalls; k++)
                    if (sub & (1u << k)) {
                        const sph_ghost_plane *p = &w->wall[k];
                        x[p->axis] = 2.0 * p->pos - x[p->axis];
                        v[p->axis] = -v[p->axis]; /* free slip: normal reversed */
                    }
                /* Colagrossi & Landrini 2003: hydrostatic pressure across the wall */
                double pg = sph_eos_pressure(c, mixed ? (double)rho32[i] : rho[i]);
                for (int d = 0; d < dim; d++) {
                    pg += w->rho0g[d] * (x[d] - pos[d][i]);
                    pos[d][g] = x[d];
                    if (mixed)
                        vel32[d][g] = (float)v[d];
                    else
                        vel[d][g] = v[d];
                }
                if (mixed)
                    rho32[g] = (float)sph_eos_density(c, pg);
                else
                    rho[g] = sph_eos_density(c, pg);
                type[g] = SPH_GHOST;
                id[g] = id[i];
            }
            g++;
        }
    }
    return g;
}

/* The most threads the build uses. */
#define GHOST_THREADS 64

long sph_wall_ghost_build(const sph_wall_ghost *w, const sph_config *c, const sph_ghost_arrays *a,
                          long n, long cap)
{
    /* Two passes over one chunk of the particles per thread: each counts its chunk's ghosts
     * (written nowhere: cap n), then writes them after those of the chunks before it, so that
     * the ghosts come in the particles' order whatever the number of threads. */
    int nt = n >= 2 * SPH_OMP_MIN ? omp_get_max_threads() : 1;
    nt = nt < GHOST_THREADS ? nt : GHOST_THREADS;
    long count[GHOST_THREADS], end = n;
#pragma omp parallel num_threads(nt)
    {
        const int t = omp_get_thread_num(), m = omp_get_num_threads();
        const long lo = n * t / m, hi = n * (t + 1) / m;
        if (m == 1) { /* one pass: nothing to count first */
            end = ghosts_of(w, c, a, 0, n, n, cap);
        } else {
            count[t] = ghosts_of(w, c, a, lo, hi, 0, 0);
#pragma omp barrier
            long g = n;
            for (int u = 0; u < t; u++)
                g += count[u];
            g = ghosts_of(w, c, a, lo, hi, g, cap);
            if (t == m - 1) /* the last chunk's ghosts end them all */
                end = g;
        }
    }
    return end - n;
}
