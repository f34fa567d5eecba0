/*
 * sph_mesh: surfaces as plain arrays, and their checks (sph_mesh.h).
 *
 * Triangle soup is welded by a hash of the coordinates' bits (exact equality; -0 is 0). A
 * polygon's sides, and a mesh's triangles for the self-intersection check, are sorted into a
 * uniform grid of cells (a 64-bit key per cell and box, radix-sorted), and only pairs sharing a
 * cell are tested, each pair once: in the cell holding the low corner of their boxes' overlap.
 * Triangle pairs are tested by the planes' signs, then each edge of one against the other
 * (orientation determinants), coplanar pairs in 2D. Pure C11 and libm; may call sph_error.h.
 */
#include "sph_mesh.h"

#include <math.h>
#include <stdint.h>
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

/* ---- small vector helpers ---- */

static void sub3(double *r, const double *a, const double *b)
{
    r[0] = a[0] - b[0];
    r[1] = a[1] - b[1];
    r[2] = a[2] - b[2];
}

static void cross3(double *r, const double *a, const double *b)
{
    r[0] = a[1] * b[2] - a[2] * b[1];
    r[1] = a[2] * b[0] - a[0] * b[2];
    r[2] = a[0] * b[1] - a[1] * b[0];
}

static double dot3(const double *a, const double *b)
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static double norm3(const double *a)
{
    return sqrt(dot3(a, a));
}

/* ---- welding ---- */

static uint64_t bits_of(double x)
{
    uint64_t u;
    if (x == 0.0)
        x = 0.0; /* -0 and 0 are one coordinate */
    memcpy(&u, &x, sizeof u);
    return u;
}

static uint64_t hash3(const double *p)
{
    uint64_t h = 0x9e3779b97f4a7c15ULL;
    for (int k = 0; k < 3; k++) {
        h ^= bits_of(p[k]);
        h *= 0xbf58476d1ce4e5b9ULL;
        h ^= h >> 31;
    }
    return h;
}

static int same3(const double *a, const double *b)
{
    return a[0] == b[0] && a[1] == b[1] && a[2] == b[2];
}

