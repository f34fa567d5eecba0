/*
 * sph_wcsph_step: the WCSPH method's time integration and its row of the method table. Velocity
 * Verlet with one force evaluation per step, the velocity-dependent terms evaluated with the
 * predicted velocity, and the density advanced with the trapezoidal rule over the two density
 * rates:
 *
 *     x(n+1)  = x(n) + dt v(n) + dt^2/2 a(n)
 *     v*      = v(n) + dt a(n),            rho* = rho(n) + dt D(n)
 *     a(n+1), D(n+1) from (x(n+1), v*, rho*)
 *     v(n+1)  = v* + dt/2 (a(n+1) - a(n)), rho(n+1) = rho* + dt/2 (D(n+1) - D(n))
 *
 * The time step is fixed (the case's `time.dt`) or adaptive: dt = CFL min(h / (c0 + vmax),
 * sqrt(h / amax)), and at most h^2 / (8 nu) with laminar viscosity.
 * Rigid bodies (boundary/sph_body.h) follow the same scheme as a whole: predicted with the
 * fluid, their particles placed rigidly before the force evaluation, which sums the force on
 * them, corrected with the fluid; dt also respects their particles' speed and acceleration.
 * After every step the state is checked: non-finite values, density outside [rho0/2, 2 rho0],
 * too many particles lost, a collapsing time step are blow-ups reported with the step.
 * With ghost walls, a particle the predictor takes across a wall is reflected back into the
 * tank (sph_wall_ghost_reflect).
 * A wavemaker's paddle is placed at the step's end time after the predictor (its law is a
 * function of time: sph_wavemaker.h); a damping zone relaxes the fluid's velocity after the
 * corrector.
 */
#include "sph_wcsph.h"
#include "sph_wcsph_particle.h"

#include <math.h>
#include <omp.h>
#include <string.h>

#define SPH_RHO_LOW  0.5 /* density collapse below rho0 times this */
#define SPH_RHO_HIGH 2.0 /* and above rho0 times this */
/* An adaptive dt below this fraction of cfl h / c0 is a blow-up (it would take forever). */
#define SPH_DT_COLLAPSE 1e-3

double sph_wcsph_dt(const sph_sim *s)
{
    const sph_config *c = &s->cfg;
    if (c->dt_fixed > 0.0)
        return c->dt_fixed;
    double dt = s->h / (c->c0 + s->vmax);
    if (s->amax > 0.0) {
        const double df = sqrt(s->h / s->amax);
        dt = df < dt ? df : dt;
    }
    dt *= c->cfl;
    if (c->visc == SPH_VISC_LAMINAR && c->nu > 0.0) {
        const double dv = 0.125 * s->h * s->h / c->nu;
        dt = dv < dt ? dv : dt;
    }
    return dt;
}

static void swap(double **a, double **b)
{
    double *t = *a;
    *a = *b;
    *b = t;
}

static void swapf(float **a, float **b)
{
    float *t = *a;
    *a = *b;
    *b = t;
}

/* The first non-finite particle, for the message. */
static long first_bad(const sph_particles *P, long n)
{
    const int M = P->mixed;
    for (long i = 0; i < n; i++)
        if (!isfinite(P->x[i]) || !isfinite(P->y[i]) || !isfinite(SPH_GET(M, P, vx, i)) ||
            !isfinite(SPH_GET(M, P, vy, i)) || !isfinite(SPH_GET(M, P, rho, i)) ||
            (P->z && (!isfinite(P->z[i]) || !isfinite(SPH_GET(M, P, vz, i)))))
            return i;
    return -1;
}

static step_ctx step_ctx_of(sph_sim *s)
{
    const sph_config *c = &s->cfg;
    step_ctx k = {.P = &s->P,
                  .ghost = &s->ghost,
                  .rho0 = c->rho0,
                  .ghosts = c->boundary == SPH_BOUNDARY_GHOST};
    for (int d = 0; d < 3; d++) {
        k.lo[d] = c->domain.min[d];
        k.hi[d] = c->domain.max[d];
    }
    return k;
}

/* The predictor over the first n particles, predict<D><M> (D and M, mixed precision, literals
 * there); returns the particles whose new position is not finite. */
