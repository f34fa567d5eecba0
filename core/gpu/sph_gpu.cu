/*
 * sph_gpu.cu: the WCSPH step on the GPU (sph_gpu.h says what it does). Scheduling only: every
 * per-particle and per-pair formula is an SPH_HD function of the C build's headers. One thread
 * per particle; the pair loop is the gather form (gather_one), so no two threads write the same
 * particle and no atomics touch the physics; the sort by cell is CUB's stable radix sort, so a
 * run is the same from one launch to the next.
 * First run on a GPU (an H100, 2026-11-28): every test of scripts/test-gpu.sh passed (the CPU
 * and the GPU agree within 1e-15 m after 100 steps).
 * Second lease (an H200, 2026-11-28): the sort by z within each cell (the pair loop's columns
 * cut in z), the sort's scratch from CUB's double buffers and the free rate arrays (179 -> 159
 * device bytes a particle in 3D), the pair loop folded per option set in blocks of 128: every
 * test passed; 200 M particle-steps/s on DualSPHysics' case at 1M (from 55 M).
 * TODO(issue 26): DualSPHysics runs that case at 255 M: the pair physics in float (it computes in
 * float; issue 24's mixed precision on the CPU) is the next step.
 */
#include <cub/cub.cuh>
#include <cuda_runtime.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>

extern "C" {
#include "sph_gpu.h"
}
#include "sph_wcsph_loop.h"
#include "sph_wcsph_particle.h"

