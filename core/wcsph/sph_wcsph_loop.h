/*
 * The WCSPH pair loop's pieces that the C loops (sph_wcsph.c) and the CUDA kernels (core/gpu/)
 * share: the force context (fctx: the particle arrays where the caller runs, the grid, the
 * constants), the one function that decides a pair's physics (pair_of, which calls
 * sph_wcsph_pair), particle i's side of it (take_i), and the gather loop of one particle
 * (gather_one: i against every neighbour in the 3 x 3 (x 3) cells around it, its side alone),
 * which is a GPU thread's work and the C reference of it (sph_wcsph_forces_gather).
 */
#ifndef SPH_WCSPH_LOOP_H
#define SPH_WCSPH_LOOP_H

#include "sph_cells.h"
#include "sph_config.h"
#include "sph_hd.h"
#include "sph_kernel.h"
#include "sph_particles.h"
#include "sph_shifting.h"
#include "sph_wcsph_pair.h"

#include <math.h>
#include <string.h>

#define F_LAMINAR  SPH_WF_LAMINAR
#define F_SPS      SPH_WF_SPS
#define F_DELTA    SPH_WF_DELTA
#define F_GHOST    SPH_WF_GHOST
#define F_MONAGHAN SPH_WF_MONAGHAN
#define F_BODY     SPH_WF_BODY
#define F_COUNT    SPH_WF_COUNT
/* Storage, not physics: the particles' hot fields in float (sph_particles.h, mixed precision).
 * The loops here read and write through SPH_GET / SPH_SET with it; sph_wcsph_pair never sees
 * it. */
#define F_MIXED SPH_WF_COUNT
/* 1 when F stores the hot fields in float: the M of SPH_GET / SPH_SET (sph_particles.h), which
 * read a force context's fields as they read a particle set's (the same names in f32). */
#define MX(F) (((F)&F_MIXED) != 0)

typedef struct fctx {
    const double *x, *y, *z, *vx, *vy, *vz, *rho, *pr;
    const unsigned char *type;
    const int *id;    /* creation index (F_BODY: which body a body particle belongs to) */
    const int *owner; /* F_BODY: body of body particle id, at owner[id - body0] */
    unsigned char from_fluid[SPH_CONFIG_MAX_BODIES]; /* F_BODY: the body's pressure from the
                                                        fluid: its continuity skips fluid pairs */
    long body0;                                      /* F_BODY: id of the first body particle */
    double *ax, *ay, *az, *drho;
    struct {
        const float *vx, *vy, *vz, *rho, *pr;
        float *ax, *ay, *az, *drho;
    } f32;              /* F_MIXED: those fields in float (the double pointers NULL) */
    double *g[6];       /* SPS: the velocity gradients xx, xy, yy, zz, xz, yz (3D: all six) */
    const double *t[6]; /* SPS: the stresses / rho, the same components */
    const int *start;
    const long *loff;      /* a reused neighbour list (sph_nlist), NULL without: particle i's */
    const int *const *lcb; /* candidates, of column cx, are lcb[cx][loff[i] - lca[cx] .. */
    const long *lca;       /* loff[i + 1] - lca[cx]) */
    int nx, ny, nz;
    double x0, y0, z0, inv_size; /* the grid (a gather loop finds a particle's cell) */
    const sph_kernel *k;
    sph_wcsph_pair_const pc; /* the pair physics' constants */
    double support2;         /* support radius squared [m^2] */
    double tiny;             /* guards r = 0 [m] */
    double wall_visc;  /* factor on the viscous terms of fluid-wall pairs (dynamic walls) [-] */
    double reach, lat; /* 3D cuts of the cell ranges: sph_cells_cut_margins [m] */
    unsigned flags;    /* the SPH_WF_ options (read at run time only with SPH_STRIPS_RUNTIME) */
} fctx;

/* The constants of a force evaluation: the pair physics', the options (SPH_WF_*), the support,
 * the walls' viscosity factor and the SPS model's (Cs dx)^2 and 2/3 CI dx^2. */
typedef struct sph_wcsph_consts {
    sph_wcsph_pair_const pc;
    unsigned flags;
    double support2, tiny, wall_visc, smag, blin;
} sph_wcsph_consts;

/* The force context of particle arrays P (where the caller runs), the grid's shape, its cells'
 * starts, the kernel k and the constants kc; the bodies' fields zeroed (the C loop adds them). */
