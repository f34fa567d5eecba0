#!/usr/bin/env bash
# SPHERIC Test 2 with its tank and box given as STL files (issue 44): the tank's walls as one
# closed solid `layers` dx thick and the box, written by scripts/make-meshes.py --only test2 from
# cases/dambreak3d.json's numbers, as a wall and an obstacle of the geometry list, against the
# case's built-in tank and obstacle: the same particles (positions, types, densities, bit for
# bit) and the same diagnostics (every diag event, bit for bit) to t = 1 s, at 12 particles over
# the depth (two runs of about a minute each on one core, side by side). The events' seq is
# not compared: the STL run has a log event per mesh more.
# Usage: geometry_test2.sh SPHD SOURCE_DIR
set -u
sphd=$1; src=$2
py=/usr/bin/python3
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
dx=${SPH_TEST2_DX:-0.0458333333333}
end=${SPH_TEST2_END:-1.0}
$py "$src/scripts/make-meshes.py" "$tmp" --only test2 --test2-dx "$dx" --check || exit 1
$py - "$src/cases/dambreak3d.json" "$tmp/stl.json" <<'PY' || exit 1
import json, sys
c = json.load(open(sys.argv[1]))
b = c["boundary"]
del b["tank"], b["obstacles"]
c["geometry"] = [{"mesh": "tank.stl", "role": "wall", "layers": b["layers"]},
                 {"mesh": "box.stl", "role": "obstacle", "layers": 64}]
json.dump(c, open(sys.argv[2], "w"), indent=1)
PY
sets=(--set "dx=$dx" --set "time.end=$end" --set output.every=0.5 --threads 1)
"$sphd" --run "$src/cases/dambreak3d.json" --out "$tmp/builtin" "${sets[@]}" >"$tmp/ev_builtin" 2>"$tmp/err_b" &
pb=$!
"$sphd" --run "$tmp/stl.json" --out "$tmp/stl" "${sets[@]}" >"$tmp/ev_stl" 2>"$tmp/err_s"
rs=$?
wait $pb
rb=$?
[ $rb = 0 ] && [ $rs = 0 ] || { echo "FAIL: exits $rb (built-in), $rs (STL)"; cat "$tmp/err_b" "$tmp/err_s"; exit 1; }
$py - "$tmp" <<'PY'
import glob, json, sys
import h5py, numpy as np
d = sys.argv[1]
fail = 0
for snap in sorted(glob.glob(d + "/builtin/snap_*.h5")):
    a, b = h5py.File(snap), h5py.File(snap.replace("/builtin/", "/stl/"))
    for k in ("pos", "vel", "rho", "type", "id"):
        if k in a and not np.array_equal(a[k][:], b[k][:]):
            print("FAIL: %s: %s differs" % (snap.split("/")[-1], k)); fail = 1
    t = a["type"][:]
    print("%s: %d fluid, %d wall particles, the same bits" % (snap.split("/")[-1], (t == 0).sum(),
                                                            (t == 1).sum()) if not fail else "")
def diags(f):
    return [{k: v for k, v in e.items() if k not in ("job", "seq")} for e in map(json.loads, open(f))
            if e["type"] == "diag"]
da, db = diags(d + "/ev_builtin"), diags(d + "/ev_stl")
same = da == db
print("%d diag events to t = %g s: %s" % (len(da), da[-1]["t"], "the same" if same else "DIFFERENT"))
if not same:
    for x, y in zip(da, db):
        if x != y:
            print("first difference:", x, y); break
    fail = 1
print("P1 %.1f Pa, P3 %.1f Pa, H2 %.4f m at the end" % (da[-1]["pressure"]["P1"],
      da[-1]["pressure"]["P3"], da[-1]["gauges"]["H2"]))
sys.exit(fail)
PY
