# Helpers for the integration tests: a real sphd on a temporary ipc endpoint and state dir.
# Source it with SPHD and SPHCTL set; it defines $tmp, start_sphd, stop_sphd, expect_rc, and a
# trap that always kills the daemon.
set -u
tmp=$(mktemp -d)
sphd_pid=""
cleanup() {
  [ -n "${watchdog_pid:-}" ] && kill "$watchdog_pid" 2>/dev/null
  if [ -n "$sphd_pid" ] && kill -0 "$sphd_pid" 2>/dev/null; then
    kill -KILL "$sphd_pid" 2>/dev/null
    wait "$sphd_pid" 2>/dev/null
  fi
  rm -rf "$tmp"
}
trap cleanup EXIT
export SPHD_ENDPOINT="ipc://$tmp/run/control"
STREAM="ipc://$tmp/run/stream"
STATE="$tmp/state"
pass=0; fail=0

# start_sphd [OPTIONS...]: starts sphd in the background and waits until it answers ping.
start_sphd() {
  "$SPHD" --listen "$SPHD_ENDPOINT" --publish "$STREAM" --state-dir "$STATE" "$@" \
    2>>"$tmp/sphd.log" &
  sphd_pid=$!
  for _ in $(seq 1 100); do
    "$SPHCTL" --timeout 1 ping >/dev/null 2>&1 && return 0
    kill -0 "$sphd_pid" 2>/dev/null || break
    sleep 0.05
  done
  echo "FAIL: sphd did not start"; cat "$tmp/sphd.log"; exit 1
}

# stop_sphd: asks sphd to shut down and checks that it exits 0.
stop_sphd() {
  "$SPHCTL" shutdown >/dev/null
  local rc=0
  wait "$sphd_pid" || rc=$?
  sphd_pid=""
  check "sphd exits 0 after shutdown" test "$rc" = 0
}

# check NAME COMMAND...: runs the command, counts a pass or a fail.
check() {
  local name=$1; shift
  echo "$name" >"$tmp/step"
  if "$@"; then pass=$((pass+1)); else echo "FAIL: $name"; fail=$((fail+1)); fi
}

# expect_rc NAME WANT COMMAND...: the command's exit code must be WANT.
expect_rc() {
  local name=$1 want=$2; shift 2
  echo "$name" >"$tmp/step"
  local rc=0
  "$@" >"$tmp/out" 2>"$tmp/err" || rc=$?
  if [ "$rc" = "$want" ]; then pass=$((pass+1)); else
    echo "FAIL: $name: exit $rc, want $want"; cat "$tmp/err"; fail=$((fail+1)); fi
}

# watchdog SECONDS: a test still running after SECONDS (set it under its ctest TIMEOUT) says
# where it hangs instead of being killed mute: the step it is at, the daemon's log, every
# sphd's and sphctl's threads' stacks (gdb, where installed); then it kills them, so that the
# test goes on to fail. Ends with the test.
watchdog() {
  local secs=$1 me=$$
  (
    trap 'exit 0' TERM
    sleep "$secs" >/dev/null 2>&1 &
    wait $!
    kill -0 "$me" 2>/dev/null || exit 0
    echo "WATCHDOG: $(basename "$0") still running after $secs s, at: $(cat "$tmp/step" 2>/dev/null)"
    echo "--- sphd log:"; tail -n 40 "$tmp/sphd.log" 2>/dev/null
    echo "--- its processes:"; ps -o pid,stat,etime,args --ppid "$me" 2>/dev/null
    self=$BASHPID
    pids=$(pgrep -P "$me" | grep -vx "$self")
    for p in $pids; do
      cmd=$(tr '\0' ' ' </proc/"$p"/cmdline 2>/dev/null)
      echo "--- $p: $cmd"
      case "$cmd" in "$SPHD "* | "$SPHCTL "*) ;; *) continue ;; esac
      if command -v gdb >/dev/null; then
        timeout 30 gdb -p "$p" -batch -ex "thread apply all bt" 2>/dev/null | grep -E '^(Thread|#)'
      fi
    done
    # shellcheck disable=SC2086
    kill -KILL $pids 2>/dev/null
  ) &
  watchdog_pid=$!
}

finish() {
  echo "$(basename "$0"): $pass passed, $fail failed"
  if [ "$fail" != 0 ]; then echo "--- sphd log:"; tail -n 40 "$tmp/sphd.log"; exit 1; fi
  exit 0
}

