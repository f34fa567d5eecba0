# Helpers for the integration tests: a real sphd on a temporary ipc endpoint and state dir.
# Source it with SPHD and SPHCTL set; it defines $tmp, start_sphd, stop_sphd, expect_rc, and a
# trap that always kills the daemon.
set -u
tmp=$(mktemp -d)
sphd_pid=""
cleanup() {
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
  if "$@"; then pass=$((pass+1)); else echo "FAIL: $name"; fail=$((fail+1)); fi
}

# expect_rc NAME WANT COMMAND...: the command's exit code must be WANT.
expect_rc() {
  local name=$1 want=$2; shift 2
  local rc=0
  "$@" >"$tmp/out" 2>"$tmp/err" || rc=$?
  if [ "$rc" = "$want" ]; then pass=$((pass+1)); else
    echo "FAIL: $name: exit $rc, want $want"; cat "$tmp/err"; fail=$((fail+1)); fi
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
