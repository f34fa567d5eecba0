#!/usr/bin/env python3
"""Steering (op `set`, PROTOCOL.md 3.12) through a real sphd over its socket.

A 2D dam break (dx 0.005 m) is steered three times while it runs (the viscosity's alpha, gravity,
the end time with the snapshots' period and the diagnostics' schedule), then sphd is killed with SIGKILL and started again on the same state directory:
the job resumes from its checkpoint and finishes. A second job of the same case, on the new
sphd, is stepped to the very steps the first was changed at (`step`), changed there while paused
(`sphctl set` for one of them), and run to its end. The two jobs' snapshots and diagnostics must
be bitwise equal (h5check.py same), their steering histories the same, and both results must
carry them. Refusals: a field of the set-up (`dx`), an output schedule, a value out of range, an
end time already past, a job that is done; each names its path and says why.
usage: steering.py SPHD SPHCTL SRC"""
import json
import os
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sphd_harness import Daemon, Failures  # noqa: E402

SETS = [["physics.viscosity.alpha=0.05"], ["physics.gravity=[0.5, -8.5]"],
        ["time.end=0.55", "output.every=0.03", "diagnostics.every=20"]]


def same(a, b):
    """Two steering histories alike: the same steps and assignments, the times to the 12
    digits that sphd's replies carry (result.json holds all 17)."""
    return (isinstance(a, list) and isinstance(b, list) and len(a) == len(b) and all(
        x["step"] == y["step"] and x["set"] == y["set"] and abs(x["t"] - y["t"]) <= 1e-11
        for x, y in zip(a, b)))


