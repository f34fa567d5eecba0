#!/usr/bin/env bash
# Rigid bodies meet each other and the floor (tests/cases/bodies/two_boxes_water.json): a box
# 0.2 x 0.1 m of density 2000 sinks onto the floor of a tank of water 0.3 m deep while a second,
# 0.1 x 0.1 m, falls onto it from 0.6 m. After 0.6 s both have stopped: the lower one's bottom
# lies within [0, 3 dx] above the floor's top, the upper one's bottom within [0, 3 dx] above the
# lower one's top (tolerance: the dynamic boundary particles' contact distance, about 1-2 dx; a
# body that passes into another has a negative gap), and both move slower than 0.05 m/s. With
# the body particles' pressure by continuity (`pressure` "continuity") only the gaps' sign is
# checked: the fluid's layer under the upper box keeps it 4-5 dx up and still bouncing at 0.6 s.
# Usage: bodies_contact.sh SPHD SOURCE_DIR
set -u
sphd=$1; src=$2
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
fail=0
for p in fluid continuity; do
  "$sphd" --run "$src/tests/cases/bodies/two_boxes_water.json" --out "$tmp/$p" --threads 1 \
    --set bodies.0.pressure=$p --set bodies.1.pressure=$p >"$tmp/ev" 2>"$tmp/err"
  rc=$?
  [ $rc = 0 ] || { echo "FAIL $p: exit $rc"; cat "$tmp/err"; fail=1; continue; }
  /usr/bin/python3 - "$tmp/ev" "$p" <<'PY' || fail=1
import json, sys
ev = [json.loads(l) for l in open(sys.argv[1])]
d = [e for e in ev if e["type"] == "diag"][-1]
dx = 0.01
low, high = d["bodies"]["low"], d["bodies"]["high"]
floor_gap = (low["x"][1] - 0.05) / dx           # the lower box's bottom above the floor
stack_gap = (high["x"][1] - 0.05 - (low["x"][1] + 0.05)) / dx
speed = max(abs(high["v"][1]), abs(low["v"][1]))
if sys.argv[2] == "fluid":
    ok = 0 <= floor_gap <= 3 and 0 <= stack_gap <= 3 and speed < 0.05
else:
    ok = floor_gap >= 0 and stack_gap >= 0
print("%s %s: t = %.2f s, lower box %.2f dx above the floor, upper box %.2f dx above it, "
      "speeds below %.3f m/s (bounds: %s)"
      % ("ok  " if ok else "FAIL", sys.argv[2], d["t"], floor_gap, stack_gap, speed,
         "[0, 3] dx, 0.05 m/s" if sys.argv[2] == "fluid" else "gaps >= 0"))
sys.exit(0 if ok else 1)
PY
done
exit $fail
