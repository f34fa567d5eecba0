#!/usr/bin/env python3
"""The files a case names travel with its job (PROTOCOL.md 3.11): sphctl sends them in
args.files, sphd checks them (names, size, CRC-32, base64, exactly the files the case names),
keeps them in JOBDIR/files/, lists them in `results` (kind "input") and serves them to `fetch`;
they survive kill -9 and a restart.

Until the geometry list parses and meshes are read (another branch), a case with a mesh is
refused by the case parser or the mesh reader at /geometry...: the test then checks that
refusal and the transfer checks that come before it; once such a case makes a job, it checks
the files end to end. usage: case_files.py SPHD SPHCTL SRC"""
import base64
import json
import os
import subprocess
import sys
import tempfile
import zlib

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from sphd_harness import Daemon, Failures  # noqa: E402



def box_stl(lo, hi):
    """A closed box as an ASCII STL (12 triangles, outward)."""
    c = [[(hi if (k >> d) & 1 else lo)[d] for d in range(3)] for k in range(8)]
    quads = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]
    out = ["solid pier"]
    for a, b, cc, d in quads:
        for tri in ((a, b, cc), (a, cc, d)):
            out += [" facet normal 0 0 0", "  outer loop"]
            out += ["   vertex %g %g %g" % tuple(c[v]) for v in tri]
            out += ["  endloop", " endfacet"]
    out.append("endsolid pier")
    return ("\n".join(out) + "\n").encode()


STL = box_stl((1.2, 0.3, 0.0), (1.4, 0.5, 0.2))
MAX_FILE = 8 << 20


def run_ctl(sphctl, d, *args):
    """sphctl against daemon d: (exit code, its output)."""
    p = subprocess.run([sphctl, "--endpoint", d.control, *args], capture_output=True, text=True,
                       timeout=120)
    return p.returncode, p.stdout + p.stderr


def entry(data, crc=None, size=None):
    return {"data": base64.b64encode(data).decode(),
            "crc32": crc if crc is not None else f"{zlib.crc32(data) & 0xffffffff:08x}",
            "size": len(data) if size is None else size}


