/*
 * sph_wcsph: the WCSPH force evaluation, in 2D and 3D: the cells or a reused neighbour list, the
 * walls' density (mDBC), the pair loop (its instantiations in sph_wcsph_strips_<type>.c, the
 * loop in sph_wcsph_strips.h; the physics of a pair is sph_wcsph_pair(), sph_wcsph_pair.h),
 * particle shifting, gravity; and its gather form, the C reference of the GPU's.
 */
#include "sph_wcsph.h"
#include "sph_mdbc.h"
#include "sph_shapes.h"
#include "sph_wcsph_loop.h"
#include "sph_wcsph_pair.h"
#include "sph_wcsph_particle.h"

#include <math.h>
#include <omp.h>
#include <stdlib.h>
#include <string.h>

#define SPH_SPS_CS 0.12   /* Smagorinsky constant, Yang et al. after Lo & Shao */
#define SPH_SPS_CI 0.0066 /* isotropic part, Dalrymple & Rogers 2006 */

/* The gather loop's instantiations (sph_wcsph_forces_gather): one per kernel type and dimension,
 * the options read at run time (it is the reference of the GPU's loop, not a fast path). */
typedef long (*gather_fn)(const fctx *c, long i);
#define SPH_GATHER_FN(T)                                                                           \
    static long gather2_##T(const fctx *c, long i)                                                 \
    {                                                                                              \
        return gather_one(T, c->flags, 2, c, i);                                                   \
    }                                                                                              \
    static long gather3_##T(const fctx *c, long i)                                                 \
    {                                                                                              \
        return gather_one(T, c->flags, 3, c, i);                                                   \
    }
SPH_GATHER_FN(SPH_KERNEL_CUBIC_SPLINE)
SPH_GATHER_FN(SPH_KERNEL_GAUSSIAN)
SPH_GATHER_FN(SPH_KERNEL_DOUBLE_COSINE)
SPH_GATHER_FN(SPH_KERNEL_WENDLAND_C2)
SPH_GATHER_FN(SPH_KERNEL_RENORMALIZED_GAUSSIAN)
static const gather_fn gather2_SPH_KERNEL_KOSHIZUKA = NULL, gather3_SPH_KERNEL_KOSHIZUKA = NULL;
static const gather_fn gather2_SPH_KERNEL_SHEU_QUARTIC = NULL,
                       gather3_SPH_KERNEL_SHEU_QUARTIC = NULL;

/* the MPS weight functions are refused for WCSPH (wcsph_check): no instantiations */
static inline sph_strip_fn sph_wcsph_strip_SPH_KERNEL_KOSHIZUKA(int D, unsigned flags)
{
    (void)D;
    (void)flags;
    return NULL;
}
static inline sph_strip_fn sph_wcsph_strip_SPH_KERNEL_SHEU_QUARTIC(int D, unsigned flags)
{
    (void)D;
    (void)flags;
    return NULL;
}

void sph_wcsph_consts_of(const sph_sim *s, sph_wcsph_consts *k)
{
    const sph_config *cfg = &s->cfg;
    const double alpha =
        cfg->visc == SPH_VISC_MONAGHAN ? sph_config_monaghan_alpha(cfg) : cfg->alpha;
    k->flags = (cfg->visc == SPH_VISC_LAMINAR ? F_LAMINAR : 0) |
               (cfg->visc == SPH_VISC_MONAGHAN ? F_MONAGHAN : 0) |
               (cfg->turb == SPH_TURB_SPS ? F_SPS : 0) | (cfg->delta_sph > 0.0 ? F_DELTA : 0) |
               (cfg->boundary == SPH_BOUNDARY_GHOST ? F_GHOST : 0) |
               (s->bodies.n > 0 ? F_BODY : 0) | (s->P.mixed ? F_MIXED : 0);
    k->pc.m = s->mass;
    k->pc.h = s->h;
    k->pc.eta2 = 0.01 * s->h * s->h;
    k->pc.alpha_c0 = alpha * cfg->c0;
    k->pc.mu8 = 8.0 * cfg->rho0 * cfg->nu;
    k->pc.dcoef = 2.0 * cfg->delta_sph * s->h * cfg->c0 * s->mass;
    for (int d = 0; d < 3; d++)
        k->pc.dgh[d] = cfg->delta_form == SPH_DELTA_FOURTAKAS
                           ? cfg->rho0 * cfg->gravity[d] / (cfg->c0 * cfg->c0)
                           : 0.0;
    k->support2 = s->kernel.support * s->kernel.support;
    k->tiny = 1e-12 * s->h;
    k->wall_visc = cfg->wall_viscosity;
    k->smag = (SPH_SPS_CS * cfg->dx) * (SPH_SPS_CS * cfg->dx);
    k->blin = 2.0 / 3.0 * SPH_SPS_CI * cfg->dx * cfg->dx;
}

/* The per-particle loops of a force evaluation, one function per dimension and storage (D and
 * M literals there: an OpenMP loop in a function that takes them outlines its body before they
 * are known): prepare (prepare_one) and gravity (gravity_one: the largest |a|^2 of the fluid). */
