#!/usr/bin/env bash
# Crash test (daemon): a dam-break job submitted to sphd, sphd killed with SIGKILL at 5 moments
# (one of them in the middle of a checkpoint write) and started again on the same state dir each
# time: the job is never lost, it continues from its checkpoint and finishes, and its snapshots
# and diagnostics are bitwise equal to those of an uninterrupted run (1 thread). After each kill
# the latest files are whole.
# Usage: daemon_crash.sh SPHD SPHCTL SOURCE_DIR [SEED]
SPHD=$1; SPHCTL=$2; SRC=$3; seed=${4:-$RANDOM}
. "$(dirname "$0")/lib.sh"
echo "seed $seed"; RANDOM=$seed
sets=(--set time.end=0.3 --set output.every=0.03)

# the uninterrupted reference, in batch mode
"$SPHD" --run "$SRC/cases/dambreak.json" --threads 1 "${sets[@]}" --out "$tmp/ref/db" \
  >/dev/null 2>&1
t0=$(date +%s.%N)
"$SPHD" --run "$SRC/cases/dambreak.json" --threads 1 "${sets[@]}" --out "$tmp/timing/db" \
  >/dev/null 2>&1
runtime=$(awk -v a="$t0" -v b="$(date +%s.%N)" 'BEGIN { print b - a }')

whole() {
  "$PY" - "$STATE/jobs/db" <<'PYEOF'
import sys, os, h5py
import xml.etree.ElementTree as ET
d = sys.argv[1]
for f in sorted(os.listdir(d)):
    if f.startswith("snap_") and f.endswith(".h5"):
        with h5py.File(os.path.join(d, f), "r") as h:
            assert {"pos", "vel", "rho", "p", "type"} <= set(h.keys()), f
if os.path.exists(os.path.join(d, "particles.xmf")):
    ET.parse(os.path.join(d, "particles.xmf"))
if os.path.exists(os.path.join(d, "diag.h5")):
    with h5py.File(os.path.join(d, "diag.h5"), "r", libver="latest", swmr=True) as h:
        h["step"][:]
PYEOF
}

start_sphd --threads 1
expect_rc "submit the dam break" 0 "$SPHCTL" submit "$SRC/cases/dambreak.json" --id db "${sets[@]}"
kills=0
for i in 1 2 3 4 5; do
  if [ $i = 3 ]; then
    # restart with a slow checkpoint writer and kill it while it writes
    kill -KILL "$sphd_pid"; wait "$sphd_pid" 2>/dev/null; sphd_pid=
    kills=$((kills+1))
    SPHD_FAULT_CKPT_DELAY_MS=400 start_sphd --threads 1
    for _ in $(seq 1 600); do
      ls "$STATE/jobs/db" | grep -q '^checkpoint\.tmp\.' && break
      sleep 0.01
    done
    check "a checkpoint write was caught" sh -c "ls '$STATE/jobs/db' | grep -q '^checkpoint\.tmp\.'"
  else
    sleep "$(awk -v r="$runtime" -v p=$((5 + RANDOM % 15)) 'BEGIN { printf "%.3f", r * p / 100 }')"
  fi
  kill -KILL "$sphd_pid"; wait "$sphd_pid" 2>/dev/null; sphd_pid=
  kills=$((kills+1))
  check "latest files whole after kill $kills" whole
  check "the job's case is on disk" test -s "$STATE/jobs/db/case.json"
  start_sphd --threads 1
  expect_rc "the job is still known after restart $i" 0 "$SPHCTL" --json status db
  check "it is queued, running or done" jtrue "$tmp/out" 'd["state"] in ("queued", "running", "done")'
done
expect_rc "watch it to the end" 0 "$SPHCTL" --json watch db
check "it finished" jlast "$tmp/out" 'd.get("state")=="done" or d.get("status",{}).get("state")=="done"'
check "the log says it resumed from a checkpoint" grep -q "resumed from" "$tmp/sphd.log"
check "snapshots and diagnostics bitwise equal to the uninterrupted run" \
  "$PY" - "$tmp/ref/db" "$STATE/jobs/db" <<'PYEOF'
import sys, os, h5py, numpy as np
a, b = sys.argv[1], sys.argv[2]
import re
snap = re.compile(r"^snap_\d+\.h5$")
snaps = sorted(f for f in os.listdir(a) if snap.match(f))
got = sorted(f for f in os.listdir(b) if snap.match(f))
assert not [f for f in os.listdir(b) if ".tmp." in f], os.listdir(b)
assert snaps == got, (snaps, got)
for s in snaps:
    with h5py.File(os.path.join(a, s), "r") as x, h5py.File(os.path.join(b, s), "r") as y:
        assert x.attrs["step"] == y.attrs["step"] and x.attrs["time"] == y.attrs["time"], s
        for k in x:
            assert np.array_equal(x[k][:], y[k][:]), (s, k)
with h5py.File(os.path.join(a, "diag.h5"), "r", libver="latest", swmr=True) as x, \
     h5py.File(os.path.join(b, "diag.h5"), "r", libver="latest", swmr=True) as y:
    for k in x:
        assert np.array_equal(x[k][:], y[k][:]), k
PYEOF
stop_sphd
echo "kills: $kills"
finish
