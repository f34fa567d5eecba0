/*
 * sph_diag: diagnostics of the current state. Serial sums in the particles' (deterministic)
 * order, so that runs are reproducible.
 *
 * Front position: the fluid is binned along x in bins of width dx; starting from the leftmost
 * occupied bin, the walk continues to the right across gaps of at most (support / dx + 1) empty
 * bins. The front is the right edge (x + dx/2) of the last particle reached: droplets farther
 * ahead than a kernel support from the connected fluid do not count. The height at the left
 * wall is the same walk upwards over the fluid within 2 dx of the wall; the run-up, the same at
 * the right wall. A height gauge walks upwards over the fluid within dx of its line across gaps
 * of at most one empty bin: the top of the continuous water column from the bottom, as a wire
 * gauge reads it (a sheet or a jet falling above the surface, with air between, does not count);
 * 0 when no fluid is there: a dry gauge. A run-up gauge (`to`) walks upwards over the fluid
 * over [x, to] across gaps of a support, as the front walks along x: the highest water there.
 */
#include "sph_sim_impl.h"

#include <math.h>
#include <string.h>

/* Walks bins [0, nb) from the first occupied one; returns the largest coordinate reached, or
 * NAN when no bin is occupied. */
static double walk(const int *count, const double *maxc, long nb, long gap)
{
    long i = 0;
    while (i < nb && count[i] == 0)
        i++;
    if (i == nb)
        return NAN;
    double best = maxc[i];
    long empty = 0;
    for (; i < nb; i++) {
        if (count[i] == 0) {
            if (++empty > gap)
                break;
            continue;
        }
        empty = 0;
        best = maxc[i] > best ? maxc[i] : best;
    }
    return best;
}

/* Histogram of coordinate u of the fluid particles with v in [vlo, vhi) (and, when w is not
 * NULL, w in [wlo, whi)) over [lo, lo + nb dx), walked across gaps of at most `gap` empty bins
 * (< 0: the bins a kernel support spans). */
static double probe2(sph_sim *s, const double *u, const double *v, double lo, double vlo,
                     double vhi, const double *w, double wlo, double whi, long gap)
{
    const sph_particles *P = &s->P;
    const double dx = s->cfg.dx;
    memset(s->bin_count, 0, (size_t)s->nbins * sizeof *s->bin_count);
    for (long b = 0; b < s->nbins; b++)
        s->bin_max[b] = -INFINITY;
    for (long i = 0; i < s->nactive; i++) {
        if (P->type[i] != SPH_FLUID || v[i] < vlo || v[i] >= vhi ||
            (w && (w[i] < wlo || w[i] >= whi)))
            continue;
        /* clamped as a double: a position far away (or NaN) is no long */
        const double fb = floor((u[i] - lo) / dx);
        const long b = !(fb >= 0.0) ? 0 : fb >= (double)s->nbins ? s->nbins - 1 : (long)fb;
        s->bin_count[b]++;
        if (u[i] > s->bin_max[b])
            s->bin_max[b] = u[i];
    }
    if (gap < 0) {
        const double g = ceil(s->kernel.support / dx) + 1.0; /* the bins a support spans */
        gap = g < (double)s->nbins ? (long)g : s->nbins;
    }
    return walk(s->bin_count, s->bin_max, s->nbins, gap) + 0.5 * dx;
}

static double probe(sph_sim *s, const double *u, const double *v, double lo, double vlo, double vhi)
{
    return probe2(s, u, v, lo, vlo, vhi, NULL, 0.0, 0.0, -1);
}

/* The pressure at x: Shepard's interpolation sum_j p_j W_j V_j / sum_j W_j V_j over the fluid
 * particles within a kernel support (V_j = m / rho_j; p_j from the EOS, or the solved pressure
 * of a method that solves one); 0 when none is within reach. */
static double pressure_at(const sph_sim *s, const double *x)
{
    const sph_particles *P = &s->P;
    const double support2 = s->kernel.support * s->kernel.support;
    const int solved = s->ops->solves_pressure;
    double num = 0.0, den = 0.0;
    for (long i = 0; i < s->nactive; i++) {
        if (P->type[i] != SPH_FLUID)
            continue;
        const double dx = P->x[i] - x[0], dy = P->y[i] - x[1], dz = P->z ? P->z[i] - x[2] : 0.0;
        const double r2 = dx * dx + dy * dy + dz * dz;
        if (r2 >= support2)
            continue;
        const double rho = SPH_GET(P->mixed, P, rho, i);
        const double w = sph_kernel_w(&s->kernel, sqrt(r2)) / rho;
        const double p = solved ? SPH_GET(P->mixed, P, p, i) : sph_eos_pressure(&s->cfg, rho);
        num += p * w;
        den += w;
    }
    return den > 0.0 ? num / den : 0.0;
}

