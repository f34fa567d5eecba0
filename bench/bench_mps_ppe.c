/*
 * bench_mps_ppe: the MPS pressure solve on Koshizuka & Oka's dam break (a column L = 0.146 m wide
 * and 2L high at the left of a tank 4L long, 2 wall + 2 dummy layers) at three resolutions
 * (L/dx = 20, 40, 80): the Poisson system of the first step (mixed source: the velocity
 * divergence after one gravity predictor of dt = 0.2 sqrt(dx/g), Tanaka & Masunaga 2010),
 * solved from zero to a relative residual of 1e-8 with plain, Jacobi- and IC(0)-preconditioned
 * CG, with 1 and 2 threads. Prints unknowns, iterations, setup + solve time. Never fails on time.
 *
 * Usage: bench_mps_ppe [koshizuka|sheu_quartic] [RE_OVER_DX]
 */
#include "sph_cells.h"
#include "sph_mps_ops.h"
#include "sph_mps_ppe.h"

#include <math.h>
#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void run(sph_kernel_type type, double re_dx, int res)
{
    const double L = 0.146, dx = L / res, g = 9.81, rho = 1000.0;
    const int nx = res, ny = 2 * res, tx = 4 * res, layers = 4, wl = 2;
    const long nwall = (long)layers * (tx + 2 * layers) + 2L * layers * (2 * ny);
    const long n = (long)nx * ny + nwall;
    sph_particles P;
    if (sph_particles_alloc(&P, n, 2, 0)) {
        fprintf(stderr, "out of memory\n");
        exit(1);
    }
    long k = 0;
    for (int i = 0; i < nx; i++)
        for (int j = 0; j < ny; j++) {
            P.x[k] = (i + 0.5) * dx;
            P.y[k] = (j + 0.5) * dx;
            P.vy[k] = 0.0;
            P.type[k] = SPH_FLUID;
            P.id[k] = (int)k;
            k++;
        }
    for (int l = 0; l < layers; l++) {
        for (int i = -layers; i < tx + layers; i++) {
            P.x[k] = (i + 0.5) * dx;
            P.y[k] = -(l + 0.5) * dx;
            P.type[k] = SPH_BOUNDARY;
            P.id[k] = (int)k;
            k++;
        }
        for (int j = 0; j < 2 * ny; j++)
            for (int side = 0; side < 2; side++) {
                P.x[k] = side ? tx * dx + (l + 0.5) * dx : -(l + 0.5) * dx;
                P.y[k] = (j + 0.5) * dx;
                P.type[k] = SPH_BOUNDARY;
                P.id[k] = (int)k;
                k++;
            }
    }
    const double re = re_dx * dx, m = (layers + 2) * dx;
    const double lo[3] = {-m, -m, 0}, hi[3] = {tx * dx + m, 2 * ny * dx + m, 0};
    sph_cells cells;
    sph_mps_nbr nl = {0};
    sph_kernel w;
    if (sph_cells_alloc(&cells, 2, lo, hi, re, n) || sph_mps_weight_init(&w, type, re, NULL)) {
        fprintf(stderr, "setup failed\n");
        exit(1);
    }
    sph_cells_sort(&cells, &P);
    if (sph_mps_nbr_build(&nl, &cells, P.x, P.y, n, re)) {
        fprintf(stderr, "out of memory\n");
        exit(1);
    }
    unsigned char *kind = malloc((size_t)n), *surf = malloc((size_t)n);
    double *nd = malloc((size_t)n * sizeof *nd), *div = malloc((size_t)n * sizeof *div);
    double *rhs = malloc((size_t)n * sizeof *rhs), *p = malloc((size_t)n * sizeof *p);
    const double dt = 0.2 * sqrt(dx / g);
    for (long i = 0; i < n; i++) {
        const double depth = fmax(fmax(-P.x[i], P.x[i] - tx * dx), -P.y[i]);
        kind[i] = P.type[i] == SPH_FLUID ? SPH_MPS_FLUID
                  : depth < wl * dx      ? SPH_MPS_WALL
                                         : SPH_MPS_DUMMY;
        P.vx[i] = 0.0;
        P.vy[i] = P.type[i] == SPH_FLUID ? -g * dt : 0.0;
    }
    const double n0 = sph_mps_lattice_n0(&w, dx, 2), lam = sph_mps_lattice_lambda(&w, dx, 2);
    sph_mps_number_density(&nl, P.x, P.y, &w, nd);
    for (long i = 0; i < n; i++)
        surf[i] = kind[i] <= SPH_MPS_WALL && nd[i] < 0.97 * n0;
    sph_mps_divergence(&nl, P.x, P.y, kind, &w, 2.0 / n0, P.vx, P.vy, div);
    for (long i = 0; i < n; i++)
        rhs[i] = -rho / dt * div[i];
    sph_mps_ppe S;
    memset(&S, 0, sizeof S);
    for (int threads = 1; threads <= 2; threads++) {
        omp_set_num_threads(threads);
        for (int pc = 0; pc < 3; pc++) {
            /* best of 3 (the machine is shared) */
            double best = INFINITY;
            sph_mps_cg_stats st = {0};
            for (int rep = 0; rep < 3; rep++) {
                memset(p, 0, (size_t)n * sizeof *p);
                const double t0 = omp_get_wtime();
                sph_mps_ppe_assemble(&S, &nl, P.x, P.y, kind, surf, &w, 4.0 / (lam * n0));
                sph_mps_ppe_solve(&S, rhs, p, (sph_mps_precond)pc, 1e-8, 100000, &st);
                best = fmin(best, omp_get_wtime() - t0);
            }
            printf("%-12s L/dx %3d  unknowns %7ld  threads %d  %-6s  iterations %5ld  "
                   "residual %.1e  assemble+solve %8.2f ms  (%.2f us per unknown-iteration)\n",
                   sph_kernel_type_name(type), res, S.n, threads, sph_mps_precond_name(pc),
                   st.iterations, st.residual, 1e3 * best,
                   1e6 * best / ((double)S.n * (st.iterations + 1)));
        }
    }
    sph_mps_ppe_free(&S);
    sph_mps_nbr_free(&nl);
    sph_cells_free(&cells);
    sph_particles_free(&P);
    free(kind);
    free(surf);
    free(nd);
    free(div);
    free(rhs);
    free(p);
}

int main(int argc, char **argv)
{
    sph_kernel_type type = SPH_KERNEL_KOSHIZUKA;
    if (argc > 1) {
        const int t = sph_kernel_type_from_name(argv[1]);
        if (t < 0 || !sph_kernel_is_mps((sph_kernel_type)t)) {
            fprintf(stderr, "usage: bench_mps_ppe [koshizuka|sheu_quartic] [RE_OVER_DX]\n");
            return 64;
        }
        type = (sph_kernel_type)t;
    }
    const double re_dx = argc > 2 ? atof(argv[2]) : 2.1;
    const int res[3] = {20, 40, 80};
    for (int r = 0; r < 3; r++)
        run(type, re_dx, res[r]);
    return 0;
}