int sph_mesh_from_triangles(sph_mesh *m, const double *xyz, long nt, const sph_mesh_limits *lim,
                            const char *path, sph_error *err)
{
    sph_mesh_limits dl = sph_mesh_limits_default();
    if (!lim)
        lim = &dl;
    memset(m, 0, sizeof *m);
    if (nt <= 0 || !xyz)
        return sph_error_set(err, SPH_ERR_INVALID, path, "mesh has no triangles");
    if (nt > lim->max_triangles)
        return sph_error_set(err, SPH_ERR_INVALID, path,
                             "mesh has %ld triangles, more than the limit of %ld: simplify it "
                             "(decimate it)",
                             nt, lim->max_triangles);
    if (nt > (INT32_MAX - 1) / 3)
        return sph_error_set(err, SPH_ERR_NOMEM, path, "mesh of %ld triangles is too large", nt);
    long nc = 3 * nt; /* corners */
    for (long i = 0; i < 3 * nc; i++)
        if (!isfinite(xyz[i]))
            return sph_error_set(err, SPH_ERR_INVALID, path,
                                 "triangle %ld has a non-finite coordinate (NaN or infinity)",
                                 i / 9);
    size_t cap = 16;
    while (cap < 2 * (size_t)nc)
        cap <<= 1;
    int *table = malloc(cap * sizeof *table);
    int *corner = malloc((size_t)nc * sizeof *corner);
    double *v = malloc((size_t)nc * 3 * sizeof *v);
    if (!table || !corner || !v) {
        free(table), free(corner), free(v);
        return sph_error_set(err, SPH_ERR_NOMEM, path, "out of memory reading a mesh");
    }
    memset(table, 0xff, cap * sizeof *table); /* -1: empty */
    long nv = 0;
    for (long c = 0; c < nc; c++) {
        const double *p = xyz + 3 * c;
        size_t h = (size_t)hash3(p) & (cap - 1);
        while (table[h] >= 0 && !same3(v + 3 * (size_t)table[h], p))
            h = (h + 1) & (cap - 1);
        if (table[h] < 0) {
            table[h] = (int)nv;
            memcpy(v + 3 * nv, p, 3 * sizeof *v);
            nv++;
        }
        corner[c] = table[h];
    }
    free(table);
    /* degenerate triangles: a repeated vertex, or an area below 1e-12 of the longest edge's square
     */
    long kept = 0, degenerate = 0;
    for (long i = 0; i < nt; i++) {
        int a = corner[3 * i], b = corner[3 * i + 1], c = corner[3 * i + 2];
        int bad = a == b || b == c || c == a;
        if (!bad) {
            double e0[3], e1[3], e2[3], n[3];
            sub3(e0, v + 3 * b, v + 3 * a);
            sub3(e1, v + 3 * c, v + 3 * b);
            sub3(e2, v + 3 * a, v + 3 * c);
            cross3(n, e0, e1);
            double l2 = fmax(dot3(e0, e0), fmax(dot3(e1, e1), dot3(e2, e2)));
            double cn = norm3(n);
            bad = cn == 0.0 || cn < 1e-12 * l2;
        }
        if (bad) {
            degenerate++;
            continue;
        }
        corner[3 * kept] = a, corner[3 * kept + 1] = b, corner[3 * kept + 2] = c;
        kept++;
    }
    if (kept == 0) {
        free(corner), free(v);
        return sph_error_set(err, SPH_ERR_INVALID, path,
                             "mesh has no triangle left: all %ld are degenerate (zero area)", nt);
    }
    /* vertices only the dropped triangles used go too */
    int *map = malloc((size_t)nv * sizeof *map);
    if (!map) {
        free(corner), free(v);
        return sph_error_set(err, SPH_ERR_NOMEM, path, "out of memory reading a mesh");
    }
    memset(map, 0xff, (size_t)nv * sizeof *map);
    long nu = 0;
    for (long c = 0; c < 3 * kept; c++) {
        int k = corner[c];
        if (map[k] < 0) {
            map[k] = (int)nu;
            memmove(v + 3 * nu, v + 3 * (size_t)k, 3 * sizeof *v); /* nu <= k: in place */
            nu++;
        }
        corner[c] = map[k];
    }
    free(map);
    double *vs = realloc(v, (size_t)nu * 3 * sizeof *v);
    int *ts = realloc(corner, (size_t)kept * 3 * sizeof *corner);
    m->dim = 3;
    m->nv = nu;
    m->v = vs ? vs : v;
    m->nt = kept;
    m->t = ts ? ts : corner;
    m->degenerate = degenerate;
    return 0;
}

/* ---- uniform grid of boxes, as (cell key, item) pairs sorted by key ---- */

typedef struct grid_entry {
    uint64_t key;
    int item;
} grid_entry;

typedef struct grid {
    int dim;
    double lo[3];  /* the grid's origin [m] */
    double h;      /* cell size [m] */
    int bits;      /* bits per axis in a key */
    long n;        /* entries */
    grid_entry *e; /* sorted by key */
} grid;

static long cell_of(const grid *g, double x, int k)
{
    double c = floor((x - g->lo[k]) / g->h);
    long lim = (1L << g->bits) - 1;
    return c < 0 ? 0 : c > (double)lim ? lim : (long)c;
}

static uint64_t key_of(const grid *g, const long *c)
{
    uint64_t k = 0;
    for (int d = 0; d < g->dim; d++)
        k = (k << g->bits) | (uint64_t)c[d];
    return k;
}

static int radix_sort(grid_entry *e, long n, int keybits)
{
    grid_entry *tmp = malloc((size_t)(n ? n : 1) * sizeof *tmp);
    if (!tmp)
        return -1;
    enum { B = 11 };
    size_t count[1 << B];
    grid_entry *src = e, *dst = tmp;
    for (int shift = 0; shift < keybits; shift += B) {
        memset(count, 0, sizeof count);
        for (long i = 0; i < n; i++)
            count[(src[i].key >> shift) & ((1u << B) - 1)]++;
        size_t s = 0;
        for (int b = 0; b < (1 << B); b++) {
            size_t c = count[b];
            count[b] = s;
            s += c;
        }
        for (long i = 0; i < n; i++)
            dst[count[(src[i].key >> shift) & ((1u << B) - 1)]++] = src[i];
        grid_entry *t = src;
        src = dst, dst = t;
    }
    if (src != e)
        memcpy(e, src, (size_t)n * sizeof *e);
    free(tmp);
    return 0;
}

