#!/usr/bin/env bash
# A short wave flume (issue 45): cases/wave_flume.json (d = 0.4 m, H = 0.05 m, T = 1.27 s,
# kd = 1.20, dx = 0.02 m: 2.5 particles per wave height, h = 2 dx) to t = 10 s, about 1.5
# minutes on one core. The result's wave analysis (zero up-crossing over the developed train: from one
# period after the ramp's end has reached the gauge at the group velocity) at the gauges g1L and
# g2L, one and two wavelengths from the paddle: g1L's period within 1% of T, the heights within
# 10% (g1L) and 12% (g2L) of H. A guard of the wavemaker's theory, the paddle's motion and the
# flume's numerics (the case's description says each): -4.4% and -7.1% (one wave) here
# (2026-11-29), where the numerics before (h = 1.414 dx, Molteni's delta-SPH, the artificial
# viscosity alpha 0.01) give -14% and -27% (-20% and -29% with Fourtakas' delta-SPH).
# Measured over the developed train to t = 14 s (2026-11-29; the table in docs/validation.md):
# -4.1%, -7.5%, -10.6% at one, two and three wavelengths, the height falling 3.4% per
# wavelength (at dx = 0.01 on a 7.5 m flume to 11 s: -2.4%, -5.1%, 2.5% per wavelength); the
# issue asks for 5% two wavelengths from the paddle, not reached yet at the case's dx.
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
k = r.get("reflection") or {}
print(f"reflection at {', '.join(k.get('gauges', []))}: Kr {k.get('coefficient')}, incident height "
      f"{k.get('incident_height')} m, from {k.get('from')} s (a short window: figures in "
      f"docs/validation.md) {k.get('why', '')}")
print(f"wall time {r['wall_time']:.1f} s, {r['steps']} steps")
def within(name, bound, period=None):
    g = w[name]
    if g["count"] < 1 or g["height"] is None:
        return False
    if period is not None and abs(g["period"] / T - 1) > period:
        return False
    return abs(g["height"] / H - 1) <= bound
ok = within("g1L", 0.10, period=0.01) and within("g2L", 0.12)
sys.exit(0 if ok else 1)
PY