namespace
{

constexpr int BS = 256; /* threads per block */

/* A step's reductions, on the device. */
struct red {
    unsigned long long bad_p, bad_c, pairs;
    double vmax2, amax2, rlo, rhi;
};

struct dmax {
    __device__ double operator()(double a, double b) const { return a > b ? a : b; }
};
struct dmin {
    __device__ double operator()(double a, double b) const { return a < b ? a : b; }
};

__device__ void atomic_max_d(double *a, double v)
{
    unsigned long long *p = reinterpret_cast<unsigned long long *>(a), old = *p;
    while (v > __longlong_as_double((long long)old)) {
        const unsigned long long was = old;
        old = atomicCAS(p, was, (unsigned long long)__double_as_longlong(v));
        if (old == was)
            break;
    }
}

__device__ void atomic_min_d(double *a, double v)
{
    unsigned long long *p = reinterpret_cast<unsigned long long *>(a), old = *p;
    while (v < __longlong_as_double((long long)old)) {
        const unsigned long long was = old;
        old = atomicCAS(p, was, (unsigned long long)__double_as_longlong(v));
        if (old == was)
            break;
    }
}

typedef cub::BlockReduce<double, BS> reduce_d;
typedef cub::BlockReduce<unsigned long long, BS> reduce_u;

__global__ void k_reset(red *r)
{
    r->bad_p = r->bad_c = r->pairs = 0;
    r->vmax2 = r->amax2 = 0.0;
    r->rlo = INFINITY;
    r->rhi = -INFINITY;
}

template <int D> __global__ void k_predict(sph_particles P, step_ctx k, double dt, long n, red *r)
{
    __shared__ typename reduce_u::TempStorage tmp;
    const long i = (long)blockIdx.x * BS + threadIdx.x;
    k.P = &P;
    unsigned long long bad = 0;
    if (i < n)
        bad = (unsigned long long)predict_one(D, 0, &k, dt, i);
    const unsigned long long b = reduce_u(tmp).Sum(bad);
    if (threadIdx.x == 0 && b)
        atomicAdd(&r->bad_p, b);
}

template <int D> __global__ void k_keys(sph_particles P, sph_cells grid, int *key, int *idx, long n)
{
    const long i = (long)blockIdx.x * BS + threadIdx.x;
    if (i < n) {
        key[i] = sph_cells_key(D, &grid, &P, i);
        idx[i] = (int)i;
    }
}

template <typename T> __global__ void k_permute(const T *src, T *dst, const int *perm, long n)
{
    const long i = (long)blockIdx.x * BS + threadIdx.x;
    if (i < n)
        dst[i] = src[perm[i]];
}

/* 3D: z in the order of the cell sort (zc[k] = z[perm[k]]) and the identity (iota), the keys
 * and values of the sort by z within each cell. The lost particles, from *nact on (the start of
 * the lost's segment), all get the same key: they stay in the cell sort's order, as on the CPU
 * (sph_cells_sort sorts the cells' particles only). */
__global__ void k_zsort_in(const double *z, const int *perm, const int *nact, double *zc, int *iota,
                           long n)
{
    const long k = (long)blockIdx.x * BS + threadIdx.x;
    if (k < n) {
        zc[k] = k < *nact ? z[perm[k]] : 0.0;
        iota[k] = (int)k;
    }
}

/* out[k] = perm[within[k]]: the sort by cell, then by z within each cell, as one permutation */
__global__ void k_compose(const int *perm, const int *within, int *out, long n)
{
    const long k = (long)blockIdx.x * BS + threadIdx.x;
    if (k < n)
        out[k] = perm[within[k]];
}

/* start[c] = the first sorted particle of a cell >= c, for c in [0, ncells + 1]: each particle
 * fills the starts of the cells from the one after its predecessor's up to its own. */
__global__ void k_starts(const int *key, int *start, long n, long ncells)
{
    const long k = (long)blockIdx.x * BS + threadIdx.x;
    if (k > n)
        return;
    const long cur = k < n ? key[k] : ncells + 1;
    const long prev = k > 0 ? key[k - 1] : -1;
    for (long c = prev + 1; c <= cur; c++)
        start[c] = (int)k;
}

template <int D>
__global__ void k_prepare(const sph_config *cfg, sph_particles P, double smag, double blin, long n)
{
    const long i = (long)blockIdx.x * BS + threadIdx.x;
    if (i < n)
        prepare_one(D, 0, cfg, &P, smag, blin, i);
}

/* The F of k_forces whose options are read at run time (c.flags). */
constexpr unsigned F_RUNTIME = ~0u;

/* The pair loop, a thread a particle (gather_one), for kernel T in D dimensions with the options
 * F (SPH_WF_ flags) folded at compile time, or read at run time with F_RUNTIME, in blocks of FBS
 * threads of which the register budget leaves room for at least MINB on a multiprocessor. The
 * folded loops read the kernel's constants from shared memory.
 * Timed on an H200 (2026-11-28, double, 100 steps, DualSPHysics' case at 1M particles; median of
 * 3-5): the run-time options' loop in blocks of 256 gave 55 M particle-steps/s (H100), the
 * folded one 158 M, with the columns cut in z (gather_one) 167 M, and in blocks of 128 with
 * room for 8 (at most 64 registers; 6 or blocks of 64 for 12 did as well, 256 for 3 a little
 * less) 198-202 M. A float prefilter of the candidates' distance (float4 positions) was
 * slower. */
template <sph_kernel_type T, int D, unsigned F, int FBS, int MINB>
__global__ void __launch_bounds__(FBS, MINB) k_forces(fctx c, long n, red *r)
{
    typedef cub::BlockReduce<unsigned long long, FBS> reduce_f;
    __shared__ typename reduce_f::TempStorage tmp;
    __shared__ sph_kernel kern;
    const long i = (long)blockIdx.x * FBS + threadIdx.x;
    unsigned long long pairs = 0;
    if constexpr (F == F_RUNTIME) {
        if (i < n)
            pairs = (unsigned long long)gather_one(T, c.flags, D, &c, i);
    } else {
        if (threadIdx.x == 0)
            kern = *c.k;
        __syncthreads();
        fctx cl = c;
        cl.k = &kern;
        if (i < n)
            pairs = (unsigned long long)gather_one(T, F, D, &cl, i);
    }
    const unsigned long long s = reduce_f(tmp).Sum(pairs);
    if (threadIdx.x == 0)
        atomicAdd(&r->pairs, s);
}

template <int D>
__global__ void k_gravity(sph_particles P, double gx, double gy, double gz, long nactive, long n,
                          red *r)
{
    __shared__ typename reduce_d::TempStorage tmp;
    const long i = (long)blockIdx.x * BS + threadIdx.x;
    const double g[3] = {gx, gy, gz};
    double a2 = 0.0;
    if (i < nactive) {
        a2 = gravity_one(D, 0, g, &P, i);
    } else if (i < n) { /* as the C loop: the lost particles' rates zeroed */
        P.ax[i] = P.ay[i] = P.drho[i] = 0.0;
        if (D == 3)
            P.az[i] = 0.0;
    }
    const double m = reduce_d(tmp).Reduce(a2, dmax());
    if (threadIdx.x == 0)
        atomic_max_d(&r->amax2, m);
}

/* A wavemaker's paddle at the displacement X and rate v (sph_wavemaker.h), and a damping zone:
 * a thread a particle, the C loops' functions. */
__global__ void k_paddle(sph_particles P, sph_paddle_law law, const double *rest, long first,
                         long np, double X, double v, long n)
{
    const long i = (long)blockIdx.x * BS + threadIdx.x;
    if (i < n)
        sph_paddle_particle(&law, rest, first, np, &P, 0, i, X, v);
}

__global__ void k_damp(sph_particles P, double dt, double beta, double from, double to, long n)
{
    const long i = (long)blockIdx.x * BS + threadIdx.x;
    if (i < n)
        sph_damping_particle(&P, 0, i, dt, beta, from, to);
}

template <int D> __global__ void k_correct(sph_particles P, step_ctx k, double dt, long n, red *r)
{
    __shared__ typename reduce_d::TempStorage tmp;
    __shared__ typename reduce_u::TempStorage tmpu;
    const long i = (long)blockIdx.x * BS + threadIdx.x;
    k.P = &P;
    double vmax2 = 0.0, rlo = INFINITY, rhi = -INFINITY;
    unsigned long long bad = 0;
    if (i < n)
        bad = (unsigned long long)correct_one(D, 0, &k, dt, i, &vmax2, &rlo, &rhi);
    const double m = reduce_d(tmp).Reduce(vmax2, dmax());
    __syncthreads();
    const double lo = reduce_d(tmp).Reduce(rlo, dmin());
    __syncthreads();
    const double hi = reduce_d(tmp).Reduce(rhi, dmax());
    const unsigned long long b = reduce_u(tmpu).Sum(bad);
    if (threadIdx.x == 0) {
        atomic_max_d(&r->vmax2, m);
        atomic_min_d(&r->rlo, lo);
        atomic_max_d(&r->rhi, hi);
        if (b)
            atomicAdd(&r->bad_c, b);
    }
}

unsigned blocks(long n)
{
    return (unsigned)((n + BS - 1) / BS);
}

} // namespace

