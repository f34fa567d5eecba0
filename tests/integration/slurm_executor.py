#!/usr/bin/python3
"""sphd's Slurm executor against a real Slurm: a one-node cluster on this machine
(scripts/slurm-local.sh: Debian's slurm-wlm and munge, as root), started here and stopped at the
end. Every job's result is compared with the same case run by the local executor (1 thread both):
the result and the last snapshot bit for bit.

- a sweep of 4 dam breaks goes as one Slurm array and runs to done;
- watch (sphctl), query with fields while the runner runs, step N (a Slurm job that ends paused);
- a stray second runner of a running job is told to quit (a job never runs twice);
- kill -9 of a runner: the job is submitted again and continues from its checkpoint;
- scancel: the job is paused with the reason; resume continues it;
- kill -9 of the daemon while two Slurm jobs run, one with a pause pending: after a restart both
  are found, the stream's seq goes on with no gap and no repeat, the paused one ends paused and
  both finish;
- CURVE: the runners use their own key pair (kept by sphd in STATE/runner), which opens the
  runners' socket only; a client's key does not;
- a slow sbatch does not hold up the daemon (it runs on sphd's Slurm thread);
- a node that cannot reach the daemon: the job fails with the runner's last words;
- bad input: an unknown resources key, a refused sbatch option, a partition Slurm refuses, a time
  limit over the partition's, the Slurm executor on a daemon without it, sphd --executor slurm
  without sbatch.

Usage: slurm_executor.py SPHD SPHCTL SOURCE_DIR     (exit 77: skipped, not root or no Slurm)
"""
import json
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sphd_harness import Daemon, Failures  # noqa: E402

sphd, sphctl, src = sys.argv[1], sys.argv[2], sys.argv[3]
if os.geteuid() != 0 or not (shutil.which("slurmctld") or os.path.exists("/usr/sbin/slurmctld")):
    print("slurm_executor: skipped (needs root and slurm-wlm + munge: scripts/setup.sh)")
    sys.exit(77)
import h5py  # noqa: E402
import numpy as np  # noqa: E402

F = Failures("slurm_executor")
T0 = time.time()
cluster = tempfile.mkdtemp(prefix="sphd-slurm-")
port = 17000 + os.getpid() % 2000
env = dict(os.environ, SLURM_CONF=os.path.join(cluster, "slurm.conf"),
           SLURM_LOCAL_PORT=str(16817 + 2 * (os.getpid() % 400)))
os.environ.update(SLURM_CONF=env["SLURM_CONF"])
r = subprocess.run([os.path.join(src, "scripts", "slurm-local.sh"), "start", cluster], env=env,
                   capture_output=True, text=True)
if r.returncode != 0:
    print("FAIL: the one-node Slurm cluster did not start:", r.stderr)
    subprocess.run([os.path.join(src, "scripts", "slurm-local.sh"), "stop", cluster], env=env)
    sys.exit(1)
print(f"slurm_executor: a one-node Slurm cluster up in {time.time() - T0:.1f} s")
case = json.load(open(os.path.join(src, "cases", "dambreak.json")))
BASE = ["dx=0.01", "time.end=0.1", "output.every=0.05"]
daemons = []


def start(state=None, *extra):
    d = Daemon(sphd, "--threads", "1", "--checkpoint-interval", "0.2", "--executor", "slurm",
               "--runner-listen", f"tcp://127.0.0.1:{port}", *extra)
    daemons.append(d)
    return d


def wait_states(d, jobs, states, timeout=180):
    deadline = time.time() + timeout
    st = {}
    while time.time() < deadline:
        st = {j["job"]: j for j in d.ok("list")["jobs"]}
        if all(st.get(j, {}).get("state") in states for j in jobs):
            return st
        time.sleep(0.1)
    raise AssertionError(f"{jobs} not {states} in {timeout} s: "
                         f"{ {j: st.get(j, {}).get('state') for j in jobs} }")


def slurm_ids(d, jobs, timeout=30):
    """The jobs' Slurm ids, once sbatch (on sphd's Slurm thread) has given them."""
    deadline = time.time() + timeout
    while time.time() < deadline:
        st = {j["job"]: j for j in d.ok("list")["jobs"]}
        sj = [st[j].get("slurm_job", "") for j in jobs]
        if all(sj):
            return sj
        time.sleep(0.05)
    return sj


