"""Opens a run's XDMF series in ParaView and reports what ParaView sees; run under pvbatch (in a virtual X server):

    xvfb-run -a pvbatch tests/io/paraview_check.py RUN_DIR REPORT.json PICTURE.png --box=X0,X1,Y0,Y1,Z0,Z1

For particles.xmf, fluid.xmf and analysis.xmf, with the XDMF reader (XDMFReader) and with the reader ParaView picks
itself for .xmf (OpenDataFile: Xdmf3ReaderS in 5.11): the time steps and, at each step, the number of points and
cells, the bounds and the array names of the reader's output and the bounds of its surface (ExtractSurface: what a
view draws). The void fraction and velocity of each gas step and of the averages, and the particle positions of
each step, go to REPORT.npz for comparison with the HDF5 files. The picture shows the particles of the last step
(XDMF reader) over the gas void fraction: the whole grid in 2D; in 3D a slice at mid-depth with the particles in
front of it. It spans the given box exactly (parallel projection), so that pixel rows map to heights. The judging is left
to tests/io/test_paraview.py."""
import argparse
import json
import os

import numpy as np
from paraview.simple import (Clip, ColorBy, CreateRenderView, ExtractSurface, GetColorTransferFunction, GetScalarBar, OpenDataFile, Render, SaveScreenshot,
                             Show, Slice, Transform, XDMFReader)
from vtkmodules.numpy_interface import dataset_adapter as dsa

ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0], formatter_class=argparse.RawDescriptionHelpFormatter)
ap.add_argument("run", help="run directory (fluidbed -output_dir) holding particles.xmf, fluid.xmf and analysis.xmf")
ap.add_argument("report", help="JSON report to write (the arrays go to the same name with .npz)")
ap.add_argument("picture", help="PNG picture to write")
ap.add_argument("--box", required=True, type=lambda s: [float(v) for v in s.split(",")],
                help="x0,x1,y0,y1,z0,z1 (m): the box the picture spans (as --box=..., the values may be negative)")
cli = ap.parse_args()
run, report, picture = cli.run, cli.report, cli.picture
SERIES = ("particles", "fluid", "analysis")


def open_series(reader, name):
    path = os.path.join(run, name + ".xmf")
    if reader == "XDMFReader":
        return XDMFReader(FileNames=[path])
    return OpenDataFile(path)


def leaf(obj):
    """The dataset of a reader's output (the first leaf if a reader wraps it in a multiblock)."""
    if obj is None or obj.IsA("vtkDataSet"):
        return obj
    it = obj.NewIterator()
    it.InitTraversal()
    return None if it.IsDoneWithTraversal() else it.GetCurrentDataObject()


def names(attributes):
    return sorted(attributes.GetArrayName(i) for i in range(attributes.GetNumberOfArrays()))


result, arrays = {}, {}
for reader in ("XDMFReader", "OpenDataFile"):
    result[reader] = {}
    for name in SERIES:
        src = open_series(reader, name)
        if src is None:
            result[reader][name] = {"error": "ParaView found no reader"}
            continue
        times = [float(v) for v in src.TimestepValues] if src.TimestepValues else []
        surface = ExtractSurface(Input=src)  # what a view draws: the reader's output as the pipeline hands it on
        steps = []
        for k, time in enumerate(times or [None]):
            src.UpdatePipeline(time) if time is not None else src.UpdatePipeline()
            surface.UpdatePipeline(time) if time is not None else surface.UpdatePipeline()
            data = leaf(src.GetClientSideObject().GetOutputDataObject(0))
            drawn = leaf(surface.GetClientSideObject().GetOutputDataObject(0))
            step = {"points": 0, "cells": 0, "bounds": None, "point_arrays": [], "cell_arrays": [], "surface_points": 0, "surface_bounds": None}
            if data is not None:
                step.update({"points": data.GetNumberOfPoints(), "cells": data.GetNumberOfCells(), "bounds": list(data.GetBounds()),
                             "point_arrays": names(data.GetPointData()), "cell_arrays": names(data.GetCellData())})
                wrapped = dsa.WrapDataObject(data)
                key = "%s/%s/%d" % (reader, name, k)
                if name == "particles" and data.GetNumberOfPoints():
                    arrays[key + "/position"] = np.array(wrapped.Points)
                for field in ("void_fraction", "velocity"):
                    if field in wrapped.CellData.keys():
                        arrays[key + "/" + field] = np.array(wrapped.CellData[field])
            if drawn is not None and drawn.GetNumberOfPoints():
                step.update({"surface_points": drawn.GetNumberOfPoints(), "surface_bounds": list(drawn.GetBounds())})
            steps.append(step)
        result[reader][name] = {"xml_name": src.GetXMLName(), "times": times, "steps": steps}
        last = steps[-1]
        print("%-12s %-9s %-13s %d step(s); last: %d points, %d cells, bounds %s, drawn %s" %
              (reader, name, src.GetXMLName(), len(times), last["points"], last["cells"],
               ["%.4g" % b for b in last["bounds"]] if last["bounds"] else None,
               ["%.4g" % b for b in last["surface_bounds"]] if last["surface_bounds"] else None))