#define SPH_GPU_NARRAYS 29

struct sph_gpu {
    sph_gpu_setup su;
    int dim;
    long n, nactive;
    sph_particles P; /* device arrays */
    sph_config *cfg; /* device copies */
    sph_kernel *kern;
    int *ib[4]; /* n ints each: the sorts' keys and values (CUB's double buffers), the
                   permutation, the ids' scratch, in no fixed order from one step to the next */
    int *start;
    void *cub_tmp;
    size_t cub_bytes; /* the larger of the two sorts' (by cell; 3D: by z within each cell) */
    int key_bits;
    double *rest; /* a paddle's rest table (su.paddle.np > 0: the device's copy) */
    red *r;
    red *r_host; /* pinned */
    cudaStream_t st;
    cudaEvent_t ev[5];
    double bytes;
};

/* The double arrays of P, in one fixed order, NULL where P has none (the host's and the device's
 * are the same set). */
static int double_arrays(sph_particles *P, double ***out)
{
    double **const all[SPH_GPU_NARRAYS] = {
        &P->x,   &P->y,   &P->z,    &P->vx,  &P->vy,  &P->vz,  &P->rho,   &P->p,   &P->pr,  &P->ax,
        &P->ay,  &P->az,  &P->drho, &P->ax0, &P->ay0, &P->az0, &P->drho0, &P->gxx, &P->gxy, &P->gyy,
        &P->gzz, &P->gxz, &P->gyz,  &P->txx, &P->txy, &P->tyy, &P->tzz,   &P->txz, &P->tyz};
    int k = 0;
    for (int a = 0; a < SPH_GPU_NARRAYS; a++)
        out[k++] = all[a];
    return k;
}

