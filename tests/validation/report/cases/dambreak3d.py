"""The 3D dam break with a box obstacle (Kleefsman et al. 2005; SPHERIC benchmark Test 2;
cases/dambreak3d.json) against the MARIN measurement: the water heights at gauges H2 (between
the box and the gate) and H4 (in the reservoir), and the pressures at sensors P1 and P3 on the
box's front face (read 1.5 h off the face along its normal, as the peers read wall sensors: the
case's `diagnostics.pressure.*.normal`), sampled every 1 ms (`diagnostics.interval`, the
experiment's rate).

Issue 23's yardsticks, over t in [0, 6] s at the finest resolution (30 particles over the 0.55 m
depth, as the SPHERIC description suggests):
- heights: the RMS difference at H2 and at H4 within 0.04 m; the first arrival of water at H2
  (the height first above ARRIVAL_H) within 0.05 s of the experiment's;
- pressures, both signals averaged over 10 ms (a centred running mean on a 1 ms grid, the
  measurement interpolated onto it): the first impact (the averaged pressure first above
  IMPACT_FRACTION of the averaged measurement's peak) within 0.02 s of the experiment's; the RMS
  difference over t in [0.35, 6] s within 15% of the averaged measurement's peak;
- each of these errors smaller at the finest resolution than at the coarsest.
Three resolutions at the full level: 12, 16 (the case's default) and 30 particles over the depth
(25,074, 49,207 and 217,422 particles, fluid and walls); the finest is a long run that resumes from
its checkpoint (--runs).

At the ci level (ctest validation_dambreak3d), the coarsest to t = 1 s (the first impact), as a
guard against regressions, not the issue's yardstick: at 12 particles over the depth a front
thinner than a particle is not resolved, so the impact comes late, and the splash off the box
falls back over H2 from 0.55 s on. Checked there: the arrival at H2, the RMS at H4 and the RMS at
H2 over [0, CI_H2_UNTIL] s (the front's arrival, before the splash) within the issue's bounds, and
the first impacts within CI_IMPACT; the RMS at H2 over [0, 1] s and the pressures' are reported.
"""
import os

import numpy as np
from validate import read_diag

TITLE = "3D dam break with a box (SPHERIC Test 2): heights and pressures against Kleefsman et al."
DEPTH = 0.55
T_END = 6.0
ARRIVAL_H = 0.05        # [m] the height that marks the water's arrival at H2
ARRIVAL_BOUND = 0.05    # [s]
HEIGHT_BOUND = 0.04     # [m] RMS
AVG = 0.010             # [s] the pressures' running mean
IMPACT_FRACTION = 0.2   # of the averaged measurement's peak: the first impact
IMPACT_BOUND = 0.02     # [s]
P_WINDOW = (0.35, T_END)
P_BOUND = 0.15          # RMS over P_WINDOW / the averaged measurement's peak
CI_H2_UNTIL = 0.5       # [s] the window of the RMS at H2 at the ci level
CI_IMPACT = 0.1         # [s] first impacts, 12 over the depth (ci level)
LAYERS = {"full": [12, 16, 30], "ci": [12]}
# SPH_DAMBREAK3D_LAYERS=12,16: the full level at these resolutions only (30 takes two hours)
if os.environ.get("SPH_DAMBREAK3D_LAYERS"):
    LAYERS["full"] = [int(v) for v in os.environ["SPH_DAMBREAK3D_LAYERS"].split(",")]
RESOLUTION = {"full": "12, 16 and 30 particles over the 0.55 m depth (dx = 45.8, 34.4, 18.3 mm)",
              "ci": "12 particles over the depth (dx = 45.8 mm), to t = 1 s"}


def running_mean(t, y, width):
    """y (on the times t) on a uniform grid of 1 ms over [t0, t1], then a centred running mean
    over width: (grid, averaged)."""
    step = 0.001
    grid = np.arange(np.ceil(t[0] / step) * step, t[-1] + 1e-12, step)
    yg = np.interp(grid, t, y)
    n = int(round(width / step))
    kern = np.ones(n) / n
    avg = np.convolve(yg, kern, mode="same")
    half = n // 2  # the ends, where the window is not full, are left out
    return grid[half:len(grid) - half], avg[half:len(grid) - half]


