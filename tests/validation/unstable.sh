#!/usr/bin/env bash
# A deliberately unstable case (the dam break with a fixed dt 20 times the stable one) must fail
# cleanly: exit 1, a final `state` event `failed` whose reason names the step and the quantity.
# Usage: unstable.sh SPHD SOURCE_DIR
set -u
sphd=$1; src=$2
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
timeout 120 "$sphd" --run "$src/cases/dambreak.json" --out "$tmp/out" --set dx=0.005 --set time.dt=0.001 \
  >"$tmp/events.jsonl" 2>"$tmp/stderr"
rc=$?
last=$(tail -n 1 "$tmp/events.jsonl")
echo "exit $rc; last event: $last"
[ "$rc" = 1 ] || { echo "FAIL: exit $rc, want 1"; cat "$tmp/stderr"; exit 1; }
echo "$last" | grep -q '"state":"failed"' || { echo "FAIL: the last event is not state failed"; exit 1; }
echo "$last" | grep -q '"reason":"unstable: .*step [0-9]' || { echo "FAIL: the reason names no step"; exit 1; }
echo "$last" | grep -Eq 'density|non-finite|left the domain|time step' || { echo "FAIL: the reason names no quantity"; exit 1; }
echo PASS
