#!/usr/bin/env bash
# Regenerates the fuzz seeds and regression inputs that are saved simulation states (after a
# change of SIM_VERSION in core/sph_checkpoint.c or of the checkpoint file, server/sphd_ckpt.c):
# tests/fuzz/corpus/{sim_restore,ckpt}/ and tests/fuzz/regress/{sim_restore,ckpt}/, written by
# tests/fuzz/make_seeds.c, which then restores each seed and prints what refuses each regression
# input (exit 1 if one is not refused by the check meant for it). Commit the changed files.
# Usage: scripts/fuzz-seeds.sh [BUILD_DIR]   (default build/; configured there if needed)
#        scripts/fuzz-seeds.sh --check [BUILD_DIR]   only checks the files in the repository
set -euo pipefail
cd "$(dirname "$0")/.."
mode=()
if [ "${1:-}" = --check ]; then mode=(--check); shift; fi
build=${1:-build}
[ -f "$build/CMakeCache.txt" ] || cmake -S . -B "$build" >/dev/null
cmake --build "$build" -j"$(nproc)" --target make_seeds >/dev/null
OMP_NUM_THREADS=1 "$build/tests/make_seeds" "${mode[@]}" tests/fuzz
