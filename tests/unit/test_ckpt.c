/*
 * Checkpoint files: round trip; rotation keeps the previous one; every kind of damage to the
 * latest (a flipped byte anywhere, truncation, a torn write, a missing file) is detected and the
 * previous checkpoint used; both damaged is an error; a full disk leaves the old ones intact.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "sphd_ckpt.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

static char dir[64];

static int setup(void **state)
{
    (void)state;
    snprintf(dir, sizeof dir, "/tmp/sphd-test-ckpt-XXXXXX");
    return mkdtemp(dir) ? 0 : -1;
}

static int teardown(void **state)
{
    (void)state;
    char cmd[128];
    snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
    return system(cmd) == 0 ? 0 : -1;
}

#define NVAL 100001 /* odd: exercises the padding */

static void write_gen(int gen)
{
    double *v = malloc(NVAL * sizeof *v);
    for (int i = 0; i < NVAL; i++)
        v[i] = gen * 1000.0 + i;
    char text[32];
    snprintf(text, sizeof text, "generation %d", gen);
    sphd_ckpt_section s[] = {
        {"case", text, strlen(text) + 1}, {"particles", v, NVAL * sizeof *v}, {"empty", NULL, 0}};
    sph_error err;
    assert_int_equal(sphd_ckpt_write(dir, s, 3, &err), 0);
    free(v);
}

static int loaded_gen(int *fell_back)
{
    sph_error err;
    sphd_ckpt *c = sphd_ckpt_load(dir, fell_back, &err);
    if (!c)
        return -1;
    size_t n;
    const double *v = sphd_ckpt_get(c, "particles", &n);
    assert_non_null(v);
    assert_int_equal(n, NVAL * sizeof(double));
    const char *text = sphd_ckpt_get(c, "case", &n);
    int gen = (int)(v[0] / 1000.0);
    char want[32];
    snprintf(want, sizeof want, "generation %d", gen);
    assert_string_equal(text, want);
    for (int i = 0; i < NVAL; i++)
        assert_true(v[i] == gen * 1000.0 + i);
    assert_non_null(sphd_ckpt_get(c, "empty", &n));
    assert_int_equal(n, 0);
    assert_null(sphd_ckpt_get(c, "nope", &n));
    sphd_ckpt_free(c);
    return gen;
}

static void corrupt_latest(long offset_from_start, int truncate_to)
{
    char path[128];
    snprintf(path, sizeof path, "%s/checkpoint", dir);
    if (truncate_to >= 0) {
        assert_int_equal(truncate(path, truncate_to), 0);
        return;
    }
    FILE *f = fopen(path, "r+b");
    fseek(f, offset_from_start, SEEK_SET);
    int c = fgetc(f);
    fseek(f, offset_from_start, SEEK_SET);
    fputc(c ^ 0x20, f);
    fclose(f);
}

static void test_round_trip_and_rotation(void **state)
{
    (void)state;
    int fb;
    write_gen(1);
    assert_int_equal(loaded_gen(&fb), 1);
    assert_int_equal(fb, 0);
    write_gen(2);
    assert_int_equal(loaded_gen(&fb), 2);
    assert_int_equal(fb, 0);
}

static void test_damage_falls_back(void **state)
{
    (void)state;
    char path[128];
    snprintf(path, sizeof path, "%s/checkpoint", dir);
    struct stat st;
    /* a flipped byte in the header, a section header, the data, the padding area, the trailer */
    const long offsets[] = {3, 12, 40, 100, 5000, 400000, -10, -3};
    for (size_t i = 0; i < sizeof offsets / sizeof offsets[0]; i++) {
        write_gen(3);
        write_gen(4);
        stat(path, &st);
        long off = offsets[i] >= 0 ? offsets[i] : (long)st.st_size + offsets[i];
        corrupt_latest(off, -1);
        int fb;
        if (loaded_gen(&fb) != 3 || fb != 1)
            fail_msg("a flipped byte at offset %ld was not detected", off);
    }
    /* truncation (a torn write) */
    write_gen(5);
    write_gen(6);
    stat(path, &st);
    corrupt_latest(0, (int)(st.st_size / 2));
    int fb;
    assert_int_equal(loaded_gen(&fb), 5);
    assert_int_equal(fb, 1);
    /* latest missing (crash between the two renames) */
    write_gen(7);
    write_gen(8);
    unlink(path);
    assert_int_equal(loaded_gen(&fb), 7);
    assert_int_equal(fb, 1);
}

static void test_both_bad(void **state)
{
    (void)state;
    write_gen(9);
    write_gen(10);
    corrupt_latest(50, -1);
    char prev[128];
    snprintf(prev, sizeof prev, "%s/checkpoint.prev", dir);
    assert_int_equal(truncate(prev, 10), 0);
    sph_error err;
    assert_null(sphd_ckpt_load(dir, NULL, &err));
    assert_int_equal(err.code, SPH_ERR_IO);
    assert_non_null(strstr(err.message, "corrupt"));
}

/* Disk full (a file-size limit, which binds root too): the write fails with io_error, no
 * temporary file is left, and the checkpoints that were there load as before. */
static void test_disk_full_keeps_old(void **state)
{
    (void)state;
    write_gen(11);
    write_gen(12);
    pid_t pid = fork();
    assert_true(pid >= 0);
    if (pid == 0) {
        signal(SIGXFSZ, SIG_IGN);
        struct rlimit rl = {256 * 1024, 256 * 1024};
        setrlimit(RLIMIT_FSIZE, &rl);
        double *v = calloc(NVAL, sizeof *v);
        sphd_ckpt_section s[] = {{"particles", v, NVAL * sizeof *v}};
        sph_error err;
        int rc = sphd_ckpt_write(dir, s, 1, &err);
        _exit(rc == SPH_ERR_IO && strstr(err.message, "File too large") ? 0 : 1);
    }
    int status;
    waitpid(pid, &status, 0);
    assert_true(WIFEXITED(status) && WEXITSTATUS(status) == 0);
    int fb;
    assert_int_equal(loaded_gen(&fb), 12);
    assert_int_equal(fb, 0);
    char cmd[160];
    snprintf(cmd, sizeof cmd, "ls %s | grep -q tmp", dir);
    assert_true(system(cmd) != 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_round_trip_and_rotation),
        cmocka_unit_test(test_damage_falls_back),
        cmocka_unit_test(test_both_bad),
        cmocka_unit_test(test_disk_full_keeps_old),
    };
    return cmocka_run_group_tests(tests, setup, teardown);
}
