"""MPS dam break at Re = 500 and 1000 (Sheu, Chiao & Huang 2011, paper 004, section 5.2 and
Figs. 6-7; cases/mps_dambreak_re500.json; issue 12): a square column of side L = 1 m at the left
wall of a tank 4L long (the paper gives no tank length), Re = L sqrt(gL) / nu, run to
T = t sqrt(g/L) = 2.5 with snapshots at the paper's T = 0, 0.5, ..., 2.5. For each Re a figure
draws the fluid particles and the free surface (the highest fluid particle per column of width
dx) at the six times, as the paper's figures do.

The paper's text gives no number to compare with (its figures compare its MPS free surfaces with
the level-set ones of its reference [16] by eye), so the checks are:
- every run finishes (state done) at T >= 2.5, and each of the six snapshots holds every fluid
  particle (the same ids, none lost);
- the less viscous surge is the faster one: the Re = 1000 front leads the Re = 500 front at
  T = 1, 1.5 and 2 (per weight and resolution);
Noted, not checked: the surge front against Martin & Moyce's (1952) Table 2, the nearest
measurement in tests/validation/reference/, for a column twice as high as wide (n^2 = 2), not a
square one: at the same t sqrt(g/a) (their T / sqrt 2), where the front is carried by the lower
part of the column, the RMS over their points with t sqrt(g/a) <= 2.35 (the full level measures
the lead of sphd's own n^2 = 2 column there); and in their own scaling, T = n t sqrt(g/a).

The ci level runs the case as it is (the paper's quartic weight sheu_quartic, re = 2 dx, dx = L/40)
at both Re; the full level adds Koshizuka's weight (re = 2.1 dx) and dx = L/80, and sphd's n^2 = 2
column.
"""
import glob
import math
import os

import h5py
import numpy as np

TITLE = "MPS dam break at Re = 500 and 1000: free surfaces at paper 004's times (Figs. 6-7)"
CASE = "cases/mps_dambreak_re500.json"
L, G, TANK = 1.0, 9.81, 4.0
NU = {500: 0.0062642, 1000: 0.0031321}    # nu = L sqrt(gL) / Re
TIMES = (0.0, 0.5, 1.0, 1.5, 2.0, 2.5)    # T = t sqrt(g/L) of the paper's panels (a)-(f)
KERNELS = {"sheu_quartic": [], "koshizuka": ["kernel.type=koshizuka", "mps.re=2.1",
                                             "mps.re_grad=2.1"]}
CASE_RUN = ("sheu_quartic", 40)   # the case as it is
RUNS = {"full": [(k, n) for k in KERNELS for n in (40, 80)], "ci": [CASE_RUN]}
RESOLUTION = {"full": "dx = L/40 (1,600 fluid particles) and L/80 (6,400), both MPS weights, "
                      "Re = 500 and 1000",
              "ci": "dx = L/40 (1,600 fluid particles), sheu_quartic, Re = 500 and 1000"}
ORDER_T = (1.0, 1.5, 2.0)   # where the Re = 1000 front must lead the Re = 500 one
MM_RAW_MAX = 2.35           # t sqrt(g/a) compared: Martin & Moyce's points up to Z = 3.89 (their
                            # last, Z = 4.11, lies beyond this tank's right wall)
MM_N = math.sqrt(2.0)       # Martin & Moyce's column: height n^2 a, n^2 = 2


def series(events, probe="front_x"):
    """(T, probe / L) of a run's diag events."""
    d = [e for e in events if e["type"] == "diag" and e.get(probe) is not None]
    return np.array([(e["t"] * math.sqrt(G / L), e[probe] / L) for e in d])


def snapshots(d):
    """The run's snapshots at the paper's times: [(T, pos of the fluid, ids of the fluid)]."""
    out = []
    files = sorted(glob.glob(os.path.join(d, "snap_*.h5")))
    for T in TIMES:
        for f in files:
            with h5py.File(f, "r") as h:
                t = float(h.attrs["time"]) * math.sqrt(G / L)
                if abs(t - T) < 1e-6:
                    fluid = h["type"][:] == 0
                    out.append((t, h["pos"][:][fluid], h["id"][:][fluid]))
                    break
        else:
            raise RuntimeError("no snapshot at T = %g in %s" % (T, d))
    return out


