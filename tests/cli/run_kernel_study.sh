#!/usr/bin/env bash
# `sphd --run cases/kernel_study.json`: exit 0, JSON Lines events with seq 1, 2, 3..., the last a
# state event "done", a result with all five kernels, and case.json + result.json in the out dir.
# Usage: run_kernel_study.sh SPHD SOURCE_DIR
set -eu
sphd=$1; src=$2
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
"$sphd" --run "$src/cases/kernel_study.json" --out "$tmp/out" > "$tmp/events.jsonl"
test -s "$tmp/out/case.json"
test -s "$tmp/out/result.json"
PY=/usr/bin/python3
"$PY" - "$tmp/events.jsonl" "$tmp/out/result.json" <<'PYEOF'
import json, sys
events = [json.loads(l) for l in open(sys.argv[1])]
assert [e["seq"] for e in events] == list(range(1, len(events) + 1)), events
assert all(e["job"] == "kernel_study" for e in events)
assert events[-1]["type"] == "state" and events[-1]["state"] == "done", events[-1]
res = [e for e in events if e["type"] == "result"]
assert len(res) == 1
r = res[0]
names = [k["type"] for k in r["kernels"]]
assert names == ["double_cosine", "cubic_spline", "gaussian", "wendland_c2", "renormalized_gaussian"], names
for k in r["kernels"]:
    assert abs(k["normalisation"] - 1) < 1e-8, k
    for fn in ("exp", "sin", "cos", "poly2"):
        for part in ("f", "dfdx"):
            s = k["functions"][fn][part]
            assert 0 <= s["rms"] <= s["max"] < 0.1, (k["type"], fn, part, s)
saved = json.load(open(sys.argv[2]))
a = saved["kernels"][0]["functions"]["exp"]["f"]["max"]; b = r["kernels"][0]["functions"]["exp"]["f"]["max"]
assert abs(a - b) <= 1e-9 * abs(b), (a, b)
print("kernel study run: 1 passed, 0 failed")
PYEOF
