/*
 * sph_sim_save / sph_sim_restore: a run saved at step 150 and restored continues bitwise like the
 * run that was never interrupted (positions, velocities, densities, time, step), with 1 thread and
 * with 2; a damaged state is refused. The MPS dam break with Koshizuka & Oka's settings (the
 * collision model) and the dynamic stabilization gives the same bits with 1 and 2 threads. The
 * AMG preconditioner (mps.preconditioner "amg"): with -DSPH_HYPRE=ON the MPS dam break saved and
 * restored continues bitwise; without it, the case is refused at /mps/preconditioner.
 * Mixed precision ("precision": "mixed"): saved and restored it continues bitwise too (dynamic
 * and ghost walls, 2D and 3D), with 1 thread and 2 the same bits; the dam break's front at
 * t = 0.3 s within 0.5% of the double run's; its bytes per particle; the refusals. A WCSPH
 * view's pressure, derived (not stored), is the EOS of its density, in double and in mixed.
 */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "sph_case.h"
#include "sph_eos.h"
#include "sph_json.h"
#include "sph_particles.h"
#include "sph_sim.h"

#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The case file at rel (under the source tree) with `--set` items (NULL-terminated), parsed into
 * *cfg: 0, or the parser's code with err set. */
static int parse_case(const char *rel, const char *const *sets, sph_config *cfg, sph_error *err)
{
    char path[4096];
    const char *src = getenv("SPH_SOURCE_DIR");
    snprintf(path, sizeof path, "%s/%s", src ? src : ".", rel);
    json_t *root;
    assert_int_equal(sph_case_load(path, &root, err), 0);
    for (; *sets; sets++)
        assert_int_equal(sph_json_apply_set(root, *sets, err), 0);
    sph_case *c = calloc(1, sizeof *c);
    assert_non_null(c);
    const int rc = sph_case_from_json(root, c, err);
    if (rc == 0)
        *cfg = c->sim;
    free(c);
    json_decref(root);
    return rc;
}

/* A case of cases/ with `--set` items (NULL-terminated). */
static sph_config load_case(const char *name, const char *const *sets)
{
    char rel[256];
    snprintf(rel, sizeof rel, "cases/%s", name);
    sph_config cfg;
    sph_error err;
    assert_int_equal(parse_case(rel, sets, &cfg, &err), 0);
    return cfg;
}

static sph_config dambreak(void)
{
    static const char *const sets[] = {"dx=0.01", NULL};
    return load_case("dambreak.json", sets);
}

/* A WCSPH view's pressure is derived, not stored: the EOS of the view's density, rounded to float
 * under mixed precision as the float storage of it was. */
static void check_pressure(const sph_sim *s, const sph_particle_view *v)
{
    const sph_config *c = sph_sim_config(s);
    for (long i = 0; i < v->n; i++) {
        if (v->rho)
            assert_true(v->p[i] == sph_eos_pressure(c, v->rho[i]));
        else
            assert_true(v->p32[i] == (float)sph_eos_pressure(c, (double)v->rho32[i]));
    }
}

