/*
 * SPH_HD: marks the physics that the C loops and the CUDA kernels share (`static inline`
 * functions in headers): __host__ __device__ under nvcc, nothing in C. A backend adds the
 * scheduling (loops, threads, transfers), never physics of its own (DESIGN.md section 2).
 * SPH_RESTRICT: C's restrict, which C++ (nvcc) spells __restrict__.
 */
#ifndef SPH_HD_H
#define SPH_HD_H

#ifdef __CUDACC__
#define SPH_HD       __host__ __device__
#define SPH_RESTRICT __restrict__
#else
#define SPH_HD
#define SPH_RESTRICT restrict
#endif

#endif
