#!/usr/bin/python3
"""The lifecycle of a long, stepped job (a coarse dam break, "method": "wcsph"), driven with pyzmq
and with sphctl: step N, step --until T, query particles (downsampled), pause, resume, stop,
watch to done, the diag rate limit, shutdown with a running job (paused and recorded).

Usage: lifecycle_wcsph.py SPHD SPHCTL SOURCE_DIR
"""
import json
import os
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sphd_harness import Daemon, Failures  # noqa: E402

sphd, sphctl, src = sys.argv[1], sys.argv[2], sys.argv[3]
case_file = os.path.join(src, "cases", "dambreak.json")
if not os.path.exists(case_file):
    print("FAIL: cases/dambreak.json is missing")
    sys.exit(1)

F = Failures("lifecycle_wcsph")
DIAG_RATE = 20
d = Daemon(sphd, "--threads", "2", "--diag-rate", str(DIAG_RATE))
log = ""
try:
    if "wcsph" not in d.ok("hello")["methods"]:
        print("FAIL: this sphd does not list wcsph among its methods")
        d.shutdown()
        sys.exit(1)
    case = json.load(open(case_file))
    coarse = ["dx=0.01", "time.end=0.25"]  # seconds of work, even under ASan
    env = dict(os.environ, SPHD_ENDPOINT=d.control)

    def ctl(*args, timeout=60):
        p = subprocess.run([sphctl, *args], env=env, capture_output=True, text=True,
                           timeout=timeout)
        return p.returncode, p.stdout, p.stderr

    def progress(job):
        return d.ok("query", {"job": job})["progress"]

    # -- step a job that was never started: N steps, then paused
    r = d.ok("submit", {"case": case, "job": "db", "set": coarse, "start": False})
    F.check(r["state"] == "paused" and r["progress"]["steps"] == 0, "submitted paused", r)
    r = d.request("query", {"job": "db", "fields": ["pos"]})
    F.check(r["error"]["code"] == "bad_state", "no particles before the first run", r)
    r = d.request("submit", {"case": case, "set": ["dx=1e-7"]})
    F.check(r["error"]["code"] == "too_large" and r["error"]["path"] == "/dx",
            "a case too large for memory: too_large at /dx", r)
    sub = d.subscribe(b"db")
    time.sleep(0.1)
    d.ok("step", {"job": "db", "n": 5})
    time.sleep(0.05)
    st = d.wait_state("db", ("paused",))
    while st.get("pending_step"):
        st = d.wait_state("db", ("paused",))
    F.check(st["progress"]["steps"] == 5, "step 5: five steps, then paused", st["progress"])
    rc, out, err = ctl("--json", "step", "db", "3")
    F.check(rc == 0, "sphctl step db 3", err)
    time.sleep(0.05)
    for _ in range(500):
        st = d.ok("query", {"job": "db"})
        if st["state"] == "paused" and not st.get("pending_step"):
            break
        time.sleep(0.01)
    F.check(st["progress"]["steps"] == 8, "sphctl step 3: eight steps in all", st["progress"])
    d.ok("step", {"job": "db", "until": 0.02})
    for _ in range(1000):
        st = d.ok("query", {"job": "db"})
        if st["state"] == "paused" and not st.get("pending_step"):
            break
        time.sleep(0.01)
    t = st["progress"]["t"]
    F.check(st["state"] == "paused" and abs(t - 0.02) < 1e-9, "step until 0.02: t = 0.02, paused",
            st["progress"])
    rc, out, err = ctl("step", "db", "--until", "0.03")
    F.check(rc == 0, "sphctl step --until", err)

    # -- particles of a paused job, downsampled (once the step has ended: a query with fields
    # while a step runs may get `busy`, ask again, which a loaded machine showed)
    for _ in range(1000):
        st = d.ok("query", {"job": "db"})
        if st["state"] == "paused" and not st.get("pending_step"):
            break
        time.sleep(0.01)
    q = d.ok("query", {"job": "db", "fields": ["pos", "rho"], "max": 10})
    parts = q.get("particles", {})
    F.check(parts.get("count", 99) <= 10 and len(parts.get("fields", {}).get("pos", [])) <= 10,
            "query fields, max 10", parts)
    r = d.request("query", {"job": "db", "fields": ["nosuchfield"]})
    F.check(not r["ok"] and r["error"]["code"] in ("bad_request", "invalid_case"),
            "an unknown particle field is refused", r)
    rc, out, err = ctl("query", "db", "--fields", "pos", "--max", "5")
    F.check(rc == 0 and json.loads(out)["particles"]["count"] <= 5, "sphctl query --fields --max",
            err)

    # -- a job long enough to catch running: particles from its worker, pause (the reply comes
    # once it is paused), a paused job does not advance, resume, stop
    d.ok("submit", {"case": case, "job": "long", "set": ["dx=0.01", "time.end=1000"]})
    d.wait_state("long", ("running",))
    time.sleep(0.1)
    q = d.request("query", {"job": "long", "fields": ["pos"], "max": 3})
    F.check(q["ok"] and q["result"]["particles"]["count"] <= 3 and
            q["result"]["state"] == "running", "particles of a running job (from its worker)", q)
    p = d.ok("pause", {"job": "long"})
    F.check(p["state"] == "paused", "pause replies when the job is paused", p)
    s1 = p["progress"]["steps"]
    F.check(s1 > 0, "it had run", p["progress"])
    time.sleep(0.2)
    F.check(progress("long")["steps"] == s1, "a paused job does not advance")
    rc, out, err = ctl("resume", "long")
    F.check(rc == 0, "sphctl resume", err)
    d.wait_state("long", ("running",))
    time.sleep(0.1)
    F.check(progress("long")["steps"] > s1, "a resumed job advances")
    s = d.ok("stop", {"job": "long"})
    F.check(s["state"] == "stopped", "stop replies when the job is stopped", s)

    # -- the stepped job: resume and watch it to the end
    st = d.ok("resume", {"job": "db"})
    F.check(st["state"] in ("queued", "running"), "resume", st)
    t0 = time.time()
    rc, out, err = ctl("--json", "watch", "db", timeout=600)
    wall = time.time() - t0
    F.check(rc == 0, "sphctl watch exits 0 when the job is done", (rc, err[-500:]))
    lines = [json.loads(l) for l in out.splitlines()]
    F.check(lines and lines[-1].get("type") == "state" and lines[-1].get("state") == "done",
            "watch ends with the done state", lines[-1:])
    diags = [e for e in lines if e.get("type") == "diag"]
    F.check(diags and len(diags) <= DIAG_RATE * wall + 5,
            f"at most {DIAG_RATE} diag events per second ({len(diags)} in {wall:.2f} s)")
    F.check(all(k in diags[-1] for k in ("step", "t", "dt", "ekin", "vmax", "rho_min")),
            "diag events carry the diagnostics", diags[-1:])
    # the subscriber from the start saw every event in order
    seqs, states = [], []
    while sub.poll(100):
        topic, body = sub.recv_multipart()
        ev = json.loads(body)
        seqs.append(ev["seq"])
        if ev["type"] == "state":
            states.append(ev["state"])
    F.check(seqs == list(range(seqs[0], seqs[0] + len(seqs))), "no gap in seq", seqs[:20])
    F.check(states[:2] == ["running", "paused"] and states[-1] == "done",
            "state events: running, paused, ..., done", states)
    st = d.ok("query", {"job": "db"})
    F.check(st["state"] == "done" and st["result"]["method"] == "wcsph", "done, with a result",
            st["state"])
    r = d.request("step", {"job": "db", "n": 1})
    F.check(r["error"]["code"] == "bad_state", "step on a finished job: bad_state", r)

    # -- stop a running job; sphctl stop / pause on the second one
    d.ok("submit", {"case": case, "job": "db2", "set": ["dx=0.01", "time.end=1000"]})
    d.wait_state("db2", ("running",))
    time.sleep(0.1)
    s = d.ok("stop", {"job": "db2"})
    F.check(s["state"] == "stopped", "stop replies when the job is stopped", s)
    rc, out, err = ctl("watch", "db2")
    F.check(rc == 1, "sphctl watch of a stopped job exits 1", rc)
    d.ok("submit", {"case": case, "job": "db3", "set": ["dx=0.01", "time.end=1000"]})
    d.wait_state("db3", ("running",))
    rc, out, err = ctl("--json", "pause", "db3")
    F.check(rc == 0 and json.loads(out)["state"] == "paused", "sphctl pause", (rc, out, err))
    rc, out, err = ctl("resume", "db3")
    F.check(rc == 0, "sphctl resume", err)
    rc, out, err = ctl("stop", "db3")
    F.check(rc == 0 and "stopped" in out, "sphctl stop", (rc, out, err))

    # -- a job that blows up: failed, with the reason; watch exits 1
    d.ok("submit", {"case": case, "job": "boom", "set": ["dx=0.01", "time.dt=0.001"]})
    rc, out, err = ctl("--json", "watch", "boom", timeout=120)
    last = json.loads(out.splitlines()[-1]) if out else {}
    final = last.get("state") or last.get("status", {}).get("state")  # event, or snapshot
    F.check(rc == 1 and final == "failed", "sphctl watch of a failed job exits 1",
            (rc, last))
    st = d.ok("query", {"job": "boom"})
    F.check(st["state"] == "failed" and st.get("reason", "").startswith("unstable"),
            "query says why the job failed", st.get("reason"))
    F.check(d.request("ping")["ok"], "the daemon is fine after a failed job")

    # -- shutdown with a running job: paused at a step boundary, recorded, exit 0
    d.ok("submit", {"case": case, "job": "db4", "set": ["dx=0.01", "time.end=1000"]})
    d.wait_state("db4", ("running",))
    deadline = time.time() + 60  # a first step done, however loaded the machine
    while time.time() < deadline and d.ok("query", {"job": "db4"})["progress"]["steps"] == 0:
        time.sleep(0.05)
    F.check(d.shutdown() == 0, "shutdown with a running job: exit 0")
    rec = json.load(open(os.path.join(d.state, "jobs", "db4", "job.json")))
    F.check(rec["state"] == "paused" and rec["resumable"] and rec["interrupted_by_shutdown"]
            and rec["progress"]["steps"] > 0, "the running job was paused and recorded", rec)
finally:
    log = d.log()
    d.close()
sys.exit(F.done(log))
