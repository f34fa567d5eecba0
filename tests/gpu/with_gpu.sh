#!/usr/bin/env bash
# Runs the command when a GPU is visible (nvidia-smi -L); else exits 77, which ctest reads as
# skipped (the GPU tests of a CUDA build on a machine without one).
nvidia-smi -L >/dev/null 2>&1 || { echo "no GPU visible: skipped"; exit 77; }
exec "$@"
