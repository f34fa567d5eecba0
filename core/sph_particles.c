#include "sph_particles.h"

#include <omp.h>

#include <stdlib.h>
#include <string.h>

/* The arrays of P that hold a hot field in double or, under mixed precision, in float (one of
 * each pair is allocated): every set's (HOT2), the third axis's (HOT3: 3D only), the pressure
 * (PRES: only for a method that solves for it, SPH_PARTICLES_PRESSURE); and those that are always
 * double: every set's (D2), the third axis's (D3), the SPS tensors' (SPS2, and SPS3 in 3D). NULL
 * where absent. */
#define HOT2(P, T)                                                                                 \
    &(P)->T vx, &(P)->T vy, &(P)->T rho, &(P)->T pr, &(P)->T ax, &(P)->T ay, &(P)->T drho,         \
        &(P)->T ax0, &(P)->T ay0, &(P)->T drho0
#define HOT3(P, T) &(P)->T vz, &(P)->T az, &(P)->T az0
#define PRES(P, T) &(P)->T p
#define D2(P)      &(P)->x, &(P)->y, &(P)->scratch
#define D3(P)      &(P)->z
#define SPS2(P)    &(P)->gxx, &(P)->gxy, &(P)->gyy, &(P)->txx, &(P)->txy, &(P)->tyy
#define SPS3(P)    &(P)->gzz, &(P)->gxz, &(P)->gyz, &(P)->tzz, &(P)->txz, &(P)->tyz
#define N_HOT2     10
#define N_HOT3     3
#define N_PRES     1
#define N_D2       3
#define N_D3       1
#define N_SPS2     6
#define N_SPS3     6
#define N_GROUPS   7
#define N_DOUBLE   (N_HOT2 + N_HOT3 + N_PRES + N_D2 + N_D3 + N_SPS2 + N_SPS3)
#define N_FLOAT    (N_HOT2 + N_HOT3 + N_PRES)

size_t sph_particles_bytes_per_particle(int dim, unsigned opts)
{
    const int sps = !!(opts & SPH_PARTICLES_SPS), mixed = !!(opts & SPH_PARTICLES_MIXED);
    const size_t nhot = N_HOT2 + (dim == 3 ? N_HOT3 : 0) + (opts & SPH_PARTICLES_PRESSURE ? 1 : 0);
    const size_t nd = N_D2 + (dim == 3 ? N_D3 : 0) + (sps ? N_SPS2 + (dim == 3 ? N_SPS3 : 0) : 0);
    /* the arrays (the scratch array among them, which also holds the sort's cell keys and
     * outlier lists: sph_cells_sort), type, id, the sort's permutation */
    return nd * sizeof(double) + nhot * (mixed ? sizeof(float) : sizeof(double)) + 1 + sizeof(int) +
           sizeof(int);
}

/* Every double array's address in P (d, N_DOUBLE) and every float array's (f, N_FLOAT), the
 * absent ones included (their pointers stay NULL). */
static void all_fields(sph_particles *P, double ***d, float ***f)
{
    double **ad[] = {HOT2(P, ), HOT3(P, ), PRES(P, ), D2(P), D3(P), SPS2(P), SPS3(P)};
    float **af[] = {HOT2(P, f32.), HOT3(P, f32.), PRES(P, f32.)};
    memcpy(d, ad, sizeof ad);
    memcpy(f, af, sizeof af);
}

int sph_particles_alloc(sph_particles *P, long n, int dim, unsigned opts)
{
    memset(P, 0, sizeof *P);
    P->n = n;
    P->cap = n;
    P->dim = dim;
    P->mixed = !!(opts & SPH_PARTICLES_MIXED);
    const int sps = !!(opts & SPH_PARTICLES_SPS), pres = !!(opts & SPH_PARTICLES_PRESSURE);
    const size_t nn = (size_t)(n > 0 ? n : 1);
    double **d[N_DOUBLE];
    float **f[N_FLOAT];
    all_fields(P, d, f);
    /* which of them this set has, in all_fields' order: the hot fields in double or in float */
    const int dd = !P->mixed, ff = P->mixed;
    const int have[N_GROUPS] = {dd ? N_HOT2 : 0,
                                dd && dim == 3 ? N_HOT3 : 0,
                                dd && pres ? N_PRES : 0,
                                N_D2,
                                dim == 3 ? N_D3 : 0,
                                sps ? N_SPS2 : 0,
                                sps && dim == 3 ? N_SPS3 : 0};
    const int group[N_GROUPS] = {N_HOT2, N_HOT3, N_PRES, N_D2, N_D3, N_SPS2, N_SPS3};
    for (int g = 0, k = 0; g < N_GROUPS; k += group[g], g++)
        for (int i = 0; i < have[g]; i++)
            if (!(*d[k + i] = calloc(nn, sizeof(double))))
                goto fail;
    const int fhave[3] = {ff ? N_HOT2 : 0, ff && dim == 3 ? N_HOT3 : 0, ff && pres ? N_PRES : 0};
    for (int g = 0, k = 0; g < 3; k += group[g], g++)
        for (int i = 0; i < fhave[g]; i++)
            if (!(*f[k + i] = calloc(nn, sizeof(float))))
                goto fail;
    P->type = calloc(nn, 1);
    P->id = calloc(nn, sizeof(int));
    if (!P->type || !P->id)
        goto fail;
    return 0;
fail:
    sph_particles_free(P);
    return -1;
}

