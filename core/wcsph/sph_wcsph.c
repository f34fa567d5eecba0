/*
 * sph_wcsph: the WCSPH pair loops (Yang, Peng & Liu 2014, section 2.2; Macia et al. for the
 * artificial viscosity), 2D.
 *
 * Each pair is computed once and applied to both particles with opposite signs. The loop is
 * written once, strip_generic(), a `static inline` function taking the kernel type and the
 * option flags as compile-time constants; SPH_KERNEL_DISPATCH picks its instantiation for the
 * job's kernel once per force evaluation, so no pair goes through a function pointer.
 *
 * Parallel without atomics: the grid's columns are grouped in strips two columns wide. A cell
 * interacts with itself, the cell above it and the three cells of the next column, so a strip
 * writes only to its own columns and the first column of the next strip: strips of the same
 * parity never write to the same particle. The even strips run in parallel, then the odd ones.
 * The order in which a particle receives its contributions is fixed by the grid alone, so the
 * results are bitwise the same whatever the number of threads.
 */
#include "sph_wcsph.h"

#include <math.h>
#include <omp.h>
#include <string.h>

/* Option flags, instantiated as constants. F_GHOST: the walls are ghost particles (free slip,
 * boundary/sph_wall_ghost.c), which take part in every term like fluid neighbours, delta-SPH
 * included; only ghost-ghost pairs are skipped. F_MONAGHAN: Monaghan's viscous term on every
 * pair, approaching or not, as a physical viscosity (Macia et al.). F_BODY: the case has rigid
 * bodies (boundary/sph_body.h), whose particles interact with everything but their own body. */
enum {
    F_LAMINAR = 1,
    F_SPS = 2,
    F_DELTA = 4,
    F_GHOST = 8,
    F_MONAGHAN = 16,
    F_BODY = 32,
    F_COUNT = 64
};

#define SPH_SPS_CS 0.12   /* Smagorinsky constant, Yang et al. after Lo & Shao */
#define SPH_SPS_CI 0.0066 /* isotropic part, Dalrymple & Rogers 2006 */

typedef struct fctx {
    const double *x, *y, *vx, *vy, *rho, *pr;
    const unsigned char *type;
    const int *id;    /* creation index (F_BODY: which body a body particle belongs to) */
    const int *owner; /* F_BODY: body of body particle id, at owner[id - body0] */
    unsigned char from_fluid[SPH_CONFIG_MAX_BODIES]; /* F_BODY: the body's pressure from the
                                                        fluid: its continuity skips fluid pairs */
    long body0;                                      /* F_BODY: id of the first body particle */
    double *ax, *ay, *drho;
    double *gxx, *gxy, *gyy;
    const double *txx, *txy, *tyy;
    const int *start;
    int nx, ny;
    const sph_kernel *k;
    double m;         /* particle mass [kg] */
    double h;         /* smoothing length [m] */
    double eta2;      /* 0.01 h^2 [m^2] */
    double support2;  /* support radius squared [m^2] */
    double tiny;      /* guards r = 0 [m] */
    double alpha_c0;  /* Monaghan's term (artificial or physical): alpha c0 [m/s] */
    double mu8;       /* laminar: 8 mu = 8 rho0 nu [Pa s] */
    double wall_visc; /* factor on the viscous terms of fluid-wall pairs (dynamic walls) [-] */
    double dcoef;     /* delta-SPH: 2 delta h c0 m [kg m^2/s] */
} fctx;

typedef struct acc {
    double ax, ay, drho, gxx, gxy, gyy;
    long pairs;
} acc;

