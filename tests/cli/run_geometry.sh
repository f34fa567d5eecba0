#!/usr/bin/env bash
# The geometry list through `sphd --run` (issue 44):
#  - cases/pier.stl is what scripts/make-meshes.py --only pier writes (to float precision);
#  - cases/pier3d.json (a mesh obstacle, skewed by its transform) runs: exit 0, the pier's wall
#    particles there;
#  - an open mesh is refused (exit 65) naming its open edges;
#  - a 3-layer wall shell inside a sphere's mesh (an icosphere) holds water falling inside it for
#    2 s: no fluid particle gets out (0 lost, none beyond the surface).
# Usage: run_geometry.sh SPHD SOURCE_DIR
set -u
sphd=$1; src=$2
py=/usr/bin/python3
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
fail=0

$py "$src/scripts/make-meshes.py" "$tmp/m" --only pier sphere --sphere-radius 0.1 \
  --sphere-subdivisions 4 >/dev/null || { echo "FAIL: make-meshes.py"; fail=1; }
$py - "$tmp/m/pier.stl" "$src/cases/pier.stl" <<'PY' || fail=1
import sys
import numpy as np
def tris(p):
    b = open(p, "rb").read()
    n = int.from_bytes(b[80:84], "little")
    r = np.frombuffer(b[84:84 + 50 * n], dtype=[("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")])
    return r["v"].astype(float)
a, b = tris(sys.argv[1]), tris(sys.argv[2])
assert a.shape == b.shape and np.abs(a - b).max() < 1e-6, "cases/pier.stl is not make-meshes.py's"
print("cases/pier.stl: make-meshes.py's,", len(a), "triangles")
PY

# the pier case, a few steps
"$sphd" --run "$src/cases/pier3d.json" --out "$tmp/pier" --set time.end=0.01 >"$tmp/ev" 2>"$tmp/err"
rc=$?
[ $rc = 0 ] || { echo "FAIL: pier3d exit $rc"; cat "$tmp/err"; fail=1; }
$py - "$tmp/ev" "$tmp/pier/snap_000000.h5" <<'PY' || fail=1
import json, sys
import h5py, numpy as np
ev = [json.loads(l) for l in open(sys.argv[1])]
assert ev[-1]["type"] == "state" and ev[-1]["state"] == "done", ev[-1]
logs = [e["message"] for e in ev if e["type"] == "log"]
assert any("mesh pier.stl: 132 triangles" in m for m in logs), logs
res = [e for e in ev if e["type"] == "result"][0]
f = h5py.File(sys.argv[2])
p, t = f["pos"][:], f["type"][:]
w = p[t == 1]
# the pier: wall particles inside the channel (its own walls lie outside the tank's box)
pier = w[(w[:, 0] > 0) & (w[:, 0] < 2) & (w[:, 1] > 0) & (w[:, 1] < 0.6) & (w[:, 2] > 0)]
c, s = np.cos(np.radians(15)), np.sin(np.radians(15))
u = (pier[:, 0] - 1.2) * c + (pier[:, 1] - 0.3) * s      # along the pier
v = -(pier[:, 0] - 1.2) * s + (pier[:, 1] - 0.3) * c     # across it
assert len(pier) > 100 and np.abs(u).max() < 0.1 and np.abs(v).max() < 0.03 \
    and pier[:, 2].max() < 0.5, (len(pier), np.abs(u).max(), np.abs(v).max())
print("pier3d: %d fluid, %d wall particles, %d of them the pier's, within its section"
      % (res["particles"]["fluid"], res["particles"]["boundary"], len(pier)))
PY

# an open mesh: two facets of a box missing
$py - "$tmp/open.stl" <<'PY'
import sys
lo, hi = (1.2, 0.3, 0.0), (1.4, 0.5, 0.2)
c = [[(hi if (k >> d) & 1 else lo)[d] for d in range(3)] for k in range(8)]
quads = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]
out = ["solid open"]
for a, b, cc, d in quads[1:]:
    for tri in ((a, b, cc), (a, cc, d)):
        out += [" facet normal 0 0 0", "  outer loop"] + \
               ["   vertex %g %g %g" % tuple(c[v]) for v in tri] + ["  endloop", " endfacet"]