/* clang-format off */
#define SPH_PREDICT_LOOP(D, M)                                                                     \
    static long predict##D##M(const step_ctx *kp, double dt, long n)                               \
    {                                                                                              \
        const step_ctx k = *kp;                                                                    \
        long bad = 0;                                                                              \
        _Pragma("omp parallel for schedule(dynamic, SPH_OMP_CHUNK) firstprivate(k) reduction(+ : bad) if (n >= SPH_OMP_MIN)") \
        for (long i = 0; i < n; i++)                                                               \
            bad += predict_one(D, M, &k, dt, i);                                                   \
        return bad;                                                                                \
    }
/* clang-format on */
SPH_PREDICT_LOOP(2, 0)
SPH_PREDICT_LOOP(3, 0)
SPH_PREDICT_LOOP(2, 1)
SPH_PREDICT_LOOP(3, 1)

/* The corrector over the first n particles, correct<D><M> (D and M literals there): the largest
 * fluid speed squared, the density range and the non-finite count out. */
/* clang-format off */
#define SPH_CORRECT_LOOP(D, M)                                                                     \
    static long correct##D##M(const step_ctx *kp, double dt, long n, double *vmax2_out,            \
                           double *rlo_out, double *rhi_out)                                       \
    {                                                                                              \
        const step_ctx k = *kp;                                                                    \
        double vmax2 = 0.0, rlo = INFINITY, rhi = -INFINITY;                                       \
        long bad = 0;                                                                              \
        _Pragma("omp parallel for schedule(dynamic, SPH_OMP_CHUNK) firstprivate(k) reduction(+ : bad) reduction(max : vmax2, rhi) reduction(min : rlo) if (n >= SPH_OMP_MIN)") \
        for (long i = 0; i < n; i++)                                                               \
            bad += correct_one(D, M, &k, dt, i, &vmax2, &rlo, &rhi);                               \
        *vmax2_out = vmax2;                                                                        \
        *rlo_out = rlo;                                                                            \
        *rhi_out = rhi;                                                                            \
        return bad;                                                                                \
    }
/* clang-format on */
SPH_CORRECT_LOOP(2, 0)
SPH_CORRECT_LOOP(3, 0)
SPH_CORRECT_LOOP(2, 1)
SPH_CORRECT_LOOP(3, 1)

int sph_wcsph_step_checks(sph_sim *s, long step, double dt, long bad, double rlo, double rhi,
                          sph_error *err)
{
    const sph_config *c = &s->cfg;
    sph_particles *P = &s->P;
    const long n = s->nactive;
    const double rho0 = c->rho0;
    if (bad) {
        const long i = first_bad(P, n);
        return sph_error_set(err, SPH_ERR_UNSTABLE, "",
                             "blow-up at step %ld (t = %g s, dt = %g s): non-finite velocity or "
                             "density (%ld particles, first: particle %d)",
                             step, s->t, dt, bad, i >= 0 ? P->id[i] : -1);
    }
    if (rlo < SPH_RHO_LOW * rho0 || rhi > SPH_RHO_HIGH * rho0)
        return sph_error_set(err, SPH_ERR_UNSTABLE, "",
                             "blow-up at step %ld (t = %g s, dt = %g s): density %s: %g kg/m^3 is "
                             "outside [%g, %g] (rho0 = %g)",
                             step, s->t, dt, rlo < SPH_RHO_LOW * rho0 ? "collapse" : "explosion",
                             rlo < SPH_RHO_LOW * rho0 ? rlo : rhi, SPH_RHO_LOW * rho0,
                             SPH_RHO_HIGH * rho0, rho0);
    return sph_sim_check_lost(s, P->n - n, err);
}

int sph_wcsph_predict_failed(const sph_sim *s, long step, double dt, long bad, sph_error *err)
{
    return sph_error_set(err, SPH_ERR_UNSTABLE, "",
                         "blow-up at step %ld (t = %g s, dt = %g s): non-finite position of %ld "
                         "particles",
                         step, s->t, dt, bad);
}

int sph_wcsph_step_dt(sph_sim *s, double dt_cap, double *dt, sph_error *err)
{
    const sph_config *c = &s->cfg;
    const double dt_free = sph_wcsph_dt(s);
    if (!(dt_free >= SPH_DT_COLLAPSE * c->cfl * s->h / c->c0))
        return sph_error_set(err, SPH_ERR_UNSTABLE, "",
                             "time step collapsed to %g s at step %ld (t = %g s, max acceleration "
                             "%g m/s^2)",
                             dt_free, s->step + 1, s->t, s->amax);
    *dt = dt_cap < dt_free ? dt_cap : dt_free;
    s->dt = *dt;
    return 0;
}

