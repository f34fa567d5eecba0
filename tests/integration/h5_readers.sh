#!/usr/bin/env bash
# The output files open in the readers users have: h5py reads the snapshots test_h5 writes (counts,
# fields, times, and every dataset the XDMF names exists with the shape it declares), and reads the
# diagnostics series while a writer is still appending to it (SWMR).
# Usage: h5_readers.sh TEST_H5 DIAG_WRITER
set -eu
test_h5=$1; writer=$2
tmp=$(mktemp -d); trap 'kill $wpid 2>/dev/null || true; rm -rf "$tmp"' EXIT
wpid=
SPH_TEST_OUT="$tmp/out" "$test_h5" >/dev/null
PY=/usr/bin/python3
"$PY" - "$tmp/out" <<'PYEOF'
import sys, os, h5py, numpy as np
import xml.etree.ElementTree as ET
d = sys.argv[1]
with h5py.File(os.path.join(d, "snap_000001.h5"), "r") as f:
    assert f.attrs["time"] == 0.25 and f.attrs["step"] == 1234 and f.attrs["n_particles"] == 1000
    assert f.attrs["n_fluid"] + f.attrs["n_boundary"] == 1000
    assert f["pos"].shape == (1000, 3) and f["vel"].shape == (1000, 3) and f["rho"].shape == (1000,)
    assert f["pos"].attrs["units"] == b"m" or f["pos"].attrs["units"] == "m"
    assert np.all(f["pos"][:, 2] == 0)
    assert f["type"].dtype == np.int8 and f["p"].dtype == np.float32
root = ET.parse(os.path.join(d, "particles.xmf")).getroot()
grids = root.findall(".//Grid[@GridType='Uniform']")
assert len(grids) == 3, len(grids)
times = [float(g.find("Time").get("Value")) for g in grids]
assert times == sorted(times) and abs(times[2] - 0.2) < 1e-12, times
checked = 0
for g in grids:
    n = int(g.find("Topology").get("NumberOfElements"))
    for item in g.iter("DataItem"):
        fname, dset = item.text.strip().split(":")
        shape = tuple(int(x) for x in item.get("Dimensions").split())
        with h5py.File(os.path.join(d, fname), "r") as f:
            assert f[dset].shape == shape, (fname, dset, f[dset].shape, shape)
            assert shape[0] == n
            assert f[dset].dtype.itemsize == int(item.get("Precision"))
        checked += 1
print("xdmf datasets checked:", checked)
PYEOF
"$writer" "$tmp/diag.h5" 150 20 &
wpid=$!
"$PY" - "$tmp/diag.h5" <<'PYEOF'
import sys, time, os, h5py
path = sys.argv[1]
t0 = time.time()
while not os.path.exists(path):
    time.sleep(0.01)
    assert time.time() - t0 < 10, "diagnostics file never appeared"
time.sleep(0.3)
f = h5py.File(path, "r", libver="latest", swmr=True)
seen = []
for _ in range(10):
    ds = f["step"]; ds.refresh()
    seen.append(ds.shape[0])
    time.sleep(0.1)
steps = f["step"][:]
assert list(steps) == list(range(len(steps))), steps
f["ekin"].refresh()
assert f["ekin"].shape[0] >= len(steps)
f.close()
assert seen[-1] > seen[0] > 0, seen
assert seen[-1] < 150, "the writer had finished: not a read during the run"
print("rows seen while the writer ran:", seen)
PYEOF
wait $wpid
echo "h5 readers: 2 passed, 0 failed"
