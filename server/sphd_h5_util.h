/* Helpers shared by the HDF5 writers (server/sphd_h5*.c); not a public interface. */
#ifndef SPHD_H5_UTIL_H
#define SPHD_H5_UTIL_H

#include "sphd_h5.h"

#include <hdf5.h>

/* Turns off HDF5's printing of error stacks (errors are reported through sph_error). */
void sphd_h5_quiet(void);
/* Once, before any other HDF5 call of the process: no HDF5 cleanup at exit, errors quiet. */
void sphd_h5_init(void);
/* Fills err (SPH_ERR_IO) from HDF5's error stack and errno; returns SPH_ERR_IO. */
int sphd_h5_fail(sph_error *err, const char *what, const char *path);
hid_t sphd_h5_type_id(sphd_h5_type t);
size_t sphd_h5_type_size(sphd_h5_type t);
/* A scalar attribute: a string, or any value of `type` (numbers; attr_string passes its string
 * type). Return 0 or -1. */
int sphd_h5_attr_string(hid_t obj, const char *name, const char *value);
int sphd_h5_attr_number(hid_t obj, const char *name, hid_t type, const void *value);
/* A contiguous 1D dataset of n values of `type` (a few: no chunks, no filter), with a `units`
 * attribute unless units is NULL. Returns 0 or -1. */
int sphd_h5_write_1d(hid_t g, const char *name, hid_t type, const void *v, long n,
                     const char *units);
/* Adds ParaView's VTKHDF layout to an open snapshot whose fields are written (sphd_vtkhdf.c);
 * nothing without "pos" and an integer "id". Returns 0 or -1. */
int sphd_vtkhdf_write(hid_t file, const sphd_h5_field *fields, int nfields, long n);
/* fsync a file by path (after HDF5 has closed it). */
int sphd_fsync_path(const char *path);

#endif
