/*
 * ParaView's own HDF5 layout inside a snapshot: VTKHDF 1.0, an unstructured grid with one vertex
 * cell per particle, in the group /VTKHDF. Its points, connectivity and point data are hard links
 * to the snapshot's datasets (pos, id, and the other fields), so the particle data is stored once;
 * only the cell offsets (0..n, the id's integer type) and the cell types (n bytes of VTK_VERTEX)
 * are new, and both are always compressed (they are regular).
 * Format: https://docs.vtk.org/en/latest/design_documents/VTKFileFormats.html (VTKHDF).
 */
#include "sphd_h5_util.h"

#include <hdf5.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum { VTK_VERTEX = 1 };

/* One number as a dataset of one element (VTKHDF's counts). */
static int one_number(hid_t g, const char *name, long long v)
{
    return sphd_h5_write_1d(g, name, H5T_NATIVE_LLONG, &v, 1, NULL);
}

/* A 1D dataset of n elements of `type`, chunked and deflated. */
static int regular(hid_t g, const char *name, hid_t type, long n, const void *data)
{
    hsize_t dims[1] = {(hsize_t)n}, chunk[1] = {(hsize_t)(n < 65536 ? n : 65536)};
    hid_t sp = H5Screate_simple(1, dims, NULL);
    hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
    H5Pset_chunk(dcpl, 1, chunk);
    H5Pset_shuffle(dcpl);
    H5Pset_deflate(dcpl, 1);
    hid_t d = H5Dcreate2(g, name, type, sp, H5P_DEFAULT, dcpl, H5P_DEFAULT);
    int rc = d < 0 || H5Dwrite(d, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0;
    if (d >= 0)
        H5Dclose(d);
    H5Pclose(dcpl);
    H5Sclose(sp);
    return rc ? -1 : 0;
}

static int link(hid_t file, const char *target, hid_t g, const char *name)
{
    return H5Lcreate_hard(file, target, g, name, H5P_DEFAULT, H5P_DEFAULT) < 0 ? -1 : 0;
}

int sphd_vtkhdf_write(hid_t file, const sphd_h5_field *fields, int nfields, long n)
{
    const sphd_h5_field *pos = NULL, *id = NULL;
    for (int i = 0; i < nfields; i++) {
        if (strcmp(fields[i].name, "pos") == 0)
            pos = &fields[i];
        else if (strcmp(fields[i].name, "id") == 0 && fields[i].ncomp == 1 &&
                 (fields[i].type == SPHD_H5_I32 || fields[i].type == SPHD_H5_I64))
            id = &fields[i];
    }
    if (!pos || !id || n < 1)
        return 0; /* no layout without points and a connectivity to link to */
    /* offsets must have the connectivity's type (vtkCellArray) */
    const int wide = id->type == SPHD_H5_I64;
    const size_t es = wide ? 8 : 4;
    void *offsets = malloc((size_t)(n + 1) * es);
    unsigned char *types = malloc((size_t)n);
    if (!offsets || !types) {
        free(offsets), free(types);
        return -1;
    }
    for (long k = 0; k <= n; k++) {
        if (wide)
            ((long long *)offsets)[k] = k;
        else
            ((int *)offsets)[k] = (int)k;
    }
    memset(types, VTK_VERTEX, (size_t)n);

    hid_t g = H5Gcreate2(file, "VTKHDF", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
    int rc = g < 0 ? -1 : 0;
    if (rc == 0) {
        hsize_t two[1] = {2};
        const long long version[2] = {1, 0};
        hid_t sp = H5Screate_simple(1, two, NULL);
        hid_t a = H5Acreate2(g, "Version", H5T_NATIVE_LLONG, sp, H5P_DEFAULT, H5P_DEFAULT);
        rc = a < 0 || H5Awrite(a, H5T_NATIVE_LLONG, version) < 0 ? -1 : 0;
        if (a >= 0)
            H5Aclose(a);
        H5Sclose(sp);
        /* a fixed-length string without a terminating NUL: vtkHDFReader compares all of it */
        hid_t t = H5Tcopy(H5T_C_S1);
        H5Tset_size(t, strlen("UnstructuredGrid"));
        H5Tset_strpad(t, H5T_STR_NULLPAD);
        rc |= sphd_h5_attr_number(g, "Type", t, "UnstructuredGrid");
        H5Tclose(t);
    }
    if (rc == 0)
        rc = one_number(g, "NumberOfPoints", n) | one_number(g, "NumberOfCells", n) |
             one_number(g, "NumberOfConnectivityIds", n);
    if (rc == 0)
        rc = regular(g, "Offsets", wide ? H5T_NATIVE_LLONG : H5T_NATIVE_INT, n + 1, offsets) |
             regular(g, "Types", H5T_NATIVE_UCHAR, n, types);
    if (rc == 0)
        rc = link(file, "/pos", g, "Points") | link(file, "/id", g, "Connectivity");
    hid_t pd = rc == 0 ? H5Gcreate2(g, "PointData", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT) : -1;
    if (rc == 0 && pd < 0)
        rc = -1;
    for (int i = 0; rc == 0 && i < nfields; i++) {
        if (&fields[i] == pos)
            continue;
        char target[256];
        snprintf(target, sizeof target, "/%s", fields[i].name);
        rc = link(file, target, pd, fields[i].name);
    }
    if (pd >= 0)
        H5Gclose(pd);
    if (g >= 0)
        H5Gclose(g);
    free(offsets), free(types);
    return rc;
}