/* clang-format off */
#define SPH_PARTICLE_LOOPS(D, M)                                                                   \
    static void prepare##D##M(const sph_config *cfg, sph_particles *P, long n, double smag,       \
                              double blin)                                                         \
    {                                                                                              \
        _Pragma("omp parallel for schedule(dynamic, SPH_OMP_CHUNK) if (n >= SPH_OMP_MIN)")         \
        for (long i = 0; i < n; i++)                                                               \
            prepare_one(D, M, cfg, P, smag, blin, i);                                              \
    }                                                                                              \
    static double gravity##D##M(const double *g, sph_particles *P, long n)                        \
    {                                                                                              \
        double amax2 = 0.0;                                                                        \
        _Pragma("omp parallel for schedule(dynamic, SPH_OMP_CHUNK) reduction(max : amax2) if (n >= SPH_OMP_MIN)") \
        for (long i = 0; i < n; i++) {                                                             \
            const double a2 = gravity_one(D, M, g, P, i);                                          \
            amax2 = a2 > amax2 ? a2 : amax2;                                                       \
        }                                                                                          \
        return amax2;                                                                              \
    }
/* clang-format on */
SPH_PARTICLE_LOOPS(2, 0)
SPH_PARTICLE_LOOPS(3, 0)
SPH_PARTICLE_LOOPS(2, 1)
SPH_PARTICLE_LOOPS(3, 1)

static void prepare(sph_sim *s, const sph_wcsph_consts *kc)
{
    const sph_config *cfg = &s->cfg;
    sph_particles *P = &s->P;
    const long n = s->nactive;
    if (P->mixed)
        (cfg->dim == 3 ? prepare31 : prepare21)(cfg, P, n, kc->smag, kc->blin);
    else
        (cfg->dim == 3 ? prepare30 : prepare20)(cfg, P, n, kc->smag, kc->blin);
}

/* Gravity on the fluid particles among the first n (the others' accelerations zeroed, those of
 * the particles beyond n with their density rates); returns the largest |a|^2 of the fluid. */
static double gravity(const sph_config *cfg, sph_particles *P, long n)
{
    const double g[3] = {cfg->gravity[0], cfg->gravity[1], cfg->gravity[2]};
    const double amax2 = P->mixed ? (cfg->dim == 3 ? gravity31 : gravity21)(g, P, n)
                                  : (cfg->dim == 3 ? gravity30 : gravity20)(g, P, n);
    const int M = P->mixed;
    for (long i = n; i < P->n; i++) {
        SPH_SET(M, P, ax, i, 0.0);
        SPH_SET(M, P, ay, i, 0.0);
        SPH_SET(M, P, drho, i, 0.0);
        if (P->dim == 3)
            SPH_SET(M, P, az, i, 0.0);
    }
    return amax2;
}

/* The reach of a walls' scan (mdbc_one's and fluid_within's: the support; nopen_one's: 1.25 dx),
 * squared, and the margin across of the 3D cut to it (sph_cells_cut_margins: only points beyond
 * the reach go). The same for every particle of a pass: found once, by the pass. */
typedef struct wall_cut {
    double reach2, lat;
} wall_cut;

static wall_cut wall_cut_of(const sph_cells *g, double reach)
{
    wall_cut k;
    sph_cells_cut_margins(g, reach, &reach, &k.lat);
    k.reach2 = reach * reach;
    return k;
}

/* The walls' scans around a point p in cell c (columns_near): the particle range of the column of
 * 3 cells at offset (a, b) across, [*jb, *je); 0 when the column holds none of what map marks, or
 * (3D) lies out of the reach across, else 1 with the range cut in z to the reach
 * (sph_cells_cut_column). */
static inline __attribute__((always_inline)) int
column_near(const int D, const sph_cells *g, const double *z, const unsigned char *map,
            const double *p, const int *c, int a, int b, const wall_cut *cut, long *jb, long *je)
{
    const long cell = sph_cells_index(g, c[0] + a, c[1] + b, c[2]);
    if (!(map[cell - 1] | map[cell] | map[cell + 1]))
        return 0;
    *jb = g->start[cell - 1];
    *je = g->start[cell + 2];
    return D == 2 || sph_cells_cut_column(g->x0, g->y0, 1.0 / g->inv_size, z, p, c[0] + a, c[1] + b,
                                          cut->reach2, cut->lat, jb, je);
}

/* The columns of 3 cells around point p in cell c that hold what map marks (column_near, in its
 * order: a, then b), as particle ranges [jb[k], je[k]); returns their count (at most 9). */
static inline __attribute__((always_inline)) int
columns_near(const int D, const sph_cells *g, const double *z, const unsigned char *map,
             const double *p, const int *c, const wall_cut *cut, long *jb, long *je)
{
    int n = 0;
    for (int a = -1; a <= 1; a++)
        for (int b = (D == 3 ? -1 : 0); b <= (D == 3 ? 1 : 0); b++)
            n += column_near(D, g, z, map, p, c, a, b, cut, &jb[n], &je[n]);
    return n;
}

/* Whether a fluid particle lies within support2 of point p in cell c (wet: the cells that hold
 * fluid; cut: the columns' cut to the support). */