def main(sphd, sphctl, src):
    t = Failures("steering")
    with open(os.path.join(src, "cases", "dambreak.json")) as f:
        case = json.load(f)
    case.update(dx=0.005)
    case["time"] = dict(case["time"], end=0.5)
    case["output"] = dict(case.get("output", {}), every=0.05)
    d = Daemon(sphd, "--threads", "1")
    d2 = None
    try:
        d.ok("submit", {"case": case, "job": "live"})
        history = []
        for k, s in enumerate(SETS):
            # a few hundred steps between the changes, the job running
            st = d.ok("query", {"job": "live"})
            step0 = st["progress"]["steps"]
            deadline = time.time() + 30
            while st["progress"]["steps"] < step0 + 200 and time.time() < deadline:
                time.sleep(0.05)
                st = d.ok("query", {"job": "live"})
            t.check(st["state"] == "running", f"change {k}: the job is running", st["state"])
            r = d.ok("set", {"job": "live", "set": s}, timeout=30)
            steer = r.get("steering", {})
            t.check("error" not in steer and "pending" not in steer,
                    f"change {k} made: {s}", steer)
            history = steer.get("history", [])
            t.check(len(history) == k + 1 and history[-1]["set"] == s,
                    f"change {k} is the history's last, at step {history[-1]['step']}", history)
        vals = d.ok("query", {"job": "live"})["steering"]["values"]
        t.check(vals == {"physics.viscosity.alpha": 0.05, "physics.gravity": [0.5, -8.5],
                         "time.end": 0.55, "output.every": 0.03, "diagnostics.every": 20},
                "query shows the values in effect", vals)
        # kill -9 while it runs, then a new sphd on the same state directory
        d.proc.kill()
        d.proc.wait()
        d2 = Daemon(sphd, "--threads", "1", "--state-dir", d.state)
        done = d2.wait_state("live", ["done", "failed"], timeout=120)
        t.check(done["state"] == "done", "the killed job resumes and ends", done)
        t.check(done["progress"]["t"] == 0.55, "it ends at the steered end time",
                done["progress"])
        t.check(same(done.get("steering", {}).get("history"), history),
                "after the restart its status has the same history", done.get("steering"))
        # the same changes at the same steps on a job that was never killed
        d2.ok("submit", {"case": case, "job": "ref", "start": False})
        at = 0
        for k, (s, h) in enumerate(zip(SETS, history)):
            d2.ok("step", {"job": "ref", "n": h["step"] - at})
            d2.wait_state("ref", ["paused"])
            at = h["step"]
            if k == 1:
                p = subprocess.run([sphctl, "--endpoint", d2.control, "set", "ref", *s],
                                   capture_output=True, text=True, timeout=30)
                t.check(p.returncode == 0 and f"changed at step {at}" in p.stdout,
                        "sphctl set on a paused job", (p.returncode, p.stdout, p.stderr))
            else:
                r = d2.ok("set", {"job": "ref", "set": s})
                t.check(r["steering"]["history"][-1]["step"] == at,
                        f"the paused job changed at step {at}", r["steering"])
        d2.ok("resume", {"job": "ref"})
        ref = d2.wait_state("ref", ["done", "failed"], timeout=120)
        t.check(ref["state"] == "done" and same(ref.get("steering", {}).get("history"), history),
                "the stepped job ends with the same history", ref.get("steering"))
        jobs = os.path.join(d.state, "jobs")
        p = subprocess.run(["/usr/bin/python3", os.path.join(os.path.dirname(__file__),
                                                             "h5check.py"), "same",
                            os.path.join(jobs, "ref"), os.path.join(jobs, "live")],
                           capture_output=True, text=True)
        t.check(p.returncode == 0, "killed and resumed equals never killed, bit for bit: "
                + p.stdout.strip(), p.stdout + p.stderr)
        with open(os.path.join(jobs, "live", "case.json")) as f:
            rec = json.load(f)
        t.check(same(rec.get("steering"), history) and rec["dx"] == case["dx"],
                "case.json: the case as submitted, with the history under steering",
                rec.get("steering"))
        # after the change, the snapshots every 0.03 s and a diag every 20 steps
        import h5py
        times = []
        for name in sorted(os.listdir(os.path.join(jobs, "live"))):
            if name.startswith("snap_") and name.endswith(".h5"):
                with h5py.File(os.path.join(jobs, "live", name), "r") as h:
                    times.append(float(h.attrs["time"]))
        t_set = history[-1]["t"]
        later = [x for x in times if t_set + 1e-9 < x < 0.55 - 1e-9]  # (and one at the end)
        t.check(len(later) >= 10 and all(abs(x / 0.03 - round(x / 0.03)) < 1e-6 for x in later)
                and later[0] < t_set + 0.03 + 1e-9,
                f"snapshots every 0.03 s from the change on ({len(later)})", later[:4])
        with h5py.File(os.path.join(jobs, "live", "diag.h5"), "r") as h:
            steps = [int(x) for x in h["step"][:]]
        after = [x for x in steps if x > history[-1]["step"]]
        t.check(after and all(x % 20 == 0 for x in after[:-1]),
                "a diag every 20 steps from the change on", after[:5])
        for job in ("live", "ref"):
            with open(os.path.join(jobs, job, "result.json")) as f:
                res = json.load(f)
            t.check(same(res.get("steering"), history), f"{job}'s result.json holds the history",
                    (res.get("steering"), history))

        # refusals, each at its path
        def refused(args, code, path, words):
            r = d2.request("set", args)
            err = r.get("error", {})
            t.check(not r["ok"] and err.get("code") == code and err.get("path") == path
                    and all(w in err.get("message", "") for w in words),
                    f"refused: {args['set'] if 'set' in args else args}: {err.get('message')}",
                    r)

        d2.ok("submit", {"case": case, "job": "third", "start": False})
        d2.ok("step", {"job": "third", "n": 10})
        d2.wait_state("third", ["paused"])
        refused({"job": "third", "set": ["dx=0.02"]}, "bad_request", "/args/set/0",
                ["'dx'", "set-up"])
        refused({"job": "third", "set": ["time.end=0.4", "output.fields=[\"pos\"]"]},
                "bad_request", "/args/set/1", ["output.fields", "output.every"])
        refused({"job": "third", "set": ["physics.viscosity.alpha=-1"]}, "invalid_case",
                "/physics/viscosity/alpha", ["alpha"])
        refused({"job": "third", "set": ["time.end=0.0001"]}, "invalid_case", "/time/end",
                ["already"])
        refused({"job": "third", "set": "alpha"}, "bad_request", "/args/set", [])
        refused({"job": "live", "set": ["time.cfl=0.1"]}, "bad_state", "/args/job", ["done"])
        st = d2.ok("query", {"job": "third"})
        t.check("steering" not in st or not st["steering"]["history"],
                "a refused change leaves no history", st.get("steering"))
        t.check(d2.request("ping")["ok"], "sphd carries on")
    finally:
        if d2:
            d2.close()
        d.close()
    return t.done()


if __name__ == "__main__":
    sys.exit(main(*sys.argv[1:4]))
