#!/usr/bin/env bash
# A dam-break job's result files as h5py and ParaView readers see them: snapshot count, fields,
# shapes, times and header attributes; every dataset the XDMF names exists with the shape it
# declares; each snapshot's RPDF (group rpdf) against an all-pairs count over its own fluid
# particles, and at t = 0 against the pairs of the 10 x 20 lattice the column starts on; no RPDF
# group once every fluid particle is lost; and the diagnostics series read (SWMR) while the job
# is still running.
# Usage: outputs_h5py.sh SPHD SOURCE_DIR
set -eu
sphd=$1; src=$2
tmp=$(mktemp -d); pid=
# (sphd --run stops on SIGTERM after a checkpoint: wait for it before removing its directory)
trap '[ -n "$pid" ] && kill $pid 2>/dev/null && wait $pid 2>/dev/null; rm -rf "$tmp"' EXIT
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

def check_rpdf(name, f, at_rest):
    """The group rpdf: 40 bins of q = r/h below 2, the pair counts an all-pairs loop over the
    file's fluid particles gives, the density those counts give (neighbours in each bin's ring
    over a uniform fluid's at the spacing dx); at rest (t = 0) the counts of the lattice."""
    g = f["rpdf"]
    assert g.attrs["bins"] == 40 and g.attrs["qmax"] == 2.0 and g.attrs["description"], name
    q, count, dens = g["q"][:], g["count"][:], g["density"][:]
    for k in ("q", "count", "density"):
        assert g[k].shape == (40,) and g[k].dtype == np.float64, (name, k, g[k].shape)
        assert g[k].attrs["units"] in (b"1", "1"), (name, k)
    assert 0 < q[0] and q[-1] < 2 and np.all(np.diff(q) > 0), (name, q)
    assert np.allclose(q, (np.arange(40) + 0.5) * 0.05, rtol=0, atol=1e-15), (name, q)
    h, dx = f.attrs["h"], f.attrs["dx"]
    typ = f["type"][:]
    p = f["pos"][:][typ == 0][:, :2]
    nf = len(p)
    # all pairs i < j, r^2 summed as the core sums it (x then y), binned by floor(r / (h q/40))
    i, j = np.triu_indices(nf, 1)
    e0, e1 = p[i, 0] - p[j, 0], p[i, 1] - p[j, 1]
    r2 = e0 * e0 + e1 * e1
    near = r2 < (2.0 * h) ** 2
    b = np.minimum((np.sqrt(r2[near]) * (1.0 / (0.05 * h))).astype(int), 39)
    want = np.bincount(b, minlength=40)
    assert np.array_equal(count, want), (name, count, want)
    r0, r1 = np.arange(40) * 0.05 * h, np.arange(1, 41) * 0.05 * h
    assert np.allclose(dens, 2 * count / (nf / dx ** 2 * np.pi * (r1 ** 2 - r0 ** 2)),
                       rtol=1e-12, atol=0), name
    if at_rest:
        # the column at rest on its lattice, nx x ny: (nx - a)(ny - b) pairs at offset (a, b)
        nx, ny = round(0.1 / dx), round(0.2 / dx)
        assert nf == nx * ny, nf
        lattice = np.zeros(40)
        for a in range(0, 3):
            for c in range(-2, 3):
                if (a, c) > (0, 0) and a * a + c * c < 8:  # r < 2h = 2.83 dx
                    k = int(np.hypot(a, c) * dx / (0.05 * h))
                    lattice[k] += (nx - a) * (ny - abs(c))
        assert np.array_equal(count, lattice), (name, count, lattice)
        # over q in [1, 2) (shells at sqrt(2), 2 and sqrt(5) dx) the density is the lattice's
        # 16 neighbours in an area of 6 pi dx^2 (0.85, not 1: a lattice, not a uniform
        # continuum), less what the column's free surface and walls take away (0.70 here)
        ring = (q > 1) & (q < 2)
        area = np.pi * (r1[ring] ** 2 - r0[ring] ** 2)
        mean = (dens[ring] * area).sum() / area.sum()
        assert 0.6 < mean < 16 / (6 * np.pi), mean


n0 = None
for i, (name, ev) in enumerate(zip(snaps, outs)):
    with h5py.File(os.path.join(d, name), "r") as f:
        t = f.attrs["time"]
        assert abs(t - 0.05 * i) < 1e-12 and abs(t - ev["t"]) < 1e-9 and f.attrs["step"] == ev["step"], (name, t)
        n = f.attrs["n_particles"]; n0 = n0 or n
        assert n == n0 == f.attrs["n_fluid"] + f.attrs["n_boundary"]
        assert f.attrs["dim"] == 2 and f.attrs["dx"] == 0.01 and f.attrs["kernel"] in (b"wendland_c2", "wendland_c2")
        assert set(f.keys()) == {"pos", "vel", "rho", "p", "type", "id", "VTKHDF", "rpdf"}, list(f.keys())
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
        check_rpdf(name, f, at_rest=(i == 0))
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
print("finished job: %d snapshots (their RPDF too), %d XDMF datasets checked" % (len(snaps), checked))
PYEOF

# 1b. four fluid particles falling out of an open domain: no RPDF group once they are all lost
"$sphd" --run "$src/cases/dambreak.json" --out "$tmp/drop/db" --set dx=0.01 \
  --set 'boundary={"type": "none"}' --set 'fluid=[{"box": {"min": [0.5, 0.02], "max": [0.52, 0.04]}}]' \
  --set time.end=0.15 >/dev/null 2>&1
"$PY" - "$tmp/drop/db" <<'PYEOF'
import sys, os, h5py, numpy as np
import xml.etree.ElementTree as ET
d = sys.argv[1]
snaps = sorted(f for f in os.listdir(d) if f.startswith("snap_") and f.endswith(".h5"))
assert len(snaps) == 4, snaps
has = []
for name in snaps:
    with h5py.File(os.path.join(d, name), "r") as f:
        lost = int((f["type"][:] == 2).sum())
        has.append(("rpdf" in f, lost))
        if "rpdf" in f:  # 6 pairs at most
            assert 0 < f["rpdf/count"][:].sum() <= 6, (name, f["rpdf/count"][:])
assert has == [(True, 0), (True, 0), (False, 4), (False, 4)], has
assert len(ET.parse(os.path.join(d, "particles.xmf")).getroot().findall(".//Grid[@GridType='Uniform']")) == 4
print("all fluid lost: no RPDF group", has)
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
kill $pid 2>/dev/null && wait $pid 2>/dev/null || true
pid=
echo "outputs via h5py: 3 passed, 0 failed"
