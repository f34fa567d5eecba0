/*
 * Case parsing, data-driven: every tests/cases/invalid/NAME.json is rejected with SPH_ERR_INVALID
 * and the JSON pointer in NAME.expect (empty: a file-level error); every cases/ *.json is valid.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "sph_case.h"
#include "sph_case_table.h"
#include "sph_json.h"

#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char *srcdir(void)
{
    const char *s = getenv("SPH_SOURCE_DIR");
    return s ? s : ".";
}

static int ends_with(const char *s, const char *suffix)
{
    size_t n = strlen(s), m = strlen(suffix);
    return n >= m && strcmp(s + n - m, suffix) == 0;
}

/* Loads and parses one case file; returns the first error's code (0: valid). */
static int parse_file(const char *path, sph_error *err)
{
    json_t *root = NULL;
    sph_case *c = calloc(1, sizeof *c);
    assert_non_null(c);
    int rc = sph_case_load(path, &root, err);
    if (rc == 0)
        rc = sph_case_from_json(root, c, err);
    sph_case_clear(c); /* a polygon's surface (cases/wave_runup.json's beach) */
    free(c);
    json_decref(root);
    return rc;
}

static void test_invalid_cases(void **state)
{
    (void)state;
    char dir[4096];
    snprintf(dir, sizeof dir, "%s/tests/cases/invalid", srcdir());
    DIR *d = opendir(dir);
    assert_non_null(d);
    int count = 0;
    struct dirent *e;
    while ((e = readdir(d))) {
        if (!ends_with(e->d_name, ".json"))
            continue;
        char path[8192], expect_path[8192], want[256] = "";
        snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
        snprintf(expect_path, sizeof expect_path, "%.*s.expect", (int)(strlen(path) - 5), path);
        FILE *f = fopen(expect_path, "r");
        assert_non_null(f);
        if (fgets(want, sizeof want, f))
            want[strcspn(want, "\n")] = '\0';
        fclose(f);

        sph_error err;
        int rc = parse_file(path, &err);
        if (rc != SPH_ERR_INVALID)
            fail_msg("%s: expected invalid_case, got code %d", e->d_name, rc);
        if (strcmp(err.path, want) != 0)
            fail_msg("%s: error names '%s', expected '%s' (%s)", e->d_name, err.path, want,
                     err.message);
        assert_true(strlen(err.message) > 10);
        count++;
    }
    closedir(d);
    assert_true(count >= 20);
}

static void test_shipped_cases_valid(void **state)
{
    (void)state;
    char dir[4096];
    snprintf(dir, sizeof dir, "%s/cases", srcdir());
    DIR *d = opendir(dir);
    assert_non_null(d);
    int count = 0;
    struct dirent *e;
    while ((e = readdir(d))) {
        if (!ends_with(e->d_name, ".json"))
            continue;
        char path[8192];
        snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
        sph_error err;
        if (parse_file(path, &err))
            fail_msg("%s: %s (at %s)", e->d_name, err.message, err.path);
        count++;
    }
    closedir(d);
    assert_true(count >= 1);
}