void sph_particles_free(sph_particles *P)
{
    double **d[N_DOUBLE];
    float **f[N_FLOAT];
    all_fields(P, d, f);
    for (int i = 0; i < N_DOUBLE; i++)
        free(*d[i]);
    for (int i = 0; i < N_FLOAT; i++)
        free(*f[i]);
    free(P->type);
    free(P->id);
    memset(P, 0, sizeof *P);
}

/* Grows *a from `old` to `cap` elements of `size` bytes, zeroing the new ones. */
static int grow(void **a, size_t size, long old, long cap)
{
    void *b = realloc(*a, (size_t)cap * size);
    if (!b)
        return -1;
    memset((char *)b + (size_t)old * size, 0, (size_t)(cap - old) * size);
    *a = b;
    return 0;
}

int sph_particles_reserve(sph_particles *P, long cap)
{
    const long old = P->cap > 0 ? P->cap : 1;
    if (cap <= old)
        return 0;
    double **d[N_DOUBLE];
    float **f[N_FLOAT];
    all_fields(P, d, f);
    for (int i = 0; i < N_DOUBLE; i++)
        if (*d[i] && grow((void **)d[i], sizeof(double), old, cap))
            return -1;
    for (int i = 0; i < N_FLOAT; i++)
        if (*f[i] && grow((void **)f[i], sizeof(float), old, cap))
            return -1;
    if (grow((void **)&P->type, 1, old, cap) || grow((void **)&P->id, sizeof(int), old, cap))
        return -1;
    P->cap = cap;
    return 0;
}

/* Threads of sph_particles_remove's partition at most. */
#define SPH_REMOVE_THREADS 64

/* The most fields one permutation moves (sph_particles_permute's doubles). */
#define SPH_PERMUTE_FIELDS 17

/* Each field *a[f] (those not NULL, nf at most SPH_PERMUTE_FIELDS) = old[perm], all in one
 * parallel region: the first field gathered into *scratch (n free elements of the same type),
 * each next one into the array the field before it left, and *scratch ends as the last one's
 * old array; so one spare array serves them all. Each loop's barrier keeps a thread from
 * writing an array another still reads. permute_doubles goes through the scratch array,
 * permute_floats (mixed precision) through the force loop's p / rho^2 (see
 * sph_particles_permute). The static split: each thread writes the same range in every field. */
/* clang-format off */
#define SPH_PERMUTE_FN(name, T)                                                                    \
    static void name(T **a[], size_t nf, T **scratch, const int *perm, long n)                     \
    {                                                                                              \
        T *src[SPH_PERMUTE_FIELDS], *dst[SPH_PERMUTE_FIELDS], *buf = *scratch;                     \
        T **to[SPH_PERMUTE_FIELDS];                                                                \
        int k = 0;                                                                                 \
        for (size_t f = 0; f < nf; f++)                                                            \
            if (*a[f]) {                                                                           \
                to[k] = a[f];                                                                      \
                src[k] = *a[f];                                                                    \
                dst[k] = buf;                                                                      \
                buf = src[k++];                                                                    \
            }                                                                                      \
        _Pragma("omp parallel if (n >= SPH_OMP_MIN)")                                              \
        for (int f = 0; f < k; f++) {                                                              \
            const T *restrict from = src[f];                                                       \
            T *restrict into = dst[f];                                                             \
            _Pragma("omp for schedule(static)")                                                    \
            for (long i = 0; i < n; i++)                                                           \
                into[i] = from[perm[i]];                                                           \
        }                                                                                          \
        for (int f = 0; f < k; f++)                                                                \
            *to[f] = dst[f];                                                                       \
        *scratch = buf;                                                                            \
    }