static void compare(const sph_sim *a, const sph_sim *b)
{
    sph_particle_view va, vb;
    sph_sim_particles(a, &va);
    sph_sim_particles(b, &vb);
    assert_int_equal(va.n, vb.n);
    const size_t n = (size_t)va.n * sizeof(double), nf = (size_t)va.n * sizeof(float);
    for (int d = 0; d < va.dim; d++) {
        assert_memory_equal(va.pos[d], vb.pos[d], n);
        if (va.vel[d])
            assert_memory_equal(va.vel[d], vb.vel[d], n);
        else
            assert_memory_equal(va.vel32[d], vb.vel32[d], nf);
    }
    if (va.rho) {
        assert_memory_equal(va.rho, vb.rho, n);
        assert_memory_equal(va.p, vb.p, n);
    } else {
        assert_memory_equal(va.rho32, vb.rho32, nf);
        assert_memory_equal(va.p32, vb.p32, nf);
    }
    assert_memory_equal(va.id, vb.id, (size_t)va.n * sizeof(int));
    if (sph_sim_config(a)->method == SPH_METHOD_WCSPH)
        check_pressure(a, &va);
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

/* With particle shifting (physics.shifting, no state across steps), dynamic walls and ghost
 * walls: the restored state runs to the same bits. */
static void test_shifting_restore(void **state)
{
    (void)state;
    omp_set_num_threads(2);
    static const char *const d2[] = {"dx=0.01", NULL};
    static const char *const ghost[] = {"dx=0.01", NULL};
    sph_config cfgs[] = {load_case("dambreak.json", d2), load_case("dambreak_ghost.json", ghost)};
    for (size_t k = 0; k < sizeof cfgs / sizeof cfgs[0]; k++) {
        cfgs[k].shifting.type = SPH_SHIFT_LIND;
        sph_sim_destroy(save_restore(&cfgs[k], 150, 120));
    }
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
    static const char *const sets[] = {"dx=0.00365", "mps.preconditioner=amg", NULL};
    sph_config cfg;
    sph_error err;
    const int rc = parse_case("cases/mps_dambreak.json", sets, &cfg, &err);
#ifdef SPH_HYPRE
    assert_int_equal(rc, 0);
    sph_sim *a = save_restore(&cfg, 100, 60);
    const sph_diag *d = sph_sim_diag(a);
    printf("amg: step %ld, CG %ld iterations, residual %.2e\n", d->step, (long)d->cg_iterations,
           d->cg_residual);
    assert_true(d->cg_residual <= cfg.mps.tol);
    sph_sim_destroy(a);
#else
    assert_int_not_equal(rc, 0);
    assert_string_equal(err.path, "/mps/preconditioner");
    assert_non_null(strstr(err.message, "built without hypre"));
#endif
}

/* Mixed precision: the dam break (dynamic walls) and its ghost-wall form in 2D, and the 3D still
 * water with ghost walls, saved and restored, continue bitwise; 1 and 2 threads give the same
 * bits. */
static void test_mixed_restore(void **state)
{
    (void)state;
    static const char *const d2[] = {"dx=0.01", "precision=mixed", NULL};
    static const char *const ghost[] = {"dx=0.01", "precision=mixed", NULL};
    const sph_config cfgs[] = {load_case("dambreak.json", d2),
                               load_case("dambreak_ghost.json", ghost)};
    const int saved = omp_get_max_threads();
    for (size_t k = 0; k < sizeof cfgs / sizeof cfgs[0]; k++) {
        assert_int_equal(cfgs[k].precision, SPH_PRECISION_MIXED);
        sph_sim *run[2];
        for (int t = 0; t < 2; t++) {
            omp_set_num_threads(t + 1);
            run[t] = save_restore(&cfgs[k], 150, 120);
        }
        compare(run[0], run[1]);
        sph_particle_view v;
        sph_sim_particles(run[0], &v);
        assert_null(v.vel[0]);
        assert_non_null(v.vel32[0]);
        sph_sim_destroy(run[0]);
        sph_sim_destroy(run[1]);
    }
    omp_set_num_threads(saved);
    /* 3D: still water with ghost walls on every side (tests/cases/ghost_still3d.json) */
    static const char *const g3[] = {"precision=mixed", NULL};
    sph_config c3;
    sph_error err;
    assert_int_equal(parse_case("tests/cases/ghost_still3d.json", g3, &c3, &err), 0);
    sph_sim_destroy(save_restore(&c3, 40, 30));
}

/* The front of the 2D dam break at t = 0.3 s (about 3.7 in t sqrt(2g/D)), mixed against double:
 * within 0.5% (the bound); the kinetic energies printed. */
static void test_mixed_front(void **state)
{
    (void)state;
    static const char *const sd[] = {"dx=0.004", NULL};
    static const char *const sm[] = {"dx=0.004", "precision=mixed", NULL};
    const sph_config cfg[2] = {load_case("dambreak.json", sd), load_case("dambreak.json", sm)};
    double front[2], ekin[2];
    sph_error err;
    for (int k = 0; k < 2; k++) {
        sph_sim *s = sph_sim_create(&cfg[k], &err);
        assert_non_null(s);
        while (sph_sim_time(s) < 0.3 - 1e-12)
            assert_int_equal(sph_sim_advance(s, 1000000, 0.3, &err), 0);
        front[k] = sph_sim_diag(s)->front_x;
        ekin[k] = sph_sim_diag(s)->ekin;
        sph_sim_destroy(s);
    }
    const double rel = (front[1] - front[0]) / front[0];
    printf("front at t = 0.3 s: double %.6f m, mixed %.6f m (%+.4f%%); ekin %.6g / %.6g J\n",
           front[0], front[1], 100.0 * rel, ekin[0], ekin[1]);
    assert_true(fabs(rel) <= 0.005);
}

/* A case of cases/ with "precision": "mixed" (and `set`, if not NULL) is refused at /precision,
 * the message naming `why`. */
static void refused(const char *name, const char *set, const char *why)
{
    char rel[256];
    snprintf(rel, sizeof rel, "cases/%s", name);
    const char *const sets[] = {"precision=mixed", set, NULL};
    sph_config cfg;
    sph_error err;
    assert_int_not_equal(parse_case(rel, sets, &cfg, &err), 0);
    printf("%s with %s: refused at %s: %s\n", name, set ? set : "mixed", err.path, err.message);
    assert_int_equal(err.code, SPH_ERR_INVALID);
    assert_string_equal(err.path, "/precision");
    assert_non_null(strstr(err.message, why));
}

/* Bytes per particle of the storage (printed): mixed at most 90 in 2D and 120 in 3D (issue 24);
 * refusals at /precision. */
static void test_mixed_bytes_and_refusals(void **state)
{
    (void)state;
    const size_t b[4] = {sph_particles_bytes_per_particle(2, 0),
                         sph_particles_bytes_per_particle(2, SPH_PARTICLES_MIXED),
                         sph_particles_bytes_per_particle(3, 0),
                         sph_particles_bytes_per_particle(3, SPH_PARTICLES_MIXED)};
    printf("bytes per particle: 2D double %zu, mixed %zu; 3D double %zu, mixed %zu\n", b[0], b[1],
           b[2], b[3]);
    assert_true(b[1] <= 90 && b[3] <= 120 && b[1] < b[0] && b[3] < b[2]);
    refused("dambreak.json", "physics.turbulence=sps", "SPS");
    refused("mps_dambreak.json", NULL, "wcsph");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_mixed_bytes_and_refusals),
        cmocka_unit_test(test_mixed_restore),
        cmocka_unit_test(test_mixed_front),
        cmocka_unit_test(test_restore_one_thread),
        cmocka_unit_test(test_shifting_restore),
        cmocka_unit_test(test_restore_two_threads),
        cmocka_unit_test(test_mps_threads),
        cmocka_unit_test(test_mps_amg),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