/* Builds the grid over n boxes (box(item) -> lo[3], hi[3]); the cell is about `h` wide, made
 * larger where the entries would exceed 32 per box on average. 0, or -1 out of memory. */
static int grid_build(grid *g, int dim, long n, double h,
                      void (*box)(const void *, long, double *, double *), const void *ctx)
{
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (long i = 0; i < n; i++) {
        double a[3], b[3];
        box(ctx, i, a, b);
        for (int k = 0; k < dim; k++)
            lo[k] = fmin(lo[k], a[k]), hi[k] = fmax(hi[k], b[k]);
    }
    memset(g, 0, sizeof *g);
    g->dim = dim;
    g->bits = dim == 3 ? 21 : 31;
    double ext = 0;
    for (int k = 0; k < dim; k++)
        g->lo[k] = lo[k], ext = fmax(ext, hi[k] - lo[k]);
    double hmin = ext / (double)((1L << g->bits) - 2);
    g->h = fmax(h, hmin);
    if (!(g->h > 0))
        g->h = 1.0;
    for (;;) {
        double total = 0, most = 32.0 * (double)n + 64;
        for (long i = 0; i < n && total <= most; i++) {
            double a[3], b[3];
            box(ctx, i, a, b);
            double cells = 1;
            for (int k = 0; k < dim; k++)
                cells *= (double)(cell_of(g, b[k], k) - cell_of(g, a[k], k) + 1);
            total += cells;
        }
        if (total <= most) {
            g->n = (long)total;
            break;
        }
        g->h *= 2;
    }
    g->e = malloc((size_t)(g->n ? g->n : 1) * sizeof *g->e);
    if (!g->e)
        return -1;
    long w = 0;
    for (long i = 0; i < n; i++) {
        double a[3], b[3];
        long c0[3] = {0, 0, 0}, c1[3] = {0, 0, 0}, c[3];
        box(ctx, i, a, b);
        for (int k = 0; k < dim; k++)
            c0[k] = cell_of(g, a[k], k), c1[k] = cell_of(g, b[k], k);
        for (c[0] = c0[0]; c[0] <= c1[0]; c[0]++)
            for (c[1] = c0[1]; c[1] <= c1[1]; c[1]++)
                for (c[2] = c0[2]; c[2] <= c1[2]; c[2]++) {
                    g->e[w].key = key_of(g, c);
                    g->e[w].item = (int)i;
                    w++;
                }
    }
    if (radix_sort(g->e, g->n, dim * g->bits) != 0) {
        free(g->e);
        g->e = NULL;
        return -1;
    }
    return 0;
}

/* Whether the cell `key` holds the low corner of the overlap of boxes (a0, a1) and (b0, b1): the
 * one cell of the pair's shared cells where it is tested. */
static int owns_pair(const grid *g, uint64_t key, const double *a0, const double *b0)
{
    long c[3] = {0, 0, 0};
    for (int k = 0; k < g->dim; k++)
        c[k] = cell_of(g, fmax(a0[k], b0[k]), k);
    return key_of(g, c) == key;
}

/* ---- polygons ---- */

static double orient2(const double *a, const double *b, const double *c)
{
    return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}

static int sgn(double x)
{
    return (x > 0) - (x < 0);
}

/* c on the closed segment ab, given the three are collinear */
static int on_seg2(const double *a, const double *b, const double *c)
{
    return fmin(a[0], b[0]) <= c[0] && c[0] <= fmax(a[0], b[0]) && fmin(a[1], b[1]) <= c[1] &&
           c[1] <= fmax(a[1], b[1]);
}

/* Whether closed segments ab and cd meet; where (one point of it) in *at. */
static int seg_seg2(const double *a, const double *b, const double *c, const double *d, double *at)
{
    double o1 = orient2(a, b, c), o2 = orient2(a, b, d), o3 = orient2(c, d, a),
           o4 = orient2(c, d, b);
    int s1 = sgn(o1), s2 = sgn(o2), s3 = sgn(o3), s4 = sgn(o4);
    if (s1 * s2 < 0 && s3 * s4 < 0) {
        double t = o3 / (o3 - o4);
        at[0] = a[0] + t * (b[0] - a[0]);
        at[1] = a[1] + t * (b[1] - a[1]);
        return 1;
    }
    const double *p = NULL;
    if (s1 == 0 && on_seg2(a, b, c))
        p = c;
    else if (s2 == 0 && on_seg2(a, b, d))
        p = d;
    else if (s3 == 0 && on_seg2(c, d, a))
        p = a;
    else if (s4 == 0 && on_seg2(c, d, b))
        p = b;
    if (!p)
        return 0;
    at[0] = p[0], at[1] = p[1];
    return 1;
}

