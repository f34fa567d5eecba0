"""MPS dam break (Koshizuka & Oka 1996; cases/mps_dambreak.json; issue 12): a column L = 0.146 m
wide and 2L high in a tank 4L long, run with the MPS method and both weights (the case's
sheu_quartic with Sheu et al.'s re = 2 dx, koshizuka with re = 2.1 dx), at the case's dx = L/20 and
at L/40 (full level; L/20 at the ci level), with the case's settings (the mixed source, the
corrected gradient, the dynamic stabilization: those under which still water stays at rest). The surge front Z = x/L over T = t sqrt(2g/L) in [0.4, 3] is compared
with tests/validation/reference/dambreak_front_KoshizukaOka1996.csv:

- `ko_mps_SIMULATION`: Koshizuka & Oka's own MPS result for this set-up: the same method (with
  their settings: the number-density source, the minimum-pressure gradient, the collision model),
  checked at every level.
- `ko_exp`: their experiment, issue 12's reference (the front within 10% RMS at L/20 and L/40):
  checked at the full level; at the ci level its RMS is only noted.
- `dualsphysics` (Martin & Moyce's points as re-plotted by Koshizuka & Oka): noted.
"""
import math

import numpy as np

TITLE = "MPS dam break: surge front against Koshizuka & Oka (1996)"
L, G = 0.146, 9.81
KERNELS = {"sheu_quartic": [], "koshizuka": ["kernel.type=koshizuka", "mps.re=2.1",
                                             "mps.re_grad=2.1"]}
RUNS = {"full": [(k, n) for k in KERNELS for n in (20, 40)],
        "ci": [(k, 20) for k in KERNELS]}
RESOLUTION = {"full": "dx = L/20 (800 fluid particles) and L/40 (3,200), both MPS weights",
              "ci": "dx = L/20 (800 fluid particles), both MPS weights"}
FRONT_T = (0.4, 3.0)   # T range compared (issue 12)
BOUND = 0.10           # RMS of (X - Z)/Z
SETS = {"ko_mps_SIMULATION": "Koshizuka & Oka's MPS result", "ko_exp": "Koshizuka & Oka's experiment",
        "dualsphysics": "Martin & Moyce via Koshizuka & Oka"}


def run(ctx):
    ref = ctx.reference_sets("dambreak_front_KoshizukaOka1996.csv")
    scale = math.sqrt(2 * G / L)
    fig = ctx.figure("front", figsize=(6.5, 4.2))
    ax = fig.add_subplot(111)
    summary = []
    for kernel, n in RUNS[ctx.level]:
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
            r = ref[name]
            sel = r[(r[:, 0] >= FRONT_T[0]) & (r[:, 0] <= FRONT_T[1])]
            X = np.interp(sel[:, 0] / scale, t, x) / L
            rel = (X - sel[:, 1]) / sel[:, 1]
            rms = float(np.sqrt(np.mean(rel ** 2)))
            k = int(np.argmax(np.abs(rel)))
            how = ("front_x interpolated at the set's times; largest %+.3f at T = %.2f"
                   % (rel[k], sel[k, 0]))
            checked = name == "ko_mps_SIMULATION" or (name == "ko_exp" and ctx.level == "full")
            if checked:
                ctx.check("%s: front against %s, RMS of (X - Z)/Z over T in [%g, %g] (%d points)"
                          % (label, what, *FRONT_T, len(sel)), rms, BOUND, rms < BOUND, how)
            else:
                print("  note %s: front against %s: RMS %.3f (%s)" % (label, what, rms, how))
            figures.append("%s %.1f%%" % (name, 100 * rms))
        ax.plot(t * scale, x / L, "-", lw=0.9, label="sphd, " + label)
        summary.append("%s: %s" % (label, ", ".join(figures)))
    marks = {"ko_exp": "o", "ko_mps_SIMULATION": "s", "dualsphysics": "^"}
    for name, what in SETS.items():
        ax.plot(ref[name][:, 0], ref[name][:, 1], marks[name], mfc="none", color="k", ms=4,
                label=what)
    ax.axvspan(*FRONT_T, color="0.93", zorder=0, label="compared")
    ax.set_xlim(0, 3.6)
    ax.set_ylim(1, 4.3)
    ax.set_xlabel("T = t sqrt(2g/L)")
    ax.set_ylabel("Z = x_front / L")
    ax.set_title("MPS dam break: surge front (tolerance: RMS rel. diff. %.2f)" % BOUND)
    ax.legend(loc="upper left", fontsize=7)
    ctx.note("RMS of the front's relative difference over T in [%g, %g], per reference set: "
             % FRONT_T + "; ".join(summary) + ".")
    ctx.note("The experiment's front is slower than both MPS results (Koshizuka & Oka's and "
             "sphd's) from T = 0.8 on; issue 12's 10% against it is checked at the full level "
             "only. The tank's walls reach Z = 4, so the front stops there.")
