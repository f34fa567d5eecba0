#!/usr/bin/python3
"""Water entry: how close the fluid comes to the cylinder (a measurement for issue 11, no bound).

Usage: water_entry_gap.py OUTDIR EVENTS.jsonl [--body NAME] [--diameter D]

For every snapshot in OUTDIR after the first (fields pos and type needed), takes the body's centre
from the nearest `diag` event in EVENTS.jsonl (sphd --run's output) and prints, for 15-degree
sectors of the lower half of the body (from -165 to -15 degrees, -90 straight down), the distance
of the nearest fluid particle's centre beyond the body's radius R, in units of dx. Particles fill
the volume around their centres, so a fluid in contact with the body has its nearest centres at
R + dx/2 (0.50 here); more means a gap between the water and the body, which makes the body
effectively larger than it is. Sectors above the waterline show the free surface instead. Also
prints the outer body layer's mean density and largest pressure, and, as a check of the same wall
treatment elsewhere, the distance of the fluid's lowest centres from the tank bottom's top layer
(1.00 dx when the fluid touches it).
"""
import glob
import json
import os
import sys

import h5py
import numpy as np


def option(args, name, default):
    if name in args:
        k = args.index(name)
        v = args[k + 1]
        del args[k:k + 2]
        return v
    return default


def main():
    args = sys.argv[1:]
    body = option(args, "--body", "cylinder")
    R = 0.5 * float(option(args, "--diameter", "0.11"))
    out, events = args
    diags = [json.loads(l) for l in open(events)]
    diags = [e for e in diags if e.get("type") == "diag" and body in e.get("bodies", {})]
    print("fluid centre - R [dx] by 15-degree sector, -165 ... -15 degrees (-90: straight down)")
    for f in sorted(glob.glob(os.path.join(out, "snap_*.h5")))[1:]:
        with h5py.File(f, "r") as h:
            t, dx = h.attrs["time"], h.attrs["dx"]
            pos, typ = h["pos"][:, :2], h["type"][:]
            rho, p = h["rho"][:], h["p"][:]
        e = min(diags, key=lambda e: abs(e["t"] - t))
        c = np.array(e["bodies"][body]["x"][:2])
        r = np.linalg.norm(pos - c, axis=1)
        ang = np.degrees(np.arctan2(pos[:, 1] - c[1], pos[:, 0] - c[0]))
        row = []
        for a in range(-165, 0, 15):
            m = (typ == 0) & (ang >= a) & (ang < a + 15) & (r < R + 5 * dx)
            row.append(f"{(r[m].min() - R) / dx:4.2f}" if m.any() else "  - ")
        outer = (typ == 4) & (r > R - dx)
        wall = pos[(typ == 1) & (pos[:, 1] < 0.0), 1]
        low = np.sort(pos[(typ == 0) & (np.abs(pos[:, 0] - c[0]) > 3 * R), 1])[:20]
        bottom = f"{(low.mean() - wall.max()) / dx:.2f}" if wall.size and low.size else "-"
        print(f"t={t:.3f} dx={dx:g} penetration={e['bodies'][body]['penetration']:.4f}: "
              f"{' '.join(row)} | outer body layer rho {rho[outer].mean():.1f} (max "
              f"{rho[outer].max():.1f}), p max {p[outer].max():.0f} Pa | bottom wall {bottom} dx")
    return 0


if __name__ == "__main__":
    sys.exit(main())
