#!/usr/bin/env bash
# `cmake --install` into a temporary prefix installs a working sphd and sphctl: the files land in
# the GNU directories, the systemd user unit names the installed sphd, and the installed programs
# run a case from the installed case files, as a daemon and its client too.
# Usage: install_prefix.sh BUILD_DIR
set -u
build=$1
SPHD=unused SPHCTL=unused
. "$(dirname "$0")/lib.sh"
pfx="$tmp/prefix"
check "cmake --install succeeds" cmake --install "$build" --prefix "$pfx" >"$tmp/install.log"
for f in bin/sphd bin/sphctl share/sphd/cases/dambreak.json share/sphd/cases/hydrostatic.json \
         share/sphd/cases/kernel_study.json share/sphd/cases/mps_dambreak.json \
         share/sphd/cases/solitary_wave.json share/doc/sphd/PROTOCOL.md \
         lib/systemd/user/sphd.service; do
  check "installed $f" test -s "$pfx/$f"
done
check "the programs are executable" test -x "$pfx/bin/sphd" -a -x "$pfx/bin/sphctl"
check "the unit runs the installed sphd" grep -qx "ExecStart=$pfx/bin/sphd" \
  "$pfx/lib/systemd/user/sphd.service"
check "the unit is enabled into the user's default target" grep -qx "WantedBy=default.target" \
  "$pfx/lib/systemd/user/sphd.service"
SPHD="$pfx/bin/sphd"; SPHCTL="$pfx/bin/sphctl"
expect_rc "installed sphd --version" 0 "$SPHD" --version
expect_rc "installed sphd --run on an installed case" 0 \
  "$SPHD" --run "$pfx/share/sphd/cases/kernel_study.json" --out "$tmp/ks"
check "its result" test -s "$tmp/ks/result.json"
# the installed daemon and client, from another working directory
cd "$tmp"
start_sphd --threads 1
expect_rc "installed sphctl submits an installed case and watches it" 0 \
  "$SPHCTL" submit "$pfx/share/sphd/cases/kernel_study.json" --id ks --watch --json
check "the job is done" grep -q '"state": *"done"' "$tmp/out"
stop_sphd
finish
