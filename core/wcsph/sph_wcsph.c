/*
 * sph_wcsph: the WCSPH pair loops, in 2D and 3D; the physics of a pair is
 * sph_wcsph_pair() (sph_wcsph_pair.h), these loops schedule it.
 *
 * Each pair is computed once and applied to both particles with opposite signs. The loop is
 * written once, strip_generic(), a `static inline` function taking the kernel type, the option
 * flags and the dimension as compile-time constants; SPH_KERNEL_DISPATCH picks its
 * instantiation for the job's kernel, flags and dimension once per force evaluation, so no pair
 * goes through a function pointer and 2D pays nothing for the third axis.
 *
 * Parallel without atomics: the grid's columns (2D) or x slabs (3D) are grouped in strips two
 * cells wide along x. A cell interacts with itself and with the neighbouring cells that come
 * after it (in 2D the cell above it and the three cells of the next column; in 3D the cell
 * above it, the three cells of the next y column and the nine of the next x slab), so a strip
 * writes only to its own cells and the first layer of the next strip: strips of the same parity
 * never write to the same particle. The even strips run in parallel, then the odd ones. The
 * order in which a particle receives its contributions is fixed by the grid alone, so the
 * results are bitwise the same whatever the number of threads.
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

/* Interactions of particle i with particles [jb, je), both sides (the symmetric loop); j's sums
 * go through restrict locals of the storage's type. */
#define SPH_INTERACT_LOOP(R, TAKE_J, A)                                                            \
    do {                                                                                           \
        R *restrict ax = (A)->ax, *restrict ay = (A)->ay, *restrict az = (A)->az,                  \
                    *restrict drho = (A)->drho;                                                    \
        for (long j = jb; j < je; j++) {                                                           \
            sph_wcsph_pair_out o;                                                                  \
            pair_take tk;                                                                          \
            if (!pair_of(T, F, D, c, &q, j, &o, &tk))                                              \
                continue;                                                                          \
            take_i(F, D, &o, &tk, ai);                                                             \
            TAKE_J;                                                                                \
        }                                                                                          \
    } while (0)
static inline __attribute__((always_inline)) void interact(sph_kernel_type T, unsigned F,
                                                           const int D, const fctx *restrict c,
                                                           long i, long jb, long je,
                                                           acc *restrict ai)
{
    pair_i q;
    pair_i_load(F, D, c, i, &q);
    if (F & F_MIXED)
        SPH_INTERACT_LOOP(float, take_j_f(F, D, ax, ay, az, drho, j, &o, &tk), &c->f32);
    else
        SPH_INTERACT_LOOP(double, take_j(F, D, c, ax, ay, az, drho, j, &o, &tk), c);
}

/* The pairs of strip `strip` (the cells with cx = 1 + 2 strip and 2 + 2 strip). Returns the
 * pair count. */