def main(sphd, sphctl, src):
    t = Failures("case_files")
    work = tempfile.mkdtemp(prefix="sphd-files-")
    with open(os.path.join(src, "cases", "dambreak3d.json")) as f:
        base = json.load(f)
    case = dict(base, name="pier", geometry=[{"mesh": "pier.stl", "role": "obstacle"}])

    def write_case(name, c):
        p = os.path.join(work, name)
        with open(p, "w") as f:
            json.dump(c, f)
        return p

    with open(os.path.join(work, "pier.stl"), "wb") as f:
        f.write(STL)
    d = Daemon(sphd)
    try:
        def ctl(*args):
            return run_ctl(sphctl, d, *args)

        # sphctl's own checks: a missing file (66), a name with '..' (65), a file too large (65)
        rc, out = ctl("submit", write_case("missing.json", dict(
            case, geometry=[{"mesh": "nothere.stl", "role": "obstacle"}])), "--no-start")
        t.check(rc == 66 and "nothere.stl" in out and "geometry item 0" in out,
                "a missing file: exit 66 naming it", (rc, out))
        rc, out = ctl("submit", write_case("dotdot.json", dict(
            case, geometry=[{"mesh": "../pier.stl", "role": "obstacle"}])), "--no-start")
        t.check(rc == 65 and "../pier.stl" in out and "/geometry/0/mesh" in out,
                "a name with '..': exit 65 naming the item", (rc, out))
        rc, out = ctl("submit", write_case("abs.json", dict(
            case, geometry=[{"mesh": "/etc/passwd", "role": "obstacle"}])), "--no-start")
        t.check(rc == 65 and "absolute" in out, "an absolute name: exit 65", (rc, out))
        with open(os.path.join(work, "big.stl"), "wb") as f:
            f.truncate(MAX_FILE + 1)
        rc, out = ctl("submit", write_case("big.json", dict(
            case, geometry=[{"mesh": "big.stl", "role": "obstacle"}])), "--no-start")
        t.check(rc == 65 and "big.stl" in out and str(MAX_FILE) in out,
                "a file over the limit: exit 65", (rc, out))

        # sphd's checks on a raw request: each at /args/files/NAME
        def refused(args, code, path, what, op="submit"):
            r = d.request(op, args)
            err = r.get("error", {})
            t.check(not r["ok"] and err.get("code") == code and err.get("path") == path,
                    what, r)
            return err.get("message", "")

        good = {"pier.stl": entry(STL)}
        msg = refused({"case": case, "job": "crc", "start": False,
                       "files": {"pier.stl": entry(STL, crc="00000000")}},
                      "bad_request", "/args/files/pier.stl", "a CRC-32 mismatch")
        t.check("CRC-32" in msg and "again" in msg, "the mismatch says what to do", msg)
        refused({"case": case, "job": "sz", "start": False,
                 "files": {"pier.stl": entry(STL, size=len(STL) + 1)}},
                "bad_request", "/args/files/pier.stl", "a size mismatch")
        refused({"case": case, "job": "b64", "start": False,
                 "files": {"pier.stl": dict(entry(STL), data="!!notbase64")}},
                "bad_request", "/args/files/pier.stl", "data that is not base64")
        refused({"case": case, "job": "big", "start": False,
                 "files": {"pier.stl": entry(STL, size=MAX_FILE + 1)}},
                "too_large", "/args/files/pier.stl", "a size over the limit")
        refused({"case": case, "job": "none", "start": False},
                "bad_request", "/args/files/pier.stl", "a named file not sent")
        refused({"case": case, "job": "extra", "start": False,
                 "files": dict(good, **{"other.stl": entry(b"x")})},
                "bad_request", "/args/files/other.stl", "a file the case does not name")
        refused({"case": base, "job": "extra2", "start": False, "files": good},
                "bad_request", "/args/files/pier.stl", "files with a case that names none")
        refused({"case": case, "job": "esc", "start": False,
                 "files": dict(good, **{"../x": entry(b"x")})},
                "bad_request", "/args/files/..~1x", "a name with '..' in files")
        refused({"case": case, "sweep": "sw", "start": False, "files": {},
                 "vary": [{"path": "dx", "values": [0.02, 0.03]}]},
                "bad_request", "/args/files/pier.stl", "a sweep without its file", op="sweep")
        for name in ("crc", "sz", "b64", "big", "none", "extra", "extra2", "esc"):
            t.check(not os.path.exists(os.path.join(d.state, "jobs", name)),
                    f"refused job {name}: no directory left")

        # a surface with a hole: refused at its path, saying how many open edges and where
        lines = STL.decode().split("\n")
        open_stl = ("\n".join(lines[:1] + lines[15:]) + "\n").encode()  # two facets fewer
        r = d.request("submit", {"case": case, "job": "holed", "start": False,
                                 "files": {"pier.stl": entry(open_stl)}})
        t.check(not r["ok"] and r["error"]["code"] == "invalid_case"
                and r["error"]["path"] == "/geometry/0/mesh"
                and "open edges" in r["error"]["message"], "an open mesh: invalid_case at its path",
                r)
        t.check(not os.path.exists(os.path.join(d.state, "jobs", "holed")),
                "the refused mesh left no job directory")
        # a sweep whose second combination names the open mesh: all or nothing, no job made
        r = d.request("sweep", {"case": case, "sweep": "sh", "start": False,
                                "files": {"pier.stl": entry(STL), "holed.stl": entry(open_stl)},
                                "vary": [{"path": "geometry.0.mesh",
                                          "values": ["pier.stl", "holed.stl"]}]})
        t.check(not r["ok"] and r["error"]["code"] == "invalid_case"
                and r["error"]["path"] == "/geometry/0/mesh"
                and "combination 1" in r["error"]["message"]
                and "open edges" in r["error"]["message"],
                "a sweep with one open mesh: invalid_case at its combination", r)
        left = [n for n in os.listdir(d.state) if n.startswith(".sweep-check")]
        t.check(not os.path.exists(os.path.join(d.state, "jobs", "sh-0")) and not left,
                "the refused sweep made no job and left no scratch files", left)
        t.check(d.request("ping", {})["ok"], "sphd carries on")

        # the transfer itself, through sphctl
        rc, out = ctl("--json", "submit", write_case("pier.json", case), "--no-start", "--id",
                      "pier")
        t.check(rc == 0, "a case with a mesh is accepted", (rc, out))
        if rc == 0:
            jobdir = os.path.join(d.state, "jobs", "pier")
            with open(os.path.join(jobdir, "files", "pier.stl"), "rb") as f:
                t.check(f.read() == STL, "the file is in JOBDIR/files/")
            res = d.ok("results", {"job": "pier", "checksums": True})
            ent = [f for f in res["files"] if f["name"] == "files/pier.stl"]
            t.check(len(ent) == 1 and ent[0]["kind"] == "input" and ent[0]["size"] == len(STL)
                    and ent[0]["crc32"] == f"{zlib.crc32(STL):08x}", "results lists it", res)
            r = d.ok("fetch", {"job": "pier", "file": "files/pier.stl"})
            t.check(base64.b64decode(r["data"]) == STL and r["eof"], "fetch returns it", r)
            refused({"job": "pier", "file": "files/../case.json"}, "bad_request", "/args/file",
                     "fetch refuses an escape", op="fetch")
            dest = os.path.join(work, "dest")
            rc, out = ctl("fetch", "pier", "--dest", dest)
            with open(os.path.join(dest, "pier", "files", "pier.stl"), "rb") as f:
                t.check(rc == 0 and f.read() == STL, "sphctl fetch brings it back", out)
            r = d.request("submit", {"case": case, "job": "pier", "start": False, "files": good})
            t.check(r["ok"] and r["result"]["created"] is False, "same case and files: same job",
                    r)
            refused({"case": case, "job": "pier", "start": False,
                     "files": {"pier.stl": entry(STL + b" ")}},
                    "conflict", "/args/files", "same case, other files: conflict")
            # kill -9, then a new sphd on the same state dir
            d.proc.kill()
            d.proc.wait()
            d2 = Daemon(sphd, "--state-dir", d.state)
            try:
                res = d2.ok("results", {"job": "pier"})
                t.check(any(f["name"] == "files/pier.stl" for f in res["files"]),
                        "after kill -9 and a restart results lists it", res)
                r = d2.request("step", {"job": "pier", "n": 2})
                t.check(r["ok"], "after the restart the job steps (its mesh read again)", r)
            finally:
                d2.close()
    finally:
        d.close()
    series(sphd, sphctl, src, work, t)
    return t.done()


