#!/usr/bin/python3
"""The validation report: runs every validation case and writes OUT/index.html (with a PNG per
figure, made with matplotlib) and OUT/results.json.

    validate.py --sphd BUILD/bin/sphd --src SOURCE_DIR --out OUT [--level full|ci] [--only NAME]
                [--threads N] [--runs DIR]

`cmake --build build --target validate` runs it at --level full (each case's full resolution);
the ctest validations run single cases at --level ci (a coarse resolution that still checks the
physics). Exit 0 when every check of every case run holds, 1 otherwise.

A case is one Python file in cases/ (loaded in name order) defining
    TITLE = "..."                    one line
    def run(ctx): ... return None    runs sphd through ctx, records checks and figures on ctx
ctx gives: ctx.level ("full" or "ci"), ctx.src, ctx.out (the case's own directory),
ctx.reference(NAME) (a file of tests/validation/reference/), ctx.reference_table(NAME) (its first
two columns as an (n, 2) array), ctx.sphd_run(CASE, sets) (runs
`sphd --run` with `--set` items, returns (events, job directory); its wall time and its sets are
recorded), ctx.sphd_run_long(CASE, sets, job) (a run of hours that survives an interruption: it
lives in RUNS/JOB (--runs, default OUT/runs), continues from its checkpoint when it was killed and
is taken as it is when it finished with the same case and sets; returns (result, diag series,
directory)), ctx.check(what, value, tolerance, ok, how=""), ctx.figure(NAME) (a new matplotlib
figure that is saved as NAME.png into the report), ctx.note(text). A new physics case is a new
file in cases/; nothing else changes.
"""
import argparse
import datetime
import fcntl
import glob
import html
import importlib.util
import json
import os
import platform
import shutil
import subprocess
import sys
import time
import traceback

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
EXTRA_SETS = []  # --set items for every run (validate.py --set)