static inline __attribute__((always_inline)) int
fluid_within(const int D, const sph_cells *g, const sph_particles *P, const unsigned char *wet,
             const double *p, const int *c, double support2, const wall_cut *cut)
{
    long jb[9], je[9];
    const int nc = columns_near(D, g, P->z, wet, p, c, cut, jb, je);
    for (int k = 0; k < nc; k++)
        for (long j = jb[k]; j < je[k]; j++) {
            if (P->type[j] != SPH_FLUID)
                continue;
            const double r[3] = {p[0] - P->x[j], p[1] - P->y[j], D == 3 ? p[2] - P->z[j] : 0.0};
            if (r[0] * r[0] + r[1] * r[1] + (D == 3 ? r[2] * r[2] : 0.0) < support2)
                return 1;
        }
    return 0;
}

/* The mirror point (mDBC's ghost node) of wall particle i at x into g: the sim's table where it
 * has one (the geometry's walls, by id: sph_fill.h), else the built-in boxes' rule. */
static inline __attribute__((always_inline)) void wall_mirror(const int D, const sph_sim *s,
                                                              const sph_particles *P, long i,
                                                              const double *x, double *g)
{
    const long k = (long)P->id[i] - s->mirror_first;
    if (s->mirror && k >= 0 && k < s->nmirror) {
        const double *m = s->mirror + (size_t)D * (size_t)k;
        g[0] = m[0];
        g[1] = m[1];
        g[2] = D == 3 ? m[2] : 0.0;
        return;
    }
    sph_shapes_wall_mirror(&s->cfg, x, g);
}

/* mDBC (sph_mdbc.h): wall particle i's density from the fluid around its mirror point. The
 * fluid is searched in the 3 x 3 (x 3) cells around the mirror point, a column of 3 cells at a
 * time; one that falls outside the grid's inner cells (no wall of this geometry sends it there)
 * leaves rho0. A wall particle with no fluid within its own support takes part in no pair
 * (wall-wall pairs are skipped; without bodies, nothing else pairs with it), so its density is
 * not sought: rho0 (the third layer under still water, each layer of a dry wall). The fluid
 * evolves the same, bit for bit.
 * TODO(issue 23): at 30 over the depth on Test 2 the water that first runs up the box's face is
 * in tension at P3 for 25 ms, which puts its first impact 26 ms late (README, mDBC); DualSPHysics'
 * mDBC2 switches off a wall particle whose ghost node is dry, where this clamps to rho0. */
static inline __attribute__((always_inline)) void mdbc_one(const int D, const sph_sim *s,
                                                           sph_particles *P,
                                                           const unsigned char *wet,
                                                           const wall_cut *cut, long i)
{
    if (P->type[i] != SPH_BOUNDARY)
        return;
    const sph_cells *g = &s->cells;
    const double x[3] = {P->x[i], P->y[i], D == 3 ? P->z[i] : 0.0};
    const double support2 = s->kernel.support * s->kernel.support, m = s->mass;
    int c[3];
    if (s->bodies.n == 0 && sph_cells_locate(D, g, x, c) &&
        !fluid_within(D, g, P, wet, x, c, support2, cut)) {
        SPH_SET(P->mixed, P, rho, i, s->cfg.rho0);
        return;
    }
    double gx[3];
    wall_mirror(D, s, P, i, x, gx);
    double rho = s->cfg.rho0;
    if (sph_cells_locate(D, g, gx, c)) {
        sph_mdbc_sum sum;
        memset(&sum, 0, sizeof sum);
        long jb[9], je[9]; /* (most of a tank's walls are dry: their columns hold no fluid) */
        const int nc = columns_near(D, g, P->z, wet, gx, c, cut, jb, je);
        for (int k = 0; k < nc; k++)
            for (long j = jb[k]; j < je[k]; j++) {
                if (P->type[j] != SPH_FLUID)
                    continue;
                const double r[3] = {gx[0] - P->x[j], gx[1] - P->y[j],
                                     D == 3 ? gx[2] - P->z[j] : 0.0};
                const double r2 = r[0] * r[0] + r[1] * r[1] + (D == 3 ? r[2] * r[2] : 0.0);
                if (r2 >= support2)
                    continue;
                const double q = sqrt(r2);
                double dwdr;
                const double w = sph_kernel_eval_t(s->kernel.type, &s->kernel, q, &dwdr);
                sph_mdbc_add(D, &sum, r, w, q > 0.0 ? dwdr / q : 0.0, m,
                             SPH_GET(P->mixed, P, rho, j));
            }
        const double dpos[3] = {x[0] - gx[0], x[1] - gx[1], x[2] - gx[2]};
        rho = sph_mdbc_density(D, &sum, dpos, s->cfg.rho0);
    }
    /* never below rho0, as the continuity walls: a wall does not pull water in (and an
     * extrapolation from a few particles of a splash cannot send it into tension) */
    SPH_SET(P->mixed, P, rho, i, rho > s->cfg.rho0 ? rho : s->cfg.rho0);
}

/* A per-particle pass of the walls' NAME##_one over the first n particles, NAME<D> (D a literal
 * there), with a map of the cells (mdbc: wet[c], 1 when cell c holds fluid; nopen: walls[c], 1
 * when it holds wall particles). Each particle reads the others' positions and writes itself
 * alone: any number of threads gives the same bits. mdbc: every wall particle's density, before
 * the pair loop reads it. */