def surface(pos, dx):
    """The free surface as a line: the highest fluid particle in each column of width dx."""
    cols = np.floor(pos[:, 0] / dx).astype(int)
    xs, ys = [], []
    for c in np.unique(cols):
        xs.append((c + 0.5) * dx)
        ys.append(pos[cols == c, 1].max() + 0.5 * dx)
    return np.array(xs), np.array(ys)


def run(ctx):
    mm = ctx.reference_table("dambreak_front_MartinMoyce1952_table2_n2eq2.csv")
    fronts, snaps = {}, {}
    for kernel, n in RUNS[ctx.level]:
        dx = L / n
        for re in NU:
            events, d = ctx.sphd_run(CASE, ["dx=%.6g" % dx, "physics.viscosity.nu=%g" % NU[re]]
                                     + KERNELS[kernel], job="re%d_%s_%d" % (re, kernel, n))
            label = "Re = %d, %s, dx = L/%d" % (re, kernel, n)
            last = events[-1]
            res = [e for e in events if e["type"] == "result"]
            T_end = res[-1]["t"] * math.sqrt(G / L) if res else float("nan")
            ctx.check("%s: the run is done at T = t sqrt(g/L) >= 2.5" % label, round(T_end, 4),
                      ">= 2.5", last.get("state") == "done" and T_end >= 2.5 - 1e-9,
                      "last event: state %s" % last.get("state"))
            s = snapshots(d)
            ids0 = np.sort(s[0][2])
            kept = [len(p) == len(ids0) and np.array_equal(np.sort(i), ids0) for _, p, i in s]
            lost = res[-1]["particles"]["lost"] if res else -1
            ctx.check("%s: every fluid particle in each of the six snapshots, none lost" % label,
                      "%s of %d" % ("/".join(str(len(p)) for _, p, _ in s), len(ids0)),
                      "all %d" % len(ids0), all(kept) and lost == 0,
                      "fluid rows (type 0) and their ids at T = %s; result lost = %d"
                      % (", ".join("%g" % T for T in TIMES), lost))
            fronts[(re, kernel, n)] = series(events)
            snaps[(re, kernel, n)] = s

    summary, rms_notes = [], []
    for kernel, n in RUNS[ctx.level]:
        f5, f10 = fronts[(500, kernel, n)], fronts[(1000, kernel, n)]
        diff = [np.interp(T, f10[:, 0], f10[:, 1]) - np.interp(T, f5[:, 0], f5[:, 1])
                for T in ORDER_T]
        ctx.check("%s, dx = L/%d: the Re = 1000 front leads the Re = 500 front at T = %s"
                  % (kernel, n, ", ".join("%g" % T for T in ORDER_T)),
                  round(min(diff), 4), "> 0 (x/L)", min(diff) > 0,
                  "Z(1000) - Z(500) = %s" % ", ".join("%+.3f" % v for v in diff))
        for re in NU:
            f = fronts[(re, kernel, n)]
            label = "Re = %d, %s, dx = L/%d" % (re, kernel, n)
            raw = mm[:, 0] / MM_N                      # their t sqrt(g/a)
            sel = raw <= MM_RAW_MAX
            Z = np.interp(raw[sel], f[:, 0], f[:, 1])
            rel = (Z - mm[sel, 1]) / mm[sel, 1]
            rms = float(np.sqrt(np.mean(rel ** 2)))
            k = int(np.argmax(np.abs(rel)))
            # noted, not checked: their column is not this one (n^2 = 2), and the scaling in
            # which the two compare was chosen after seeing the runs
            print("  note %s: front against Martin & Moyce's n^2 = 2 column at the same "
                  "t sqrt(g/a), RMS of (Z - Z_MM)/Z_MM over t sqrt(g/a) <= %g (%d points): %.4f "
                  "(largest %+.3f at t sqrt(g/a) = %.2f)" % (label, MM_RAW_MAX, int(sel.sum()),
                                                             rms, rel[k], raw[sel][k]))
            sw = mm[mm[:, 0] <= 2.5]
            rel_n = (np.interp(sw[:, 0], f[:, 0], f[:, 1]) - sw[:, 1]) / sw[:, 1]
            rms_n = float(np.sqrt(np.mean(rel_n ** 2)))
            hit = f[f[:, 1] >= TANK / L - 1.0 / n]   # within one spacing of the right wall
            reach = "reaches the right wall at T = %.2f" % hit[0, 0] if len(hit) else \
                "at x = %.2f L at T = 2.5" % np.interp(2.5, f[:, 0], f[:, 1])
            summary.append("%s: front %s; against Martin & Moyce %.1f%% RMS at equal "
                           "t sqrt(g/a)" % (label, reach, 100 * rms))
            rms_notes.append("%s %.0f%%" % (label, 100 * rms_n))

    tall_note = ""
    if ctx.level == "full":   # sphd's own n^2 = 2 column: how far equal t sqrt(g/a) carries
        events, _ = ctx.sphd_run(CASE, ["dx=%.6g" % (L / 40), "physics.viscosity.nu=%g" % NU[500],
                                        "fluid=[{\"box\": {\"min\": [0, 0], \"max\": [1, 2]}}]",
                                        "boundary.tank.max=[4, 3]", "time.end=0.6"],
                                 job="tall_%s_%d" % CASE_RUN)
        tall, sq = series(events), fronts[(500,) + CASE_RUN]
        Ts = np.arange(0.5, 1.81, 0.1)   # t sqrt(g/a), within the tall run (to 1.88)
        Ts = Ts[np.interp(Ts, tall[:, 0], tall[:, 1]) < TANK - 0.1]   # before it meets the wall
        lead_raw = np.interp(Ts, tall[:, 0], tall[:, 1]) / np.interp(Ts, sq[:, 0], sq[:, 1]) - 1
        lead_n = (np.interp(Ts / MM_N, tall[:, 0], tall[:, 1])
                  / np.interp(Ts, sq[:, 0], sq[:, 1]) - 1)
        tall_note = (" sphd's own n^2 = 2 column (%s, L/%d, the same nu) leads its " % CASE_RUN +
                     "square column by %+.1f%% to %+.1f%% at equal t sqrt(g/a) and trails it by "
                     "%.1f%% to %.1f%% at equal n t sqrt(g/a), over t sqrt(g/a) in [%.1f, %.1f]: "
                     "at these early times the front is set by the lower part of the column, "
                     "and Martin & Moyce's scaling holds only later."
                     % (100 * lead_raw.min(), 100 * lead_raw.max(), -100 * lead_n.max(),
                        -100 * lead_n.min(), Ts[0], Ts[-1]))

    colours = {("koshizuka", 40): "C0", ("koshizuka", 80): "C2", ("sheu_quartic", 40): "C1",
               ("sheu_quartic", 80): "C3"}
    for re in NU:
        fig = ctx.figure("free_surface_re%d" % re, figsize=(12, 3.9))
        dots = CASE_RUN
        for j, T in enumerate(TIMES):
            ax = fig.add_subplot(2, 3, j + 1)
            _, pos, _ = snaps[(re,) + dots][j]
            ax.plot(pos[:, 0], pos[:, 1], ".", ms=1.2, color="0.6", label="particles, %s L/%d"
                    % dots)
            for kernel, n in RUNS[ctx.level]:
                _, p, _ = snaps[(re, kernel, n)][j]
                xs, ys = surface(p, L / n)
                ax.plot(xs, ys, "-", lw=0.9, color=colours[(kernel, n)],
                        label="surface, %s L/%d" % (kernel, n))
            ax.plot([0, 0, TANK, TANK], [2, 0, 0, 2], "k-", lw=1.2)
            ax.set_xlim(-0.05, TANK + 0.05)
            ax.set_ylim(-0.05, 1.15)
            ax.set_aspect("equal")
            ax.set_title("(%s) t sqrt(g/L) = %.1f" % ("abcdef"[j], T), fontsize=9)
            ax.tick_params(labelsize=7)
            if j == 0:
                ax.legend(loc="upper right", fontsize=6, markerscale=4)
        fig.suptitle("MPS dam break, Re = %d (paper 004 Fig. %d): x/L, y/L" % (re, 6 if re == 500
                                                                               else 7),
                     fontsize=10)

    fig = ctx.figure("front", figsize=(6.5, 4.2))
    ax = fig.add_subplot(111)
    for (re, kernel, n), f in fronts.items():
        ax.plot(f[:, 0], f[:, 1], "-" if re == 500 else "--", lw=0.9, color=colours[(kernel, n)],
                label="Re = %d, %s, L/%d" % (re, kernel, n))
    ax.plot(mm[:, 0] / MM_N, mm[:, 1], "o", mfc="none", color="k", ms=4,
            label="Martin & Moyce n^2 = 2, at t sqrt(g/a)")
    ax.plot(mm[:, 0], mm[:, 1], "s", mfc="none", color="0.5", ms=4,
            label="Martin & Moyce n^2 = 2, at n t sqrt(g/a)")
    ax.axvspan(0, MM_RAW_MAX, color="0.94", zorder=0)
    ax.set_xlim(0, 2.6)
    ax.set_ylim(1, 4.2)
    ax.set_xlabel("T = t sqrt(g/L)")
    ax.set_ylabel("Z = x_front / L")
    ax.set_title("Square column: surge front (tank 4L; Martin & Moyce's n^2 = 2 column at "
                 "the same t sqrt(g/a), noted)", fontsize=9)
    ax.legend(loc="upper left", fontsize=6)

    rise = []   # the water's top can only fall after the release: a rise is numerical
    for (re, kernel, n), sn in snaps.items():
        top0 = sn[0][1][:, 1].max()
        above = [(T, p[:, 1].max()) for T, p, _ in sn[1:] if p[:, 1].max() > top0 + 0.5 / n]
        if above:
            rise.append("Re = %d, %s L/%d (%s)" % (re, kernel, n, ", ".join(
                "%.3f L at T = %.1f" % (y, T) for T, y in above)))
    ctx.note("; ".join(summary) + ". Fluid above the column's initial top (by more than dx/2) "
             "in a snapshot (numerical: after the release the top can only fall): "
             + ("; ".join(rise) if rise else "none") + ".")
    ctx.note("In Martin & Moyce's own scaling (their T = n t sqrt(g/a) against ours, the "
             "shallow-water collapse) the square column's front leads their n^2 = 2 column's "
             "by (RMS over T <= 2.5) " + ", ".join(rms_notes) + ": not a like-for-like "
             "comparison, noted only." + tall_note)
    case = RUNS[ctx.level][0]
    at = {re: ", ".join("%.2f" % np.interp(T, fronts[(re,) + case][:, 0],
                                          fronts[(re,) + case][:, 1]) for T in TIMES[1:])
          for re in NU}
    near, wall = {}, []
    for (re, kernel, n), sn in snaps.items():
        pos = sn[-1][1]   # T = 2.5
        xs, ys = surface(pos, L / n)
        near[(re, kernel, n)] = np.interp(0.1 * L, xs, ys) / L
        wall.append("%.2f L (Re = %d, %s L/%d)" % (pos[pos[:, 0] < L / n, 1].max() / L, re,
                                                   kernel, n))
    ctx.note("Against paper 004: its text says only that Figs. 6 (Re = 500) and 7 (Re = 1000; "
             "the caption's 'Re = 500' contradicts the text) compare the MPS free surfaces, "
             "dotted, with the level-set ones of its reference [16] (Sheu, Yu & Chiu 2009) at "
             "t = 0, 0.5, ..., 2.5; the figures themselves are missing from the extraction, and "
             "the text gives neither the tank's length, nor the time unit, nor a front position "
             "or run-up height. So no number of the paper is checked here; the times are taken "
             "as t sqrt(g/L) (with L = 1 m, t in seconds would put the last panel at "
             "T = 7.8, long after the surge hits the right wall). What the figures here show "
             "(%s L/%d): the column collapses into a surge along the floor, its front at "
             "x/L = %s (Re = 500) and %s (Re = 1000) at T = 0.5, 1, ..., 2.5; at T = 2.5 the "
             "surface 0.1 L from the left wall stands at %.2f L and %.2f L. In a 4L tank the "
             "surge meets the right wall only at the end of the paper's window, so the six "
             "panels hold no run-up or overturning wave."
             % (case + (at[500], at[1000], near[(500,) + case], near[(1000,) + case])))
    ctx.note("Not physical: the one column of particles next to the left wall lags the water "
             "beside it as it drains, a spike at the wall in the figures: at T = 2.5 its top is "
             "at " + ", ".join(wall) + ". It is one spacing wide at every resolution, and "
             "measured once beside this report (Re = 500 set-up, koshizuka L/40, Koshizuka & "
             "Oka's settings) with "
             "nu = 1e-6 it still stands at 0.71 L: it comes from the wall treatment, not the "
             "viscosity. It also lifts the height_left probe.")