void sph_diag_compute(sph_sim *s)
{
    const sph_config *c = &s->cfg;
    const sph_particles *P = &s->P;
    sph_diag *d = &s->diag;
    const double m = s->mass, gx = c->gravity[0], gy = c->gravity[1], gz = c->gravity[2];
    double ekin = 0.0, epot = 0.0, v2max = 0.0, rlo = INFINITY, rhi = -INFINITY;
    for (long i = 0; i < s->nactive; i++) {
        if (P->type[i] != SPH_FLUID)
            continue;
        const int M = P->mixed;
        const double vx = SPH_GET(M, P, vx, i), vy = SPH_GET(M, P, vy, i);
        const double rho = SPH_GET(M, P, rho, i);
        double v2 = vx * vx + vy * vy;
        if (P->z) {
            const double vz = SPH_GET(M, P, vz, i);
            v2 += vz * vz;
            epot -= m * (gx * P->x[i] + gy * P->y[i] + gz * P->z[i]);
        } else {
            epot -= m * (gx * P->x[i] + gy * P->y[i]);
        }
        ekin += 0.5 * m * v2;
        v2max = v2 > v2max ? v2 : v2max;
        rlo = rho < rlo ? rho : rlo;
        rhi = rho > rhi ? rho : rhi;
    }
    d->t = s->t;
    d->step = s->step;
    d->dt = s->dt;
    d->ekin = ekin;
    d->epot = epot;
    d->vmax = sqrt(v2max);
    d->rho_min = rlo;
    d->rho_max = rhi;
    d->lost = s->P.n - s->nactive;
    d->nfluid = s->nfluid;
    d->nboundary = s->nboundary;
    d->nbody = s->bodies.np;
    d->nbodies = s->bodies.n;
    d->penetration = NAN;
    for (int k = 0; k < s->bodies.n; k++) {
        const sph_body_state *b = &s->bodies.b[k].s;
        sph_body_diag *o = &d->body[k];
        for (int j = 0; j < 3; j++) {
            o->x[j] = b->x[j];
            o->v[j] = b->v[j];
            o->force[j] = b->force[j];
        }
        o->angle = b->theta;
        o->omega = b->omega;
        o->torque = b->torque;
        o->penetration = sph_bodies_penetration(&s->bodies, c, k);
        if (k == 0)
            d->penetration = o->penetration;
    }

    /* heights along the vertical, the last axis (y in 2D, z in 3D) */
    const int V = c->dim - 1;
    const double *vert = V == 2 ? P->z : P->y;
    const double wall = c->has_tank ? c->tank.min[0] : c->domain.min[0];
    const double bottom = c->has_tank ? c->tank.min[V] : c->domain.min[V];
    d->front_x = probe(s, P->x, vert, c->domain.min[0], -INFINITY, INFINITY);
    d->height_left = probe(s, vert, P->x, bottom, wall, wall + 2.0 * c->dx) - bottom;
    const double right = c->has_tank ? c->tank.max[0] : c->domain.max[0];
    d->runup = probe(s, vert, P->x, bottom, right - 2.0 * c->dx, right) - bottom;
    d->ngauges = c->ngauges;
    for (int k = 0; k < c->ngauges; k++) {
        const double xg = c->gauges[k].x, yg = c->gauges[k].y;
        /* the fluid within dx of the vertical line (x) in 2D, (x, y) in 3D */
        /* a run-up gauge: the fluid over [x, to] (3D: within dx of y), across gaps of a
         * support (a sheet on a beach is thin) */
        const int range = isfinite(c->gauges[k].to);
        const double top = range ? probe2(s, vert, P->x, bottom, xg, c->gauges[k].to,
                                          V == 2 ? P->y : NULL, yg - c->dx, yg + c->dx, -1)
                                 : probe2(s, vert, P->x, bottom, xg - c->dx, xg + c->dx,
                                          V == 2 ? P->y : NULL, yg - c->dx, yg + c->dx, 1);
        d->gauge[k] = isnan(top) ? 0.0 : top - bottom; /* a dry gauge reads 0 */
    }
    d->npressure = c->npressure;
    for (int k = 0; k < c->npressure; k++) {
        double x[3];
        sph_config_pressure_point(c, &c->pressure[k], x);
        d->pressure[k] = pressure_at(s, x);
    }
    if (s->ops->diag)
        s->ops->diag(s);
}