def first_above(t, y, level):
    k = np.nonzero(y > level)[0]
    return float(t[k[0]]) if len(k) else float("nan")


def compare(diag, exp_h, exp_p, t_end):
    """The errors of one run: {name: value} (heights [m], times [s], pressures as a fraction of
    the averaged measurement's peak), and the averaged series for the figures."""
    t = np.asarray(diag["t"], float)
    e = {}
    th = exp_h["t_s"]
    sel = (th >= 0.0) & (th <= t_end)
    for g, col in (("H2", "H2_x0.992_m"), ("H4", "H4_x2.638_m")):
        sim = np.interp(th[sel], t, np.asarray(diag[g], float))
        e[g + " rms"] = float(np.sqrt(np.mean((sim - exp_h[col][sel]) ** 2)))
    early = (th >= 0.0) & (th <= CI_H2_UNTIL)
    sim = np.interp(th[early], t, np.asarray(diag["H2"], float))
    e["H2 rms early"] = float(np.sqrt(np.mean((sim - exp_h["H2_x0.992_m"][early]) ** 2)))
    e["H2 arrival"] = first_above(t, np.asarray(diag["H2"], float), ARRIVAL_H)
    e["H2 arrival exp"] = first_above(th, exp_h["H2_x0.992_m"], ARRIVAL_H)
    avg = {}
    for p in ("P1", "P3"):
        tp = exp_p["t_s"]
        keep = tp <= t_end + AVG
        ge, ye = running_mean(tp[keep], exp_p[p + "_Pa"][keep], AVG)
        gs, ys = running_mean(t, np.asarray(diag[p], float), AVG)
        n = min(len(ge), len(gs))
        g, ye, ys = ge[:n], ye[:n], ys[:n]
        inw = (g >= P_WINDOW[0]) & (g <= min(P_WINDOW[1], t_end))
        peak = float(ye[g <= t_end].max())
        e[p + " peak exp"] = peak
        e[p + " impact"] = first_above(g, ys, IMPACT_FRACTION * peak)
        e[p + " impact exp"] = first_above(g, ye, IMPACT_FRACTION * peak)
        e[p + " rms"] = float(np.sqrt(np.mean((ys[inw] - ye[inw]) ** 2)) / peak)
        avg[p] = (g, ys, ye)
    return e, avg


