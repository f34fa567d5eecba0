#!/usr/bin/env bash
# Crash test (batch mode): a dam break killed with SIGKILL at 5 moments, one of them in the middle
# of a checkpoint write, and resumed each time with --resume, ends with snapshots and diagnostics
# bitwise equal to those of an uninterrupted run (1 thread). After every kill the latest files are
# whole: every snapshot opens with all its fields, the XDMF parses, the diagnostics file opens.
# With 3d: the same for a 3D dam break (issue 23: a column 0.2 x 0.25 x 0.6 m at the end of the
# 3D still-water tank, dx = 0.05 m), its diag at a fixed interval of simulated time (7 ms).
# With gpu: the 2D dam break on the GPU ("device": "gpu", a build with -DSPH_CUDA=ON; exit 77,
# skipped, when no GPU is visible): checkpointed, killed and resumed like a CPU job.
# Usage: crash_resume.sh SPHD SOURCE_DIR [SEED [3d|gpu]]
set -eu
sphd=$1; src=$2; seed=${3:-$RANDOM}; mode=${4:-2d}
[ -n "$seed" ] || seed=$RANDOM
tmp=$(mktemp -d); pid=
trap '[ -n "$pid" ] && kill -9 $pid 2>/dev/null || true; rm -rf "$tmp"' EXIT
PY=${SPH_PYTHON:-/usr/bin/python3}
if [ "$mode" = gpu ]; then
  nvidia-smi -L >/dev/null 2>&1 || { echo "no GPU visible: skipped"; exit 77; }
  args=(--run "$src/cases/dambreak.json" --threads 1 --set dx=0.005 --set time.end=0.3
        --set output.every=0.03 --set 'device="gpu"')
elif [ "$mode" = 3d ]; then
  args=(--run "$src/cases/hydrostatic3d.json" --threads 1 --set dx=0.05 --set time.end=0.3
        --set output.every=0.03 --set diagnostics.interval=0.007
        --set 'fluid=[{"box": {"min": [0, 0, 0], "max": [0.2, 0.25, 0.6]}}]')
else
  args=(--run "$src/cases/dambreak.json" --threads 1 --set dx=0.005 --set time.end=0.3
        --set output.every=0.03)
fi
echo "seed $seed"; RANDOM=$seed

"$sphd" "${args[@]}" --out "$tmp/ref/db" >/dev/null 2>&1
t0=$(date +%s.%N)
"$sphd" "${args[@]}" --out "$tmp/full/db" >/dev/null 2>&1   # a timing run
runtime=$(awk -v a="$t0" -v b="$(date +%s.%N)" 'BEGIN { print b - a }')

check_whole() { "$PY" "$(dirname "$0")/h5check.py" whole "$1"; }

kills=0
for i in 1 2 3 4 5; do
  if [ $i = 3 ]; then
    # in the middle of a checkpoint write: the writer pauses after the header
    SPHD_FAULT_CKPT_DELAY_MS=400 "$sphd" "${args[@]}" --out "$tmp/crash/db" --resume >/dev/null 2>&1 &
    pid=$!
    for _ in $(seq 1 600); do
      ls "$tmp/crash/db" 2>/dev/null | grep -q '^checkpoint\.tmp\.' && break
      sleep 0.01
    done
    ls "$tmp/crash/db" | grep -q '^checkpoint\.tmp\.' || { echo "FAIL: no checkpoint write seen"; exit 1; }
  else
    "$sphd" "${args[@]}" --out "$tmp/crash/db" --resume >/dev/null 2>&1 &
    pid=$!
    delay=$(awk -v r="$runtime" -v p=$((5 + RANDOM % 20)) 'BEGIN { printf "%.3f", r * p / 100 }')
    sleep "$delay"
  fi
  if kill -9 $pid 2>/dev/null; then kills=$((kills+1)); fi
  wait $pid 2>/dev/null || true
  pid=
  check_whole "$tmp/crash/db"
done
[ $kills -ge 4 ] || { echo "FAIL: only $kills kills landed before the run ended"; exit 1; }
"$sphd" "${args[@]}" --out "$tmp/crash/db" --resume > "$tmp/last.jsonl" 2>"$tmp/last.err"
tail -n1 "$tmp/last.jsonl" | grep -q '"state":"done"'
"$PY" "$(dirname "$0")/h5check.py" same "$tmp/ref/db" "$tmp/crash/db"
# between snapshots, checkpoints come from the wall clock (--checkpoint-interval)
"$sphd" --run "$src/cases/dambreak.json" --threads 1 --set dx=0.005 --set output.every=100 \
  --checkpoint-interval 0.2 --out "$tmp/interval/db" >/dev/null 2>&1 &
pid=$!
for _ in $(seq 1 600); do
  [ -s "$tmp/interval/db/checkpoint.prev" ] && break   # the t = 0 one, then one from the clock
  sleep 0.01
done
kill -9 $pid 2>/dev/null || true; wait $pid 2>/dev/null || true; pid=
"$sphd" --run "$src/cases/dambreak.json" --threads 1 --set dx=0.005 --set output.every=100 --out "$tmp/interval/db" \
  --resume > "$tmp/interval.jsonl" 2>"$tmp/interval.err"
grep -q "resuming from its checkpoint" "$tmp/interval.err"
"$PY" -c "import json,sys; d=json.loads(open(sys.argv[1]).readlines()[1]); sys.exit(0 if d['type']=='diag' and d['step']>0 else 1)" "$tmp/interval.jsonl"
echo "crash and resume: $kills kills; 2 passed, 0 failed"
