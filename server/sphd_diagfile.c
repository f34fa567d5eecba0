/*
 * The diagnostics time series: one extendible dataset per column in one HDF5 file, written in
 * SWMR mode (readers open it with swmr=True while the job runs). The file is created complete
 * under a temporary name and renamed before SWMR writing starts; a resumed job rebuilds it from
 * the rows up to its checkpoint's step the same way, so a crash mid-write never leaves a file
 * that cannot be opened as the latest one.
 */
#include "sphd_h5.h"
#include "sphd_h5_util.h"

#include <errno.h>
#include <hdf5.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define DIAG_MAX_COLUMNS 64
#define DIAG_CHUNK       256

struct sphd_diagfile {
    hid_t file;
    hid_t dsets[DIAG_MAX_COLUMNS + 1]; /* [0] is "step" */
    int ncolumns;                      /* value columns, "step" excluded */
    long rows;
    char path[4096];
};

/* Rows read back from an existing file, to rebuild it. */
typedef struct {
    long rows;
    long long *step;
    double *values; /* rows x ncolumns, row-major */
} diag_rows;

static hid_t swmr_fapl(void)
{
    hid_t fapl = H5Pcreate(H5P_FILE_ACCESS);
    H5Pset_libver_bounds(fapl, H5F_LIBVER_LATEST, H5F_LIBVER_LATEST);
    return fapl;
}

/* Reads rows with step <= max_step from an existing file (any state, via SWMR read). */
static int read_rows(const char *path, const char *const *columns, int ncolumns, long max_step,
                     diag_rows *out)
{
    memset(out, 0, sizeof *out);
    hid_t fapl = swmr_fapl();
    hid_t f = H5Fopen(path, H5F_ACC_RDONLY | H5F_ACC_SWMR_READ, fapl);
    H5Pclose(fapl);
    if (f < 0)
        return -1;
    int rc = 0;
    hid_t ds = H5Dopen2(f, "step", H5P_DEFAULT);
    hsize_t n = 0;
    if (ds < 0) {
        rc = -1;
    } else {
        hid_t sp = H5Dget_space(ds);
        H5Sget_simple_extent_dims(sp, &n, NULL);
        H5Sclose(sp);
        out->step = malloc((n ? n : 1) * sizeof *out->step);
        if (!out->step ||
            (n && H5Dread(ds, H5T_NATIVE_LLONG, H5S_ALL, H5S_ALL, H5P_DEFAULT, out->step) < 0))
            rc = -1;
        H5Dclose(ds);
    }
    long keep = 0;
    while (rc == 0 && (hsize_t)keep < n && out->step[keep] <= max_step)
        keep++;
    if (rc == 0)
        out->values = calloc((size_t)(keep ? keep : 1) * (size_t)ncolumns, sizeof(double));
    if (rc == 0 && !out->values)
        rc = -1;
    double *col = rc == 0 ? malloc((n ? n : 1) * sizeof *col) : NULL;
    for (int c = 0; rc == 0 && c < ncolumns; c++) {
        hid_t d = H5Dopen2(f, columns[c], H5P_DEFAULT);
        if (d < 0)
            continue; /* a column the old file lacks stays zero */
        hsize_t m = 0;
        hid_t sp = H5Dget_space(d);
        H5Sget_simple_extent_dims(sp, &m, NULL);
        H5Sclose(sp);
        if (m >= n && n > 0 &&
            H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, col) >= 0)
            for (long r = 0; r < keep; r++)
                out->values[(size_t)r * (size_t)ncolumns + (size_t)c] = col[r];
        H5Dclose(d);
    }
    free(col);
    H5Fclose(f);
    H5Eclear2(H5E_DEFAULT);
    out->rows = keep;
    return rc;
}

