#!/usr/bin/env bash
# sphctl against a real sphd: ping, submit --watch, list, status --json, idempotent resubmit and
# conflict, the exit codes, 4 jobs at once on 2 threads, shutdown, a second sphd, SIGTERM; where
# sphd's threads run.
# Usage: sphctl_basics.sh SPHD SPHCTL SOURCE_DIR
SPHD=$1; SPHCTL=$2; SRC=$3
. "$(dirname "$0")/lib.sh"
KS="$SRC/cases/kernel_study.json"
C=$SPHCTL

expect_rc "ping before sphd runs: unreachable" 69 "$C" --timeout 1 ping
start_sphd --threads 2 --max-jobs 8

expect_rc "ping" 0 "$C" ping
# the socket loop and the ZeroMQ I/O thread share the last CPU; the workers keep every CPU and
# run 5 nice levels lower (the default --worker-nice)
check "request threads on the last CPU, workers on all, 5 nice levels lower" "$PY" - "$sphd_pid" "$tmp/sphd.log" <<'PYEOF'
import os, sys
pid, log = sys.argv[1], open(sys.argv[2]).read()
mine = os.sched_getaffinity(0)
assert f"request threads on CPU {max(mine)}" in log, log
def cpus(tid):
    return os.sched_getaffinity(int(tid))
def nice(tid):
    stat = open(f"/proc/{pid}/task/{tid}/stat").read()
    return int(stat[stat.rindex(")") + 2:].split()[16])
main_nice = nice(pid)
seen = set()
for tid in os.listdir(f"/proc/{pid}/task"):
    comm = open(f"/proc/{pid}/task/{tid}/comm").read().strip()
    if comm == "sphd" or comm.startswith("ZMQbg/IO/"):
        assert cpus(tid) == {max(mine)}, (comm, cpus(tid))
        assert nice(tid) == main_nice, (comm, nice(tid), main_nice)
    elif comm.startswith("sphd-worker-"):
        assert cpus(tid) == mine, (comm, cpus(tid))
        assert nice(tid) == min(main_nice + 5, 19), (comm, nice(tid), main_nice)
    seen.add(comm.rstrip("0123456789"))
assert {"sphd", "ZMQbg/IO/", "sphd-worker-"} <= seen, seen
PYEOF
expect_rc "sphd --request-cpu: a CPU it may not use is a usage error" 64 "$SPHD" --request-cpu 4000
expect_rc "sphd --worker-nice 20: a usage error" 64 "$SPHD" --worker-nice 20
expect_rc "ping --json" 0 "$C" --json ping
check "ping --json is one JSON document" jtrue "$tmp/out" 'd["pong"]'

expect_rc "submit --watch a kernel study" 0 "$C" --json submit "$KS" --id ks1 --watch
check "watch ends with the job done" jlast "$tmp/out" 'd.get("state")=="done" or d.get("status",{}).get("state")=="done"'

# submit --watch listens before it submits: a job of a few steps, ended before a watch that
# subscribed after the submit could connect, still shows its diag events and its end (with and
# without an id of its own, so with the daemon's id too)
for k in 1 2 3; do
  expect_rc "submit --watch a short dam break ($k, its own id)" 0 "$C" --json submit \
    "$SRC/cases/dambreak.json" --id "short$k" --set dx=0.04 --set time.end=0.0002 --watch
  check "short$k: diag events on the stream" "$PY" -c 'import json,sys; ev=[json.loads(l) for l in open(sys.argv[1])]; sys.exit(0 if any(e.get("type")=="diag" and e.get("job")=="short'"$k"'" for e in ev) else 1)' "$tmp/out"
  expect_rc "submit --watch a short dam break ($k, the daemon's id)" 0 "$C" --json submit \
    "$SRC/cases/dambreak.json" --set dx=0.04 --set time.end=0.0002 --set name="anon$k" --watch
  check "anon$k: diag events on the stream" "$PY" -c 'import json,sys; ev=[json.loads(l) for l in open(sys.argv[1])]; sys.exit(0 if any(e.get("type")=="diag" for e in ev) and ev[-1].get("state")=="done" else 1)' "$tmp/out"
done

# a 3D job through the daemon (issue 23): submit --watch to done, then its particles with z
expect_rc "submit --watch a 3D tank" 0 "$C" --json submit "$SRC/cases/hydrostatic3d.json" \
  --id tank3d --set dx=0.05 --set time.end=0.01 --watch
check "tank3d: done" jlast "$tmp/out" 'd.get("state")=="done"'
expect_rc "query tank3d after it ended: bad_state (its particles are gone)" 1 "$C" --json query tank3d --fields pos
expect_rc "submit a 3D tank, not started" 0 "$C" --json submit "$SRC/cases/hydrostatic3d.json" \
  --id tank3d2 --set dx=0.05 --set time.end=0.01 --no-start