SPH_HD static inline void fctx_init(fctx *c, const sph_particles *P, const sph_cells *grid,
                                    const int *start, const sph_kernel *k,
                                    const sph_wcsph_consts *kc)
{
    memset(c, 0, sizeof *c);
    c->x = P->x;
    c->y = P->y;
    c->z = P->z;
    c->vx = P->vx;
    c->vy = P->vy;
    c->vz = P->vz;
    c->rho = P->rho;
    c->pr = P->pr;
    c->type = P->type;
    c->id = P->id;
    c->ax = P->ax;
    c->ay = P->ay;
    c->az = P->az;
    c->drho = P->drho;
    c->f32.vx = P->f32.vx;
    c->f32.vy = P->f32.vy;
    c->f32.vz = P->f32.vz;
    c->f32.rho = P->f32.rho;
    c->f32.pr = P->f32.pr;
    c->f32.ax = P->f32.ax;
    c->f32.ay = P->f32.ay;
    c->f32.az = P->f32.az;
    c->f32.drho = P->f32.drho;
    double *const gs[6] = {P->gxx, P->gxy, P->gyy, P->gzz, P->gxz, P->gyz};
    const double *const ts[6] = {P->txx, P->txy, P->tyy, P->tzz, P->txz, P->tyz};
    for (int q = 0; q < 6; q++) {
        c->g[q] = gs[q];
        c->t[q] = ts[q];
    }
    c->start = start;
    c->nx = grid->nx;
    c->ny = grid->ny;
    c->nz = grid->nz;
    c->x0 = grid->x0;
    c->y0 = grid->y0;
    c->z0 = grid->z0;
    c->inv_size = grid->inv_size;
    c->k = k;
    c->pc = kc->pc;
    c->support2 = kc->support2;
    c->tiny = kc->tiny;
    c->wall_visc = kc->wall_visc;
    c->flags = kc->flags;
    sph_cells_cut_margins(grid, sqrt(kc->support2), &c->reach, &c->lat);
}

typedef struct acc {
    double a[3], drho, g[6];
    long pairs;
} acc;

/* What a pair loop keeps of particle i while it visits its neighbours. */
typedef struct pair_i {
    double x[3], v[3], rho, pr, t[6];
    unsigned char wall; /* the walls' type: SPH_BOUNDARY (dynamic) or SPH_GHOST */
    int b;              /* i is a wall particle */
    int o;              /* F_BODY: i's body, -1 when i is not a body particle */
    int f;              /* i is fluid */
} pair_i;

SPH_HD static inline __attribute__((always_inline)) void
pair_i_load(unsigned F, const int D, const fctx *SPH_RESTRICT c, long i, pair_i *SPH_RESTRICT q)
{
    q->x[0] = c->x[i];
    q->x[1] = c->y[i];
    q->x[2] = D == 3 ? c->z[i] : 0.0;
    q->v[0] = SPH_GET(MX(F), c, vx, i);
    q->v[1] = SPH_GET(MX(F), c, vy, i);
    q->v[2] = D == 3 ? SPH_GET(MX(F), c, vz, i) : 0.0;
    q->rho = SPH_GET(MX(F), c, rho, i);
    q->pr = SPH_GET(MX(F), c, pr, i);
    for (int k = 0; k < 6; k++)
        q->t[k] = 0.0;
    if (F & F_SPS)
        for (int k = 0; k < (D == 3 ? 6 : 3); k++)
            q->t[k] = c->t[k][i];
    q->wall = (F & F_GHOST) ? SPH_GHOST : SPH_BOUNDARY;
    q->b = c->type[i] == q->wall;
    q->o = (F & F_BODY) && c->type[i] == SPH_BODY ? c->owner[c->id[i] - c->body0] : -1;
    q->f = c->type[i] == SPH_FLUID;
}

/* Which sides of a pair take what: skip_i, skip_j (continuity, bodies that take their
 * pressure from the fluid), delta (whether delta-SPH acts on the pair). */
typedef struct pair_take {
    int skip_i, skip_j, delta;
} pair_take;

/* The pair (i, j): 0 when j is out of reach or the pair does not interact (wall-wall, one
 * rigid body), else 1 with what it adds in *o and who takes it in *tk. The one place that
 * decides a pair's physics, for the symmetric loops here and the gather loops (a GPU's). */
