/*
 * MPS still water (issue 12): a tank of water H = 0.2 m deep and 0.4 m wide at rest, both MPS
 * kernels. After 2 s the largest speed must be below 1% of sqrt(g H) and the mean pressure of the
 * bottom fluid row within 5% of rho0 g H (the row's centres are dx/2 above the floor: rho0 g (H -
 * dx/2) is what it should hold; the tolerance is against rho0 g H, so both are printed and
 * the hydrostatic value of the row is also held to 5%).
 *
 * The ctest (validation_mps_still) runs it without arguments: dx = 0.005 m = H/40 (80 x 40
 * particles, 7924 steps each, about a minute for both kernels on one core), with the settings of
 * the MPS cases (cases/mps_dambreak.json, solitary_wave.json, mps_dambreak_re500.json; the
 * eighth session made them one): mps.surface 0 (Koshizuka & Oka's p = 0 at the surface
 * particles' centres), the mixed source with relax 0.005, the corrected gradient, the dynamic
 * stabilization at 0.9 dx; the Koshizuka weight with re = 2.1 dx (Koshizuka & Oka 1996) and the
 * quartic with re = 2.0 dx (Sheu et al. 2011: re = 2h, h the spacing; the cases' weight).
 * Figures there after 2 s (vmax in % of sqrt(gH) / bottom row in % of rho0 g H): koshizuka
 * 0.26 / -3.29, sheu_quartic 0.00 / -2.58. Both pass, but the Koshizuka run is not at rest: a
 * checkerboard mode under the surface near the side walls grows at about 4/s from 1 s (vmax
 * 0.003% at 0.5 s, 0.006% at 1 s, 0.026% at 1.5 s, 0.26% at 2 s), which the stabilization at
 * 0.9 dx does not touch (at 1.0 dx it damps it: 0.02%); at that rate it would cross the 1% bound
 * near 2.35 s (an extrapolation, not run). See below for what it is and what was tried. At
 * dx = 0.01 (H/20) the Koshizuka weight misses the bottom-row bound by 0.02% (-5.02%: p = 0 on
 * the top row's centres is a -dx/(2H) bias), so the test does not run there; mps.surface 1
 * removes that bias but makes the mode blow the Koshizuka weight up at dx = 0.005 (below).
 *
 * Usage: test_mps_still [DX [KERNEL [SURFACE [STAB [END]]]]] (default 0.005 m; KERNEL koshizuka or
 * sheu_quartic for one only, `both` for both; SURFACE the mps.surface condition, default the
 * case default 0, -1 for it; STAB mps.stabilization in dx, default 0.9, the cases'; 0: off; END the
 * end time, default 2 s, at which the bounds are checked). Prints the figures every 0.5 s too.
 *
 * Settings: mixed source (Tanaka & Masunaga) with relax 0.005, corrected gradient (without the
 * local minimum), dt = 0.1 dx / sqrt(2 g H) (the method's CFL limit with cfl 0.1), nu = 1e-6.
 *
 * State (issue 12, third session): passes at dx 0.01 with sheu_quartic and at dx 0.005 with both
 * kernels; koshizuka at dx 0.01 misses the bottom-row bound by 0.02% (the p = 0 placement below).
 * Figures after 2 s (vmax in % of sqrt(gH), bottom row in % of rho0 g H):
 *
 *                         koshizuka 0.01  sheu 0.01     koshizuka 0.005     sheu 0.005
 *   before (2nd session)  0.04   -5.02    0.12  -4.93   blow-up at 1.74 s   0.04  -2.59
 *   walls: normal only    0.01   -5.02    0.01  -4.96   0.25  -3.74         0.002 -2.58
 *   + mps.surface = 1     0.04   -2.55    0.05  -2.49   34 (grows > 1.5 s)  0.08  -1.34
 *
 * (1) What drove the growing mode at the contact line: the Neumann walls' ghost gradient was
 *   (rho/dt) u* in every direction, so a wall also "stopped" the tangential motion of the fluid
 *   next to it with a gain rho/dt (hence faster growth with a smaller dt): an odd-even mode of
 *   the columns next to each side wall under the free surface (vx, vy and n* alternating column
 *   by column, spreading from the wall; the free-surface set never flickered before the mode
 *   was large: flicker is its consequence, not its cause). The ghost now holds (rho/dt) u* only
 *   on the wall's normal and the body forces rho (u* - u)/dt along it (Adami, Hu & Adams 2012's
 *   wall pressure; sph_mps_ops.h). vmax fell 4-20x and koshizuka at dx 0.005 no longer blows
 *   up, but the same odd-even mode still grows slowly from the side walls with koshizuka at
 *   dx 0.005 (0.006% at 1 s, 0.026% at 1.5 s, 0.25% at 2 s). Dropping the velocity term
 *   altogether (G = rho g) blows up at once (no-penetration is lost).
 * (2) The -dx/H bias: mps.surface = 1 (sph_config.h; `test_mps_still DX KERNEL 1`) puts p = 0 on
 *   the water line dx/2 above the top row's centres by the ghost-fluid extrapolation of Gibou
 *   et al. 2002 (surface particles become unknowns with a diagonal term from their missing
 *   neighbours, sph_mps.c): the bottom row is then within 0.1% of rho0 g (H - dx/2) at both
 *   resolutions, but the near-wall odd-even mode grows faster with it, and blows koshizuka up
 *   at dx 0.005 after 1.5 s; so the default stays 0 (Koshizuka & Oka). With the one-sided
 *   velocity divergence in the surface rows' source, the surface row itself went odd-even
 *   unstable within 0.2 s: their source is 0.
 * Fourth session (issue 12): the mode is not fixed; mps.surface stays 0, the test stays out of
 *   ctest (it fails for one case with either condition). Figures (re-measured, unchanged: the
 *   session's code changes are a refactor and a unit test), vmax in % of sqrt(gH) / bottom row in
 *   % of rho0 g H at 0.5, 1, 1.5, 2 s:
 *     surface 0: koshizuka 0.01   0.011 0.010 0.013 0.01  / -5.04 -5.03 -5.03 -5.02 (FAILS)
 *                sheu 0.01        0.007 0.004 0.011 0.01  / -4.99 -4.97 -4.96 -4.96
 *                koshizuka 0.005  0.003 0.006 0.026 0.25  / -2.62 -2.62 -2.64 -3.74
 *                sheu 0.005       ok at 2 s: 0.002 / -2.58
 *     surface 1: koshizuka 0.01   ok at 2 s: 0.04 / -2.55;  sheu 0.01: 0.05 / -2.49
 *                koshizuka 0.005  0.016 0.017 0.050 34 (FAILS) / -1.39 -1.39 -1.46 -9.80
 *                sheu 0.005       ok at 2 s: 0.08 / -1.34
 *   What the mode is (koshizuka 0.005, surface 1, velocities and p - rho g (H - y) dumped at
 *   1.7 s): a checkerboard, not a column mode of the wall rows: p alternates row by row and
 *   column by column (+-5 Pa), vx alternates by row on every other column, vy by column, in the
 *   rows 1-11 below the surface (the surface row itself quiet) and 2-12 columns from each side
 *   wall, the wall columns quiet; it starts in the second row 8 columns from the wall. All of it
 *   is invisible to the interior gradient and divergence of a lattice (a checkerboard has neither),
 *   so it is not the walls' ghosts. It grows at about 4/s from 1 s (both conditions; with
 *   surface 1 it turns nonlinear at 2e-3 m/s near 1.75 s and blows up; with surface 0 it reaches
 *   0.25% at 2 s). What it depends on (koshizuka 0.005 surface 1 unless said, vmax at 2 s):
 *     - the number-density term's stiffness relax rho / dt^2: relax 0.0025: 0.02% and flat;
 *       0.001: flat to 1.5 s; 0.01: 0.34% by 1 s; cfl 0.05 (dt halved, the stiffness x4): blows
 *       up at 1.06 s, and with surface 0 too (4.6% at 1 s, blow-up at 1.08 s): the surface
 *       condition only sets where it turns nonlinear. Its growth rate scales with
 *       sqrt(relax) / dt, not with the physics: an overstability of the density spring, which
 *       the MPS gradient (w / r^2 with the corrective matrix, not the derivative of the number
 *       density) does not oppose conservatively.
 *     - the weight's edge: koshizuka with re = 2.0 dx or 2.5 dx instead of 2.1: flat (0.03% and
 *       0.01% at 2 s). At 2.1 dx the neighbours 2 dx away weigh w = 0.05 in the Laplacian but
 *       move n* with dw/dr = -0.525 / dx: the number density sees them ten times more than the
 *       pressure equation couples them.
 *     - the quartic needs the spring: sheu with relax 0.0025 grows to 0.34% (dx 0.01) and 0.09%
 *       (0.005) at 2 s, with 0.001 to 1.2-1.3% (both fail; the free-surface set flickers). relax
 *       0.0025 would pass all four at 2 s (koshizuka 0.03% / 0.02%, the quartic 0.34% / 0.09%
 *       and growing): a window between two instabilities that narrows with dt, not a fix, so the
 *       test keeps 0.005 (tuning it to this test is not done).
 *   Tried, none fixes it (each koshizuka 0.005 surface 1 unless said):
 *     - walls counted (at rest) in the velocity divergence, the walls' ghosts the body forces
 *       only (the other consistent pairing of the Neumann condition and the source): the floor's
 *       gravity counted twice, bottom row -10.7% from 0.5 s, vmax 2.5% at 2 s.
 *     - the surface rows' Neumann velocity term dropped (their source is 0): 25% at 2 s.
 *     - Khayyer & Gotoh 2011's error-compensating source (relax -> dt |div u*| per particle, the
 *       divergence term times 1 + |n* - n0| / n0; n* at the predicted positions): koshizuka passes
 *       at both resolutions (0.09% / 0.05% at 2 s, bottom row -2.37% / -1.07%), but the quartic
 *       blows up at both (139% at 2 s at dx 0.01, at 1.84 s at 0.005): it is a small relax at
 *       rest, and the quartic needs the spring (above).
 *     - Khayyer & Gotoh 2009's higher-order source (minus the rate of change of n* from dw/dr
 *       over n0, instead of the MPS divergence; also normalised by the lattice sum of -r dw/dr):
 *       blows up by 0.86 s.
 *     - the Laplacian of the body force's linear pressure made exact on any distribution (the
 *       right-hand side less coef rho (u* - u)/dt . sum_j w_ij r_ij, a lagged first-order
 *       correction of (3.5)), on every row or only next to the surface: blows up at 1.92 s /
 *       48% at 2 s.
 *   The hypothesis checked: the energy-conserving pair gradient -(2/S) sum_j (p_i + p_j) dw/dr
 *   (r_j - r_i)/r (S the lattice sum of -r dw/dr; exact for a linear pressure on a lattice; the
 *   force minus the derivative of sum_k p_k n_k) in place of the corrected one, surface 0,
 *   koshizuka dx 0.005 at cfl 0.05 (blows up at 1.08 s with the corrected gradient): no blow-up,
 *   vmax 1.1-1.6e-2 m/s at 1.25-1.5 s and not growing. But it is not a fix as it stands: its
 *   p_i sum_j dw/dr term pushes the rows whose neighbourhood is cut by the surface (5-8% of
 *   sqrt(gH) in the first 0.5 s, the free-surface set flickering), which needs the missing
 *   neighbours' ghost pressures in the pair sum (for surface 1: computable from the present
 *   neighbours' sums and the lattice's, as the Laplacian's ghost diagonal is). Tried that too
 *   (the missing pairs from the present sums: Dirichlet ghosts on surface rows, p_i + rho (u* -
 *   u)/dt . r below them): blows up by 0.2 s (dx 0.01, either surface condition), starting at
 *   the floor: the pair gradient of the solved pressure is 0.6% off the corrected one on the
 *   bottom row (-9883 against -9828 Pa/m), i.e. it is not the gradient the pressure equation's
 *   Laplacian was solved for; a projection consistent with it needs its own Laplacian.
 *   Next: what is left is the number-density term against a gradient that is not its adjoint.
 *   Candidates: that conservative gradient with the surface's ghost pairs, or
 *   Koshizuka & Oka's own radii (n* and the gradient at 2.1 dx, the Laplacian at 4 dx: the wide
 *   Laplacian couples the 2 dx neighbours that n* sees; needs 8 wall layers and the surface
 *   condition for the rows whose stencil crosses the water line, see below), or a dt-independent
 *   density relaxation time. The ghost-fluid condition also misses, with re > 2 dx, the share of
 *   the second row's neighbours beyond the water line (unit test test_surface_ghost_hydrostatic:
 *   +0.49% on the bottom row of a 15-row column with the Koshizuka weight, exact with the
 *   quartic); extending the extrapolation to every row whose stencil crosses the line (Gibou et
 *   al. do it for every crossing link) is not done (koshizuka with re = 2.5 dx misses more and
 *   is stable, so it is not the mode's cause).
 * Fifth session (issue 12): the dam break (cases/mps_dambreak.json) does not run with this test's
 *   settings: mixed source, relaxation 0.005, corrected gradient blows up at t = 0.13 s at
 *   dx = L/20 (the density error grows to 17%; with the collision model too, at 0.15 s, and at
 *   0.09 s at L/40). It runs with Koshizuka & Oka's (density source, relaxation 1, the local
 *   minimum) and the collision model of Koshizuka's codes (0.5 dx), and its front then follows
 *   their MPS result within 1-5% RMS; but under those settings still water is far from rest
 *   (dx 0.01, 2 s: vmax 44% of sqrt(gH) with koshizuka, 46% with sheu_quartic). One set of
 *   settings for both is still to be found.
 * Sixth session (issue 12): measured why (the dam break, cases/mps_dambreak.json, to t = 0.05 s,
 *   T = 0.58): with the number-density source and relaxation 1 the pressure is 0 on 54% / 91% /
 *   90% of the fluid at L/20 / L/40 / L/80 (negative solutions clipped) and n* < beta n0 on 7% /
 *   31% / 46% (the upper column "boils": the source's noise grows as 1/dt^2 while the hydrostatic
 *   pressure stays, so it gets worse with resolution); the bottom row holds 4-8% of rho0 g 2L
 *   at L/20 and L/40. The mixed source with relaxation 0.05 (the minimum gradient, collision
 *   0.5) cuts the false surface to 124 of 3,200 at L/40 and runs the dam break (front 0.7% RMS
 *   from K&O's MPS, 14.4% from their experiment; relaxation 1: 1.3% / 16.1%), but still water
 *   (dx 0.01, 2 s) is not at rest under the minimum gradient with any source (vmax 17-38% of
 *   sqrt(gH)); the corrected gradient keeps it at rest (mixed 0.01: 0.11%, -4.9%) but fails the
 *   dam break with or without the collision model (mixed 0.05 and 0.01 at L/40). The gradient
 *   is the crux: a gradient that is exact on a lattice (still water) and as robust as the local
 *   minimum's in splashing flow. The solitary wave (cases/solitary_wave.json) shows the same:
 *   every setting that runs it expands the water 1.5-3.6% (centre of mass by t = 8 s) and gains
 *   0.8-7.9 times the wave's kinetic energy by t = 5 s; its run-up at dx 0.8 ranges from -25% to
 *   +23% of third order over relaxations 0.2-1, the mixed source, cfl 0.05 and the water-line
 *   condition, each with snapshots every 0.5 s and 0.2 s.
 * Seventh session (issue 12, branch mps-ds): the dynamic stabilization (mps.stabilization d/dx,
 *   after Tsuruta, Khayyer & Gotoh 2013; sph_mps_stabilize in sph_mps_ops.h: pairs that would end
 *   the next step closer than d lose the approach beyond it; the paper's own equations were not
 *   at hand, the kinematic condition is derived) with this test's settings (corrected, mixed,
 *   relax 0.005), STAB the fourth argument. Still water, vmax % / bottom row % at 2 s: d = 0.9 dx
 *   changes nothing (dx 0.01: 0.01 / -5.02 koshizuka (the bias), 0.01 / -4.96 sheu; dx 0.005:
 *   0.26 / -3.29, 0.00 / -2.58); d = dx damps the checkerboard mode (approaching lattice pairs
 *   lose their approach): dx 0.01 0.01 / -4.98, 0.00 / -5.00; dx 0.005 0.02 / -2.61, 0.00 / -2.59.
 *   The dam break then runs with the corrected gradient (without it: blow-up at 0.13 s at L/20,
 *   0.09 s at L/40): d = 0.9 dx, relax 0.005, front RMS against K&O's MPS / experiment 1.4% /
 *   14.6% at L/20, 1.0% / 15.5% at L/40 (relax 0.05: 1.6 / 13.4, 0.9 / 15.1; the collision model
 *   changes nothing; d = 0.5 dx blows up at L/40, 0.8 and 1.0 run). The solitary wave runs too
 *   (without DS: blow-up at 1 s): R/d within -8% to +6% of third order over relax 0.005-0.05,
 *   d = 0.9-1.0 dx and snapshot intervals; but the water still expands (centre of mass +1.5-3%
 *   by 8 s with d = 0.9 dx, +0.7-1.5% with d = dx) and gains energy (0.6-2.7 times the wave's
 *   kinetic energy), a wave of height dx as much, independently of dt, dx, the clipping of
 *   negative pressures, mps.surface and nu. With Sheu et al.'s quartic (re = 2 dx) it does not:
 *   centre of mass within +-0.3%, energy slightly lost, R/d -1.6% (-1.3% to +3.9% over relax
 *   0.005-0.05 and snapshot intervals; +5.2% at dx 0.4), and that setting (quartic, corrected,
 *   mixed 0.005, d = 0.9 dx) also passes still water (above; and at dx 0.0025: 0.00% / -1.46%)
 *   and runs the dam break (front RMS against K&O's MPS / experiment: L/20 3.7 / 10.4%, L/40
 *   1.6 / 13.2%, L/80 0.8 / 14.7%).
 *   Figures and runs: /work/runs/ds/README.md.
 * Issue 22 (branch mps-defects): the walls no longer pull back a particle that moves away from
 *   them while the flow beside it stretches away too (sph_mps.c: the wall column of the draining
 *   dam break hung on the wall). Still water at dx 0.005, vmax % / bottom row % at 0.5, 1, 1.5,
 *   2 s: koshizuka 0.003 0.006 0.025 0.28 / -2.62 -2.63 -2.65 -3.26 (before: 0.003 0.006 0.026
 *   0.264 / -2.62 -2.62 -2.64 -3.29); sheu_quartic 0.001 0.000 0.000 0.00 / -2.59 at each
 *   (before: 0.00 / -2.58 at 2 s). Past 2 s (before the change, `test_mps_still 0.005 koshizuka
 *   -1 0.9 10`): the Koshizuka checkerboard keeps growing, vmax 3.34% at 2.5 s (bottom row
 *   -3.30%), 4.41% at 3 s (+0.75%): the 1% bound is crossed between 2 and 2.5 s, the growth slows
 *   past 2.5 s (nonlinear). After the change, to 8 s: vmax 0.28% at 2 s, 3.40% at 2.5 s, 3.67%
 *   at 3 s, 6.03% at 4 s, 4.72% at 5 s, 5.30% at 7 s, 5.83% at 8 s, 7.87% at 9 s, 7.70% at
 *   10 s (bottom row -4.72% at 8 s, -22.2% at 9.5 s, -8.17% at 10 s): past 2.5 s it grows more
 *   slowly but keeps growing and the pressure swings, so a still tank with that weight is not at
 *   rest past 2.5 s and fails both bounds by 10 s. The quartic (the cases' weight) shows no such
 *   mode. At H/20 (`test_mps_still 0.01 koshizuka -1 0.9 8`, dt twice as long) the same mode
 *   comes at the same step, not the same time: vmax 0.013% to 3 s, 0.026% at 3.5 s, 0.066% at
 *   4 s (7920 steps; H/40: 0.28% at 7924), 0.265% at 4.5 s, 2.19% at 5 s (9900 steps), 3.9% at
 *   6 s, 5.8% at 6.5 s, 6.32% at 8 s (15856 steps; H/40: 6.03% at 15848), the bottom row -8.9%
 *   at 7.5 s. So it is a mode of the step (its rate scales with sqrt(relax) / dt, above), and
 *   since nothing tried here damps it for both weights, sphd refuses the Koshizuka weight at
 *   /kernel/type for runs estimated at more than 8000 steps (time.end over the step at rest;
 *   sph_mps.c, MPS_KOSHIZUKA_MAX_STEPS), where the mode is still 0.07-0.3% of sqrt(gH). The
 *   cases' Koshizuka runs stay well below it (the dam breaks under 3000 steps, the solitary wave
 *   at dx 0.4 m about 4900). This test's END goes past it through the core's advance (run()).
 * Earlier sessions: the first (walls as unknowns of the pressure equation): vmax after 2 s
 *   0.11-0.4 m/s (8-29% of sqrt(gH)) over every option tried: the fluid column next to each side
 *   wall slid down and drove a circulation that never settled. Walls as a Neumann boundary cured
 *   that. The second then found the slowly growing contact-line mode: it grows faster with a
 *   larger relax (relax 1 and 0.2 blow up within 0.3-0.7 s, 0.05 at 1.5 s, 0.01 grows at
 *   dx 0.01); the local minimum with the corrective matrix drives a row-sliding mode instead
 *   (the plain gradient with the local minimum: 34% of sqrt(gH) by 1.6 s at dx 0.005, third
 *   session); a split of the source (number density moving positions only) and particle
 *   shifting (Lind et al. 2012, tangential at the surface) made it worse.
 */