static int fail(sph_error *err, sph_error_code code, const char *what, cudaError_t e)
{
    sph_error_set(err, code, "", "GPU: %s: %s", what, cudaGetErrorString(e));
    return -1;
}

#define CK(call, what)                                                                             \
    do {                                                                                           \
        cudaError_t e_ = (call);                                                                   \
        if (e_ != cudaSuccess)                                                                     \
            return fail(err, e_ == cudaErrorMemoryAllocation ? SPH_ERR_NOMEM : SPH_ERR_IO, what,   \
                        e_);                                                                       \
    } while (0)

extern "C" int sph_gpu_count(void)
{
    int n = 0;
    if (cudaGetDeviceCount(&n) != cudaSuccess)
        return 0;
    return n;
}

extern "C" int sph_gpu_describe(int k, char *name, size_t len, double *bytes)
{
    cudaDeviceProp p;
    if (cudaGetDeviceProperties(&p, k) != cudaSuccess)
        return -1;
    if (name && len)
        snprintf(name, len, "%s", p.name);
    if (bytes)
        *bytes = (double)p.totalGlobalMem;
    return 0;
}

static int alloc_arrays(sph_gpu *g, const sph_particles *H, sph_error *err)
{
    const size_t n = (size_t)g->n;
    sph_particles *P = &g->P;
    memset(P, 0, sizeof *P);
    P->n = g->n;
    P->cap = g->n;
    P->dim = g->dim;
    sph_particles hc = *H;
    double **hd[SPH_GPU_NARRAYS], **dd[SPH_GPU_NARRAYS];
    double_arrays(&hc, hd);
    double_arrays(P, dd);
    for (int a = 0; a < SPH_GPU_NARRAYS; a++)
        if (*hd[a]) {
            CK(cudaMalloc((void **)dd[a], n * sizeof(double)), "allocating the particles");
            g->bytes += (double)(n * sizeof(double));
        }
    CK(cudaMalloc((void **)&P->type, n), "allocating the particles");
    CK(cudaMalloc((void **)&P->id, n * sizeof(int)), "allocating the particles");
    for (int k = 0; k < 4; k++)
        CK(cudaMalloc((void **)&g->ib[k], n * sizeof(int)), "allocating the sort");
    const long ncells = g->su.grid.ncells;
    CK(cudaMalloc((void **)&g->start, (size_t)(ncells + 2) * sizeof(int)), "allocating the cells");
    g->bytes +=
        (double)(n * (1 + sizeof(int) + 4 * sizeof(int))) + (double)(ncells + 2) * sizeof(int);
    g->key_bits = 1;
    while ((1L << g->key_bits) <= ncells)
        g->key_bits++;
    /* double buffers: CUB sorts in place of them, with no copy of its own */
    cub::DoubleBuffer<int> kb(g->ib[0], g->ib[2]), vb(g->ib[1], g->ib[3]);
    CK(cub::DeviceRadixSort::SortPairs(nullptr, g->cub_bytes, kb, vb, (int)g->n, 0, g->key_bits,
                                       g->st),
       "sizing the sort");
    if (g->dim == 3) {
        size_t zbytes = 0;
        cub::DoubleBuffer<double> zb(P->ay, P->az);
        CK(cub::DeviceSegmentedSort::StableSortPairs(nullptr, zbytes, zb, vb, (int)g->n,
                                                     (int)(ncells + 1), g->start, g->start + 1,
                                                     g->st),
           "sizing the sort by z");
        g->cub_bytes = zbytes > g->cub_bytes ? zbytes : g->cub_bytes;
    }
    CK(cudaMalloc(&g->cub_tmp, g->cub_bytes ? g->cub_bytes : 1), "allocating the sort");
    g->bytes += (double)g->cub_bytes;
    if (g->su.paddle.np > 0) {
        const size_t rb = (size_t)g->su.paddle.np * 2 * sizeof(double);
        CK(cudaMalloc((void **)&g->rest, rb), "allocating the paddle");
        CK(cudaMemcpy(g->rest, g->su.paddle.rest, rb, cudaMemcpyHostToDevice),
           "copying the paddle");
        g->bytes += (double)rb;
    }
    CK(cudaMalloc((void **)&g->cfg, sizeof(sph_config)), "allocating the setup");
    CK(cudaMalloc((void **)&g->kern, sizeof(sph_kernel)), "allocating the setup");
    CK(cudaMalloc((void **)&g->r, sizeof(red)), "allocating the setup");
    CK(cudaMallocHost((void **)&g->r_host, sizeof(red)), "allocating the setup");
    return 0;
}