SPH_HD static inline __attribute__((always_inline)) int
pair_of(sph_kernel_type T, unsigned F, const int D, const fctx *SPH_RESTRICT c,
        const pair_i *SPH_RESTRICT q, long j, sph_wcsph_pair_out *SPH_RESTRICT o,
        pair_take *SPH_RESTRICT tk)
{
    double d[3];
    d[0] = q->x[0] - c->x[j];
    d[1] = q->x[1] - c->y[j];
    if (D == 3)
        d[2] = q->x[2] - c->z[j];
    const double r2 = D == 3 ? d[0] * d[0] + d[1] * d[1] + d[2] * d[2] : d[0] * d[0] + d[1] * d[1];
    if (r2 >= c->support2)
        return 0;
    const int bj = c->type[j] == q->wall;
    if (q->b & bj) /* wall-wall pairs: nothing a fluid particle feels */
        return 0;
    if ((F & F_BODY) && q->o >= 0 && c->type[j] == SPH_BODY &&
        c->owner[c->id[j] - c->body0] == q->o) /* one rigid body: no force within it */
        return 0;
    const double r = sqrt(r2);
    double dwdr;
    (void)sph_kernel_eval_t(T, c->k, r, &dwdr);
    const double fw = dwdr / (r + c->tiny); /* grad_a W_ab = fw (x_a - x_b) */
    double dv[3];
    dv[0] = q->v[0] - SPH_GET(MX(F), c, vx, j);
    dv[1] = q->v[1] - SPH_GET(MX(F), c, vy, j);
    if (D == 3)
        dv[2] = q->v[2] - SPH_GET(MX(F), c, vz, j);
    double tj[6] = {0};
    if (F & F_SPS)
        for (int k = 0; k < (D == 3 ? 6 : 3); k++)
            tj[k] = c->t[k][j];
    /* the viscous terms between fluid and dynamic wall particles are scaled by the case's
     * boundary.viscosity_factor (DualSPHysics' ViscoBoundFactor); ghosts are not walls here */
    const double vf = (!(F & F_GHOST) && (q->b | bj)) ? c->wall_visc : 1.0;
    /* delta-SPH on fluid and ghost pairs only (a ghost's density is the hydrostatic one
     * behind the wall, dynamic particles' is not) */
    tk->delta = (F & F_GHOST) || ((F & F_BODY) ? q->f && c->type[j] == SPH_FLUID : !(q->b | bj));
    sph_wcsph_pair(D, F, &c->pc, d, r2, fw, dv, q->rho, SPH_GET(MX(F), c, rho, j), q->pr,
                   SPH_GET(MX(F), c, pr, j), vf, q->t, tj, tk->delta, o);
    /* continuity: the same for both particles, except that the particles of a body that takes
     * its pressure from the fluid count only solid neighbours (walls, other bodies): their
     * density is the contact's */
    tk->skip_i = (F & F_BODY) && q->o >= 0 && c->from_fluid[q->o] && c->type[j] == SPH_FLUID;
    tk->skip_j = (F & F_BODY) && q->f && c->type[j] == SPH_BODY &&
                 c->from_fluid[c->owner[c->id[j] - c->body0]];
    return 1;
}

/* i's side of a pair, into its sums. */
SPH_HD static inline __attribute__((always_inline)) void
take_i(unsigned F, const int D, const sph_wcsph_pair_out *SPH_RESTRICT o, const pair_take *tk,
       acc *SPH_RESTRICT ai)
{
    ai->pairs++;
    if (!tk->skip_i)
        ai->drho += o->dd;
    if (F & F_SPS)
        for (int k = 0; k < (D == 3 ? 6 : 3); k++)
            ai->g[k] += o->ga[k];
    if ((F & F_DELTA) && tk->delta)
        ai->drho += o->dwa;
    ai->a[0] += o->f[0];
    ai->a[1] += o->f[1];
    if (D == 3)
        ai->a[2] += o->f[2];
}

/* j's side of a pair in a symmetric loop (the opposite of take_i), into the arrays of the
 * caller's restrict locals (c->ax ... through them; c gives the SPS gradients). */
SPH_HD static inline __attribute__((always_inline)) void
take_j(unsigned F, const int D, const fctx *c, double *SPH_RESTRICT ax, double *SPH_RESTRICT ay,
       double *SPH_RESTRICT az, double *SPH_RESTRICT drho, long j,
       const sph_wcsph_pair_out *SPH_RESTRICT o, const pair_take *tk)
{
    if (!tk->skip_j)
        drho[j] += o->dd;
    if (F & F_SPS)
        for (int k = 0; k < (D == 3 ? 6 : 3); k++)
            c->g[k][j] += o->gb[k];
    if ((F & F_DELTA) && tk->delta)
        drho[j] -= o->dwb;
    ax[j] -= o->f[0];
    ay[j] -= o->f[1];
    if (D == 3)
        az[j] -= o->f[2];
}