static inline __attribute__((always_inline)) long
strip_generic(sph_kernel_type T, unsigned F, const int D, const fctx *cp, int strip)
{
    /* a local copy of the constants: nothing the loops store can alias it */
    const fctx cl = *cp, *const c = &cl;
    const int ny = c->ny, nz = c->nz;
    const int *start = c->start;
    const int cx0 = 1 + 2 * strip, cx1 = cx0 + 2 < c->nx - 1 ? cx0 + 2 : c->nx - 1;
    long pairs = 0;
    if (D == 2) {
        for (int cx = cx0; cx < cx1; cx++)
            for (int cy = 1; cy < ny - 1; cy++) {
                const long cell = (long)cx * ny + cy;
                const long ib = start[cell], ie = start[cell + 1];
                if (ib == ie)
                    continue;
                const long up = start[cell + 2]; /* end of the cell above */
                long rb[1], re[1];
                (void)half_stencil(2, start, cell, ny, 1, rb, re); /* the next column */
                for (long i = ib; i < ie; i++) {
                    acc a = {0};
                    interact(T, F, D, c, i, i + 1, up, &a);
                    interact(T, F, D, c, i, rb[0], re[0], &a);
                    add_acc(F, D, c, i, &a);
                    pairs += a.pairs;
                }
            }
        return pairs;
    }
    /* In 3D each range is a column of cells along z whose particles are sorted by z
     * (sph_cells_sort), so it is cut to the particles whose z is within reach of i's: two
     * pointers per range that only move forward, as i's z only grows through its cell. The cut
     * is wider than the support by a margin far above the rounding of z +- reach, so that it
     * only drops candidates pair_of would refuse: the same pairs in the same order as the whole
     * ranges. Both cuts take the positions as sorted: forces() sorts before every evaluation (a
     * loop over cells built earlier, from positions since moved, would lose pairs). */
    const double *restrict z = c->z;
    const double size = 1.0 / c->inv_size;
    const double reach = c->reach, reach2 = reach * reach;
    /* A neighbour column is also at a distance across (x, y) from i, at least that of i to the
     * column's cells (less the margin lat), which leaves it the reach in z sqrt(reach^2 - d^2),
     * or none. */
    const double lat = c->lat;
    for (int cx = cx0; cx < cx1; cx++)
        for (int cy = 1; cy < ny - 1; cy++)
            for (int cz = 1; cz < nz - 1; cz++) {
                const long cell = ((long)cx * ny + cy) * nz + cz;
                const long ib = start[cell], ie = start[cell + 1];
                if (ib == ie)
                    continue;
                const long up = start[cell + 2]; /* end of the cell above (cz + 1) */
                long rb[4], re[4];               /* the next y column and the next x slab's three */
                (void)half_stencil(3, start, cell, ny, nz, rb, re);
                long lo[4], hi[4], top = ib + 1;
                for (int k = 0; k < 4; k++)
                    lo[k] = hi[k] = rb[k];
                /* the faces of the neighbour columns: y of the next y column (and of the next
                 * slab's cy + 1 one), y of the slab's cy - 1 one, x of the next slab */
                const double yup = c->y0 + (cy + 1) * size, ydn = c->y0 + cy * size;
                const double xup = c->x0 + (cx + 1) * size;
                for (long i = ib; i < ie; i++) {
                    const double zlo = z[i] - reach, zhi = z[i] + reach;
                    acc a = {0};
                    top = top > i + 1 ? top : i + 1;
                    while (top < up && z[top] < zhi)
                        top++;
                    interact(T, F, D, c, i, i + 1, top, &a);
                    const double ux = fmax(xup - c->x[i] - lat, 0.0);
                    const double uy = fmax(yup - c->y[i] - lat, 0.0);
                    const double dy = fmax(c->y[i] - ydn - lat, 0.0);
                    /* the columns' squared distances across, in half_stencil's order */
                    const double d2[4] = {uy * uy, ux * ux + dy * dy, ux * ux, ux * ux + uy * uy};
                    for (int k = 0; k < 4; k++) {
                        while (lo[k] < re[k] && z[lo[k]] <= zlo)
                            lo[k]++;
                        hi[k] = hi[k] > lo[k] ? hi[k] : lo[k];
                        while (hi[k] < re[k] && z[hi[k]] < zhi)
                            hi[k]++;
                        if (d2[k] >= reach2)
                            continue; /* the whole column is out of reach */
                        /* within the window, the part within the column's own reach in z */
                        const double rz = sqrt(reach2 - d2[k]);
                        long b = lo[k], e = hi[k];
                        while (b < e && z[b] <= z[i] - rz)
                            b++;
                        while (e > b && z[e - 1] >= z[i] + rz)
                            e--;
                        interact(T, F, D, c, i, b, e, &a);
                    }
                    add_acc(F, D, c, i, &a);
                    pairs += a.pairs;
                }
            }
    return pairs;
}

typedef long (*strip_fn)(const fctx *c, int strip);

/* One instantiation per kernel type, option set and dimension a job can make:
 * strips<D>_<TYPE>[flags], the flags' value naming the instantiation. The combinations
 * sph_sim_check refuses (laminar with monaghan: one viscosity; ghost walls with bodies:
 * sph_body_check; bodies in 3D) have none, their entry is NULL: in 2D 36 of the 64 per kernel,
 * in 3D 24. Mixed precision's, strips<D>m_<TYPE>[flags] (F_MIXED with the flags, no SPS and no
 * bodies: sph_sim_check), 12 per kernel and dimension: 420 in all.
 * SPH_STRIPS_RUNTIME (the sanitizer and fuzz builds: CMakeLists.txt) keeps the tables but points
 * every entry at one instantiation per kernel type and dimension that reads the options (and
 * F_MIXED) at run time: the same source and the same arithmetic (the options only pick
 * branches), 10 functions instead of 420; with 300 the sanitizers' instrumentation took this file
 * 6 minutes to compile. */
#ifdef SPH_STRIPS_RUNTIME
#define SPH_STRIP_FN(T, FL, D)
#define SPH_STRIP_REF(T, FL, D) strip##D##_##T##_rt
#define SPH_STRIP_RT(T, D)                                                                         \
    static long strip##D##_##T##_rt(const fctx *c, int strip)                                      \
    {                                                                                              \
        return strip_generic(T, c->flags, D, c, strip);                                            \
    }
