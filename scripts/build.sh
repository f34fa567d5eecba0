#!/usr/bin/env bash
# Configures and builds into build/ (sphd and sphctl land in build/bin/). Arguments go to cmake
# (scripts/test.sh passes -DSPH_WERROR=ON).
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build -DCMAKE_BUILD_TYPE=RelWithDebInfo "$@" >/dev/null
cmake --build build -j"$(nproc)"
