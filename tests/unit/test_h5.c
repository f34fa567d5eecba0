/*
 * HDF5 outputs: snapshots (attributes, datasets, shapes, values, compression, no temporary file
 * left), the XDMF sidecar, the diagnostics series (append, resume truncating to a step, CSV), and
 * an unwritable directory giving an io_error instead of a crash.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "sphd_h5.h"

#include <dirent.h>
#include <hdf5.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

static char dir[256];

static int setup(void **state)
{
    (void)state;
    const char *keep = getenv("SPH_TEST_OUT");
    if (keep) {
        snprintf(dir, sizeof dir, "%s", keep);
        mkdir(dir, 0700);
    } else {
        snprintf(dir, sizeof dir, "/tmp/sphd-test-h5-XXXXXX");
        assert_non_null(mkdtemp(dir));
    }
    return 0;
}

#define N 1000

typedef struct {
    double x[N], y[N], u[N], v[N], rho[N];
    float p[N];
    int8_t type[N];
    int64_t id[N];
} particles;

static void fill(particles *P, double t)
{
    for (int i = 0; i < N; i++) {
        P->x[i] = 0.001 * i + t;
        P->y[i] = 0.002 * (i % 37);
        P->u[i] = -1.0 * i;
        P->v[i] = 0.5 * i;
        P->rho[i] = 1000.0 + 0.01 * i;
        P->p[i] = (float)(100.0 * i);
        P->type[i] = (int8_t)(i < 800 ? 0 : 1);
        P->id[i] = i;
    }
}

static int make_fields(const particles *P, sphd_h5_field *f)
{
    f[0] = (sphd_h5_field){"pos", "m", SPHD_H5_F64, 2, {P->x, P->y, NULL}};
    f[1] = (sphd_h5_field){"vel", "m/s", SPHD_H5_F64, 2, {P->u, P->v, NULL}};
    f[2] = (sphd_h5_field){"rho", "kg/m^3", SPHD_H5_F64, 1, {P->rho}};
    f[3] = (sphd_h5_field){"p", "Pa", SPHD_H5_F32, 1, {P->p}};
    f[4] = (sphd_h5_field){"type", "", SPHD_H5_I8, 1, {P->type}};
    f[5] = (sphd_h5_field){"id", "", SPHD_H5_I64, 1, {P->id}};
    return 6;
}

static void test_snapshot(void **state)
{
    (void)state;
    particles *P = calloc(1, sizeof *P);
    fill(P, 0.25);
    sphd_h5_field f[6];
    int nf = make_fields(P, f);
    enum { NB = 40 };
    double q[NB], count[NB], dens[NB];
    for (int b = 0; b < NB; b++) {
        q[b] = (b + 0.5) * 0.05;
        count[b] = 3.0 * b;
        dens[b] = 0.025 * b;
    }
    const sphd_h5_rpdf rpdf = {NB, 2.0, q, count, dens};
    sphd_h5_header h = {.t = 0.25,
                        .step = 1234,
                        .dim = 2,
                        .dx = 0.005,
                        .kernel = "wendland_c2",
                        .job = "unit",
                        .n = N,
                        .n_fluid = 800,
                        .n_boundary = 200,
                        .n_body = 0,
                        .mass = 0.025,
                        .h = 0.007,
                        .rpdf = &rpdf};
    char path[512];
    snprintf(path, sizeof path, "%s/snap_000001.h5", dir);
    sph_error err;
    assert_int_equal(sphd_h5_write_snapshot(path, &h, f, nf, 4, &err), 0);

    hid_t file = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
    assert_true(file >= 0);
    double t;
    long long step, n;
    hid_t a = H5Aopen(file, "time", H5P_DEFAULT);
    H5Aread(a, H5T_NATIVE_DOUBLE, &t);
    H5Aclose(a);
    a = H5Aopen(file, "step", H5P_DEFAULT);
    H5Aread(a, H5T_NATIVE_LLONG, &step);
    H5Aclose(a);
    a = H5Aopen(file, "n_fluid", H5P_DEFAULT);
    H5Aread(a, H5T_NATIVE_LLONG, &n);
    H5Aclose(a);
    assert_true(t == 0.25);
    assert_int_equal(step, 1234);
    assert_int_equal(n, 800);
    /* pos is (N, 3), zero-padded z */
    hid_t d = H5Dopen2(file, "pos", H5P_DEFAULT);
    hid_t sp = H5Dget_space(d);
    hsize_t dims[2];
    assert_int_equal(H5Sget_simple_extent_ndims(sp), 2);
    H5Sget_simple_extent_dims(sp, dims, NULL);
    assert_int_equal(dims[0], N);
    assert_int_equal(dims[1], 3);
    double *pos = malloc(sizeof(double) * 3 * N);
    H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, pos);
    for (int i = 0; i < N; i++) {
        assert_true(pos[3 * i] == P->x[i]);
        assert_true(pos[3 * i + 1] == P->y[i]);
        assert_true(pos[3 * i + 2] == 0.0);
    }
    free(pos);
    /* compressed with deflate */
    hid_t dcpl = H5Dget_create_plist(d);
    assert_true(H5Pget_nfilters(dcpl) == 2);
    H5Pclose(dcpl);
    H5Sclose(sp);
    H5Dclose(d);
    float p[N];
    d = H5Dopen2(file, "p", H5P_DEFAULT);
    H5Dread(d, H5T_NATIVE_FLOAT, H5S_ALL, H5S_ALL, H5P_DEFAULT, p);
    H5Dclose(d);
    assert_true(p[999] == P->p[999]);
    /* mass and smoothing length as attributes */
    double mass = 0, hh = 0;
    a = H5Aopen(file, "mass", H5P_DEFAULT);
    H5Aread(a, H5T_NATIVE_DOUBLE, &mass);
    H5Aclose(a);
    a = H5Aopen(file, "h", H5P_DEFAULT);
    H5Aread(a, H5T_NATIVE_DOUBLE, &hh);
    H5Aclose(a);
    assert_true(mass == 0.025 && hh == 0.007);
    /* ParaView's VTKHDF layout: the arrays are the same datasets (links), offsets 0..N */
    H5O_info_t o1, o2; /* HDF5 1.10: objects by address */
    assert_true(H5Oget_info_by_name2(file, "pos", &o1, H5O_INFO_BASIC, H5P_DEFAULT) >= 0);
    assert_true(H5Oget_info_by_name2(file, "VTKHDF/Points", &o2, H5O_INFO_BASIC, H5P_DEFAULT) >= 0);
    assert_true(o1.addr == o2.addr);
    assert_int_equal(o1.rc, 2);
    assert_true(
        H5Oget_info_by_name2(file, "VTKHDF/PointData/rho", &o2, H5O_INFO_BASIC, H5P_DEFAULT) >= 0);
    assert_int_equal(o2.rc, 2);
    long long off[N + 1];
    d = H5Dopen2(file, "VTKHDF/Offsets", H5P_DEFAULT);
    H5Dread(d, H5T_NATIVE_LLONG, H5S_ALL, H5S_ALL, H5P_DEFAULT, off);
    H5Dclose(d);
    assert_int_equal(off[0], 0);
    assert_int_equal(off[N], N);
    /* the RPDF: a group of three (NB) float64 datasets with units, and what it is */
    int bins = 0;
    double qmax = 0;
    a = H5Aopen_by_name(file, "rpdf", "bins", H5P_DEFAULT, H5P_DEFAULT);
    H5Aread(a, H5T_NATIVE_INT, &bins);
    H5Aclose(a);
    a = H5Aopen_by_name(file, "rpdf", "qmax", H5P_DEFAULT, H5P_DEFAULT);
    H5Aread(a, H5T_NATIVE_DOUBLE, &qmax);
    H5Aclose(a);
    assert_int_equal(bins, NB);
    assert_true(qmax == 2.0);
    assert_true(H5Aexists_by_name(file, "rpdf", "description", H5P_DEFAULT) > 0);
    const char *names[] = {"rpdf/q", "rpdf/count", "rpdf/density"};
    const double *want[] = {q, count, dens};
    for (int k = 0; k < 3; k++) {
        d = H5Dopen2(file, names[k], H5P_DEFAULT);
        assert_true(d >= 0);
        sp = H5Dget_space(d);
        assert_int_equal(H5Sget_simple_extent_ndims(sp), 1);
        H5Sget_simple_extent_dims(sp, dims, NULL);
        assert_int_equal(dims[0], NB);
        H5Sclose(sp);
        double got[NB];
        H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, got);
        for (int b = 0; b < NB; b++)
            assert_true(got[b] == want[k][b]);
        assert_true(H5Aexists(d, "units") > 0);
        H5Dclose(d);
    }
    /* not a field: ParaView's layout does not take it up */
    assert_int_equal(H5Lexists(file, "VTKHDF/PointData/rpdf", H5P_DEFAULT), 0);
    H5Fclose(file);

    /* nothing but the final file: no *.tmp.* left */
    DIR *dd = opendir(dir);
    struct dirent *e;
    while ((e = readdir(dd)))
        assert_null(strstr(e->d_name, ".tmp."));
    closedir(dd);
    free(P);
}

