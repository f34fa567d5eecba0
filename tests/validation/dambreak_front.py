#!/usr/bin/python3
"""Dam-break surge front against Martin & Moyce (1952), Table 2 (n^2 = 2, our H/D = 2).

Usage: dambreak_front.py EVENTS.jsonl REFERENCE.csv [--bound 0.10]

Reads the `diag` events of `sphd --run` (front_x, t), interpolates the front at the experimental
times, and compares X = x/D with the table's Z over T = t sqrt(2g/D) in [0.4, 3.3]. Passes when the
RMS of the relative difference (X - Z)/Z is below the bound (10% by default, the issue's
acceptance criterion). Prints the table and the RMS.
"""
import json
import math
import sys

D = 0.1   # column width [m]
G = 9.81  # [m/s^2]
T_LO, T_HI = 0.4, 3.3


def main():
    args = sys.argv[1:]
    bound = 0.10
    if "--bound" in args:
        k = args.index("--bound")
        bound = float(args[k + 1])
        del args[k:k + 2]
    events, ref = args
    ts, xs = [], []
    state = None
    with open(events) as f:
        for line in f:
            e = json.loads(line)
            if e["type"] == "diag" and e.get("front_x") is not None:
                ts.append(e["t"])
                xs.append(e["front_x"])
            elif e["type"] == "state":
                state = e["state"]
    if state != "done":
        print(f"FAIL: the run ended in state {state}")
        return 1
    rows = []
    with open(ref) as f:
        for line in f:
            if line.startswith("#") or line.startswith("T,"):
                continue
            c = line.strip().split(",")
            rows.append((float(c[0]), float(c[1])))
    scale = math.sqrt(2 * G / D)
    errs = []
    print(f"{'T':>6} {'Z (M&M)':>8} {'X (sphd)':>9} {'rel':>8}")
    for T, Z in rows:
        if not (T_LO <= T <= T_HI):
            continue
        t = T / scale
        if t > ts[-1]:
            print(f"FAIL: the run ends at t = {ts[-1]} s before T = {T}")
            return 1
        k = next(i for i in range(1, len(ts)) if ts[i] >= t)
        w = (t - ts[k - 1]) / (ts[k] - ts[k - 1])
        X = ((1 - w) * xs[k - 1] + w * xs[k]) / D
        errs.append((X - Z) / Z)
        print(f"{T:6.2f} {Z:8.3f} {X:9.3f} {errs[-1]:+8.3f}")
    rms = math.sqrt(sum(e * e for e in errs) / len(errs))
    print(f"RMS relative difference over T in [{T_LO}, {T_HI}] ({len(errs)} points): "
          f"{rms:.4f} (bound {bound})")
    if not rms < bound:
        print("FAIL: the front is too far from Martin & Moyce")
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