PY=/usr/bin/python3
# jtrue FILE EXPR: EXPR (Python over `d`, the JSON document in FILE) must be true.
jtrue() { "$PY" -c "import json,sys; d=json.load(open(sys.argv[1])); sys.exit(0 if ($2) else 1)" "$1"; }
# jlast FILE EXPR: the same over `d`, the last line of a JSON Lines file.
jlast() { "$PY" -c "import json,sys; d=json.loads(open(sys.argv[1]).read().splitlines()[-1]); sys.exit(0 if ($2) else 1)" "$1"; }

# batch_reference JOB ARGS...: `sphd --run "$CASE" ARGS` the uninterrupted reference
# ($tmp/ref/JOB, its events in $tmp/ref.jsonl), once more timed (sets $runtime [s], to scale the
# sleeps of a crash test), and with 2 threads, which must be bitwise the 1-thread run.
batch_reference() {
  local job=$1; shift
  "$SPHD" --run "$CASE" --threads 1 "$@" --out "$tmp/ref/$job" >"$tmp/ref.jsonl" 2>/dev/null
  check "the reference run is done" jlast "$tmp/ref.jsonl" 'd.get("state")=="done"'
  local t0; t0=$(date +%s.%N)
  "$SPHD" --run "$CASE" --threads 1 "$@" --out "$tmp/timing/$job" >/dev/null 2>&1
  runtime=$(awk -v a="$t0" -v b="$(date +%s.%N)" 'BEGIN { print b - a }')
  "$SPHD" --run "$CASE" --threads 2 "$@" --out "$tmp/two/$job" >/dev/null 2>&1
  check "2 threads: bitwise the 1-thread run" "$PY" "$(dirname "$0")/h5check.py" same \
    "$tmp/ref/$job" "$tmp/two/$job"
}

# submit_step_pause JOB WHAT ARGS...: submits "$CASE" (described as WHAT) as JOB without
# starting it, with ARGS, steps it 7 times and checks that it then waits, paused.
submit_step_pause() {
  local job=$1 what=$2; shift 2
  expect_rc "submit the $what, not started" 0 "$SPHCTL" submit "$CASE" --id "$job" --no-start "$@"
  expect_rc "step 7" 0 "$SPHCTL" step "$job" 7
  for _ in $(seq 1 500); do
    "$SPHCTL" --json status "$job" >"$tmp/st" 2>/dev/null
    jtrue "$tmp/st" 'd["state"]=="paused" and not d.get("pending_step")' && break
    sleep 0.02
  done
  check "seven steps, then paused" jtrue "$tmp/st" \
    'd["state"]=="paused" and d["progress"]["steps"]==7'
}

# run_pause_kill JOB: resumes the paused JOB, pauses and resumes it while it runs, then kills
# sphd with SIGKILL twice at random moments (scaled by $runtime) and starts it again on the same
# state dir, checking the job's latest files are whole after each kill, and watches the job to
# its end (the watch's events in $tmp/out). Sets $kills.
run_pause_kill() {
  local job=$1
  expect_rc "resume" 0 "$SPHCTL" resume "$job"
  sleep "$(awk -v r="$runtime" 'BEGIN { printf "%.3f", r * 0.15 }')"
  expect_rc "pause while running" 0 "$SPHCTL" --json pause "$job"
  check "paused" jtrue "$tmp/out" 'd["state"] in ("paused", "done")'
  expect_rc "resume again" 0 "$SPHCTL" resume "$job"
  kills=0
  for i in 1 2; do
    sleep "$(awk -v r="$runtime" -v p=$((10 + RANDOM % 20)) 'BEGIN { printf "%.3f", r * p / 100 }')"
    kill -KILL "$sphd_pid"; wait "$sphd_pid" 2>/dev/null; sphd_pid=
    kills=$((kills+1))
    check "latest files whole after kill $kills" "$PY" "$(dirname "$0")/h5check.py" whole \
      "$STATE/jobs/$job"
    start_sphd --threads 1
    expect_rc "the job is still known after restart $i" 0 "$SPHCTL" --json status "$job"
  done
  expect_rc "watch it to the end" 0 "$SPHCTL" --json watch "$job"
  check "it finished" jlast "$tmp/out" \
    'd.get("state")=="done" or d.get("status",{}).get("state")=="done"'
}