/* clang-format off */
#define SPH_WALL_LOOP(NAME, D)                                                                     \
    static void NAME##D(const sph_sim *s, sph_particles *P, const unsigned char *map,             \
                        wall_cut cut, long n)                                                      \
    {                                                                                              \
        _Pragma("omp parallel for schedule(dynamic, SPH_OMP_CHUNK) if (n >= SPH_OMP_MIN)")         \
        for (long i = 0; i < n; i++)                                                               \
            NAME##_one(D, s, P, map, &cut, i);                                                     \
    }
/* clang-format on */
SPH_WALL_LOOP(mdbc, 2)
SPH_WALL_LOOP(mdbc, 3)

/* mDBC's no-penetration control (DualSPHysics 5.4's, for its mDBC slip modes): fluid particle
 * i, closer than 1.25 dx to a wall particle of the first layer (its mirror point within 1.75 dx)
 * and within 0.75 of that distance of it along the wall's normal n, loses the part of its
 * velocity that approaches the wall, reversed in part the closer it is: v -= f (v.n) n, f = 2.5 -
 * 2 max(d_n / |g - x_b|, 1/4) (1 at three quarters of the way, 2 at a quarter), averaged over the
 * wall particles that act. The walls are fixed. walls[c]: 1 when cell c holds wall particles. */
static inline __attribute__((always_inline)) void nopen_one(const int D, const sph_sim *s,
                                                            sph_particles *P,
                                                            const unsigned char *walls,
                                                            const wall_cut *cut, long i)
{
    if (P->type[i] != SPH_FLUID)
        return;
    const sph_cells *g = &s->cells;
    const double x[3] = {P->x[i], P->y[i], D == 3 ? P->z[i] : 0.0};
    int c[3];
    if (!sph_cells_locate(D, g, x, c))
        return;
    const int M = P->mixed;
    const double dx = s->cfg.dx, near2 = 1.5625 * dx * dx, first2 = 3.0625 * dx * dx;
    double v[3] = {SPH_GET(M, P, vx, i), SPH_GET(M, P, vy, i), D == 3 ? SPH_GET(M, P, vz, i) : 0.0};
    double shift[3] = {0.0, 0.0, 0.0};
    int count = 0;
    long jb[9], je[9];
    const int nc = columns_near(D, g, P->z, walls, x, c, cut, jb, je);
    for (int k = 0; k < nc; k++)
        for (long j = jb[k]; j < je[k]; j++) {
            if (P->type[j] != SPH_BOUNDARY)
                continue;
            const double xb[3] = {P->x[j], P->y[j], D == 3 ? P->z[j] : 0.0};
            const double dr[3] = {x[0] - xb[0], x[1] - xb[1], x[2] - xb[2]};
            if (dr[0] * dr[0] + dr[1] * dr[1] + dr[2] * dr[2] >= near2)
                continue;
            double gb[3];
            wall_mirror(D, s, P, j, xb, gb);
            const double bn[3] = {gb[0] - xb[0], gb[1] - xb[1], D == 3 ? gb[2] - xb[2] : 0.0};
            const double norm2 = bn[0] * bn[0] + bn[1] * bn[1] + bn[2] * bn[2];
            if (!(norm2 > 0.0 && norm2 < first2))
                continue; /* not of the first layer */
            const double norm = sqrt(norm2);
            const double n[3] = {bn[0] / norm, bn[1] / norm, bn[2] / norm};
            const double dn = n[0] * dr[0] + n[1] * dr[1] + n[2] * dr[2];
            const double vn = n[0] * v[0] + n[1] * v[1] + n[2] * v[2];
            if (!(dn < 0.75 * norm && vn < 0.0))
                continue;
            const double ratio = dn / norm > 0.25 ? dn / norm : 0.25;
            const double f = 2.5 - 2.0 * ratio;
            for (int d = 0; d < 3; d++)
                shift[d] -= f * vn * n[d];
            count++;
        }
    if (!count)
        return;
    SPH_SET(M, P, vx, i, v[0] + shift[0] / count);
    SPH_SET(M, P, vy, i, v[1] + shift[1] / count);
    if (D == 3)
        SPH_SET(M, P, vz, i, v[2] + shift[2] / count);
}

SPH_WALL_LOOP(nopen, 2)
SPH_WALL_LOOP(nopen, 3)

int sph_wcsph_no_penetration(sph_sim *s)
{
    const unsigned char *walls = sph_cells_walls(&s->cells, &s->P);
    if (!walls)
        return -1;
    const wall_cut k = wall_cut_of(&s->cells, 1.25 * s->cfg.dx); /* nopen_one's reach */
    if (s->cfg.dim == 3)
        nopen3(s, &s->P, walls, k, s->nactive);
    else
        nopen2(s, &s->P, walls, k, s->nactive);
    return 0;
}

/* Appends the ghosts of the free-slip walls after the real particles (room made as needed).
 * Returns 0 or -1 when out of memory. */
