/*
 * The symmetric pair loop of the WCSPH method (sph_wcsph.c's force evaluation), its
 * instantiations made per kernel type in a file of their own each (sph_wcsph_strips_<type>.c:
 * SPH_STRIPS_OF), so that a parallel build compiles them at once. Included by those files only.
 *
 * Each pair is computed once and applied to both particles with opposite signs. The loop is
 * written once, strip_generic(), a `static inline` function taking the kernel type, the option
 * flags and the dimension as compile-time constants; the force evaluation picks its
 * instantiation for the job's kernel, flags and dimension once (sph_wcsph_strip_of), so no pair
 * goes through a function pointer and 2D pays nothing for the third axis.
 *
 * Parallel without atomics: the grid's columns (2D) or x slabs (3D) are grouped in strips two
 * cells wide along x. A cell interacts with itself and with the neighbouring cells that come
 * after it (in 2D the cell above it and the three cells of the next column; in 3D the cell
 * above it, the three cells of the next y column and the nine of the next x slab), so a strip
 * writes only to its own cells and the first layer of the next strip: strips of the same parity
 * never write to the same particle. The even strips run in parallel, then the odd ones. The
 * order in which a particle receives its contributions is fixed by the grid alone, so the
 * results are bitwise the same whatever the number of threads. A reused neighbour list
 * (sph_nlist) keeps that order: its rows are the cells' half stencils of its build.
 */
#ifndef SPH_WCSPH_STRIPS_H
#define SPH_WCSPH_STRIPS_H

#include "sph_wcsph.h"
#include "sph_wcsph_loop.h"
#include "sph_wcsph_pair.h"

#include <math.h>

/* Interactions of particle i with particles J(k) for k in [jb, je) (J: k itself over a range of
 * the cells, a neighbour list's entry over a list), both sides (the symmetric loop); j's sums
 * go through restrict locals of the storage's type. */
#define SPH_INTERACT_LOOP(R, TAKE_J, A, J)                                                         \
    do {                                                                                           \
        R *restrict ax = (A)->ax, *restrict ay = (A)->ay, *restrict az = (A)->az,                  \
                    *restrict drho = (A)->drho;                                                    \
        for (long k = jb; k < je; k++) {                                                           \
            const long j = (J);                                                                    \
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
        SPH_INTERACT_LOOP(float, take_j_f(F, D, ax, ay, az, drho, j, &o, &tk), &c->f32, k);
    else
        SPH_INTERACT_LOOP(double, take_j(F, D, c, ax, ay, az, drho, j, &o, &tk), c, k);
}

/* The same over particle i's entries of the neighbour list, lj[jb .. je). */
static inline __attribute__((always_inline)) void interact_list(sph_kernel_type T, unsigned F,
                                                                const int D, const fctx *restrict c,
                                                                long i, const int *restrict lj,
                                                                long jb, long je, acc *restrict ai)
{
    pair_i q;
    pair_i_load(F, D, c, i, &q);
    if (F & F_MIXED)
        SPH_INTERACT_LOOP(float, take_j_f(F, D, ax, ay, az, drho, j, &o, &tk), &c->f32, lj[k]);
    else
        SPH_INTERACT_LOOP(double, take_j(F, D, c, ax, ay, az, drho, j, &o, &tk), c, lj[k]);
}

/* Whether the option set F can run over a reused neighbour list (sph_sim_check refuses the
 * list with ghosts and bodies: no instantiation of theirs carries its loop). */
#define LISTABLE(F) (((F) & (F_GHOST | F_BODY)) == 0)

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
    if (LISTABLE(F) && c->loff) {
        /* over the list: the strip's particles, the columns (2D) or x slabs (3D) cx0 .. cx1 - 1
         * of the list's build, each against its candidates, in the cells' order */
        const long slab = (long)ny * nz; /* (nz = 1 in 2D) */
        for (int cx = cx0; cx < cx1; cx++) {
            const int *const cb = c->lcb[cx];
            const long ca = c->lca[cx];
            for (long i = start[cx * slab]; i < start[(cx + 1) * slab]; i++) {
                acc a = {0};
                interact_list(T, F, D, c, i, cb, c->loff[i] - ca, c->loff[i + 1] - ca, &a);
                add_acc(F, D, c, i, &a);
                pairs += a.pairs;
            }
        }
        return pairs;
    }
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
    static const sph_strip_fn strips2_##T[F_COUNT] = { \
        SPH_STRIP_COMMON_ROWS(T, 2) \
        SPH_STRIP_ROW(T, 32, 2) SPH_STRIP_ROW(T, 33, 2) SPH_STRIP_ROW(T, 34, 2) \
        SPH_STRIP_ROW(T, 35, 2) SPH_STRIP_ROW(T, 36, 2) SPH_STRIP_ROW(T, 37, 2) \
        SPH_STRIP_ROW(T, 38, 2) SPH_STRIP_ROW(T, 39, 2) SPH_STRIP_ROW(T, 48, 2) \
        SPH_STRIP_ROW(T, 50, 2) SPH_STRIP_ROW(T, 52, 2) SPH_STRIP_ROW(T, 54, 2) \
    }; \
    static const sph_strip_fn strips3_##T[F_COUNT] = { SPH_STRIP_COMMON_ROWS(T, 3) }; \
    SPH_STRIP_MIXED(T, 2) SPH_STRIP_MIXED(T, 3) \
    static const sph_strip_fn strips2m_##T[F_COUNT] = { SPH_STRIP_MIXED_ROWS(T, 2) }; \
    static const sph_strip_fn strips3m_##T[F_COUNT] = { SPH_STRIP_MIXED_ROWS(T, 3) };
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

/* The instantiations of kernel type T and the lookup of its row, sph_wcsph_strip_<T> (declared
 * in sph_wcsph.h). */
#define SPH_STRIPS_OF(T)                                                                           \
    SPH_STRIP_TABLE(T)                                                                             \
    sph_strip_fn sph_wcsph_strip_##T(int D, unsigned flags)                                        \
    {                                                                                              \
        return (flags & F_MIXED) ? (D == 3 ? strips3m_##T : strips2m_##T)[flags & (F_COUNT - 1)]   \
                                 : (D == 3 ? strips3_##T : strips2_##T)[flags];                    \
    }

#endif
