/* Particle snapshots (HDF5). */
#include "sphd_h5.h"
#include "sphd_h5_util.h"

#include <errno.h>
#include <fcntl.h>
#include <hdf5.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* One field as an (n) or (n, 3) dataset, interleaving components into a row buffer. */
static int write_field(hid_t file, const sphd_h5_field *f, long n, int compress)
{
    const int vec = f->ncomp > 1;
    const int width = vec ? 3 : 1;
    const size_t es = sphd_h5_type_size(f->type);
    hsize_t dims[2] = {(hsize_t)n, (hsize_t)width};
    hid_t space = H5Screate_simple(vec ? 2 : 1, dims, NULL);
    hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
    if (n > 0) {
        /* chunks of at most 65536 rows, sized so that the last one is not mostly empty */
        const long nchunks = (n + 65535) / 65536;
        hsize_t chunk[2] = {(hsize_t)((n + nchunks - 1) / nchunks), (hsize_t)width};
        H5Pset_chunk(dcpl, vec ? 2 : 1, chunk);
        if (compress > 0) {
            H5Pset_shuffle(dcpl);
            H5Pset_deflate(dcpl, (unsigned)(compress > 9 ? 9 : compress));
        }
    }
    const hid_t mtype = sphd_h5_type_id(f->type);
    hid_t d = H5Dcreate2(file, f->name, mtype, space, H5P_DEFAULT, dcpl, H5P_DEFAULT);
    int rc = d < 0 ? -1 : 0;
    if (rc == 0 && f->units)
        rc = sphd_h5_attr_string(d, "units", f->units);
    if (rc == 0 && n > 0) {
        const void *src = f->comp[0];
        char *buf = NULL;
        if (vec) {
            buf = calloc((size_t)n * 3, es);
            if (!buf)
                rc = -1;
            for (long i = 0; buf && i < n; i++)
                for (int c = 0; c < f->ncomp && c < 3; c++)
                    memcpy(buf + ((size_t)i * 3 + (size_t)c) * es,
                           (const char *)f->comp[c] + (size_t)i * es, es);
            src = buf;
        }
        if (rc == 0 && H5Dwrite(d, mtype, H5S_ALL, H5S_ALL, H5P_DEFAULT, src) < 0)
            rc = -1;
        free(buf);
    }
    if (d >= 0)
        H5Dclose(d);
    H5Pclose(dcpl);
    H5Sclose(space);
    return rc;
}

/* The group /rpdf: the fluid's radial particle density function (PROTOCOL.md section 4). */
static int write_rpdf(hid_t file, const sphd_h5_rpdf *r)
{
    if (r->nbins < 1)
        return -1;
    hid_t g = H5Gcreate2(file, "rpdf", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    if (g < 0)
        return -1;
    const int bins = r->nbins;
    int rc = 0;
    rc |= sphd_h5_attr_string(g, "description",
                              "radial particle density function of the fluid: the pairs of fluid "
                              "particles closer than qmax h, binned by q = r/h (h the smoothing "
                              "length); density = neighbours per particle in the bin's ring over "
                              "those of a uniform fluid at the initial spacing dx (1 for a "
                              "uniform fluid, less near a free surface)");
    rc |= sphd_h5_attr_number(g, "qmax", H5T_NATIVE_DOUBLE, &r->qmax);
    rc |= sphd_h5_attr_number(g, "bins", H5T_NATIVE_INT, &bins);
    rc |= sphd_h5_write_1d(g, "q", H5T_NATIVE_DOUBLE, r->q, bins, "1");
    rc |= sphd_h5_write_1d(g, "count", H5T_NATIVE_DOUBLE, r->count, bins, "1");
    rc |= sphd_h5_write_1d(g, "density", H5T_NATIVE_DOUBLE, r->density, bins, "1");
    if (H5Gclose(g) < 0)
        rc = -1;
    return rc ? -1 : 0;
}

int sphd_h5_write_snapshot(const char *path, const sphd_h5_header *hdr, const sphd_h5_field *fields,
                           int nfields, int compress, sph_error *err)
{
    sphd_h5_quiet();
    char tmp[4096];
    if (snprintf(tmp, sizeof tmp, "%s.tmp.%ld", path, (long)getpid()) >= (int)sizeof tmp)
        return sph_error_set(err, SPH_ERR_IO, "", "snapshot path too long: %s", path);
    errno = 0;
    hid_t file = H5Fcreate(tmp, H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT);
    if (file < 0)
        return sphd_h5_fail(err, "creating snapshot", tmp);
    const long long step = hdr->step, n = hdr->n, nf = hdr->n_fluid, nb = hdr->n_boundary,
                    nbody = hdr->n_body;
    const int dim = hdr->dim;
    int rc = 0;
    rc |= sphd_h5_attr_number(file, "time", H5T_NATIVE_DOUBLE, &hdr->t);
    rc |= sphd_h5_attr_number(file, "step", H5T_NATIVE_LLONG, &step);
    rc |= sphd_h5_attr_number(file, "dim", H5T_NATIVE_INT, &dim);
    rc |= sphd_h5_attr_number(file, "dx", H5T_NATIVE_DOUBLE, &hdr->dx);
    rc |= sphd_h5_attr_number(file, "n_particles", H5T_NATIVE_LLONG, &n);
    rc |= sphd_h5_attr_number(file, "n_fluid", H5T_NATIVE_LLONG, &nf);
    rc |= sphd_h5_attr_number(file, "n_boundary", H5T_NATIVE_LLONG, &nb);
    rc |= sphd_h5_attr_number(file, "n_body", H5T_NATIVE_LLONG, &nbody);
    rc |= sphd_h5_attr_string(file, "kernel", hdr->kernel ? hdr->kernel : "");
    rc |= sphd_h5_attr_string(file, "job", hdr->job ? hdr->job : "");
    rc |= sphd_h5_attr_string(file, "code_version", "sphd " SPH_VERSION);
    rc |= sphd_h5_attr_string(file, "units", "SI: m, s, kg (mass per metre in 2D), Pa");
    if (hdr->mass > 0)
        rc |= sphd_h5_attr_number(file, "mass", H5T_NATIVE_DOUBLE, &hdr->mass);
    if (hdr->h > 0)
        rc |= sphd_h5_attr_number(file, "h", H5T_NATIVE_DOUBLE, &hdr->h);
    for (int i = 0; rc == 0 && i < nfields; i++)
        rc = write_field(file, &fields[i], hdr->n, compress);
    if (rc == 0)
        rc = sphd_vtkhdf_write(file, fields, nfields, hdr->n);
    if (rc == 0 && hdr->rpdf)
        rc = write_rpdf(file, hdr->rpdf);
    if (rc != 0) {
        sphd_h5_fail(err, "writing snapshot", tmp);
        H5Fclose(file);
        unlink(tmp);
        return SPH_ERR_IO;
    }
    if (H5Fclose(file) < 0) {
        sphd_h5_fail(err, "closing snapshot", tmp);
        unlink(tmp);
        return SPH_ERR_IO;
    }
    if (sphd_fsync_path(tmp) != 0 || rename(tmp, path) != 0) {
        int e = errno;
        unlink(tmp);
        return sph_error_set(err, SPH_ERR_IO, "", "saving snapshot '%s' failed: %s", path,
                             strerror(e));
    }
    return 0;
}
