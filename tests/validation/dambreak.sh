#!/usr/bin/env bash
# Dam break (Yang et al. 2014, section 4.1) against Martin & Moyce (1952): the RMS of the relative
# difference of the front X = x/D (Table 2) over T = t sqrt(2g/D) in [0.4, 3.3], and of the water
# height at the left wall h/2D (Table 6) over tau = t sqrt(g/D) from 0.5 to the end, must each be
# under 10%.
# Usage: dambreak.sh SPHD SOURCE_DIR [CASE] [--set PATH=VALUE ...]   (e.g. --set dx=0.0025: the
# fine run; CASE: a case file under cases/, default dambreak.json, dambreak_ghost.json the same
# dam break with free-slip ghost walls)
set -u
sphd=$1; src=$2; shift 2
case=dambreak.json
if [ $# -gt 0 ] && [ "${1#--}" = "$1" ]; then case=$1; shift; fi
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
"$sphd" --run "$src/cases/$case" --out "$tmp/out" "$@" >"$tmp/events.jsonl" || {
  echo "FAIL: sphd --run exited $?"; tail -n 3 "$tmp/events.jsonl"; exit 1; }
tail -n 2 "$tmp/events.jsonl" | head -n 1
/usr/bin/python3 "$src/tests/validation/dambreak_front.py" "$tmp/events.jsonl" \
  "${SPH_REFERENCE_DIR:-$src/tests/validation/reference}/dambreak_front_MartinMoyce1952_table2_n2eq2.csv" --bound 0.10 \
  --height "${SPH_REFERENCE_DIR:-$src/tests/validation/reference}/dambreak_height_MartinMoyce1952_table6_n2eq2.csv"
