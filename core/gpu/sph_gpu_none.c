/*
 * sph_gpu without CUDA (the default build): no devices; a GPU case is refused at /device before
 * a simulation is made (sph_wcsph_gpu.c), and sph_gpu_create says why if it is reached anyway.
 */
#include "sph_gpu.h"

int sph_gpu_count(void)
{
    return 0;
}

int sph_gpu_describe(int k, char *name, size_t len, double *bytes)
{
    (void)k;
    (void)name;
    (void)len;
    (void)bytes;
    return -1;
}

sph_gpu *sph_gpu_create(const sph_gpu_setup *su, const sph_particles *P, sph_error *err)
{
    (void)su;
    (void)P;
    sph_error_set(err, SPH_ERR_INVALID, "/device",
                  "this sphd was built without CUDA (cmake -DSPH_CUDA=ON builds the GPU backend)");
    return NULL;
}

int sph_gpu_step(sph_gpu *g, double t, double dt, sph_gpu_step_out *o, sph_error *err)
{
    (void)g;
    (void)t;
    (void)dt;
    (void)o;
    return sph_error_set(err, SPH_ERR_INVALID, "/device", "this sphd was built without CUDA");
}

int sph_gpu_download(sph_gpu *g, sph_particles *P, sph_error *err)
{
    (void)g;
    (void)P;
    return sph_error_set(err, SPH_ERR_INVALID, "/device", "this sphd was built without CUDA");
}

double sph_gpu_bytes(const sph_gpu *g)
{
    (void)g;
    return 0.0;
}

void sph_gpu_destroy(sph_gpu *g)
{
    (void)g;
}