#else
#define SPH_STRIP_FN(T, FL, D)                                                                     \
    static long strip##D##_##T##_##FL(const fctx *c, int strip)                                    \
    {                                                                                              \
        return strip_generic(T, FL, D, c, strip);                                                  \
    }
#define SPH_STRIP_REF(T, FL, D) strip##D##_##T##_##FL
#define SPH_STRIP_RT(T, D)
#endif
/* clang-format off */
#define SPH_STRIP_COMMON(T, D) \
    SPH_STRIP_FN(T, 0, D) SPH_STRIP_FN(T, 1, D) SPH_STRIP_FN(T, 2, D) SPH_STRIP_FN(T, 3, D) \
    SPH_STRIP_FN(T, 4, D) SPH_STRIP_FN(T, 5, D) SPH_STRIP_FN(T, 6, D) SPH_STRIP_FN(T, 7, D) \
    SPH_STRIP_FN(T, 8, D) SPH_STRIP_FN(T, 9, D) SPH_STRIP_FN(T, 10, D) SPH_STRIP_FN(T, 11, D) \
    SPH_STRIP_FN(T, 12, D) SPH_STRIP_FN(T, 13, D) SPH_STRIP_FN(T, 14, D) SPH_STRIP_FN(T, 15, D) \
    SPH_STRIP_FN(T, 16, D) SPH_STRIP_FN(T, 18, D) SPH_STRIP_FN(T, 20, D) SPH_STRIP_FN(T, 22, D) \
    SPH_STRIP_FN(T, 24, D) SPH_STRIP_FN(T, 26, D) SPH_STRIP_FN(T, 28, D) SPH_STRIP_FN(T, 30, D)
#define SPH_STRIP_ROW(T, FL, D) [FL] = SPH_STRIP_REF(T, FL, D),
#define SPH_STRIP_COMMON_ROWS(T, D) \
    SPH_STRIP_ROW(T, 0, D) SPH_STRIP_ROW(T, 1, D) SPH_STRIP_ROW(T, 2, D) SPH_STRIP_ROW(T, 3, D) \
    SPH_STRIP_ROW(T, 4, D) SPH_STRIP_ROW(T, 5, D) SPH_STRIP_ROW(T, 6, D) SPH_STRIP_ROW(T, 7, D) \
    SPH_STRIP_ROW(T, 8, D) SPH_STRIP_ROW(T, 9, D) SPH_STRIP_ROW(T, 10, D) SPH_STRIP_ROW(T, 11, D) \
    SPH_STRIP_ROW(T, 12, D) SPH_STRIP_ROW(T, 13, D) SPH_STRIP_ROW(T, 14, D) SPH_STRIP_ROW(T, 15, D) \
    SPH_STRIP_ROW(T, 16, D) SPH_STRIP_ROW(T, 18, D) SPH_STRIP_ROW(T, 20, D) SPH_STRIP_ROW(T, 22, D) \
    SPH_STRIP_ROW(T, 24, D) SPH_STRIP_ROW(T, 26, D) SPH_STRIP_ROW(T, 28, D) SPH_STRIP_ROW(T, 30, D)
#define SPH_STRIP_TABLE(T) \
    SPH_STRIP_RT(T, 2) SPH_STRIP_RT(T, 3) \
    SPH_STRIP_COMMON(T, 2) \
    SPH_STRIP_FN(T, 32, 2) SPH_STRIP_FN(T, 33, 2) SPH_STRIP_FN(T, 34, 2) SPH_STRIP_FN(T, 35, 2) \
    SPH_STRIP_FN(T, 36, 2) SPH_STRIP_FN(T, 37, 2) SPH_STRIP_FN(T, 38, 2) SPH_STRIP_FN(T, 39, 2) \
    SPH_STRIP_FN(T, 48, 2) SPH_STRIP_FN(T, 50, 2) SPH_STRIP_FN(T, 52, 2) SPH_STRIP_FN(T, 54, 2) \
    SPH_STRIP_COMMON(T, 3) \
    static const strip_fn strips2_##T[F_COUNT] = { \
        SPH_STRIP_COMMON_ROWS(T, 2) \
        SPH_STRIP_ROW(T, 32, 2) SPH_STRIP_ROW(T, 33, 2) SPH_STRIP_ROW(T, 34, 2) \
        SPH_STRIP_ROW(T, 35, 2) SPH_STRIP_ROW(T, 36, 2) SPH_STRIP_ROW(T, 37, 2) \
        SPH_STRIP_ROW(T, 38, 2) SPH_STRIP_ROW(T, 39, 2) SPH_STRIP_ROW(T, 48, 2) \
        SPH_STRIP_ROW(T, 50, 2) SPH_STRIP_ROW(T, 52, 2) SPH_STRIP_ROW(T, 54, 2) \
    }; \
    static const strip_fn strips3_##T[F_COUNT] = { SPH_STRIP_COMMON_ROWS(T, 3) }; \
    SPH_STRIP_MIXED(T, 2) SPH_STRIP_MIXED(T, 3) \
    static const strip_fn strips2m_##T[F_COUNT] = { SPH_STRIP_MIXED_ROWS(T, 2) }; \
    static const strip_fn strips3m_##T[F_COUNT] = { SPH_STRIP_MIXED_ROWS(T, 3) };
