"""Water entry of a horizontal circular cylinder (Yang, Peng & Liu 2014, section 4.2;
cases/water_entry.json) against Greenhow & Lin (1983): a cylinder of D = 0.11 m touching still
water at 2.955 m/s. The penetration (the depth of its lowest point below the still-water level)
of the half-buoyant cylinder (density 500) over tau = t sqrt(g/D), compared with the measured
points over tau in [0.1, 1.1] (issue 11's window): Wendland C2 at the case's dx = 5 mm (D/dx = 22)
and at dx/2 (44), the cubic spline and the double cosine at dx = 5 mm; the neutrally buoyant
cylinder (density 1000) is drawn beside it (no measurement of it in tests/validation/reference/),
and Wendland with the body's pressure by continuity (`bodies.0.pressure=continuity`, as dynamic
walls) instead of from the fluid. At the ci level, Wendland at D/dx = 22 only.

Issue 22, section 3: the first measured point (tau = 0.1) is uncertain: it disagrees with the next
one (the measured slopes are not monotonic there) and lies below both published solutions in the
same figure of Sun et al. 2018 (BEM 0.180 D, delta-plus SPH 0.207 D against 0.168 D). So for
Wendland at D/dx = 22 and 44: the RMS of the relative difference over the points with tau >= 0.2
within 8%, and smaller at 44 than at 22 (full level); the RMS over all the points within 12%; the
tau = 0.1 point's error reported with that reason.
"""
import math

import numpy as np

TITLE = "water entry of a cylinder: penetration against Greenhow & Lin (1983)"
D, G = 0.11, 9.81
TAU = (0.1, 1.1)           # the compared range of tau = t sqrt(g/D) (issue 11)
TAU_CERTAIN = 0.2          # the points from here on (issue 22: the first one is uncertain)
BOUND_CERTAIN = 0.08       # RMS of the relative difference over the points with tau >= 0.2
BOUND_ALL = 0.12           # RMS over all the points in TAU
# (kernel, dx, density, checked, the body's pressure)
RUNS = {"full": [("wendland_c2", 0.005, 500, True, "fluid"),
                 ("wendland_c2", 0.0025, 500, True, "fluid"),
                 ("cubic_spline", 0.005, 500, False, "fluid"),
                 ("double_cosine", 0.005, 500, False, "fluid"),
                 ("wendland_c2", 0.005, 500, False, "continuity"),
                 ("wendland_c2", 0.005, 1000, False, "fluid")],
        "ci": [("wendland_c2", 0.005, 500, True, "fluid")]}
RESOLUTION = {"full": "D/dx = 22 (dx = 5 mm, 20,000 fluid particles) and 44 (dx = 2.5 mm)",
              "ci": "D/dx = 22 (dx = 5 mm, 20,000 fluid particles)"}


def rms(r):
    return float(np.sqrt(np.mean(r ** 2)))


