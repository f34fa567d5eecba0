#include "sph_mps_ops.h"

#include "sph_particles.h"

#include <math.h>

int sph_mps_weight_init(sph_kernel *k, sph_kernel_type type, double re, sph_error *err)
{
    const sph_kernel_spec spec = sph_kernel_spec_default(type);
    if (!sph_kernel_is_mps(type))
        return sph_error_set(err, SPH_ERR_INVALID, "/type",
                             "'%s' is an SPH kernel, not an MPS weight function: use koshizuka or "
                             "sheu_quartic",
                             sph_kernel_type_name(type) ? sph_kernel_type_name(type) : "?");
    return sph_kernel_init(k, &spec, 2, 0.5 * re, err);
}

/* w(r) with the singular origin guarded (see SPH_MPS_RMIN). */
static inline __attribute__((always_inline)) double weight(sph_kernel_type T, const sph_kernel *k,
                                                           double r)
{
    const double rmin = SPH_MPS_RMIN * k->support;
    double d;
    return sph_kernel_eval_t(T, k, r > rmin ? r : rmin, &d);
}

/* sum of r^p w(r) over the lattice points other than the origin, p = 0 or 2. */
static double lattice_sum(const sph_kernel *k, double dx, int dim, int p)
{
    const int m = (int)ceil(k->support / dx) + 1;
    const int my = dim > 1 ? m : 0, mz = dim > 2 ? m : 0;
    double s = 0.0;
    for (int a = -m; a <= m; a++)
        for (int b = -my; b <= my; b++)
            for (int c = -mz; c <= mz; c++) {
                if (a == 0 && b == 0 && c == 0)
                    continue;
                const double r2 = dx * dx * (double)(a * a + b * b + c * c);
                const double r = sqrt(r2);
                if (r >= k->support)
                    continue;
                s += (p ? r2 : 1.0) * sph_kernel_w(k, r);
            }
    return s;
}

double sph_mps_lattice_n0(const sph_kernel *k, double dx, int dim)
{
    return lattice_sum(k, dx, dim, 0);
}

double sph_mps_lattice_lambda(const sph_kernel *k, double dx, int dim)
{
    return lattice_sum(k, dx, dim, 2) / lattice_sum(k, dx, dim, 0);
}

double sph_mps_lambda_integral(const sph_kernel *k, int dim)
{
    if (k->type == SPH_KERNEL_KOSHIZUKA && dim == 1)
        return NAN; /* int (re/r - 1) dr diverges at 0 */
    /* lambda = int_0^re r^(d+1) w dr / int_0^re r^(d-1) w dr (the sphere's area cancels), by
     * 3-point Gauss-Legendre on 4000 panels: exact for the quartic's polynomial pieces up to
     * round-off, and it never evaluates the Koshizuka weight at r = 0. */
    static const double gx[3] = {-0.7745966692414834, 0.0, 0.7745966692414834};
    static const double gw[3] = {5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0};
    const int panels = 4000;
    const double hpan = k->support / panels;
    double num = 0.0, den = 0.0;
    for (int p = 0; p < panels; p++)
        for (int q = 0; q < 3; q++) {
            const double r = hpan * (p + 0.5 + 0.5 * gx[q]);
            const double f = gw[q] * pow(r, dim - 1) * sph_kernel_w(k, r);
            den += f;
            num += f * r * r;
        }
    return num / den;
}

/* The ghost pressure gradient of wall particle j seen from fluid particle i (sph_mps_neumann_rhs):
 * G_i, less the tangential part of T_i where j's wall has a normal mask. */
static inline __attribute__((always_inline)) void ghost_grad(const sph_mps_ghost *G, long i, long j,
                                                             double *gx, double *gy)
{
    double x = G->gx[i], y = G->gy[i];
    if (G->tx) {
        const int nm = G->normal[j];
        if (!(nm & SPH_MPS_NORMAL_X))
            x -= G->tx[i];
        else if (G->ux)
            x -= G->ux[i];
        if (!(nm & SPH_MPS_NORMAL_Y))
            y -= G->ty[i];
        else if (G->uy)
            y -= G->uy[i];
    }
    *gx = x;
    *gy = y;
}