/* The mps object lands in sph_config.mps, names as their values, defaults where absent. */
static void test_mps_fields(void **state)
{
    (void)state;
    sph_error err;
    json_t *root = json_loads(
        "{\"method\": \"mps\", \"kernel\": {\"type\": \"sheu_quartic\"}, \"dx\": 0.01, "
        "\"domain\": {\"min\": [0, 0], \"max\": [1, 1]}, "
        "\"fluid\": [{\"box\": {\"min\": [0, 0], \"max\": [0.2, 0.2]}}], "
        "\"boundary\": {\"layers\": 4, \"tank\": {\"min\": [0, 0], \"max\": [1, 0.5]}}, "
        "\"physics\": {\"viscosity\": {\"type\": \"laminar\", \"nu\": 1e-6}}, "
        "\"mps\": {\"re\": 2.0, \"re_grad\": 2.5, \"beta\": 0.95, \"tol\": 1e-6, "
        "\"max_iterations\": 300, \"preconditioner\": \"jacobi\", \"source\": \"mixed\", "
        "\"relaxation\": 0.01, \"gradient\": \"corrected\", \"surface\": \"water_line\", "
        "\"collision\": 0.5, \"restitution\": 0.1}, \"time\": {\"end\": 0.1}}",
        0, NULL);
    assert_non_null(root);
    sph_case *c = calloc(1, sizeof *c);
    assert_non_null(c);
    if (sph_case_from_json(root, c, &err))
        fail_msg("%s (at %s)", err.message, err.path);
    const sph_mps_config *m = &c->sim.mps;
    assert_int_equal(c->method, SPH_METHOD_MPS);
    assert_int_equal(c->sim.kernel.type, SPH_KERNEL_SHEU_QUARTIC);
    assert_true(m->re == 2.0 && m->re_grad == 2.5 && m->beta == 0.95 && m->tol == 1e-6);
    assert_int_equal(m->maxit, 300);
    assert_int_equal(m->precond, 1);
    assert_int_equal(m->source, 1);
    assert_true(m->relax == 0.01);
    assert_int_equal(m->corrected, 1);
    assert_int_equal(m->surface, 1);
    assert_true(m->collision == 0.5 && m->restitution == 0.1);
    json_object_del(root, "mps"); /* the defaults: Koshizuka & Oka's */
    if (sph_case_from_json(root, c, &err))
        fail_msg("%s (at %s)", err.message, err.path);
    const sph_mps_config def = sph_mps_config_default();
    assert_memory_equal(&c->sim.mps, &def, sizeof def);
    free(c);
    json_decref(root);
}

static void test_apply_set(void **state)
{
    (void)state;
    sph_error err;
    json_t *root = json_loads("{\"dx\": 0.01, \"kernel\": {\"type\": \"wendland_c2\"}, "
                              "\"kernels\": [{\"type\": \"double_cosine\"}]}",
                              0, NULL);
    assert_int_equal(sph_json_apply_set(root, "dx=0.004", &err), 0);
    assert_true(json_real_value(json_object_get(root, "dx")) == 0.004);
    assert_int_equal(sph_json_apply_set(root, "kernel.type=cubic_spline", &err), 0);
    assert_string_equal(json_string_value(json_object_get(json_object_get(root, "kernel"), "type")),
                        "cubic_spline");
    assert_int_equal(sph_json_apply_set(root, "kernels.0.kappa=2.5", &err), 0);
    assert_true(json_number_value(json_object_get(
                    json_array_get(json_object_get(root, "kernels"), 0), "kappa")) == 2.5);
    assert_int_equal(sph_json_apply_set(root, "output.every=0.1", &err), 0);
    assert_true(json_is_object(json_object_get(root, "output")));
    assert_int_equal(sph_json_apply_set(root, "kernels.3.kappa=2", &err), SPH_ERR_INVALID);
    assert_int_equal(sph_json_apply_set(root, "dx.y=2", &err), SPH_ERR_INVALID);
    assert_int_equal(sph_json_apply_set(root, "novalue", &err), SPH_ERR_INVALID);
    assert_int_equal(sph_json_apply_set(root, "=3", &err), SPH_ERR_INVALID);
    json_decref(root);
}

/* The case table's defaults are the core's (sph_config_default), and its rows are well formed:
 * every parent is an object row listed before its children, every `when` names an enum row. */
