#!/usr/bin/env bash
# Crash test (batch mode): a dam break killed with SIGKILL at 5 moments, one of them in the middle
# of a checkpoint write, and resumed each time with --resume, ends with snapshots and diagnostics
# bitwise equal to those of an uninterrupted run (1 thread). After every kill the latest files are
# whole: every snapshot opens with all its fields, the XDMF parses, the diagnostics file opens.
# Usage: crash_resume.sh SPHD SOURCE_DIR [SEED]
set -eu
sphd=$1; src=$2; seed=${3:-$RANDOM}
tmp=$(mktemp -d); pid=
trap '[ -n "$pid" ] && kill -9 $pid 2>/dev/null; rm -rf "$tmp"' EXIT
PY=/usr/bin/python3
args=(--run "$src/cases/dambreak.json" --threads 1 --set time.end=0.3 --set output.every=0.03)
echo "seed $seed"; RANDOM=$seed

"$sphd" "${args[@]}" --out "$tmp/ref/db" >/dev/null 2>&1
t0=$(date +%s.%N)
"$sphd" "${args[@]}" --out "$tmp/full/db" >/dev/null 2>&1   # a timing run
runtime=$(awk -v a="$t0" -v b="$(date +%s.%N)" 'BEGIN { print b - a }')

check_whole() {
  "$PY" - "$1" <<'PYEOF'
import sys, os, h5py
import xml.etree.ElementTree as ET
d = sys.argv[1]
for f in sorted(os.listdir(d)):
    if f.startswith("snap_") and f.endswith(".h5"):
        with h5py.File(os.path.join(d, f), "r") as h:
            assert {"pos", "vel", "rho", "p", "type"} <= set(h.keys()), f
            h["pos"][:]
if os.path.exists(os.path.join(d, "particles.xmf")):
    ET.parse(os.path.join(d, "particles.xmf"))
if os.path.exists(os.path.join(d, "diag.h5")):
    with h5py.File(os.path.join(d, "diag.h5"), "r", libver="latest", swmr=True) as h:
        h["step"][:]
PYEOF
}

kills=0
for i in 1 2 3 4 5; do
  if [ $i = 3 ]; then
    # in the middle of a checkpoint write: the writer pauses after the header
    SPHD_FAULT_CKPT_DELAY_MS=400 "$sphd" "${args[@]}" --out "$tmp/crash/db" --resume >/dev/null 2>&1 &
    pid=$!
    for _ in $(seq 1 600); do
      ls "$tmp/crash/db" 2>/dev/null | grep -q '^checkpoint\.tmp\.' && break
      sleep 0.01
    done
    ls "$tmp/crash/db" | grep -q '^checkpoint\.tmp\.' || { echo "FAIL: no checkpoint write seen"; exit 1; }
  else
    "$sphd" "${args[@]}" --out "$tmp/crash/db" --resume >/dev/null 2>&1 &
    pid=$!
    delay=$(awk -v r="$runtime" -v p=$((5 + RANDOM % 20)) 'BEGIN { printf "%.3f", r * p / 100 }')
    sleep "$delay"
  fi
  if kill -9 $pid 2>/dev/null; then kills=$((kills+1)); fi
  wait $pid 2>/dev/null || true
  pid=
  check_whole "$tmp/crash/db"
done
[ $kills -ge 4 ] || { echo "FAIL: only $kills kills landed before the run ended"; exit 1; }
"$sphd" "${args[@]}" --out "$tmp/crash/db" --resume > "$tmp/last.jsonl" 2>"$tmp/last.err"
tail -n1 "$tmp/last.jsonl" | grep -q '"state":"done"'
"$PY" - "$tmp/ref/db" "$tmp/crash/db" <<'PYEOF'
import sys, os, h5py, numpy as np
a, b = sys.argv[1], sys.argv[2]
import re
snap = re.compile(r"^snap_\d+\.h5$")
snaps = sorted(f for f in os.listdir(a) if snap.match(f))
assert snaps == sorted(f for f in os.listdir(b) if snap.match(f)), os.listdir(b)
assert not [f for f in os.listdir(b) if ".tmp." in f], os.listdir(b)
for s in snaps:
    with h5py.File(os.path.join(a, s), "r") as x, h5py.File(os.path.join(b, s), "r") as y:
        assert x.attrs["step"] == y.attrs["step"] and x.attrs["time"] == y.attrs["time"], s
        for k in x:
            assert np.array_equal(x[k][:], y[k][:]), (s, k)
with h5py.File(os.path.join(a, "diag.h5"), "r", libver="latest", swmr=True) as x, \
     h5py.File(os.path.join(b, "diag.h5"), "r", libver="latest", swmr=True) as y:
    for k in x:
        assert np.array_equal(x[k][:], y[k][:]), k
print("%d snapshots and the diagnostics series bitwise equal to the uninterrupted run" % len(snaps))
PYEOF
echo "crash and resume: $kills kills; 1 passed, 0 failed"