typedef struct poly_ctx {
    const double *v; /* 3 per point */
    long n;
} poly_ctx;

static void poly_box(const void *ctx, long i, double *lo, double *hi)
{
    const poly_ctx *p = ctx;
    const double *a = p->v + 3 * i, *b = p->v + 3 * ((i + 1) % p->n);
    for (int k = 0; k < 3; k++)
        lo[k] = fmin(a[k], b[k]), hi[k] = fmax(a[k], b[k]);
}

int sph_mesh_polygon(sph_mesh *m, const double *xy, long n, const char *path, sph_error *err)
{
    memset(m, 0, sizeof *m);
    if (n > SPH_POLYGON_MAX_POINTS)
        return sph_error_set(err, SPH_ERR_INVALID, path,
                             "polygon has %ld points, more than the limit of %ld", n,
                             SPH_POLYGON_MAX_POINTS);
    for (long i = 0; i < 2 * n; i++)
        if (!isfinite(xy[i]))
            return sph_error_set(err, SPH_ERR_INVALID, path,
                                 "polygon point %ld has a non-finite coordinate", i / 2);
    if (n >= 2 && xy[0] == xy[2 * (n - 1)] && xy[1] == xy[2 * (n - 1) + 1])
        n--; /* the closing point repeated */
    if (n < 3)
        return sph_error_set(err, SPH_ERR_INVALID, path,
                             "polygon has %ld distinct points: a closed polygon needs at least 3",
                             n < 0 ? 0 : n);
    for (long i = 0; i < n; i++) {
        long j = (i + 1) % n;
        if (xy[2 * i] == xy[2 * j] && xy[2 * i + 1] == xy[2 * j + 1])
            return sph_error_set(err, SPH_ERR_INVALID, path,
                                 "polygon points %ld and %ld are the same point (%g, %g): remove "
                                 "one of them",
                                 i, j, xy[2 * i], xy[2 * i + 1]);
    }
    double *v = calloc((size_t)n * 3, sizeof *v);
    int *t = malloc((size_t)n * 2 * sizeof *t);
    if (!v || !t) {
        free(v), free(t);
        return sph_error_set(err, SPH_ERR_NOMEM, path, "out of memory reading a polygon");
    }
    for (long i = 0; i < n; i++) {
        v[3 * i] = xy[2 * i], v[3 * i + 1] = xy[2 * i + 1];
        t[2 * i] = (int)i, t[2 * i + 1] = (int)((i + 1) % n);
    }
    /* sides i and i+1 folding back on each other (a spike of zero width) */
    for (long i = 0; i < n; i++) {
        const double *a = v + 3 * i, *b = v + 3 * ((i + 1) % n), *c = v + 3 * ((i + 2) % n);
        double d = (b[0] - a[0]) * (c[0] - b[0]) + (b[1] - a[1]) * (c[1] - b[1]);
        if (orient2(a, b, c) == 0 && d < 0) {
            int rc = sph_error_set(err, SPH_ERR_INVALID, path,
                                   "polygon sides %ld and %ld fold back on each other at point "
                                   "%ld (%g, %g): the polygon must not overlap itself",
                                   i, (i + 1) % n, (i + 1) % n, b[0], b[1]);
            free(v), free(t);
            return rc;
        }
    }
    /* non-adjacent sides crossing or touching, over a grid of about one side per cell */
    poly_ctx pc = {v, n};
    double len = 0;
    for (long i = 0; i < n; i++) {
        double lo[3], hi[3];
        poly_box(&pc, i, lo, hi);
        len += fmax(hi[0] - lo[0], hi[1] - lo[1]);
    }
    grid g;
    if (grid_build(&g, 2, n, len / (double)n, poly_box, &pc) != 0) {
        free(v), free(t);
        return sph_error_set(err, SPH_ERR_NOMEM, path, "out of memory checking a polygon");
    }
    long bi = -1, bj = -1;
    double at[2] = {0, 0};
    for (long s = 0; s < g.n;) {
        long e = s;
        while (e < g.n && g.e[e].key == g.e[s].key)
            e++;
        for (long p = s; p < e; p++)
            for (long q = p + 1; q < e; q++) {
                long i = g.e[p].item, j = g.e[q].item;
                if (i > j) {
                    long x = i;
                    i = j, j = x;
                }
                if (j == i + 1 || (i == 0 && j == n - 1))
                    continue; /* adjacent: they share a point */
                if (bi >= 0 && (i > bi || (i == bi && j >= bj)))
                    continue; /* the lowest pair is reported */
                double l0[3], h0[3], l1[3], h1[3], w[2];
                poly_box(&pc, i, l0, h0);
                poly_box(&pc, j, l1, h1);
                if (l0[0] > h1[0] || l1[0] > h0[0] || l0[1] > h1[1] || l1[1] > h0[1])
                    continue;
                if (!owns_pair(&g, g.e[s].key, l0, l1))
                    continue;
                if (seg_seg2(v + 3 * i, v + 3 * ((i + 1) % n), v + 3 * j, v + 3 * ((j + 1) % n), w))
                    bi = i, bj = j, at[0] = w[0], at[1] = w[1];
            }
        s = e;
    }
    free(g.e);
    if (bi >= 0) {
        free(v), free(t);
        return sph_error_set(err, SPH_ERR_INVALID, path,
                             "polygon sides %ld (points %ld-%ld) and %ld (points %ld-%ld) cross or "
                             "touch at (%g, %g): a polygon must not cross itself",
                             bi, bi, (bi + 1) % n, bj, bj, (bj + 1) % n, at[0], at[1]);
    }
    m->dim = 2;
    m->nv = n;
    m->v = v;
    m->nt = n;
    m->t = t;
    m->degenerate = 0;
    return 0;
}