expect_rc "step it once" 0 "$C" step tank3d2 1
for _ in $(seq 1 50); do "$C" --json status tank3d2 | grep -q '"paused"' && break; sleep 0.1; done
expect_rc "query tank3d2 --fields pos,vel" 0 "$C" --json query tank3d2 --fields pos,vel --max 5
check "3D particles: pos and vel of 3 components" jtrue "$tmp/out" 'all(len(p)==3 for p in d["particles"]["fields"]["pos"]+d["particles"]["fields"]["vel"])'

expect_rc "status ks1 --json" 0 "$C" status ks1 --json
check "status: done, with its result" jtrue "$tmp/out" 'd["state"]=="done" and d["result"]["method"]=="kernel_study"'
check "result.json and case.json in the job dir" test -s "$STATE/jobs/ks1/result.json" -a -s "$STATE/jobs/ks1/case.json"

expect_rc "resubmit same case, same id" 0 "$C" --json submit "$KS" --id ks1
check "resubmit returns the existing job" jtrue "$tmp/out" 'd["created"] is False and d["job"]=="ks1"'
expect_rc "same id, different case: conflict" 1 "$C" --json submit "$KS" --id ks1 --set particles=51
check "conflict code" jtrue "$tmp/out" 'd["error"]["code"]=="conflict"'

expect_rc "invalid case over --set: 65" 65 "$C" submit "$KS" --set particles=2
check "names the field" grep -qF "(at /particles)" "$tmp/err"
expect_rc "missing file: 66" 66 "$C" submit "$tmp/nope.json"
echo '{"method": ' > "$tmp/bad.json"
expect_rc "not JSON: 65" 65 "$C" submit "$tmp/bad.json"
expect_rc "unsafe job id refused" 1 "$C" submit "$KS" --id ../../etc
expect_rc "unknown job: 1" 1 "$C" status nosuchjob
expect_rc "stop a finished job: 1 (bad_state)" 1 "$C" stop ks1
expect_rc "usage error: 64" 64 "$C" step
expect_rc "unknown command: 64" 64 "$C" frobnicate
for cmd in ping submit status list watch start step pause resume stop query shutdown; do
  expect_rc "$cmd --help" 0 "$C" "$cmd" --help
done

# 4 jobs at once on 2 threads: 2 run, 2 wait in the queue, all finish.
"$PY" - "$KS" "$tmp/big.json" <<'PYEOF'
import json, sys
c = json.load(open(sys.argv[1]))
c.update(name="big", particles=600000, kernels=[{"type": "cubic_spline"}, {"type": "wendland_c2"}],
         functions=["exp", "sin"])
json.dump(c, open(sys.argv[2], "w"))
PYEOF
for i in 1 2 3 4; do "$C" submit "$tmp/big.json" --id "q$i" >/dev/null; done
expect_rc "list --json" 0 "$C" --json list
check "never more than 2 running, the others queued" "$PY" -c '
import json,sys
d=json.load(open(sys.argv[1])); q=[j for j in d["jobs"] if j["job"].startswith("q")]
running=sum(j["state"]=="running" for j in q); queued=sum(j["state"]=="queued" for j in q)
assert running<=2 and len(q)==4, q
assert queued>=1, [j["state"] for j in q]' "$tmp/out"
for i in 1 2 3 4; do expect_rc "q$i finishes" 0 "$C" watch "q$i"; done
expect_rc "list (table)" 0 "$C" list
check "list shows the 4 jobs done" test "$(grep -c ' done ' "$tmp/out")" -ge 4

# --max-jobs 8: the ninth unfinished job is refused as busy (75); stopping one makes room
for i in 1 2 3 4 5 6 7 8; do "$C" submit "$KS" --id "held$i" --no-start >/dev/null; done
expect_rc "beyond --max-jobs: busy" 75 "$C" submit "$KS" --id held9 --no-start
check "busy says why" grep -q "max-jobs" "$tmp/err"
expect_rc "stop one" 0 "$C" stop held1
expect_rc "then there is room" 0 "$C" submit "$KS" --id held9 --no-start
expect_rc "--json prints one document" 0 "$C" --json list
check "one line of JSON" test "$(wc -l <"$tmp/out")" = 1
for i in 2 3 4 5 6 7 8 9; do "$C" stop "held$i" >/dev/null; done

# a second sphd on the same endpoint refuses
expect_rc "second sphd refuses" 75 "$SPHD" --listen "$SPHD_ENDPOINT" --publish "ipc://$tmp/run/s2" --state-dir "$tmp/state2"
check "with a clear message" grep -q "already serving" "$tmp/err"
expect_rc "first sphd still answers" 0 "$C" ping

stop_sphd
check "socket file removed" test ! -e "$tmp/run/control"

# SIGTERM stops it cleanly too
start_sphd --threads 1
kill -TERM "$sphd_pid"; rc=0; wait "$sphd_pid" || rc=$?; sphd_pid=""
check "SIGTERM: exit 0" test "$rc" = 0

finish