static int write_column(hid_t file, const char *name, hid_t type, long rows, const void *data)
{
    hsize_t dims[1] = {(hsize_t)rows}, maxdims[1] = {H5S_UNLIMITED}, chunk[1] = {DIAG_CHUNK};
    hid_t space = H5Screate_simple(1, dims, maxdims);
    hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
    H5Pset_chunk(dcpl, 1, chunk);
    hid_t d = H5Dcreate2(file, name, type, space, H5P_DEFAULT, dcpl, H5P_DEFAULT);
    int rc = d < 0 ? -1 : 0;
    if (rc == 0 && rows > 0 && H5Dwrite(d, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0)
        rc = -1;
    if (d >= 0)
        H5Dclose(d);
    H5Pclose(dcpl);
    H5Sclose(space);
    return rc;
}

/* Creates the file complete (with `initial` rows) under a temporary name and renames it. */
static int create_file(const char *path, const char *const *columns, int ncolumns,
                       const diag_rows *initial, sph_error *err)
{
    char tmp[4200];
    snprintf(tmp, sizeof tmp, "%s.tmp.%ld", path, (long)getpid());
    hid_t fapl = swmr_fapl();
    errno = 0;
    hid_t f = H5Fcreate(tmp, H5F_ACC_TRUNC, H5P_DEFAULT, fapl);
    H5Pclose(fapl);
    if (f < 0)
        return sphd_h5_fail(err, "creating diagnostics file", tmp);
    /* "columns": the order of the series, for readers and the CSV export */
    size_t len = 5;
    for (int c = 0; c < ncolumns; c++)
        len += strlen(columns[c]) + 1;
    char *list = malloc(len + 1);
    int rc = list ? 0 : -1;
    if (list) {
        strcpy(list, "step");
        for (int c = 0; c < ncolumns; c++) {
            strcat(list, ",");
            strcat(list, columns[c]);
        }
        rc = sphd_h5_attr_string(f, "columns", list);
        free(list);
    }
    const long rows = initial ? initial->rows : 0;
    if (rc == 0)
        rc = write_column(f, "step", H5T_NATIVE_LLONG, rows, initial ? initial->step : NULL);
    double *col = rows ? malloc((size_t)rows * sizeof *col) : NULL;
    for (int c = 0; rc == 0 && c < ncolumns; c++) {
        for (long r = 0; r < rows && col; r++)
            col[r] = initial->values[(size_t)r * (size_t)ncolumns + (size_t)c];
        rc = write_column(f, columns[c], H5T_NATIVE_DOUBLE, rows, col);
    }
    free(col);
    if (rc != 0) {
        sphd_h5_fail(err, "writing diagnostics file", tmp);
        H5Fclose(f);
        unlink(tmp);
        return SPH_ERR_IO;
    }
    if (H5Fclose(f) < 0 || sphd_fsync_path(tmp) != 0 || rename(tmp, path) != 0) {
        int e = errno;
        unlink(tmp);
        return sph_error_set(err, SPH_ERR_IO, "", "saving diagnostics file '%s' failed: %s", path,
                             strerror(e));
    }
    return 0;
}

sphd_diagfile *sphd_diagfile_open(const char *path, const char *const *columns, int ncolumns,
                                  long resume_step, sph_error *err)
{
    sphd_h5_quiet();
    if (ncolumns < 0 || ncolumns > DIAG_MAX_COLUMNS) {
        sph_error_set(err, SPH_ERR_INTERNAL, "", "too many diagnostics columns (%d)", ncolumns);
        return NULL;
    }
    diag_rows old = {0};
    if (resume_step >= 0 && access(path, F_OK) == 0)
        read_rows(path, columns, ncolumns, resume_step, &old);
    int rc = create_file(path, columns, ncolumns, old.rows ? &old : NULL, err);
    free(old.step);
    free(old.values);
    if (rc)
        return NULL;

    sphd_diagfile *d = calloc(1, sizeof *d);
    if (!d) {
        sph_error_set(err, SPH_ERR_NOMEM, "", "out of memory");
        return NULL;
    }
    snprintf(d->path, sizeof d->path, "%s", path);
    d->ncolumns = ncolumns;
    d->rows = old.rows;
    hid_t fapl = swmr_fapl();
    d->file = H5Fopen(path, H5F_ACC_RDWR | H5F_ACC_SWMR_WRITE, fapl);
    H5Pclose(fapl);
    if (d->file < 0) {
        sphd_h5_fail(err, "opening diagnostics file", path);
        free(d);
        return NULL;
    }
    for (int c = 0; c <= ncolumns; c++) {
        d->dsets[c] = H5Dopen2(d->file, c == 0 ? "step" : columns[c - 1], H5P_DEFAULT);
        if (d->dsets[c] < 0) {
            sphd_h5_fail(err, "opening diagnostics dataset in", path);
            for (int j = 0; j < c; j++)
                H5Dclose(d->dsets[j]);
            H5Fclose(d->file);
            free(d);
            return NULL;
        }
    }
    return d;
}

static int append_value(hid_t ds, long row, hid_t type, const void *value)
{
    hsize_t size[1] = {(hsize_t)row + 1}, start[1] = {(hsize_t)row}, count[1] = {1};
    if (H5Dset_extent(ds, size) < 0)
        return -1;
    hid_t fs = H5Dget_space(ds);
    hid_t ms = H5Screate_simple(1, count, NULL);
    herr_t rc = H5Sselect_hyperslab(fs, H5S_SELECT_SET, start, NULL, count, NULL);
    if (rc >= 0)
        rc = H5Dwrite(ds, type, ms, fs, H5P_DEFAULT, value);
    H5Sclose(ms);
    H5Sclose(fs);
    return rc < 0 ? -1 : 0;
}

int sphd_diagfile_append(sphd_diagfile *d, long step, const double *values, sph_error *err)
{
    const long long s = step;
    errno = 0;
    int rc = append_value(d->dsets[0], d->rows, H5T_NATIVE_LLONG, &s);
    for (int c = 0; rc == 0 && c < d->ncolumns; c++)
        rc = append_value(d->dsets[c + 1], d->rows, H5T_NATIVE_DOUBLE, &values[c]);
    /* values first, "step" last: a reader that sees a row's step sees its values */
    for (int c = d->ncolumns; rc == 0 && c >= 0; c--)
        if (H5Dflush(d->dsets[c]) < 0)
            rc = -1;
    if (rc != 0)
        return sphd_h5_fail(err, "appending to diagnostics file", d->path);
    d->rows++;
    return 0;
}

long sphd_diagfile_rows(const sphd_diagfile *d)
{
    return d->rows;
}

void sphd_diagfile_close(sphd_diagfile *d)
{
    if (!d)
        return;
    for (int c = 0; c <= d->ncolumns; c++)
        H5Dclose(d->dsets[c]);
    H5Fclose(d->file);
    free(d);
}

int sphd_diagfile_export_csv(const char *path, FILE *out, sph_error *err)
{
    sphd_h5_quiet();
    hid_t fapl = swmr_fapl();
    hid_t f = H5Fopen(path, H5F_ACC_RDONLY | H5F_ACC_SWMR_READ, fapl);
    H5Pclose(fapl);
    if (f < 0)
        return sphd_h5_fail(err, "opening diagnostics file", path);
    char list[4096] = "";
    hid_t a = H5Aopen(f, "columns", H5P_DEFAULT);
    if (a >= 0) {
        hid_t t = H5Aget_type(a);
        size_t sz = H5Tget_size(t);
        if (sz < sizeof list)
            H5Aread(a, t, list);
        H5Tclose(t);
        H5Aclose(a);
    }
    if (!list[0]) {
        H5Fclose(f);
        return sph_error_set(err, SPH_ERR_IO, "", "'%s' is not a diagnostics file", path);
    }
    char *names[DIAG_MAX_COLUMNS + 1];
    int ncol = 0;
    char *save = NULL;
    for (char *tok = strtok_r(list, ",", &save); tok && ncol <= DIAG_MAX_COLUMNS;
         tok = strtok_r(NULL, ",", &save))
        names[ncol++] = tok;
    /* the shortest column bounds the rows (a writer may be between two datasets) */
    double *cols[DIAG_MAX_COLUMNS + 1] = {0};
    hsize_t rows = (hsize_t)-1;
    int rc = 0;
    for (int c = 0; c < ncol && rc == 0; c++) {
        hid_t d = H5Dopen2(f, names[c], H5P_DEFAULT);
        if (d < 0) {
            rc = -1;
            break;
        }
        H5Drefresh(d);
        hsize_t n = 0;
        hid_t sp = H5Dget_space(d);
        H5Sget_simple_extent_dims(sp, &n, NULL);
        H5Sclose(sp);
        cols[c] = malloc((n ? n : 1) * sizeof(double));
        if (!cols[c] ||
            (n && H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, cols[c]) < 0))
            rc = -1;
        rows = n < rows ? n : rows;
        H5Dclose(d);
    }
    if (rc == 0) {
        for (int c = 0; c < ncol; c++)
            fprintf(out, "%s%s", c ? "," : "", names[c]);
        fputc('\n', out);
        for (hsize_t r = 0; r < rows && ncol > 0; r++) {
            fprintf(out, "%lld", (long long)cols[0][r]);
            for (int c = 1; c < ncol; c++)
                fprintf(out, ",%.17g", cols[c][r]);
            fputc('\n', out);
        }
    }
    for (int c = 0; c < ncol; c++)
        free(cols[c]);
    H5Fclose(f);
    if (rc != 0)
        return sphd_h5_fail(err, "reading diagnostics file", path);
    return 0;
}
