#!/usr/bin/python3
"""Parameter sweeps through a real sphd (local executor): the `sweep` op makes one job per
combination (the product of the lists, the last varying fastest), `list` with `sweep`, the sweep's
table from `export` (CSV and JSON; a wave flume's sweep over the period with its wave analysis),
each job's result equal to the same case submitted alone,
idempotent resubmission, and bad input refused whole (nothing created). With sphctl: `sweep`,
`list --sweep`, `export --sweep`, and `sweep --watch` (lines, --json, a TTY; the exit code of the
worst job; SIGINT leaves the jobs alone).

Usage: sweep_local.py SPHD SPHCTL SOURCE_DIR
"""
import csv
import fcntl
import io
import json
import os
import pty
import re
import signal
import struct
import subprocess
import sys
import termios
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sphd_harness import Daemon, Failures  # noqa: E402

sphd, sphctl, src = sys.argv[1], sys.argv[2], sys.argv[3]
case_file = os.path.join(src, "cases", "dambreak.json")
F = Failures("sweep_local")
d = Daemon(sphd, "--threads", "2", "--max-jobs", "12")
env = dict(os.environ, SPHD_ENDPOINT=d.control)


def ctl(*args):
    p = subprocess.run([sphctl, *args], env=env, capture_output=True, text=True, timeout=120)
    return p.returncode, p.stdout, p.stderr


def wait_done(jobs, timeout=300):
    deadline = time.time() + timeout
    while time.time() < deadline:
        st = {j["job"]: j for j in d.ok("list")["jobs"]}
        if all(st[j]["state"] in ("done", "failed", "stopped") for j in jobs):
            return st
        time.sleep(0.1)
    raise AssertionError(f"{jobs} not finished in {timeout} s")


def wait_listed(sweep, timeout=30):
    deadline = time.time() + timeout
    while time.time() < deadline:
        if d.request("list", {"sweep": sweep}).get("ok"):
            return
        time.sleep(0.05)
    raise AssertionError(f"sweep {sweep} not made in {timeout} s")


def same_result(a, b):
    a, b = dict(a), dict(b)
    a.pop("wall_time", None)
    b.pop("wall_time", None)
    return a == b


