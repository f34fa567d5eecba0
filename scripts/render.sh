#!/usr/bin/env bash
# Renders a job's fluid at one time to a PNG with ParaView (scripts/render.py): pvbatch needs an X
# server to render, so without a DISPLAY this starts Xvfb (Debian xvfb) for the run.
# Usage: scripts/render.sh JOB_DIR TIME OUT.png     (e.g. out/dambreak 0.3 dambreak.png)
set -euo pipefail
[ $# = 3 ] || { echo "usage: scripts/render.sh JOB_DIR TIME OUT.png" >&2; exit 64; }
here=$(cd "$(dirname "$0")" && pwd)
xpid=
if [ -z "${DISPLAY:-}" ]; then
  for n in $(seq 90 120); do [ -e "/tmp/.X$n-lock" ] || break; done
  Xvfb ":$n" -screen 0 1600x1200x24 -nolisten tcp >/dev/null 2>&1 &
  xpid=$!
  trap 'kill $xpid 2>/dev/null || true' EXIT
  export DISPLAY=":$n"
  for _ in $(seq 1 50); do [ -e "/tmp/.X11-unix/X$n" ] && break; sleep 0.1; done
  sleep 1  # the socket comes before the server accepts
fi
pvbatch "$here/render.py" "$@" 2> >(grep -v -E 'Warning|^$' >&2)