def series(sphd, sphctl, src, work, t):
    """A wavemaker's series file travels like a mesh: sphctl sends it, sphd keeps it, checks its
    rows (a jump is invalid_case at /wavemaker/waves/file naming the row), runs the job with it
    and, after kill -9 and a restart, steps a paused one."""
    with open(os.path.join(src, "cases", "wave_flume.json")) as f:
        flume = json.load(f)
    del flume["diagnostics"]["reflection"]
    flume.update(name="series", dx=0.05, time=dict(flume["time"], end=0.3))
    flume["wavemaker"] = dict(flume["wavemaker"], layers=3,
                              waves={"type": "series", "file": "paddle/motion.csv"})
    rows = "time,displacement\n" + "".join(
        "%g,%g\n" % (0.01 * i, 0.01 * (0.01 * i) ** 2) for i in range(101))
    os.makedirs(os.path.join(work, "paddle"), exist_ok=True)
    with open(os.path.join(work, "paddle", "motion.csv"), "w") as f:
        f.write(rows)
    p = os.path.join(work, "series.json")
    with open(p, "w") as f:
        json.dump(flume, f)
    d = Daemon(sphd)
    try:
        def ctl(*args):
            return run_ctl(sphctl, d, *args)

        gone = dict(flume, wavemaker=dict(flume["wavemaker"],
                                          waves={"type": "series", "file": "gone.csv"}))
        q = os.path.join(work, "gone.json")
        with open(q, "w") as f:
            json.dump(gone, f)
        rc, out = ctl("submit", q, "--no-start")
        t.check(rc == 66 and "gone.csv" in out and "series" in out,
                "a missing series: exit 66 naming it", (rc, out))
        jump = "0,0\n0.1,0\n0.2,0.5\n1,0.5\n".encode()
        r = d.request("submit", {"case": flume, "job": "jump", "start": False,
                                 "files": {"paddle/motion.csv": entry(jump)}})
        t.check(not r["ok"] and r["error"]["code"] == "invalid_case"
                and r["error"]["path"] == "/wavemaker/waves/file"
                and "row 3" in r["error"]["message"], "a jump: invalid_case naming the row", r)
        t.check(not os.path.exists(os.path.join(d.state, "jobs", "jump")),
                "the refused series left no job directory")
        rc, out = ctl("--json", "submit", p, "--id", "ser", "--watch")
        t.check(rc == 0, "a series flume runs to its end", (rc, out[-400:]))
        jobdir = os.path.join(d.state, "jobs", "ser")
        with open(os.path.join(jobdir, "files", "paddle", "motion.csv")) as f:
            t.check(f.read() == rows, "the series is in JOBDIR/files/")
        res = d.ok("results", {"job": "ser"})
        t.check(any(f["name"] == "files/paddle/motion.csv" and f["kind"] == "input"
                    for f in res["files"]), "results lists the series", res)
        rc, out = ctl("--json", "submit", p, "--id", "ser2", "--no-start")
        t.check(rc == 0, "a second series job, paused", (rc, out))
        d.proc.kill()
        d.proc.wait()
        d2 = Daemon(sphd, "--state-dir", d.state)
        try:
            r = d2.request("step", {"job": "ser2", "n": 5})
            t.check(r["ok"], "after kill -9 and a restart the series job steps (its series read "
                    "again)", r)
        finally:
            d2.close()
    finally:
        d.close()


if __name__ == "__main__":
    sys.exit(main(*sys.argv[1:4]))
