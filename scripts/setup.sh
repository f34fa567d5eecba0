#!/usr/bin/env bash
# Installs what sphd needs to build and test (and the tools the tests read results with: meshio,
# ParaView's pvbatch, matplotlib for the validation report), from Debian's packages.
# --main: only what scripts/run-main.sh needs, the build of sphd and sphctl without the tests
# (-DSPH_BUILD_TESTS=OFF): the compiler, cmake, pkg-config and the libraries they link against.
# Does nothing when all is there. Runs apt-get as root, or through sudo.
set -euo pipefail
main_only=0
case "${1:-}" in
  --main) main_only=1 ;;
  "") ;;
  *) echo "usage: $0 [--main]" >&2; exit 64 ;;
esac
# sphd and sphctl (the top CMakeLists.txt: OpenMP comes with gcc; meshes are read with assimp and
# queried over Embree's hierarchies, core/scene and protocol/sph_mesh_io.c; the dashboard is
# served with libmicrohttpd)
pkgs=(gcc libc6-dev make cmake pkg-config libzmq3-dev libjansson-dev libhdf5-dev zlib1g-dev
      libassimp-dev libembree-dev libmicrohttpd-dev)
if [ "$main_only" -eq 0 ]; then
  # the unit tests, and the tools the tests read results with
  pkgs+=(libcmocka-dev python3 python3-zmq python3-h5py python3-numpy python3-jsonschema
         python3-meshio python3-matplotlib paraview python3-paraview xvfb xauth)
  # the second compiler of CI, its OpenMP and libFuzzer
  pkgs+=(clang libomp-dev libclang-rt-dev)
  # the CURVE test captures loopback traffic
  pkgs+=(tcpdump)
  # the dashboard's browser test: Debian's chromium driven by Playwright (from the npm registry,
  # its version pinned in tests/web/package-lock.json)
  pkgs+=(chromium)
  command -v node >/dev/null 2>&1 || pkgs+=(nodejs) # (a machine's own Node.js, with its npm,
  command -v npm >/dev/null 2>&1 || pkgs+=(npm)     # is used where there is one)
  # the Slurm executor's test runs a one-node Slurm cluster (scripts/slurm-local.sh)
  pkgs+=(slurm-wlm munge)
  # the clang build of test.sh builds with hypre's AMG (-DSPH_HYPRE=ON: mps.preconditioner "amg")
  pkgs+=(libhypre-dev mpi-default-dev)
fi
missing=()
for p in "${pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] && exit 0
echo "setup: installing ${missing[*]}" >&2
sudo=""
[ "$(id -u)" -eq 0 ] || sudo="sudo"
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
