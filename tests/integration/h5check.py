"""Checks of a job directory's result files, shared by the crash tests.

    h5check.py whole DIR        every snapshot opens with its fields, the XDMF parses, the
                                diagnostics file opens (SWMR); no snapshot is a temporary
    h5check.py same REF DIR     DIR's snapshots (their RPDF too) and diagnostics are bitwise equal
                                to REF's, and DIR holds no temporary file
Exit 0 when the check holds, 1 (with the reason) when not.
"""
import os
import re
import sys
import xml.etree.ElementTree as ET

import h5py
import numpy as np

SNAP = re.compile(r"^snap_\d+\.h5$")


def snapshots(d):
    return sorted(f for f in os.listdir(d) if SNAP.match(f))


def whole(d):
    for f in snapshots(d):
        with h5py.File(os.path.join(d, f), "r") as h:
            assert {"pos", "vel", "rho", "p", "type"} <= set(h.keys()), f
            h["pos"][:]
    if os.path.exists(os.path.join(d, "particles.xmf")):
        ET.parse(os.path.join(d, "particles.xmf"))
    if os.path.exists(os.path.join(d, "diag.h5")):
        with h5py.File(os.path.join(d, "diag.h5"), "r", libver="latest", swmr=True) as h:
            h["step"][:]


def same(a, b):
    snaps = snapshots(a)
    assert snaps == snapshots(b), (snaps, os.listdir(b))
    assert not [f for f in os.listdir(b) if ".tmp." in f], os.listdir(b)
    for s in snaps:
        with h5py.File(os.path.join(a, s), "r") as x, h5py.File(os.path.join(b, s), "r") as y:
            assert x.attrs["step"] == y.attrs["step"] and x.attrs["time"] == y.attrs["time"], s
            for k in x:
                if isinstance(x[k], h5py.Dataset):
                    assert np.array_equal(x[k][:], y[k][:]), (s, k)
            assert ("rpdf" in x) == ("rpdf" in y), s
            for k in x["rpdf"] if "rpdf" in x else ():
                assert np.array_equal(x["rpdf"][k][:], y["rpdf"][k][:]), (s, "rpdf/" + k)
    with h5py.File(os.path.join(a, "diag.h5"), "r", libver="latest", swmr=True) as x, \
         h5py.File(os.path.join(b, "diag.h5"), "r", libver="latest", swmr=True) as y:
        for k in x:  # bytes, not values: NaN (a probe without a body) equals itself bitwise
            u, v = x[k][:], y[k][:]
            assert u.dtype == v.dtype and u.shape == v.shape and u.tobytes() == v.tobytes(), k
    print("%d snapshots and the diagnostics series bitwise equal" % len(snaps))


if __name__ == "__main__":
    try:
        if sys.argv[1] == "whole":
            whole(sys.argv[2])
        elif sys.argv[1] == "same":
            same(sys.argv[2], sys.argv[3])
        else:
            sys.exit("usage: h5check.py whole DIR | same REF DIR")
    except AssertionError as e:
        print("h5check %s: %r" % (sys.argv[1], e))
        sys.exit(1)