/* The same into float arrays (F_MIXED: no SPS): each contribution rounded to float and added in
 * float, as the sums are stored (one conversion a field).
 * TODO(issue 48): mixed precision's pair loop runs 0.65-0.84x double's rate (bench_dambreak, 1
 * thread); the pair physics in float did not change that (bench/README.md, "Mixed precision's
 * arithmetic in float": the loss is in these float read-modify-writes; left to try: j's sums
 * without them, or the candidates compacted with AVX-512 behind dispatch). */
SPH_HD static inline __attribute__((always_inline)) void
take_j_f(unsigned F, const int D, float *SPH_RESTRICT ax, float *SPH_RESTRICT ay,
         float *SPH_RESTRICT az, float *SPH_RESTRICT drho, long j,
         const sph_wcsph_pair_out *SPH_RESTRICT o, const pair_take *tk)
{
    double dr = tk->skip_j ? 0.0 : o->dd;
    if ((F & F_DELTA) && tk->delta)
        dr -= o->dwb;
    drho[j] += (float)dr;
    ax[j] -= (float)o->f[0];
    ay[j] -= (float)o->f[1];
    if (D == 3)
        az[j] -= (float)o->f[2];
}

/* Adds particle i's sums. */
SPH_HD static inline __attribute__((always_inline)) void
add_acc(unsigned F, const int D, const fctx *c, long i, const acc *a)
{
    SPH_SET(MX(F), c, ax, i, SPH_GET(MX(F), c, ax, i) + a->a[0]);
    SPH_SET(MX(F), c, ay, i, SPH_GET(MX(F), c, ay, i) + a->a[1]);
    if (D == 3)
        SPH_SET(MX(F), c, az, i, SPH_GET(MX(F), c, az, i) + a->a[2]);
    SPH_SET(MX(F), c, drho, i, SPH_GET(MX(F), c, drho, i) + a->drho);
    if (F & F_SPS)
        for (int q = 0; q < (D == 3 ? 6 : 3); q++)
            c->g[q][i] += a->g[q];
}

/* The half stencil of a cell, for the symmetric loops: the particle ranges after the cell's own
 * that its particles pair with, [rb[k], re[k]) for k < the count returned. 2D (cells ordered
 * cy fastest, ny per column): the next column's three cells cy - 1 .. cy + 1, one range. 3D
 * (cz fastest, ny nz per x slab): the next y column's cells cz - 1 .. cz + 1, then the three
 * columns cy - 1 .. cy + 1 of the next x slab, four ranges. With the cell above (start[cell +
 * 2] ends it), each pair of neighbouring cells is visited once. */
SPH_HD static inline __attribute__((always_inline)) int
half_stencil(const int D, const int *SPH_RESTRICT start, long cell, int ny, int nz,
             long *SPH_RESTRICT rb, long *SPH_RESTRICT re)
{
    if (D == 2) {
        rb[0] = start[cell + ny - 1];
        re[0] = start[cell + ny + 2];
        return 1;
    }
    const long slab = (long)ny * nz;
    rb[0] = start[cell + nz - 1];
    re[0] = start[cell + nz + 2];
    for (int k = 0; k < 3; k++) {
        const long base = cell + slab + (long)(k - 1) * nz;
        rb[k + 1] = start[base - 1];
        re[k + 1] = start[base + 2];
    }
    return 4;
}

/* The gather form (a GPU thread's, and the C reference of it): particle i against every
 * neighbour in the 3 x 3 (x 3) cells around its own, i's side alone; no other particle's sums
 * are written, so the particles can run in any order at once. In 3D each column, sorted by z
 * (by sph_cells_sort, or the GPU's sort), is cut to the particles within reach of i, as the
 * symmetric loop cuts them: the same pairs in the same order, from 45% fewer candidates (Test 2's
 * ci case, 164 against 300 a particle). Adds i's sums; returns its pairs. */