/* ---- closed, manifold, oriented ---- */

typedef struct half_edge {
    int hi;  /* the larger vertex */
    int fwd; /* 1: lo -> hi in its triangle, 0: hi -> lo */
} half_edge;

static int cmp_half(const void *a, const void *b)
{
    const half_edge *x = a, *y = b;
    return (x->hi > y->hi) - (x->hi < y->hi);
}

static int check_edges(const sph_mesh *m, const char *path, sph_error *err)
{
    long nv = m->nv, nt = m->nt;
    long *start = calloc((size_t)nv + 1, sizeof *start);
    half_edge *he = malloc((size_t)(3 * nt) * sizeof *he);
    if (!start || !he) {
        free(start), free(he);
        return sph_error_set(err, SPH_ERR_NOMEM, path, "out of memory checking a mesh");
    }
    for (long i = 0; i < 3 * nt; i++) {
        int a = m->t[i], b = m->t[i % 3 == 2 ? i - 2 : i + 1];
        start[(a < b ? a : b) + 1]++;
    }
    for (long k = 0; k < nv; k++)
        start[k + 1] += start[k];
    for (long i = 0; i < 3 * nt; i++) {
        int a = m->t[i], b = m->t[i % 3 == 2 ? i - 2 : i + 1];
        int lo = a < b ? a : b;
        half_edge h = {a < b ? b : a, a < b};
        he[start[lo]++] = h;
    }
    for (long k = nv; k > 0; k--)
        start[k] = start[k - 1];
    start[0] = 0;
    long open = 0, nonman = 0, flipped = 0;
    int open_e[2] = {0, 0}, nonman_e[2] = {0, 0}, flip_e[2] = {0, 0};
    long nonman_n = 0;
    for (long k = 0; k < nv; k++) {
        half_edge *h = he + start[k];
        long c = start[k + 1] - start[k];
        qsort(h, (size_t)c, sizeof *h, cmp_half);
        for (long s = 0; s < c;) {
            long e = s, fwd = 0;
            while (e < c && h[e].hi == h[s].hi)
                fwd += h[e++].fwd;
            long uses = e - s;
            if (uses == 1) {
                if (open++ == 0)
                    open_e[0] = (int)k, open_e[1] = h[s].hi;
            } else if (uses > 2) {
                if (nonman++ == 0)
                    nonman_e[0] = (int)k, nonman_e[1] = h[s].hi, nonman_n = uses;
            } else if (fwd != 1) {
                if (flipped++ == 0)
                    flip_e[0] = (int)k, flip_e[1] = h[s].hi;
            }
            s = e;
        }
    }
    free(start), free(he);
    const double *v = m->v;
    if (open) {
        const double *a = v + 3 * open_e[0], *b = v + 3 * open_e[1];
        return sph_error_set(err, SPH_ERR_INVALID, path,
                             "mesh is not closed: %ld open edge%s, one from (%g, %g, %g) to (%g, "
                             "%g, %g): a surface with an inside needs every edge shared by two "
                             "triangles (fill the holes)",
                             open, open == 1 ? "" : "s", a[0], a[1], a[2], b[0], b[1], b[2]);
    }
    if (nonman) {
        const double *a = v + 3 * nonman_e[0], *b = v + 3 * nonman_e[1];
        return sph_error_set(err, SPH_ERR_INVALID, path,
                             "mesh is not manifold: %ld edge%s in more than two triangles, one "
                             "from (%g, %g, %g) to (%g, %g, %g) in %ld: separate the solids that "
                             "touch there",
                             nonman, nonman == 1 ? "" : "s", a[0], a[1], a[2], b[0], b[1], b[2],
                             nonman_n);
    }
    if (flipped) {
        const double *a = v + 3 * flip_e[0], *b = v + 3 * flip_e[1];
        return sph_error_set(err, SPH_ERR_INVALID, path,
                             "mesh is not consistently oriented: %ld edge%s used twice in the same "
                             "direction, one from (%g, %g, %g) to (%g, %g, %g): turn the faces "
                             "there over so that all wind the same way",
                             flipped, flipped == 1 ? "" : "s", a[0], a[1], a[2], b[0], b[1], b[2]);
    }
    return 0;
}

