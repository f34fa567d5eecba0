#!/usr/bin/env bash
# The GPU tests, on a machine with an NVIDIA GPU and CUDA's toolkit (nvcc on PATH or in
# /usr/local/cuda): builds with -DSPH_CUDA=ON and runs the tests labelled gpu, the device halves
# included. Today: ctest gpu_physics (the shared physics headers on the GPU against the C build).
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
cmake -S . -B build-cuda -DSPH_CUDA=ON -DSPH_WERROR=ON -DCMAKE_CUDA_COMPILER="$nvcc" \
  ${SPH_CUDA_ARCH:+-DCMAKE_CUDA_ARCHITECTURES=$SPH_CUDA_ARCH} >/dev/null
cmake --build build-cuda -j"$(nproc)" --target test_gpu_physics
rc=0
out=$(ctest --test-dir build-cuda --output-on-failure -L gpu -V) || rc=$?
echo "$out" | grep -E "gpu_physics:|tests passed|FAIL" || true
[ "$rc" -eq 0 ] || exit "$rc"
if echo "$out" | grep -q "device half is skipped"; then
  echo "test-gpu: the GPU was not usable from the tests" >&2
  exit 1
fi
