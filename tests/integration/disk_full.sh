#!/usr/bin/env bash
# Disk full: a job whose directory sits on a 1 MiB tmpfs fails with a reason naming the full disk,
# sphd keeps answering, and another job (on the roomy disk) finishes. Needs mount (root); skipped
# (exit 77) where tmpfs cannot be mounted.
# Usage: disk_full.sh SPHD SPHCTL SOURCE_DIR
SPHD=$1; SPHCTL=$2; SRC=$3
. "$(dirname "$0")/lib.sh"
mnt="$STATE/jobs/full"
mkdir -p "$mnt"
if ! mount -t tmpfs -o size=1m tmpfs "$mnt" 2>/dev/null; then
  echo "disk_full.sh: cannot mount a tmpfs here; skipped"; exit 77
fi
trap 'umount "$mnt" 2>/dev/null; cleanup' EXIT
start_sphd --threads 2
expect_rc "submit a job that fills its disk" 0 "$SPHCTL" submit "$SRC/cases/dambreak.json" --id full \
  --set dx=0.005 --set output.every=0.01
expect_rc "submit another job" 0 "$SPHCTL" submit "$SRC/cases/dambreak.json" --id other \
  --set dx=0.005 --set time.end=0.2
expect_rc "watch the full one: it fails (exit 1)" 1 "$SPHCTL" --json watch full
expect_rc "its status" 0 "$SPHCTL" --json status full
check "failed, with a reason naming the full disk" jtrue "$tmp/out" \
  'd["state"]=="failed" and "io_error" in d["reason"] and "No space left" in d["reason"]'
expect_rc "sphd answers ping" 0 "$SPHCTL" ping
expect_rc "the other job finishes" 0 "$SPHCTL" --json watch other
check "done" jlast "$tmp/out" 'd.get("state")=="done" or d.get("status",{}).get("state")=="done"'
check "the full job's snapshots that were written are whole" "$PY" - "$mnt" <<'PYEOF'
import sys, os, h5py
d = sys.argv[1]
snaps = [f for f in os.listdir(d) if f.startswith("snap_") and f.endswith(".h5")]
assert snaps
for f in snaps:
    with h5py.File(os.path.join(d, f), "r") as h:
        h["pos"][:]
assert not [f for f in os.listdir(d) if ".tmp." in f], os.listdir(d)
PYEOF
stop_sphd
finish
