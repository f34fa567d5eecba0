#!/usr/bin/env bash
# sphctl watch reports a gap in seq when it could not keep up: a dam break publishing a diag event
# every step (--diag-rate 1000000, diagnostics.every 1) while `sphctl watch` is stopped (SIGSTOP)
# overflows the stream's buffers; once continued, watch must say which events it missed, both as
# a message and as a {"type": "gap"} line, and still end with the job's final state.
# Usage: watch_gap.sh SPHD SPHCTL SOURCE_DIR
SPHD=$1; SPHCTL=$2; SRC=$3
. "$(dirname "$0")/lib.sh"
[ -f "$SRC/cases/dambreak.json" ] || { echo "FAIL: cases/dambreak.json is missing"; exit 1; }
start_sphd --threads 1 --diag-rate 1000000
C=$SPHCTL
expect_rc "submit" 0 "$C" submit "$SRC/cases/dambreak.json" --id flood \
  --set dx=0.01 --set time.end=1000 --set diagnostics.every=1
"$C" --json watch flood >"$tmp/watch.jsonl" 2>"$tmp/watch.err" &
wpid=$!
sleep 0.5
seq0=$("$C" --json status flood | "$PY" -c 'import json,sys; print(json.load(sys.stdin)["seq"])')
kill -STOP "$wpid"
sleep 4
seq1=$("$C" --json status flood | "$PY" -c 'import json,sys; print(json.load(sys.stdin)["seq"])')
kill -CONT "$wpid"
sleep 1
expect_rc "stop" 0 "$C" stop flood
rc=0; wait "$wpid" || rc=$?
check "watch of a stopped job exits 1" test "$rc" = 1
check "watch ends with the stopped state" jlast "$tmp/watch.jsonl" 'd.get("state")=="stopped"'
# PUB high-water mark 10000 + SUB's 1000: beyond about 11000 events in the pause, some are lost
echo "$((seq1 - seq0)) events published while watch was stopped"
if [ $((seq1 - seq0)) -gt 20000 ]; then
  check "a gap line" grep -q '"type":"gap"' "$tmp/watch.jsonl"
  check "a gap message" grep -q "missed events" "$tmp/watch.err"
else
  echo "note: only $((seq1 - seq0)) events during the pause (a slow build): no gap to see"
fi
expect_rc "sphd still answers" 0 "$C" ping
stop_sphd
finish