/* Host P -> device (to_device) or back, every array P has. */
static int copy_all(sph_gpu *g, sph_particles *H, int to_device, sph_error *err)
{
    const size_t n = (size_t)g->n;
    double **hd[SPH_GPU_NARRAYS], **dd[SPH_GPU_NARRAYS];
    double_arrays(H, hd);
    double_arrays(&g->P, dd);
    const cudaMemcpyKind kind = to_device ? cudaMemcpyHostToDevice : cudaMemcpyDeviceToHost;
    for (int a = 0; a < SPH_GPU_NARRAYS; a++)
        if (*hd[a] && *dd[a])
            CK(cudaMemcpyAsync(to_device ? (void *)*dd[a] : (void *)*hd[a],
                               to_device ? (const void *)*hd[a] : (const void *)*dd[a],
                               n * sizeof(double), kind, g->st),
               "copying the particles");
    CK(cudaMemcpyAsync(to_device ? (void *)g->P.type : (void *)H->type,
                       to_device ? (const void *)H->type : (const void *)g->P.type, n, kind, g->st),
       "copying the particles");
    CK(cudaMemcpyAsync(to_device ? (void *)g->P.id : (void *)H->id,
                       to_device ? (const void *)H->id : (const void *)g->P.id, n * sizeof(int),
                       kind, g->st),
       "copying the particles");
    CK(cudaStreamSynchronize(g->st), "copying the particles");
    return 0;
}

extern "C" sph_gpu *sph_gpu_create(const sph_gpu_setup *su, const sph_particles *P, sph_error *err)
{
    if (sph_gpu_count() < 1) {
        sph_error_set(err, SPH_ERR_INVALID, "/device", "no GPU is visible to this sphd");
        return NULL;
    }
    sph_gpu *g = (sph_gpu *)calloc(1, sizeof *g);
    if (!g) {
        sph_error_set(err, SPH_ERR_NOMEM, "", "out of memory for the GPU's state");
        return NULL;
    }
    g->su = *su;
    g->dim = su->cfg.dim;
    g->n = P->n;
    g->nactive = su->nactive;
    sph_particles hc = *P;
    int ok = cudaStreamCreateWithFlags(&g->st, cudaStreamNonBlocking) == cudaSuccess;
    for (int k = 0; k < 5 && ok; k++)
        ok = cudaEventCreate(&g->ev[k]) == cudaSuccess;
    if (!ok) {
        sph_error_set(err, SPH_ERR_IO, "", "GPU: cannot create a stream");
        sph_gpu_destroy(g);
        return NULL;
    }
    if (alloc_arrays(g, P, err) || copy_all(g, &hc, 1, err) ||
        cudaMemcpy(g->cfg, &su->cfg, sizeof(sph_config), cudaMemcpyHostToDevice) != cudaSuccess ||
        cudaMemcpy(g->kern, &su->kernel, sizeof(sph_kernel), cudaMemcpyHostToDevice) !=
            cudaSuccess ||
        cudaDeviceSynchronize() != cudaSuccess) { /* (a pageable copy may still be in flight:
                                                     the step's stream does not wait for it) */
        if (err && err->code == SPH_OK)
            sph_error_set(err, SPH_ERR_IO, "", "GPU: cannot copy the set-up");
        sph_gpu_destroy(g);
        return NULL;
    }
    return g;
}

