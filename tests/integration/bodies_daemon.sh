#!/usr/bin/env bash
# Rigid bodies through the daemon: a coarse water entry (cases/water_entry.json, one free
# cylinder) submitted without starting, stepped, watched, paused and resumed, then sphd killed
# with SIGKILL twice and started again on the same state dir: the job continues from its
# checkpoint (the body's state with it) and its snapshots and diagnostics are bitwise equal to
# those of an uninterrupted batch run (1 thread; a 2-thread batch run is bitwise the same too).
# Diag events and queries carry the body, queries name its particles "body", the result counts
# them.
# Usage: bodies_daemon.sh SPHD SPHCTL SOURCE_DIR [SEED]
SPHD=$1; SPHCTL=$2; SRC=$3; seed=${4:-$RANDOM}
. "$(dirname "$0")/lib.sh"
echo "seed $seed"; RANDOM=$seed
CASE="$SRC/cases/water_entry.json"
# long enough that the sleeps below, scaled by the batch run time, end well before the job does
# even when each sphctl call is slow (ASan, a loaded machine): the kills must find it running
sets=(--set dx=0.01 --set time.end=0.15 --set output.every=0.05 --set diagnostics.every=5)

# the uninterrupted reference in batch mode, timed, and with 2 threads (5,000 fluid particles:
# the parallel loops run), bitwise
batch_reference we "${sets[@]}"

start_sphd --threads 1
submit_step_pause we "water entry" "${sets[@]}"
expect_rc "query a paused job with bodies" 0 "$SPHCTL" --json query we --fields pos,type
check "the query names the body's particles" jtrue "$tmp/out" \
  'sum(1 for t in d["particles"]["fields"]["type"] if t=="body") > 0'
check "the query's diagnostics carry the body" jtrue "$tmp/out" \
  '"cylinder" in d["diag"]["bodies"] and d["diag"]["penetration"] == d["diag"]["bodies"]["cylinder"]["penetration"]'
run_pause_kill we
check "diag events carry bodies.cylinder" "$PY" -c '
import json, sys
ev = [json.loads(l) for l in open(sys.argv[1])]
diags = [e for e in ev if e.get("type") == "diag"]
sys.exit(0 if diags and all("cylinder" in e.get("bodies", {}) for e in diags) else 1)' "$tmp/out"
check "diag.h5 keeps the body's series, equal to the diag events" "$PY" -c '
import json, sys, h5py, math
ev = [json.loads(l) for l in open(sys.argv[1])]
diags = {e["step"]: e for e in ev if e.get("type") == "diag"}
with h5py.File(sys.argv[2], "r", libver="latest", swmr=True) as f:
    n = int(f["rows"][0]); tab = f["diag"][:n]
    cols = f.attrs["columns"]
    cols = cols.decode() if isinstance(cols, bytes) else cols
    units = dict(zip(tab.dtype.names, [u.decode() for u in f["diag"].attrs["units"]]))
names = ("x", "y", "vx", "vy", "angle", "omega", "fx", "fy", "torque", "penetration")
ok = all("cylinder." + m in tab.dtype.names and "cylinder." + m in cols.split(",") for m in names)
ok = ok and units["cylinder.fy"] == "N/m" and units["cylinder.penetration"] == "m"
seen = 0
for row in tab:
    e = diags.get(int(row["step"]))
    if not e:
        continue
    b = e["bodies"]["cylinder"]
    want = b["x"] + b["v"] + [b["angle"], b["omega"]] + b["force"] + [b["torque"], b["penetration"]]
    got = [float(row["cylinder." + m]) for m in names]
    ok = ok and all(abs(g - w) <= 1e-9 * max(abs(w), 1e-12) for g, w in zip(got, want))
    ok = ok and abs(float(row["penetration"]) - e["penetration"]) <= 1e-9 * abs(e["penetration"]) + 1e-15
    seen += 1
print("rows compared with events:", seen, "of", n)
sys.exit(0 if ok and seen >= 3 else 1)' "$tmp/out" "$STATE/jobs/we/diag.h5"
check "snapshots mark the body's particles 4 and their units say so" "$PY" -c '
import sys, h5py
with h5py.File(sys.argv[1], "r") as f:
    t = f["type"][:]
    u = f["type"].attrs["units"]
    u = u.decode() if isinstance(u, bytes) else u
    nb = int(f.attrs["n_body"])
print("type units:", u, "body particles:", int((t == 4).sum()), "of", nb)
sys.exit(0 if "4 body" in u and (t == 4).sum() == nb > 0 else 1)' "$STATE/jobs/we/snap_000000.h5"
check "the log says it resumed from a checkpoint" grep -q "resumed from" "$tmp/sphd.log"
expect_rc "query the finished job" 0 "$SPHCTL" --json query we
check "the result counts the body's particles" jtrue "$tmp/out" \
  'd["result"]["particles"]["body"] > 0'
# (the JSON numbers are printed to 10 digits in batch mode, 12 by the daemon)
check "the result's body equals the reference run's" "$PY" -c '
import json, sys
def close(a, b):
    if isinstance(a, dict):
        return a.keys() == b.keys() and all(close(a[k], b[k]) for k in a)
    if isinstance(a, list):
        return len(a) == len(b) and all(close(x, y) for x, y in zip(a, b))
    return abs(a - b) <= 1e-9 * max(abs(a), abs(b)) + 1e-300
ref = [json.loads(l) for l in open(sys.argv[1])]
r = [e for e in ref if e.get("type") == "result"][0]
d = json.load(open(sys.argv[2]))["result"]
sys.exit(0 if close(r["diag"]["bodies"], d["diag"]["bodies"]) and r["steps"] == d["steps"] else 1)' \
  "$tmp/ref.jsonl" "$tmp/out"
check "snapshots and diagnostics bitwise equal to the uninterrupted run" \
  "$PY" "$(dirname "$0")/h5check.py" same "$tmp/ref/we" "$STATE/jobs/we"
stop_sphd
echo "kills: $kills"
finish
