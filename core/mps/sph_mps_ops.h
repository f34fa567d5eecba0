/*
 * sph_mps_ops: the particle interaction models of the MPS method (Koshizuka & Oka 1996; equation
 * numbers are Sheu, Chiao & Huang 2011, section 3), 2D, over neighbour lists (sph_mps_nbr.h):
 *
 *   number density   n_i = sum_{j != i} w(|r_j - r_i|)
 *   gradient  (3.4)  <grad phi>_i = d/n0 sum_{j != i} (phi_j - phi^_i) (r_j - r_i) / |r_j - r_i|^2
 *                    w(|r_j - r_i|), with phi^_i the smallest phi among i and its neighbours
 *                    (Koshizuka & Oka's local minimum: the pairwise forces are then repulsive
 *                    only, which keeps the particles from clustering). The extraction of (3.4)
 *                    prints one |r_j - r_i| in the denominator; (3.3) and Koshizuka & Oka have
 *                    its square, which is what reproduces a linear field (tested).
 *   Laplacian (3.5)  <lap phi>_i = 2d/(lambda n0) sum_{j != i} (phi_j - phi_i) w(|r_j - r_i|),
 *             (3.6)  lambda = int r^2 w dV / int w dV.
 *
 * Weights are the MPS kernels of sph_kernel.h, initialised with h = re / 2 (the library's
 * convention: support 2h = re): koshizuka w = re/r - 1, sheu_quartic (4.8). Their constant factors
 * (1 and 1/re) cancel in every operator, which divides by n0 of the same weight.
 *
 * n0 and lambda are lattice sums over the initial square lattice of spacing dx (what MPS codes
 * use: with them a quadratic field's Laplacian is exact on the lattice, tested); the continuous
 * lambda of (3.6) is available for comparison.
 *
 * Particle kinds: fluid and wall particles carry a pressure; dummy particles (the outer wall
 * layers) only fill the number density of the particles near the wall; off particles (lost)
 * take part in nothing. Every loop is parallel over particles, each writing only its own
 * entries in a fixed order: results do not depend on the number of threads. Kernel types are
 * compile-time constants inside the loops (SPH_KERNEL_DISPATCH), no call through a pointer.
 */
#ifndef SPH_MPS_OPS_H
#define SPH_MPS_OPS_H

#include "sph_kernel.h"
#include "sph_mps_nbr.h"

enum { SPH_MPS_FLUID = 0, SPH_MPS_WALL = 1, SPH_MPS_DUMMY = 2, SPH_MPS_OFF = 3 };

/* Distances below this fraction of re count as this fraction of re (the Koshizuka weight is
 * singular at r = 0; two particles that close have blown up anyway). */
#define SPH_MPS_RMIN 1e-3

/* Initialises an MPS weight of effective radius re (h = re / 2). Returns 0 or an SPH_ERR_*. */
int sph_mps_weight_init(sph_kernel *k, sph_kernel_type type, double re, sph_error *err);

/* sum over the points of the square lattice of spacing dx (dim 1..3) other than the origin of
 * w(r) (n0), and the ratio of sum r^2 w to sum w (lambda [m^2]). */
double sph_mps_lattice_n0(const sph_kernel *k, double dx, int dim);
double sph_mps_lattice_lambda(const sph_kernel *k, double dx, int dim);
/* lambda of eq. (3.6) by quadrature over the ball r < re in dim dimensions [m^2]; NAN where the
 * integral diverges (the Koshizuka weight in 1D). */
double sph_mps_lambda_integral(const sph_kernel *k, int dim);

/* n[i] for i < L->n: every neighbour counts, dummy included (off particles have no list and are
 * in nobody's, being sorted past L->n). Neighbours beyond the weight's re are skipped. */
void sph_mps_number_density(const sph_mps_nbr *L, const double *x, const double *y,
                            const sph_kernel *k, double *n);

/* m[i] = |sum_j w_ij (r_j - r_i)| [m] over every neighbour within re (as the number density):
 * the first moment of i's neighbourhood, 0 on a full lattice; at a free surface it equals the
 * first moment of the missing neighbours along the surface's normal. */
void sph_mps_moment(const sph_mps_nbr *L, const double *x, const double *y, const sph_kernel *k,
                    double *m);

/* The free-surface condition mps.surface = 1 (sph_mps.c): ghost[i] = coef |sum_j w_ij (r_j - r_i)|
 * / (dx/2) [1/m^2] for the particles flagged in surface, 0 for the others: the diagonal term
 * with which p = 0 on the water line, dx/2 beyond a surface particle's centre along the surface's
 * normal, enters that particle's row of the Poisson equation (coef the Laplacian's 2d/(lambda
 * n0)). Exact for a pressure linear along the normal on a lattice. */
