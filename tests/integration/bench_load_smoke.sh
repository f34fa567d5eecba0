#!/usr/bin/env bash
# bench/load.sh still runs end to end: sphd with 2 jobs, a short paced and closed-loop load, and
# the table it prints has its rows with every request answered. No figure is judged here: speed
# and latency are measured by running bench/load.sh by hand (README).
# Usage: bench_load_smoke.sh SOURCE_DIR BUILD_DIR
set -u
SRC=$1; BUILD=$2
out=$(mktemp)
trap 'rm -f "$out"' EXIT
if ! "$SRC/bench/load.sh" "$BUILD" --clients 4 --rates 10,0 --rounds 1 --seconds 0.5 \
  --quiet-seconds 0.3 >"$out" 2>&1; then
  echo "FAIL: bench/load.sh exited non-zero"; cat "$out"; exit 1
fi
fail=0
for row in "^quiet " "^10/s each " "^closed loop "; do
  grep -q "$row" "$out" || { echo "FAIL: no row '$row'"; fail=1; }
done
grep -q "failed requests" "$out" && { echo "FAIL: some requests failed"; fail=1; }
grep -q "NOT running" "$out" && { echo "FAIL: a job stopped running"; fail=1; }
awk '/^10\/s each|^closed loop/ { if ($3 + 0 <= 0) bad = 1 } END { exit bad }' "$out" ||
  { echo "FAIL: a loaded phase answered no requests"; fail=1; }
cat "$out"
[ "$fail" = 0 ] && echo "bench_load_smoke: ok"
exit "$fail"
