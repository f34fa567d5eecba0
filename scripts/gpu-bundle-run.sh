#!/bin/bash
# The GPU tests and the benchmark from a bundle that scripts/gpu-bundle.sh made (programs built
# on another machine, their libraries in .gpu/lib), run in the repository root of a copy of it.
# Usage: bash .gpu/run.sh [STEP...]  (smoke physics solver bench hydro crash valid; memcheck)
# Logs in $OUT (default /tmp/out); a line per step and a summary on stdout.
set -u
R=$PWD; G=$R/.gpu; B=$G/bin; export PATH=$PATH:/usr/local/cuda/bin
export SPH_SOURCE_DIR=$R SPH_PYTHON=$(command -v python3)
OUT=${OUT:-/tmp/out}; mkdir -p "$OUT"
T0=$(date +%s)
steps=${*:-"smoke physics solver bench hydro crash valid"}
nvidia-smi --query-gpu=name,driver_version,memory.used,memory.total,clocks.sm --format=csv,noheader
LD_LIBRARY_PATH=$G/lib ldd $G/bin/real/sphd | grep "not found"
summary=""
step() {
  local name=$1 lim=$2; shift 2
  local s=$(date +%s.%N)
  timeout "$lim" "$@" >"$OUT/$name.log" 2>&1; local rc=$?
  local dt=$(awk -v a="$s" -v b="$(date +%s.%N)" 'BEGIN{printf "%.1f", b-a}')
  echo "=== $name rc=$rc ${dt}s (at $(( $(date +%s) - T0 ))s)"
  grep -E "FAIL|rror|passed|ok |PASS|worst|diff|M/s|B/p|particles|^ *(test2|dsph01)|rows|front|press|skip" "$OUT/$name.log" | head -40
  [ $rc -eq 0 ] || tail -n 15 "$OUT/$name.log"
  summary="$summary $name=$rc"
}
for st in $steps; do
  case $st in
  smoke) step smoke 60 $B/sphd --run "$R/cases/dambreak.json" --threads 4 --set dx=0.01 \
           --set time.end=0.05 --set output.every=0.05 --set 'device="gpu"' --out /tmp/smoke ;;
  physics) step physics 60 $B/test_gpu_physics ;;
  solver) step solver 150 $B/test_gpu_solver ;;
  bench) step bench 200 $B/bench_dambreak --device gpu --threads 16 --sizes "" --steps3d 100 \
           --repeats 3 --sizes3d "250000 1000000" --dsph "0.0074 0.0046" ;;
  hydro) SPH_TEST_DEVICE=gpu step hydro 90 $B/test_hydrostatic "$R" ;;
  crash) step crash 150 bash "$R/tests/integration/crash_resume.sh" $B/sphd "$R" "" gpu ;;
  valid) step valid 150 python3 "$R/tests/validation/report/validate.py" --sphd $B/sphd --src "$R" \
           --level ci --only dambreak --threads 1 --set 'device="gpu"' --out /tmp/valgpu ;;
  memcheck) step memcheck 200 env LD_LIBRARY_PATH=$G/lib compute-sanitizer --tool memcheck --print-limit 20 $B/real/sphd \
           --run "$R/cases/dambreak.json" --threads 4 --set dx=0.02 --set time.end=0.002 \
           --set output.every=1 --set 'device="gpu"' --out /tmp/mc ;;
  *) echo "=== $st: no such step (smoke physics solver bench hydro crash valid memcheck)"
     summary="$summary $st=2" ;;
  esac
  if [ $st = smoke ] && [ "${summary##* }" != smoke=0 ]; then
    echo "smoke failed: memcheck and physics only"; bash "$0" memcheck physics; break
  fi
done
echo "SUMMARY$summary (total $(( $(date +%s) - T0 ))s)"
case "$summary " in *=[1-9]*) exit 1 ;; esac
