#!/usr/bin/env bash
# The README's main command: set up (scripts/setup.sh --main: only what sphd and sphctl need),
# build sphd and sphctl alone into build/ (the tests not configured: scripts/build.sh configures
# them again), start sphd in the background with its web dashboard on this machine (its address
# printed), submit the dam break and
# watch it to the end (a progress line on a terminal, JSON Lines otherwise), print where the
# results are, and stop the daemon. The daemon never outlives this script.
# MAIN_CASE=FILE runs another case the same way.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh --main
cmake -S . -B build -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSPH_BUILD_TESTS=OFF >/dev/null
cmake --build build -j"$(nproc)" --target sphd sphctl

case_file=${MAIN_CASE:-cases/dambreak.json}
job=$(basename "$case_file" .json)-$(date +%Y%m%d-%H%M%S)
state="$PWD/out/state"
run=$(mktemp -d "${TMPDIR:-/tmp}/sphd-main.XXXXXX")
export SPHD_ENDPOINT="ipc://$run/control"
# the dashboard on this machine only, on a free port (MAIN_HTTP=HOST:PORT to choose)
build/bin/sphd --listen "$SPHD_ENDPOINT" --publish "ipc://$run/stream" --state-dir "$state" \
  --http "${MAIN_HTTP:-127.0.0.1:0}" 2>"$run/sphd.log" &
pid=$!
cleanup() {
  if kill -0 "$pid" 2>/dev/null; then
    kill -TERM "$pid" 2>/dev/null || true
    wait "$pid" 2>/dev/null || true
  fi
  rm -rf "$run"
}
trap cleanup EXIT
for _ in $(seq 1 100); do
  build/bin/sphctl --timeout 1 ping >/dev/null 2>&1 && break
  kill -0 "$pid" 2>/dev/null || { cat "$run/sphd.log" >&2; exit 69; }
  sleep 0.05
done
echo "sphd is running (pid $pid, $SPHD_ENDPOINT); submitting $case_file as job $job" >&2
dash=$(grep -o 'dashboard on http://[^ ]*' "$run/sphd.log" | head -n1 | cut -d' ' -f3 || true)
[ -n "$dash" ] && echo "dashboard: $dash?job=$job (open it in a browser while the job runs)" >&2
rc=0
build/bin/sphctl submit "$case_file" --id "$job" --watch || rc=$?
build/bin/sphctl status "$job" >&2 || true
echo "results: $state/jobs/$job/" >&2
echo "  particles.xmf (open in ParaView: the run as a time series), snap_*.h5 (particle snapshots)," >&2
echo "  diag.h5 (diagnostics series), result.json (the summary), case.json (the case as run)" >&2
build/bin/sphctl shutdown >/dev/null
wait "$pid" || rc=$?
exit "$rc"
