#!/usr/bin/env bash
# `sphd --run` on a WCSPH case: JSON Lines events (diag with the probes, result, the final state),
# exit 0; a case needing more memory than allowed exits 65 with too_large.
# Usage: run_wcsph.sh SPHD SOURCE_DIR
set -u
sphd=$1; src=$2
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
fail=0
"$sphd" --run "$src/cases/dambreak.json" --out "$tmp/out" --set dx=0.005 --set time.end=0.02 >"$tmp/ev" 2>"$tmp/err"
rc=$?
[ $rc = 0 ] || { echo "FAIL: dam break exit $rc"; cat "$tmp/err"; fail=1; }
/usr/bin/python3 - "$tmp/ev" <<'PY' || fail=1
import json, sys
ev = [json.loads(l) for l in open(sys.argv[1])]
assert ev[-1]["type"] == "state" and ev[-1]["state"] == "done", ev[-1]
assert [e["seq"] for e in ev] == list(range(1, len(ev) + 1)), "seq gaps"
diags = [e for e in ev if e["type"] == "diag"]
assert len(diags) >= 2 and diags[0]["step"] == 0, diags[:1]
for k in ("step", "t", "dt", "ekin", "epot", "vmax", "rho_min", "rho_max", "front_x", "height_left"):
    assert k in diags[-1], k
assert abs(diags[-1]["t"] - 0.02) < 1e-12, diags[-1]["t"]
res = [e for e in ev if e["type"] == "result"]
assert len(res) == 1 and res[0]["particles"]["fluid"] == 800, res
print("dam break events OK:", len(ev), "events, front_x", diags[-1]["front_x"])
PY
# diagnostics.interval: diag at t = k * interval exactly (the steps land there), in the events and
# in diag.h5, and at the end time
"$sphd" --run "$src/cases/dambreak.json" --out "$tmp/iv" --set dx=0.005 --set time.end=0.02 \
  --set diagnostics.interval=0.003 >"$tmp/ev_iv" 2>"$tmp/err_iv" ||
  { echo "FAIL: diagnostics.interval: exit $?"; cat "$tmp/err_iv"; fail=1; }
/usr/bin/python3 - "$tmp/ev_iv" "$tmp/iv/diag.h5" <<'PY' || fail=1
import json, sys
import h5py
ev = [json.loads(l) for l in open(sys.argv[1])]
t = [e["t"] for e in ev if e["type"] == "diag"]
want = [k * 0.003 for k in range(7)] + [0.02]
assert len(t) == len(want) and all(abs(a - b) < 1e-12 for a, b in zip(t, want)), (t, want)
steps = [e["step"] for e in ev if e["type"] == "diag"]
assert steps == sorted(set(steps)), steps
with h5py.File(sys.argv[2], "r") as f:
    th = list(f["t"][:])
    assert len(th) == len(want) and all(abs(a - b) < 1e-12 for a, b in zip(th, want)), th
print("diagnostics.interval OK: diag at", t)
PY
# SIGTERM: a checkpoint, a last state "paused", exit 75; --resume finishes it as if never stopped
sets=(--set dx=0.01 --set time.end=1.5 --set diagnostics.every=50)
"$sphd" --run "$src/cases/dambreak.json" --out "$tmp/ref" "${sets[@]}" --threads 1 >"$tmp/ev_ref" 2>/dev/null
"$sphd" --run "$src/cases/dambreak.json" --out "$tmp/int" "${sets[@]}" --threads 1 >"$tmp/ev_a" 2>"$tmp/err_a" &
pid=$!
for _ in $(seq 1 500); do  # until it has stepped (the handler is in place by then)
  grep -q '"type":"diag".*"step":[1-9]' "$tmp/ev_a" 2>/dev/null && break
  sleep 0.02
done
kill -TERM $pid; wait $pid; rc=$?
"$sphd" --run "$src/cases/dambreak.json" --out "$tmp/int" "${sets[@]}" --threads 1 --resume >"$tmp/ev_b" 2>"$tmp/err_b"
rc2=$?
if [ $rc != 75 ] || [ $rc2 != 0 ] || ! grep -q "checkpoint written" "$tmp/err_a" ||
   ! grep -q "resuming from its checkpoint" "$tmp/err_b"; then
  echo "FAIL: SIGTERM: exit $rc then $rc2"; cat "$tmp/err_a" "$tmp/err_b"; fail=1
