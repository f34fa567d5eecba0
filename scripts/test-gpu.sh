#!/usr/bin/env bash
# The GPU tests, on a machine with an NVIDIA GPU and CUDA's toolkit (nvcc on PATH or in
# /usr/local/cuda): builds with -DSPH_CUDA=ON and runs the tests labelled gpu, the device halves
# included: gpu_physics (the shared physics headers on the GPU against the C build), gpu_solver
# (the same cases on the CPU and the GPU, 100 steps; GPU checkpoints restored on the GPU and on
# the CPU), gpu_crash_resume (a GPU job through sphd killed and resumed); then the benchmark
# (bench_dambreak --device gpu: Test 2 and DualSPHysics' 01_DamBreak at about 250k and 1M).
# A few minutes at most. Exit 69 when no GPU is visible (CI runs the host halves in test.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
nvcc=$(command -v nvcc || echo /usr/local/cuda/bin/nvcc)
if [ ! -x "$nvcc" ]; then
  echo "test-gpu: no nvcc (CUDA's toolkit) on PATH or in /usr/local/cuda" >&2
  exit 69
fi
if ! nvidia-smi -L >/dev/null 2>&1; then
  echo "test-gpu: no GPU visible (nvidia-smi -L): run it on a machine with one" >&2
  exit 69
fi
nvidia-smi -L
scripts/setup.sh
cmake -S . -B build-cuda -DSPH_CUDA=ON -DSPH_WERROR=ON -DSPH_STRIPS_RUNTIME=OFF \
  -DCMAKE_CUDA_COMPILER="$nvcc" \
  ${SPH_CUDA_ARCH:+-DCMAKE_CUDA_ARCHITECTURES=$SPH_CUDA_ARCH} >/dev/null
cmake --build build-cuda -j"$(nproc)" --target test_gpu_physics test_gpu_solver test_hydrostatic sphd bench_dambreak
rc=0
out=$(ctest --test-dir build-cuda --output-on-failure -L gpu -V) || rc=$?
echo "$out" | grep -E "gpu_physics:|gpu_solver:|: [0-9]+ particles|tests passed|Skipped|FAIL" || true
[ "$rc" -eq 0 ] || exit "$rc"
if echo "$out" | grep -qE "device half is skipped|no GPU visible"; then
  echo "test-gpu: the GPU was not usable from the tests" >&2
  exit 1
fi
# the benchmark (figures, not a test): Test 2 at about 250k and 1M particles, DualSPHysics'
# 01_DamBreak at dx 7.4 mm (249k) and 4.6 mm (about 1M), 100 steps, median of 3
SPH_BENCH_GPU=${SPH_BENCH_GPU:-1}
if [ "$SPH_BENCH_GPU" = 1 ]; then
  build-cuda/bin/bench_dambreak --device gpu --threads 1 --sizes "" --steps3d 100 \
    --sizes3d "250000 1000000" --dsph "0.0074 0.0046"
fi