/* Interactions of particle i with particles [jb, je). */
static inline __attribute__((always_inline)) void interact(sph_kernel_type T, unsigned F,
                                                           const fctx *restrict c, long i, long jb,
                                                           long je, acc *restrict ai)
{
    const double *restrict x = c->x, *restrict y = c->y, *restrict vx = c->vx, *restrict vy = c->vy,
                           *restrict rho = c->rho, *restrict pr = c->pr;
    double *restrict ax = c->ax, *restrict ay = c->ay, *restrict drho = c->drho;
    const double xi = x[i], yi = y[i], vxi = vx[i], vyi = vy[i], rhoi = rho[i], pri = pr[i];
    /* the walls: dynamic boundary particles, or ghosts */
    const unsigned char wall = (F & F_GHOST) ? SPH_GHOST : SPH_BOUNDARY;
    const int bi = c->type[i] == wall;
    /* F_BODY: the body of particle i (-1: not a body particle), and whether i is fluid */
    const int oi = (F & F_BODY) && c->type[i] == SPH_BODY ? c->owner[c->id[i] - c->body0] : -1;
    const int fi = c->type[i] == SPH_FLUID;
    const double m = c->m, support2 = c->support2, eta2 = c->eta2;
    for (long j = jb; j < je; j++) {
        const double dx = xi - x[j], dy = yi - y[j];
        const double r2 = dx * dx + dy * dy;
        if (r2 >= support2)
            continue;
        const int bj = c->type[j] == wall;
        if (bi & bj) /* wall-wall pairs: nothing a fluid particle feels */
            continue;
        if ((F & F_BODY) && oi >= 0 && c->type[j] == SPH_BODY &&
            c->owner[c->id[j] - c->body0] == oi) /* one rigid body: no force within it */
            continue;
        ai->pairs++;
        const double r = sqrt(r2);
        double dwdr;
        (void)sph_kernel_eval_t(T, c->k, r, &dwdr);
        const double fw = dwdr / (r + c->tiny); /* grad_a W_ab = fw (x_a - x_b) */
        const double dvx = vxi - vx[j], dvy = vyi - vy[j];
        const double vr = dvx * dx + dvy * dy;
        const double rhoj = rho[j];

        /* Yang et al. 2014, eq. (12): continuity; the same for both particles, except that the
         * particles of a body that takes its pressure from the fluid count only solid
         * neighbours (walls, other bodies): their density is the contact's */
        const double dd = m * vr * fw;
        const int skip_i = (F & F_BODY) && oi >= 0 && c->from_fluid[oi] && c->type[j] == SPH_FLUID;
        const int skip_j = (F & F_BODY) && fi && c->type[j] == SPH_BODY &&
                           c->from_fluid[c->owner[c->id[j] - c->body0]];
        if (!skip_i)
            ai->drho += dd;
        if (!skip_j)
            drho[j] += dd;

        /* the viscous terms between fluid and dynamic wall particles are scaled by the case's
         * boundary.viscosity_factor (DualSPHysics' ViscoBoundFactor); ghosts are not walls here */
        const double vf = (!(F & F_GHOST) && (bi | bj)) ? c->wall_visc : 1.0;

        /* eq. (13): pressure, with Monaghan's viscous term Pi_ab (Macia et al.): artificial
         * (approaching pairs only) or physical (every pair, alpha from nu) */
        double pt = pri + pr[j];
        if ((F & F_MONAGHAN) || (!(F & F_LAMINAR) && vr < 0.0)) {
            const double mu = c->h * vr / (r2 + eta2);
            pt -= vf * c->alpha_c0 * mu * 2.0 / (rhoi + rhoj);
        }
        double fx = -m * pt * fw * dx, fy = -m * pt * fw * dy;

        if (F & F_LAMINAR) { /* eq. (14) */
            const double rs = rhoi + rhoj;
            const double lc = vf * c->mu8 * m * fw * r2 / (rs * rs * (r2 + eta2));
            fx += lc * dvx;
            fy += lc * dvy;
        }
        if (F & F_SPS) { /* eq. (15): sub-particle stress; velocity gradients for eq. (9) */
            const double sxx = c->txx[i] + c->txx[j], sxy = c->txy[i] + c->txy[j],
                         syy = c->tyy[i] + c->tyy[j];
            fx += m * fw * (sxx * dx + sxy * dy);
            fy += m * fw * (sxy * dx + syy * dy);
            const double gx = fw * dx, gy = fw * dy;
            const double vi = -m / rhoj, vj = -m / rhoi;
            ai->gxx += vi * dvx * gx;
            ai->gxy += vi * (dvx * gy + dvy * gx);
            ai->gyy += vi * dvy * gy;
            c->gxx[j] += vj * dvx * gx;
            c->gxy[j] += vj * (dvx * gy + dvy * gx);
            c->gyy[j] += vj * dvy * gy;
        }
        if ((F & F_DELTA) &&
            ((F & F_GHOST) || ((F & F_BODY) ? fi && c->type[j] == SPH_FLUID : !(bi | bj)))) {
            /* delta-SPH (Molteni & Colagrossi 2009): 2 delta h c0 sum (rho_b - rho_a)
             * (x_b - x_a).grad_a W / (r^2 + eta^2) V_b, fluid and ghost pairs only (a ghost's
             * density is the hydrostatic one behind the wall, dynamic particles' is not) */
            const double w = c->dcoef * (rhoj - rhoi) * (-fw * r2) / (r2 + eta2);
            ai->drho += w / rhoj;
            drho[j] -= w / rhoi;
        }
        ai->ax += fx;
        ai->ay += fy;
        ax[j] -= fx;
        ay[j] -= fy;
    }
}

