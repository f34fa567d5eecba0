#!/usr/bin/env bash
# A 3D job's outputs opened with the field's tools (issue 23): SPHERIC Test 2 (cases/dambreak3d.json)
# at 12 particles over the depth, 0.05 s with three snapshots, then meshio (meshio_read.py) and
# ParaView (paraview_read.sh: the default XDMF reader, the legacy one, VTKHDF) read it with a cell
# per particle, meshio's points are the snapshots' positions, and those have three coordinates.
# Usage: job3d.sh SPHD SOURCE_DIR
set -eu
sphd=$1; src=$2
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
d=$tmp/dambreak3d
"$sphd" --run "$src/cases/dambreak3d.json" --out "$d" --threads 1 --set dx=0.0458333333 \
  --set time.end=0.05 --set output.every=0.025 >/dev/null 2>"$tmp/err" ||
  { echo "FAIL: sphd --run exited $?"; cat "$tmp/err"; exit 1; }
/usr/bin/python3 "$src/tests/readers/meshio_read.py" "$d"
"$src/tests/readers/paraview_read.sh" "$src" "$d"
/usr/bin/python3 - "$d" <<'PY'
import os, sys
import h5py
import numpy as np
with h5py.File(os.path.join(sys.argv[1], "snap_000000.h5"), "r") as f:
    assert f.attrs["dim"] == 3, f.attrs["dim"]
    z = f["pos"][:, 2]
assert np.ptp(z) > 0.5, np.ptp(z)
print("3D: z spans %.3f m (meshio's points are the snapshots' positions, every step)" % np.ptp(z))
PY
echo "3D job read by meshio and ParaView: passed"