static int wcsph_step(sph_sim *s, double dt_cap, sph_error *err)
{
    const sph_config *c = &s->cfg;
    sph_particles *P = &s->P;
    const double t0 = omp_get_wtime();
    const long step = s->step + 1;
    double dt;
    const int rc = sph_wcsph_step_dt(s, dt_cap, &dt, err);
    if (rc)
        return rc;

    /* the latest rates become the old ones */
    if (P->mixed) {
        swapf(&P->f32.ax, &P->f32.ax0);
        swapf(&P->f32.ay, &P->f32.ay0);
        if (P->f32.az)
            swapf(&P->f32.az, &P->f32.az0);
        swapf(&P->f32.drho, &P->f32.drho0);
    } else {
        swap(&P->ax, &P->ax0);
        swap(&P->ay, &P->ay0);
        if (P->az)
            swap(&P->az, &P->az0);
        swap(&P->drho, &P->drho0);
    }

    /* predictor */
    const long n0 = s->nactive;
    const step_ctx k = step_ctx_of(s);
    /* a reused neighbour list: this step's largest displacement, dt |v + dt a0 / 2|, at most
     * dt vmax + dt^2 amax / 2 (the fluid's largest speed and acceleration, which the previous
     * step found); the first step of a new sim, whose vmax is not its fluid's yet, measures it */
    const int listed = c->neighbour_skin > 0.0;
    if (listed)
        s->nlist.moved +=
            s->step > 0 ? dt * (s->vmax + 0.5 * dt * s->amax) : sph_wcsph_nlist_moved(s, dt, n0);
    long bad = P->mixed ? (c->dim == 3 ? predict31 : predict21)(&k, dt, n0)
                        : (c->dim == 3 ? predict30 : predict20)(&k, dt, n0);
    if (bad)
        return sph_wcsph_predict_failed(s, step, dt, bad, err);
    /* a particle that left the domain leaves the list's pairs: the list is built anew (the
     * sort puts it after the active ones) */
    if (listed && memchr(P->type, SPH_LOST, (size_t)n0))
        s->nlist.built = 0;
    sph_paddle_move(&s->paddle, P, n0, s->t + dt); /* a wavemaker's paddle at the step's end */
    if (s->bodies.n > 0) {
        const double tb = omp_get_wtime();
        const int out = sph_bodies_predict(&s->bodies, dt, &c->domain);
        if (out >= 0)
            return sph_error_set(err, SPH_ERR_UNSTABLE, "",
                                 "blow-up at step %ld (t = %g s): the body '%s' left the domain",
                                 step, s->t, c->bodies[out].name);
        sph_bodies_move(&s->bodies, P, n0);
        s->timing.bodies += omp_get_wtime() - tb;
    }
    s->timing.integration += omp_get_wtime() - t0;

    /* sorts by cell: the arrays are permuted, nactive updated */
    if (sph_wcsph_forces_step(s, dt))
        return sph_error_set(err, SPH_ERR_NOMEM, "",
                             "out of memory for the ghost particles, the wet-cell map or the "
                             "shifting's displacements at step %ld",
                             step);

    /* corrector and checks */
    const double t1 = omp_get_wtime();
    const long n = s->nactive;
    double vmax2, rlo, rhi;
    bad = (P->mixed ? (c->dim == 3 ? correct31 : correct21)
                    : (c->dim == 3 ? correct30 : correct20))(&k, dt, n, &vmax2, &rlo, &rhi);
    s->vmax = sqrt(vmax2);
    /* mDBC's walls hold no pressure against a thin layer of fast water (theirs is taken from
     * it): its no-penetration control keeps the fluid out of them */
    if (c->wall_density == SPH_WALL_MDBC && sph_wcsph_no_penetration(s))
        return sph_error_set(err, SPH_ERR_NOMEM, "",
                             "out of memory for the walls' cell map at step %ld", step);
    if (s->bodies.n > 0) {
        const double tb = omp_get_wtime();
        sph_bodies_correct(&s->bodies, dt);
        sph_bodies_move(&s->bodies, P, n);
        s->vmax = fmax(s->vmax, sph_bodies_vmax(&s->bodies));
        s->timing.bodies += omp_get_wtime() - tb;
    }
    sph_damping_apply(c, P, n, dt);                     /* a damping zone (Altomare et al. 2017) */
    sph_paddle_absorb(&s->paddle, P, n, s->t + dt, dt); /* a piston's active absorption */
    s->t += dt;
    s->step = step;
    s->timing.integration += omp_get_wtime() - t1;

    return sph_wcsph_step_checks(s, step, dt, bad, rlo, rhi, err);
}