static int add_ghosts(sph_sim *s)
{
    sph_particles *P = &s->P;
    const long n = P->n;
    for (;;) {
        const sph_ghost_arrays a = {.pos = {P->x, P->y, P->z},
                                    .vel = {P->vx, P->vy, P->vz},
                                    .rho = P->rho,
                                    .vel32 = {P->f32.vx, P->f32.vy, P->f32.vz},
                                    .rho32 = P->f32.rho,
                                    .mixed = P->mixed,
                                    .type = P->type,
                                    .id = P->id};
        const long need = sph_wall_ghost_build(&s->ghost, &s->cfg, &a, n, P->cap);
        if (n + need <= P->cap) {
            s->nghost = need;
            P->n = n + need;
            return 0;
        }
        const long cap = n + need + need / 4 + 16;
        if (sph_particles_reserve(P, cap) || sph_cells_reserve(&s->cells, cap))
            return -1;
    }
}

/* A thread's candidates while the neighbour list is built. */
typedef struct sph_nlist_buf nl_buf;

/* Appends j; 0, or -1 when out of memory. */
static inline int nl_push(nl_buf *B, long j)
{
    if (B->len == B->cap) {
        const long cap = B->cap ? 2 * B->cap : 1 << 16;
        int *p = realloc(B->b, (size_t)cap * sizeof *p);
        if (!p)
            return -1;
        B->b = p;
        B->cap = cap;
    }
    B->b[B->len++] = (int)j;
    return 0;
}

/* Particle i's candidates in [jb, je): within reach (r^2 < reach2), wall pairs left out (walls
 * do not move: they never interact, pair_of refuses them). Returns 0 or -1. */
static inline __attribute__((always_inline)) int
nl_range(const int D, const sph_particles *P, long i, long jb, long je, double reach2, nl_buf *B)
{
    const double xi = P->x[i], yi = P->y[i], zi = D == 3 ? P->z[i] : 0.0;
    const int wi = P->type[i] == SPH_BOUNDARY;
    for (long j = jb; j < je; j++) {
        const double dx = xi - P->x[j], dy = yi - P->y[j], dz = D == 3 ? zi - P->z[j] : 0.0;
        const double r2 = D == 3 ? dx * dx + dy * dy + dz * dz : dx * dx + dy * dy;
        if (r2 < reach2 && !(wi && P->type[j] == SPH_BOUNDARY) && nl_push(B, j))
            return -1;
    }
    return 0;
}

/* The candidates of the particles of x column (2D) or slab (3D) cx, in the strip loops' order:
 * each particle's cell after it and the cell above (one range), then the half stencil
 * (half_stencil): ascending indices. In 3D each range, a column of cells sorted by z, is first
 * cut to the part that can be within reach (sph_cells_cut_column, with the margins of
 * sph_cells_cut_margins: only candidates beyond the reach go, so the list is the same). Each
 * particle's count into off[i + 1]. Returns 0 or -1. */
static inline __attribute__((always_inline)) int nl_column(const int D, const sph_cells *g,
                                                           const sph_particles *P, int cx,
                                                           double reach, long *off, nl_buf *B)
{
    const int ny = g->ny, nz = D == 3 ? g->nz : 1;
    const int *start = g->start;
    const double size = 1.0 / g->inv_size, reach2 = reach * reach;
    double cut = reach, lat = 0.0;
    if (D == 3)
        sph_cells_cut_margins(g, reach, &cut, &lat);
    /* the columns of half_stencil's ranges, as offsets (x, y) from i's */
    static const int ox[4] = {0, 1, 1, 1}, oy[4] = {1, -1, 0, 1};
    for (int cy = 1; cy < ny - 1; cy++)
        for (int cz = D == 3 ? 1 : 0; cz < (D == 3 ? nz - 1 : 1); cz++) {
            const long cell = ((long)cx * ny + cy) * nz + cz;
            const long ib = start[cell], ie = start[cell + 1];
            if (ib == ie)
                continue;
            long rb[4], re[4];
            const int nr = half_stencil(D, start, cell, ny, nz, rb, re);
            for (long i = ib; i < ie; i++) {
                const long before = B->len;
                long b = i + 1, e = start[cell + 2];
                const double p[3] = {P->x[i], P->y[i], D == 3 ? P->z[i] : 0.0};
                if (D == 3)
                    sph_cells_cut_z(P->z, p[2], cut, &b, &e);
                if (nl_range(D, P, i, b, e, reach2, B))
                    return -1;
                for (int k = 0; k < nr; k++) {
                    b = rb[k];
                    e = re[k];
                    if (D == 3 && !sph_cells_cut_column(g->x0, g->y0, size, P->z, p, cx + ox[k],
                                                        cy + oy[k], cut * cut, lat, &b, &e))
                        continue;
                    if (nl_range(D, P, i, b, e, reach2, B))
                        return -1;
                }
                off[i + 1] = B->len - before;
            }
        }
    return 0;
}

/* Builds the reused neighbour list of the particles [0, nactive) from their cells
 * (s->cells.start, which a sort or a restored state made) and their current positions (the
 * displacement bound, s->nlist.moved, is the caller's):
 * everything within (1 + skin) times the support, the margin a step's motion may use up before
 * the next build. The columns go to the threads; each thread's candidates are then copied into
 * place. Returns 0 or -1 when out of memory. */