/* ---- self-intersection ---- */

static double orient3(const double *a, const double *b, const double *c, const double *d)
{
    double u[3], w[3], x[3], n[3];
    sub3(u, b, a);
    sub3(w, c, a);
    sub3(x, d, a);
    cross3(n, u, w);
    return dot3(n, x);
}

/* Signs of the points p[0..2] against the plane of triangle q, with values within a relative
 * 1e-12 taken as on it. */
static void plane_signs(const double *const *q, const double *const *p, int *s)
{
    double e0[3], e1[3], n[3], d[3], dist[3], far = 0;
    sub3(e0, q[1], q[0]);
    sub3(e1, q[2], q[0]);
    cross3(n, e0, e1);
    for (int i = 0; i < 3; i++) {
        sub3(d, p[i], q[0]);
        dist[i] = dot3(n, d);
        far = fmax(far, norm3(d));
    }
    far = fmax(far, fmax(norm3(e0), norm3(e1)));
    double eps = 1e-12 * norm3(n) * far;
    for (int i = 0; i < 3; i++)
        s[i] = dist[i] > eps ? 1 : dist[i] < -eps ? -1 : 0;
}

/* The line through p and q (which are on either side of triangle t's plane, or one on it) meets
 * the closed triangle t. */
static int line_meets_tri(const double *p, const double *q, const double *const *t)
{
    int s0 = sgn(orient3(p, q, t[0], t[1])), s1 = sgn(orient3(p, q, t[1], t[2])),
        s2 = sgn(orient3(p, q, t[2], t[0]));
    return (s0 >= 0 && s1 >= 0 && s2 >= 0) || (s0 <= 0 && s1 <= 0 && s2 <= 0);
}

/* Closed triangles a and b in one plane (normal n), in 2D. */
static int coplanar_meet(const double *const *a, const double *const *b, const double *n)
{
    int ax = fabs(n[0]) >= fabs(n[1]) && fabs(n[0]) >= fabs(n[2]) ? 0
             : fabs(n[1]) >= fabs(n[2])                           ? 1
                                                                  : 2;
    int i0 = ax == 0 ? 1 : 0, i1 = ax == 2 ? 1 : 2;
    double pa[3][2], pb[3][2], w[2];
    for (int i = 0; i < 3; i++) {
        pa[i][0] = a[i][i0], pa[i][1] = a[i][i1];
        pb[i][0] = b[i][i0], pb[i][1] = b[i][i1];
    }
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            if (seg_seg2(pa[i], pa[(i + 1) % 3], pb[j], pb[(j + 1) % 3], w))
                return 1;
    /* one inside the other */
    for (int k = 0; k < 2; k++) {
        double(*t)[2] = k ? pa : pb;
        const double *p = k ? pb[0] : pa[0];
        int s0 = sgn(orient2(t[0], t[1], p)), s1 = sgn(orient2(t[1], t[2], p)),
            s2 = sgn(orient2(t[2], t[0], p));
        if ((s0 >= 0 && s1 >= 0 && s2 >= 0) || (s0 <= 0 && s1 <= 0 && s2 <= 0))
            return 1;
    }
    return 0;
}

