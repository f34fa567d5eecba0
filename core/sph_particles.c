#include "sph_particles.h"

#include <stdlib.h>
#include <string.h>

/* Persistent double fields: follow their particle through reorderings. */
#define SPH_NPERSIST 8
#define SPH_NSPS     3

size_t sph_particles_bytes_per_particle(int sps)
{
    /* x y vx vy rho p pr ax ay drho ax0 ay0 drho0 scratch + SPS 6, type, id, cell key, perm */
    return (14 + (sps ? 6 : 0)) * sizeof(double) + 1 + sizeof(int) + sizeof(int) + sizeof(long);
}

int sph_particles_alloc(sph_particles *P, long n, int sps)
{
    memset(P, 0, sizeof *P);
    P->n = n;
    P->cap = n;
    const size_t nb = (size_t)(n > 0 ? n : 1) * sizeof(double);
    double **d[] = {&P->x,  &P->y,  &P->vx,   &P->vy,  &P->rho, &P->p,     &P->pr,
                    &P->ax, &P->ay, &P->drho, &P->ax0, &P->ay0, &P->drho0, &P->scratch};
    for (size_t i = 0; i < sizeof d / sizeof d[0]; i++)
        if (!(*d[i] = calloc(1, nb)))
            goto fail;
    if (sps) {
        double **s[] = {&P->gxx, &P->gxy, &P->gyy, &P->txx, &P->txy, &P->tyy};
        for (size_t i = 0; i < sizeof s / sizeof s[0]; i++)
            if (!(*s[i] = calloc(1, nb)))
                goto fail;
    }
    P->type = calloc((size_t)(n > 0 ? n : 1), 1);
    P->id = calloc((size_t)(n > 0 ? n : 1), sizeof(int));
    if (!P->type || !P->id)
        goto fail;
    return 0;
fail:
    sph_particles_free(P);
    return -1;
}

void sph_particles_free(sph_particles *P)
{
    double *d[] = {P->x,   P->y,   P->vx,   P->vy,  P->rho, P->p,     P->pr,
                   P->ax,  P->ay,  P->drho, P->ax0, P->ay0, P->drho0, P->scratch,
                   P->gxx, P->gxy, P->gyy,  P->txx, P->txy, P->tyy};
    for (size_t i = 0; i < sizeof d / sizeof d[0]; i++)
        free(d[i]);
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
    double **d[] = {&P->x,   &P->y,   &P->vx,   &P->vy,  &P->rho, &P->p,     &P->pr,
                    &P->ax,  &P->ay,  &P->drho, &P->ax0, &P->ay0, &P->drho0, &P->scratch,
                    &P->gxx, &P->gxy, &P->gyy,  &P->txx, &P->txy, &P->tyy};
    for (size_t i = 0; i < sizeof d / sizeof d[0]; i++)
        if (*d[i] && grow((void **)d[i], sizeof(double), old, cap))
            return -1;
    if (grow((void **)&P->type, 1, old, cap) || grow((void **)&P->id, sizeof(int), old, cap))
        return -1;
    P->cap = cap;
    return 0;
}

/* *a = old[perm]: gathered into the scratch array, which then takes the field's place. */
static void permute_doubles(double **a, double **scratch, const long *perm, long n)
{
    const double *src = *a;
    double *dst = *scratch;
#pragma omp parallel for schedule(dynamic, SPH_OMP_CHUNK) if (n >= SPH_OMP_MIN)
    for (long i = 0; i < n; i++)
        dst[i] = src[perm[i]];
    *scratch = *a;
    *a = dst;
}

void sph_particles_permute(sph_particles *P, const long *perm)
{
    const long n = P->n;
    double **d[] = {&P->x, &P->y, &P->vx, &P->vy, &P->rho, &P->ax0, &P->ay0, &P->drho0};
    for (int f = 0; f < SPH_NPERSIST; f++)
        permute_doubles(d[f], &P->scratch, perm, n);
    if (P->gxx) {
        double **s[] = {&P->gxx, &P->gxy, &P->gyy};
        for (int f = 0; f < SPH_NSPS; f++)
            permute_doubles(s[f], &P->scratch, perm, n);
    }
    /* the 1- and 4-byte fields go through the scratch buffer too (it holds n doubles) */
    unsigned char *t = (unsigned char *)P->scratch;
    int *id = (int *)(t + ((n + 7) / 8) * 8); /* n bytes, then n ints: fits in n doubles */
#pragma omp parallel for schedule(dynamic, SPH_OMP_CHUNK) if (n >= SPH_OMP_MIN)
    for (long i = 0; i < n; i++) {
        t[i] = P->type[perm[i]];
        id[i] = P->id[perm[i]];
    }
    memcpy(P->type, t, (size_t)n);
    memcpy(P->id, id, (size_t)n * sizeof(int));
}

long sph_particles_remove(sph_particles *P, unsigned char type, long *perm)
{
    const long n = P->n;
    long k = 0;
    for (long i = 0; i < n; i++)
        if (P->type[i] != type)
            perm[k++] = i;
    const long kept = k;
    if (kept == n)
        return n;
    for (long i = 0; i < n; i++)
        if (P->type[i] == type)
            perm[k++] = i;
    sph_particles_permute(P, perm);
    double **r[] = {&P->ax, &P->ay, &P->drho};
    for (int f = 0; f < 3; f++)
        permute_doubles(r[f], &P->scratch, perm, n);
    P->n = kept;
    return kept;
}