/* *a reordered by the permutation perm through *scratch, the two swapped. */
template <typename T> static void permute(sph_gpu *g, const int *perm, T **a, T **scratch)
{
    k_permute<T><<<blocks(g->n), BS, 0, g->st>>>(*a, *scratch, perm, g->n);
    T *t = *a;
    *a = *scratch;
    *scratch = t;
}

static fctx fctx_of(const sph_gpu *g)
{
    fctx c;
    fctx_init(&c, &g->P, &g->su.grid, g->start, g->kern, &g->su.k);
    return c;
}

/* The folded loops' launch shape (k_forces) */
constexpr int FBS = 128, FMINB = 8;

template <sph_kernel_type T, int D, unsigned F>
static void launch_folded(sph_gpu *g, const fctx &c, long n)
{
    k_forces<T, D, F, FBS, FMINB><<<(n + FBS - 1) / FBS, FBS, 0, g->st>>>(c, n, g->r);
}

/* k_forces for kernel T: an instantiation of its own for the common option sets (artificial or
 * laminar viscosity, with or without delta-SPH), the run-time options' for the rest (SPS). */
template <sph_kernel_type T, int D> static void launch_forces_t(sph_gpu *g, const fctx &c, long n)
{
    switch (c.flags) {
    case 0:
        launch_folded<T, D, 0>(g, c, n);
        break;
    case F_DELTA:
        launch_folded<T, D, F_DELTA>(g, c, n);
        break;
    case F_LAMINAR:
        launch_folded<T, D, F_LAMINAR>(g, c, n);
        break;
    case F_LAMINAR | F_DELTA:
        launch_folded<T, D, F_LAMINAR | F_DELTA>(g, c, n);
        break;
    default:
        k_forces<T, D, F_RUNTIME, BS, 1><<<blocks(n), BS, 0, g->st>>>(c, n, g->r);
        break;
    }
}

template <int D> static void launch_forces(sph_gpu *g, long n)
{
    const fctx c = fctx_of(g);
    switch (g->su.kernel.type) {
    case SPH_KERNEL_CUBIC_SPLINE:
        launch_forces_t<SPH_KERNEL_CUBIC_SPLINE, D>(g, c, n);
        break;
    case SPH_KERNEL_GAUSSIAN:
        launch_forces_t<SPH_KERNEL_GAUSSIAN, D>(g, c, n);
        break;
    case SPH_KERNEL_DOUBLE_COSINE:
        launch_forces_t<SPH_KERNEL_DOUBLE_COSINE, D>(g, c, n);
        break;
    case SPH_KERNEL_WENDLAND_C2:
        launch_forces_t<SPH_KERNEL_WENDLAND_C2, D>(g, c, n);
        break;
    case SPH_KERNEL_RENORMALIZED_GAUSSIAN:
        launch_forces_t<SPH_KERNEL_RENORMALIZED_GAUSSIAN, D>(g, c, n);
        break;
    default: /* the MPS weights: refused for WCSPH before a sim exists */
        break;
    }
}

static step_ctx step_ctx_of(const sph_gpu *g)
{
    step_ctx k;
    memset(&k, 0, sizeof k);
    k.ghost = NULL;
    k.ghosts = 0;
    k.rho0 = g->su.cfg.rho0;
    for (int d = 0; d < 3; d++) {
        k.lo[d] = g->su.cfg.domain.min[d];
        k.hi[d] = g->su.cfg.domain.max[d];
    }
    return k;
}

