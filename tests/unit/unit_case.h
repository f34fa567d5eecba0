/*
 * A unit test's case: cases/<name> (under $SPH_SOURCE_DIR) with `--set` overrides, as the sim's
 * config; the test fails on any error. Shared by the tests that build sims from the shipped cases.
 */
#ifndef UNIT_CASE_H
#define UNIT_CASE_H

#include "sph_case.h"
#include "sph_json.h"

#include <stdio.h>
#include <stdlib.h>

static sph_config load_case(const char *name, const char *const *sets)
{
    char path[4096];
    const char *src = getenv("SPH_SOURCE_DIR");
    snprintf(path, sizeof path, "%s/cases/%s", src ? src : ".", name);
    json_t *root;
    sph_error err;
    assert_int_equal(sph_case_load(path, &root, &err), 0);
    for (; *sets; sets++)
        if (sph_json_apply_set(root, *sets, &err) != 0)
            fail_msg("--set %s: %s", *sets, err.message);
    sph_case *c = calloc(1, sizeof *c);
    if (sph_case_from_json(root, c, &err) != 0)
        fail_msg("%s: %s: %s", name, err.path, err.message);
    sph_config cfg = c->sim;
    free(c);
    json_decref(root);
    return cfg;
}

#endif
