#!/usr/bin/env bash
# The load test: a real sphd (2 threads) running 2 jobs, 32 clients sending status queries
# (bench_load): quiet phases alternate with loaded ones (each client at 10/s, at 100/s, and in a
# closed loop, by default). Prints requests/s, p50/p90/p99 latency, how much the jobs slowed,
# and where the CPU went (solver threads, sphd's loop and ZeroMQ threads, the load generator).
# The jobs are hydrostatic tanks, whose cost per step is steady: what changes between phases is
# the load, and the machine's own drift, which the short alternating phases average out.
# The load generator runs on the CPU that sphd keeps for its request threads (--cpu auto).
# Usage: bench/load.sh [BUILD_DIR] [bench_load options]   (build first: scripts/build.sh)
#   e.g. bench/load.sh build --rates 100 --seconds 20
#   SPHD_OPTS="--request-cpu any" bench/load.sh build --cpu any     (nothing pinned)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
shift || true
run=$(mktemp -d)
export SPHD_ENDPOINT="ipc://$run/control"
"$build/bin/sphd" --listen "$SPHD_ENDPOINT" --publish "ipc://$run/stream" --state-dir "$run/state" \
  --threads 2 ${SPHD_OPTS:-} 2>"$run/sphd.log" &
pid=$!
trap 'kill -TERM $pid 2>/dev/null; wait $pid 2>/dev/null; rm -rf "$run"' EXIT
for _ in $(seq 1 100); do "$build/bin/sphctl" --timeout 1 ping >/dev/null 2>&1 && break; sleep 0.05; done
# long enough to run through the whole measurement
for j in load1 load2; do
  "$build/bin/sphctl" submit cases/hydrostatic.json --id "$j" --set time.end=100000 >/dev/null
done
sleep 1
"$build/bin/sphctl" list
echo "machine: $(nproc) CPUs, load average $(cut -d" " -f1-3 /proc/loadavg) (the clients share the CPUs with sphd)"
"$build/bin/bench_load" --endpoint "$SPHD_ENDPOINT" --cpu auto "$@" load1 load2