static int nlist_build(sph_sim *s)
{
    sph_nlist *L = &s->nlist;
    const sph_cells *g = &s->cells;
    const sph_particles *P = &s->P;
    const int D = s->cfg.dim;
    const long n = s->nactive, slab = (long)g->ny * (D == 3 ? g->nz : 1);
    const double reach = s->kernel.support * (1.0 + s->cfg.neighbour_skin);
    L->built = 0;
    if (n + 1 > L->off_cap) {
        long *o = realloc(L->off, (size_t)(n + 1) * sizeof *o);
        if (!o)
            return -1;
        L->off = o;
        L->off_cap = n + 1;
    }
    const int nth = omp_get_max_threads(), nx = g->nx;
    if (nth > L->ntb) { /* the threads' lists: kept from one build to the next */
        nl_buf *t = realloc(L->tb, (size_t)nth * sizeof *t);
        if (!t)
            return -1;
        memset(t + L->ntb, 0, (size_t)(nth - L->ntb) * sizeof *t);
        L->tb = t;
        L->ntb = nth;
    }
    nl_buf *const tb = L->tb;
    for (int t = 0; t < nth; t++)
        tb[t].len = 0;
    int *col_th = calloc((size_t)nx, sizeof *col_th);
    long *col_at = calloc((size_t)nx, sizeof *col_at),
         *col_len = calloc((size_t)nx + 1, sizeof *col_len);
    int fail = !col_th || !col_at || !col_len;
    if (!fail) {
        long *const off = L->off;
        off[0] = 0;
#pragma omp parallel num_threads(nth) if (n >= SPH_OMP_MIN)
        {
            nl_buf *B = &tb[omp_get_thread_num()];
#pragma omp for schedule(dynamic, 1) reduction(| : fail)
            for (int cx = 1; cx < nx - 1; cx++) {
                col_th[cx] = omp_get_thread_num();
                col_at[cx] = B->len;
                if (!fail)
                    fail |= D == 3 ? nl_column(3, g, P, cx, reach, off, B)
                                   : nl_column(2, g, P, cx, reach, off, B);
                col_len[cx] = B->len - col_at[cx];
            }
        }
    }
    if (!fail) {
        /* the columns' offsets (few), then each column's particles' in parallel: a column writes
         * off[i + 1] for its own particles i alone */
        long *const off = L->off;
        long total = 0;
        for (int cx = 1; cx < nx - 1; cx++) {
            const long len = col_len[cx];
            col_len[cx] = total;
            total += len;
        }
#pragma omp parallel for schedule(static) if (n >= SPH_OMP_MIN)
        for (int cx = 1; cx < nx - 1; cx++) {
            long at = col_len[cx];
            for (long i = g->start[cx * slab]; i < g->start[(cx + 1) * slab]; i++) {
                at += off[i + 1];
                off[i + 1] = at;
            }
        }
        /* the list is the threads' lists, each column's where its thread built it */
        if (nx > L->ncol) {
            const int **cb = realloc(L->cb, (size_t)nx * sizeof *cb);
            long *ca = cb ? realloc(L->ca, (size_t)nx * sizeof *ca) : NULL;
            if (cb)
                L->cb = cb;
            if (ca) {
                L->ca = ca;
                L->ncol = nx;
            }
            fail = !cb || !ca;
        }
    }
    if (!fail) {
        for (int cx = 0; cx < nx; cx++) {
            const int inner = cx >= 1 && cx < nx - 1 && tb[col_th[cx]].b;
            L->cb[cx] = inner ? tb[col_th[cx]].b + col_at[cx] : NULL;
            L->ca[cx] = inner ? col_len[cx] : 0;
        }
        L->built = 1;
    }
    free(col_th);
    free(col_at);
    free(col_len);
    return fail ? -1 : 0;
}

int sph_wcsph_resume(sph_sim *s, sph_error *err)
{
    if (s->cfg.neighbour_skin > 0.0 && nlist_build(s))
        return sph_error_set(err, SPH_ERR_NOMEM, "", "out of memory for the neighbour list");
    return 0;
}

double sph_wcsph_nlist_moved(const sph_sim *s, double dt, long n)
{
    const sph_particles *P = &s->P;
    const int D = s->cfg.dim, M = P->mixed;
    double m2 = 0.0;
#pragma omp parallel for schedule(static) reduction(max : m2) if (n >= SPH_OMP_MIN)
    for (long i = 0; i < n; i++) {
        if (P->type[i] != SPH_FLUID)
            continue;
        /* the predictor's displacement, dt (v + dt a0 / 2) */
        const double dx = dt * (SPH_GET(M, P, vx, i) + 0.5 * dt * SPH_GET(M, P, ax0, i));
        const double dy = dt * (SPH_GET(M, P, vy, i) + 0.5 * dt * SPH_GET(M, P, ay0, i));
        const double dz =
            D == 3 ? dt * (SPH_GET(M, P, vz, i) + 0.5 * dt * SPH_GET(M, P, az0, i)) : 0.0;
        const double d2 = dx * dx + dy * dy + dz * dz;
        m2 = d2 > m2 ? d2 : m2;
    }
    return sqrt(m2);
}

/* The pressure of the current density, which the particles do not store (the force loop reads
 * p / rho^2), into their scratch array: for a view (outputs, queries) and for the bodies'
 * pressure within a force evaluation, after the sort. Doubles, or floats under mixed precision
 * (the value the float storage of before held: the same bits in the outputs). */