/* The pairs of strip `strip` (columns 1 + 2 strip and 2 + 2 strip). Returns the pair count. */
static inline __attribute__((always_inline)) long strip_generic(sph_kernel_type T, unsigned F,
                                                                const fctx *c, int strip)
{
    const int ny = c->ny;
    const int *start = c->start;
    const int cx0 = 1 + 2 * strip, cx1 = cx0 + 2 < c->nx - 1 ? cx0 + 2 : c->nx - 1;
    long pairs = 0;
    for (int cx = cx0; cx < cx1; cx++)
        for (int cy = 1; cy < ny - 1; cy++) {
            const long cell = (long)cx * ny + cy;
            const long ib = start[cell], ie = start[cell + 1];
            if (ib == ie)
                continue;
            const long up = start[cell + 2]; /* end of the cell above */
            const long nb = start[cell + ny - 1], ne = start[cell + ny + 2]; /* next column */
            for (long i = ib; i < ie; i++) {
                acc a = {0};
                interact(T, F, c, i, i + 1, up, &a);
                interact(T, F, c, i, nb, ne, &a);
                c->ax[i] += a.ax;
                c->ay[i] += a.ay;
                c->drho[i] += a.drho;
                if (F & F_SPS) {
                    c->gxx[i] += a.gxx;
                    c->gxy[i] += a.gxy;
                    c->gyy[i] += a.gyy;
                }
                pairs += a.pairs;
            }
        }
    return pairs;
}

typedef long (*strip_fn)(const fctx *c, int strip);

/* One instantiation per kernel type and option set a job can make: strips_<TYPE>[flags], the
 * flags' value naming the instantiation. The combinations sph_sim_check refuses (laminar with
 * monaghan: one viscosity; ghost walls with bodies: sph_body_check) have none, their entry is
 * NULL: 36 of the 64 per kernel, 180 functions instead of 320. */
#define SPH_STRIP_FN(T, FL)                                                                        \
    static long strip_##T##_##FL(const fctx *c, int strip)                                         \
    {                                                                                              \
        return strip_generic(T, FL, c, strip);                                                     \
    }
