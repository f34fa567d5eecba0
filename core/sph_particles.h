/*
 * sph_particles: particle storage as structure of arrays, in 2D or 3D. Hot fields (what the pair
 * loops read and write) are separate arrays of doubles; every per-particle array that must follow
 * a particle when the particles are reordered by cell is listed in sph_particles_permute(). The
 * third axis's arrays (z, vz, az, az0 and the SPS tensors' z components) exist in 3D only: in 2D
 * they are NULL, so 2D pays no memory for them.
 *
 * The pressure p is stored only for a method that solves for it (SPH_PARTICLES_PRESSURE: MPS);
 * WCSPH derives it from the density by the EOS where it is read (P->p and P->f32.p NULL).
 *
 * Mixed precision (SPH_PARTICLES_MIXED, the case's "precision": "mixed"): the positions stay in
 * double and the other hot fields (velocity, density, p / rho^2, the rates and the previous
 * rates; the pressure where it is stored) are stored in float, in P->f32; their double pointers are
 * then NULL. Every reader goes through SPH_GET / SPH_SET, whose M (mixed) is a compile-time
 * constant in the hot loops and P->mixed elsewhere; the arithmetic stays in double, only the
 * storage is narrowed.
 */
#ifndef SPH_PARTICLES_H
#define SPH_PARTICLES_H

#include <stddef.h>

/* Particle kinds (the `type` array). */
enum {
    SPH_FLUID = 0,    /* moves, feels forces */
    SPH_BOUNDARY = 1, /* dynamic boundary particle: fixed, density by continuity */
    SPH_LOST = 2,     /* fluid that left the domain: frozen, excluded from interactions */
    SPH_GHOST = 3,    /* mirror of a fluid particle behind a free-slip wall: rebuilt for every
                         force evaluation, never integrated, never in outputs or diagnostics */
    SPH_BODY = 4      /* particle of a rigid body (boundary/sph_body.h): moves with its body,
                         density by continuity */
};

/* Loops over fewer particles than this run on the calling thread alone: for small jobs the
 * threads' fork and join costs more than it saves, and when the machine is oversubscribed
 * (several jobs, each with its threads) waiting threads make it far worse. */
#define SPH_OMP_MIN 4096
/* Particles per chunk of the parallel loops: handed out dynamically, so that a thread the
 * operating system has put aside (other jobs, other programs) does not hold up its team. */
#define SPH_OMP_CHUNK 2048

typedef struct sph_particles {
    long n;                  /* particles stored (fluid + boundary, lost included; ghosts only
                                inside a force evaluation) */
    long cap;                /* particles the arrays can hold (>= n) */
    int dim;                 /* 2 or 3 */
    double *x, *y, *z;       /* position [m] (z: 3D only) */
    double *vx, *vy, *vz;    /* velocity [m/s] */
    double *rho;             /* density [kg/m^3] */
    double *p;               /* pressure [Pa] (SPH_PARTICLES_PRESSURE only: else NULL) */
    double *pr;              /* p / rho^2, scratch of the force loop [m^5/(kg s^2)] */
    double *ax, *ay, *az;    /* acceleration of the latest force evaluation [m/s^2] */
    double *drho;            /* density rate of the latest force evaluation [kg/(m^3 s)] */
    double *ax0, *ay0, *az0; /* acceleration of the previous evaluation [m/s^2] */
    double *drho0;           /* density rate of the previous evaluation [kg/(m^3 s)] */
    double *gxx, *gxy, *gyy; /* SPS: du/dx, du/dy + dv/dx, dv/dy [1/s] (NULL without SPS) */
    double *gzz, *gxz, *gyz; /* SPS in 3D: dw/dz, du/dz + dw/dx, dv/dz + dw/dy [1/s] */
    double *txx, *txy, *tyy; /* SPS: sub-particle stress / rho, Yang et al. eq. (7) [m^2/s^2] */
    double *tzz, *txz, *tyz; /* SPS in 3D: its z components [m^2/s^2] */
    unsigned char *type;     /* SPH_FLUID, SPH_BOUNDARY, SPH_LOST */
    int *id;                 /* creation index, stable across reorderings [-] */
    double *scratch;         /* n doubles for permutations */
    int mixed;               /* 1: the fields of f32 in float, their double pointers NULL */
    struct {
        float *vx, *vy, *vz, *rho, *p, *pr, *ax, *ay, *az, *drho, *ax0, *ay0, *az0, *drho0;
    } f32; /* mixed precision's storage of those fields (NULL in double) */
} sph_particles;

/* sph_particles_alloc's options. */
enum {
    SPH_PARTICLES_SPS = 1,     /* the SPS tensors (double only) */
    SPH_PARTICLES_MIXED = 2,   /* mixed precision: P->f32 instead of the double hot fields */
    SPH_PARTICLES_PRESSURE = 4 /* the pressure p stored (a method that solves for it) */
};

/* Field f (vx ... drho0) of particle i as a double, and a store to it (rounded to float under
 * mixed precision). M: 1 for mixed; a compile-time constant in the hot loops. */
#define SPH_GET(M, P, f, i)    ((M) ? (double)(P)->f32.f[i] : (P)->f[i])
#define SPH_SET(M, P, f, i, v) ((M) ? (void)((P)->f32.f[i] = (float)(v)) : (void)((P)->f[i] = (v)))

/* Bytes per particle the storage needs in dim dimensions with the options (SPH_PARTICLES_*). */
size_t sph_particles_bytes_per_particle(int dim, unsigned opts);

/* Allocates n particles (zeroed) in dim (2 or 3) dimensions with the options (SPH_PARTICLES_SPS,
 * SPH_PARTICLES_MIXED). Returns 0 or -1 when out of memory (then frees what it got). */
int sph_particles_alloc(sph_particles *P, long n, int dim, unsigned opts);
void sph_particles_free(sph_particles *P);

/* Makes room for cap particles (n unchanged, the new room zeroed). Returns 0 or -1 when out of
 * memory (then P is unchanged). */
int sph_particles_reserve(sph_particles *P, long cap);

/* Removes every particle of kind `type`, keeping the order of the others: the persistent fields
 * and the rates of the latest evaluation (ax, ay, az, drho) follow their particles. perm: P->n
 * ints of scratch. Returns the new P->n. */
long sph_particles_remove(sph_particles *P, unsigned char type, int *perm);

/* Reorders every persistent field by perm: new[i] = old[perm[i]]. The field arrays are swapped
 * with the scratch array (under mixed precision the float ones with f32.pr, p / rho^2, which
 * must hold nothing then: it is the force loop's scratch), so their addresses change. */
void sph_particles_permute(sph_particles *P, const int *perm);

#endif
