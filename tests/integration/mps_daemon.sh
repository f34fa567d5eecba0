#!/usr/bin/env bash
# The MPS method through the daemon (issue 12): a coarse MPS dam break (cases/mps_dambreak.json
# at dx = 5 mm, 1,700 fluid particles) submitted without starting, stepped, queried, paused and
# resumed, then sphd killed with SIGKILL twice and started again on the same state dir: the job
# continues from its checkpoint (the pressure that warm-starts the solve with it) and its
# snapshots and diagnostics are bitwise equal to those of an uninterrupted batch run (1 thread;
# a 2-thread batch run is bitwise the same too). Diag events carry the pressure solve
# (cg_iterations, cg_residual, free_surface). A solve that cannot converge within
# mps.max_iterations fails its job with `unstable` and a reason, and the daemon goes on.
# Usage: mps_daemon.sh SPHD SPHCTL SOURCE_DIR [SEED]
SPHD=$1; SPHCTL=$2; SRC=$3; seed=${4:-$RANDOM}
. "$(dirname "$0")/lib.sh"
echo "seed $seed"; RANDOM=$seed
CASE="$SRC/cases/mps_dambreak.json"
# long enough that the sleeps below, scaled by the batch run time, end well before the job does
sets=(--set dx=0.005 --set time.end=0.3 --set output.every=0.05 --set diagnostics.every=5)

# the uninterrupted reference in batch mode, timed, and with 2 threads, bitwise
batch_reference db "${sets[@]}"

start_sphd --threads 1
submit_step_pause db "MPS dam break" "${sets[@]}"
expect_rc "query a paused MPS job" 0 "$SPHCTL" --json query db --fields pos,p,type
check "the query has particles and the pressure solve" jtrue "$tmp/out" \
  'len(d["particles"]["fields"]["p"]) > 0 and d["diag"]["cg_iterations"] > 0 and d["diag"]["free_surface"] > 0 and d["diag"]["cg_residual"] < 1e-8'
run_pause_kill db
check "diag events carry the pressure solve" "$PY" -c '
import json, sys
ev = [json.loads(l) for l in open(sys.argv[1])]
diags = [e for e in ev if e.get("type") == "diag" and e["step"] > 0]
sys.exit(0 if diags and all(e["cg_iterations"] > 0 and e["cg_residual"] <= 1e-8 and
                            e["free_surface"] > 0 for e in diags) else 1)' "$tmp/out"
check "the log says it resumed from a checkpoint" grep -q "resumed from" "$tmp/sphd.log"
expect_rc "query the finished job" 0 "$SPHCTL" --json query db
check "the result is the reference run's" "$PY" -c '
import json, sys
ref = [json.loads(l) for l in open(sys.argv[1])]
r = [e for e in ref if e.get("type") == "result"][0]
d = json.load(open(sys.argv[2]))["result"]
ok = r["method"] == d["method"] == "mps" and r["steps"] == d["steps"]
ok = ok and abs(r["diag"]["front_x"] - d["diag"]["front_x"]) <= 1e-9 * r["diag"]["front_x"]
sys.exit(0 if ok else 1)' "$tmp/ref.jsonl" "$tmp/out"
check "snapshots and diagnostics bitwise equal to the uninterrupted run" \
  "$PY" "$(dirname "$0")/h5check.py" same "$tmp/ref/db" "$STATE/jobs/db"

# a pressure solve that cannot converge fails the job with a reason, not a hang
expect_rc "submit with 3 CG iterations allowed" 0 "$SPHCTL" submit "$CASE" --id cg \
  --set mps.max_iterations=3 --set mps.preconditioner=none
for _ in $(seq 1 500); do
  "$SPHCTL" --json status cg >"$tmp/st" 2>/dev/null
  jtrue "$tmp/st" 'd["state"] in ("failed", "done")' && break
  sleep 0.02
done
check "it failed as unstable, naming the solve" jtrue "$tmp/st" \
  'd["state"]=="failed" and "unstable" in d.get("reason", "") and "max_iterations" in d.get("reason", "")'
expect_rc "the daemon still answers" 0 "$SPHCTL" ping
stop_sphd
echo "kills: $kills"
finish