static void test_xdmf(void **state)
{
    (void)state;
    particles *P = calloc(1, sizeof *P);
    sphd_h5_field f[6];
    int nf = make_fields(P, f);
    sphd_xdmf_entry e[3];
    sph_error err;
    for (int i = 0; i < 3; i++) {
        fill(P, 0.1 * i);
        snprintf(e[i].file, sizeof e[i].file, "snap_%06d.h5", i + 10);
        e[i].t = 0.1 * i;
        e[i].step = 100 * i;
        e[i].n = N;
        sphd_h5_header h = {.t = e[i].t,
                            .step = e[i].step,
                            .dim = 2,
                            .dx = 0.005,
                            .kernel = "wendland_c2",
                            .job = "unit",
                            .n = N,
                            .n_fluid = 800,
                            .n_boundary = 200};
        char path[1200];
        snprintf(path, sizeof path, "%s/%s", dir, e[i].file);
        assert_int_equal(sphd_h5_write_snapshot(path, &h, f, nf, 0, &err), 0);
        if (i == 0) { /* without an RPDF, no group */
            hid_t file = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
            assert_int_equal(H5Lexists(file, "rpdf", H5P_DEFAULT), 0);
            H5Fclose(file);
        }
        char xmf[512];
        snprintf(xmf, sizeof xmf, "%s/particles.xmf", dir);
        assert_int_equal(sphd_xdmf_write(xmf, e, i + 1, f, nf, &err), 0);
    }
    char xmf[512];
    snprintf(xmf, sizeof xmf, "%s/particles.xmf", dir);
    FILE *x = fopen(xmf, "r");
    assert_non_null(x);
    char buf[65536];
    size_t len = fread(buf, 1, sizeof buf - 1, x);
    buf[len] = '\0';
    fclose(x);
    assert_non_null(strstr(buf, "CollectionType=\"Temporal\""));
    assert_non_null(strstr(buf, "snap_000012.h5:/pos"));
    assert_non_null(strstr(buf, "<Time Value=\"0.20000000000000001\"/>"));
    assert_non_null(strstr(buf, "Dimensions=\"1000 3\" NumberType=\"Float\" Precision=\"8\""));
    assert_non_null(
        strstr(buf, "NumberType=\"Char\" Precision=\"1\" Format=\"HDF\">snap_000010.h5:/type"));
    free(P);
}