/* Whether closed triangles a and b (sharing no vertex) meet. */
static int tri_tri(const double *const *a, const double *const *b)
{
    int sa[3], sb[3]; /* a's vertices against b's plane, b's against a's */
    plane_signs(b, a, sa);
    if (sa[0] == sa[1] && sa[1] == sa[2] && sa[0] != 0)
        return 0;
    plane_signs(a, b, sb);
    if (sb[0] == sb[1] && sb[1] == sb[2] && sb[0] != 0)
        return 0;
    if ((sa[0] | sa[1] | sa[2]) == 0 || (sb[0] | sb[1] | sb[2]) == 0) {
        double e0[3], e1[3], n[3];
        sub3(e0, b[1], b[0]);
        sub3(e1, b[2], b[0]);
        cross3(n, e0, e1);
        return coplanar_meet(a, b, n);
    }
    for (int i = 0; i < 3; i++) {
        int j = (i + 1) % 3;
        if (sa[i] * sa[j] <= 0 && (sa[i] | sa[j]) != 0 && line_meets_tri(a[i], a[j], b))
            return 1;
        if (sb[i] * sb[j] <= 0 && (sb[i] | sb[j]) != 0 && line_meets_tri(b[i], b[j], a))
            return 1;
    }
    return 0;
}

static void tri_box(const void *ctx, long i, double *lo, double *hi)
{
    const sph_mesh *m = ctx;
    const int *t = m->t + 3 * i;
    for (int k = 0; k < 3; k++) {
        double x0 = m->v[3 * t[0] + k], x1 = m->v[3 * t[1] + k], x2 = m->v[3 * t[2] + k];
        lo[k] = fmin(x0, fmin(x1, x2));
        hi[k] = fmax(x0, fmax(x1, x2));
    }
}

static int check_crossings(const sph_mesh *m, const char *path, sph_error *err)
{
    long nt = m->nt;
    double size = 0;
    for (long i = 0; i < nt; i++) {
        double lo[3], hi[3];
        tri_box(m, i, lo, hi);
        size += fmax(hi[0] - lo[0], fmax(hi[1] - lo[1], hi[2] - lo[2]));
    }
    grid g;
    if (grid_build(&g, 3, nt, size / (double)nt, tri_box, m) != 0)
        return sph_error_set(err, SPH_ERR_NOMEM, path, "out of memory checking a mesh");
    long pairs = 0, fi = -1, fj = -1;
    double at[3] = {0, 0, 0};
    for (long s = 0; s < g.n;) {
        long e = s;
        while (e < g.n && g.e[e].key == g.e[s].key)
            e++;
        for (long p = s; p < e; p++) {
            long i = g.e[p].item;
            const int *ti = m->t + 3 * i;
            double li[3], hi_[3];
            tri_box(m, i, li, hi_);
            for (long q = p + 1; q < e; q++) {
                long j = g.e[q].item;
                const int *tj = m->t + 3 * j;
                double lj[3], hj[3];
                tri_box(m, j, lj, hj);
                if (li[0] > hj[0] || lj[0] > hi_[0] || li[1] > hj[1] || lj[1] > hi_[1] ||
                    li[2] > hj[2] || lj[2] > hi_[2])
                    continue;
                int shared = 0;
                for (int x = 0; x < 3; x++)
                    for (int y = 0; y < 3; y++)
                        shared |= ti[x] == tj[y];
                if (shared || !owns_pair(&g, g.e[s].key, li, lj))
                    continue;
                const double *a[3] = {m->v + 3 * ti[0], m->v + 3 * ti[1], m->v + 3 * ti[2]};
                const double *b[3] = {m->v + 3 * tj[0], m->v + 3 * tj[1], m->v + 3 * tj[2]};
                if (tri_tri(a, b)) {
                    if (pairs++ == 0 || (i < j ? i : j) < fi) {
                        fi = i < j ? i : j, fj = i < j ? j : i;
                        for (int k = 0; k < 3; k++)
                            at[k] = 0.5 * (fmax(li[k], lj[k]) + fmin(hi_[k], hj[k]));
                    }
                }
            }
        }
        s = e;
    }
    free(g.e);
    if (pairs)
        return sph_error_set(err, SPH_ERR_INVALID, path,
                             "mesh intersects itself: %ld pair%s of triangles cross or touch, "
                             "one is triangles %ld and %ld near (%g, %g, %g): separate or merge "
                             "the solids that overlap there",
                             pairs, pairs == 1 ? "" : "s", fi, fj, at[0], at[1], at[2]);
    return 0;
}

