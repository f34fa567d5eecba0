#!/usr/bin/env bash
# Crash test (daemon): a dam-break job submitted to sphd, sphd killed with SIGKILL at 5 moments
# (one of them in the middle of a checkpoint write) and started again on the same state dir each
# time: the job is never lost, it continues from its checkpoint and finishes (its events' seq
# following the last one published before each kill), and its snapshots
# and diagnostics are bitwise equal to those of an uninterrupted run (1 thread). After each kill
# the latest files are whole.
# Usage: daemon_crash.sh SPHD SPHCTL SOURCE_DIR [SEED]
SPHD=$1; SPHCTL=$2; SRC=$3; seed=${4:-$RANDOM}
. "$(dirname "$0")/lib.sh"
echo "seed $seed"; RANDOM=$seed
sets=(--set dx=0.005 --set time.end=0.3 --set output.every=0.03)

# the uninterrupted reference, in batch mode
"$SPHD" --run "$SRC/cases/dambreak.json" --threads 1 "${sets[@]}" --out "$tmp/ref/db" \
  >/dev/null 2>&1
t0=$(date +%s.%N)
"$SPHD" --run "$SRC/cases/dambreak.json" --threads 1 "${sets[@]}" --out "$tmp/timing/db" \
  >/dev/null 2>&1
runtime=$(awk -v a="$t0" -v b="$(date +%s.%N)" 'BEGIN { print b - a }')

whole() { "$PY" "$(dirname "$0")/h5check.py" whole "$STATE/jobs/db"; }

# the seqs in a journal from line N on, in order (a torn line skipped)
seqs='import json, sys
for line in open(sys.argv[1]).readlines()[int(sys.argv[2]):]:
    try:
        print(json.loads(line)["seq"])
    except (ValueError, KeyError):
        pass'
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
  # every published seq is journaled first: the largest, and where the restart's records begin
  jn="$STATE/jobs/db/journal.jsonl"
  jlines=$(wc -l <"$jn")
  jmax=$("$PY" -c "$seqs" "$jn" 0 | tail -1)
  start_sphd --threads 1
  expect_rc "the job is still known after restart $i" 0 "$SPHCTL" --json status db
  next=$("$PY" -c "$seqs" "$jn" "$jlines" | head -1)
  if [ -n "$next" ] || ! jtrue "$tmp/out" 'd["state"] == "done"'; then
    check "after restart $i the next seq follows the last published (no gap, no repeat)" \
      test "$next" = $((jmax + 1))
  fi # (else it was done before the kill: a finished job publishes nothing when taken up)
  check "it is queued, running or done" jtrue "$tmp/out" 'd["state"] in ("queued", "running", "done")'
done
expect_rc "watch it to the end" 0 "$SPHCTL" --json watch db
check "it finished" jlast "$tmp/out" 'd.get("state")=="done" or d.get("status",{}).get("state")=="done"'
check "the log says it resumed from a checkpoint" grep -q "resumed from" "$tmp/sphd.log"
check "snapshots and diagnostics bitwise equal to the uninterrupted run" \
  "$PY" "$(dirname "$0")/h5check.py" same "$tmp/ref/db" "$STATE/jobs/db"

# a checkpoint this sphd cannot read (another version's state, or damaged): the job starts
# afresh and the unreadable files are kept as checkpoint.unreadable, not overwritten
expect_rc "submit a second dam break" 0 "$SPHCTL" submit "$SRC/cases/dambreak.json" --id db2 \
  "${sets[@]}"
for _ in $(seq 1 3000); do
  [ -s "$STATE/jobs/db2/checkpoint" ] && break
  sleep 0.01
done
kill -KILL "$sphd_pid"; wait "$sphd_pid" 2>/dev/null; sphd_pid=
check "the second job wrote a checkpoint" test -s "$STATE/jobs/db2/checkpoint"
for f in checkpoint checkpoint.prev; do
  [ -e "$STATE/jobs/db2/$f" ] && echo "not a checkpoint" >"$STATE/jobs/db2/$f"
done
start_sphd --threads 1
expect_rc "watch the second job to the end" 0 "$SPHCTL" --json watch db2
check "it finished" jlast "$tmp/out" 'd.get("state")=="done" or d.get("status",{}).get("state")=="done"'
check "the log says the unreadable checkpoint is kept" \
  grep -q "starting afresh (the checkpoint that could not be read is kept as checkpoint.unreadable)" \
  "$tmp/sphd.log"
check "the unreadable checkpoint is kept as it was" \
  grep -qx "not a checkpoint" "$STATE/jobs/db2/checkpoint.unreadable"
stop_sphd
echo "kills: $kills"
finish
