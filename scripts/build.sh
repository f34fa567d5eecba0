#!/usr/bin/env bash
# Configures and builds every target into build/ (sphd and sphctl land in build/bin/), the tests
# included (-DSPH_BUILD_TESTS=ON: scripts/run-main.sh configures build/ without them). Arguments go
# to cmake (scripts/test.sh passes -DSPH_WERROR=ON).
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build -DCMAKE_BUILD_TYPE=RelWithDebInfo -DSPH_BUILD_TESTS=ON "$@" >/dev/null
cmake --build build -j"$(nproc)"
