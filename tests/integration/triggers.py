#!/usr/bin/env python3
"""Triggers (a case's "triggers", PROTOCOL.md 1.7) through a real sphd over its socket.

A 2D dam break with three triggers: pause when the front passes x = 0.4 m, a snapshot past
t = 0.05 s, a checkpoint once ekin > 1 J. The job must pause at the first diagnostic whose
front_x is past 0.4 (diag.h5: that row's front_x > 0.4, every earlier row's not), with the reason,
after one snapshot out of the schedule; then a `set` replaces the triggers (the pause kept, a stop
past t = 0.3 added), and the resumed job stops at the first diagnostic past 0.3 s without pausing
again. Bad triggers are refused at their paths; `sphd --run` pauses on one (exit 75) and
`--resume` finishes. usage: triggers.py SPHD SPHCTL SRC"""
import json
import os
import subprocess
import sys
import tempfile

import h5py

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sphd_harness import Daemon, Failures  # noqa: E402

PAUSE = {"when": "front_x > 0.4", "do": "pause"}


def diag(jobdir):
    with h5py.File(os.path.join(jobdir, "diag.h5"), "r", libver="latest", swmr=True) as h:
        return {k: h[k][:] for k in ("step", "t", "front_x")}


def main(sphd, sphctl, src):
    t = Failures("triggers")
    with open(os.path.join(src, "cases", "dambreak.json")) as f:
        case = json.load(f)
    case.update(dx=0.01)
    case["time"] = dict(case["time"], end=0.5)
    case["output"] = dict(case.get("output", {}), every=0.1)
    case["triggers"] = [PAUSE, {"when": "t > 0.05", "do": "snapshot"},
                        {"when": "ekin > 1", "do": "checkpoint"}]
    d = Daemon(sphd, "--threads", "1")
    try:
        d.ok("submit", {"case": case, "job": "tr"})
        st = d.wait_state("tr", ["paused", "done", "failed"], timeout=60)
        t.check(st["state"] == "paused" and "front_x > 0.4" in st.get("reason", ""),
                "the trigger paused the job, saying which", st)
        jobdir = os.path.join(d.state, "jobs", "tr")
        g = diag(jobdir)
        step = st["progress"]["steps"]
        at = list(g["step"]).index(step) if step in list(g["step"]) else -1
        t.check(at > 0 and g["front_x"][at] > 0.4 and all(g["front_x"][:at] <= 0.4),
                f"paused at the first diagnostic past 0.4 (step {step}, front_x "
                f"{g['front_x'][at] if at >= 0 else None})", list(zip(g["step"], g["front_x"])))
        snaps = [f["name"] for f in d.ok("results", {"job": "tr"})["files"]
                 if f["kind"] == "snapshot"]
        times = []
        for name in sorted(snaps):
            with h5py.File(os.path.join(jobdir, name), "r") as h:
                times.append(float(h.attrs["time"]))
        off = [x for x in times if abs(x / 0.1 - round(x / 0.1)) > 1e-6]
        t.check(len(off) == 1 and 0.05 < off[0] < 0.06 and
                len(times) == 2 + int(g["t"][at] / 0.1 + 1e-9),
                f"the scheduled snapshots and one from the trigger (t = {off})", times)
        with open(os.path.join(jobdir, "journal.jsonl")) as f:
            recs = [json.loads(line) for line in f]
        fired = [r["trigger"] for r in recs if "trigger" in r]
        t.check(fired == ["t > 0.05", "ekin > 1", "front_x > 0.4"] or
                sorted(fired) == sorted(["t > 0.05", "ekin > 1", "front_x > 0.4"]),
                "the journal records each trigger once", fired)
        # a stop added by `set`; the pause that fired stays fired
        r = d.ok("set", {"job": "tr", "set": [
            'triggers=[{"when": "front_x > 0.4", "do": "pause"}, {"when": "t > 0.3", "do": '
            '"stop"}]']})
        t.check("error" not in r.get("steering", {}), "set replaces the triggers", r)
        d.ok("resume", {"job": "tr"})
        st = d.wait_state("tr", ["stopped", "paused", "done", "failed"], timeout=60)
        t.check(st["state"] == "stopped" and "t > 0.3" in st.get("reason", ""),
                "the trigger set on the paused job stopped it (not paused again)", st)
        g = diag(jobdir)
        t.check(g["t"][-1] > 0.3 and all(g["t"][:-1] <= 0.3),
                f"stopped at the first diagnostic past 0.3 s (t = {g['t'][-1]:.4f})",
                list(g["t"][-3:]))

        # bad triggers, at their paths
        def refused(trig, path, words):
            r = d.request("submit", {"case": dict(case, triggers=trig), "start": False})
            err = r.get("error", {})
            t.check(not r["ok"] and err.get("code") == "invalid_case" and err.get("path") == path
                    and all(w in err.get("message", "") for w in words),
                    f"refused {trig}: {err.get('message')}", r)

        refused([{"when": "P9 > 1", "do": "pause"}], "/triggers/0/when", ["no series 'P9'"])
        refused([{"when": "front_x >> 1", "do": "pause"}], "/triggers/0/when", ["OP"])
        refused([PAUSE, {"when": "t > 1", "do": "explode"}], "/triggers/1/do", ["explode"])
        refused([{"when": "t > 1"}], "/triggers/0/do", ["do"])
        refused({"when": "t > 1"}, "/triggers", ["array"])
    finally:
        d.close()

    # batch mode: paused by the trigger (exit 75, resumable), then finished by --resume
    with tempfile.TemporaryDirectory() as tmp:
        cf = os.path.join(tmp, "tr.json")
        with open(cf, "w") as f:
            json.dump(dict(case, triggers=[PAUSE]), f)
        out = os.path.join(tmp, "out")
        p = subprocess.run([sphd, "--run", cf, "--threads", "1", "--out", out],
                           capture_output=True, text=True, timeout=120)
        last = json.loads(p.stdout.strip().splitlines()[-1])
        t.check(p.returncode == 75 and last.get("state") == "paused"
                and "front_x > 0.4" in last.get("reason", ""),
                "sphd --run pauses on the trigger: exit 75", (p.returncode, last))
        p = subprocess.run([sphd, "--run", cf, "--threads", "1", "--out", out, "--resume"],
                           capture_output=True, text=True, timeout=120)
        last = json.loads(p.stdout.strip().splitlines()[-1])
        t.check(p.returncode == 0 and last.get("state") == "done",
                "--resume goes on to the end (the trigger does not fire again)",
                (p.returncode, last, p.stderr[-500:]))
    return t.done()


if __name__ == "__main__":
    sys.exit(main(*sys.argv[1:4]))
