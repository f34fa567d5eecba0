#!/usr/bin/python3
"""sphd driven by an independent pyzmq client: envelopes (REQ and DEALER), bad input of every kind
(each answered with its error code while a job keeps running and the daemon stays up), oversized
messages, clients that vanish mid-request, a subscriber that never reads, idempotent submit,
conflict, the job states on queued jobs, 4 jobs on 2 threads, list, shutdown.

Usage: protocol_pyzmq.py SPHD SOURCE_DIR
"""
import glob
import json
import os
import sys
import time

import zmq

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sphd_harness import Daemon, Failures, big_study  # noqa: E402

sphd, src = sys.argv[1], sys.argv[2]
F = Failures("protocol_pyzmq")
d = Daemon(sphd, "--threads", "2", "--max-jobs", "200")
try:
    ks = json.load(open(os.path.join(src, "cases", "kernel_study.json")))

    # -- hello, envelopes
    h = d.ok("hello")
    F.check(h["stream"] == d.stream, "hello names the stream endpoint", h)
    F.check(h.get("security") == "none", "hello says the sockets are not secured", h)
    F.check(h["ops"] == ["hello", "ping", "submit", "start", "step", "pause", "resume", "query",
                         "stop", "set", "sweep", "list", "shutdown", "results", "fetch",
                         "export"],
            "hello lists the ops", h["ops"])
    F.check(h["protocol"] == 1 and "kernel_study" in h["methods"], "hello: protocol, methods", h)
    ph = h.get("physics", {})
    F.check(ph.get("initial") == ["rest", "standing_wave", "solitary_wave"]
            and ph.get("boundary") == ["dynamic", "ghost", "none"]
            and ph.get("viscosity") == ["artificial", "laminar", "monaghan"],
            "hello: the physics names are the case table's", ph)
    req = d.socket(zmq.REQ)
    r = d.request("ping", sock=req)
    F.check(r["ok"] and r["id"] == "t-ping" and r["v"] == 1, "REQ client (empty delimiter)", r)
    req.close()
    dl = d.socket(zmq.DEALER)
    dl.send_multipart([b"", json.dumps({"v": 1, "id": 7, "op": "ping"}).encode()])
    F.check(dl.poll(5000), "DEALER with its own empty delimiter gets a reply")
    parts = dl.recv_multipart()
    F.check(json.loads(parts[-1])["id"] == 7, "integer ids are echoed", parts)
    dl.close()

    # -- a job that keeps running through the bad input below
    bg = d.ok("submit", {"case": big_study(src, 2500000, "bg"), "job": "bg"})
    F.check(bg["state"] in ("queued", "running") and bg["created"], "background job accepted", bg)

    # and a simulation that runs all along, when this sphd has the solver
    sim = "wcsph" in h["methods"] and os.path.exists(os.path.join(src, "cases", "dambreak.json"))
    if sim:
        db = json.load(open(os.path.join(src, "cases", "dambreak.json")))
        d.ok("submit", {"case": db, "job": "bgsim", "set": ["dx=0.01", "time.end=1000"]})
        sim_steps0 = d.wait_state("bgsim", ("running",))["progress"]["steps"]

    # -- bad input: (what, raw bytes or request dict, code, path or None)
    def req_(op, args=None, **extra):
        m = {"v": 1, "id": "bad", "op": op}
        if args is not None:
            m["args"] = args
        m.update(extra)
        return m

    bad = [
        ("non-JSON bytes", b"\xff\xfe\x00garbage", "bad_request", None),
        ("text that is not JSON", b"hello sphd", "bad_request", None),
        ("truncated JSON", b'{"v": 1, "op": "ping"', "bad_request", None),
        ("JSON array", b"[1, 2]", "bad_request", ""),
        ("JSON string", b'"ping"', "bad_request", ""),
        ("duplicate keys", b'{"v":1,"op":"ping","op":"list"}', "bad_request", None),
        ("missing op", {"v": 1, "id": "x"}, "bad_request", "/op"),
        ("op not a string", {"v": 1, "op": 42}, "bad_request", "/op"),
        ("unknown op", req_("frobnicate"), "unknown_op", "/op"),
        ("wrong protocol version", {"v": 2, "op": "ping"}, "bad_request", "/v"),
        ("v not an integer", {"v": "1", "op": "ping"}, "bad_request", "/v"),
        ("unknown top-level field", req_("ping", extra=1), "bad_request", "/extra"),
        ("id of a wrong type", {"v": 1, "id": [1], "op": "ping"}, "bad_request", "/id"),
        ("args not an object", req_("ping", [1]), "bad_request", "/args"),
        ("unknown argument", req_("ping", {"x": 1}), "bad_request", "/args/x"),
        ("unknown argument of query", req_("query", {"job": "bg", "bogus": 1}), "bad_request",
         "/args/bogus"),
        ("missing argument", req_("submit", {}), "bad_request", "/args/case"),
        ("case not an object", req_("submit", {"case": "cases/x.json"}), "bad_request",
         "/args/case"),
        ("start not a boolean", req_("submit", {"case": ks, "start": "yes"}), "bad_request",
         "/args/start"),
        ("set not an array", req_("submit", {"case": ks, "set": "dx=1"}), "bad_request",
         "/args/set"),
        ("set item not a string", req_("submit", {"case": ks, "set": [1]}), "bad_request",
         "/args/set/0"),
        ("set making the case invalid", req_("submit", {"case": ks, "set": ["particles=2"]}),
         "invalid_case", "/particles"),
        ("set through a number", req_("submit", {"case": ks, "set": ["particles.x=2"]}),
         "invalid_case", "/particles/x"),
        ("job id that is not a file name", req_("submit", {"case": ks, "job": "../../x"}),
         "bad_request", "/args/job"),
        ("job id with a slash", req_("submit", {"case": ks, "job": "a/b"}), "bad_request",
         "/args/job"),
        ("job id starting with a dot", req_("submit", {"case": ks, "job": ".hidden"}),
         "bad_request", "/args/job"),
        ("job id too long", req_("submit", {"case": ks, "job": "x" * 64}), "bad_request",
         "/args/job"),
        ("job not a string", req_("query", {"job": 5}), "bad_request", "/args/job"),
        ("n not an integer", req_("step", {"job": "bg", "n": "3"}), "bad_request", "/args/n"),
        ("n a real", req_("step", {"job": "bg", "n": 1.5}), "bad_request", "/args/n"),
        ("until not a number", req_("step", {"job": "bg", "until": "1"}), "bad_request",
         "/args/until"),
        ("step with both n and until", req_("step", {"job": "bg", "n": 1, "until": 1.0}),
         "bad_request", "/args"),
        ("step with neither", req_("step", {"job": "bg"}), "bad_request", "/args"),
        ("n zero", req_("step", {"job": "bg", "n": 0}), "bad_request", "/args/n"),
        ("fields not an array", req_("query", {"job": "bg", "fields": "pos"}), "bad_request",
         "/args/fields"),
        ("max without fields", req_("query", {"job": "bg", "max": 10}), "bad_request",
         "/args/max"),
        ("a job that does not exist", req_("query", {"job": "nosuchjob"}), "not_found",
         "/args/job"),
        ("pause a job that does not exist", req_("pause", {"job": "nosuchjob"}), "not_found",
         "/args/job"),
        ("unknown method", req_("submit", {"case": {"name": "x", "method": "sph"}}),
         "invalid_case", "/method"),
    ]
    # every invalid case file of the kernel and solver issues, over the wire
    for f in sorted(glob.glob(os.path.join(src, "tests", "cases", "invalid", "*.json"))):
        def no_dups(pairs):
            keys = [k for k, _ in pairs]
            if len(keys) != len(set(keys)):
                raise ValueError("duplicate key")
            return dict(pairs)
        try:
            case = json.load(open(f), object_pairs_hook=no_dups)
        except ValueError:
            continue  # not JSON at all, or duplicate keys: the raw-bytes cases above cover it
        if not isinstance(case, dict):
            bad.append((os.path.basename(f), req_("submit", {"case": case}), "bad_request",
                        "/args/case"))
            continue
        want = open(f[:-5] + ".expect").readline().strip()
        bad.append((os.path.basename(f), req_("submit", {"case": case}), "invalid_case", want))
    for what, msg, code, path in bad:
        raw = msg if isinstance(msg, bytes) else json.dumps(msg).encode()
        try:
            r = d.request("bad", raw=raw, timeout=5)
        except TimeoutError as e:
            F.check(False, what, e)
            continue
        e = r.get("error") or {}
        ok = (r.get("ok") is False and e.get("code") == code and
              (path is None or e.get("path", "") == path) and e.get("message"))
        F.check(ok, f"bad input: {what} -> {code} {path}", r)
    F.check(d.request("ping")["ok"], "daemon answers after the bad input")

    # two frames after the envelope
    dl = d.socket(zmq.DEALER)
    dl.send_multipart([b'{"v":1,"op":"ping"}', b'{"v":1,"op":"ping"}'])
    F.check(dl.poll(5000) and json.loads(dl.recv_multipart()[-1])["error"]["code"] ==
            "bad_request", "two JSON frames in one request: bad_request")
    dl.close()

    # -- a 100 MiB message: over --max-msg-size (16 MiB): read and refused with too_large
    big = d.socket(zmq.DEALER)
    big.send(b'{"v":1,"id":"big","op":"ping","args":{"pad":"' + b"x" * (100 << 20) + b'"}}')
    got = big.poll(20000) and json.loads(big.recv_multipart()[-1])
    F.check(got and got["ok"] is False and got["error"]["code"] == "too_large",
            "100 MiB request: too_large", got)
    big.close()
    F.check(d.request("ping")["ok"], "daemon answers after the 100 MiB message")
    # just under the limit is read, parsed and refused politely
    pad = d.request("bad", raw=b'{"v":1,"op":"ping","args":{"pad":"' + b"x" * (8 << 20) + b'"}}')
    F.check(pad["error"]["code"] == "bad_request" and pad["error"]["path"] == "/args/pad",
            "8 MiB request with an unknown argument: bad_request", pad["error"])

    # -- clients that vanish mid-request
    for i in range(20):
        s = d.socket(zmq.DEALER)
        s.setsockopt(zmq.LINGER, 1000)
        s.send(json.dumps({"v": 1, "op": "list"}).encode())
        s.close()  # gone before the reply
        s = d.socket(zmq.DEALER)
        s.send(b'{"v":1,', zmq.SNDMORE)  # half a multipart message, then gone
        s.close()
    F.check(d.request("ping")["ok"], "daemon answers after 40 vanished clients")
    if sim:
        st = d.ok("query", {"job": "bgsim"})
        F.check(st["state"] == "running" and st["progress"]["steps"] > sim_steps0,
                "the simulation kept running through the bad input", st["progress"])
        F.check(d.ok("stop", {"job": "bgsim"})["state"] == "stopped", "and stops on request")

    # -- idempotent submit, conflict
    a = d.ok("submit", {"case": ks, "job": "idem"})
    b = d.ok("submit", {"case": ks, "job": "idem"})
    F.check(a["created"] and not b["created"] and a["job"] == b["job"] == "idem",
            "same id + same case = same job", (a, b))
    c = dict(ks, particles=51)
    r = d.request("submit", {"case": c, "job": "idem"})
    F.check(r["error"]["code"] == "conflict", "same id + other case = conflict", r)
    r = d.request("submit", {"case": ks, "job": "idem", "set": ["particles=51"]})
    F.check(r["error"]["code"] == "conflict", "set counts as part of the case", r)
    auto = d.ok("submit", {"case": ks})
    F.check(auto["job"].startswith("kernel_study-"), "generated job ids from the case name", auto)

    # -- a subscriber that never reads, and one that does
    lazy = d.subscribe(b"")
    lazy.setsockopt(zmq.RCVHWM, 4)
    eager = d.subscribe(b"")
    time.sleep(0.2)  # both subscriptions in place
    t0 = time.time()
    ids = [d.ok("submit", {"case": ks, "job": f"flood{i}"})["job"] for i in range(60)]
    for j in ids:
        d.wait_state(j, ("done",), timeout=60)
    F.check(True, f"60 jobs done in {time.time() - t0:.2f} s with a subscriber that never reads")
    seen = {}
    while eager.poll(200):
        topic, body = eager.recv_multipart()
        ev = json.loads(body)
        F.check(topic.decode() == ev["job"], "topic = job id", (topic, ev))
        seen.setdefault(ev["job"], []).append(ev["seq"])
    gaps = {j: s for j, s in seen.items() if j.startswith("flood") and s != list(range(1, len(s) + 1))}
    F.check(len([j for j in seen if j.startswith("flood")]) == 60 and not gaps,
            "a reading subscriber sees every event of every job in seq order", gaps)
    lazy.close()
    eager.close()

    # -- job states with kernel studies held in the queue behind two busy workers
    blockers = [d.ok("submit", {"case": big_study(src, 1500000, f"blk{i}"), "job": f"blk{i}"})
                for i in range(2)]
    q = d.ok("submit", {"case": ks, "job": "held"})
    F.check(q["state"] == "queued", "third job waits in the queue (2 threads)", q)
    p = d.ok("pause", {"job": "held"})
    F.check(p["state"] == "paused", "pause a queued job", p)
    r = d.ok("resume", {"job": "held"})
    F.check(r["state"] == "queued", "resume puts it back in the queue", r)
    s = d.ok("stop", {"job": "held"})
    F.check(s["state"] == "stopped", "stop a queued job", s)
    r = d.request("resume", {"job": "held"})
    F.check(r["error"]["code"] == "bad_state", "resume a stopped job: bad_state", r)
    ns = d.ok("submit", {"case": ks, "job": "nostart", "start": False})
    F.check(ns["state"] == "paused", "start: false leaves the job paused", ns)
    st = d.ok("step", {"job": "nostart", "n": 1})
    F.check(st["state"] == "paused" and st.get("pending_step") == {"n": 1}, "step is pending", st)
    d.wait_state("nostart", ("done",))
    F.check(True, "a stepped kernel study runs (one step finishes a study)")
    r = d.request("step", {"job": "nostart", "n": 1})
    F.check(r["error"]["code"] == "bad_state", "step on a finished job: bad_state", r)
    r = d.request("stop", {"job": "nostart"})
    F.check(r["error"]["code"] == "bad_state", "stop on a finished job: bad_state", r)
    ns2 = d.ok("submit", {"case": ks, "job": "nostart2", "start": False})
    d.ok("start", {"job": "nostart2"})
    d.wait_state("nostart2", ("done",))
    r = d.request("start", {"job": "nostart2"})
    F.check(r["error"]["code"] == "bad_state", "start on a finished job: bad_state", r)
    r = d.request("query", {"job": "nostart2", "fields": ["pos"]})
    F.check(r["error"]["code"] == "bad_state", "particles of a finished job: bad_state", r)

    # -- 4 jobs at once on 2 threads: at most 2 run, all finish
    for i in range(4):
        d.ok("submit", {"case": big_study(src, 400000, f"four{i}"), "job": f"four{i}"})
    max_running = 0
    deadline = time.time() + 120
    while time.time() < deadline:
        jobs = [j for j in d.ok("list")["jobs"]]
        running = sum(j["state"] == "running" for j in jobs)
        max_running = max(max_running, running)
        four = [j for j in jobs if j["job"].startswith("four")]
        if all(j["state"] == "done" for j in four):
            break
        time.sleep(0.01)
    F.check(max_running <= 2, "never more than --threads jobs running", max_running)
    F.check(all(j["state"] == "done" for j in four), "the 4 jobs finish", four)
    st = d.ok("query", {"job": "bg"})
    F.check(st["state"] == "done" and st["result"]["particles"] == 2500000,
            "the background job finished despite everything", st["state"])
    lst = d.ok("list")["jobs"]
    F.check({"bg", "idem", "held", "four3"} <= {j["job"] for j in lst}, "list holds the jobs")

    # -- too many jobs: busy
    d2 = Daemon(sphd, "--threads", "1", "--max-jobs", "2")
    try:
        d2.ok("submit", {"case": big_study(src, 1500000, "m1"), "start": False})
        d2.ok("submit", {"case": ks, "start": False})
        r = d2.request("submit", {"case": ks})
        F.check(r["error"]["code"] == "busy", "beyond --max-jobs: busy", r)
        r = d2.request("bad", raw=json.dumps({"v": 1, "op": "submit"}).encode())
        F.check(r["error"]["code"] == "bad_request", "argument errors come before busy", r)
        F.check(d2.shutdown() == 0, "second daemon exits 0")
    finally:
        d2.close()

    F.check(d.shutdown() == 0, "shutdown: exit 0")
finally:
    log = d.log()
    d.close()
sys.exit(F.done(log))