void sph_mps_surface_ghost(const sph_mps_nbr *L, const double *x, const double *y,
                           const sph_kernel *k, double coef, double dx,
                           const unsigned char *surface, double *ghost);

/* out[i] = coef sum_j (phi_j - phi_i) w_ij over the neighbours j whose kind is not above
 * max_kind (SPH_MPS_WALL: fluid and walls; SPH_MPS_DUMMY: dummies too), coef = 2d/(lambda n0);
 * for the particles of kind fluid (others get 0). */
void sph_mps_laplacian(const sph_mps_nbr *L, const double *x, const double *y,
                       const unsigned char *kind, int max_kind, const sph_kernel *k, double coef,
                       const double *phi, double *out);

/* (gx[i], gy[i]) = coef sum_j (phi_j - phi^_i) (r_j - r_i) / r_ij^2 w_ij over fluid and wall
 * neighbours, coef = d/n0; phi^_i = min(phi_i, phi_j over those neighbours within re) when
 * local_min, else phi_i. For fluid particles (others get 0). corrected: d/n0 is replaced by the
 * inverse of sum_j w_ij (r_j - r_i)(r_j - r_i)^T / r_ij^2 (the corrective matrix of Khayyer &
 * Gotoh 2011; equal to d/n0 times the identity on a full lattice), which makes the model exact
 * for a linear field with any neighbourhood, the one-sided one of a free-surface particle
 * included; where that matrix is near-singular (fewer than two independent directions), d/n0. */
void sph_mps_gradient(const sph_mps_nbr *L, const double *x, const double *y,
                      const unsigned char *kind, const sph_kernel *k, double coef, int local_min,
                      int corrected, const double *phi, double *gx, double *gy);

/* div[i] = coef sum_j (u_j - u_i) . (r_j - r_i) / r_ij^2 w_ij (the divergence counterpart of
 * (3.4), coef = d/n0) over every neighbour except off ones (walls and dummies at rest count),
 * for fluid and wall particles (others get 0). */
void sph_mps_divergence(const sph_mps_nbr *L, const double *x, const double *y,
                        const unsigned char *kind, const sph_kernel *k, double coef,
                        const double *ux, const double *uy, double *div);

/* Walls as a Neumann boundary of the pressure (the alternative to walls as unknowns): a wall or
 * dummy neighbour j of fluid particle i holds the ghost pressure p_i + G_ij . (r_j - r_i), G_ij
 * the pressure gradient that stops i's motion through j's wall. In a projection step that is
 * dp/dn = (rho / dt) u*_i . n on the wall's normal n (u* the predicted velocity; rho g at rest:
 * hydrostatic) and, along the wall, the gradient of the body forces alone, rho (u*_i - u_i) / dt
 * (the wall does not stop a tangential motion, it only supports the fluid's weight): Adami, Hu &
 * Adams 2012's wall pressure extrapolation, dp/dn = rho (g - a_wall) . n, with the projection's
 * velocity term on the normal. sph_mps_ghost holds G = (rho / dt) u* per fluid particle and
 * T = (rho / dt) u, taken off G along the directions that are not j's normal (normal[j]:
 * SPH_MPS_NORMAL_X | _Y; a floor corner has both); T NULL: G in every direction. U = (rho / dt)
 * times the normal velocity a wall does not stop (that of a particle moving away from it in a flow
 * that stretches away from it; sph_mps.c), taken off G on j's normal directions; NULL: none. Then
 *   sph_mps_neumann_rhs:      b[i] += coef sum_walls G_ij . (r_j - r_i) w_ij (coef = 2d/(lambda
 *                             n0)), the ghosts' share of row i of A p = b, A assembled with
 *                             sph_mps_ppe_assemble_kinds(..., SPH_MPS_FLUID);
 *   sph_mps_gradient_neumann: the gradient of sph_mps_gradient with the walls' values the
 *                             ghosts and the local minimum over fluid only;
 *   sph_mps_divergence_fluid: the divergence over fluid neighbours only (the walls' share of the
 *                             source is the ghosts'). */
