"""ParaView (Debian paraview 5.11, run by pvbatch) opens a job's results the way a user does:
particles.xmf with the reader OpenDataFile picks (Xdmf3ReaderS, the GUI's default) has every
particle as a cell at the first and the last step, and Threshold on `type` in [0, 0] gives the
fluid alone (the snapshot's n_fluid); the legacy XDMFReader reads the cells too; a snapshot on its
own opens with the VTKHDF reader (File > Open, then "VTKHDF Reader": ParaView 5.11 offers it for
.hdf names only) with one cell per particle, the fields as point data and Threshold working there.

Usage: pvbatch paraview_read.py JOB_DIR N_PARTICLES N_FLUID_FIRST N_FLUID_LAST
"""
import os
import sys

from paraview.simple import OpenDataFile, Threshold, VTKHDFReader, XDMFReader

d = sys.argv[1]
n, nfluid0, nfluid1 = (int(x) for x in sys.argv[2:5])
fails = []
passes = []


def check(what, ok, got=""):
    print("%s %s %s" % ("ok  " if ok else "FAIL", what, got))
    (passes if ok else fails).append(what)


def counts(src, t=None):
    if t is None:
        src.UpdatePipeline()
    else:
        src.UpdatePipeline(t)
    i = src.GetDataInformation()
    return i.GetNumberOfPoints(), i.GetNumberOfCells()


def fluid(src, t=None):
    th = Threshold(Input=src)
    th.Scalars = ["POINTS", "type"]
    th.LowerThreshold = 0
    th.UpperThreshold = 0
    return counts(th, t)


xmf = os.path.join(d, "particles.xmf")
r = OpenDataFile(xmf)
check("default reader for particles.xmf is Xdmf3ReaderS", r.GetXMLName() == "Xdmf3ReaderS",
      r.GetXMLName())
ts = list(r.TimestepValues)
snaps = sorted(f for f in os.listdir(d) if f.startswith("snap_") and f.endswith(".h5"))
check("one time step per snapshot", len(ts) == len(snaps), "%d, %d" % (len(ts), len(snaps)))
for t, nf in ((ts[0], nfluid0), (ts[-1], nfluid1)):
    check("t = %g: every particle a cell" % t, counts(r, t) == (n, n), counts(r, t))
    check("t = %g: Threshold type = 0 gives the fluid" % t, fluid(r, t) == (nf, nf), fluid(r, t))
    check("t = %g: point arrays" % t, {"p", "rho", "vel", "type", "id"} <= set(r.PointData.keys()),
          r.PointData.keys())
legacy = XDMFReader(FileNames=[xmf])
check("legacy XDMFReader: every particle a cell at the last step",
      counts(legacy, ts[-1]) == (n, n), counts(legacy, ts[-1]))
snap = VTKHDFReader(FileName=[os.path.join(d, snaps[-1])])
check("%s alone (VTKHDF): every particle a cell" % snaps[-1], counts(snap) == (n, n), counts(snap))
check("%s alone: point arrays" % snaps[-1],
      {"p", "rho", "vel", "type", "id"} <= set(snap.PointData.keys()), snap.PointData.keys())
check("%s alone: Threshold type = 0 gives the fluid" % snaps[-1], fluid(snap) == (nfluid1, nfluid1),
      fluid(snap))
prange = snap.PointData["p"].GetRange()
check("%s alone: pressure range finite" % snaps[-1], all(abs(x) < 1e7 for x in prange), prange)
print("paraview: %d passed, %d failed" % (len(passes), len(fails)))
sys.exit(1 if fails else 0)
