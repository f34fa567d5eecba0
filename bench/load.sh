#!/usr/bin/env bash
# The load test: a real sphd (2 threads) running 2 dam breaks, 32 clients sending status queries
# for 10 s (bench_load). Prints requests/s, p50/p99 latency and how much the jobs slowed.
# Usage: bench/load.sh [BUILD_DIR] [bench_load options]   (build first: scripts/build.sh)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}; shift || true
run=$(mktemp -d)
export SPHD_ENDPOINT="ipc://$run/control"
"$build/bin/sphd" --listen "$SPHD_ENDPOINT" --publish "ipc://$run/stream" --state-dir "$run/state" \
  --threads 2 2>"$run/sphd.log" &
pid=$!
trap 'kill -TERM $pid 2>/dev/null; wait $pid 2>/dev/null; rm -rf "$run"' EXIT
for _ in $(seq 1 100); do "$build/bin/sphctl" --timeout 1 ping >/dev/null 2>&1 && break; sleep 0.05; done
# long enough to run through the whole measurement (quiet, loaded, quiet)
for j in load1 load2; do
  "$build/bin/sphctl" submit cases/dambreak.json --id "$j" --set time.end=1000 >/dev/null
done
sleep 1
"$build/bin/sphctl" list
echo "machine: $(nproc) CPUs, load average $(cut -d" " -f1-3 /proc/loadavg) (the clients share the CPUs with sphd)"
"$build/bin/bench_load" --endpoint "$SPHD_ENDPOINT" "$@" load1 load2
# --rate R: each client paced at R requests/s (e.g. bench/load.sh build --rate 100)
# TODO(issue 4): print sphd's own CPU per request (its loop and ZeroMQ I/O threads, from
# /proc/PID/task/*/stat) apart from the clients', and run a steady job (hydrostatic) so that the
# quiet phases before and after agree.
