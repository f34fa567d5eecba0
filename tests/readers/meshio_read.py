#!/usr/bin/python3
"""meshio (Debian python3-meshio) reads a job's particles.xmf: the time series reader gives a
vertex cell per particle and every step's point data; and each step's grid, read alone by meshio's
XDMF reader (the step's <Grid> element, less its <Time>, in a file of its own), has its cells and point data too.
Times and values match the snapshots (h5py).

Usage: meshio_read.py JOB_DIR
"""
import os
import sys
import tempfile
import xml.etree.ElementTree as ET

import h5py
import meshio
import numpy as np


def main():
    d = sys.argv[1]
    xmf = os.path.join(d, "particles.xmf")
    snaps = sorted(f for f in os.listdir(d) if f.startswith("snap_") and f.endswith(".h5"))
    assert len(snaps) >= 2, snaps
    with meshio.xdmf.TimeSeriesReader(xmf) as r:
        points, cells = r.read_points_cells()
        n = points.shape[0]
        assert [c.type for c in cells] == ["vertex"] and len(cells[0].data) == n, cells
        assert r.num_steps == len(snaps), (r.num_steps, len(snaps))
        for k, name in enumerate(snaps):
            t, pd, _ = r.read_data(k)
            with h5py.File(os.path.join(d, name), "r") as f:
                assert abs(t - f.attrs["time"]) < 1e-12, (k, t)
                assert set(pd) >= {"vel", "rho", "p", "type", "id"}, list(pd)
                for key in pd:
                    assert len(pd[key]) == n, (k, key)
                assert np.array_equal(pd["p"], f["p"][:]), k
                assert np.array_equal(pd["id"], np.arange(n)), k
    # every step read alone: its topology has cells
    root = ET.parse(xmf).getroot()
    grids = root.findall(".//Grid[@GridType='Uniform']")
    assert len(grids) == len(snaps)
    with tempfile.TemporaryDirectory(dir=d) as tmp:
        for k, g in enumerate(grids):
            one = ET.Element("Xdmf", Version="3.0")
            dom = ET.SubElement(one, "Domain")
            for tm in g.findall("Time"):  # meshio's single-grid reader knows no <Time>
                g.remove(tm)
            dom.append(g)
            for item in g.iter("DataItem"):  # the snapshots are one level up
                item.text = "../" + item.text.strip()
            path = os.path.join(tmp, "step.xmf")
            ET.ElementTree(one).write(path)
            m = meshio.read(path)
            assert m.points.shape[0] == n and m.cells[0].type == "vertex", k
            assert len(m.cells[0].data) == n, (k, len(m.cells[0].data))
            with h5py.File(os.path.join(d, snaps[k]), "r") as f:
                assert np.array_equal(m.point_data["rho"], f["rho"][:]), k
                assert np.array_equal(m.points, f["pos"][:]), k
    print("meshio: %d steps, %d vertex cells each (time series reader and every step alone)"
          % (len(snaps), n))
    return 0


if __name__ == "__main__":
    try:
        sys.exit(main())
    except AssertionError as e:
        print("FAIL: %r" % (e,))
        sys.exit(1)
