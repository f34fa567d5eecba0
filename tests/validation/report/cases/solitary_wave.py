"""Solitary-wave run-up on a vertical wall (Sheu, Chiao & Huang 2011, paper 004, section 5.1;
cases/solitary_wave.json; issue 12): still depth d = 10 m, wave height H = 2 m, a channel 16d long,
the crest starting at x0 = 60 m with the surface and velocities of eqs. (5.1)-(5.2), MPS with
Koshizuka & Oka's settings. The largest run-up R on the right wall above the still water (the
`runup` probe less its value at t = 0, which is the depth the lattice's whole rows hold: 9.6 m at
dx = 0.8 m, 10 m at 0.4 m) against the third-order value of Su & Mirie (1980) at eps = H/d of that
depth (tests/validation/reference/solitary_wave_runup_vertical_wall.csv: R/d = 0.426 at
eps = 0.2). The issue's bounds: 10% at the paper's dx = 0.8 m and 5% at 0.4 m (the full level);
the ci level runs dx = 0.8 m with a loose 25%: there the figure moves from -14% to +4% with the
time-step sequence alone (snapshots every 0.2 s or 0.5 s: the steps stop on the output times), as
the run-up carries the pressure noise of Koshizuka & Oka's settings. The full level measures that
spread (the case at dx = 0.8 m with snapshots every 0.2 s and 0.25 s beside its 0.5 s: noted), and
runs the quartic weight of Sheu et al. beside (noted, not checked).
"""
import glob
import math
import os

import numpy as np

TITLE = "solitary wave: run-up on a vertical wall against third-order theory"
G, H = 9.81, 2.0
SETS = {"koshizuka": [], "sheu_quartic": ["kernel.type=sheu_quartic", "mps.re=2",
                                          "mps.re_grad=2"]}
# (weight, dx, bound on the relative difference of R/d or None: noted, snapshot interval [s])
RUNS = {"full": [("koshizuka", 0.8, 0.10, 0.5), ("koshizuka", 0.4, 0.05, 0.5),
                 ("koshizuka", 0.8, None, 0.2), ("koshizuka", 0.8, None, 0.25),
                 ("sheu_quartic", 0.8, None, 0.5), ("sheu_quartic", 0.4, None, 0.5)],
        "ci": [("koshizuka", 0.8, 0.25, 0.5)]}
RESOLUTION = {"full": "dx = 0.8 m (the paper's, 2,500 fluid particles) and 0.4 m (10,000), both "
                      "MPS weights",
              "ci": "dx = 0.8 m (the paper's spacing, 2,500 fluid particles), Koshizuka's weight"}


def surface(snap):
    """The fluid's time, and its free surface as (column centres, top + dx/2) of a snapshot."""
    import h5py
    with h5py.File(snap, "r") as f:
        t, dx = float(f.attrs["time"]), float(f.attrs["dx"])
        pos, typ = f["pos"][:], f["type"][:]
    p = pos[typ == 0]
    col = np.floor(p[:, 0] / dx).astype(int)
    top = np.full(col.max() + 1, np.nan)
    for k in np.unique(col):
        top[k] = p[col == k, 1].max() + 0.5 * dx
    x = (np.arange(len(top)) + 0.5) * dx
    return t, x, top, p