void sph_wcsph_pressure(const sph_sim *s, const double **p, const float **p32)
{
    const sph_particles *P = &s->P;
    const long n = P->n;
    const int M = P->mixed;
    double *const q = P->scratch;
    float *const q32 = (float *)P->scratch;
#pragma omp parallel for schedule(static) if (n >= SPH_OMP_MIN)
    for (long i = 0; i < n; i++) {
        const double v = sph_eos_pressure(&s->cfg, SPH_GET(M, P, rho, i));
        if (M)
            q32[i] = (float)v;
        else
            q[i] = v;
    }
    *p = M ? NULL : q;
    *p32 = M ? q32 : NULL;
}

/* Particle shifting's pass (sph_shifting.h), shift<D>_<TYPE>: the sums of fluid particle i. */
typedef void (*shift_fn)(const fctx *c, long i, sph_shift_sum *sum);
#define SPH_SHIFT_FN(T)                                                                            \
    static void shift2_##T(const fctx *c, long i, sph_shift_sum *sum)                              \
    {                                                                                              \
        shift_one(T, c->flags, 2, c, i, sum);                                                      \
    }                                                                                              \
    static void shift3_##T(const fctx *c, long i, sph_shift_sum *sum)                              \
    {                                                                                              \
        shift_one(T, c->flags, 3, c, i, sum);                                                      \
    }
SPH_SHIFT_FN(SPH_KERNEL_CUBIC_SPLINE)
SPH_SHIFT_FN(SPH_KERNEL_GAUSSIAN)
SPH_SHIFT_FN(SPH_KERNEL_DOUBLE_COSINE)
SPH_SHIFT_FN(SPH_KERNEL_WENDLAND_C2)
SPH_SHIFT_FN(SPH_KERNEL_RENORMALIZED_GAUSSIAN)
static const shift_fn shift2_SPH_KERNEL_KOSHIZUKA = NULL, shift3_SPH_KERNEL_KOSHIZUKA = NULL;
static const shift_fn shift2_SPH_KERNEL_SHEU_QUARTIC = NULL, shift3_SPH_KERNEL_SHEU_QUARTIC = NULL;

/* Particle shifting over the first n particles of the force evaluation c (sorted, ghosts among
 * them): every fluid particle's displacement from the positions and densities of the evaluation
 * and its predicted speed (DualSPHysics takes the speed of its corrector's evaluation too), all of
 * them computed before any moves, then added to the positions. dt: the step's. The corrector
 * reads no position, so the step's result is as if the corrector moved them. Returns 0 or -1
 * when out of memory. */
static int shift_pass(sph_sim *s, const fctx *c, long n, double dt)
{
    const sph_config *cfg = &s->cfg;
    sph_particles *P = &s->P;
    const int D = cfg->dim, M = P->mixed;
    if (n > s->shift_cap) {
        double *b = realloc(s->shift, (size_t)n * (size_t)D * sizeof(double));
        if (!b)
            return -1;
        s->shift = b;
        s->shift_cap = n;
    }
    shift_fn fn = NULL;
#define SPH_PICK(T) fn = D == 3 ? shift3_##T : shift2_##T
    SPH_KERNEL_DISPATCH(s->kernel.type, SPH_PICK);
#undef SPH_PICK
    if (!fn)
        return 0; /* an MPS weight: sph_sim_check refuses it first */
    const sph_shift_const k = {.ahdt = cfg->shifting.coefficient * s->h * dt,
                               .tfs = cfg->shifting.free_surface > 0.0 ? cfg->shifting.free_surface
                                                                       : (D == 3 ? 2.75 : 1.5),
                               .maxd = 0.1 * cfg->dx};
    double *const dr = s->shift;
#pragma omp parallel for schedule(dynamic, SPH_OMP_CHUNK) if (n >= SPH_OMP_MIN)
    for (long i = 0; i < n; i++) {
        if (P->type[i] != SPH_FLUID)
            continue;
        sph_shift_sum sum;
        fn(c, i, &sum);
        const double vx = SPH_GET(M, P, vx, i), vy = SPH_GET(M, P, vy, i),
                     vz = D == 3 ? SPH_GET(M, P, vz, i) : 0.0;
        sph_shifting_displacement(D, &k, &sum, sqrt(vx * vx + vy * vy + vz * vz),
                                  dr + (size_t)i * (size_t)D);
    }
#pragma omp parallel for schedule(static) if (n >= SPH_OMP_MIN)
    for (long i = 0; i < n; i++) {
        if (P->type[i] != SPH_FLUID)
            continue;
        P->x[i] += dr[(size_t)i * (size_t)D];
        P->y[i] += dr[(size_t)i * (size_t)D + 1];
        if (D == 3)
            P->z[i] += dr[(size_t)i * (size_t)D + 2];
    }
    return 0;
}

