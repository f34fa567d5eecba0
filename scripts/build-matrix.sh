#!/usr/bin/env bash
# Builds sphd with the project's default options and warnings as errors, once per COMPILER:TYPE
# given (default: gcc and clang, each Release, RelWithDebInfo and Debug), each in
# build-matrix/COMPILER-TYPE/, and prints one line per build. Exits 1 when one fails.
# Usage: scripts/build-matrix.sh [COMPILER:TYPE ...]     e.g. clang:Debug
set -uo pipefail
cd "$(dirname "$0")/.."
combos=("$@")
[ ${#combos[@]} -gt 0 ] || combos=(gcc:Release gcc:RelWithDebInfo gcc:Debug
                                   clang:Release clang:RelWithDebInfo clang:Debug)
mkdir -p build-matrix
failed=0
for combo in "${combos[@]}"; do
  cc=${combo%%:*} type=${combo#*:}
  dir=build-matrix/$cc-$type
  start=$(date +%s)
  if CC=$cc cmake -S . -B "$dir" -DCMAKE_BUILD_TYPE="$type" -DSPH_WERROR=ON >"$dir.log" 2>&1 &&
     cmake --build "$dir" -j"$(nproc)" >>"$dir.log" 2>&1; then
    echo "build-matrix: $cc $type: ok, $(grep -c 'warning:' "$dir.log") warnings," \
         "$(( $(date +%s) - start )) s"
  else
    echo "build-matrix: $cc $type: FAILED (log: $dir.log)"; tail -n 30 "$dir.log"
    failed=1
  fi
done
exit "$failed"