/* clang-format off */
#define SPH_STRIP_TABLE(T) \
    SPH_STRIP_FN(T, 0) SPH_STRIP_FN(T, 1) SPH_STRIP_FN(T, 2) SPH_STRIP_FN(T, 3) \
    SPH_STRIP_FN(T, 4) SPH_STRIP_FN(T, 5) SPH_STRIP_FN(T, 6) SPH_STRIP_FN(T, 7) \
    SPH_STRIP_FN(T, 8) SPH_STRIP_FN(T, 9) SPH_STRIP_FN(T, 10) SPH_STRIP_FN(T, 11) \
    SPH_STRIP_FN(T, 12) SPH_STRIP_FN(T, 13) SPH_STRIP_FN(T, 14) SPH_STRIP_FN(T, 15) \
    SPH_STRIP_FN(T, 16) SPH_STRIP_FN(T, 18) SPH_STRIP_FN(T, 20) SPH_STRIP_FN(T, 22) \
    SPH_STRIP_FN(T, 24) SPH_STRIP_FN(T, 26) SPH_STRIP_FN(T, 28) SPH_STRIP_FN(T, 30) \
    SPH_STRIP_FN(T, 32) SPH_STRIP_FN(T, 33) SPH_STRIP_FN(T, 34) SPH_STRIP_FN(T, 35) \
    SPH_STRIP_FN(T, 36) SPH_STRIP_FN(T, 37) SPH_STRIP_FN(T, 38) SPH_STRIP_FN(T, 39) \
    SPH_STRIP_FN(T, 48) SPH_STRIP_FN(T, 50) SPH_STRIP_FN(T, 52) SPH_STRIP_FN(T, 54) \
    static const strip_fn strips_##T[F_COUNT] = { \
        [0] = strip_##T##_0, [1] = strip_##T##_1, [2] = strip_##T##_2, [3] = strip_##T##_3, \
        [4] = strip_##T##_4, [5] = strip_##T##_5, [6] = strip_##T##_6, [7] = strip_##T##_7, \
        [8] = strip_##T##_8, [9] = strip_##T##_9, [10] = strip_##T##_10, [11] = strip_##T##_11, \
        [12] = strip_##T##_12, [13] = strip_##T##_13, [14] = strip_##T##_14, [15] = strip_##T##_15, \
        [16] = strip_##T##_16, [18] = strip_##T##_18, [20] = strip_##T##_20, [22] = strip_##T##_22, \
        [24] = strip_##T##_24, [26] = strip_##T##_26, [28] = strip_##T##_28, [30] = strip_##T##_30, \
        [32] = strip_##T##_32, [33] = strip_##T##_33, [34] = strip_##T##_34, [35] = strip_##T##_35, \
        [36] = strip_##T##_36, [37] = strip_##T##_37, [38] = strip_##T##_38, [39] = strip_##T##_39, \
        [48] = strip_##T##_48, [50] = strip_##T##_50, [52] = strip_##T##_52, [54] = strip_##T##_54, \
    };
/* clang-format on */

SPH_STRIP_TABLE(SPH_KERNEL_CUBIC_SPLINE)
SPH_STRIP_TABLE(SPH_KERNEL_GAUSSIAN)
SPH_STRIP_TABLE(SPH_KERNEL_DOUBLE_COSINE)
SPH_STRIP_TABLE(SPH_KERNEL_WENDLAND_C2)
SPH_STRIP_TABLE(SPH_KERNEL_RENORMALIZED_GAUSSIAN)
/* the MPS weight functions are refused for WCSPH (wcsph_check): no instantiations */
static const strip_fn strips_SPH_KERNEL_KOSHIZUKA[F_COUNT] = {0};
static const strip_fn strips_SPH_KERNEL_SHEU_QUARTIC[F_COUNT] = {0};