enum { SPH_MPS_NORMAL_X = 1, SPH_MPS_NORMAL_Y = 2 };
typedef struct sph_mps_ghost {
    const double *gx, *gy;       /* (rho / dt) u* of the fluid particles [Pa/m] */
    const double *tx, *ty;       /* (rho / dt) u of the fluid particles, or NULL [Pa/m] */
    const unsigned char *normal; /* per wall particle: SPH_MPS_NORMAL_* of its wall's normal */
    const double *ux, *uy;       /* (rho / dt) U on x / y normals, or NULL [Pa/m] */
} sph_mps_ghost;
/* The strain along the walls that sets U (sph_mps.c): (dudx[i], dvdy[i]) the diagonal of the
 * corrected gradient (as sph_mps_gradient's) of the velocity (ux, uy) over the fluid neighbours
 * only (d/n0 where their matrix is near-singular), for fluid particles with a wall or dummy among
 * their neighbours, the only ones a wall's ghost reads (others get 0). */
void sph_mps_strain_fluid(const sph_mps_nbr *L, const double *x, const double *y,
                          const unsigned char *kind, const sph_kernel *k, double coef,
                          const double *ux, const double *uy, double *dudx, double *dvdy);
void sph_mps_neumann_rhs(const sph_mps_nbr *L, const double *x, const double *y,
                         const unsigned char *kind, const sph_kernel *k, double coef,
                         const sph_mps_ghost *G, double *b);
void sph_mps_gradient_neumann(const sph_mps_nbr *L, const double *x, const double *y,
                              const unsigned char *kind, const sph_kernel *k, double coef,
                              int local_min, int corrected, const double *phi,
                              const sph_mps_ghost *G, double *gx, double *gy);
void sph_mps_divergence_fluid(const sph_mps_nbr *L, const double *x, const double *y,
                              const unsigned char *kind, const sph_kernel *k, double coef,
                              const double *ux, const double *uy, double *div);

/* Dynamic stabilization, after Tsuruta, Khayyer & Gotoh (2013, Comput. Fluids 82: 158-164): a
 * pairwise repulsive term of the pressure gradient that acts only on pairs about to come closer
 * than d, sized by a kinematic condition instead of the pressure equation. For fluid particle i
 * and neighbour j (fluid or wall; dummies and off particles take no part) at distance r, e =
 * (r_j - r_i) / r, with vn = (u_i - u_j) . e their speed of approach, the pair would end the
 * next step at r - dt vn; where that is below d, the approach in excess of what brings them to d
 * is removed:
 *
 *   du_ij = max(0, vn - max(0, r - d) / dt)   (relative normal velocity removed),
 *
 * half from each of two fluid particles (equal masses: momentum is conserved; a lone pair only
 * loses kinetic energy), all from the fluid particle against a wall (fixed). In the gradient's form
 * (2D) this is the pair term (2/n0) dP_ij (r_j - r_i) w_ij / r^2 added to (3.4), with dP_ij = c rho
 * n0 r du_ij / (2 dt w_ij), c = 1/2 against a fluid particle and 1 against a wall; like the rest of
 * the gradient it changes u by du and r by dt du (r = r* + dt u'), so the pair also ends this
 * step dt du farther apart than without it: a margin on top of the condition. A pair at rest, and
 * any pair of a lattice of spacing dx > d moving slower than (dx - d) / dt, is untouched: still
 * water is not moved. Pairs already closer than d stop approaching but are not pushed apart (no
 * energy is added). The paper's equations were not at hand: this is the kinematic condition it
 * describes (a repulsion just sufficient to keep pairs from clustering), not a transcription.
 *
 * vx0, vy0 are the velocities before it (read only, every particle of L), vx, vy, x, y are
 * written for fluid particles only, each from its own pairs: parallel and order-independent.
 * Returns the number of (i, j) entries that acted (a pair of fluid particles counts twice). */
long sph_mps_stabilize(const sph_mps_nbr *L, const unsigned char *kind, double d, double dt,
                       const double *vx0, const double *vy0, double *x, double *y, double *vx,
                       double *vy);

/* Koshizuka's collision model: fluid particle i closer than d to a neighbour j (fluid or wall)
 * and approaching it (vn > 0, as above) loses (1 + e)/2 of vn along e (j's mass equal to i's;
 * walls as fixed particles of the same mass, as in Koshizuka's codes), e the restitution; the
 * positions move by dt times the change, as in the correction. The same contract as
 * sph_mps_stabilize: parallel and independent of the particles' order and the threads (the
 * pairs see the positions and velocities before the pass). Returns the entries that acted. */
long sph_mps_collide(const sph_mps_nbr *L, const unsigned char *kind, double d, double restitution,
                     double dt, const double *vx0, const double *vy0, double *x, double *y,
                     double *vx, double *vy);

#endif