static int forces(sph_sim *s, int gather, double shift_dt)
{
    const sph_config *cfg = &s->cfg;
    sph_particles *P = &s->P;
    const int ghosts = cfg->boundary == SPH_BOUNDARY_GHOST;
    /* a reused neighbour list (not for the gather loop, which searches the cells): built anew
     * when some particle may have moved half its skin since the last build, so that every pair
     * within the support now was within the support and the skin then; the margin leaves the
     * rounding of the distances out of it */
    const int listed = cfg->neighbour_skin > 0.0 && !gather;
    const double skin = cfg->neighbour_skin * s->kernel.support;
    double t0 = omp_get_wtime();
    if (ghosts && add_ghosts(s))
        return -1;
    if (!listed || !s->nlist.built || 2.0 * s->nlist.moved > skin * (1.0 - 1e-6)) {
        s->nactive = sph_cells_sort(&s->cells, P);
        s->nlist.built = 0; /* (the gather loop's sort moved the particles) */
        if (listed && nlist_build(s))
            return -1;
        s->nlist.moved = 0.0;
        s->timing.lists += listed;
    }
    double t1 = omp_get_wtime();
    s->timing.neighbours += t1 - t0;

    if (cfg->wall_density == SPH_WALL_MDBC) { /* (dynamic walls only: sph_sim_check) */
        const unsigned char *wet = sph_cells_wet(&s->cells, P);
        if (!wet)
            return -1;
        const wall_cut k = wall_cut_of(&s->cells, s->kernel.support);
        if (cfg->dim == 3)
            mdbc3(s, P, wet, k, s->nactive);
        else
            mdbc2(s, P, wet, k, s->nactive);
    }
    sph_wcsph_consts kc;
    sph_wcsph_consts_of(s, &kc);
    prepare(s, &kc);
    if (s->bodies.n > 0) { /* the body particles' pressure from the fluid around them */
        const double tb = omp_get_wtime();
        const double *p; /* (bodies run in double: sph_sim_check) */
        const float *p32;
        sph_wcsph_pressure(s, &p, &p32);
        sph_bodies_pressure(&s->bodies, cfg, &s->kernel, &s->cells, p, P, s->nactive);
        s->timing.bodies += omp_get_wtime() - tb;
    }
    const unsigned flags = kc.flags;
    const int D = cfg->dim;
    fctx c;
    fctx_init(&c, P, &s->cells, s->cells.start, &s->kernel, &kc);
    if (listed) {
        c.loff = s->nlist.off;
        c.lcb = s->nlist.cb;
        c.lca = s->nlist.ca;
    }
    c.owner = s->bodies.owner;
    c.body0 = s->bodies.first;
    for (int k = 0; k < s->bodies.n; k++)
        c.from_fluid[k] = (unsigned char)s->bodies.b[k].from_fluid;
    sph_strip_fn fn = NULL;
#define SPH_PICK(T) fn = sph_wcsph_strip_##T(D, flags)
    SPH_KERNEL_DISPATCH(s->kernel.type, SPH_PICK);
#undef SPH_PICK
    if (!fn) /* an MPS weight or a refused combination: sph_sim_check refuses them first */
        return -1;
    const int nstrips = (s->cells.nx - 2 + 1) / 2;
    const long n = s->nactive;
    long pairs = 0;
    if (gather) {
        gather_fn gf = NULL;
#define SPH_PICK(T) gf = D == 3 ? gather3_##T : gather2_##T
        SPH_KERNEL_DISPATCH(s->kernel.type, SPH_PICK);
#undef SPH_PICK
#pragma omp parallel for schedule(dynamic, SPH_OMP_CHUNK) reduction(+ : pairs) if (n >= SPH_OMP_MIN)
        for (long i = 0; i < n; i++)
            pairs += gf(&c, i);
        pairs /= 2; /* each pair was visited from both sides */
    } else {
        for (int parity = 0; parity < 2; parity++) {
#pragma omp parallel for schedule(dynamic, 1) reduction(+ : pairs) if (n >= SPH_OMP_MIN)
            for (int st = parity; st < nstrips; st += 2)
                pairs += fn(&c, st);
        }
    }

    /* particle shifting, while the ghosts are there (they count in the concentration) */
    if (shift_dt > 0.0 && cfg->shifting.type != SPH_SHIFT_NONE && shift_pass(s, &c, n, shift_dt))
        return -1;

    /* the bodies take the force and torque their particles received */
    double t2 = omp_get_wtime();
    sph_bodies_gather(&s->bodies, P, n, s->mass);
    s->timing.bodies += omp_get_wtime() - t2;

    /* gravity on the fluid; walls, bodies' particles and lost particles do not move by it */
    const double amax2 = gravity(cfg, P, n);
    s->amax = fmax(sqrt(amax2), sph_bodies_amax(&s->bodies));
    double t3 = omp_get_wtime();
    s->timing.interactions += t3 - t1;
    s->timing.pairs = pairs;
    if (ghosts) { /* what the ghosts received is discarded with them */
        sph_particles_remove(P, SPH_GHOST, s->cells.perm);
        s->nactive -= s->nghost;
        s->timing.neighbours += omp_get_wtime() - t3;
    }
    s->timing.active = s->nactive;
    return 0;
}

int sph_wcsph_forces(sph_sim *s)
{
    return forces(s, 0, 0.0);
}

int sph_wcsph_forces_step(sph_sim *s, double dt)
{
    return forces(s, 0, dt);
}

int sph_wcsph_forces_gather(sph_sim *s)
{
    return forces(s, 1, 0.0);
}