def last_snapshot(d, job):
    jd = os.path.join(d.state, "jobs", job)
    snaps = sorted(f for f in os.listdir(jd) if f.startswith("snap_"))
    with h5py.File(os.path.join(jd, snaps[-1]), "r") as h:
        return snaps[-1], {k: np.array(h[k]) for k in ("pos", "vel", "rho", "p")}


def same_run(d, a, b):
    """a's and b's results (less the wall times) and last snapshots, bit for bit."""
    ra, rb = (json.load(open(os.path.join(d.state, "jobs", j, "result.json"))) for j in (a, b))
    for r in (ra, rb):
        r.pop("wall_time", None)
    sa, fa = last_snapshot(d, a)
    sb, fb = last_snapshot(d, b)
    return ra == rb and sa == sb and all(np.array_equal(fa[k], fb[k]) for k in fa)


def runner_pids(job):
    out = subprocess.run(["pgrep", "-f", "--", f"--job-dir \\S*/{job}( |$)"], capture_output=True,
                         text=True).stdout
    return [int(p) for p in out.split()]


try:
    d = start()
    h = d.ok("hello")
    F.check("slurm" in h.get("executors", []), "hello lists the Slurm executor", h.get("executors"))

    # -- a sweep of 4 as one array, against the local executor
    t = time.time()
    r = d.ok("sweep", {"case": case, "set": BASE, "sweep": "A",
                       "vary": [{"path": "kernel.type", "values": ["wendland_c2", "cubic_spline"]},
                                {"path": "physics.viscosity.alpha", "values": [0.05, 0.1]}]})
    ids = [j["job"] for j in r["jobs"]]
    sj = slurm_ids(d, ids)
    F.check(len({s.split("_")[0] for s in sj}) == 1 and [s.split("_")[-1] for s in sj] ==
            ["0", "1", "2", "3"], "the sweep is one Slurm array, task i is job A-i", sj)
    locals_ = []
    for j in r["jobs"]:
        sets = BASE + [f"{k}={json.dumps(v)}" for k, v in j["params"].items()]
        loc = d.ok("submit", {"case": case, "job": "L" + j["job"], "set": sets,
                              "resources": {"executor": "local"}})
        F.check("executor" not in loc, "resources.executor local keeps a job here", loc)
        locals_.append("L" + j["job"])
    st = wait_states(d, ids + locals_, ("done", "failed", "stopped"))
    F.check(all(st[j]["state"] == "done" for j in ids), "the array's 4 jobs are done",
            {j: (st[j]["state"], st[j].get("reason")) for j in ids})
    print(f"slurm_executor: sweep of 4 as a Slurm array done in {time.time() - t:.1f} s")
    for j in ids:
        F.check(same_run(d, j, "L" + j), f"{j} (Slurm) is bit for bit L{j} (local)")
    # the same sweep with one more kernel: only its 2 new jobs go to Slurm, as tasks 4 and 5
    r = d.ok("sweep", {"case": case, "set": BASE, "sweep": "A",
                       "vary": [{"path": "kernel.type",
                                 "values": ["wendland_c2", "cubic_spline", "gaussian"]},
                                {"path": "physics.viscosity.alpha", "values": [0.05, 0.1]}]})
    F.check([j["created"] for j in r["jobs"]] == [False] * 4 + [True] * 2,
            "a sweep grown by a value: the 2 new jobs are made", [j["created"] for j in r["jobs"]])
    sj = slurm_ids(d, ["A-4", "A-5"])
    F.check([s.split("_")[-1] for s in sj] == ["4", "5"],
            "the new jobs are tasks 4 and 5 of a new array (task K runs job A-K)", sj)
    d.ok("submit", {"case": case, "job": "LA-5", "resources": {"executor": "local"},
                    "set": BASE + ['kernel.type="gaussian"', "physics.viscosity.alpha=0.1"]})
    wait_states(d, ["A-4", "A-5", "LA-5"], ("done",))
    F.check(same_run(d, "A-5", "LA-5"), "A-5 (task 5) is bit for bit its local run")
    rows = d.ok("export", {"sweep": "A", "format": "json"})["rows"]
    F.check(len(rows) == 6 and all(row.get("steps", 0) > 0 for row in rows),
            "the sweep's table has the 6 results", rows[:1])

    # -- sphctl sweep --resources: one array too
    envc = dict(os.environ, SPHD_ENDPOINT=d.control)
    p = subprocess.run([sphctl, "--json", "sweep", os.path.join(src, "cases", "dambreak.json"),
                        "--set", "dx=0.01", "--set", "time.end=0.02,0.03", "--id", "B",
                        "--resources", '{"partition": "debug", "threads": 1}'], env=envc,
                       capture_output=True, text=True, timeout=60)
    F.check(p.returncode == 0, "sphctl sweep --resources", p.stderr)
    if p.returncode == 0:
        jobs = json.loads(p.stdout)["jobs"]
        sj = slurm_ids(d, [j["job"] for j in jobs])
        F.check(len({s.split("_")[0] for s in sj}) == 1 and
                all(j.get("resources", {}).get("partition") == "debug" for j in jobs),
                "sphctl sweep --resources: one array, the resources on each job", jobs[:1])
        wait_states(d, ["B-0", "B-1"], ("done",))

    # -- submission to first diagnostic: Slurm against local
    def first_diag(resources):
        sub = d.subscribe(b"")
        time.sleep(0.2)
        t = time.time()
        jid = d.ok("submit", {"case": case, "set": BASE, "resources": resources})["job"]
        while True:
            if not sub.poll(60000):
                raise AssertionError("no diag within 60 s")
            topic, body = sub.recv_multipart()
            ev = json.loads(body)
            if ev["job"] == jid and ev["type"] == "diag":
                sub.close()
                wait_states(d, [jid], ("done",))
                return time.time() - t
    loc_s = sorted(first_diag({"executor": "local"}) for _ in range(3))[1]
    slu_s = sorted(first_diag({}) for _ in range(3))[1]
    print(f"slurm_executor: submission to first diagnostic, median of 3: local {loc_s * 1e3:.0f} "
          f"ms, Slurm {slu_s * 1e3:.0f} ms (overhead {(slu_s - loc_s) * 1e3:.0f} ms)")

    # -- watch, query with fields, step
    long_sets = ["dx=0.005", "time.end=0.45", "output.every=0.1"]
    d.ok("submit", {"case": case, "job": "W", "set": long_sets})
    envc = dict(os.environ, SPHD_ENDPOINT=d.control)
    w = subprocess.Popen([sphctl, "--json", "watch", "W"], env=envc, stdout=subprocess.PIPE,
                         stderr=subprocess.PIPE, text=True)
    deadline = time.time() + 60
    q = None
    while time.time() < deadline:
        st = d.ok("query", {"job": "W"})
        if st["state"] == "running" and st["progress"]["steps"] > 0:
            q = d.request("query", {"job": "W", "fields": ["pos", "rho"], "max": 50}, timeout=30)
            if q.get("ok"):
                break
        time.sleep(0.1)
    F.check(q and q.get("ok") and q["result"]["particles"]["count"] == 50,
            "query with fields of a running Slurm job: its runner answers", str(q)[:300])
    # a second runner of the same job (a stray run): told to quit, the job runs once
    stray = subprocess.Popen([sphd, "--runner", f"tcp://127.0.0.1:{port}", "--job-dir",
                              os.path.join(d.state, "jobs", "W"), "--runner-wait", "20"],
                             env=dict(os.environ, SLURM_JOB_ID="424242"),
                             stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        src_rc = stray.wait(timeout=15)
    except subprocess.TimeoutExpired:
        stray.kill()
        src_rc = None
    F.check(src_rc == 0 and "W@424242 has no job to run here" in d.log(),
            "a stray second runner of a running job is told to quit", src_rc)
    out, err = w.communicate(timeout=300)
    evs = [json.loads(x) for x in out.splitlines() if x.strip()]
    F.check(w.returncode == 0 and any(e.get("type") == "diag" for e in evs) and
            evs[-1].get("type") in ("result", "state"), "sphctl watch follows a Slurm job to done",
            (w.returncode, err[-300:]))
    d.ok("submit", {"case": case, "job": "S", "set": BASE, "start": False})
    d.ok("step", {"job": "S", "n": 25})
    st = wait_states(d, ["S"], ("paused",))
    deadline = time.time() + 60
    while st["S"].get("pending_step") or st["S"]["progress"]["steps"] < 25:
        if time.time() > deadline:
            break
        time.sleep(0.1)
        st = wait_states(d, ["S"], ("paused",))
    F.check(st["S"]["progress"]["steps"] == 25, "step 25 on the Slurm executor: 25 steps, paused",
            st["S"]["progress"])
    q = d.request("query", {"job": "S", "fields": ["pos", "rho"], "max": 10}, timeout=30)
    F.check(q.get("ok") and q["result"]["particles"]["count"] == 10,
            "query with fields of a paused Slurm job: read from its checkpoint", str(q)[:300])
    d.ok("resume", {"job": "S"})
    d.ok("submit", {"case": case, "job": "LS", "set": BASE, "resources": {"executor": "local"}})
    wait_states(d, ["S", "LS"], ("done",))
    F.check(same_run(d, "S", "LS"), "stepped, paused (Slurm job ended) and resumed: bit for bit")

    # -- kill -9 of a runner: submitted again, continues from the checkpoint
    d.ok("submit", {"case": case, "job": "K", "set": long_sets})
    deadline = time.time() + 60
    while time.time() < deadline:
        st = d.ok("query", {"job": "K"})
        if st["progress"]["steps"] > 200 and os.path.exists(
                os.path.join(d.state, "jobs", "K", "checkpoint")) and runner_pids("K"):
            break
        time.sleep(0.1)
    first = st.get("slurm_job")
    for p in runner_pids("K"):
        os.kill(p, signal.SIGKILL)
    st = None
    deadline = time.time() + 60
    while time.time() < deadline:
        st = d.ok("query", {"job": "K"})
        if st.get("slurm_job") != first and st.get("retries") == 1:
            break
        time.sleep(0.2)
    F.check(st.get("retries") == 1 and st.get("slurm_job") != first,
            "a runner killed: its job goes to a new Slurm job (retry 1)", st)
    d.ok("submit", {"case": case, "job": "LK", "set": long_sets,
                    "resources": {"executor": "local"}})
    wait_states(d, ["K", "LK"], ("done",), timeout=300)
    F.check(same_run(d, "K", "LK"), "the killed job's result is bit for bit the local one")

    # -- scancel: paused with the reason, resume continues
    d.ok("submit", {"case": case, "job": "C", "set": long_sets})
    deadline = time.time() + 60
    while time.time() < deadline:
        st = d.ok("query", {"job": "C"})
        if st["progress"]["steps"] > 100 and os.path.exists(
                os.path.join(d.state, "jobs", "C", "checkpoint")):
            break
        time.sleep(0.1)
    subprocess.run(["scancel", st["slurm_job"]], check=True)
    st = wait_states(d, ["C"], ("paused",), timeout=60)["C"]
    F.check("cancelled" in st.get("reason", ""), "scancel: the job is paused and says why", st)
    d.ok("resume", {"job": "C"})
    wait_states(d, ["C", "LK"], ("done",), timeout=300)
    F.check(same_run(d, "C", "LK"), "cancelled and resumed: bit for bit the local run")

    # -- kill -9 of the daemon while two Slurm jobs run (one node with room for both:
    # scripts/slurm-local.sh), D2 with a pause pending. Long enough (about 10 s each here) that
    # D1 is still running through the kill, the restart and its first events after it.
    d_sets = ["dx=0.005", "time.end=2.0", "output.every=0.5"]
    for j in ("D1", "D2"):
        d.ok("submit", {"case": case, "job": j, "set": d_sets})
    deadline = time.time() + 60
    while time.time() < deadline:
        st = {j["job"]: j for j in d.ok("list")["jobs"]}
        if all(st[j]["progress"]["steps"] > 50 and runner_pids(j) for j in ("D1", "D2")):
            break
        time.sleep(0.1)
    seq0 = {j: st[j]["seq"] for j in ("D1", "D2")}
    # D2 is paused just before the kill: its runner held (SIGSTOP) until after the restart so
    # that the pause is pending when sphd dies; after the restart it still ends paused (issue 47)
    sub1 = d.subscribe(b"D1")
    time.sleep(0.3)
    held = runner_pids("D2")
    for p in held:
        os.kill(p, signal.SIGSTOP)
    pause = subprocess.Popen([sphctl, "--endpoint", d.control, "--json", "pause", "D2"],
                             stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    j2 = os.path.join(d.state, "jobs", "D2", "journal.jsonl")
    deadline = time.time() + 10
    while time.time() < deadline and '"pause":true' not in open(j2).read():
        time.sleep(0.05)
    F.check('"pause":true' in open(j2).read(), "a pause of a running Slurm job is journaled")
    seen1 = []  # D1's seqs on the stream up to the kill (it publishes all the while)
    until = time.time() + 1.0
    while time.time() < until and sub1.poll(200):
        seen1.append(json.loads(sub1.recv_multipart()[1])["seq"])
    st = {j["job"]: j for j in d.ok("list")["jobs"]}
    F.check(all(st[j]["state"] == "running" for j in ("D1", "D2")) and len(held) == 1,
            "both Slurm jobs run at the kill, D2's runner held",
            ({j: st[j]["state"] for j in ("D1", "D2")}, held))
    d.proc.send_signal(signal.SIGKILL)
    d.proc.wait()
    pause.kill()
    pause.wait()
    while sub1.poll(100):
        seen1.append(json.loads(sub1.recv_multipart()[1])["seq"])
    sub1.close()

    def journal(j):
        with open(os.path.join(d.state, "jobs", j, "journal.jsonl")) as f:
            return [json.loads(x) for x in f]
    before = {j: journal(j) for j in ("D1", "D2")}
    jseq = {j: max(r.get("seq", 0) for r in before[j]) for j in ("D1", "D2")}
    F.check(bool(seen1) and seen1 == list(range(seen1[0], seen1[-1] + 1)) and
            seen1[0] > seq0["D1"] and seen1[-1] <= jseq["D1"],
            "D1's stream before the kill: no gap, every seq journaled first",
            (seen1[:3], seen1[-3:], jseq["D1"]))
    time.sleep(0.5)
    state = d.state
    d2 = Daemon(sphd, "--threads", "1", "--checkpoint-interval", "0.2", "--executor", "slurm",
                "--runner-listen", f"tcp://127.0.0.1:{port}", "--state-dir", state)
    d2.state = state
    daemons.append(d2)
    st = {j["job"]: j for j in d2.ok("list")["jobs"]}
    F.check(all(st.get(j, {}).get("state") == "running" for j in ("D1", "D2")),
            "after a restart both Slurm jobs are found, running",
            {j: st.get(j, {}).get("state") for j in ("D1", "D2")})
    # D2's runner goes on now: it finds the pause (sent before the kill, or again by the new
    # daemon when it hears from the runner) and ends paused; without the journaled pause the new
    # daemon took its `end: paused` for a stale one and ran it on
    for p in held:
        os.kill(p, signal.SIGCONT)
    # the local run both are compared with, alongside (D2 is held, then paused)
    d2.ok("submit", {"case": case, "job": "LD", "set": d_sets,
                     "resources": {"executor": "local"}})
    sub = d2.subscribe(b"D1")
    got = []  # D1's seqs on the new daemon's stream, every event
    deadline = time.time() + 30
    while time.time() < deadline and len(got) < 20:
        if sub.poll(1000):
            got.append(json.loads(sub.recv_multipart()[1])["seq"])
    sub.close()
    after = {j: journal(j)[len(before[j]):] for j in ("D1", "D2")}
    seqs1 = sorted({r["seq"] for r in after["D1"] if "seq" in r})
    F.check(len(got) == 20 and got == list(range(got[0], got[0] + len(got))) and
            got[0] > jseq["D1"] and set(got) <= set(seqs1),
            "D1's stream comes back after the restart: seq goes on, no gap, no jump",
            (jseq["D1"], got[:3], got[-3:]))
    # the journal after the restart: the seqs after the last one published, one by one
    for j in ("D1", "D2"):
        seqs = sorted({r["seq"] for r in after[j] if "seq" in r})
        F.check(after[j] and after[j][0].get("seq") == jseq[j] + 1 and
                seqs == list(range(jseq[j] + 1, jseq[j] + 1 + len(seqs))),
                f"{j}: after a restart the next event's seq follows the last published (no gap, "
                "no repeat)", (jseq[j], after[j][:2], seqs[-3:]))
    st = wait_states(d2, ["D1", "D2"], ("done", "failed", "paused", "stopped"), timeout=300)
    F.check(st["D1"]["state"] == "done", "D1 finishes", (st["D1"]["state"], st["D1"].get("reason")))
    F.check(st["D2"]["state"] == "paused",
            "a pause pending when sphd was killed: after the restart the job ends paused",
            (st["D2"]["state"], st["D2"].get("reason")))
    d2.ok("resume", {"job": "D2"})
    st = wait_states(d2, ["D2", "LD"], ("done", "failed", "paused", "stopped"), timeout=300)
    F.check(st["D2"]["state"] == "done", "D2, resumed, finishes", st["D2"].get("reason"))
    F.check(same_run(d2, "D1", "LD") and same_run(d2, "D2", "LD"),
            "both are bit for bit the local run")

    # -- bad input
    bad = [
        ({"resources": {"threads": 1, "gpus": 2}}, "bad_request", "/args/resources/gpus"),
        ({"resources": {"sbatch": ["--wrap=rm -rf /"]}}, "bad_request",
         "/args/resources/sbatch/0"),
        ({"resources": {"threads": 0}}, "bad_request", "/args/resources/threads"),
    ]
    for args, code, path in bad:
        a = {"case": case, "set": BASE}
        a.update(args)
        r = d2.request("submit", a)
        F.check(r.get("error", {}).get("code") == code and r["error"].get("path") == path,
                f"refused: {code} at {path}", r)
    for res, words in (({"partition": "nosuch"}, "Invalid partition"),
                       ({"partition": "short", "time_limit": 5}, "time limit")):
        jid = d2.ok("submit", {"case": case, "set": BASE, "resources": res})["job"]
        st = wait_states(d2, [jid], ("failed",), timeout=30)[jid]
        F.check(words in st.get("reason", ""), f"sbatch refuses {res}: failed with its message",
                st.get("reason"))
    # a slow sbatch (3 s) does not hold up the daemon: it runs on sphd's Slurm thread
    slow = tempfile.mkdtemp()
    with open(os.path.join(slow, "sbatch"), "w") as f:
        f.write(f"#!/bin/sh\n[ \"$1\" = --version ] || sleep 3\nexec {shutil.which('sbatch')} \"$@\"\n")
    os.chmod(os.path.join(slow, "sbatch"), 0o755)
    old_path = os.environ["PATH"]
    os.environ["PATH"] = slow + ":" + old_path
    try:
        sd = Daemon(sphd, "--threads", "1", "--executor", "slurm", "--runner-listen",
                    f"tcp://127.0.0.1:{port + 3}")
    finally:
        os.environ["PATH"] = old_path
    daemons.append(sd)
    jid = sd.ok("submit", {"case": case, "set": BASE})["job"]
    t = time.time()
    pong = sd.request("ping")
    ping_s = time.time() - t
    st = sd.ok("query", {"job": jid})
    F.check(pong.get("ok") and ping_s < 0.5 and st["state"] == "running" and
            "slurm_job" not in st,
            "a slow sbatch: ping answered at once while the job waits for sbatch",
            (ping_s, st.get("state"), st.get("slurm_job")))
    F.check(wait_states(sd, [jid], ("done",), timeout=60)[jid]["state"] == "done",
            "and the job runs once sbatch answers")
    shutil.rmtree(slow, ignore_errors=True)

    # a node that cannot reach the daemon: the runner gives up, the job fails with its words
    lost = Daemon(sphd, "--threads", "1", "--executor", "slurm", "--runner-listen",
                  f"tcp://127.0.0.1:{port + 2}", "--runner-connect", "tcp://127.0.0.1:9",
                  "--runner-wait", "2")
    daemons.append(lost)
    jid = lost.ok("submit", {"case": case, "set": BASE, "resources": {"retries": 0}})["job"]
    st = wait_states(lost, [jid], ("failed",), timeout=60)[jid]
    F.check("without a result" in st.get("reason", "") and
            "no word from the daemon" in st.get("reason", ""),
            "a runner that cannot reach the daemon: the job fails with the runner's words",
            st.get("reason"))
    # CURVE: the runners use a key pair that sphd keeps in STATE/runner; a client key does not
    # open the runners' socket
    import zmq
    ctmp = tempfile.mkdtemp(prefix="sphd-slurm-curve-")
    os.makedirs(f"{ctmp}/srv/clients")
    server_pub, server_sec = zmq.curve_keypair()
    alice_pub, alice_sec = zmq.curve_keypair()
    fd = os.open(f"{ctmp}/srv/server.key", os.O_WRONLY | os.O_CREAT, 0o600)
    os.write(fd, server_sec + b"\n")
    os.close(fd)
    with open(f"{ctmp}/srv/clients/alice.pub", "wb") as fh:
        fh.write(alice_pub + b"\n")
    clog = open(f"{ctmp}/sphd.log", "w")
    cport = port + 4
    cproc = subprocess.Popen([sphd, "--curve", f"{ctmp}/srv", "--listen",
                              f"tcp://127.0.0.1:{cport + 1}", "--publish",
                              f"tcp://127.0.0.1:{cport + 2}", "--state-dir", f"{ctmp}/state",
                              "--threads", "1", "--executor", "slurm", "--runner-listen",
                              f"tcp://127.0.0.1:{cport}"], stderr=clog)
    cctx = zmq.Context()
    cs = cctx.socket(zmq.DEALER)
    cs.setsockopt(zmq.LINGER, 0)
    cs.curve_serverkey = server_pub
    cs.curve_publickey, cs.curve_secretkey = alice_pub, alice_sec
    cs.connect(f"tcp://127.0.0.1:{cport + 1}")

    def creq(op, args):
        cs.send(json.dumps({"v": 1, "id": op, "op": op, "args": args}).encode())
        if not cs.poll(10000):
            raise AssertionError(f"no reply to {op} over CURVE")
        return json.loads(cs.recv())
    try:
        r = creq("submit", {"case": case, "job": "V", "set": BASE})
        F.check(r.get("ok"), "CURVE: a job submitted", r)
        deadline = time.time() + 60
        st = {}
        while time.time() < deadline:
            st = creq("query", {"job": "V"}).get("result", {})
            if st.get("state") in ("done", "failed"):
                break
            time.sleep(0.2)
        F.check(st.get("state") == "done", "CURVE: its runner connects with the runner key and "
                "the job is done", st.get("state"))
        kd = f"{ctmp}/state/runner"
        F.check(os.stat(kd).st_mode & 0o777 == 0o700 and
                os.stat(f"{kd}/runner.key").st_mode & 0o777 == 0o600 and
                "--runner-keys" in open(f"{ctmp}/state/jobs/V/slurm.sh").read(),
                "CURVE: the runner key pair is private (700/600) and the script passes it")
        intr = cctx.socket(zmq.DEALER)
        intr.setsockopt(zmq.LINGER, 0)
        intr.setsockopt(zmq.ROUTING_ID, b"V")
        intr.curve_serverkey = server_pub
        intr.curve_publickey, intr.curve_secretkey = alice_pub, alice_sec
        intr.connect(f"tcp://127.0.0.1:{cport}")
        intr.send_multipart([b"hello", b'{"job": "V"}'])
        time.sleep(1.0)
        intr.close()
        clog.flush()
        F.check("refused a client" in open(f"{ctmp}/sphd.log").read(),
                "CURVE: a client key does not open the runners' socket")
        creq("shutdown", {})
        cproc.wait(timeout=30)
    finally:
        if cproc.poll() is None:
            cproc.kill()
            cproc.wait()
        cctx.destroy(linger=0)
        shutil.rmtree(ctmp, ignore_errors=True)

    plain = Daemon(sphd, "--threads", "1")
    daemons.append(plain)
    r = plain.request("submit", {"case": case, "resources": {"executor": "slurm"}})
    F.check(r.get("error", {}).get("path") == "/args/resources/executor",
            "the Slurm executor on a daemon without it: refused at /args/resources/executor", r)
    tmp = tempfile.mkdtemp()
    p = subprocess.run([sphd, "--executor", "slurm", "--listen", f"ipc://{tmp}/c", "--publish",
                        f"ipc://{tmp}/s", "--state-dir", f"{tmp}/st", "--runner-listen",
                        f"tcp://127.0.0.1:{port + 1}"], env=dict(os.environ, PATH="/nonexistent"),
                       capture_output=True, text=True, timeout=30)
    shutil.rmtree(tmp, ignore_errors=True)
    F.check(p.returncode == 69 and "sbatch" in p.stderr,
            "sphd --executor slurm without Slurm: exit 69, says sbatch is missing",
            (p.returncode, p.stderr[-300:]))
    for dd in daemons:
        if dd.proc.poll() is None:
            F.check(dd.shutdown() == 0, "sphd shuts down cleanly", dd.log()[-1500:])
except Exception as e:  # noqa: BLE001
    F.check(False, f"the test ran to its end ({type(e).__name__}: {e})")
    for dd in daemons:
        print(dd.log()[-3000:])
finally:
    for dd in daemons:
        dd.close()
    subprocess.run(["scancel", "--user=root"], capture_output=True)
    subprocess.run([os.path.join(src, "scripts", "slurm-local.sh"), "stop", cluster], env=env)
    shutil.rmtree(cluster, ignore_errors=True)
print(f"slurm_executor: {time.time() - T0:.0f} s in all")
sys.exit(F.done())
