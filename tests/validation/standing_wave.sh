#!/usr/bin/env bash
# Viscous standing wave (Macia et al., paper 001; cases/standing_wave.json: Re = 500, Wendland C2,
# dx/h = 0.5, ghost walls, Monaghan viscosity) at H/dx = 50, run just past 8 periods. Passes when
# the period fitted to the kinetic-energy peaks is within 2% of 2 pi/omega and the fitted decay
# rate of the envelope within RATE_BOUND (default 0.20: the CI's loose bound at this coarse
# resolution; the issue's 15% and 10% hold for H/dx = 100 and 200, run by `validate`) of
# Lighthill's 4 nu k^2 (eq. 8).
# One thread: ctest runs two tests at once on the 2-core CI machine.
# Usage: standing_wave.sh SPHD SOURCE_DIR [RATE_BOUND] [--set PATH=VALUE ...]
set -u
sphd=$1; src=$2; shift 2
bound=0.20
if [ $# -gt 0 ] && [ "${1#--}" = "$1" ]; then bound=$1; shift; fi
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
"$sphd" --run "$src/cases/standing_wave.json" --out "$tmp/out" --threads 1 --set time.end=6.7 "$@" \
  >"$tmp/events.jsonl" || { echo "FAIL: sphd --run exited $?"; tail -n 3 "$tmp/events.jsonl"; exit 1; }
/usr/bin/python3 - "$tmp/events.jsonl" "$bound" <<'PY'
import json, sys
events = [json.loads(l) for l in open(sys.argv[1]) if l.strip()]
bound = float(sys.argv[2])
res = [e for e in events if e["type"] == "result"]
if not res or "wave" not in res[-1]:
    print("FAIL: no result with a wave fit"); sys.exit(1)
w, v = res[-1]["wave"], res[-1]["viscosity"]
perr = (w["period"] - w["period_theory"]) / w["period_theory"]
rerr = (w["decay_rate"] - w["decay_rate_theory"]) / w["decay_rate_theory"]
print("standing wave: %d peaks up to t = %.3f s, alpha %.5f (nu %g)" % (w["peaks"], w["fit_until"], v["alpha"], v["nu"]))
print("standing wave: period %.4f s, theory %.4f s, error %+.2f%% (bound 2%%)" % (w["period"], w["period_theory"], 100 * perr))
print("standing wave: decay rate %.4f 1/s, theory 4 nu k^2 %.4f 1/s, error %+.1f%% (bound %g%%)" % (w["decay_rate"], w["decay_rate_theory"], 100 * rerr, 100 * bound))
ok = w["peaks"] >= 16 and abs(perr) <= 0.02 and abs(rerr) <= bound
print("PASS" if ok else "FAIL")
sys.exit(0 if ok else 1)
PY