int sph_mesh_check_closed(const sph_mesh *m, const char *path, sph_error *err)
{
    if (!m || m->nt <= 0)
        return sph_error_set(err, SPH_ERR_INVALID, path, "mesh is empty");
    if (m->dim == 2)
        return 0;
    int rc = check_edges(m, path, err);
    if (rc == 0)
        rc = check_crossings(m, path, err);
    return rc;
}

/* ---- volume, orientation ---- */

double sph_mesh_volume(const sph_mesh *m)
{
    if (!m || m->nv <= 0)
        return 0;
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (long i = 0; i < m->nv; i++)
        for (int k = 0; k < 3; k++)
            lo[k] = fmin(lo[k], m->v[3 * i + k]), hi[k] = fmax(hi[k], m->v[3 * i + k]);
    double o[3]; /* the origin of the sum: the box's centre (fewer digits lost) */
    for (int k = 0; k < 3; k++)
        o[k] = 0.5 * (lo[k] + hi[k]);
    double s = 0;
    if (m->dim == 2) {
        for (long i = 0; i < m->nt; i++) {
            const double *a = m->v + 3 * m->t[2 * i], *b = m->v + 3 * m->t[2 * i + 1];
            s += (a[0] - o[0]) * (b[1] - o[1]) - (b[0] - o[0]) * (a[1] - o[1]);
        }
        return 0.5 * s;
    }
    for (long i = 0; i < m->nt; i++) {
        double a[3], b[3], c[3], n[3];
        sub3(a, m->v + 3 * m->t[3 * i], o);
        sub3(b, m->v + 3 * m->t[3 * i + 1], o);
        sub3(c, m->v + 3 * m->t[3 * i + 2], o);
        cross3(n, b, c);
        s += dot3(a, n);
    }
    return s / 6.0;
}

void sph_mesh_flip(sph_mesh *m)
{
    if (!m || !m->t)
        return;
    int per = m->dim == 2 ? 2 : 3;
    for (long i = 0; i < m->nt; i++) {
        int *t = m->t + per * i;
        int x = t[per - 2];
        t[per - 2] = t[per - 1];
        t[per - 1] = x;
    }
}

int sph_mesh_torus(sph_mesh *m, double R, double r, int nu, int nv)
{
    memset(m, 0, sizeof *m);
    m->dim = 3;
    m->nv = (long)nu * nv;
    m->nt = 2L * nu * nv;
    m->v = malloc(3 * (size_t)m->nv * sizeof *m->v);
    m->t = malloc(3 * (size_t)m->nt * sizeof *m->t);
    if (!m->v || !m->t) {
        sph_mesh_free(m);
        return SPH_ERR_NOMEM;
    }
    for (int i = 0; i < nu; i++)
        for (int j = 0; j < nv; j++) {
            const double u = 2.0 * M_PI * i / nu, w = 2.0 * M_PI * j / nv;
            double *p = m->v + 3 * (size_t)(i * nv + j);
            p[0] = (R + r * cos(w)) * cos(u);
            p[1] = (R + r * cos(w)) * sin(u);
            p[2] = r * sin(w);
        }
    long f = 0;
    for (int i = 0; i < nu; i++)
        for (int j = 0; j < nv; j++, f += 2) {
            const int a = i * nv + j, b = ((i + 1) % nu) * nv + j;
            const int c = ((i + 1) % nu) * nv + (j + 1) % nv, d = i * nv + (j + 1) % nv;
            int *t = m->t + 3 * (size_t)f;
            t[0] = a, t[1] = b, t[2] = c, t[3] = a, t[4] = c, t[5] = d;
        }
    if (sph_mesh_volume(m) < 0.0)
        sph_mesh_flip(m);
    return 0;
}