class Context:
    def __init__(self, name, args, out):
        self.name, self.level, self.src, self.out = name, args.level, args.src, out
        self.sphd = args.sphd
        self.threads = args.threads
        self.runs_dir = args.runs or os.path.join(args.out, "runs")
        self.checks, self.figures, self.runs, self.notes = [], [], [], []
        self._open = []

    def reference(self, name):
        base = os.environ.get("SPH_REFERENCE_DIR") or os.path.join(self.src, "tests", "validation",
                                                                   "reference")
        return os.path.join(base, name)

    def _reference_rows(self, name, header=False):
        """The data rows of a reference CSV, split at commas (# lines and the header skipped:
        the header is the first line that is not a comment; with header, it comes first)."""
        with open(self.reference(name)) as f:
            lines = [l.strip() for l in f if not l.startswith("#") and l.strip()]
        return [l.split(",") for l in lines[0 if header else 1:]]

    def reference_columns(self, name):
        """A reference CSV of numbers as {header: numpy array of its column}."""
        import numpy as np
        rows = self._reference_rows(name, header=True)
        return {h.strip(): np.array([float(r[k]) for r in rows[1:]])
                for k, h in enumerate(rows[0])}

    def reference_table(self, name):
        """The first two columns of a reference CSV as an (n, 2) numpy array."""
        import numpy as np
        return np.array([(float(c[0]), float(c[1])) for c in self._reference_rows(name)])

    def reference_sets(self, name):
        """A reference CSV whose first column names a set: {set: (n, 2) numpy array of the next
        two columns}, in the file's order."""
        import numpy as np
        sets = {}
        for c in self._reference_rows(name):
            sets.setdefault(c[0], []).append((float(c[1]), float(c[2])))
        return {k: np.array(v) for k, v in sets.items()}

    def sphd_run(self, case, sets=(), job=None):
        job = job or os.path.splitext(os.path.basename(case))[0]
        d = os.path.join(self.out, "run-%d-%s" % (len(self.runs), job))
        cmd = [self.sphd, "--run", os.path.join(self.src, case), "--out", d,
               "--threads", str(self.threads)]
        for s in list(sets) + EXTRA_SETS:
            cmd += ["--set", s]
        t0 = time.time()
        p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        wall = time.time() - t0
        events = [json.loads(line) for line in p.stdout.splitlines() if line.strip()]
        self.runs.append({"case": case, "sets": list(sets), "wall": wall, "exit": p.returncode,
                          "dir": os.path.relpath(d, os.path.dirname(self.out))})
        print("  %s %s: exit %d, %.1f s" % (case, " ".join(sets), p.returncode, wall), flush=True)
        if p.returncode != 0:
            raise RuntimeError("sphd --run %s exited %d: %s" % (case, p.returncode,
                                                               p.stderr.strip()[-500:]))
        return events, d

    def sphd_run_long(self, case, sets, job):
        """A long run in the runs directory: resumed from its checkpoint, or taken as it is when
        it finished earlier with the same case and sets. Another process's run of the same job
        (a second report sharing --runs) is waited for, not run twice."""
        os.makedirs(self.runs_dir, exist_ok=True)
        with open(os.path.join(self.runs_dir, job + ".lock"), "w") as lock:
            try:
                fcntl.flock(lock, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except BlockingIOError:
                print("  %s: another process is running it; waiting" % job, flush=True)
                fcntl.flock(lock, fcntl.LOCK_EX)
            return self._sphd_run_long(case, sets, job)

    def _sphd_run_long(self, case, sets, job):
        d = os.path.join(self.runs_dir, job)
        stamp_path = os.path.join(d, "report-run.json")
        stamp = {"case": case, "sets": list(sets)}
        old = None
        if os.path.exists(stamp_path):
            with open(stamp_path) as f:
                old = json.load(f)
        if old != stamp and os.path.exists(d):  # another run's directory: not resumed
            shutil.rmtree(d)
        done = old == stamp and os.path.exists(os.path.join(d, "result.json"))
        t0 = time.time()
        if not done:
            os.makedirs(d, exist_ok=True)
            with open(stamp_path, "w") as f:
                json.dump(stamp, f)
            cmd = [self.sphd, "--run", os.path.join(self.src, case), "--out", d, "--resume",
                   "--id", job, "--threads", str(self.threads)]
            for s in list(sets) + EXTRA_SETS:
                cmd += ["--set", s]
            p = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
            if p.returncode != 0:
                raise RuntimeError("sphd --run %s exited %d: %s" % (case, p.returncode,
                                                                   p.stderr.strip()[-500:]))
        wall = time.time() - t0
        with open(os.path.join(d, "result.json")) as f:
            result = json.load(f)
        self.runs.append({"case": case, "sets": list(sets), "wall": wall, "exit": 0,
                          "dir": d, "reused": done})
        print("  %s %s: %s, %.1f s" % (case, " ".join(sets), "finished earlier" if done else
                                       "done", wall), flush=True)
        return result, read_diag(os.path.join(d, "diag.h5")), d

    def check(self, what, value, tolerance, ok, how=""):
        self.checks.append({"what": what, "value": value, "tolerance": tolerance, "ok": bool(ok),
                            "how": how})
        print("  %s %s: %s (tolerance %s)" % ("ok  " if ok else "FAIL", what, value, tolerance))

    def figure(self, name, **kw):
        fig = plt.figure(**kw)
        self._open.append((name, fig))
        return fig

    def note(self, text):
        self.notes.append(text)

    def save_figures(self):
        for name, fig in self._open:
            fig.tight_layout()
            fig.savefig(os.path.join(self.out, name + ".png"), dpi=110)
            plt.close(fig)
            self.figures.append(name + ".png")
        self._open = []


def read_diag(path):
    """The diagnostics series of a job's diag.h5, {column: numpy array}, its complete rows."""
    import h5py
    with h5py.File(path, "r") as f:
        rows = int(f["rows"][0])
        table = f["diag"][:rows]
    return {name: table[name] for name in table.dtype.names}


def commit(src):
    try:
        rev = subprocess.run(["git", "-C", src, "rev-parse", "--short", "HEAD"], text=True,
                             capture_output=True).stdout.strip()
        dirty = subprocess.run(["git", "-C", src, "status", "--porcelain", "--untracked-files=no"],
                               text=True, capture_output=True).stdout.strip()
        return rev + (" (with uncommitted changes)" if dirty else "") if rev else "unknown"
    except OSError:
        return "unknown"


def fmt(v):
    if isinstance(v, float):
        return "%.4g" % v
    return html.escape(str(v))


def write_html(out, report):
    e = html.escape
    rows = []
    for c in report["cases"]:
        status = "pass" if c["ok"] else "FAIL"
        rows.append("<tr><td><a href='#%s'>%s</a></td><td class='%s'>%s</td><td>%s</td>"
                    "<td>%.1f s</td></tr>" % (e(c["name"]), e(c["name"]), status.lower(), status,
                                              e(c["resolution"]), c["wall"]))
    parts = ["<!DOCTYPE html><html><head><meta charset='utf-8'><title>sphd validation</title>",
             "<style>body{font-family:sans-serif;max-width:1100px;margin:auto}"
             "td,th{border:1px solid #bbb;padding:3px 8px}table{border-collapse:collapse}"
             ".pass{color:#070}.fail{color:#b00;font-weight:bold}img{max-width:100%}</style>",
             "</head><body><h1>sphd validation report</h1>",
             "<p>commit <b>%s</b>, level <b>%s</b>, %s, %s, %d CPUs, sphd with %d threads; "
             "total wall time %.1f s</p>" % (e(report["commit"]), e(report["level"]),
                                             e(report["date"]), e(report["machine"]),
                                             report["cpus"], report["threads"], report["wall"]),
             "<table><tr><th>case</th><th>result</th><th>resolution</th><th>wall time</th></tr>",
             "\n".join(rows), "</table>"]
    for c in report["cases"]:
        parts.append("<h2 id='%s'>%s: %s</h2>" % (e(c["name"]), e(c["name"]), e(c["title"])))
        parts.append("<p>resolution: %s; wall time %.1f s</p>" % (e(c["resolution"]), c["wall"]))
        if c.get("error"):
            parts.append("<pre class='fail'>%s</pre>" % e(c["error"]))
        parts.append("<table><tr><th>check</th><th>value</th><th>tolerance</th><th></th>"
                     "<th>how</th></tr>")
        for k in c["checks"]:
            parts.append("<tr><td>%s</td><td>%s</td><td>%s</td><td class='%s'>%s</td><td>%s</td>"
                         "</tr>" % (e(k["what"]), fmt(k["value"]), fmt(k["tolerance"]),
                                    "pass" if k["ok"] else "fail", "pass" if k["ok"] else "FAIL",
                                    e(k["how"])))
        parts.append("</table>")
        for n in c["notes"]:
            parts.append("<p>%s</p>" % e(n))
        for f in c["figures"]:
            parts.append("<p><img src='%s/%s' alt='%s'></p>" % (e(c["name"]), e(f), e(f)))
        parts.append("<p>runs: %s</p>" % "; ".join(
            "<code>sphd --run %s %s</code> (%s)" % (e(r["case"]), e(" ".join(
                "--set " + s for s in r["sets"])), "finished earlier, in " + e(r["dir"])
                if r.get("reused") else "%.1f s" % r["wall"]) for r in c["runs"]))
    parts.append("</body></html>")
    with open(os.path.join(out, "index.html"), "w") as f:
        f.write("\n".join(parts) + "\n")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--sphd", required=True)
    ap.add_argument("--src", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--level", choices=("full", "ci"), default="full")
    ap.add_argument("--only", action="append", help="run this case only (repeatable)")
    ap.add_argument("--threads", type=int, default=os.cpu_count() or 1)
    ap.add_argument("--set", action="append", default=[], dest="sets",
                    help="a --set item for every run, after the case's own (repeatable): "
                         "device=\"gpu\" runs the report on the GPU")
    ap.add_argument("--runs", help="where the long runs live and resume (default OUT/runs)")
    args = ap.parse_args()
    EXTRA_SETS.extend(args.sets)
    os.makedirs(args.out, exist_ok=True)
    files = sorted(glob.glob(os.path.join(HERE, "cases", "*.py")))
    names = [os.path.splitext(os.path.basename(f))[0] for f in files]
    if args.only:
        unknown = set(args.only) - set(names)
        if unknown:
            sys.exit("validate.py: no case %s (cases: %s)" % (", ".join(unknown), ", ".join(names)))
    report = {"commit": commit(args.src), "level": args.level,
              "date": datetime.datetime.now().strftime("%Y-%m-%d %H:%M"),
              "machine": "%s %s" % (platform.system(), platform.machine()),
              "cpus": os.cpu_count() or 1, "threads": args.threads, "cases": []}
    t0 = time.time()
    for f, name in zip(files, names):
        if args.only and name not in args.only:
            continue
        spec = importlib.util.spec_from_file_location("case_" + name, f)
        mod = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(mod)
        out = os.path.join(args.out, name)
        os.makedirs(out, exist_ok=True)
        ctx = Context(name, args, out)
        print("== %s (%s)" % (name, args.level), flush=True)
        tc = time.time()
        err = None
        try:
            mod.run(ctx)
        except Exception:  # a case that breaks is a failed case in the report, not a lost report
            err = traceback.format_exc()
            print(err)
        ctx.save_figures()
        res = sorted({" ".join(r["sets"]) or "as in the case file" for r in ctx.runs})
        report["cases"].append({
            "name": name, "title": getattr(mod, "TITLE", name), "checks": ctx.checks,
            "figures": ctx.figures, "notes": ctx.notes, "runs": ctx.runs, "error": err,
            "resolution": getattr(mod, "RESOLUTION", {}).get(args.level, "; ".join(res)),
            "wall": time.time() - tc,
            "ok": err is None and bool(ctx.checks) and all(k["ok"] for k in ctx.checks)})
    report["wall"] = time.time() - t0
    report["ok"] = all(c["ok"] for c in report["cases"])
    with open(os.path.join(args.out, "results.json"), "w") as f:
        json.dump(report, f, indent=1)
    write_html(args.out, report)
    npass = sum(c["ok"] for c in report["cases"])
    print("report: %s (commit %s, %.0f s)" % (os.path.join(args.out, "index.html"),
                                             report["commit"], report["wall"]))
    print("%d passed, %d failed" % (npass, len(report["cases"]) - npass))
    return 0 if report["ok"] else 1


if __name__ == "__main__":
    sys.exit(main())