/* Mixed precision's (F_MIXED = 64 added to the flags): the options it takes (no SPS, no bodies:
 * sph_sim_check), the row the flags without F_MIXED. */
#define SPH_STRIP_MIXED(T, D) \
    SPH_STRIP_FN(T, 64, D) SPH_STRIP_FN(T, 65, D) SPH_STRIP_FN(T, 68, D) SPH_STRIP_FN(T, 69, D) \
    SPH_STRIP_FN(T, 72, D) SPH_STRIP_FN(T, 73, D) SPH_STRIP_FN(T, 76, D) SPH_STRIP_FN(T, 77, D) \
    SPH_STRIP_FN(T, 80, D) SPH_STRIP_FN(T, 84, D) SPH_STRIP_FN(T, 88, D) SPH_STRIP_FN(T, 92, D)
#define SPH_STRIP_MROW(T, FL, D) [FL - F_MIXED] = SPH_STRIP_REF(T, FL, D),
#define SPH_STRIP_MIXED_ROWS(T, D) \
    SPH_STRIP_MROW(T, 64, D) SPH_STRIP_MROW(T, 65, D) SPH_STRIP_MROW(T, 68, D) \
    SPH_STRIP_MROW(T, 69, D) SPH_STRIP_MROW(T, 72, D) SPH_STRIP_MROW(T, 73, D) \
    SPH_STRIP_MROW(T, 76, D) SPH_STRIP_MROW(T, 77, D) SPH_STRIP_MROW(T, 80, D) \
    SPH_STRIP_MROW(T, 84, D) SPH_STRIP_MROW(T, 88, D) SPH_STRIP_MROW(T, 92, D)
/* clang-format on */

SPH_STRIP_TABLE(SPH_KERNEL_CUBIC_SPLINE)
SPH_STRIP_TABLE(SPH_KERNEL_GAUSSIAN)
SPH_STRIP_TABLE(SPH_KERNEL_DOUBLE_COSINE)
SPH_STRIP_TABLE(SPH_KERNEL_WENDLAND_C2)
SPH_STRIP_TABLE(SPH_KERNEL_RENORMALIZED_GAUSSIAN)
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
static const strip_fn strips2_SPH_KERNEL_KOSHIZUKA[F_COUNT] = {0};
static const strip_fn strips2_SPH_KERNEL_SHEU_QUARTIC[F_COUNT] = {0};
static const strip_fn strips3_SPH_KERNEL_KOSHIZUKA[F_COUNT] = {0};
static const strip_fn strips3_SPH_KERNEL_SHEU_QUARTIC[F_COUNT] = {0};
static const strip_fn strips2m_SPH_KERNEL_KOSHIZUKA[F_COUNT] = {0};
static const strip_fn strips2m_SPH_KERNEL_SHEU_QUARTIC[F_COUNT] = {0};
static const strip_fn strips3m_SPH_KERNEL_KOSHIZUKA[F_COUNT] = {0};
static const strip_fn strips3m_SPH_KERNEL_SHEU_QUARTIC[F_COUNT] = {0};

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
    double t0 = omp_get_wtime();
    if (ghosts && add_ghosts(s))
        return -1;
    s->nactive = sph_cells_sort(&s->cells, P);
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
    c.owner = s->bodies.owner;
    c.body0 = s->bodies.first;
    for (int k = 0; k < s->bodies.n; k++)
        c.from_fluid[k] = (unsigned char)s->bodies.b[k].from_fluid;
    strip_fn fn = NULL;
#define SPH_PICK(T)                                                                                \
    fn = (flags & F_MIXED) ? (D == 3 ? strips3m_##T : strips2m_##T)[flags & (F_COUNT - 1)]         \
                           : (D == 3 ? strips3_##T : strips2_##T)[flags]
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
