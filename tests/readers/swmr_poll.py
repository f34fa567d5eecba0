#!/usr/bin/python3
"""Polls a diagnostics file (diag.h5) with h5py in SWMR mode while its job runs, as PROTOCOL.md
section 4 tells a live reader to: refresh and read `rows` first, then read at most that many rows
of the `diag` table and of the per-column datasets. Every poll must be whole: each series holds at
least `rows` rows, none of them unwritten (steps strictly increasing from 0, times increasing,
every float finite or NaN for a null probe), and each per-column dataset equals the table's
column. Passes when at least --min-polls polls were made while the writer was alive and the rows
grew meanwhile.

Usage: swmr_poll.py DIAG.h5 WRITER_PID [--min-polls N]
"""
import os
import sys
import time

import h5py
import numpy as np


def alive(pid):
    try:
        os.kill(pid, 0)
    except OSError:
        return False
    try:  # a zombie (exited, not yet reaped) is not writing any more
        with open("/proc/%d/stat" % pid) as f:
            return f.read().split(")")[-1].split()[0] != "Z"
    except OSError:
        return False


def main():
    path, pid = sys.argv[1], int(sys.argv[2])
    min_polls = int(sys.argv[sys.argv.index("--min-polls") + 1]) if "--min-polls" in sys.argv else 200
    t0 = time.time()
    while not os.path.exists(path):
        if not alive(pid) or time.time() - t0 > 120:
            print("FAIL: no diagnostics file appeared")
            return 1
        time.sleep(0.01)
    f = h5py.File(path, "r", libver="latest", swmr=True)
    table, count = f["diag"], f["rows"]
    names = table.dtype.names
    units = [u.decode() if isinstance(u, bytes) else u for u in table.attrs["units"]]
    assert len(units) == len(names), (names, units)
    assert table.dtype["step"].kind == "i" and table.dtype["lost"].kind == "i", table.dtype
    cols = {k: f[k] for k in names}
    polls, seen, last = 0, [], -1
    while alive(pid):
        count.refresh()
        n = int(count[0])
        table.refresh()
        for d in cols.values():
            d.refresh()
        lengths = {k: d.shape[0] for k, d in cols.items()}
        lengths["diag"] = table.shape[0]
        short = {k: v for k, v in lengths.items() if v < n}
        assert not short, "poll %d: rows = %d but %s" % (polls, n, short)
        rows = table[:n]
        step = rows["step"]
        assert n == 0 or (step[0] == 0 and np.all(np.diff(step) > 0)), (polls, step[-5:])
        assert np.all(np.diff(rows["t"]) > 0), (polls, rows["t"][-5:])
        assert np.all(rows["t"] >= 0) and np.all(rows["dt"][1:] > 0), (polls, rows[-3:])
        for k in names:
            assert np.array_equal(cols[k][:n], rows[k], equal_nan=rows.dtype[k].kind == "f"), \
                (polls, k)
        if alive(pid):
            polls += 1
            if n != last:
                seen.append(n)
                last = n
        time.sleep(0.01)
    f.close()
    print("%d polls while the job ran, rows seen growing %d times (%s ... %s); units %s"
          % (polls, len(seen), seen[:3], seen[-3:], dict(zip(names, units))))
    if polls < min_polls or len(seen) < 3:
        print("FAIL: too few polls (%d, want %d) or growth (%d) during the run"
              % (polls, min_polls, len(seen)))
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