#include "sph_sim.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Mean pressure of the bottom fluid row (centres below dx) and its size. */
static double bottom_pressure_n(sph_sim *s, double dx, long *nrow)
{
    sph_particle_view v;
    sph_sim_particles(s, &v);
    double psum = 0.0;
    long n = 0;
    for (long i = 0; i < v.n; i++)
        if (v.type[i] == 0 && v.pos[1][i] < dx) {
            psum += v.p[i];
            n++;
        }
    *nrow = n;
    return n ? psum / n : 0.0;
}

static double bottom_pressure(sph_sim *s, double dx)
{
    long n;
    return bottom_pressure_n(s, dx, &n);
}

static int run(sph_kernel_type type, double dx, int surface, double stab, double t_end)
{
    const double H = 0.2, W = 0.4, g = 9.81;
    sph_config c = sph_config_default();
    c.method = SPH_METHOD_MPS;
    c.kernel = sph_kernel_spec_default(type);
    c.dx = dx;
    c.domain = (sph_box){{-0.1, -0.1, 0}, {W + 0.1, 0.5, 0}};
    c.nfluid = 1;
    c.fluid[0] = (sph_box){{0, 0, 0}, {W, H, 0}};
    c.boundary = SPH_BOUNDARY_DYNAMIC;
    c.layers = 4;
    c.has_tank = 1;
    c.tank = (sph_box){{0, 0, 0}, {W, 0.4, 0}};
    c.visc = SPH_VISC_LAMINAR;
    c.nu = 1e-6;
    /* sphd refuses the Koshizuka weight for runs of more than 8000 steps (sph_mps.c: the mode
     * below); the core's advance is not bound by time.end, so END studies it past that: the
     * configuration holds at most 2 s (7924 steps at H/40), the loop below runs to END */
    c.t_end = fmin(t_end, 2.0);
    c.cfl = 0.1;      /* dt = 0.1 dx / sqrt(2 g H) */
    c.mps.source = 1; /* mixed (Tanaka & Masunaga 2010) */
    c.mps.relax = 0.005;
    c.mps.corrected = 1;
    if (surface >= 0)
        c.mps.surface = surface;
    c.mps.stabilization = stab;
    if (type == SPH_KERNEL_SHEU_QUARTIC) /* Sheu et al.: re = 2h, h the spacing */
        c.mps.re = c.mps.re_grad = 2.0;
    sph_error err;
    sph_sim *s = sph_sim_create(&c, &err);
    if (!s) {
        fprintf(stderr, "create: %s: %s\n", err.path, err.message);
        return 1;
    }
    const double pH = c.rho0 * g * H, prow = c.rho0 * g * (H - 0.5 * dx), vref = sqrt(g * H);
    const int nq = (int)ceil(t_end / 0.5 - 1e-9);
    for (int q = 1; q <= nq; q++) { /* figures every 0.5 s and at the end */
        const double tq = q < nq ? 0.5 * q : t_end;
        while (sph_sim_time(s) < tq)
            if (sph_sim_advance(s, 1000, tq, &err)) {
                fprintf(stderr, "%s dx %g: %s\n", sph_kernel_type_name(type), dx, err.message);
                sph_sim_destroy(s);
                return 1;
            }
        if (q < nq) {
            const sph_diag *d = sph_sim_diag(s);
            printf("  %-12s dx %g t %.2f s: vmax %.3f%% of sqrt(gH), bottom row %+.2f%% of "
                   "rho0 g H\n",
                   sph_kernel_type_name(type), dx, d->t, 100 * d->vmax / vref,
                   100 * (bottom_pressure(s, dx) / pH - 1));
            fflush(stdout);
        }
    }
    const sph_diag *d = sph_sim_diag(s);
    long nrow = 0;
    const double pb = bottom_pressure_n(s, dx, &nrow);
    const int ok = d->vmax < 0.01 * vref && fabs(pb / pH - 1) < 0.05 && fabs(pb / prow - 1) < 0.05;
    printf("mps still water %-12s dx %g: t %.3f s, %ld steps, vmax %.3e m/s = %.2f%% of sqrt(gH) "
           "(limit 1%%); bottom row (%ld) mean p %.1f Pa: %+.2f%% of rho0 g H, %+.2f%% of "
           "rho0 g (H - dx/2) (limit 5%%); CG %ld iterations, free surface %ld: %s\n",
           sph_kernel_type_name(type), dx, d->t, d->step, d->vmax, 100 * d->vmax / vref, nrow, pb,
           100 * (pb / pH - 1), 100 * (pb / prow - 1), d->cg_iterations, d->free_surface,
           ok ? "ok" : "FAILED");
    sph_sim_destroy(s);
    return !ok;
}

int main(int argc, char **argv)
{
    const double dx = argc > 1 ? atof(argv[1]) : 0.005;
    const char *only = argc > 2 && strcmp(argv[2], "both") ? argv[2] : NULL; /* one kernel */
    const int surface = argc > 3 ? atoi(argv[3]) : -1;
    const double stab = argc > 4 ? atof(argv[4]) : 0.9;  /* mps.stabilization [dx] */
    const double t_end = argc > 5 ? atof(argv[5]) : 2.0; /* [s] */
    if (!(t_end > 0.0)) {
        fprintf(stderr, "usage: test_mps_still [DX [KERNEL [SURFACE [STAB [END]]]]]\n");
        return 2;
    }
    int rc = 0;
    if (!only || strcmp(only, "koshizuka") == 0)
        rc |= run(SPH_KERNEL_KOSHIZUKA, dx, surface, stab, t_end);
    if (!only || strcmp(only, "sheu_quartic") == 0)
        rc |= run(SPH_KERNEL_SHEU_QUARTIC, dx, surface, stab, t_end);
    return rc;
}