/* ---- number density ---------------------------------------------------------------------- */

static inline __attribute__((always_inline)) void
nd_generic(sph_kernel_type T, const sph_mps_nbr *L, const double *restrict x,
           const double *restrict y, const sph_kernel *k, double *restrict n)
{
    const long np = L->n;
    const double re2 = k->support * k->support;
#pragma omp parallel for schedule(dynamic, SPH_OMP_CHUNK) if (np >= SPH_OMP_MIN)
    for (long i = 0; i < np; i++) {
        double s = 0.0;
        for (long e = L->ptr[i]; e < L->ptr[i + 1]; e++) {
            const long j = L->j[e];
            const double dx = x[j] - x[i], dy = y[j] - y[i];
            const double r2 = dx * dx + dy * dy;
            if (r2 < re2)
                s += weight(T, k, sqrt(r2));
        }
        n[i] = s;
    }
}

void sph_mps_number_density(const sph_mps_nbr *L, const double *x, const double *y,
                            const sph_kernel *k, double *n)
{
#define ND(T) nd_generic(T, L, x, y, k, n)
    SPH_KERNEL_DISPATCH(k->type, ND);
#undef ND
}

static inline __attribute__((always_inline)) void
moment_generic(sph_kernel_type T, const sph_mps_nbr *L, const double *restrict x,
               const double *restrict y, const sph_kernel *k, double *restrict m)
{
    const long np = L->n;
    const double re2 = k->support * k->support;
#pragma omp parallel for schedule(dynamic, SPH_OMP_CHUNK) if (np >= SPH_OMP_MIN)
    for (long i = 0; i < np; i++) {
        double sx = 0.0, sy = 0.0;
        for (long e = L->ptr[i]; e < L->ptr[i + 1]; e++) {
            const long j = L->j[e];
            const double dx = x[j] - x[i], dy = y[j] - y[i];
            const double r2 = dx * dx + dy * dy;
            if (r2 < re2) {
                const double w = weight(T, k, sqrt(r2));
                sx += w * dx;
                sy += w * dy;
            }
        }
        m[i] = sqrt(sx * sx + sy * sy);
    }
}

void sph_mps_moment(const sph_mps_nbr *L, const double *x, const double *y, const sph_kernel *k,
                    double *m)
{
#define MOM(T) moment_generic(T, L, x, y, k, m)
    SPH_KERNEL_DISPATCH(k->type, MOM);
#undef MOM
}

void sph_mps_surface_ghost(const sph_mps_nbr *L, const double *x, const double *y,
                           const sph_kernel *k, double coef, double dx,
                           const unsigned char *surface, double *ghost)
{
    sph_mps_moment(L, x, y, k, ghost);
    const double gc = coef / (0.5 * dx);
    for (long i = 0; i < L->n; i++)
        ghost[i] = surface[i] ? gc * ghost[i] : 0.0;
}

/* ---- Laplacian (3.5) ----------------------------------------------------------------------- */

static inline __attribute__((always_inline)) void
lap_generic(sph_kernel_type T, const sph_mps_nbr *L, const double *restrict x,
            const double *restrict y, const unsigned char *restrict kind, int max_kind,
            const sph_kernel *k, double coef, const double *restrict phi, double *restrict out)
{
    const long np = L->n;
    const double re2 = k->support * k->support;
#pragma omp parallel for schedule(dynamic, SPH_OMP_CHUNK) if (np >= SPH_OMP_MIN)
    for (long i = 0; i < np; i++) {
        if (kind[i] != SPH_MPS_FLUID) {
            out[i] = 0.0;
            continue;
        }
        const double phii = phi[i];
        double s = 0.0;
        for (long e = L->ptr[i]; e < L->ptr[i + 1]; e++) {
            const long j = L->j[e];
            if (kind[j] > max_kind)
                continue;
            const double dx = x[j] - x[i], dy = y[j] - y[i];
            const double r2 = dx * dx + dy * dy;
            if (r2 < re2)
                s += (phi[j] - phii) * weight(T, k, sqrt(r2));
        }
        out[i] = coef * s;
    }
}

