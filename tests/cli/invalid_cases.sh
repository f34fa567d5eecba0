#!/usr/bin/env bash
# Every invalid case file makes `sphd --run` exit 65 with a message naming the field.
# Usage: invalid_cases.sh SPHD SOURCE_DIR
set -u
sphd=$1; src=$2
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
pass=0; fail=0
for f in "$src"/tests/cases/invalid/*.json; do
  want=$(head -n1 "${f%.json}.expect")
  "$sphd" --run "$f" --out "$tmp/out" >"$tmp/stdout" 2>"$tmp/stderr"
  rc=$?
  if [ "$rc" != 65 ]; then
    echo "FAIL $(basename "$f"): exit $rc, want 65"; cat "$tmp/stderr"; fail=$((fail+1)); continue
  fi
  if [ -n "$want" ] && ! grep -qF -- "(at $want)" "$tmp/stderr"; then
    echo "FAIL $(basename "$f"): message does not name $want:"; cat "$tmp/stderr"; fail=$((fail+1)); continue
  fi
  if [ -s "$tmp/stdout" ]; then
    echo "FAIL $(basename "$f"): printed events for an invalid case"; fail=$((fail+1)); continue
  fi
  pass=$((pass+1))
done
# a missing file is 66, a bad --set is 65, a bad option is 64
"$sphd" --run "$tmp/nope.json" >/dev/null 2>&1; rc=$?
[ $rc = 66 ] && pass=$((pass+1)) || { echo "FAIL missing file: exit $rc, want 66"; fail=$((fail+1)); }
"$sphd" --run "$src/cases/kernel_study.json" --out "$tmp/o2" --set particles=2 >/dev/null 2>"$tmp/stderr"; rc=$?
[ $rc = 65 ] && grep -qF "(at /particles)" "$tmp/stderr" && pass=$((pass+1)) || { echo "FAIL --set particles=2: exit $rc"; fail=$((fail+1)); }
# a 3D case too big for the memory cap: refused before any allocation, naming dx (issue 23)
"$sphd" --run "$src/cases/hydrostatic3d.json" --out "$tmp/o3" --set dx=0.0005 >/dev/null 2>"$tmp/stderr"; rc=$?
[ $rc = 65 ] && grep -q "too_large: the case needs about .* MB .* use a larger dx" "$tmp/stderr" && pass=$((pass+1)) || { echo "FAIL 3D too big: exit $rc"; cat "$tmp/stderr"; fail=$((fail+1)); }
"$sphd" --bogus >/dev/null 2>&1; rc=$?
[ $rc = 64 ] && pass=$((pass+1)) || { echo "FAIL --bogus: exit $rc, want 64"; fail=$((fail+1)); }
echo "invalid cases: $pass passed, $fail failed"
[ $fail = 0 ]
