"""Dam break (Yang, Peng & Liu 2014, section 4.1; cases/dambreak.json, the main job's physics)
against Martin & Moyce (1952): the surge front Z = x/D over T = t sqrt(2g/D) (their Table 2) and
the residual height of the column at the left wall H = h/(2D) over tau = t sqrt(g/D) (their
Table 6), for the column of width D = 0.1 m and height 2D; with dynamic boundary particles
(cases/dambreak.json) and with free-slip ghost walls (cases/dambreak_ghost.json), each at the
case's dx = 2 mm and at dx/2 (full level; dynamic walls at dx = 5 mm at the ci level).
"""
import math

import numpy as np

TITLE = "dam break: surge front and residual height against Martin & Moyce (1952)"
D, G = 0.1, 9.81
WALLS = {"dynamic": "cases/dambreak.json", "ghost": "cases/dambreak_ghost.json"}
RUNS = {"full": [("dynamic", 0.002), ("dynamic", 0.001), ("ghost", 0.002), ("ghost", 0.001)],
        "ci": [("dynamic", 0.005)]}
RESOLUTION = {"full": "dx = 2 mm (5,000 fluid particles) and 1 mm (20,000), dynamic and ghost walls",
              "ci": "dx = 5 mm (800 fluid particles), dynamic walls"}
FRONT_T = (0.4, 3.3)       # T range compared (the table's, less its first instants)
FRONT_BOUND = 0.10         # RMS of (X - Z)/Z
HEIGHT_BOUND = 0.10        # RMS of (H_sph - H_M&M), in units of the initial height


def run(ctx):
    ref = ctx.reference_table("dambreak_front_MartinMoyce1952_table2_n2eq2.csv")
    ref6 = ctx.reference_table("dambreak_height_MartinMoyce1952_table6_n2eq2.csv")
    scale, tau_scale = math.sqrt(2 * G / D), math.sqrt(G / D)
    figf = ctx.figure("front", figsize=(6.5, 4.2))
    axf = figf.add_subplot(111)
    figh = ctx.figure("height", figsize=(6.5, 4.2))
    axh = figh.add_subplot(111)
    summary = []
    for walls, dx in RUNS[ctx.level]:
        events, _ = ctx.sphd_run(WALLS[walls], ["dx=%g" % dx], job="dambreak_%s" % walls)
        assert events[-1].get("state") == "done", events[-1]
        diag = [e for e in events if e["type"] == "diag"]
        t = np.array([e["t"] for e in diag])
        x = np.array([np.nan if e.get("front_x") is None else e["front_x"] for e in diag])
        h = np.array([np.nan if e.get("height_left") is None else e["height_left"]
                      for e in diag])
        label = "%s walls, dx = %g mm" % (walls, 1000 * dx)

        # the front, Table 2
        sel = ref[(ref[:, 0] >= FRONT_T[0]) & (ref[:, 0] <= FRONT_T[1])]
        X = np.interp(sel[:, 0] / scale, t, x) / D
        rel = (X - sel[:, 1]) / sel[:, 1]
        rms = float(np.sqrt(np.mean(rel ** 2)))
        ctx.check("%s: front, RMS of (X - Z)/Z over T in [%g, %g] (%d points)" %
                  (label, *FRONT_T, len(sel)), rms, FRONT_BOUND, rms < FRONT_BOUND,
                  "front_x interpolated at the table's times; largest %+.3f at T = %.2f" %
                  (rel[np.argmax(np.abs(rel))], sel[np.argmax(np.abs(rel)), 0]))
        axf.plot(t * scale, x / D, "-", lw=0.9, label="sphd, " + label)

        # the residual height at the wall, Table 6
        sel6 = ref6[ref6[:, 0] / tau_scale <= t[-1]]
        H = np.interp(sel6[:, 0] / tau_scale, t, h) / (2 * D)
        dH = H - sel6[:, 1]
        rms6 = float(np.sqrt(np.mean(dH ** 2)))
        ctx.check("%s: height at the wall, RMS of H - H_M&M over tau <= %.2f (%d points)"
                  % (label, t[-1] * tau_scale, len(sel6)), rms6, HEIGHT_BOUND,
                  rms6 < HEIGHT_BOUND, "height_left / 2D interpolated at the table's times; "
                  "H in units of the initial height")
        ctx.check("%s: height at the wall, largest |H - H_M&M|" % label,
                  float(np.max(np.abs(dH))), 1.5 * HEIGHT_BOUND,
                  np.max(np.abs(dH)) < 1.5 * HEIGHT_BOUND)
        axh.plot(t * tau_scale, h / (2 * D), "-", lw=0.9, label="sphd, " + label)
        summary.append("%s: front %.1f%%, height %.1f%%" % (label, 100 * rms, 100 * rms6))

    axf.plot(ref[:, 0], ref[:, 1], "o", mfc="none", color="k",
             label="Martin & Moyce (1952), Table 2")
    axf.axvspan(*FRONT_T, color="0.93", zorder=0, label="compared")
    axf.set_xlim(0, 3.6)
    axf.set_ylim(1, 4.5)
    axf.set_xlabel("T = t sqrt(2g/D)")
    axf.set_ylabel("Z = x_front / D")
    axf.set_title("dam break: surge front (tolerance: RMS rel. diff. %.2f)" % FRONT_BOUND)
    axf.legend(loc="upper left", fontsize=7)
    axh.plot(ref6[:, 0], ref6[:, 1], "s", mfc="none", color="k",
             label="Martin & Moyce (1952), Table 6")
    axh.set_xlim(0, 7.6)
    axh.set_ylim(0, 1.1)
    axh.set_xlabel("tau = t sqrt(g/D)")
    axh.set_ylabel("H = h_wall / 2D")
    axh.set_title("dam break: residual height at the wall (tolerance: RMS %.2f)" % HEIGHT_BOUND)
    axh.legend(loc="upper right", fontsize=7)
    ctx.note("RMS against Martin & Moyce: " + "; ".join(summary) + ".")
    ctx.note("Reference data: tests/validation/reference/ (provenance in each file's header; "
             "public transcriptions of the tables, not checked against the paper). The "
             "experiment's time origin is uncertain (the release of the column). The simulation "
             "ends at t = %.2f s (T = %.2f, tau = %.2f)." % (t[-1], t[-1] * scale,
                                                             t[-1] * tau_scale))