void sph_mps_laplacian(const sph_mps_nbr *L, const double *x, const double *y,
                       const unsigned char *kind, int max_kind, const sph_kernel *k, double coef,
                       const double *phi, double *out)
{
#define LAP(T) lap_generic(T, L, x, y, kind, max_kind, k, coef, phi, out)
    SPH_KERNEL_DISPATCH(k->type, LAP);
#undef LAP
}

/* ---- gradient (3.4) ------------------------------------------------------------------------ */

/* The corrected gradient's solve (Khayyer & Gotoh 2011): (gx, gy) = M^-1 (sx, sy) for the
 * corrective matrix M = sum w r r^T / r^2 = [[mxx, mxy], [mxy, myy]], which is (n0 / d) I on a full
 * lattice; where M is near-singular (det below 1e-2 (n0 / d)^2, coef = d / n0) the uncorrected
 * coef (sx, sy) instead. Returns 1 when corrected. */
static inline int corrective_solve(double mxx, double mxy, double myy, double coef, double sx,
                                   double sy, double *gx, double *gy)
{
    const double det = mxx * myy - mxy * mxy, ref = 1.0 / (coef * coef);
    if (det > 1e-2 * ref) {
        *gx = (myy * sx - mxy * sy) / det;
        *gy = (mxx * sy - mxy * sx) / det;
        return 1;
    }
    *gx = coef * sx;
    *gy = coef * sy;
    return 0;
}

static inline __attribute__((always_inline)) void
grad_generic(sph_kernel_type T, const sph_mps_nbr *L, const double *restrict x,
             const double *restrict y, const unsigned char *restrict kind, const sph_kernel *k,
             double coef, int local_min, int corrected, const double *restrict phi,
             const sph_mps_ghost *G, double *restrict gx, double *restrict gy)
{
    const long np = L->n;
    const double re2 = k->support * k->support;
#pragma omp parallel for schedule(dynamic, SPH_OMP_CHUNK) if (np >= SPH_OMP_MIN)
    for (long i = 0; i < np; i++) {
        if (kind[i] != SPH_MPS_FLUID) {
            gx[i] = gy[i] = 0.0;
            continue;
        }
        const double xi = x[i], yi = y[i];
        double pmin = phi[i];
        if (local_min)
            for (long e = L->ptr[i]; e < L->ptr[i + 1]; e++) {
                const long j = L->j[e];
                const double dx = x[j] - xi, dy = y[j] - yi;
                if ((G ? kind[j] == SPH_MPS_FLUID : kind[j] <= SPH_MPS_WALL) &&
                    dx * dx + dy * dy < re2 && phi[j] < pmin)
                    pmin = phi[j];
            }
        double sx = 0.0, sy = 0.0, mxx = 0.0, mxy = 0.0, myy = 0.0;
        for (long e = L->ptr[i]; e < L->ptr[i + 1]; e++) {
            const long j = L->j[e];
            if (kind[j] > SPH_MPS_WALL)
                continue;
            const double dx = x[j] - xi, dy = y[j] - yi;
            const double r2 = dx * dx + dy * dy;
            if (r2 >= re2)
                continue;
            const double rmin = SPH_MPS_RMIN * k->support;
            const double wr = weight(T, k, sqrt(r2)) / (r2 > rmin * rmin ? r2 : rmin * rmin);
            /* Neumann walls (G set): the ghost pressure of wall j seen from i */
            double pj = phi[j];
            if (G && kind[j] != SPH_MPS_FLUID) {
                double ggx, ggy;
                ghost_grad(G, i, j, &ggx, &ggy);
                pj = phi[i] + ggx * dx + ggy * dy;
            }
            const double f = (pj - pmin) * wr;
            sx += f * dx;
            sy += f * dy;
            if (corrected) {
                mxx += wr * dx * dx;
                mxy += wr * dx * dy;
                myy += wr * dy * dy;
            }
        }
        if (corrected) {
            corrective_solve(mxx, mxy, myy, coef, sx, sy, &gx[i], &gy[i]);
            continue;
        }
        gx[i] = coef * sx;
        gy[i] = coef * sy;
    }
}