SPH_HD static inline __attribute__((always_inline)) long
gather_one(sph_kernel_type T, unsigned F, const int D, const fctx *SPH_RESTRICT c, long i)
{
    pair_i q;
    pair_i_load(F, D, c, i, &q);
    const int cx = (int)((q.x[0] - c->x0) * c->inv_size);
    const int cy = (int)((q.x[1] - c->y0) * c->inv_size);
    const int cz = D == 3 ? (int)((q.x[2] - c->z0) * c->inv_size) : 0;
    const int ny = c->ny, nz = D == 3 ? c->nz : 1;
    const double size = 1.0 / c->inv_size, reach2 = c->reach * c->reach;
    acc a;
    a.a[0] = a.a[1] = a.a[2] = a.drho = 0.0;
    for (int k = 0; k < 6; k++)
        a.g[k] = 0.0;
    a.pairs = 0;
    /* one pair's output for the whole loop; its SPS gradients zeroed once, as the options may be
     * read at run time, where the compiler cannot see that pair_of writes them when taken */
    sph_wcsph_pair_out o;
    for (int k = 0; k < 6; k++)
        o.ga[k] = o.gb[k] = 0.0;
    for (int ox = -1; ox <= 1; ox++)
        for (int oy = (D == 3 ? -1 : 0); oy <= (D == 3 ? 1 : 0); oy++) {
            /* one contiguous range: the column of 3 cells along the fastest axis */
            const long mid =
                D == 3 ? ((long)(cx + ox) * ny + (cy + oy)) * nz + cz : (long)(cx + ox) * ny + cy;
            long jb = c->start[mid - 1], je = c->start[mid + 2];
            /* 3D: the part within reach of i (the symmetric loop's cut) */
            if (D == 3 && !sph_cells_cut_column(c->x0, c->y0, size, c->z, q.x, cx + ox, cy + oy,
                                                reach2, c->lat, &jb, &je))
                continue;
            for (long j = jb; j < je; j++) {
                pair_take tk;
                if (j != i && pair_of(T, F, D, c, &q, j, &o, &tk))
                    take_i(F, D, &o, &tk, &a);
            }
        }
    add_acc(F, D, c, i, &a);
    return a.pairs;
}

/* Particle shifting's sums of fluid particle i (sph_shifting.h): i against every neighbour in the
 * 3 x 3 (x 3) cells around it, walls, ghosts and bodies counted as fluid (DualSPHysics' "full"
 * mode), in the order gather_one visits them; F gives F_MIXED alone. A GPU thread's work later. */
SPH_HD static inline __attribute__((always_inline)) void
shift_one(sph_kernel_type T, unsigned F, const int D, const fctx *SPH_RESTRICT c, long i,
          sph_shift_sum *SPH_RESTRICT s)
{
    double x[3];
    x[0] = c->x[i];
    x[1] = c->y[i];
    x[2] = D == 3 ? c->z[i] : 0.0;
    const int cx = (int)((x[0] - c->x0) * c->inv_size);
    const int cy = (int)((x[1] - c->y0) * c->inv_size);
    const int cz = D == 3 ? (int)((x[2] - c->z0) * c->inv_size) : 0;
    const int ny = c->ny, nz = D == 3 ? c->nz : 1;
    const double size = 1.0 / c->inv_size, reach2 = c->reach * c->reach, m = c->pc.m;
    s->g[0] = s->g[1] = s->g[2] = s->div = 0.0;
    for (int ox = -1; ox <= 1; ox++)
        for (int oy = (D == 3 ? -1 : 0); oy <= (D == 3 ? 1 : 0); oy++) {
            const long mid =
                D == 3 ? ((long)(cx + ox) * ny + (cy + oy)) * nz + cz : (long)(cx + ox) * ny + cy;
            long jb = c->start[mid - 1], je = c->start[mid + 2];
            if (D == 3 && !sph_cells_cut_column(c->x0, c->y0, size, c->z, x, cx + ox, cy + oy,
                                                reach2, c->lat, &jb, &je))
                continue;
            for (long j = jb; j < je; j++) {
                if (j == i)
                    continue;
                double d[3];
                d[0] = x[0] - c->x[j];
                d[1] = x[1] - c->y[j];
                d[2] = D == 3 ? x[2] - c->z[j] : 0.0;
                const double r2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
                if (r2 >= c->support2)
                    continue;
                const double r = sqrt(r2);
                double dwdr;
                (void)sph_kernel_eval_t(T, c->k, r, &dwdr);
                sph_shifting_pair(D, d, r2, dwdr / (r + c->tiny), m / SPH_GET(MX(F), c, rho, j), s);
            }
        }
}

#endif
