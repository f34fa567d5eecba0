/*
 * sphd_exec on a WCSPH case, as `sphd --run` and the daemon's workers drive it: bounded slices
 * (max_steps, until), diag events every diagnostics.every steps, progress, particle queries
 * (downsampled), the result at t_end; a blow-up fails with `unstable`.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "sph_json.h"
#include "sphd_exec.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct events {
    int ndiag, nresult;
    long last_step;
} events;

static void on_event(void *ud, const char *type, json_t *body)
{
    events *e = ud;
    if (strcmp(type, "diag") == 0) {
        e->ndiag++;
        e->last_step = (long)json_integer_value(json_object_get(body, "step"));
        assert_non_null(json_object_get(body, "front_x"));
        assert_true(json_is_number(json_object_get(body, "rho_min")));
    } else if (strcmp(type, "result") == 0) {
        e->nresult++;
    }
    json_decref(body);
}

static sph_case *load(const char *const *sets, int nsets)
{
    char file[4096];
    const char *src = getenv("SPH_SOURCE_DIR");
    snprintf(file, sizeof file, "%s/cases/dambreak.json", src ? src : ".");
    sph_error err;
    json_t *root;
    assert_int_equal(sph_case_load(file, &root, &err), 0);
    for (int i = 0; i < nsets; i++)
        assert_int_equal(sph_json_apply_set(root, sets[i], &err), 0);
    sph_case *c = calloc(1, sizeof *c);
    assert_int_equal(sph_case_from_json(root, c, &err), 0);
    json_decref(root);
    return c;
}

static void test_slices(void **state)
{
    (void)state;
    const char *sets[] = {"dx=0.005", "time.end=0.01", "diagnostics.every=10"};
    sph_case *c = load(sets, 3);
    sph_error err;
    sphd_exec *x = sphd_exec_new(c, NULL, &err);
    assert_non_null(x);
    events e = {0};
    /* 25 steps: diag at 0 (initial), 10, 20 */
    assert_int_equal(sphd_exec_advance(x, 25, INFINITY, on_event, &e, &err), SPHD_EXEC_RUNNING);
    assert_int_equal(e.ndiag, 3);
    assert_int_equal(e.last_step, 20);
    json_t *p = sphd_exec_progress(x);
    assert_int_equal(json_integer_value(json_object_get(p, "step")), 25);
    assert_true(json_real_value(json_object_get(p, "t_end")) == 0.01);
    assert_non_null(json_object_get(p, "diag"));
    json_decref(p);
    /* until: stops at t = 0.005 exactly */
    assert_int_equal(sphd_exec_advance(x, 100000, 0.005, on_event, &e, &err), SPHD_EXEC_RUNNING);
    p = sphd_exec_progress(x);
    assert_true(json_real_value(json_object_get(p, "t")) == 0.005);
    json_decref(p);
    /* particles, downsampled */
    const char *fields[] = {"pos", "rho", "type"};
    json_t *q = sphd_exec_particles(x, fields, 3, 100, &err);
    assert_non_null(q);
    assert_int_equal(json_integer_value(json_object_get(q, "count")), 100);
    assert_int_equal(json_integer_value(json_object_get(q, "total")), 800 + 1338);
    json_t *pos = json_object_get(json_object_get(q, "fields"), "pos");
    assert_int_equal(json_array_size(pos), 100);
    assert_int_equal(json_array_size(json_array_get(pos, 0)), 2);
    json_decref(q);
    const char *bad[] = {"temperature"};
    assert_null(sphd_exec_particles(x, bad, 1, 100, &err));
    assert_int_equal(err.code, SPH_ERR_INVALID);
    /* to the end: result once, then DONE */
    sphd_exec_status st;
    while ((st = sphd_exec_advance(x, 1000, INFINITY, on_event, &e, &err)) == SPHD_EXEC_RUNNING)
        ;
    assert_int_equal(st, SPHD_EXEC_DONE);
    assert_int_equal(e.nresult, 1);
    assert_int_equal(sphd_exec_advance(x, 1000, INFINITY, on_event, &e, &err), SPHD_EXEC_DONE);
    assert_int_equal(e.nresult, 1);
    sphd_exec_free(x);
    free(c);
}

static void test_unstable(void **state)
{
    (void)state;
    const char *sets[] = {"dx=0.005", "time.dt=0.001"};
    sph_case *c = load(sets, 2);
    sph_error err;
    sphd_exec *x = sphd_exec_new(c, NULL, &err);
    assert_non_null(x);
    events e = {0};
    sphd_exec_status st;
    while ((st = sphd_exec_advance(x, 1000, INFINITY, on_event, &e, &err)) == SPHD_EXEC_RUNNING)
        ;
    assert_int_equal(st, SPHD_EXEC_FAILED);
    assert_int_equal(err.code, SPH_ERR_UNSTABLE);
    assert_non_null(strstr(err.message, "step"));
    assert_int_equal(e.nresult, 0);
    sphd_exec_free(x);
    free(c);
}

static void test_too_large(void **state)
{
    (void)state;
    const char *sets[] = {"dx=1e-5"};
    sph_case *c = load(sets, 1);
    sph_error err;
    assert_null(sphd_exec_new(c, NULL, &err));
    assert_int_equal(err.code, SPH_ERR_NOMEM);
    assert_string_equal(err.path, "/dx");
    free(c);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_slices),
        cmocka_unit_test(test_unstable),
        cmocka_unit_test(test_too_large),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