static inline __attribute__((always_inline)) void
div_generic(sph_kernel_type T, const sph_mps_nbr *L, const double *restrict x,
            const double *restrict y, const unsigned char *restrict kind, const sph_kernel *k,
            double coef, int maxk, const double *restrict ux, const double *restrict uy,
            double *restrict div)
{
    const long np = L->n;
    const double re2 = k->support * k->support;
    const double rmin = SPH_MPS_RMIN * k->support, rmin2 = rmin * rmin;
#pragma omp parallel for schedule(dynamic, SPH_OMP_CHUNK) if (np >= SPH_OMP_MIN)
    for (long i = 0; i < np; i++) {
        if (kind[i] > SPH_MPS_WALL) {
            div[i] = 0.0;
            continue;
        }
        double s = 0.0;
        for (long e = L->ptr[i]; e < L->ptr[i + 1]; e++) {
            const long j = L->j[e];
            if (kind[j] > maxk)
                continue;
            const double dx = x[j] - x[i], dy = y[j] - y[i];
            const double r2 = dx * dx + dy * dy;
            if (r2 >= re2)
                continue;
            const double du = (ux[j] - ux[i]) * dx + (uy[j] - uy[i]) * dy;
            s += du * weight(T, k, sqrt(r2)) / (r2 > rmin2 ? r2 : rmin2);
        }
        div[i] = coef * s;
    }
}

void sph_mps_divergence(const sph_mps_nbr *L, const double *x, const double *y,
                        const unsigned char *kind, const sph_kernel *k, double coef,
                        const double *ux, const double *uy, double *div)
{
#define DIV(T) div_generic(T, L, x, y, kind, k, coef, SPH_MPS_DUMMY, ux, uy, div)
    SPH_KERNEL_DISPATCH(k->type, DIV);
#undef DIV
}

void sph_mps_divergence_fluid(const sph_mps_nbr *L, const double *x, const double *y,
                              const unsigned char *kind, const sph_kernel *k, double coef,
                              const double *ux, const double *uy, double *div)
{
#define DIV(T) div_generic(T, L, x, y, kind, k, coef, SPH_MPS_FLUID, ux, uy, div)
    SPH_KERNEL_DISPATCH(k->type, DIV);
#undef DIV
}

