#!/usr/bin/env bash
# The README's main command: set up, build, and run the main job.
# For now the main job is the kernel study of Yang et al. (2014) run in batch mode; it becomes the
# daemon + dam break once sphd's daemon mode lands (issue 4).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
scripts/build.sh
build/bin/sphd --run cases/kernel_study.json --out out/kernel_study
echo "results: out/kernel_study/result.json" >&2
