#!/usr/bin/env bash
# The README's test command: set up, build (warnings are errors here), run every test; then build
# again with AddressSanitizer and UndefinedBehaviorSanitizer (optimised, -O2 -g: several times
# faster than -O0 under ASan) and run the unit, command-line, integration and regression tests
# under them (but for the physics runs through the daemon, which take minutes there; the golden
# 2D run there also checks that the pair loop with its options read at run time, as the sanitizer
# builds compile it, gives the specialised loops' bits);
# then build with clang, with hypre's AMG preconditioner (-DSPH_HYPRE=ON: the default builds have
# none), and run the unit tests; then the CUDA code with nvcc where it is (-DSPH_CUDA=ON: the
# shared physics headers against the C build; scripts/test-gpu.sh runs the rest on a GPU); then
# gcc Release (-O3: scripts/build-matrix.sh; it builds the other types too), without a warning;
# last, each fuzz target runs for 10 s (as many at once as there are cores)
# from its seed corpus with a fixed random seed (SPH_FUZZ_SEED, default 1): about the same inputs
# each run, so a find most likely fails the change that brought it, not a later one by chance.
set -euo pipefail
cd "$(dirname "$0")/.."
# Each stage's start is printed with the seconds since the script began (CI's limit is 30 min).
stage() { echo "== $* (at ${SECONDS} s) =="; }
stage "set-up and build"
scripts/setup.sh
scripts/build.sh -DSPH_WERROR=ON
stage "tests"
# three at once on two cores: the Slurm test mostly waits on Slurm (10 s of CPU in 2 minutes)
ctest --test-dir build --output-on-failure -j3

stage "sanitizers (ASan + UBSan)"
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSPH_SANITIZE=ON -DSPH_WERROR=ON >/dev/null
cmake --build build-asan -j"$(nproc)"
ASAN_OPTIONS=detect_leaks=1:abort_on_error=0 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  LSAN_OPTIONS="suppressions=$PWD/tests/lsan.supp:print_suppressions=0" \
  ctest --test-dir build-asan --output-on-failure -j2 -L 'unit|cli|integration|regress' \
    -E 'integration_(mps|bodies)_daemon|integration_crash_resume'  # physics through the daemon:
    # 5 minutes under ASan; they run above, and their code under ASan in test_mps, test_body,
    # test_sim_checkpoint and integration_daemon_crash

stage "clang (Release, with hypre's AMG): build, unit tests"
CC=clang cmake -S . -B build-clang -DCMAKE_BUILD_TYPE=Release -DSPH_WERROR=ON -DSPH_HYPRE=ON >/dev/null
cmake --build build-clang -j"$(nproc)"
ctest --test-dir build-clang --output-on-failure -j2 -L unit

stage "CUDA (the GPU backend: nvcc, warnings as errors; the tests that need a GPU skip here)"
nvcc=$(command -v nvcc || echo /usr/local/cuda/bin/nvcc)
if [ -x "$nvcc" ]; then
  cmake -S . -B build-cuda -DSPH_CUDA=ON -DSPH_WERROR=ON -DSPH_STRIPS_RUNTIME=ON \
    -DCMAKE_CUDA_COMPILER="$nvcc" >/dev/null
  cmake --build build-cuda -j"$(nproc)" --target test_gpu_physics test_gpu_solver test_hydrostatic sphd bench_dambreak
  ctest --test-dir build-cuda --output-on-failure -L gpu
else
  echo "no nvcc (CUDA's toolkit): the CUDA build is skipped"
fi

stage "the other build types, warnings as errors"
# (gcc RelWithDebInfo, gcc with the sanitizers and clang Release are built above)
scripts/build-matrix.sh gcc:Release

stage "fuzzing: each libFuzzer target for 10 s (scripts/fuzz.sh)"
scripts/fuzz.sh --seconds "${SPH_FUZZ_SECONDS:-10}" --jobs "$(nproc)" --seed "${SPH_FUZZ_SEED:-1}" --fresh
stage "all passed"
