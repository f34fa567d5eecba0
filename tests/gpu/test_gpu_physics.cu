/*
 * ctest gpu_physics (built with -DSPH_CUDA=ON): the physics is written once. The SPH_HD headers
 * of core/ (kernels, EOS, the WCSPH pair, the SPS stress) compile under nvcc, for the device and
 * for the host, and give what the C build gives:
 *   - host: nvcc's host code against the C compiler's (physics_ref.c), bit for bit;
 *   - device (when a GPU is visible): the GPU against the C compiler's, within 1e-12 relative
 *     (the device's exp, sin and sqrt may differ from the C library's in the last bits).
 * Without a GPU the device half is skipped and said so; the host half still runs.
 */
#include <cuda_runtime.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>

extern "C" {
#include "physics_cases.h"
void pc_reference(const sph_kernel *kern, const sph_config *lin, const sph_config *tait,
                  double *out);
}

__global__ void pc_device(const sph_kernel *kern, const sph_config *lin, const sph_config *tait,
                          double *out)
{
    const int i = blockIdx.x * blockDim.x + threadIdx.x;
    if (i < PC_SAMPLES)
        pc_eval(i, kern, lin, tait, out + (long)i * PC_OUT);
}

static double max_rel(const double *a, const double *b, long n, long *where)
{
    double m = 0.0;
    for (long k = 0; k < n; k++) {
        const double s = fmax(fabs(a[k]), fabs(b[k]));
        const double e = s > 0.0 ? fabs(a[k] - b[k]) / s : 0.0;
        if (!(e <= m)) {
            m = e;
            *where = k;
        }
    }
    return m;
}

int main()
{
    const sph_kernel_type types[PC_KERNELS] = {SPH_KERNEL_CUBIC_SPLINE, SPH_KERNEL_GAUSSIAN,
                                               SPH_KERNEL_DOUBLE_COSINE, SPH_KERNEL_WENDLAND_C2,
                                               SPH_KERNEL_RENORMALIZED_GAUSSIAN};
    sph_kernel kern[PC_KERNELS];
    for (int t = 0; t < PC_KERNELS; t++) {
        sph_kernel_spec spec = sph_kernel_spec_default(types[t]);
        sph_error err;
        if (sph_kernel_init(&kern[t], &spec, 2, 0.0028, &err) != 0) {
            std::printf("FAIL: kernel %d: %s\n", t, err.message);
            return 1;
        }
    }
    static sph_config lin, tait;
    lin.rho0 = tait.rho0 = 1000.0;
    lin.c0 = tait.c0 = 25.0;
    lin.eos = SPH_EOS_LINEAR;
    tait.eos = SPH_EOS_TAIT;
    const long n = (long)PC_SAMPLES * PC_OUT;
    double *ref = (double *)std::malloc(n * sizeof(double));
    double *host = (double *)std::malloc(n * sizeof(double));
    double *dev = (double *)std::malloc(n * sizeof(double));
    if (!ref || !host || !dev)
        return 1;
    pc_reference(kern, &lin, &tait, ref);
    for (int i = 0; i < PC_SAMPLES; i++)
        pc_eval(i, kern, &lin, &tait, host + (long)i * PC_OUT);
    int fails = 0;
    long where = -1;
    const int same = std::memcmp(ref, host, n * sizeof(double)) == 0;
    const double host_rel = max_rel(ref, host, n, &where);
    std::printf("gpu_physics: host (nvcc) against C: %ld values, %s (max relative difference "
                "%.3g)\n",
                n, same ? "bit for bit" : "DIFFERENT", host_rel);
    fails += !same;

    int ndev = 0;
    if (cudaGetDeviceCount(&ndev) != cudaSuccess || ndev == 0) {
        std::printf("gpu_physics: no GPU visible: the device half is skipped\n");
    } else {
        sph_kernel *dk;
        sph_config *dl, *dt;
        double *dout;
        cudaMalloc(&dk, sizeof kern);
        cudaMalloc(&dl, sizeof lin);
        cudaMalloc(&dt, sizeof tait);
        cudaMalloc(&dout, n * sizeof(double));
        cudaMemcpy(dk, kern, sizeof kern, cudaMemcpyHostToDevice);
        cudaMemcpy(dl, &lin, sizeof lin, cudaMemcpyHostToDevice);
        cudaMemcpy(dt, &tait, sizeof tait, cudaMemcpyHostToDevice);
        pc_device<<<(PC_SAMPLES + 127) / 128, 128>>>(dk, dl, dt, dout);
        const cudaError_t e = cudaMemcpy(dev, dout, n * sizeof(double), cudaMemcpyDeviceToHost);
        if (e != cudaSuccess) {
            std::printf("FAIL: the device run: %s\n", cudaGetErrorString(e));
            fails++;
        } else {
            where = -1;
            const double rel = max_rel(ref, dev, n, &where);
            std::printf("gpu_physics: device against C: max relative difference %.3g%s\n", rel,
                        rel <= 1e-12 ? " (within 1e-12)" : "");
            if (!(rel <= 1e-12)) {
                std::printf("FAIL: value %ld: %.17g on the GPU, %.17g in C\n", where, dev[where],
                            ref[where]);
                fails++;
            }
        }
        cudaFree(dk);
        cudaFree(dl);
        cudaFree(dt);
        cudaFree(dout);
    }
    std::free(ref);
    std::free(host);
    std::free(dev);
    std::printf("gpu_physics: %s\n", fails ? "FAILED" : "passed");
    return fails ? 1 : 0;
}