template <int D>
static int step_d(sph_gpu *g, double t, double dt, sph_gpu_step_out *o, sph_error *err)
{
    sph_particles *P = &g->P;
    const long n = g->n;
    /* the latest rates become the old ones */
    std::swap(P->ax, P->ax0);
    std::swap(P->ay, P->ay0);
    if (D == 3)
        std::swap(P->az, P->az0);
    std::swap(P->drho, P->drho0);
    const step_ctx k = step_ctx_of(g);
    cudaEventRecord(g->ev[0], g->st);
    k_reset<<<1, 1, 0, g->st>>>(g->r);
    if (g->nactive > 0) /* (a grid of no blocks is a launch error) */
        k_predict<D><<<blocks(g->nactive), BS, 0, g->st>>>(*P, k, dt, g->nactive, g->r);
    if (g->su.paddle.np > 0 && g->nactive > 0) { /* the paddle at the step's end, as the CPU */
        double v;
        const double X = sph_paddle_motion(&g->su.paddle.law, t + dt, &v);
        k_paddle<<<blocks(g->nactive), BS, 0, g->st>>>(
            *P, g->su.paddle.law, g->rest, g->su.paddle.first, g->su.paddle.np, X, v, g->nactive);
    }
    cudaEventRecord(g->ev[1], g->st);

    /* the sort by cell: keys, a stable radix sort, the cells' starts, the arrays permuted. The
     * rates ax, ay and az are free until the forces rewrite them: they hold the sort by z's keys
     * and the permutation's scratch, so no array of the particles' size is kept for them. */
    cub::DoubleBuffer<int> kb(g->ib[0], g->ib[2]), vb(g->ib[1], g->ib[3]);
    k_keys<D><<<blocks(n), BS, 0, g->st>>>(*P, g->su.grid, kb.Current(), vb.Current(), n);
    CK(cub::DeviceRadixSort::SortPairs(g->cub_tmp, g->cub_bytes, kb, vb, (int)n, 0, g->key_bits,
                                       g->st),
       "sorting by cell");
    const long ncells = g->su.grid.ncells;
    k_starts<<<blocks(n + 1), BS, 0, g->st>>>(kb.Current(), g->start, n, ncells);
    int *perm = vb.Current(), *spare[3] = {kb.Current(), kb.Alternate(), vb.Alternate()};
    if (D == 3) {
        /* then by z within each cell (stable), as the C sort: a column of cells along z is one
         * range sorted by z, which the pair loop cuts to the z within reach (gather_one) */
        cub::DoubleBuffer<double> zb(P->ay, P->az);
        cub::DoubleBuffer<int> wb(spare[0], spare[1]);
        k_zsort_in<<<blocks(n), BS, 0, g->st>>>(P->z, perm, g->start + ncells, zb.Current(),
                                                wb.Current(), n);
        CK(cub::DeviceSegmentedSort::StableSortPairs(g->cub_tmp, g->cub_bytes, zb, wb, (int)n,
                                                     (int)(ncells + 1), g->start, g->start + 1,
                                                     g->st),
           "sorting by z");
        k_compose<<<blocks(n), BS, 0, g->st>>>(perm, wb.Current(), spare[2], n);
        std::swap(perm, spare[2]); /* the composed permutation; the old one spare */
    }
    double **arr[SPH_GPU_NARRAYS];
    double_arrays(P, arr);
    for (int a = 0; a < SPH_GPU_NARRAYS; a++) {
        double **f = arr[a];
        /* what the step reads before it writes: state, old rates, SPS gradients */
        const int keep = *f && f != &P->p && f != &P->pr && f != &P->ax && f != &P->ay &&
                         f != &P->az && f != &P->drho && f != &P->txx && f != &P->txy &&
                         f != &P->tyy && f != &P->tzz && f != &P->txz && f != &P->tyz;
        if (keep)
            permute<double>(g, perm, f, &P->ax);
    }
    /* the types through ax's bytes and back (a scratch of n bytes swapped in would leave an
     * array too small for what it next holds), the ids through a spare int array */
    k_permute<unsigned char>
        <<<blocks(n), BS, 0, g->st>>>(P->type, reinterpret_cast<unsigned char *>(P->ax), perm, n);
    CK(cudaMemcpyAsync(P->type, P->ax, (size_t)n, cudaMemcpyDeviceToDevice, g->st),
       "sorting by cell");
    permute<int>(g, perm, &P->id, &spare[0]);
    g->ib[0] = perm;
    for (int k = 0; k < 3; k++)
        g->ib[k + 1] = spare[k];
    int nact = 0;
    cudaEventRecord(g->ev[2], g->st);
    CK(cudaMemcpyAsync(&nact, g->start + ncells, sizeof nact, cudaMemcpyDeviceToHost, g->st),
       "reading the active count");
    CK(cudaStreamSynchronize(g->st), "sorting by cell");
    g->nactive = nact;

    /* forces */
    if (nact > 0) {
        k_prepare<D><<<blocks(nact), BS, 0, g->st>>>(g->cfg, *P, g->su.k.smag, g->su.k.blin, nact);
        launch_forces<D>(g, nact);
    }
    const double *gr = g->su.cfg.gravity;
    if (n > 0)
        k_gravity<D><<<blocks(n), BS, 0, g->st>>>(*P, gr[0], gr[1], gr[2], nact, n, g->r);
    cudaEventRecord(g->ev[3], g->st);

    /* corrector */
    if (nact > 0)
        k_correct<D><<<blocks(nact), BS, 0, g->st>>>(*P, k, dt, nact, g->r);
    const sph_absorption_spec *ab = &g->su.cfg.absorption;
    if (ab->type != 0 && nact > 0) /* a damping zone, after the corrector's figures, as the CPU */
        k_damp<<<blocks(nact), BS, 0, g->st>>>(*P, dt, ab->beta, ab->from, ab->to, nact);
    cudaEventRecord(g->ev[4], g->st);
    CK(cudaMemcpyAsync(g->r_host, g->r, sizeof(red), cudaMemcpyDeviceToHost, g->st),
       "reading the step's figures");
    CK(cudaStreamSynchronize(g->st), "the step");
    CK(cudaGetLastError(), "the step's kernels");
    const red *r = g->r_host;
    o->nactive = nact;
    o->bad_predict = (long)r->bad_p;
    o->bad_correct = (long)r->bad_c;
    o->pairs = (long)(r->pairs / 2);
    o->vmax2 = r->vmax2;
    o->amax2 = r->amax2;
    o->rho_lo = r->rlo;
    o->rho_hi = r->rhi;
    float ms[4] = {0};
    for (int q = 0; q < 4; q++)
        cudaEventElapsedTime(&ms[q], g->ev[q], g->ev[q + 1]);
    o->t_integration = 1e-3 * (ms[0] + ms[3]);
    o->t_neighbours = 1e-3 * ms[1];
    o->t_interactions = 1e-3 * ms[2];
    return 0;
}

