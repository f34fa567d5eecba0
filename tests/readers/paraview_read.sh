#!/usr/bin/env bash
# Runs paraview_read.py under pvbatch (offscreen) on a job directory, with the particle counts
# taken from its first and last snapshot (h5py).
# Usage: paraview_read.sh SOURCE_DIR JOB_DIR
set -eu
src=$1; d=$2
command -v pvbatch >/dev/null || { echo "FAIL: pvbatch missing (Debian paraview, python3-paraview)"; exit 1; }
read -r n f0 f1 < <(/usr/bin/python3 - "$d" <<'PY'
import os, sys, h5py
d = sys.argv[1]
s = sorted(f for f in os.listdir(d) if f.startswith("snap_") and f.endswith(".h5"))
def fluid(name):
    with h5py.File(os.path.join(d, name), "r") as f:
        return int(f.attrs["n_particles"]), int((f["type"][:] == 0).sum())
(n, a), (_, b) = fluid(s[0]), fluid(s[-1])
print(n, a, b)
PY
)
exec pvbatch --force-offscreen-rendering "$src/tests/readers/paraview_read.py" "$d" "$n" "$f0" "$f1"
