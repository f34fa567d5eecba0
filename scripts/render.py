"""Renders a job's particles at one time to a PNG with ParaView, the way a user would look at them:
particles.xmf opened with ParaView's default reader, the fluid alone (Threshold on `type`),
coloured by pressure, the walls in grey (in 3D, the obstacles inside the tank solid: the wall
particles inside boundary.tank's box, read from the job's case.json). A 2D case is seen from the front, the walls' width filling
the picture, and the front position, the layer thickness and the pressure range are printed; a 3D
case (z up) in perspective from the front left, above, the walls faint, and the fluid's extent
and pressure range are printed.

Usage: scripts/render.sh JOB_DIR TIME OUT.png   (pvbatch under an X server: Xvfb when there is no
       DISPLAY), or pvbatch scripts/render.py JOB_DIR TIME OUT.png on a desktop
"""
import json
import os
import sys

import numpy as np
from paraview import servermanager as sm
from paraview.simple import (Clip, ColorBy, GetActiveCamera, GetActiveViewOrCreate, GetColorTransferFunction,
                             GetScalarBar, OpenDataFile, Render, SaveScreenshot, Show, Threshold)
from vtk.numpy_interface import dataset_adapter as dsa

d, t, out = sys.argv[1], float(sys.argv[2]), sys.argv[3]
r = OpenDataFile(os.path.join(d, "particles.xmf"))
ts = list(r.TimestepValues)
t = min(ts, key=lambda x: abs(x - t))
view = GetActiveViewOrCreate("RenderView")
view.ViewSize = [1400, 700]
view.ViewTime = t
view.OrientationAxesVisibility = 0
view.Background = [1, 1, 1]
try:
    view.UseColorPaletteForBackground = 0
except AttributeError:
    pass

fluid = Threshold(Input=r)
fluid.Scalars = ["POINTS", "type"]
fluid.LowerThreshold = 0
fluid.UpperThreshold = 0
walls = Threshold(Input=r)
walls.Scalars = ["POINTS", "type"]
walls.LowerThreshold = 1
walls.UpperThreshold = 1
for src in (fluid, walls):
    src.UpdatePipeline(t)

data = dsa.WrapDataObject(sm.Fetch(fluid))
pos, p = np.asarray(data.Points), np.asarray(data.PointData["p"])
wpos = np.asarray(dsa.WrapDataObject(sm.Fetch(walls)).Points)
dim3 = bool(np.any(wpos[:, 2] != 0.0)) if len(wpos) else bool(np.any(pos[:, 2] != 0.0))

wd = Show(walls, view)
wd.SetRepresentationType("Points")
wd.PointSize = 1 if dim3 else 2
ColorBy(wd, None)
wd.AmbientColor = wd.DiffuseColor = [0.6, 0.6, 0.6]
if dim3:
    wd.Opacity = 0.25
# in 3D, the wall particles inside the tank (obstacles, meshes) solid: the tank's own walls lie
# outside its box
tank = None
try:
    with open(os.path.join(d, "case.json")) as f:
        tank = json.load(f).get("boundary", {}).get("tank")
except (OSError, ValueError):
    pass
if dim3 and tank:
    inner = Clip(Input=walls)
    inner.ClipType = "Box"
    inner.Crinkleclip = 1
    inner.Invert = 1
    lo_t, hi_t = np.array(tank["min"], float), np.array(tank["max"], float)
    inner.ClipType.Position = [float(v) for v in lo_t + 1e-6]
    inner.ClipType.Length = [float(v) for v in hi_t - lo_t - 2e-6]
    inner.UpdatePipeline(t)
    od = Show(inner, view)
    od.SetRepresentationType("Points")
    od.PointSize = 4
    ColorBy(od, None)
    od.AmbientColor = od.DiffuseColor = [0.35, 0.35, 0.35]
fd = Show(fluid, view)
fd.SetRepresentationType("Points")
fd.PointSize = 3
ColorBy(fd, ("POINTS", "p"))
fd.SetScalarBarVisibility(view, True)
lut = GetColorTransferFunction("p")
lo, hi = np.percentile(p, 1), np.percentile(p, 99)
lut.RescaleTransferFunction(float(min(lo, 0.0)), float(hi))
bar = GetScalarBar(lut, view)
bar.Title = "p [Pa], t = %g s" % t
bar.ComponentTitle = ""
bar.TitleColor = bar.LabelColor = [0, 0, 0]
bar.WindowLocation = "Any Location"
bar.Position = [0.86, 0.35]
bar.ScalarBarLength = 0.5

Render(view)  # a first render resets the camera
lo3, hi3 = (wpos.min(axis=0), wpos.max(axis=0)) if len(wpos) else (pos.min(axis=0), pos.max(axis=0))
mid = 0.5 * (lo3 + hi3)
if dim3:
    # perspective from the front left, above: the walls' box fills the picture
    span = float(np.max(hi3 - lo3))
    view.CameraFocalPoint = [float(mid[0]), float(mid[1]), float(lo3[2] + 0.3 * (hi3[2] - lo3[2]))]
    view.CameraPosition = [float(mid[0] - 0.35 * span), float(mid[1] - 1.1 * span),
                           float(mid[2] + 0.8 * span)]
    view.CameraViewUp = [0, 0, 1]
    view.CameraParallelProjection = 0
    view.ResetCamera(False)
    GetActiveCamera().Zoom(1.2)
else:
    # the walls' width filling the picture, from their bottom up
    scale = 0.5 * float(hi3[0] - lo3[0]) / 2.0
    view.CameraPosition = [float(mid[0]), float(lo3[1]) + scale, 3.0]
    view.CameraFocalPoint = [float(mid[0]), float(lo3[1]) + scale, 0.0]
    view.CameraViewUp = [0, 1, 0]
    view.CameraParallelProjection = 1
    view.CameraParallelScale = scale
Render(view)
SaveScreenshot(out, view, ImageResolution=[1400, 700])

if dim3:
    print("t = %g s: %d fluid particles, within x %.3f-%.3f, y %.3f-%.3f, z %.3f-%.3f m"
          % (t, len(pos), *(v for a in range(3) for v in (pos[:, a].min(), pos[:, a].max()))))
else:
    # the front and the layer: the leading fluid's x, the water depth along the bed
    x, y = pos[:, 0], pos[:, 1]
    front = np.sort(x)[-3]
    bins = np.arange(0.0, front, 0.05)
    depth = [(b, y[(x >= b) & (x < b + 0.05)].max()) for b in bins
             if ((x >= b) & (x < b + 0.05)).any()]
    print("t = %g s: %d fluid particles, front at x = %.3f m" % (t, len(x), front))
    print("water depth along the bed (max y per 5 cm): " +
          ", ".join("%.2f-%.2f: %.3f" % (b, b + 0.05, h) for b, h in depth))
print("fluid pressure: min %.0f Pa, 1st-99th percentile %.0f to %.0f Pa, max %.0f Pa"
      % (p.min(), lo, hi, p.max()))
print("wrote", out)
