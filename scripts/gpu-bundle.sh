#!/usr/bin/env bash
# Bundles the GPU tests for a GPU machine that lacks this project's Debian packages (libzmq,
# jansson, HDF5) and cannot install them, such as a lent machine with no network: builds
# build-cuda here (-DSPH_CUDA=ON, nvcc from /usr/local/cuda), copies the programs the GPU tests
# need, stripped, into .gpu/bin/real with a wrapper each that finds the libraries the bundle
# carries in .gpu/lib (every one the programs load except the C and C++ runtimes, which a newer
# system has), and scripts/gpu-bundle-run.sh as .gpu/run.sh. On the GPU machine, in a copy of
# the repository with .gpu beside the sources: bash .gpu/run.sh (all the tests, then the
# benchmark; `bash .gpu/run.sh solver bench` for some). The machine needs a glibc at least this
# one's (Debian 12: 2.36) and a CUDA 13 driver. About 40 MiB.
set -euo pipefail
cd "$(dirname "$0")/.."
nvcc=$(command -v nvcc || echo /usr/local/cuda/bin/nvcc)
cmake -S . -B build-cuda -DSPH_CUDA=ON -DSPH_WERROR=ON -DSPH_STRIPS_RUNTIME=OFF \
  -DCMAKE_CUDA_COMPILER="$nvcc" >/dev/null
progs="bin/sphd bin/sphctl bin/bench_dambreak tests/test_gpu_solver tests/test_gpu_physics
       tests/test_hydrostatic"
cmake --build build-cuda -j"$(nproc)" --target sphd sphctl bench_dambreak test_gpu_solver \
  test_gpu_physics test_hydrostatic
rm -rf .gpu
mkdir -p .gpu/bin/real .gpu/lib
for p in $progs; do
  n=$(basename "$p")
  strip -o ".gpu/bin/real/$n" "build-cuda/$p"
  printf '#!/bin/sh\nd=$(dirname "$(readlink -f "$0")")\nLD_LIBRARY_PATH="$d/../lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}" exec "$d/real/%s" "$@"\n' \
    "$n" >".gpu/bin/$n"
  chmod +x ".gpu/bin/$n"
done
for p in .gpu/bin/real/*; do ldd "$p"; done | awk '$3 ~ /^\// { print $3 }' | sort -u |
  grep -Ev '/(libc|libm|libdl|libpthread|librt|libresolv|ld-linux[^/]*|libgcc_s|libstdc\+\+)\.so' |
  while read -r l; do cp -L "$l" .gpu/lib/; done
cp scripts/gpu-bundle-run.sh .gpu/run.sh
git_exclude=$(git rev-parse --git-path info/exclude 2>/dev/null || true)
if [ -n "$git_exclude" ]; then
  mkdir -p "$(dirname "$git_exclude")"
  grep -qx '/.gpu/' "$git_exclude" 2>/dev/null || echo /.gpu/ >>"$git_exclude"
fi
echo "gpu-bundle: .gpu is $(du -sh .gpu | cut -f1) (git ignores it); on the GPU machine: bash .gpu/run.sh"
