#!/usr/bin/env bash
# Builds the libFuzzer targets (clang, -fsanitize=fuzzer,address,undefined) into build-fuzz/ and
# runs each for SECONDS (default 30), one after another, from its seed corpus in
# tests/fuzz/corpus/NAME/ (new inputs go to build-fuzz/corpus/NAME/, never into the repo).
# A crash stops with exit 1 and leaves its input in build-fuzz/artifacts/NAME/; keep it as a
# regression test in tests/fuzz/regress/NAME/ with the fix. Each run's last status line
# (executions, cov, ft) goes to build-fuzz/logs/NAME.log and is printed.
# --keep-going: go on after a crash, a timeout or running out of memory (libFuzzer's fork mode:
# every finding is kept in build-fuzz/artifacts/NAME/ and counted in the log; for long runs).
# --no-build: run what build-fuzz/ holds (several runs at once share one build).
# --seed S: libFuzzer's random seed (default 0, a new one each run). A fixed seed starts every
# run from the same random state and corpus, so runs stay close to one another (not exactly: how
# far a run gets, and some of libFuzzer's choices, depend on its speed); scripts/test.sh fixes
# it so that CI tries about the same inputs each time rather than new ones by chance.
# --fresh: start from the seed corpus only, not from what earlier runs in build-fuzz/ found.
# --jobs J: run up to J targets at once (default 1; each is one process on one core).
# Usage: scripts/fuzz.sh [--seconds S] [--jobs J] [--seed S] [--fresh] [--keep-going]
#                        [--build-only | --no-build] [TARGET ...]
#   targets: request case sim_restore ckpt journal mesh (default: all). FUZZ_NICE=19 runs it niced.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=30 jobs=1 seed=0 fresh=0 build_only=0 build=1 targets=() mode=()
while [ $# -gt 0 ]; do
  case $1 in
    --seconds) seconds=$2; shift 2 ;;
    --seed) seed=$2; shift 2 ;;
    --jobs) jobs=$2; shift 2 ;;
    --fresh) fresh=1; shift ;;
    --build-only) build_only=1; shift ;;
    --no-build) build=0; shift ;;
    --keep-going) mode=(-fork=1 -ignore_crashes=1 -ignore_timeouts=1 -ignore_ooms=1); shift ;;
    -h|--help) sed -n '2,19p' "$0"; exit 0 ;;
    *) targets+=("$1"); shift ;;
  esac
done
[ ${#targets[@]} -gt 0 ] || targets=(request case sim_restore ckpt journal mesh)
if [ "$build" = 1 ]; then
  CC=clang cmake -S . -B build-fuzz -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSPH_FUZZ=ON >/dev/null
  cmake --build build-fuzz -j"$(nproc)" --target $(printf 'fuzz_%s ' "${targets[@]}") >/dev/null
fi
[ "$build_only" = 1 ] && exit 0
export OMP_NUM_THREADS=1
export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=0}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
# One target's run; its summary goes to build-fuzz/logs/NAME.result (printed in order at the
# end), its status is the exit code.
run_one() {
  local t=$1
  [ "$fresh" = 0 ] || rm -rf "build-fuzz/corpus/$t"
  mkdir -p "build-fuzz/corpus/$t" "build-fuzz/artifacts/$t" build-fuzz/logs
  local dict=()
  [ -f "tests/fuzz/$t.dict" ] && dict=(-dict="tests/fuzz/$t.dict")
  # assimp's own leaks are suppressed (tests/lsan.supp); its frames show only with slow unwinding
  local lsan=${LSAN_OPTIONS:-}
  [ "$t" != mesh ] || lsan="suppressions=$PWD/tests/lsan.supp:fast_unwind_on_malloc=0"
  local log="build-fuzz/logs/$t-$(date +%Y%m%d-%H%M%S).log" out="build-fuzz/logs/$t.result"
  # a saved state's seeds are about 163 kB (scripts/fuzz-seeds.sh): below that length libFuzzer
  # cuts every seed short and the target never gets past the size check
  local maxlen=65536
  case $t in sim_restore | ckpt) maxlen=262144 ;; esac
  if LSAN_OPTIONS=$lsan nice -n "${FUZZ_NICE:-0}" "build-fuzz/fuzz/fuzz_$t" "build-fuzz/corpus/$t" "tests/fuzz/corpus/$t" \
       "${dict[@]}" "${mode[@]}" -seed="$seed" -max_total_time="$seconds" -max_len="$maxlen" -rss_limit_mb=2048 -timeout=20 \
       -print_final_stats=1 -artifact_prefix="build-fuzz/artifacts/$t/" >"$log" 2>&1; then
    echo "fuzz $t: $(grep -E '^#[0-9]+' "$log" | tail -n 1)" >"$out"
    [ ${#mode[@]} -eq 0 ] || echo "  findings kept: $(ls "build-fuzz/artifacts/$t/" | wc -l)" >>"$out"
  else
    { echo "fuzz $t: FAILED (a crash; log $log)"; grep -E 'ERROR|SUMMARY|runtime error' "$log" | head -n 5
      ls "build-fuzz/artifacts/$t/"; } >"$out"
    return 1
  fi
}
rc=0 pids=() names=()
for t in "${targets[@]}"; do
  while [ "$(jobs -rp | wc -l)" -ge "$jobs" ]; do sleep 1; done
  run_one "$t" &
  pids+=($!) names+=("$t")
done
for k in "${!pids[@]}"; do
  wait "${pids[$k]}" || rc=1
  cat "build-fuzz/logs/${names[$k]}.result"
done
exit "$rc"
