#!/usr/bin/python3
"""The 2D solver bit for bit (issue 23: the core made dimension-generic must leave 2D exactly as
it was). Runs a few short 2D cases with `sphd --run` and compares, bit for bit, what they give
with the files made before the change (tests/regress/golden/NAME.json):

- the diag series of diag.h5 (every column, every row), stored as exact decimal floats;
- the last snapshot's particles at the end time, every field (Points and each PointData array of
  the VTKHDF file: positions, velocities, density, pressure, type, id, mass), stored as SHA-256 of
  their bytes;
- result.json (without its wall time).
The checkpoint file is not compared as a file: its header embeds the configuration's struct,
which the change reshapes (its format version goes up); the particle state it holds at the end is
the snapshot's, and anything else it carries (the integrator's scalars, bodies) shows in the diag
series and the result.

A failure names the first diag row and column that differ, or the array whose bytes differ.
The files were made with this project's default build (gcc, x86-64 without -march, so without
FMA contraction: OpenMP thread counts do not change a bit, tests/integration/crash_resume.sh);
another compiler may differ in the last bits: make the files anew with it (--make) on the
commit before a change, then compare on the change.

Usage: golden.py SPHD SOURCE_DIR [--make] [--only NAME]
"""
import hashlib
import json
import os
import subprocess
import sys
import tempfile

import h5py
import numpy as np

# name: (case, sets). Short runs (about a second each), each system of the 2D core once: WCSPH
# with dynamic and with ghost walls, a rigid body, Monaghan's viscosity on an initial wave, MPS,
# the laminar viscosity with SPS turbulence.
CASES = {
    "dambreak": ("cases/dambreak.json", ["dx=0.005", "time.end=0.1", "output.every=0.05"]),
    "dambreak_ghost": ("cases/dambreak_ghost.json",
                       ["dx=0.005", "time.end=0.1", "output.every=0.05"]),
    "water_entry": ("cases/water_entry.json", ["dx=0.01", "time.end=0.03", "output.every=0.01"]),
    "standing_wave": ("cases/standing_wave.json", ["dx=0.02", "time.end=0.2",
                                                   "output.every=0.1"]),
    "mps_dambreak": ("cases/mps_dambreak.json", ["time.end=0.05", "output.every=0.025"]),
    # the laminar viscosity with SPS turbulence and dynamic walls' viscosity factor 1
    "dambreak_sps": ("cases/dambreak.json", ["dx=0.005", "time.end=0.1", "output.every=0.05",
                                             'physics.viscosity={"type": "laminar", "nu": 1e-6}',
                                             "physics.turbulence=sps",
                                             "boundary.viscosity_factor=1"]),
}
HERE = os.path.dirname(os.path.abspath(__file__))
# every per-particle field a snapshot can hold
FIELDS = 'output.fields=["pos", "vel", "rho", "p", "type", "id", "mass"]'


def sha(b):
    return hashlib.sha256(b).hexdigest()


def run(sphd, src, name):
    case, sets = CASES[name]
    with tempfile.TemporaryDirectory() as d:
        out = os.path.join(d, name)
        cmd = [sphd, "--run", os.path.join(src, case), "--out", out, "--threads", "1"]
        for s in sets + [FIELDS]:
            cmd += ["--set", s]
        p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        if p.returncode != 0:
            sys.exit("golden: %s: sphd exited %d: %s" % (name, p.returncode, p.stderr[-500:]))
        with h5py.File(os.path.join(out, "diag.h5"), "r") as f:
            rows = int(f["rows"][0])
            table = f["diag"][:rows]
        diag = {c: [v.item() for v in table[c]] for c in table.dtype.names}
        snaps = sorted(x for x in os.listdir(out) if x.startswith("snap_") and x.endswith(".h5"))
        arrays = {}
        with h5py.File(os.path.join(out, snaps[-1]), "r") as f:
            g = f["VTKHDF"]
            arrays["Points"] = sha(np.ascontiguousarray(g["Points"][()]).tobytes())
            for k in sorted(g["PointData"]):
                arrays[k] = sha(np.ascontiguousarray(g["PointData"][k][()]).tobytes())
        with open(os.path.join(out, "result.json")) as f:
            result = json.load(f)
        result.pop("wall_time", None)
        return {"case": case, "sets": sets, "snapshot": snaps[-1], "diag": diag,
                "arrays": arrays, "result": result}


def first_difference(want, got):
    if set(want["diag"]) != set(got["diag"]):
        return "diag columns %s, want %s" % (sorted(got["diag"]), sorted(want["diag"]))
    n_w, n_g = len(want["diag"]["step"]), len(got["diag"]["step"])
    for r in range(min(n_w, n_g)):
        for c in want["diag"]:
            a, b = want["diag"][c][r], got["diag"][c][r]
            if not (a == b or (a != a and b != b)):  # NaN (a dry probe) equals NaN here
                return "diag row %d (step %s), column %s: %r, want %r" % (
                    r, got["diag"]["step"][r], c, b, a)
    if n_w != n_g:
        return "diag has %d rows, want %d" % (n_g, n_w)
    if want["snapshot"] != got["snapshot"]:
        return "last snapshot %s, want %s" % (got["snapshot"], want["snapshot"])
    for k in want["arrays"]:
        if got["arrays"].get(k) != want["arrays"][k]:
            return "snapshot array %s differs (bytes)" % k
    if set(got["arrays"]) != set(want["arrays"]):
        return "snapshot arrays %s, want %s" % (sorted(got["arrays"]), sorted(want["arrays"]))
    if got["result"] != want["result"]:
        keys = sorted(k for k in set(want["result"]) | set(got["result"])
                      if want["result"].get(k) != got["result"].get(k))
        return "result.json differs in %s" % ", ".join(keys)
    return None


def main():
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    if len(args) < 2:
        sys.exit(__doc__)
    sphd, src = args[0], args[1]
    make = "--make" in sys.argv
    names = list(CASES)
    if "--only" in sys.argv:
        names = [sys.argv[sys.argv.index("--only") + 1]]
    os.makedirs(os.path.join(HERE, "golden"), exist_ok=True)
    failed = 0
    for name in names:
        got = run(sphd, src, name)
        path = os.path.join(HERE, "golden", name + ".json")
        if make:
            with open(path, "w") as f:
                json.dump(got, f, indent=0, sort_keys=True)
                f.write("\n")
            print("golden %s: made (%d diag rows, %s)" % (name, len(got["diag"]["step"]),
                                                         got["snapshot"]))
            continue
        with open(path) as f:
            want = json.load(f)
        if (want["case"], want["sets"]) != (got["case"], got["sets"]):
            print("FAIL golden %s: the stored file is of another run (make it anew)" % name)
            failed += 1
            continue
        diff = first_difference(want, got)
        print("%s golden %s: %s" % ("FAIL" if diff else "ok  ", name,
                                    diff or "bit for bit (%d diag rows, %d arrays of %s)" % (
                                        len(got["diag"]["step"]), len(got["arrays"]),
                                        got["snapshot"])))
        failed += diff is not None
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