static inline __attribute__((always_inline)) void
strain_generic(sph_kernel_type T, const sph_mps_nbr *L, const double *restrict x,
               const double *restrict y, const unsigned char *restrict kind, const sph_kernel *k,
               double coef, const double *restrict ux, const double *restrict uy,
               double *restrict dudx, double *restrict dvdy)
{
    const long np = L->n;
    const double re2 = k->support * k->support;
    const double rmin = SPH_MPS_RMIN * k->support, rmin2 = rmin * rmin;
#pragma omp parallel for schedule(dynamic, SPH_OMP_CHUNK) if (np >= SPH_OMP_MIN)
    for (long i = 0; i < np; i++) {
        dudx[i] = dvdy[i] = 0.0;
        if (kind[i] != SPH_MPS_FLUID)
            continue;
        /* only a wall's ghost reads the strain (ghost_grad: fluid i, wall j among i's
         * neighbours): the interior skips the weighted pass */
        long e0 = L->ptr[i];
        while (e0 < L->ptr[i + 1] && kind[L->j[e0]] == SPH_MPS_FLUID)
            e0++;
        if (e0 == L->ptr[i + 1])
            continue;
        double sux = 0.0, suy = 0.0, svx = 0.0, svy = 0.0, mxx = 0.0, mxy = 0.0, myy = 0.0;
        for (long e = L->ptr[i]; e < L->ptr[i + 1]; e++) {
            const long j = L->j[e];
            if (kind[j] != SPH_MPS_FLUID)
                continue;
            const double dx = x[j] - x[i], dy = y[j] - y[i];
            const double r2 = dx * dx + dy * dy;
            if (r2 >= re2)
                continue;
            const double wr = weight(T, k, sqrt(r2)) / (r2 > rmin2 ? r2 : rmin2);
            const double du = (ux[j] - ux[i]) * wr, dv = (uy[j] - uy[i]) * wr;
            sux += du * dx;
            suy += du * dy;
            svx += dv * dx;
            svy += dv * dy;
            mxx += wr * dx * dx;
            mxy += wr * dx * dy;
            myy += wr * dy * dy;
        }
        double unused;
        corrective_solve(mxx, mxy, myy, coef, sux, suy, &dudx[i], &unused);
        corrective_solve(mxx, mxy, myy, coef, svx, svy, &unused, &dvdy[i]);
    }
}

void sph_mps_strain_fluid(const sph_mps_nbr *L, const double *x, const double *y,
                          const unsigned char *kind, const sph_kernel *k, double coef,
                          const double *ux, const double *uy, double *dudx, double *dvdy)
{
#define STR(T) strain_generic(T, L, x, y, kind, k, coef, ux, uy, dudx, dvdy)
    SPH_KERNEL_DISPATCH(k->type, STR);
#undef STR
}

/* ---- Neumann wall terms of the Poisson equation --------------------------------------------- */

static inline __attribute__((always_inline)) void
neumann_generic(sph_kernel_type T, const sph_mps_nbr *L, const double *restrict x,
                const double *restrict y, const unsigned char *restrict kind, const sph_kernel *k,
                double coef, const sph_mps_ghost *G, double *restrict b)
{
    const long np = L->n;
    const double re2 = k->support * k->support;
#pragma omp parallel for schedule(dynamic, SPH_OMP_CHUNK) if (np >= SPH_OMP_MIN)
    for (long i = 0; i < np; i++) {
        if (kind[i] != SPH_MPS_FLUID)
            continue;
        double s = 0.0;
        for (long e = L->ptr[i]; e < L->ptr[i + 1]; e++) {
            const long j = L->j[e];
            if (kind[j] != SPH_MPS_WALL && kind[j] != SPH_MPS_DUMMY)
                continue;
            const double dx = x[j] - x[i], dy = y[j] - y[i];
            const double r2 = dx * dx + dy * dy;
            if (r2 < re2) {
                double ggx, ggy;
                ghost_grad(G, i, j, &ggx, &ggy);
                s += (ggx * dx + ggy * dy) * weight(T, k, sqrt(r2));
            }
        }
        b[i] += coef * s;
    }
}

void sph_mps_neumann_rhs(const sph_mps_nbr *L, const double *x, const double *y,
                         const unsigned char *kind, const sph_kernel *k, double coef,
                         const sph_mps_ghost *G, double *b)
{
#define NEU(T) neumann_generic(T, L, x, y, kind, k, coef, G, b)
    SPH_KERNEL_DISPATCH(k->type, NEU);
#undef NEU
}

void sph_mps_gradient(const sph_mps_nbr *L, const double *x, const double *y,
                      const unsigned char *kind, const sph_kernel *k, double coef, int local_min,
                      int corrected, const double *phi, double *gx, double *gy)
{
#define GRAD(T) grad_generic(T, L, x, y, kind, k, coef, local_min, corrected, phi, NULL, gx, gy)
    SPH_KERNEL_DISPATCH(k->type, GRAD);
#undef GRAD
}