try:
    case = json.load(open(case_file))
    fixed = ["dx=0.01", "time.end=0.02"]
    vary = [{"path": "kernel.type", "values": ["wendland_c2", "cubic_spline"]},
            {"path": "time.end", "values": [0.01, 0.02]}]
    r = d.ok("sweep", {"case": case, "set": fixed, "vary": vary, "sweep": "S"})
    ids = [j["job"] for j in r["jobs"]]
    F.check(r["sweep"] == "S" and r["count"] == 4 and ids == ["S-0", "S-1", "S-2", "S-3"],
            "4 jobs S-0..S-3", r)
    want = [{"kernel.type": k, "time.end": t} for k in ("wendland_c2", "cubic_spline")
            for t in (0.01, 0.02)]
    F.check([j["params"] for j in r["jobs"]] == want,
            "params: the product, the last list varying fastest", [j["params"] for j in r["jobs"]])
    F.check(all(j["created"] and j["sweep"] == "S" for j in r["jobs"]), "all created, in S")
    # one combination alone, by submit
    alone = d.ok("submit", {"case": case, "job": "alone",
                            "set": fixed + ["kernel.type=cubic_spline", "time.end=0.01"]})
    st = wait_done(ids + ["alone"])
    F.check(all(st[j]["state"] == "done" for j in ids), "the sweep's jobs are done",
            {j: st[j]["state"] for j in ids})
    res = {j: d.ok("query", {"job": j}).get("result", {}) for j in ids + ["alone"]}
    F.check(same_result(res["S-2"], res["alone"]),
            "S-2 gives what the same case submitted alone gives (bit for bit)",
            {"S-2": res["S-2"].get("diag"), "alone": res["alone"].get("diag")})
    F.check(res["S-0"]["t"] < res["S-1"]["t"], "time.end varied", [res["S-0"]["t"], res["S-1"]["t"]])

    lst = d.ok("list", {"sweep": "S"})["jobs"]
    F.check([j["job"] for j in lst] == ids, "list with sweep: only its jobs", [j["job"] for j in lst])
    F.check(len(d.ok("list")["jobs"]) == 5, "list: all jobs")
    r = d.request("list", {"sweep": "nosuch"})
    F.check(r["error"]["code"] == "not_found", "list of an unknown sweep: not_found", r)

    t = d.ok("export", {"sweep": "S", "format": "json"})
    F.check(t["count"] == 4 and t["params"] == ["kernel.type", "time.end"] and
            t["columns"][:4] == ["job", "state", "kernel.type", "time.end"] and
            "steps" in t["columns"], "export json: columns", t.get("columns"))
    rows = t.get("rows", [])
    F.check([row["job"] for row in rows] == ids and rows[1]["steps"] == res["S-1"]["steps"] and
            rows[3]["kernel.type"] == "cubic_spline", "export json: rows", rows[:2])
    c = d.ok("export", {"sweep": "S"})
    table = list(csv.DictReader(io.StringIO(c["csv"])))
    F.check(c["format"] == "csv" and len(table) == 4 and table[2]["kernel.type"] == "cubic_spline"
            and float(table[2]["time.end"]) == 0.01 and int(table[2]["steps"]) == res["S-2"]["steps"],
            "export csv: the same table", table[:1])

    # a wave flume swept over the period (issue 45): the table carries each job's wave analysis
    # (the result's waves and reflection under dotted names); a coarse, short flume (dx 0.05,
    # no ramp: g1L's window opens at T + distance / cg, about 3 s)
    flume = json.load(open(os.path.join(src, "cases", "wave_flume.json")))
    fset = ["dx=0.05", "wavemaker.layers=3", "wavemaker.ramp=0", "time.end=6",
            "output.every=100"]
    fr = d.ok("sweep", {"case": flume, "set": fset, "sweep": "WF",
                        "vary": [{"path": "wavemaker.waves.period", "values": [1.27, 1.5]}]})
    wait_done([j["job"] for j in fr["jobs"]])
    w = d.ok("export", {"sweep": "WF", "format": "json"})
    cols = w.get("columns", [])
    wrows = w.get("rows", [])
    F.check(all(c in cols for c in ("waves.g1L.height", "waves.g1L.period",
                                    "reflection.coefficient")),
            "export of a flume sweep: the wave analysis' columns", cols)
    F.check(len(wrows) == 2 and all(r.get("waves.g1L.count", 0) >= 1 for r in wrows) and
            abs(wrows[0]["waves.g1L.period"] / 1.27 - 1) < 0.02 and
            abs(wrows[1]["waves.g1L.period"] / 1.5 - 1) < 0.02,
            "export of a flume sweep: each job's measured period is its own",
            [{k: r.get(k) for k in ("wavemaker.waves.period", "waves.g1L.period",
                                    "waves.g1L.height")} for r in wrows])

    # again: the same jobs (created false); another case under the same id: conflict
    r2 = d.ok("sweep", {"case": case, "set": fixed, "vary": vary, "sweep": "S"})
    F.check([j["created"] for j in r2["jobs"]] == [False] * 4, "resubmitted: the same jobs")
    r3 = d.request("sweep", {"case": case, "set": ["dx=0.02"], "vary": vary, "sweep": "S"})
    F.check(r3["error"]["code"] == "conflict", "a different case under the same sweep id", r3)

    # bad input: nothing is created
    n0 = len(d.ok("list")["jobs"])
    bad = [
        ({"vary": []}, "bad_request", "/args/vary"),
        ({"vary": [{"path": "dx"}]}, "bad_request", "/args/vary/0"),
        ({"vary": [{"path": "dx", "values": []}]}, "bad_request", "/args/vary/0/values"),
        ({"vary": [{"path": "dx", "values": [0.01]}, {"path": "dx", "values": [0.02]}]},
         "bad_request", "/args/vary/1/path"),
        ({"vary": [{"path": "kernel.type", "values": ["wendland_c2", "no_such_kernel"]}]},
         "invalid_case", "/kernel/type"),
        ({"vary": [{"path": "dx", "values": [0.01, 1e-7]}]}, "too_large", "/dx"),
        ({"vary": [{"path": "dx", "values": list(range(1, 101))},
                   {"path": "time.end", "values": list(range(1, 101))},
                   {"path": "h", "values": [1, 2]}]}, "too_large", "/args/vary"),
        ({"vary": [{"path": "time.end", "values": [0.1] * 13}]}, "busy", None),
        ({"vary": [{"path": "dx", "values": [0.01, 0.02]}], "sweep": "../x"}, "bad_request",
         "/args/sweep"),
    ]
    for args, code, path in bad:
        a = {"case": case, "set": fixed}
        a.update(args)
        r = d.request("sweep", a)
        e = r.get("error", {})
        F.check(e.get("code") == code and e.get("path") == path,
                f"refused: {code} at {path}", r)
    F.check(len(d.ok("list")["jobs"]) == n0, "nothing was created by the refused sweeps")
    r = d.request("export", {"sweep": "nosuch"})
    F.check(r["error"]["code"] == "not_found", "export of an unknown sweep: not_found", r)
    r = d.request("export", {"job": "alone", "sweep": "S"})
    F.check(r["error"]["code"] == "bad_request", "export with job and sweep: bad_request", r)

    # sphctl
    rc, out, err = ctl("--json", "sweep", case_file, "--set", "dx=0.01", "--set",
                       "time.end=0.01,0.02", "--id", "C")
    F.check(rc == 0, "sphctl sweep", err)
    if rc == 0:
        r = json.loads(out)
        F.check(r["sweep"] == "C" and r["count"] == 2 and
                [j["params"] for j in r["jobs"]] == [{"time.end": 0.01}, {"time.end": 0.02}],
                "sphctl sweep: two jobs with their params", r)
        wait_done(["C-0", "C-1"])
    rc, out, err = ctl("--json", "list", "--sweep", "C")
    F.check(rc == 0 and [j["job"] for j in json.loads(out or "{}").get("jobs", [])] ==
            ["C-0", "C-1"], "sphctl list --sweep", out + err)
    rc, out, err = ctl("export", "--sweep", "C")
    F.check(rc == 0 and out.splitlines()[0].startswith("job,state,time.end") and
            len(out.splitlines()) == 3, "sphctl export --sweep: CSV", out + err)
    rc, out, err = ctl("sweep", case_file, "--set", "dx=0.01")
    F.check(rc == 64, "sphctl sweep without a varied --set: usage error", (rc, err))

    # sphctl sweep --watch, stdout not a TTY: the table, then a line per change of state, then
    # the summary; exit 0 when every job is done
    two = ["--set", "dx=0.01", "--set", "time.end=0.01,0.02"]
    rc, out, err = ctl("sweep", case_file, *two, "--id", "W", "--watch")
    F.check(rc == 0, "sphctl sweep --watch: exit 0, every job done", (rc, err))
    F.check(all(re.search(rf"^W-{k}\s+time\.end={t}\s+done\b", out, re.M)
                for k, t in ((0, 0.01), (1, 0.02))) and
            out.splitlines()[-1:] == ["sweep W: 2 jobs: 2 done"],
            "sphctl sweep --watch: each job's final state, then the summary", out + err)
    # with --json: one document once all have ended, every job final
    rc, out, err = ctl("--json", "sweep", case_file, *two, "--id", "WJ", "--watch")
    try:
        r = json.loads(out)
    except ValueError:
        r = {}
    F.check(rc == 0 and r.get("sweep") == "WJ" and r.get("count") == 2 and
            [(j["job"], j["state"]) for j in r.get("jobs", [])] ==
            [("WJ-0", "done"), ("WJ-1", "done")], "sphctl --json sweep --watch: the final statuses",
            (rc, out, err))
    # on a TTY: a block redrawn in place on stderr, each job's final line in its last draw
    master, slave = pty.openpty()
    fcntl.ioctl(slave, termios.TIOCSWINSZ, struct.pack("HHHH", 40, 200, 0, 0))
    p = subprocess.Popen([sphctl, "sweep", case_file, *two, "--id", "WT", "--watch"], env=env,
                         stdin=subprocess.DEVNULL, stdout=slave, stderr=slave)
    os.close(slave)
    tty = b""
    while True:
        try:
            chunk = os.read(master, 65536)
        except OSError:  # EIO: the process has closed the terminal
            break
        if not chunk:
            break
        tty += chunk
    os.close(master)
    rc = p.wait(timeout=60)
    last = tty.decode(errors="replace").split("\x1b[J")[-1]
    F.check(rc == 0 and "sweep WT: 2 jobs: 2 done" in last and
            all(re.search(rf"WT-{k}\s+time\.end=[0-9.]+\s+done\b", last) for k in (0, 1)),
            "sphctl sweep --watch on a TTY: the last draw has every job done", (rc, last))
    # the worst job's exit code: one stopped, one done -> 1 (as watch: done 0, failed or stopped 1)
    p = subprocess.Popen([sphctl, "sweep", case_file, *two, "--id", "M", "--no-start", "--watch"],
                         env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    wait_listed("M")
    d.ok("stop", {"job": "M-0"})
    d.ok("start", {"job": "M-1"})
    out, err = p.communicate(timeout=120)
    F.check(p.returncode == 1 and re.search(r"^M-0\s+\S+\s+stopped\b", out, re.M) and
            re.search(r"^M-1\s+\S+\s+done\b", out, re.M),
            "sphctl sweep --watch: exit 1 when a job was stopped, the others done", (out, err))
    # Ctrl-C stops watching; the jobs are left as they are
    p = subprocess.Popen([sphctl, "sweep", case_file, *two, "--id", "I", "--no-start", "--watch"],
                         env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    head = [p.stdout.readline() for _ in range(3)]  # the table: the watch is on
    p.send_signal(signal.SIGINT)
    p.wait(timeout=30)
    F.check(head[-1] == "sweep I: 2 jobs\n" and p.returncode == -signal.SIGINT and
            [j["state"] for j in d.ok("list", {"sweep": "I"})["jobs"]] == ["paused", "paused"],
            "sphctl sweep --watch: SIGINT ends the watch, the jobs stay", (head, p.returncode))
    F.check(d.shutdown() == 0, "sphd shuts down cleanly", d.log()[-2000:])
finally:
    d.close()
sys.exit(F.done())
