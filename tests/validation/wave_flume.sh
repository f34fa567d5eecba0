#!/usr/bin/env bash
# A short wave flume (issue 45): cases/wave_flume.json (d = 0.4 m, H = 0.05 m, T = 1.27 s,
# kd = 1.20, dx = 0.02 m: 2.5 particles per wave height) to t = 10 s, about 1.5 minutes on one
# core. The result's wave analysis (zero up-crossing, from the end of the ramp plus the group
# velocity's travel to the gauge) at the gauge g1L, one wavelength from the paddle: the period
# within 2% of T, and the height within 25% of H. This is a guard of the wavemaker's theory and
# the paddle's motion (a wrong transfer function or stroke is off by far more), NOT the issue's
# accuracy, which the flume does not reach yet: measured (2026-11-29), the height one, two and
# three wavelengths from the paddle is -15%, -25%, -36% of H to t = 10 s at dx = 0.02, the same
# at dx = 0.01 (-15%, -28%, -42%: not a matter of resolution), and -11%, -18%, -31% over the
# longer window of a run to t = 20 s (the first waves of the train are the lowest); the issue
# asks for 5% two wavelengths from the paddle. The cause is open (issue 45's notes).
# Usage: wave_flume.sh SPHD SOURCE_DIR
set -u
sphd=$1; src=$2
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
"$sphd" --run "$src/cases/wave_flume.json" --out "$tmp/out" --threads 1 \
  --set time.end=10 --set output.every=100 >"$tmp/ev" 2>"$tmp/err" || { cat "$tmp/err"; exit 1; }
/usr/bin/python3 - "$tmp/out/result.json" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
H, T = 0.05, 1.27
w = r["waves"]
for g, v in w.items():
    if v["height"] is None:
        print(f"{g}: no whole wave after {v['from']:.2f} s")
        continue
    print(f"{g}: height {v['height']} m ({100 * (v['height'] / H - 1):+.1f}%), period "
          f"{v['period']} s ({100 * (v['period'] / T - 1):+.2f}%), {v['count']} waves from {v['from']:.2f} s")
print(f"wall time {r['wall_time']:.1f} s, {r['steps']} steps")
g = w["g1L"]
ok = g["count"] >= 1 and g["height"] is not None and abs(g["period"] / T - 1) <= 0.02 and abs(g["height"] / H - 1) <= 0.25
sys.exit(0 if ok else 1)
PY