def run(ctx):
    exp_h = ctx.reference_columns("dambreak3d_Kleefsman2005_heights_H2_H4.csv")
    exp_p = ctx.reference_columns("dambreak3d_Kleefsman2005_pressures_P1_P3.csv")
    t_end = T_END if ctx.level == "full" else 1.0
    figs = {}
    for name, ylabel in (("H2", "height [m]"), ("H4", "height [m]"), ("P1", "pressure [Pa]"),
                         ("P3", "pressure [Pa]")):
        fig = ctx.figure("dambreak3d_" + name, figsize=(7.5, 3.4))
        figs[name] = fig.add_subplot(111)
        figs[name].set_xlabel("t [s]")
        figs[name].set_ylabel(ylabel)
    errs = []
    for n in LAYERS[ctx.level]:
        dx = DEPTH / n
        sets = ["dx=%.9g" % dx, "time.end=%g" % t_end, "output.every=%g" % t_end]
        if ctx.level == "full":
            res, diag, _ = ctx.sphd_run_long("cases/dambreak3d.json", sets, "dambreak3d-n%d" % n)
        else:
            events, d = ctx.sphd_run("cases/dambreak3d.json", sets, job="dambreak3d")
            assert events[-1].get("state") == "done", events[-1]
            diag = read_diag(os.path.join(d, "diag.h5"))
        e, avg = compare(diag, exp_h, exp_p, t_end)
        errs.append((n, e))
        label = "sphd, %d over the depth (dx = %.1f mm)" % (n, 1e3 * dx)
        for g in ("H2", "H4"):
            figs[g].plot(diag["t"], diag[g], lw=0.9, label=label)
        for p in ("P1", "P3"):
            figs[p].plot(avg[p][0], avg[p][1], lw=0.9, label=label + ", 10 ms mean")
        ctx.note("%d particles over the depth (dx = %.1f mm): %s" % (n, 1e3 * dx, "; ".join(
            "%s %.4g" % (k, v) for k, v in e.items())))
    n, e = errs[-1]
    at = "%d over the depth" % n
    full = ctx.level == "full"
    for g in ("H2", "H4"):
        if full or g == "H4":
            ctx.check("%s, %s: RMS height difference over t in [0, %g] s [m]" % (g, at, t_end),
                      round(e[g + " rms"], 4), HEIGHT_BOUND, e[g + " rms"] <= HEIGHT_BOUND)
        else:
            ctx.check("H2, %s: RMS height difference over t in [0, %g] s (the front's arrival) "
                      "[m]" % (at, CI_H2_UNTIL), round(e["H2 rms early"], 4), HEIGHT_BOUND,
                      e["H2 rms early"] <= HEIGHT_BOUND)
            ctx.note("H2, %s: RMS height difference over t in [0, %g] s: %.3f m (not checked at "
                     "the ci level: the splash off the box falls back over the gauge)"
                     % (at, t_end, e["H2 rms"]))
    d = e["H2 arrival"] - e["H2 arrival exp"]
    ctx.check("H2, %s: first arrival (height > %g m) against the experiment's [s]" % (at, ARRIVAL_H),
              round(d, 4), ARRIVAL_BOUND, abs(d) <= ARRIVAL_BOUND,
              "sphd %.3f s, experiment %.3f s" % (e["H2 arrival"], e["H2 arrival exp"]))
    for p in ("P1", "P3"):
        d = e[p + " impact"] - e[p + " impact exp"]
        bound = IMPACT_BOUND if full else CI_IMPACT
        ctx.check("%s, %s: first impact (10 ms mean > %g of the measured peak) against the "
                  "experiment's [s]" % (p, at, IMPACT_FRACTION), round(d, 4), bound,
                  abs(d) <= bound, "sphd %.3f s, experiment %.3f s" % (
                      e[p + " impact"], e[p + " impact exp"]))
        what = "%s, %s: RMS difference of the 10 ms means over t in [%g, %g] s / the measured " \
            "peak" % (p, at, P_WINDOW[0], min(P_WINDOW[1], t_end))
        if full:
            ctx.check(what, round(e[p + " rms"], 4), P_BOUND, e[p + " rms"] <= P_BOUND,
                      "measured peak (10 ms mean) %.0f Pa" % e[p + " peak exp"])
        else:
            ctx.note("%s: %.3f (not checked at the ci level; the bound %g is the full level's, at "
                     "30 over the depth)" % (what, e[p + " rms"], P_BOUND))
    if len(errs) > 1:
        (n0, e0), (n1, e1) = errs[0], errs[-1]
        for k in ("H2 rms", "H4 rms", "H2 arrival", "P1 impact", "P3 impact", "P1 rms", "P3 rms"):
            ref = e0.get(k + " exp", 0.0) if k.endswith(("arrival", "impact")) else 0.0
            a, b = abs(e0[k] - ref), abs(e1[k] - ref)
            ctx.check("%s error smaller at %d than at %d over the depth" % (k, n1, n0),
                      round(b - a, 4), 0.0, b < a, "%.4g at %d, %.4g at %d" % (a, n0, b, n1))
    t_e = exp_h["t_s"]
    for g, col in (("H2", "H2_x0.992_m"), ("H4", "H4_x2.638_m")):
        s = t_e <= t_end
        figs[g].plot(t_e[s], exp_h[col][s], "k-", lw=0.7, label="Kleefsman et al. (2005)")
        figs[g].set_title("height at %s" % g)
    for p in ("P1", "P3"):
        g, _, ye = avg[p]
        figs[p].plot(g, ye, "k-", lw=0.7, label="Kleefsman et al. (2005), 10 ms mean")
        figs[p].set_title("pressure at %s (box front face)" % p)
    for ax in figs.values():
        ax.legend(fontsize=7)