/* Exports the diagnostics file at path as CSV (to dir/NAME) and reads it back: its header line,
 * its data rows and its last line. */
static int export_csv(const char *path, const char *name, char *header, char *last)
{
    char csv[512];
    snprintf(csv, sizeof csv, "%s/%s", dir, name);
    FILE *out = fopen(csv, "w");
    sph_error err;
    assert_int_equal(sphd_diagfile_export_csv(path, out, &err), 0);
    fclose(out);
    FILE *in = fopen(csv, "r");
    char line[512];
    assert_non_null(fgets(header, 512, in));
    int rows = 0;
    while (fgets(line, sizeof line, in)) {
        rows++;
        strcpy(last, line);
    }
    fclose(in);
    return rows;
}

static void test_diagfile(void **state)
{
    (void)state;
    const sphd_diag_column cols[] = {
        {"t", "s", 0}, {"dt", "s", 0}, {"ekin", "J/m", 0}, {"lost", "1", 1}};
    char path[512];
    snprintf(path, sizeof path, "%s/diag.h5", dir);
    sph_error err;
    sphd_diagfile *d = sphd_diagfile_open(path, cols, 4, -1, &err);
    assert_non_null(d);
    for (long s = 0; s < 50; s++) {
        double v[4] = {1e-3 * s, 1e-3, 0.5 * s, (double)(s / 7)};
        assert_int_equal(sphd_diagfile_append(d, s * 10, v, &err), 0);
    }
    assert_int_equal(sphd_diagfile_rows(d), 50);
    sphd_diagfile_close(d);

    /* resume at step 200: rows with step <= 200 kept (21 rows), then continue */
    d = sphd_diagfile_open(path, cols, 4, 200, &err);
    assert_non_null(d);
    assert_int_equal(sphd_diagfile_rows(d), 21);
    double v[4] = {9, 9, 9, 9};
    assert_int_equal(sphd_diagfile_append(d, 210, v, &err), 0);
    sphd_diagfile_close(d);

    char header[512], last[512] = "";
    assert_int_equal(export_csv(path, "diag.csv", header, last), 22);
    assert_string_equal(header, "step,t,dt,ekin,lost\n");
    assert_string_equal(last, "210,9,9,9,9\n");

    /* the table: 22 rows, counted by /rows; lost is an integer; units per member */
    hid_t f = H5Fopen(path, H5F_ACC_RDONLY, H5P_DEFAULT);
    long long count = 0;
    hid_t ds = H5Dopen2(f, "rows", H5P_DEFAULT);
    H5Dread(ds, H5T_NATIVE_LLONG, H5S_ALL, H5S_ALL, H5P_DEFAULT, &count);
    H5Dclose(ds);
    assert_int_equal(count, 22);
    ds = H5Dopen2(f, "diag", H5P_DEFAULT);
    hid_t sp = H5Dget_space(ds);
    hsize_t n = 0;
    H5Sget_simple_extent_dims(sp, &n, NULL);
    H5Sclose(sp);
    assert_int_equal(n, 22);
    hid_t t = H5Dget_type(ds);
    assert_int_equal(H5Tget_nmembers(t), 5);
    assert_int_equal(H5Tget_member_class(t, 4), H5T_INTEGER);
    assert_int_equal(H5Tget_member_class(t, 1), H5T_FLOAT);
    H5Tclose(t);
    assert_true(H5Aexists(ds, "units") > 0);
    H5Dclose(ds);
    ds = H5Dopen2(f, "lost", H5P_DEFAULT);
    t = H5Dget_type(ds);
    assert_int_equal(H5Tget_class(t), H5T_INTEGER);
    H5Tclose(t);
    H5Dclose(ds);
    H5Fclose(f);
}

