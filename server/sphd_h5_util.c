/* The helpers the HDF5 writers share (sphd_h5_util.h): errors, types, attributes, small datasets.
 */
#include "sphd_h5_util.h"

#include <errno.h>
#include <fcntl.h>
#include <hdf5.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

static herr_t walk_cb(unsigned n, const H5E_error2_t *e, void *ud)
{
    (void)n;
    char *msg = ud;
    if (msg[0] == '\0' && e->desc)
        snprintf(msg, 200, "%s", e->desc);
    return 0;
}

void sphd_h5_init(void)
{
    /* No cleanup of HDF5's own at exit: sphd closes what it opens, and a file whose close failed
     * (a full disk) stays in HDF5's table in a state its exit-time close crashes on (HDF5 1.10). */
    H5dont_atexit();
    sphd_h5_quiet();
}

void sphd_h5_quiet(void)
{
    H5Eset_auto2(H5E_DEFAULT, NULL, NULL);
}

int sphd_h5_fail(sph_error *err, const char *what, const char *path)
{
    char msg[200] = "";
    H5Ewalk2(H5E_DEFAULT, H5E_WALK_UPWARD, walk_cb, msg);
    H5Eclear2(H5E_DEFAULT);
    const int e = errno;
    return sph_error_set(err, SPH_ERR_IO, "", "%s '%s' failed: %s%s%s", what, path,
                         msg[0] ? msg : "HDF5 error", e ? "; " : "", e ? strerror(e) : "");
}

hid_t sphd_h5_type_id(sphd_h5_type t)
{
    switch (t) {
    case SPHD_H5_F32:
        return H5T_NATIVE_FLOAT;
    case SPHD_H5_F64:
        return H5T_NATIVE_DOUBLE;
    case SPHD_H5_I8:
        return H5T_NATIVE_INT8;
    case SPHD_H5_I32:
        return H5T_NATIVE_INT32;
    case SPHD_H5_I64:
    default:
        return H5T_NATIVE_INT64;
    }
}

size_t sphd_h5_type_size(sphd_h5_type t)
{
    switch (t) {
    case SPHD_H5_I8:
        return 1;
    case SPHD_H5_F32:
    case SPHD_H5_I32:
        return 4;
    default:
        return 8;
    }
}

int sphd_h5_attr_number(hid_t obj, const char *name, hid_t type, const void *value)
{
    hid_t space = H5Screate(H5S_SCALAR);
    hid_t a = H5Acreate2(obj, name, type, space, H5P_DEFAULT, H5P_DEFAULT);
    herr_t rc = a < 0 ? -1 : H5Awrite(a, type, value);
    if (a >= 0)
        H5Aclose(a);
    H5Sclose(space);
    return rc < 0 ? -1 : 0;
}

int sphd_h5_attr_string(hid_t obj, const char *name, const char *value)
{
    hid_t type = H5Tcopy(H5T_C_S1); /* a scalar of a fixed-length string type */
    H5Tset_size(type, strlen(value) + 1);
    int rc = sphd_h5_attr_number(obj, name, type, value);
    H5Tclose(type);
    return rc;
}

int sphd_fsync_path(const char *path)
{
    int fd = open(path, O_RDONLY | O_CLOEXEC);
    if (fd < 0)
        return -1;
    int rc = fsync(fd);
    int saved = errno;
    close(fd);
    errno = saved;
    return rc;
}

int sphd_h5_write_1d(hid_t g, const char *name, hid_t type, const void *v, long n,
                     const char *units)
{
    hsize_t dims[1] = {(hsize_t)n};
    hid_t space = H5Screate_simple(1, dims, NULL);
    hid_t d = H5Dcreate2(g, name, type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    int rc = d < 0 ? -1 : 0;
    if (rc == 0 && H5Dwrite(d, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, v) < 0)
        rc = -1;
    if (rc == 0 && units)
        rc = sphd_h5_attr_string(d, "units", units);
    if (d >= 0)
        H5Dclose(d);
    H5Sclose(space);
    return rc;
}