extern "C" int sph_gpu_step(sph_gpu *g, double t, double dt, sph_gpu_step_out *o, sph_error *err)
{
    memset(o, 0, sizeof *o);
    return g->dim == 3 ? step_d<3>(g, t, dt, o, err) : step_d<2>(g, t, dt, o, err);
}

extern "C" int sph_gpu_download(sph_gpu *g, sph_particles *P, sph_error *err)
{
    if (P->n != g->n)
        return sph_error_set(err, SPH_ERR_INVALID, "", "GPU: %ld particles on the host, %ld here",
                             P->n, g->n);
    return copy_all(g, P, 0, err);
}

extern "C" double sph_gpu_bytes(const sph_gpu *g)
{
    return g ? g->bytes : 0.0;
}

extern "C" void sph_gpu_destroy(sph_gpu *g)
{
    if (!g)
        return;
    if (g->st)
        cudaStreamSynchronize(g->st);
    double **arr[SPH_GPU_NARRAYS];
    double_arrays(&g->P, arr);
    for (int a = 0; a < SPH_GPU_NARRAYS; a++)
        cudaFree(*arr[a]);
    cudaFree(g->P.type);
    cudaFree(g->P.id);
    for (int k = 0; k < 4; k++)
        cudaFree(g->ib[k]);
    cudaFree(g->start);
    cudaFree(g->cub_tmp);
    cudaFree(g->rest);
    cudaFree(g->cfg);
    cudaFree(g->kern);
    cudaFree(g->r);
    cudaFreeHost(g->r_host);
    for (int k = 0; k < 5; k++)
        if (g->ev[k])
            cudaEventDestroy(g->ev[k]);
    if (g->st)
        cudaStreamDestroy(g->st);
    free(g);
}