/* A writer killed inside an append leaves the columns it flushed before "step" one row longer
 * (the appends flush "step" last): a resume reads the rows "step" has, and no more (it once read
 * the longer columns whole into a buffer of that size: a heap overflow, "double free or
 * corruption" in the daemon's crash-recovery test). Run under ASan by the sanitizer suite. */
static void test_diagfile_torn_row(void **state)
{
    (void)state;
    const sphd_diag_column cols[] = {{"t", "s", 0}, {"ekin", "J/m", 0}, {"lost", "1", 1}};
    char path[512];
    snprintf(path, sizeof path, "%s/torn.h5", dir);
    sph_error err;
    sphd_diagfile *d = sphd_diagfile_open(path, cols, 3, -1, &err);
    assert_non_null(d);
    for (long s = 0; s < 30; s++) {
        double v[3] = {0.5 * s, 2.0 * s, 0.0};
        assert_int_equal(sphd_diagfile_append(d, s, v, &err), 0);
    }
    sphd_diagfile_close(d);
    /* the torn row: ekin and lost extended by 7 rows, step and t not */
    hid_t f = H5Fopen(path, H5F_ACC_RDWR, H5P_DEFAULT);
    assert_true(f >= 0);
    for (int k = 0; k < 2; k++) {
        hid_t ds = H5Dopen2(f, k ? "lost" : "ekin", H5P_DEFAULT);
        hsize_t size[1] = {37};
        assert_true(H5Dset_extent(ds, size) >= 0);
        H5Dclose(ds);
    }
    H5Fclose(f);
    d = sphd_diagfile_open(path, cols, 3, 1000, &err);
    assert_non_null(d);
    assert_int_equal(sphd_diagfile_rows(d), 30);
    sphd_diagfile_close(d);
    char header[512], last[512] = "";
    assert_int_equal(export_csv(path, "torn.csv", header, last), 30);
    assert_string_equal(last, "29,14.5,58,0\n");
}

