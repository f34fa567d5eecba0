/*
 * sph_sim_save / sph_sim_restore: a run saved at step 150 and restored continues bitwise like the
 * run that was never interrupted (positions, velocities, densities, time, step), with 1 thread and
 * with 2; a damaged state is refused. The MPS dam break with Koshizuka & Oka's settings (the
 * collision model) and the dynamic stabilization gives the same bits with 1 and 2 threads. The
 * AMG preconditioner (mps.preconditioner "amg"): with -DSPH_HYPRE=ON the MPS dam break saved and
 * restored continues bitwise; without it, the case is refused at /mps/preconditioner.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "sph_case.h"
#include "sph_json.h"
#include "sph_sim.h"

#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* A case of cases/ with `--set` items (NULL-terminated). */
static sph_config load_case(const char *name, const char *const *sets)
{
    char path[4096];
    const char *src = getenv("SPH_SOURCE_DIR");
    snprintf(path, sizeof path, "%s/cases/%s", src ? src : ".", name);
    json_t *root;
    sph_error err;
    assert_int_equal(sph_case_load(path, &root, &err), 0);
    for (; *sets; sets++)
        assert_int_equal(sph_json_apply_set(root, *sets, &err), 0);
    sph_case *c = calloc(1, sizeof *c);
    assert_int_equal(sph_case_from_json(root, c, &err), 0);
    sph_config cfg = c->sim;
    free(c);
    json_decref(root);
    return cfg;
}

static sph_config dambreak(void)
{
    static const char *const sets[] = {"dx=0.01", NULL};
    return load_case("dambreak.json", sets);
}

static void compare(const sph_sim *a, const sph_sim *b)
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
    assert_memory_equal(va.p, vb.p, n);
    assert_memory_equal(va.id, vb.id, (size_t)va.n * sizeof(int));
    assert_true(sph_sim_time(a) == sph_sim_time(b));
    assert_int_equal(sph_sim_diag(a)->step, sph_sim_diag(b)->step);
}

/* Runs cfg n1 steps, saves, runs n2 more; the restored state runs the same n2 steps to the same
 * bits; a damaged state is refused. Returns the first sim (the caller destroys it). */
static sph_sim *save_restore(const sph_config *cfg, long n1, long n2)
{
    sph_error err;
    sph_sim *a = sph_sim_create(cfg, &err);
    assert_non_null(a);
    assert_int_equal(sph_sim_step(a, n1, &err), 0);
    void *buf;
    size_t len;
    assert_int_equal(sph_sim_save(a, &buf, &len, &err), 0);
    assert_int_equal(sph_sim_step(a, n2, &err), 0);

    sph_sim *b = sph_sim_restore(buf, len, &err);
    assert_non_null(b);
    assert_int_equal(sph_sim_diag(b)->step, n1);
    assert_int_equal(sph_sim_step(b, n2, &err), 0);
    compare(a, b);

    /* damaged: truncated, bad magic */
    assert_null(sph_sim_restore(buf, len / 2, &err));
    assert_int_equal(err.code, SPH_ERR_IO);
    ((char *)buf)[0] ^= 1;
    assert_null(sph_sim_restore(buf, len, &err));
    assert_int_equal(err.code, SPH_ERR_IO);
    free(buf);
    sph_sim_destroy(b);
    return a;
}

static void run_case(int threads)
{
    omp_set_num_threads(threads);
    const sph_config cfg = dambreak();
    sph_sim_destroy(save_restore(&cfg, 150, 120));
}

static void test_restore_one_thread(void **state)
{
    (void)state;
    run_case(1);
}

static void test_restore_two_threads(void **state)
{
    (void)state;
    run_case(2);
}

/* The MPS dam break at L/40 (3,200 fluid particles and the walls: above SPH_OMP_MIN, so its loops
 * run in parallel) with the collision model and the stabilization both acting, 200 steps: the
 * same bits with 1 and 2 threads (both move positions after their pair loops). */
static void test_mps_threads(void **state)
{
    (void)state;
    static const char *const sets[] = {"dx=0.00365",           "mps.collision=0.5",
                                       "mps.source=density",   "mps.relaxation=1",
                                       "mps.gradient=minimum", NULL};
    const sph_config cfg = load_case("mps_dambreak.json", sets);
    const int saved = omp_get_max_threads();
    sph_sim *sim[2];
    sph_error err;
    for (int t = 0; t < 2; t++) {
        omp_set_num_threads(t + 1);
        sim[t] = sph_sim_create(&cfg, &err);
        assert_non_null(sim[t]);
        assert_int_equal(sph_sim_step(sim[t], 200, &err), 0);
    }
    omp_set_num_threads(saved);
    sph_particle_view v;
    sph_sim_particles(sim[0], &v);
    assert_true(v.n >= 4096);
    compare(sim[0], sim[1]);
    sph_sim_destroy(sim[0]);
    sph_sim_destroy(sim[1]);
}

/* The MPS dam break at L/40 with mps.preconditioner "amg". */
static void test_mps_amg(void **state)
{
    (void)state;
    char path[4096];
    const char *src = getenv("SPH_SOURCE_DIR");
    snprintf(path, sizeof path, "%s/cases/mps_dambreak.json", src ? src : ".");
    json_t *root;
    sph_error err;
    assert_int_equal(sph_case_load(path, &root, &err), 0);
    assert_int_equal(sph_json_apply_set(root, "dx=0.00365", &err), 0);
    assert_int_equal(sph_json_apply_set(root, "mps.preconditioner=amg", &err), 0);
    sph_case *c = calloc(1, sizeof *c);
    const int rc = sph_case_from_json(root, c, &err);
    json_decref(root);
#ifdef SPH_HYPRE
    assert_int_equal(rc, 0);
    const sph_config cfg = c->sim;
    free(c);
    sph_sim *a = save_restore(&cfg, 100, 60);
    const sph_diag *d = sph_sim_diag(a);
    printf("amg: step %ld, CG %ld iterations, residual %.2e\n", d->step, (long)d->cg_iterations,
           d->cg_residual);
    assert_true(d->cg_residual <= cfg.mps.tol);
    sph_sim_destroy(a);
#else
    free(c);
    assert_int_not_equal(rc, 0);
    assert_string_equal(err.path, "/mps/preconditioner");
    assert_non_null(strstr(err.message, "built without hypre"));
#endif
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_restore_one_thread),
        cmocka_unit_test(test_restore_two_threads),
        cmocka_unit_test(test_mps_threads),
        cmocka_unit_test(test_mps_amg),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
