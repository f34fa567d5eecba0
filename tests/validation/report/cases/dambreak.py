"""Dam break (Yang, Peng & Liu 2014, section 4.1; cases/dambreak.json, the main job's physics)
against Martin & Moyce (1952): the surge front Z = x/D over T = t sqrt(2g/D) (their Table 2) and
the residual height of the column at the left wall H = h/(2D) over tau = t sqrt(g/D) (their
Table 6), for the column of width D = 0.1 m and height 2D; with dynamic boundary particles
(cases/dambreak.json) and with free-slip ghost walls (cases/dambreak_ghost.json), each at the
case's dx = 2 mm and at dx/2 (full level; dynamic walls at the case's dx = 2 mm at the ci level).

The yardsticks of issue 22, section 1. The experiment's clock has no stated origin relative to the
release, so the front is compared raw and with one fitted time shift delta >= 0 (front.py): the
shifted RMS of (X - Z)/Z over T in [0.4, 3.0] within 5%, delta below 0.3 in T, delta at dx and
dx/2 within 0.05 of each other (full level), the raw RMS within 15%; the height at the wall,
unshifted, within 5% RMS (in units of the initial height).
"""
import math

import numpy as np

import front

TITLE = "dam break: surge front and residual height against Martin & Moyce (1952)"
D, G = 0.1, 9.81
WALLS = {"dynamic": "cases/dambreak.json", "ghost": "cases/dambreak_ghost.json"}
RUNS = {"full": [("dynamic", 0.002), ("dynamic", 0.001), ("ghost", 0.002), ("ghost", 0.001)],
        "ci": [("dynamic", 0.002)]}
RESOLUTION = {"full": "dx = 2 mm (5,000 fluid particles) and 1 mm (20,000), dynamic and ghost walls",
              "ci": "dx = 2 mm (the case's, 5,000 fluid particles), dynamic walls"}
FRONT_T = front.WINDOW     # T range compared and fitted (issue 22)
HEIGHT_BOUND = 0.05        # RMS of (H_sph - H_M&M), in units of the initial height, unshifted


def run(ctx):
    ref = ctx.reference_table("dambreak_front_MartinMoyce1952_table2_n2eq2.csv")
    ref6 = ctx.reference_table("dambreak_height_MartinMoyce1952_table6_n2eq2.csv")
    scale, tau_scale = math.sqrt(2 * G / D), math.sqrt(G / D)
    figf = ctx.figure("front", figsize=(7, 4.6))
    axf = figf.add_subplot(111)
    figh = ctx.figure("height", figsize=(6.5, 4.2))
    axh = figh.add_subplot(111)
    summary, shifts = [], {}
    for k, (walls, dx) in enumerate(RUNS[ctx.level]):
        events, _ = ctx.sphd_run(WALLS[walls], ["dx=%g" % dx], job="dambreak_%s" % walls)
        assert events[-1].get("state") == "done", events[-1]
        diag = [e for e in events if e["type"] == "diag"]
        t = np.array([e["t"] for e in diag])
        x = np.array([np.nan if e.get("front_x") is None else e["front_x"] for e in diag])
        h = np.array([np.nan if e.get("height_left") is None else e["height_left"]
                      for e in diag])
        label = "%s walls, dx = %g mm" % (walls, 1000 * dx)

        # the front, Table 2: raw and with the fitted time origin
        c = front.compare(t * scale, x / D, ref, FRONT_T)
        ms = front.checks(ctx, label, c, scale, "Martin & Moyce")
        shifts.setdefault(walls, []).append(("%g mm" % (1000 * dx), c["shift"]))
        color = "C%d" % k
        axf.plot(t * scale, x / D, "-", lw=0.9, color=color, label="sphd, " + label + ", raw")
        axf.plot(t * scale + c["shift"], x / D, "--", lw=0.9, color=color,
                 label="  shifted by delta = %.3f (%.1f ms)" % (c["shift"], ms))

        # the residual height at the wall, Table 6, unshifted
        sel6 = ref6[ref6[:, 0] / tau_scale <= t[-1]]
        H = np.interp(sel6[:, 0] / tau_scale, t, h) / (2 * D)
        dH = H - sel6[:, 1]
        rms6 = float(np.sqrt(np.mean(dH ** 2)))
        k6 = int(np.argmax(np.abs(dH)))
        ctx.check("%s: height at the wall, RMS of H - H_M&M over tau <= %.2f (%d points)"
                  % (label, t[-1] * tau_scale, len(sel6)), round(rms6, 4), HEIGHT_BOUND,
                  rms6 <= HEIGHT_BOUND, "height_left / 2D interpolated at the table's times, "
                  "unshifted; H in units of the initial height; largest %+.3f at tau = %.2f"
                  % (dH[k6], sel6[k6, 0]))
        axh.plot(t * tau_scale, h / (2 * D), "-", lw=0.9, label="sphd, " + label)
        summary.append("%s: front raw %.1f%%, delta = %.3f in T (%.1f ms), shifted %.1f%%; "
                       "height %.1f%%" % (label, 100 * c["raw_rms"], c["shift"], ms,
                                         100 * c["shifted_rms"], 100 * rms6))
    for walls, s in shifts.items():
        front.shift_convergence(ctx, "%s walls" % walls, s)

    axf.plot(ref[:, 0], ref[:, 1], "o", mfc="none", color="k",
             label="Martin & Moyce (1952), Table 2")
    axf.axvspan(*FRONT_T, color="0.93", zorder=0, label="compared and fitted")
    axf.set_xlim(0, 3.6)
    axf.set_ylim(1, 4.5)
    axf.set_xlabel("T = t sqrt(2g/D)")
    axf.set_ylabel("Z = x_front / D")
    axf.set_title("dam break: surge front (RMS rel. diff.: raw %.2f, shifted %.2f)"
                  % (front.RAW_BOUND, front.SHIFTED_BOUND))
    axf.legend(loc="upper left", fontsize=6)
    axh.plot(ref6[:, 0], ref6[:, 1], "s", mfc="none", color="k",
             label="Martin & Moyce (1952), Table 6")
    axh.set_xlim(0, 7.6)
    axh.set_ylim(0, 1.1)
    axh.set_xlabel("tau = t sqrt(g/D)")
    axh.set_ylabel("H = h_wall / 2D")
    axh.set_title("dam break: residual height at the wall (tolerance: RMS %.2f)" % HEIGHT_BOUND)
    axh.legend(loc="upper right", fontsize=7)
    ctx.note("Against Martin & Moyce: " + "; ".join(summary) + ".")
    ctx.note("The time origin: Martin & Moyce do not state when their clock started relative to "
             "the release of the column; gate-timed experiments (Lobovsky et al. 2014) lead them "
             "by about 0.1-0.2 in T, and the simulated front leads them by a constant delay, not "
             "a different speed. So the simulated front is also compared shifted later by one "
             "delta >= 0 for all points, fitted by least squares of (X - Z)/Z over T in [%g, %g] "
             "(issue 22): the bounds are %.0f%% RMS shifted, %.0f%% raw, delta < %g in T and "
             "within %g between dx and dx/2. The height at the wall is compared unshifted."
             % (*FRONT_T, 100 * front.SHIFTED_BOUND, 100 * front.RAW_BOUND, front.SHIFT_MAX,
                front.SHIFT_CONVERGED))
    ctx.note("Reference data: tests/validation/reference/ (provenance in each file's header; "
             "public transcriptions of the tables, not checked against the paper). The "
             "simulation ends at t = %.2f s (T = %.2f, tau = %.2f)." % (t[-1], t[-1] * scale,
                                                                      t[-1] * tau_scale))