/* clang-format on */
SPH_PERMUTE_FN(permute_doubles, double)
SPH_PERMUTE_FN(permute_floats, float)

void sph_particles_permute(sph_particles *P, const int *perm)
{
    const long n = P->n;
    /* the persistent fields: the state and the previous rates (the SPS velocity gradients of
     * the latest evaluation too: the next one's stresses come from them) */
    double **d[] = {&P->x,   &P->y,   &P->vx, &P->vy, &P->rho, &P->ax0, &P->ay0, &P->drho0, &P->gxx,
                    &P->gxy, &P->gyy, &P->z,  &P->vz, &P->az0, &P->gzz, &P->gxz, &P->gyz};
    _Static_assert(sizeof d / sizeof d[0] <= SPH_PERMUTE_FIELDS, "SPH_PERMUTE_FIELDS too small");
    permute_doubles(d, sizeof d / sizeof d[0], &P->scratch, perm, n);
    /* mixed precision's float fields swap places with p / rho^2, which holds nothing between
     * two force evaluations (their prepare computes it, their pair loop alone reads it) */
    float **fl[] = {&P->f32.vx,  &P->f32.vy,    &P->f32.rho, &P->f32.ax0,
                    &P->f32.ay0, &P->f32.drho0, &P->f32.vz,  &P->f32.az0};
    _Static_assert(sizeof fl / sizeof fl[0] <= SPH_PERMUTE_FIELDS, "SPH_PERMUTE_FIELDS too small");
    permute_floats(fl, sizeof fl / sizeof fl[0], &P->f32.pr, perm, n);
    /* the 1- and 4-byte fields go through the scratch buffer too (it holds n doubles); read
     * through restrict locals, since a char store may alias anything, P included */
    unsigned char *restrict t = (unsigned char *)P->scratch;
    int *restrict id = (int *)(P->scratch + (n + 7) / 8); /* n bytes, then n ints */
    unsigned char *restrict type = P->type;
    int *restrict pid = P->id;
#pragma omp parallel if (n >= SPH_OMP_MIN)
    {
#pragma omp for schedule(dynamic, SPH_OMP_CHUNK)
        for (long i = 0; i < n; i++) {
            t[i] = type[perm[i]];
            id[i] = pid[perm[i]];
        }
        /* (the loop's barrier: every old value read) copied back in parallel too */
#pragma omp for schedule(static)
        for (long i = 0; i < n; i++) {
            type[i] = t[i];
            pid[i] = id[i];
        }
    }
}

long sph_particles_remove(sph_particles *P, unsigned char type, int *perm)
{
    const long n = P->n;
    const unsigned char *ty = P->type; /* (not restrict: permuted below) */
    /* a stable partition in parallel: each thread counts the particles its chunk keeps, then
     * lists its chunk's kept ones after those of the chunks before it, and its removed ones
     * after every kept one and the removed ones of the chunks before it */
    int nt = n >= 2 * SPH_OMP_MIN ? omp_get_max_threads() : 1;
    nt = nt < SPH_REMOVE_THREADS ? nt : SPH_REMOVE_THREADS;
    long count[SPH_REMOVE_THREADS + 1];
    long kept = 0;
#pragma omp parallel num_threads(nt)
    {
        const int t = omp_get_thread_num(), m = omp_get_num_threads();
        const long lo = n * t / m, hi = n * (t + 1) / m;
        long c = 0;
        for (long i = lo; i < hi; i++)
            c += ty[i] != type;
        count[t] = c;
#pragma omp barrier
#pragma omp single
        {
            long sum = 0;
            for (int u = 0; u < m; u++) {
                const long cu = count[u];
                count[u] = sum;
                sum += cu;
            }
            kept = sum;
        } /* (a barrier) */
        if (kept < n) {
            long k = count[t], r = kept + (lo - count[t]);
            for (long i = lo; i < hi; i++) {
                if (ty[i] != type)
                    perm[k++] = (int)i;
                else
                    perm[r++] = (int)i;
            }
        }
    }
    if (kept == n)
        return n;
    sph_particles_permute(P, perm);
    double **r[] = {&P->ax, &P->ay, &P->drho, &P->az};
    permute_doubles(r, sizeof r / sizeof r[0], &P->scratch, perm, n);
    float **rf[] = {&P->f32.ax, &P->f32.ay, &P->f32.drho, &P->f32.az};
    permute_floats(rf, sizeof rf / sizeof rf[0], &P->f32.pr, perm, n);
    P->n = kept;
    return kept;
}