/* EOS, p / rho^2, SPS stresses from the previous velocity gradients; zeroes the accumulators. */
static void prepare(sph_sim *s)
{
    const sph_config *cfg = &s->cfg;
    sph_particles *P = &s->P;
    const long n = s->nactive;
    const double smag = (SPH_SPS_CS * cfg->dx) * (SPH_SPS_CS * cfg->dx);
    const double blin = 2.0 / 3.0 * SPH_SPS_CI * cfg->dx * cfg->dx;
#pragma omp parallel for schedule(dynamic, SPH_OMP_CHUNK) if (n >= SPH_OMP_MIN)
    for (long i = 0; i < n; i++) {
        const double rho = P->rho[i];
        const double p = sph_eos_pressure(cfg, rho);
        P->p[i] = p;
        P->pr[i] = p / (rho * rho);
        P->ax[i] = 0.0;
        P->ay[i] = 0.0;
        P->drho[i] = 0.0;
        if (P->gxx) {
            /* Yang et al. eqs. (7)-(9), Smagorinsky; isotropic part after Dalrymple & Rogers
             * 2006. Stored as R / rho as eq. (15) uses it. Boundary particles carry none. */
            double txx = 0.0, txy = 0.0, tyy = 0.0;
            if (P->type[i] == SPH_FLUID) {
                const double dudx = P->gxx[i], sxy = P->gxy[i], dvdy = P->gyy[i];
                const double s2 = 2.0 * (dudx * dudx + dvdy * dvdy) + sxy * sxy; /* 2 S:S */
                const double nut = smag * sqrt(s2);                              /* eq. (8) */
                const double iso = -(2.0 / 3.0 * nut * (dudx + dvdy) + blin * s2);
                txx = (2.0 * nut * dudx + iso) / rho;
                txy = nut * sxy / rho;
                tyy = (2.0 * nut * dvdy + iso) / rho;
            }
            P->txx[i] = txx;
            P->txy[i] = txy;
            P->tyy[i] = tyy;
            P->gxx[i] = P->gxy[i] = P->gyy[i] = 0.0;
        }
    }
}

/* Appends the ghosts of the free-slip walls after the real particles (room made as needed).
 * Returns 0 or -1 when out of memory. */
static int add_ghosts(sph_sim *s)
{
    sph_particles *P = &s->P;
    const long n = P->n;
    for (;;) {
        const sph_ghost_arrays a = {.pos = {P->x, P->y, NULL},
                                    .vel = {P->vx, P->vy, NULL},
                                    .rho = P->rho,
                                    .type = P->type,
                                    .id = P->id};
        const long need = sph_wall_ghost_build(&s->ghost, &s->cfg, &a, n, P->cap);
        if (n + need <= P->cap) {
            s->nghost = need;
            P->n = n + need;
            return 0;
        }
        const long cap = n + need + need / 4 + 16;
        if (sph_particles_reserve(P, cap) || sph_cells_reserve(&s->cells, cap))
            return -1;
    }
}