open(sys.argv[1], "w").write("\n".join(out + ["endsolid open"]) + "\n")
PY
$py - "$src/cases/pier3d.json" "$tmp/open.json" <<'PY'
import json, sys
c = json.load(open(sys.argv[1]))
c["geometry"][0]["mesh"] = "open.stl"
json.dump(c, open(sys.argv[2], "w"))
PY
"$sphd" --run "$tmp/open.json" --out "$tmp/open" >/dev/null 2>"$tmp/err_open"
rc=$?
if [ $rc != 65 ] || ! grep -q "4 open edges" "$tmp/err_open" || ! grep -q "/geometry/0/mesh" "$tmp/err_open"; then
  echo "FAIL: an open mesh: exit $rc"; cat "$tmp/err_open"; fail=1
else
  echo "open mesh refused: $(cat "$tmp/err_open")"
fi

# water falling inside a spherical shell of 3 layers (the mesh of an icosphere, radius 0.1 m =
# 8 dx): after 2 s no fluid particle is lost or beyond the sphere's surface
cat >"$tmp/shell.json" <<'JSON'
{"name": "shell", "method": "wcsph", "dim": 3, "dx": 0.0125,
 "domain": {"min": [-0.15, -0.15, -0.15], "max": [0.15, 0.15, 0.15]},
 "geometry": [{"mesh": "m/sphere.stl", "role": "wall", "layers": 3},
              {"sphere": {"center": [0, 0, 0], "radius": 0.0625}, "role": "fluid"},
              {"box": {"min": [-0.1, -0.1, -0.1], "max": [0.1, 0.1, 0.0]}, "role": "void"}],
 "physics": {"gravity": [0, 0, -9.81], "eos": {"type": "linear", "c0": 15},
             "viscosity": {"type": "artificial", "alpha": 0.1}, "delta_sph": 0.1},
 "time": {"end": 2.0, "cfl": 0.2}, "output": {"every": 2.0},
 "diagnostics": {"every": 1000, "probes": []}}
JSON
"$sphd" --run "$tmp/shell.json" --out "$tmp/shell" >"$tmp/ev_shell" 2>"$tmp/err_shell"
rc=$?
[ $rc = 0 ] || { echo "FAIL: the shell case: exit $rc"; cat "$tmp/err_shell"; fail=1; }
$py - "$tmp/ev_shell" "$tmp/shell" <<'PY' || fail=1
import glob, json, sys
import h5py, numpy as np
ev = [json.loads(l) for l in open(sys.argv[1])]
d = [e for e in ev if e["type"] == "diag"]
assert ev[-1]["type"] == "state" and ev[-1]["state"] == "done", ev[-1]
last = sorted(glob.glob(sys.argv[2] + "/snap_*.h5"))[-1]
f = h5py.File(last)
p, t = f["pos"][:], f["type"][:]
r = np.linalg.norm(p[t == 0], axis=1)
rw = np.linalg.norm(p[t == 1], axis=1)
print("shell: t = %.2f s, %d fluid particles, lost %d, the farthest %.4f m from the centre; the "
      "shell's %d particles from %.4f to %.4f m" % (d[-1]["t"], len(r), d[-1]["lost"], r.max(),
                                                   len(rw), rw.min(), rw.max()))
assert abs(d[-1]["t"] - 2.0) < 1e-9 and d[-1]["lost"] == 0 and r.max() < rw.min(), "fluid got out"
assert rw.min() < 0.1 - 2.5 * 0.0125 and rw.max() < 0.1, "not a 3-layer shell inside the surface"
PY
[ $fail = 0 ] && echo "run_geometry: all passed"
exit $fail