def run(ctx):
    ref = ctx.reference_table("water_entry_GreenhowLin1983_rho500.csv")
    sel = ref[(ref[:, 0] >= TAU[0]) & (ref[:, 0] <= TAU[1])]
    scale = math.sqrt(G / D)
    fig = ctx.figure("penetration", figsize=(6.5, 4.2))
    ax = fig.add_subplot(111)
    summary, certain_rms = [], []
    for kernel, dx, density, checked, pressure in RUNS[ctx.level]:
        sets = ["dx=%g" % dx, "kernel.type=" + kernel, "bodies.0.density=%g" % density,
                "bodies.0.pressure=" + pressure]
        events, _ = ctx.sphd_run("cases/water_entry.json", sets, job="water_entry")
        assert events[-1].get("state") == "done", events[-1]
        diag = [e for e in events if e["type"] == "diag"]
        t = np.array([e["t"] for e in diag])
        pen = np.array([e["bodies"]["cylinder"]["penetration"] for e in diag])
        label = "%s, D/dx = %d, density %g%s" % (kernel, round(D / dx), density,
                                                 ", pressure by continuity"
                                                 if pressure == "continuity" else "")
        ax.plot(t * scale, pen / D, "-", lw=0.9, label="sphd, " + label)
        if density != 500:
            continue
        p = np.interp(sel[:, 0] / scale, t, pen) / D
        rel = (p - sel[:, 1]) / sel[:, 1]
        certain = sel[:, 0] >= TAU_CERTAIN
        r_all, r_certain = rms(rel), rms(rel[certain])
        how = "at tau = " + ", ".join("%.2f: %+.1f%%" % (a, 100 * r)
                                      for a, r in zip(sel[:, 0], rel))
        first = "tau = %.2f point (uncertain): %+.1f%%" % (sel[0, 0], 100 * rel[0])
        what = "%s: penetration, RMS of the relative difference over the %d points with tau in " \
            "[%g, %g]" % (label, certain.sum(), TAU_CERTAIN, TAU[1])
        what_all = "%s: penetration, RMS of the relative difference over all %d points with " \
            "tau in [%g, %g]" % (label, len(sel), *TAU)
        if checked:
            ctx.check(what, round(r_certain, 4), BOUND_CERTAIN, r_certain <= BOUND_CERTAIN, how)
            ctx.check(what_all, round(r_all, 4), BOUND_ALL, r_all <= BOUND_ALL, first)
            if kernel == "wendland_c2":
                certain_rms.append((round(D / dx), r_certain))
        else:
            ctx.note("%s: %.3f; over all the points %.3f; %s (%s)" % (what, r_certain, r_all,
                                                                     first, how))
        summary.append("%s: %.3f with tau >= %g, %.3f over all, %s" % (
            label, r_certain, TAU_CERTAIN, r_all, first))
        beyond = ref[ref[:, 0] > TAU[1]]
        if len(beyond) and t[-1] * scale >= beyond[-1, 0]:
            pb = np.interp(beyond[:, 0] / scale, t, pen) / D
            summary[-1] += " (beyond the window: " + ", ".join(
                "tau = %.2f: %+.1f%%" % (a, 100 * (b - c) / c)
                for a, b, c in zip(beyond[:, 0], pb, beyond[:, 1])) + ")"
    for (na, a), (nb, b) in zip(certain_rms, certain_rms[1:]):
        ctx.check("wendland_c2: RMS over tau >= %g smaller at D/dx = %d than at %d"
                  % (TAU_CERTAIN, nb, na), round(b - a, 4), 0.0, b < a,
                  "RMS %.4f at %d, %.4f at %d (the difference; negative: it shrinks)"
                  % (a, na, b, nb))
    unc = ref[(ref[:, 0] >= TAU[0]) & (ref[:, 0] < TAU_CERTAIN)]
    ax.plot(unc[:, 0], unc[:, 1], "x", color="C3", ms=9,
            label="tau = %.2f: uncertain (BEM 0.180 D, SPH 0.207 D)" % unc[0, 0])
    ax.plot(ref[:, 0], ref[:, 1], "ko", mfc="none", label="Greenhow & Lin (1983), density 500")
    ax.axvspan(*TAU, color="0.93", zorder=0, label="compared")
    ax.set_xlabel("tau = t sqrt(g/D)")
    ax.set_ylabel("penetration / D")
    ax.set_title("water entry of a cylinder, D = 0.11 m, V0 = 2.955 m/s")
    ax.legend(fontsize=7, loc="lower right")
    ctx.note("RMS against Greenhow & Lin: " + "; ".join(summary) + ". The reference is digitised "
             "from a figure (a few percent of scatter; tests/validation/reference/); its time "
             "origin is the first contact.")
    ctx.note("The first measured point (tau = 0.1) is uncertain (issue 22): it disagrees with "
             "the next measured point (the measured slopes are not monotonic there) and lies "
             "below both published solutions drawn in the same figure of Sun et al. (2018): "
             "their BEM gives 0.180 D and their delta-plus SPH 0.207 D against the measured "
             "0.168 D. So the bounds are %.0f%% RMS over the points with tau >= %g, smaller at "
             "D/dx = 44 than at 22, and %.0f%% over all the points; the first point's error is "
             "reported." % (100 * BOUND_CERTAIN, TAU_CERTAIN, 100 * BOUND_ALL))
