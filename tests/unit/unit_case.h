/*
 * A unit test's case: cases/<name> (under $SPH_SOURCE_DIR) with `--set` overrides, as the sim's
 * config; the test fails on any error. Shared by the tests that build sims from the shipped cases,
 * with the check that two sims hold the same bits (double storage).
 */
#ifndef UNIT_CASE_H
#define UNIT_CASE_H

#include "sph_case.h"
#include "sph_json.h"
#include "sph_sim.h"

#include <stdio.h>
#include <stdlib.h>

/* cases/<name> with the overrides into the whole case *c (the caller clears it with
 * sph_case_clear): 0, or the parser's code with err set (a set that does not apply fails the
 * test). */
static int parse_full_case(const char *name, const char *const *sets, sph_case *c, sph_error *err)
{
    char path[4096];
    const char *src = getenv("SPH_SOURCE_DIR");
    snprintf(path, sizeof path, "%s/cases/%s", src ? src : ".", name);
    json_t *root;
    assert_int_equal(sph_case_load(path, &root, err), 0);
    for (; *sets; sets++)
        if (sph_json_apply_set(root, *sets, err) != 0)
            fail_msg("--set %s: %s", *sets, err->message);
    const int rc = sph_case_from_json(root, c, err);
    json_decref(root);
    return rc;
}

/* The same, its sim's configuration alone into *cfg. */
static int parse_case(const char *name, const char *const *sets, sph_config *cfg, sph_error *err)
{
    sph_case *c = calloc(1, sizeof *c);
    assert_non_null(c);
    const int rc = parse_full_case(name, sets, c, err);
    if (rc == 0)
        *cfg = c->sim;
    free(c);
    return rc;
}

static sph_config load_case(const char *name, const char *const *sets)
{
    sph_config cfg;
    sph_error err;
    if (parse_case(name, sets, &cfg, &err) != 0)
        fail_msg("%s: %s: %s", name, err.path, err.message);
    return cfg;
}

/* Two sims in double storage hold the same bits: positions, velocities, densities and ids in the
 * same order, the same time and step. */
static inline void unit_same_bits(const sph_sim *a, const sph_sim *b)
{
    sph_particle_view va, vb;
    sph_sim_particles(a, &va);
    sph_sim_particles(b, &vb);
    assert_int_equal(va.n, vb.n);
    const size_t n = (size_t)va.n * sizeof(double);
    for (int d = 0; d < va.dim; d++) {
        assert_memory_equal(va.pos[d], vb.pos[d], n);
        assert_memory_equal(va.vel[d], vb.vel[d], n);
    }
    assert_memory_equal(va.rho, vb.rho, n);
    assert_memory_equal(va.id, vb.id, (size_t)va.n * sizeof(int));
    assert_true(sph_sim_time(a) == sph_sim_time(b));
    assert_int_equal(sph_sim_diag(a)->step, sph_sim_diag(b)->step);
}

#endif