def save_picture(box):
    """The particles of the last gas step over its void fraction, both through the XDMF reader, in the box
    (x0, x1, y0, y1, z0, z1) seen from +z: the picture spans the box's x and y exactly."""
    particles, gas = XDMFReader(FileNames=[os.path.join(run, "particles.xmf")]), XDMFReader(FileNames=[os.path.join(run, "fluid.xmf")])
    last = result["XDMFReader"]["fluid"]["times"][-1]
    particles.UpdatePipeline(last)
    diameter = float(np.mean(dsa.WrapDataObject(leaf(particles.GetClientSideObject().GetOutputDataObject(0))).PointData["diameter"]))
    three_d = box[5] > box[4]
    zmid = 0.5 * (box[4] + box[5])
    view = CreateRenderView()
    height = 960  # 960 pixels tall (within xvfb-run's screen of 1280 x 1024), as wide as the box's aspect asks
    width = int(round(height * (box[1] - box[0]) / (box[3] - box[2])))
    view.ViewSize = [width, height]
    view.ViewTime = last
    view.OrientationAxesVisibility = 1
    field = gas
    if three_d:  # a slice at mid-depth; only the particles in front of it (z above mid-depth) are drawn
        field = Slice(Input=gas)
        field.SliceType = "Plane"
        field.SliceType.Origin = [0.5 * (box[0] + box[1]), 0.5 * (box[2] + box[3]), zmid]
        field.SliceType.Normal = [0, 0, 1]
        front = Clip(Input=particles)
        front.ClipType = "Plane"
        front.ClipType.Origin = [0, 0, zmid]
        front.ClipType.Normal = [0, 0, 1]
        front.Invert = 0
        particles = front
    else:  # 2D: the particles lie in the plane of the gas grid; a diameter towards the camera (parallel projection:
        # drawn at the same x, y), so that no depth test between the points and the cells decides what shows
        lifted = Transform(Input=particles)
        lifted.Transform.Translate = [0, 0, diameter]
        particles = lifted
    shown = Show(field, view)
    shown.Ambient, shown.Diffuse = 1.0, 0.0  # unlit: each cell in its colour map's colour
    ColorBy(shown, ("CELLS", "void_fraction"))
    lut = GetColorTransferFunction("void_fraction")
    lut.ApplyPreset("Viridis (matplotlib)", True)
    lut.RescaleTransferFunction(0.3, 1.0)
    shown.SetScalarBarVisibility(view, True)
    GetScalarBar(lut, view).WindowLocation = "Upper Right Corner"  # over the freeboard, clear of the bed
    # Points (as spheres) rather than Point Gaussian, 70 % of a diameter across: the void fraction shows between.
    dots = Show(particles, view)
    dots.SetRepresentationType("Points")
    dots.ColorArrayName = ["POINTS", ""]
    dots.AmbientColor = dots.DiffuseColor = [1.0, 1.0, 1.0]
    # unlit, like the cells: flat white disks whatever lights the renderer sets (lit spheres came out white on a
    # tenth of their area on one machine and a fiftieth on another)
    dots.Ambient, dots.Diffuse, dots.Specular = 1.0, 0.0, 0.0
    dots.RenderPointsAsSpheres = 1
    dots.PointSize = max(2.0, 0.7 * diameter * height / (box[3] - box[2]))
    Render(view)  # the first render resets the camera: place it after
    view.CameraParallelProjection = 1
    view.ResetCamera()  # clipping planes around everything shown; then the box's centre in the middle, seen from +z
    distance = view.GetActiveCamera().GetDistance()
    cx, cy = 0.5 * (box[0] + box[1]), 0.5 * (box[2] + box[3])
    view.CameraFocalPoint = [cx, cy, zmid]
    view.CameraPosition = [cx, cy, zmid + distance]
    view.CameraViewUp = [0, 1, 0]
    view.CameraParallelScale = 0.5 * (box[3] - box[2])
    Render(view)
    SaveScreenshot(picture, view, ImageResolution=[width, height])
    return {"path": picture, "time": last, "size": [width, height], "three_d": three_d}


# the measures first, so that they reach the test even when the picture cannot be drawn
with open(report, "w") as f:
    json.dump(result, f, indent=1)
np.savez(os.path.splitext(report)[0] + ".npz", **arrays)
try:
    result["picture"] = save_picture(cli.box)
except Exception as e:  # the test reports it
    result["picture"] = {"error": "%s: %s" % (type(e).__name__, e)}
with open(report, "w") as f:
    json.dump(result, f, indent=1)
print("report %s, picture %s" % (report, result["picture"]))