def run(ctx):
    ref = ctx.reference_columns("solitary_wave_runup_vertical_wall.csv")
    fig = ctx.figure("runup", figsize=(6.5, 4.2))
    ax = fig.add_subplot(111)
    fig2 = ctx.figure("free_surface", figsize=(7.5, 2.2 * len(RUNS[ctx.level]) + 0.6))
    summary = []
    for k, (weight, dx, bound, every) in enumerate(RUNS[ctx.level]):
        sets = ["dx=%g" % dx, "output.every=%g" % every] + SETS[weight]
        events, out = ctx.sphd_run("cases/solitary_wave.json", sets,
                                   job="solitary_wave_%s_%g" % (weight, dx))
        assert events[-1].get("state") == "done", events[-1]
        diag = [e for e in events if e["type"] == "diag"]
        t = np.array([e["t"] for e in diag])
        r = np.array([np.nan if e.get("runup") is None else e["runup"] for e in diag])
        d = r[0]  # the still depth the lattice holds (the wave's hump is far from the wall)
        expect_d = math.floor(10.0 / dx + 1e-6) * dx
        assert abs(d - expect_d) < 0.5 * dx, (d, expect_d)
        eps = H / d
        ref_r = float(np.interp(eps, ref["eps"], ref["R_over_d_3rd_SuMirie"]))
        kmax = int(np.nanargmax(r))
        R = (r[kmax] - d) / d
        rel = (R - ref_r) / ref_r
        label = "%s, dx = %g m%s" % (weight, dx, "" if every == 0.5 else
                                     ", snapshots every %g s" % every)
        lost = diag[-1]["lost"]
        ctx.check("%s: no fluid particle lost" % label, lost, 0, lost == 0)
        how = ("largest run-up %.3f m above the still depth %.2f m at t = %.2f s; third order "
               "R/d = %.4f at eps = %.4f" % (r[kmax] - d, d, t[kmax], ref_r, eps))
        if bound is not None:
            ctx.check("%s: largest run-up R/d against third order, relative difference"
                      % label, round(rel, 4), bound, abs(rel) <= bound, how)
        else:
            print("  note %s: R/d %.4f, %+.1f%% against third order (%s)"
                  % (label, R, 100 * rel, how))
        summary.append("%s: R/d = %.3f (%+.1f%%) at t = %.2f s" % (label, R, 100 * rel, t[kmax]))
        ax.plot(t * math.sqrt(G / d), (r - d) / d, "-", lw=0.9, label="sphd, " + label)
        # the free surface at the snapshot nearest the largest run-up
        snaps = sorted(glob.glob(os.path.join(out, "snap_*.h5")))
        ts = [round(i * every, 9) for i in range(len(snaps))]
        j = int(np.argmin(np.abs(np.array(ts) - t[kmax])))
        ts_j, x, top, p = surface(snaps[j])
        a = fig2.add_subplot(len(RUNS[ctx.level]), 1, k + 1)
        a.plot(p[:, 0], p[:, 1], ".", ms=0.8, color="0.6")
        a.plot(x, top, "-", lw=0.9, color="C0", label="free surface (top particle + dx/2)")
        a.axhline(d, color="k", lw=0.5, ls=":")
        a.axhline(d + ref_r * d, color="C3", lw=0.8, ls="--", label="third-order run-up")
        a.set_xlim(100, 160)
        a.set_ylim(0, d + 2.5 * H)
        a.set_title("%s, t = %.2f s (largest run-up at %.2f s)" % (label, ts_j, t[kmax]),
                    fontsize=8)
        a.set_ylabel("y [m]")
        a.legend(loc="upper left", fontsize=6)
    for name in ("R_over_d_3rd_SuMirie", "R_over_d_linear"):
        v = float(np.interp(H / 10.0, ref["eps"], ref[name]))
        ax.axhline(v, color="k", lw=0.7, ls="--" if "3rd" in name else ":",
                   label="%s order, eps = 0.2" % ("third" if "3rd" in name else "linear"))
    ax.set_xlabel("t sqrt(g/d)")
    ax.set_ylabel("(run-up - d) / d at the right wall")
    ax.set_title("Solitary wave H/d = 0.2: run-up on the right wall")
    ax.legend(loc="upper left", fontsize=7)
    fig2.axes[-1].set_xlabel("x [m]")
    ctx.note("Largest run-up against Su & Mirie's third order: " + "; ".join(summary) + ".")
    ctx.note("Koshizuka & Oka's settings do not keep still water at rest (the still-water test "
             "uses other settings, which blow this case up within 2 s): the total energy grows "
             "by about twice the wave's initial kinetic energy in the first 5 s, so the wave "
             "runs on a disturbed sea and the run-up carries that noise.")