int sph_wcsph_forces(sph_sim *s)
{
    const sph_config *cfg = &s->cfg;
    sph_particles *P = &s->P;
    const int ghosts = cfg->boundary == SPH_BOUNDARY_GHOST;
    double t0 = omp_get_wtime();
    if (ghosts && add_ghosts(s))
        return -1;
    s->nactive = sph_cells_sort(&s->cells, P);
    double t1 = omp_get_wtime();
    s->timing.neighbours += t1 - t0;

    prepare(s);
    if (s->bodies.n > 0) { /* the body particles' pressure from the fluid around them */
        const double tb = omp_get_wtime();
        sph_bodies_pressure(&s->bodies, cfg, &s->kernel, &s->cells, P, s->nactive);
        s->timing.bodies += omp_get_wtime() - tb;
    }
    const double alpha =
        cfg->visc == SPH_VISC_MONAGHAN ? sph_config_monaghan_alpha(cfg) : cfg->alpha;
    const unsigned flags = (cfg->visc == SPH_VISC_LAMINAR ? F_LAMINAR : 0) |
                           (cfg->visc == SPH_VISC_MONAGHAN ? F_MONAGHAN : 0) |
                           (cfg->turb == SPH_TURB_SPS ? F_SPS : 0) |
                           (cfg->delta_sph > 0.0 ? F_DELTA : 0) | (ghosts ? F_GHOST : 0) |
                           (s->bodies.n > 0 ? F_BODY : 0);
    fctx c = {.x = P->x,
              .y = P->y,
              .vx = P->vx,
              .vy = P->vy,
              .rho = P->rho,
              .pr = P->pr,
              .type = P->type,
              .id = P->id,
              .owner = s->bodies.owner,
              .body0 = s->bodies.first,
              .ax = P->ax,
              .ay = P->ay,
              .drho = P->drho,
              .gxx = P->gxx,
              .gxy = P->gxy,
              .gyy = P->gyy,
              .txx = P->txx,
              .txy = P->txy,
              .tyy = P->tyy,
              .start = s->cells.start,
              .nx = s->cells.nx,
              .ny = s->cells.ny,
              .k = &s->kernel,
              .m = s->mass,
              .h = s->h,
              .eta2 = 0.01 * s->h * s->h,
              .support2 = s->kernel.support * s->kernel.support,
              .tiny = 1e-12 * s->h,
              .alpha_c0 = alpha * cfg->c0,
              .mu8 = 8.0 * cfg->rho0 * cfg->nu,
              .wall_visc = cfg->wall_viscosity,
              .dcoef = 2.0 * cfg->delta_sph * s->h * cfg->c0 * s->mass};
    for (int k = 0; k < s->bodies.n; k++)
        c.from_fluid[k] = (unsigned char)s->bodies.b[k].from_fluid;
    strip_fn fn = NULL;
#define SPH_PICK(T) fn = strips_##T[flags]
    SPH_KERNEL_DISPATCH(s->kernel.type, SPH_PICK);
#undef SPH_PICK
    if (!fn) /* an MPS weight or a refused combination: sph_sim_check refuses them first */
        return -1;
    const int nstrips = (s->cells.nx - 2 + 1) / 2;
    const long n = s->nactive;
    long pairs = 0;
    for (int parity = 0; parity < 2; parity++) {
#pragma omp parallel for schedule(dynamic, 1) reduction(+ : pairs) if (n >= SPH_OMP_MIN)
        for (int st = parity; st < nstrips; st += 2)
            pairs += fn(&c, st);
    }

    /* the bodies take the force and torque their particles received */
    double t2 = omp_get_wtime();
    sph_bodies_gather(&s->bodies, P, n, s->mass);
    s->timing.bodies += omp_get_wtime() - t2;

    /* gravity on the fluid; walls, bodies' particles and lost particles do not move by it */
    const double gx = cfg->gravity[0], gy = cfg->gravity[1];
    double amax2 = 0.0;
#pragma omp parallel for schedule(dynamic, SPH_OMP_CHUNK) reduction(max                            \
                                                                    : amax2) if (n >= SPH_OMP_MIN)
    for (long i = 0; i < n; i++) {
        if (P->type[i] == SPH_FLUID) {
            P->ax[i] += gx;
            P->ay[i] += gy;
            const double a2 = P->ax[i] * P->ax[i] + P->ay[i] * P->ay[i];
            amax2 = a2 > amax2 ? a2 : amax2;
        } else {
            P->ax[i] = P->ay[i] = 0.0;
        }
    }
    for (long i = n; i < P->n; i++)
        P->ax[i] = P->ay[i] = P->drho[i] = 0.0;
    s->amax = fmax(sqrt(amax2), sph_bodies_amax(&s->bodies));
    double t3 = omp_get_wtime();
    s->timing.interactions += t3 - t1;
    s->timing.pairs = pairs;
    if (ghosts) { /* what the ghosts received is discarded with them */
        sph_particles_remove(P, SPH_GHOST, s->cells.perm);
        s->nactive -= s->nghost;
        s->timing.neighbours += omp_get_wtime() - t3;
    }
    s->timing.active = s->nactive;
    return 0;
}
