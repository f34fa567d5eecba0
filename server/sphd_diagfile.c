/*
 * The diagnostics time series in one HDF5 file, written in SWMR mode (readers open it with
 * swmr=True while the job runs):
 *   /diag    one extendible table (a compound dataset): a row per diag event, `step` then the
 *            columns, integers as int64 and the rest as float64; attribute `units`, one per member;
 *   /rows    (1,) int64: the rows complete, written and flushed after each row's data, so that a
 *            reader that reads `rows` first and then at most that many rows never sees a torn row;
 *   /step, /t, ...  the same series one dataset per column (each with a `units` attribute), the
 *            layout of earlier versions, kept for the readers written for it; also flushed
 *            before `rows`.
 * The file is created complete under a temporary name and renamed before SWMR writing starts; a
 * resumed job rebuilds it from the rows up to its checkpoint's step the same way, so a crash
 * mid-write never leaves a file that cannot be opened as the latest one.
 */
#include "sphd_h5.h"
#include "sphd_h5_util.h"

#include <errno.h>
#include <hdf5.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define DIAG_MAX_COLUMNS SPHD_DIAG_MAX_COLUMNS
#define DIAG_CHUNK       256

struct sphd_diagfile {
    hid_t file;
    hid_t table;                       /* /diag */
    hid_t count;                       /* /rows */
    hid_t rowtype;                     /* the table's compound type (memory = file) */
    hid_t dsets[DIAG_MAX_COLUMNS + 1]; /* the per-column datasets; [0] is "step" */
    unsigned char integer[DIAG_MAX_COLUMNS + 1];
    int ncolumns; /* value columns, "step" excluded */
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
static int read_rows(const char *path, const sphd_diag_column *columns, int ncolumns, long max_step,
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
    /* a column may hold more rows than "step": the appends flush "step" last, so a writer
     * killed in between leaves the later columns one row longer; only the first n are read */
    double *col = rc == 0 ? malloc((n ? n : 1) * sizeof *col) : NULL;
    for (int c = 0; rc == 0 && c < ncolumns; c++) {
        hid_t d = H5Dopen2(f, columns[c].name, H5P_DEFAULT);
        if (d < 0)
            continue; /* a column the old file lacks stays zero */
        hsize_t m = 0;
        hid_t sp = H5Dget_space(d);
        H5Sget_simple_extent_dims(sp, &m, NULL);
        hsize_t start[1] = {0}, count[1] = {n};
        hid_t ms = H5Screate_simple(1, count, NULL);
        if (m >= n && n > 0 &&
            H5Sselect_hyperslab(sp, H5S_SELECT_SET, start, NULL, count, NULL) >= 0 &&
            H5Dread(d, H5T_NATIVE_DOUBLE, ms, sp, H5P_DEFAULT, col) >= 0)
            for (long r = 0; r < keep; r++)
                out->values[(size_t)r * (size_t)ncolumns + (size_t)c] = col[r];
        H5Sclose(ms);
        H5Sclose(sp);
        H5Dclose(d);
    }
    free(col);
    H5Fclose(f);
    H5Eclear2(H5E_DEFAULT);
    out->rows = keep;
    return rc;
}

/* The table's row: "step" and the columns, 8 bytes each. */
static hid_t row_type(const sphd_diag_column *columns, int ncolumns)
{
    hid_t t = H5Tcreate(H5T_COMPOUND, 8 * (size_t)(ncolumns + 1));
    H5Tinsert(t, "step", 0, H5T_NATIVE_LLONG);
    for (int c = 0; c < ncolumns; c++)
        H5Tinsert(t, columns[c].name, 8 * (size_t)(c + 1),
                  columns[c].integer ? H5T_NATIVE_LLONG : H5T_NATIVE_DOUBLE);
    return t;
}

/* Packs one row: step, then each value (rounded in the integer columns: integer[c] != 0). */
static void pack_row(unsigned char *row, const unsigned char *integer, int ncolumns, long long step,
                     const double *values)
{
    memcpy(row, &step, 8);
    for (int c = 0; c < ncolumns; c++) {
        if (integer[c]) {
            const long long v = (long long)llround(values[c]);
            memcpy(row + 8 * (c + 1), &v, 8);
        } else {
            memcpy(row + 8 * (c + 1), &values[c], 8);
        }
    }
}

/* An extendible 1D dataset of `rows` elements of `type` (chunked), with a `units` attribute. */
static hid_t create_series(hid_t file, const char *name, hid_t type, long rows, const void *data,
                           const char *units)
{
    hsize_t dims[1] = {(hsize_t)rows}, maxdims[1] = {H5S_UNLIMITED}, chunk[1] = {DIAG_CHUNK};
    hid_t space = H5Screate_simple(1, dims, maxdims);
    hid_t dcpl = H5Pcreate(H5P_DATASET_CREATE);
    H5Pset_chunk(dcpl, 1, chunk);
    hid_t d = H5Dcreate2(file, name, type, space, H5P_DEFAULT, dcpl, H5P_DEFAULT);
    int rc = d < 0 ? -1 : 0;
    if (rc == 0 && rows > 0 && H5Dwrite(d, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0)
        rc = -1;
    if (rc == 0 && units)
        rc = sphd_h5_attr_string(d, "units", units);
    H5Pclose(dcpl);
    H5Sclose(space);
    if (rc != 0 && d >= 0) {
        H5Dclose(d);
        d = -1;
    }
    return d;
}

/* The table's `units`: one fixed-length string per member, "step" first. */
static int table_units(hid_t table, const sphd_diag_column *columns, int ncolumns)
{
    size_t width = 2;
    for (int c = 0; c < ncolumns; c++)
        if (strlen(columns[c].units) + 1 > width)
            width = strlen(columns[c].units) + 1;
    char *buf = calloc((size_t)(ncolumns + 1), width);
    if (!buf)
        return -1;
    strcpy(buf, "1");
    for (int c = 0; c < ncolumns; c++)
        strcpy(buf + width * (size_t)(c + 1), columns[c].units);
    hid_t t = H5Tcopy(H5T_C_S1);
    H5Tset_size(t, width);
    hsize_t n[1] = {(hsize_t)(ncolumns + 1)};
    hid_t sp = H5Screate_simple(1, n, NULL);
    hid_t a = H5Acreate2(table, "units", t, sp, H5P_DEFAULT, H5P_DEFAULT);
    int rc = a < 0 || H5Awrite(a, t, buf) < 0 ? -1 : 0;
    if (a >= 0)
        H5Aclose(a);
    H5Sclose(sp);
    H5Tclose(t);
    free(buf);
    return rc;
}

static int write_count(hid_t count, long rows)
{
    const long long n = rows;
    return H5Dwrite(count, H5T_NATIVE_LLONG, H5S_ALL, H5S_ALL, H5P_DEFAULT, &n) < 0 ? -1 : 0;
}

/* Creates the file complete (with `initial` rows) under a temporary name and renames it. */
static int create_file(const char *path, const sphd_diag_column *columns, int ncolumns,
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
        len += strlen(columns[c].name) + 1;
    char *list = malloc(len + 1);
    int rc = list ? 0 : -1;
    if (list) {
        strcpy(list, "step");
        for (int c = 0; c < ncolumns; c++) {
            strcat(list, ",");
            strcat(list, columns[c].name);
        }
        rc = sphd_h5_attr_string(f, "columns", list);
        free(list);
    }
    const long rows = initial ? initial->rows : 0;
    const size_t rowsize = 8 * (size_t)(ncolumns + 1);
    unsigned char *table = malloc((size_t)(rows ? rows : 1) * rowsize);
    double *col = malloc((size_t)(rows ? rows : 1) * sizeof *col);
    long long *icol = malloc((size_t)(rows ? rows : 1) * sizeof *icol);
    if (!table || !col || !icol)
        rc = -1;
    unsigned char integer[DIAG_MAX_COLUMNS];
    for (int c = 0; c < ncolumns; c++)
        integer[c] = (unsigned char)columns[c].integer;
    for (long r = 0; rc == 0 && r < rows; r++)
        pack_row(table + (size_t)r * rowsize, integer, ncolumns, initial->step[r],
                 initial->values + (size_t)r * (size_t)ncolumns);
    hid_t type = row_type(columns, ncolumns);
    hid_t d = rc == 0 ? create_series(f, "diag", type, rows, table, NULL) : -1;
    if (d < 0 || table_units(d, columns, ncolumns) != 0)
        rc = -1;
    if (d >= 0)
        H5Dclose(d);
    H5Tclose(type);
    if (rc == 0) {
        hsize_t one[1] = {1};
        hid_t sp = H5Screate_simple(1, one, NULL);
        hid_t cnt =
            H5Dcreate2(f, "rows", H5T_NATIVE_LLONG, sp, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
        if (cnt < 0 || write_count(cnt, rows) != 0)
            rc = -1;
        if (cnt >= 0)
            H5Dclose(cnt);
        H5Sclose(sp);
    }
    if (rc == 0) {
        d = create_series(f, "step", H5T_NATIVE_LLONG, rows, initial ? initial->step : NULL, "1");
        rc = d < 0 ? -1 : 0;
        if (d >= 0)
            H5Dclose(d);
    }
    for (int c = 0; rc == 0 && c < ncolumns; c++) {
        for (long r = 0; r < rows; r++) {
            col[r] = initial->values[(size_t)r * (size_t)ncolumns + (size_t)c];
            icol[r] = (long long)llround(col[r]);
        }
        d = columns[c].integer
                ? create_series(f, columns[c].name, H5T_NATIVE_LLONG, rows, icol, columns[c].units)
                : create_series(f, columns[c].name, H5T_NATIVE_DOUBLE, rows, col, columns[c].units);
        rc = d < 0 ? -1 : 0;
        if (d >= 0)
            H5Dclose(d);
    }
    free(table), free(col), free(icol);
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

static void close_all(sphd_diagfile *d)
{
    for (int c = 0; c <= d->ncolumns; c++)
        if (d->dsets[c] >= 0)
            H5Dclose(d->dsets[c]);
    if (d->table >= 0)
        H5Dclose(d->table);
    if (d->count >= 0)
        H5Dclose(d->count);
    if (d->rowtype >= 0)
        H5Tclose(d->rowtype);
    if (d->file >= 0)
        H5Fclose(d->file);
    free(d);
}

sphd_diagfile *sphd_diagfile_open(const char *path, const sphd_diag_column *columns, int ncolumns,
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
    d->table = d->count = d->rowtype = -1;
    for (int c = 0; c <= ncolumns; c++) {
        d->dsets[c] = -1;
        d->integer[c] = (unsigned char)(c == 0 || columns[c - 1].integer);
    }
    hid_t fapl = swmr_fapl();
    d->file = H5Fopen(path, H5F_ACC_RDWR | H5F_ACC_SWMR_WRITE, fapl);
    H5Pclose(fapl);
    if (d->file < 0) {
        sphd_h5_fail(err, "opening diagnostics file", path);
        close_all(d);
        return NULL;
    }
    d->rowtype = row_type(columns, ncolumns);
    d->table = H5Dopen2(d->file, "diag", H5P_DEFAULT);
    d->count = H5Dopen2(d->file, "rows", H5P_DEFAULT);
    int ok = d->rowtype >= 0 && d->table >= 0 && d->count >= 0;
    for (int c = 0; ok && c <= ncolumns; c++) {
        d->dsets[c] = H5Dopen2(d->file, c == 0 ? "step" : columns[c - 1].name, H5P_DEFAULT);
        ok = d->dsets[c] >= 0;
    }
    if (!ok) {
        sphd_h5_fail(err, "opening diagnostics dataset in", path);
        close_all(d);
        return NULL;
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
    unsigned char row[8 * (DIAG_MAX_COLUMNS + 1)];
    errno = 0;
    /* the table's row, then the per-column datasets, all flushed; the count last: a reader that
     * reads `rows` first finds that many whole rows everywhere */
    pack_row(row, d->integer + 1, d->ncolumns, s, values);
    int rc = append_value(d->table, d->rows, d->rowtype, row);
    for (int c = 0; rc == 0 && c <= d->ncolumns; c++)
        rc = append_value(d->dsets[c], d->rows,
                          d->integer[c] ? H5T_NATIVE_LLONG : H5T_NATIVE_DOUBLE, row + 8 * c);
    if (rc == 0 && H5Dflush(d->table) < 0)
        rc = -1;
    for (int c = d->ncolumns; rc == 0 && c >= 0; c--)
        if (H5Dflush(d->dsets[c]) < 0)
            rc = -1;
    if (rc == 0 && (write_count(d->count, d->rows + 1) != 0 || H5Dflush(d->count) < 0))
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
    if (d)
        close_all(d);
}

int sphd_diagfile_export_csv(const char *path, FILE *out, sph_error *err)
{
    sphd_h5_quiet();
    hid_t fapl = swmr_fapl();
    hid_t f = H5Fopen(path, H5F_ACC_RDONLY | H5F_ACC_SWMR_READ, fapl);
    H5Pclose(fapl);
    if (f < 0)
        return sphd_h5_fail(err, "opening diagnostics file", path);
    char list[DIAG_MAX_COLUMNS * 64] = "";
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
    /* the rows complete: `rows` (written after each row), or in files of earlier versions the
     * shortest column (a writer may be between two datasets) */
    hsize_t rows = (hsize_t)-1;
    hid_t cnt = H5Dopen2(f, "rows", H5P_DEFAULT);
    if (cnt >= 0) {
        long long n = 0;
        if (H5Dread(cnt, H5T_NATIVE_LLONG, H5S_ALL, H5S_ALL, H5P_DEFAULT, &n) >= 0 && n >= 0)
            rows = (hsize_t)n;
        H5Dclose(cnt);
    }
    H5Eclear2(H5E_DEFAULT);
    double *cols[DIAG_MAX_COLUMNS + 1] = {0};
    int integer[DIAG_MAX_COLUMNS + 1] = {0};
    int rc = 0;
    for (int c = 0; c < ncol && rc == 0; c++) {
        hid_t d = H5Dopen2(f, names[c], H5P_DEFAULT);
        if (d < 0) {
            rc = -1;
            break;
        }
        H5Drefresh(d);
        hid_t t = H5Dget_type(d);
        integer[c] = H5Tget_class(t) == H5T_INTEGER;
        H5Tclose(t);
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
            for (int c = 0; c < ncol; c++) {
                if (integer[c])
                    fprintf(out, "%s%lld", c ? "," : "", (long long)cols[c][r]);
                else
                    fprintf(out, "%s%.17g", c ? "," : "", cols[c][r]);
            }
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
