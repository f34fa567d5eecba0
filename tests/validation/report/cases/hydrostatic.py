"""Hydrostatic tank (cases/hydrostatic.json): water 0.2 m deep at rest in a closed tank for 1 s
must stay at rest with the pressure p = rho0 g (H - y). The fluid's pressure at t = 1 s is
compared with that line, bottom layer and profile.
"""
import glob
import math
import os

import h5py
import numpy as np

TITLE = "hydrostatic tank: at rest, p = rho0 g (H - y)"
SETS = {"full": ["output.every=0.5"], "ci": ["output.every=0.5", "time.end=0.5"]}
RESOLUTION = {"full": "dx = 5 mm (3,200 fluid particles), 1 s", "ci": "dx = 5 mm, 0.5 s"}
RHO0, G, H = 1000.0, 9.81, 0.2
SPEED_BOUND = 0.01     # vmax / sqrt(g H)
BOTTOM_BOUND = 0.03    # bottom layer's mean pressure against rho0 g H
PROFILE_BOUND = 0.03   # RMS of the layer means' difference, in units of rho0 g H


def run(ctx):
    events, d = ctx.sphd_run("cases/hydrostatic.json", SETS[ctx.level])
    last = [e for e in events if e["type"] == "diag"][-1]
    speed = last["vmax"] / math.sqrt(G * H)
    ctx.check("at rest: vmax / sqrt(g H) at t = %g s" % last["t"], speed, SPEED_BOUND,
              speed < SPEED_BOUND)
    snap = sorted(glob.glob(os.path.join(d, "snap_*.h5")))[-1]
    with h5py.File(snap, "r") as f:
        fluid = f["type"][:] == 0
        y, p, dx = f["pos"][:, 1][fluid], f["p"][:][fluid], float(f.attrs["dx"])
    layers = np.round((y - dx / 2) / dx).astype(int)
    yl = np.array([y[layers == k].mean() for k in range(layers.max() + 1)])
    pl = np.array([p[layers == k].mean() for k in range(layers.max() + 1)])
    exact = RHO0 * G * (H - yl)
    bottom = abs(pl[0] - RHO0 * G * H) / (RHO0 * G * H)
    ctx.check("bottom layer: |p - rho0 g H| / rho0 g H", float(bottom), BOTTOM_BOUND,
              bottom < BOTTOM_BOUND, "mean over the bottom layer of fluid particles")
    prof = float(np.sqrt(np.mean((pl - exact) ** 2)) / (RHO0 * G * H))
    ctx.check("profile: RMS of layer-mean p - rho0 g (H - y), over rho0 g H", prof, PROFILE_BOUND,
              prof < PROFILE_BOUND)
    fig = ctx.figure("pressure", figsize=(5, 4))
    ax = fig.add_subplot(111)
    ax.plot(p, y, ".", ms=1.5, color="0.7", label="fluid particles")
    ax.plot(pl, yl, "o", ms=3, mfc="none", label="sphd, layer means (t = %g s)" % last["t"])
    ax.plot(RHO0 * G * (H - np.array([0, H])), [0, H], "k-", label="rho0 g (H - y)")
    ax.set_xlabel("p [Pa]")
    ax.set_ylabel("y [m]")
    ax.set_title("hydrostatic tank: pressure (bottom %.2f%%)" % (100 * bottom))
    ax.legend(fontsize=8)
