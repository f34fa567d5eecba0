"""MPS dam break (Koshizuka & Oka 1996; cases/mps_dambreak.json; issues 12 and 22): a column
L = 0.146 m wide and 2L high in a tank 4L long, run with the MPS method and both weights (the
case's sheu_quartic with Sheu et al.'s re = 2 dx, koshizuka with re = 2.1 dx), at the case's
dx = L/20 and at L/40 (full level; L/20 at the ci level), with the case's settings (the mixed
source, the corrected gradient, the dynamic stabilization: those under which still water stays at
rest). The surge front Z = x/L over T = t sqrt(2g/L) in [0.4, 3] is compared with
tests/validation/reference/dambreak_front_KoshizukaOka1996.csv:

- `ko_exp`: their experiment. Issue 22's yardsticks for the case's weight (front.py, the same as
  the WCSPH dam break's against Martin & Moyce): the raw RMS of (X - Z)/Z within 15%, one fitted
  time shift delta >= 0 below 0.3 in T, the shifted RMS within 5%, and (full level) delta at L/20
  and L/40 within 0.05 of each other. Koshizuka's weight: noted.
- `ko_mps_SIMULATION`: Koshizuka & Oka's own MPS result for this set-up: the same method (with
  their settings: the number-density source, the minimum-pressure gradient, the collision model),
  within 10% RMS for both weights at every level.
- `dualsphysics` (Martin & Moyce's points as re-plotted by Koshizuka & Oka): noted.
"""
import math

import numpy as np

import front

TITLE = "MPS dam break: surge front against Koshizuka & Oka (1996)"
L, G = 0.146, 9.81
CASE_WEIGHT = "sheu_quartic"
KERNELS = {"sheu_quartic": [], "koshizuka": ["kernel.type=koshizuka", "mps.re=2.1",
                                             "mps.re_grad=2.1"]}
RUNS = {"full": [(k, n) for k in KERNELS for n in (20, 40)],
        "ci": [(k, 20) for k in KERNELS]}
RESOLUTION = {"full": "dx = L/20 (800 fluid particles) and L/40 (3,200), both MPS weights",
              "ci": "dx = L/20 (800 fluid particles), both MPS weights"}
FRONT_T = front.WINDOW     # T range compared (issues 12 and 22)
MPS_BOUND = 0.10           # RMS of (X - Z)/Z against Koshizuka & Oka's MPS front
SETS = {"ko_mps_SIMULATION": "Koshizuka & Oka's MPS result",
        "ko_exp": "Koshizuka & Oka's experiment",
        "dualsphysics": "Martin & Moyce via Koshizuka & Oka"}


def run(ctx):
    ref = ctx.reference_sets("dambreak_front_KoshizukaOka1996.csv")
    scale = math.sqrt(2 * G / L)
    fig = ctx.figure("front", figsize=(7, 4.6))
    ax = fig.add_subplot(111)
    summary, shifts = [], []
    for k, (kernel, n) in enumerate(RUNS[ctx.level]):
        dx = L / n
        events, _ = ctx.sphd_run("cases/mps_dambreak.json", ["dx=%.6g" % dx] + KERNELS[kernel],
                                 job="mps_dambreak_%s_%d" % (kernel, n))
        assert events[-1].get("state") == "done", events[-1]
        diag = [e for e in events if e["type"] == "diag"]
        t = np.array([e["t"] for e in diag])
        x = np.array([np.nan if e.get("front_x") is None else e["front_x"] for e in diag])
        label = "%s, dx = L/%d" % (kernel, n)
        figures = []
        for name, what in SETS.items():
            c = front.compare(t * scale, x / L, ref[name], FRONT_T)
            if name == "ko_exp" and kernel == CASE_WEIGHT:
                ms = front.checks(ctx, label, c, scale, what)
                shifts.append(("L/%d" % n, c["shift"]))
                figures.append("%s raw %.1f%%, delta = %.3f in T (%.1f ms), shifted %.1f%%" % (
                    name, 100 * c["raw_rms"], c["shift"], ms, 100 * c["shifted_rms"]))
                continue
            if name == "ko_mps_SIMULATION":
                ctx.check("%s: front against %s, RMS of (X - Z)/Z over T in [%g, %g] (%d "
                          "points)" % (label, what, *FRONT_T, c["n"]), round(c["raw_rms"], 4),
                          MPS_BOUND, c["raw_rms"] <= MPS_BOUND,
                          "front_x interpolated at the set's times; " + front.worst(c, "raw"))
            else:
                print("  note %s: front against %s: raw RMS %.3f, delta %.3f, shifted %.3f"
                      % (label, what, c["raw_rms"], c["shift"], c["shifted_rms"]))
            figures.append("%s raw %.1f%% (delta %.3f: %.1f%%)" % (
                name, 100 * c["raw_rms"], c["shift"], 100 * c["shifted_rms"]))
        ax.plot(t * scale, x / L, "-", lw=0.9, color="C%d" % k, label="sphd, " + label)
        if kernel == CASE_WEIGHT:
            c = front.compare(t * scale, x / L, ref["ko_exp"], FRONT_T)
            ax.plot(t * scale + c["shift"], x / L, "--", lw=0.9, color="C%d" % k,
                    label="  shifted by delta = %.3f (%.1f ms; fitted to ko_exp)"
                    % (c["shift"], 1000 * c["shift"] / scale))
        summary.append("%s: %s" % (label, ", ".join(figures)))
    front.shift_convergence(ctx, CASE_WEIGHT, shifts)
    marks = {"ko_exp": "o", "ko_mps_SIMULATION": "s", "dualsphysics": "^"}
    for name, what in SETS.items():
        ax.plot(ref[name][:, 0], ref[name][:, 1], marks[name], mfc="none", color="k", ms=4,
                label=what)
    ax.axvspan(*FRONT_T, color="0.93", zorder=0, label="compared")
    ax.set_xlim(0, 3.6)
    ax.set_ylim(1, 4.3)
    ax.set_xlabel("T = t sqrt(2g/L)")
    ax.set_ylabel("Z = x_front / L")
    ax.set_title("MPS dam break: surge front (experiment: RMS raw %.2f, shifted %.2f)"
                 % (front.RAW_BOUND, front.SHIFTED_BOUND))
    ax.legend(loc="upper left", fontsize=6)
    ctx.note("RMS of the front's relative difference over T in [%g, %g], per reference set "
             "(raw, and with the time shift fitted to that set): " % FRONT_T + "; ".join(summary)
             + ".")
    ctx.note("Like Martin & Moyce's, Koshizuka & Oka's experimental clock has no stated origin "
             "relative to the release, and both MPS results (theirs and sphd's) lead it by a "
             "delay from T = 0.8 on: issue 22 bounds the case's weight against it raw (%.0f%%) "
             "and with one fitted time shift (%.0f%%, delta < %g in T, converged within %g "
             "between L/20 and L/40). Koshizuka's weight is noted. The tank's walls reach Z = 4, "
             "so the front stops there." % (100 * front.RAW_BOUND, 100 * front.SHIFTED_BOUND,
                                            front.SHIFT_MAX, front.SHIFT_CONVERGED))