void sph_mps_gradient_neumann(const sph_mps_nbr *L, const double *x, const double *y,
                              const unsigned char *kind, const sph_kernel *k, double coef,
                              int local_min, int corrected, const double *phi,
                              const sph_mps_ghost *G, double *gx, double *gy)
{
#define GRAD(T) grad_generic(T, L, x, y, kind, k, coef, local_min, corrected, phi, G, gx, gy)
    SPH_KERNEL_DISPATCH(k->type, GRAD);
#undef GRAD
}

/* The pair passes after the correction: the stabilization and Koshizuka's collision model, as
 * stated in sph_mps_ops.h. One loop with a compile-time mode (each caller passes a constant, so
 * the compiler specialises it): for fluid particle i and neighbour j (fluid or wall) at r, vn the
 * speed of approach from the velocities before the pass, du the normal relative velocity i
 * loses. Velocities first, each from the positions and velocities before the pass; then the
 * positions, by dt times the change of velocity. */
enum { PASS_STABILIZE, PASS_COLLIDE };

static inline long pair_pass(const int mode, const sph_mps_nbr *L, const unsigned char *kind,
                             double d, double a, double dt, const double *vx0, const double *vy0,
                             double *x, double *y, double *vx, double *vy)
{
    const long n = L->n;
    long active = 0;
#pragma omp parallel for schedule(dynamic, SPH_OMP_CHUNK) reduction(+ : active) if (n >= SPH_OMP_MIN)
    for (long i = 0; i < n; i++) {
        if (kind[i] != SPH_MPS_FLUID)
            continue;
        const double xi = x[i], yi = y[i];
        double ux = vx0[i], uy = vy0[i];
        for (long e = L->ptr[i]; e < L->ptr[i + 1]; e++) {
            const long j = L->j[e];
            if (kind[j] > SPH_MPS_WALL)
                continue;
            const double rx = x[j] - xi, ry = y[j] - yi;
            const double r = sqrt(rx * rx + ry * ry);
            if (r == 0.0 || (mode == PASS_COLLIDE && r >= d))
                continue;
            const double vn = ((vx0[i] - vx0[j]) * rx + (vy0[i] - vy0[j]) * ry) / r;
            double du;
            if (mode == PASS_STABILIZE) /* a: share of a fluid neighbour's pair */
                du = (kind[j] == SPH_MPS_FLUID ? a : 1.0) * (vn - fmax(0.0, r - d) / dt);
            else /* a: (1 + e) / 2, walls as particles of the same mass */
                du = a * vn;
            if (du > 0.0) {
                const double f = du / r;
                ux -= f * rx;
                uy -= f * ry;
                active++;
            }
        }
        vx[i] = ux;
        vy[i] = uy;
    }
#pragma omp parallel for schedule(static) if (n >= SPH_OMP_MIN)
    for (long i = 0; i < n; i++)
        if (kind[i] == SPH_MPS_FLUID) {
            x[i] += dt * (vx[i] - vx0[i]);
            y[i] += dt * (vy[i] - vy0[i]);
        }
    return active;
}

long sph_mps_stabilize(const sph_mps_nbr *L, const unsigned char *kind, double d, double dt,
                       const double *vx0, const double *vy0, double *x, double *y, double *vx,
                       double *vy)
{
    return pair_pass(PASS_STABILIZE, L, kind, d, 0.5, dt, vx0, vy0, x, y, vx, vy);
}

long sph_mps_collide(const sph_mps_nbr *L, const unsigned char *kind, double d, double restitution,
                     double dt, const double *vx0, const double *vy0, double *x, double *y,
                     double *vx, double *vy)
{
    return pair_pass(PASS_COLLIDE, L, kind, d, 0.5 * (1.0 + restitution), dt, vx0, vy0, x, y, vx,
                     vy);
}
