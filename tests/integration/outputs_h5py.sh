#!/usr/bin/env bash
# A dam-break job's result files as h5py and ParaView readers see them: snapshot count, fields,
# shapes, times and header attributes; every dataset the XDMF names exists with the shape it
# declares; and the diagnostics series read (SWMR) while the job is still running.
# Usage: outputs_h5py.sh SPHD SOURCE_DIR
set -eu
sphd=$1; src=$2
tmp=$(mktemp -d); pid=
trap '[ -n "$pid" ] && kill $pid 2>/dev/null || true; rm -rf "$tmp"' EXIT
PY=/usr/bin/python3

# 1. a finished job (coarse, quick)
"$sphd" --run "$src/cases/dambreak.json" --out "$tmp/done/db" --set dx=0.01 --set time.end=0.3 \
  > "$tmp/events.jsonl" 2>/dev/null
"$PY" - "$tmp/done/db" "$tmp/events.jsonl" <<'PYEOF'
import sys, os, json, h5py, numpy as np
import xml.etree.ElementTree as ET
d, evfile = sys.argv[1], sys.argv[2]
events = [json.loads(l) for l in open(evfile)]
outs = [e for e in events if e["type"] == "output"]
assert len(outs) == 7, [o["t"] for o in outs]          # t = 0, 0.05, ..., 0.3
snaps = sorted(f for f in os.listdir(d) if f.startswith("snap_") and f.endswith(".h5"))
assert snaps == [o["file"] for o in outs], (snaps, outs)
assert not [f for f in os.listdir(d) if ".tmp." in f], os.listdir(d)
n0 = None
for i, (name, ev) in enumerate(zip(snaps, outs)):
    with h5py.File(os.path.join(d, name), "r") as f:
        t = f.attrs["time"]
        assert abs(t - 0.05 * i) < 1e-12 and abs(t - ev["t"]) < 1e-9 and f.attrs["step"] == ev["step"], (name, t)
        n = f.attrs["n_particles"]; n0 = n0 or n
        assert n == n0 == f.attrs["n_fluid"] + f.attrs["n_boundary"]
        assert f.attrs["dim"] == 2 and f.attrs["dx"] == 0.01 and f.attrs["kernel"] in (b"wendland_c2", "wendland_c2")
        assert set(f.keys()) == {"pos", "vel", "rho", "p", "type", "id", "VTKHDF"}, list(f.keys())
        assert np.array_equal(f["id"][:], np.arange(f.attrs["n_particles"]))
        assert f.attrs["mass"] == 1000 * 0.01 ** 2 and abs(f.attrs["h"] - 1.414 * 0.01) < 1e-15
        assert f["VTKHDF/Points"].id == f["pos"].id      # a link, not a copy
        assert f["pos"].shape == (n, 3) and f["vel"].shape == (n, 3) and f["rho"].shape == (n,)
        pos, typ = f["pos"][:], f["type"][:]
        assert np.all(pos[:, 2] == 0) and np.all(np.isfinite(pos))
        assert (typ == 0).sum() == f.attrs["n_fluid"] and (typ == 1).sum() == f.attrs["n_boundary"]
        if i == 0:
            assert np.all(f["vel"][:] == 0)                 # the column starts at rest
        rho = f["rho"][:]
        assert 900 < rho.min() and rho.max() < 1100, (rho.min(), rho.max())
root = ET.parse(os.path.join(d, "particles.xmf")).getroot()
grids = root.findall(".//Grid[@GridType='Uniform']")
assert len(grids) == len(snaps)
checked = 0
for g, name in zip(grids, snaps):
    n = int(g.find("Topology").get("NumberOfElements"))
    for item in g.iter("DataItem"):
        fname, dset = item.text.strip().split(":")
        assert fname == name
        shape = tuple(int(x) for x in item.get("Dimensions").split())
        with h5py.File(os.path.join(d, fname), "r") as f:
            assert f[dset].shape == shape and shape[0] == n, (fname, dset)
            assert f[dset].dtype.itemsize == int(item.get("Precision"))
        checked += 1
with h5py.File(os.path.join(d, "diag.h5"), "r", libver="latest", swmr=True) as f:
    diags = [e for e in events if e["type"] == "diag"]
    assert list(f["step"][:]) == [e["step"] for e in diags]
    assert np.allclose(f["front_x"][:], [e["front_x"] for e in diags], rtol=1e-9)
    n = f["rows"][0]
    assert n == len(diags) and list(f["diag"]["step"]) == list(f["step"][:])
    assert f["diag"].dtype["lost"].kind == "i" and f["lost"].dtype.kind == "i"
    assert f["t"].attrs["units"] in (b"s", "s") and f["front_x"].attrs["units"] in (b"m", "m")
print("finished job: %d snapshots, %d XDMF datasets checked" % (len(snaps), checked))
PYEOF

# 2. the diagnostics series read while the job runs
"$sphd" --run "$src/cases/dambreak.json" --out "$tmp/run/db" --threads 1 --set dx=0.005 \
  >/dev/null 2>&1 &
pid=$!
"$PY" - "$tmp/run/db/diag.h5" "$pid" <<'PYEOF'
import sys, os, time, h5py
path, pid = sys.argv[1], int(sys.argv[2])
def alive():
    try:
        os.kill(pid, 0); return True
    except OSError:
        return False
t0 = time.time()
while not os.path.exists(path):
    assert time.time() - t0 < 60 and alive(), "no diagnostics file"
    time.sleep(0.02)
f = h5py.File(path, "r", libver="latest", swmr=True)
seen = []
while alive() and len(seen) < 5:
    f["step"].refresh(); f["t"].refresh()
    n = f["step"].shape[0]
    if n and (not seen or n > seen[-1]):
        seen.append(n)
        t = f["t"][n - 1]
        assert 0 <= t < 0.6
    time.sleep(0.05)
assert alive(), "the job finished before the reader saw the series grow: %s" % seen
assert len(seen) >= 3 and seen == sorted(seen), seen
f.close()
print("rows seen while the job ran:", seen)
PYEOF
kill $pid 2>/dev/null || true
echo "outputs via h5py: 2 passed, 0 failed"