static void test_unwritable(void **state)
{
    (void)state;
    particles *P = calloc(1, sizeof *P);
    sphd_h5_field f[6];
    int nf = make_fields(P, f);
    sphd_h5_header h = {.n = N, .dim = 2};
    sph_error err;
    assert_int_equal(sphd_h5_write_snapshot("/nonexistent-dir/x.h5", &h, f, nf, 0, &err),
                     SPH_ERR_IO);
    assert_non_null(strstr(err.message, "/nonexistent-dir/x.h5"));
    const sphd_diag_column cols[] = {{"t", "s", 0}};
    assert_null(sphd_diagfile_open("/nonexistent-dir/diag.h5", cols, 1, -1, &err));
    assert_int_equal(err.code, SPH_ERR_IO);
    free(P);
}

/* Disk full (a file-size limit, which binds root too): the snapshot write fails with io_error,
 * the file already at that path is untouched and no temporary file is left. */
static void test_disk_full(void **state)
{
    (void)state;
    particles *P = calloc(1, sizeof *P);
    fill(P, 0.5);
    sphd_h5_field f[6];
    int nf = make_fields(P, f);
    sphd_h5_header h = {.t = 0.5, .step = 7, .dim = 2, .n = N, .n_fluid = N};
    char path[512];
    snprintf(path, sizeof path, "%s/full.h5", dir);
    sph_error err;
    assert_int_equal(sphd_h5_write_snapshot(path, &h, f, nf, 0, &err), 0);
    struct stat before;
    stat(path, &before);
    pid_t pid = fork();
    assert_true(pid >= 0);
    if (pid == 0) {
        signal(SIGXFSZ, SIG_IGN);
        struct rlimit rl = {16 * 1024, 16 * 1024};
        setrlimit(RLIMIT_FSIZE, &rl);
        h.step = 8;
        int rc = sphd_h5_write_snapshot(path, &h, f, nf, 0, &err);
        _exit(rc == SPH_ERR_IO ? 0 : 1);
    }
    int status;
    waitpid(pid, &status, 0);
    assert_true(WIFEXITED(status) && WEXITSTATUS(status) == 0);
    struct stat after;
    stat(path, &after);
    assert_int_equal(before.st_size, after.st_size);
    assert_int_equal(before.st_ino, after.st_ino);
    DIR *dd = opendir(dir);
    struct dirent *e;
    while ((e = readdir(dd)))
        assert_null(strstr(e->d_name, ".tmp."));
    closedir(dd);
    free(P);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_snapshot),   cmocka_unit_test(test_xdmf),
        cmocka_unit_test(test_diagfile),   cmocka_unit_test(test_diagfile_torn_row),
        cmocka_unit_test(test_unwritable), cmocka_unit_test(test_disk_full),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
