#!/usr/bin/python3
"""Water entry of a cylinder against Greenhow & Lin (1983): penetration over time.

Usage: water_entry_penetration.py EVENTS.jsonl REFERENCE.csv [--bound 0.10] [--body NAME]
                                  [--png FILE --label TEXT]

Reads the `diag` events of `sphd --run` (t, and the body's `penetration`, the depth of its lowest
point below the still-water level), interpolates the penetration at the experimental times and
compares pen/D with the reference over tau = t sqrt(g/D) in [0.1, 1.1]. Passes when the RMS of the
relative difference is below the bound (10% by default, the issue's acceptance criterion). Prints
the table and the RMS; with --png, also plots the run against the reference (matplotlib, when
installed).
"""
import json
import math
import sys

D = 0.11  # cylinder diameter [m]
G = 9.81  # [m/s^2]
TAU_LO, TAU_HI = 0.1, 1.1


def option(args, name, default):
    if name in args:
        k = args.index(name)
        v = args[k + 1]
        del args[k:k + 2]
        return v
    return default


def main():
    args = sys.argv[1:]
    bound = float(option(args, "--bound", "0.10"))
    body = option(args, "--body", "cylinder")
    png = option(args, "--png", None)
    label = option(args, "--label", "sphd")
    events, ref = args
    ts, ps = [], []
    state = None
    with open(events) as f:
        for line in f:
            e = json.loads(line)
            if e["type"] == "diag":
                b = e.get("bodies", {}).get(body)
                if b is not None and b.get("penetration") is not None:
                    ts.append(e["t"])
                    ps.append(b["penetration"])
            elif e["type"] == "state":
                state = e["state"]
    if state != "done":
        print(f"FAIL: the run ended in state {state}")
        return 1
    rows = []
    with open(ref) as f:
        for line in f:
            if line.startswith("#") or line.startswith("tau,"):
                continue
            c = line.strip().split(",")
            rows.append((float(c[0]), float(c[1])))
    scale = math.sqrt(G / D)
    errs = []
    print(f"{'tau':>6} {'pen/D (G&L)':>11} {'pen/D (sphd)':>12} {'rel':>8}")
    for tau, ref_pen in rows:
        if not (TAU_LO <= tau <= TAU_HI):
            continue
        t = tau / scale
        if not ts or t > ts[-1]:
            print(f"FAIL: the run ends before tau = {tau}")
            return 1
        k = next(i for i in range(1, len(ts)) if ts[i] >= t)
        w = (t - ts[k - 1]) / (ts[k] - ts[k - 1])
        pen = ((1 - w) * ps[k - 1] + w * ps[k]) / D
        errs.append((pen - ref_pen) / ref_pen)
        print(f"{tau:6.3f} {ref_pen:11.4f} {pen:12.4f} {errs[-1]:+8.3f}")
    rms = math.sqrt(sum(e * e for e in errs) / len(errs))
    print(f"RMS relative difference over tau in [{TAU_LO}, {TAU_HI}] ({len(errs)} points): "
          f"{rms:.4f} (bound {bound})")
    if png:
        try:
            import matplotlib
            matplotlib.use("Agg")
            import matplotlib.pyplot as plt
            fig, ax = plt.subplots(figsize=(6, 4))
            ax.plot([t * scale for t in ts], [p / D for p in ps], "-", label=f"{label} (RMS {rms:.3f})")
            ax.plot([r[0] for r in rows], [r[1] for r in rows], "ko", label="Greenhow & Lin 1983")
            ax.set_xlabel("t sqrt(g/D)")
            ax.set_ylabel("penetration / D")
            ax.legend()
            fig.tight_layout()
            fig.savefig(png, dpi=120)
            print(f"wrote {png}")
        except ImportError:
            print("no matplotlib: no PNG")
    if not rms < bound:
        print("FAIL: the penetration is too far from Greenhow & Lin")
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