static void test_table_defaults(void **state)
{
    (void)state;
    const sph_config def = sph_config_default();
    int checked = 0;
    for (const sph_case_field *f = sph_case_fields; f->path; f++) {
        const char *slash = strrchr(f->path, '/');
        const int element = strstr(f->path, "/*/") != NULL; /* a row of an array's elements */
        if (slash != f->path) {
            /* the parent: an object row, or for an element row the array row above the "*" */
            const size_t plen = (size_t)(slash - f->path) - (element ? 2 : 0);
            int found = 0;
            for (const sph_case_field *g = sph_case_fields; g < f; g++)
                found |= (g->type == (element ? SPH_CF_ARRAY : SPH_CF_OBJECT)) &&
                         strlen(g->path) == plen && strncmp(g->path, f->path, plen) == 0;
            if (!found)
                fail_msg("%s: no object row before it for its parent", f->path);
        }
        if (f->when) {
            const char *eq = strchr(f->when, '=');
            int found = 0;
            for (const sph_case_field *g = sph_case_fields; g < f; g++)
                found |= (g->type == SPH_CF_ENUM || g->type == SPH_CF_INTEGER) &&
                         strlen(g->path) == (size_t)(eq - f->when) &&
                         strncmp(g->path, f->when, (size_t)(eq - f->when)) == 0;
            if (!found)
                fail_msg("%s: its condition '%s' names no enum or integer row before it", f->path,
                         f->when);
        }
        if (f->dst != SPH_CF_CFG || !(f->has_def || f->type == SPH_CF_NAMES) || element)
            continue; /* element rows land in an element (no default element to compare) */
        const char *p = (const char *)&def + f->off;
        switch (f->type) {
        case SPH_CF_NUMBER:
            if (*(const double *)p != f->def)
                fail_msg("%s: table default %g, sph_config_default %g", f->path, f->def,
                         *(const double *)p);
            break;
        case SPH_CF_INTEGER: {
            const long v = f->size == sizeof(long) ? *(const long *)p : *(const int *)p;
            if (v != (long)f->def)
                fail_msg("%s: table default %g, sph_config_default %ld", f->path, f->def, v);
            break;
        }
        case SPH_CF_ENUM: {
            const int want = f->values ? f->values[(int)f->def] : (int)f->def;
            if (*(const int *)p != want)
                fail_msg("%s: table default %d, sph_config_default %d", f->path, want,
                         *(const int *)p);
            break;
        }
        case SPH_CF_NAMES:
            if (*(const unsigned *)p != f->def_mask)
                fail_msg("%s: table default %#x, sph_config_default %#x", f->path, f->def_mask,
                         *(const unsigned *)p);
            break;
        default:
            fail_msg("%s: a default on a row of this type is not supported", f->path);
        }
        checked++;
    }
    print_message("case table: %d defaults agree with sph_config_default()\n", checked);
    assert_true(checked >= 15);
}

/* A number out of range names the interval with its open and closed ends as the table has them. */
static void test_range_messages(void **state)
{
    (void)state;
    static const struct {
        const char *file, *set, *path, *want;
    } rows[] = {
        {"dambreak.json", "dx=2000", "/dx", "'dx' must be in (0, 1000], got 2000"},
        {"dambreak.json", "dx=0", "/dx", "'dx' must be in (0, 1000], got 0"},
        {"mps_dambreak.json", "mps.beta=1", "/mps/beta", "'beta' must be in (0, 1), got 1"},
        {"mps_dambreak.json", "mps.re=7", "/mps/re", "'re' must be in (1, 6], got 7"},
        {"mps_dambreak.json", "mps.collision=-0.5", "/mps/collision",
         "'collision' must be in [0, 1), got -0.5"},
    };
    for (size_t r = 0; r < sizeof rows / sizeof rows[0]; r++) {
        char path[4096];
        snprintf(path, sizeof path, "%s/cases/%s", srcdir(), rows[r].file);
        json_t *root = NULL;
        sph_error err;
        assert_int_equal(sph_case_load(path, &root, &err), 0);
        assert_int_equal(sph_json_apply_set(root, rows[r].set, &err), 0);
        sph_case *c = calloc(1, sizeof *c);
        assert_non_null(c);
        assert_int_equal(sph_case_from_json(root, c, &err), SPH_ERR_INVALID);
        assert_string_equal(err.path, rows[r].path);
        assert_string_equal(err.message, rows[r].want);
        free(c);
        json_decref(root);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_invalid_cases),  cmocka_unit_test(test_shipped_cases_valid),
        cmocka_unit_test(test_mps_fields),     cmocka_unit_test(test_apply_set),
        cmocka_unit_test(test_table_defaults), cmocka_unit_test(test_range_messages),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
