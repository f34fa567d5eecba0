/*
 * bench_kernel: kernel evaluations per second, per kernel, through the per-type inlined path
 * (SPH_KERNEL_DISPATCH, as the solver's pair loops use it) and through the generic switch.
 * Prints figures; never fails on time.
 */
#include "sph_kernel.h"

#include <stdio.h>
#include <time.h>

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

#define NEVAL 20000000L

static inline __attribute__((always_inline)) double loop_t(sph_kernel_type t, const sph_kernel *k)
{
    double s = 0.0, step = k->support / (double)NEVAL;
    for (long i = 0; i < NEVAL; i++) {
        double d;
        s += sph_kernel_eval_t(t, k, (double)i * step, &d) + d;
    }
    return s;
}

static double loop_generic(const sph_kernel *k)
{
    double s = 0.0, step = k->support / (double)NEVAL;
    for (long i = 0; i < NEVAL; i++)
        s += sph_kernel_w(k, (double)i * step) + sph_kernel_dwdr(k, (double)i * step);
    return s;
}

int main(void)
{
    printf("%-22s %14s %14s\n", "kernel", "inlined Meval/s", "generic Meval/s");
    for (int t = 0; t < SPH_KERNEL_COUNT; t++) {
        sph_kernel_spec spec = sph_kernel_spec_default((sph_kernel_type)t);
        sph_kernel k;
        sph_kernel_init(&k, &spec, 2, 0.01, NULL);
        double sink = 0.0, t0 = now();
#define CALL(T) sink += loop_t(T, &k)
        SPH_KERNEL_DISPATCH(k.type, CALL);
#undef CALL
        double t1 = now();
        sink += loop_generic(&k);
        double t2 = now();
        printf("%-22s %14.1f %14.1f   (checksum %.3g)\n", sph_kernel_type_name(k.type),
               NEVAL / (t1 - t0) / 1e6, NEVAL / (t2 - t1) / 1e6, sink);
    }
    return 0;
}