else
  /usr/bin/python3 - "$tmp/ev_ref" "$tmp/ev_a" "$tmp/ev_b" <<'PY' || fail=1
import json, sys
ref, a, b = ([json.loads(l) for l in open(f)] for f in sys.argv[1:])
assert a[-1]["type"] == "state" and a[-1]["state"] == "paused", a[-1]
assert a[-1]["reason"] == "interrupted by SIGTERM", a[-1]
assert b[-1]["state"] == "done", b[-1]
last = max(e["step"] for e in a if e["type"] == "diag")
assert 0 < last, last
r1 = [e for e in ref if e["type"] == "result"][0]
r2 = [e for e in b if e["type"] == "result"][0]
assert r1["steps"] == r2["steps"] and r1["diag"] == r2["diag"], (r1["diag"], r2["diag"])
print("SIGTERM OK: stopped after step", last, "exit 75; resumed to", r2["steps"], "steps, as the uninterrupted run")
PY
fi
# --resume past output times (output.every made shorter than at the checkpoint, written after the
# snapshot at t = 0.1): it goes on from there (it spun on the first missed time before), the
# missed times passed over
sets=(--set dx=0.01 --set time.end=0.4)
"$sphd" --run "$src/cases/dambreak.json" --out "$tmp/sk" "${sets[@]}" --set time.end=0.2 \
  --set output.every=0.1 --threads 1 >/dev/null 2>&1
timeout 60 "$sphd" --run "$src/cases/dambreak.json" --out "$tmp/sk" "${sets[@]}" \
  --set output.every=0.02 --threads 1 --resume >"$tmp/ev_sk" 2>"$tmp/err_sk"
rc=$?
if [ $rc != 0 ] || ! grep -q "resuming from its checkpoint" "$tmp/err_sk"; then
  echo "FAIL: resume past output times: exit $rc"; cat "$tmp/err_sk"; fail=1
else
  /usr/bin/python3 - "$tmp/ev_sk" <<'PY' || fail=1
import json, sys
ev = [json.loads(l) for l in open(sys.argv[1])]
out = [round(e["t"], 9) for e in ev if e["type"] == "output"]
want = [round(0.12 + 0.02 * k, 9) for k in range(15)]
assert ev[-1]["state"] == "done" and out == want, out
print("resume past output times OK: outputs at", out[0], "...", out[-1])
PY
fi
# --resume with a checkpoint it cannot read: kept as checkpoint.unreadable, the run starts afresh
printf 'not a checkpoint' >"$tmp/sk/checkpoint"
printf 'not a checkpoint' >"$tmp/sk/checkpoint.prev"
"$sphd" --run "$src/cases/dambreak.json" --out "$tmp/sk" "${sets[@]}" --set time.end=0.01 \
  --set output.every=0.1 --threads 1 --resume >/dev/null 2>"$tmp/err_un"
rc=$?
if [ $rc != 0 ] || ! grep -q "kept as checkpoint.unreadable" "$tmp/err_un" ||
   [ "$(cat "$tmp/sk/checkpoint.unreadable" 2>/dev/null)" != "not a checkpoint" ]; then
  echo "FAIL: unreadable checkpoint: exit $rc"; cat "$tmp/err_un"; fail=1
else
  echo "unreadable checkpoint OK: $(cat "$tmp/err_un")"
fi
for dx in 1e-5 1e-300; do
  "$sphd" --run "$src/cases/dambreak.json" --out "$tmp/o2" --set dx=$dx >"$tmp/ev2" 2>"$tmp/err2"
  rc=$?
  if [ $rc != 65 ] || ! grep -q too_large "$tmp/err2" || [ -s "$tmp/ev2" ]; then
    echo "FAIL: too large case (dx = $dx): exit $rc"; cat "$tmp/err2"; fail=1
  else
    echo "too large OK: $(cat "$tmp/err2")"
  fi
done
exit $fail