static int wcsph_check(const sph_config *c, sph_error *err)
{
    if (sph_kernel_is_mps(c->kernel.type))
        return sph_error_set(err, SPH_ERR_INVALID, "/kernel/type",
                             "'%s' is an MPS weight function, not an SPH kernel",
                             sph_kernel_type_name(c->kernel.type));
    if (!(c->c0 > 0.0))
        return sph_error_set(err, SPH_ERR_INVALID, "/physics/eos/c0", "c0 must be positive");
    if ((c->visc == SPH_VISC_LAMINAR || c->visc == SPH_VISC_MONAGHAN) &&
        !(c->nu > 0.0 && isfinite(c->nu)))
        return sph_error_set(err, SPH_ERR_INVALID, "/physics/viscosity/nu",
                             "the %s viscosity needs a positive nu",
                             c->visc == SPH_VISC_LAMINAR ? "laminar" : "monaghan");
    return 0;
}

size_t sph_wcsph_bytes_per_particle(const sph_config *c)
{
    /* with shifting, its displacements (sph_sim.shift: ghosts included, as the estimate counts
     * them) */
    const size_t shift = c->shifting.type != SPH_SHIFT_NONE ? (size_t)c->dim * sizeof(double) : 0;
    /* a reused neighbour list (sph_config_nlist_bytes) */
    const size_t list = (size_t)ceil(sph_config_nlist_bytes(c));
    return sph_particles_bytes_per_particle(c->dim, sph_sim_particle_opts(c)) + shift + list;
}

static int wcsph_init(sph_sim *s, sph_error *err)
{
    if (sph_wcsph_forces(s))
        return sph_error_set(err, SPH_ERR_NOMEM, "",
                             "out of memory for the ghost particles or the wet-cell map");
    return 0;
}

/* What lives from one step to the next: the state and the previous rates of the corrector. */
int sph_wcsph_arrays(const sph_sim *s, sph_array *d, int maxd)
{
    const sph_particles *P = &s->P;
    const size_t z = sizeof(double), f = sizeof(float);
    /* the third axis's arrays last (NULL in 2D: the 2D list is what it was); a hot field's
     * double array or, under mixed precision, its float one (the other is NULL) */
#define HOT(a)                                                                                     \
    {P->a, z},                                                                                     \
    {                                                                                              \
        P->f32.a, f                                                                                \
    }
    const sph_array all[] = {
        {P->x, z},   {P->y, z},   HOT(vx),     HOT(vy),     HOT(rho),    HOT(ax),     HOT(ay),
        HOT(drho),   HOT(ax0),    HOT(ay0),    HOT(drho0),  {P->txx, z}, {P->txy, z}, {P->tyy, z},
        {P->gxx, z}, {P->gxy, z}, {P->gyy, z}, {P->z, z},   HOT(vz),     HOT(az),     HOT(az0),
        {P->tzz, z}, {P->txz, z}, {P->tyz, z}, {P->gzz, z}, {P->gxz, z}, {P->gyz, z}};
#undef HOT
    return sph_method_arrays(all, (int)(sizeof all / sizeof all[0]), d, maxd);
}

const sph_method_ops sph_wcsph_ops = {
    .name = "wcsph",
    .check = wcsph_check,
    .bytes_per_particle = sph_wcsph_bytes_per_particle,
    .init = wcsph_init,
    .dt = sph_wcsph_dt,
    .step = wcsph_step,
    .pressure = sph_wcsph_pressure,
    .diag = NULL,
    .arrays = sph_wcsph_arrays,
    .resume = sph_wcsph_resume,
    .destroy = NULL,
};
