#!/usr/bin/env pvpython
"""Open a DEM sample's particle states (sample-KKK/particles.xdmf) in ParaView, print what the
reader sees as one JSON line, and optionally render the deformed stones and the cracks to a PNG.

    scripts/with_display.sh pvpython scripts/pv_dem.py results/wall-cyclic-shear/sample-000/particles.xdmf
    scripts/with_display.sh pvpython scripts/pv_dem.py results/wall-shear/sample-000/particles.xdmf \
        --state last --scale 50 --out stones.png

JSON: the number of time steps (recorded states), and at the chosen state the points, the cells,
the stones (cells with particle >= 0), the cracks present (crack >= 0, tension 0 / shear 1) and
the point and cell arrays. The picture: stones warped by `displacement` x `--scale`, coloured by
their rotation, with their edges; broken beams as thick lines, red for tension, blue for
shear/rotation (as in the crack SVGs).
"""
import argparse
import json
import sys

from paraview import simple as pv
from paraview import servermanager as sm


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("xdmf")
    ap.add_argument("--state", default="last", help="'last', 'first' or a time step number (0-based)")
    ap.add_argument("--scale", type=float, default=50.0, help="displacement magnification of the picture")
    ap.add_argument("--out", help="PNG to write")
    ap.add_argument("--size", default="1000x1100")
    a = ap.parse_args()

    reader = pv.OpenDataFile(a.xdmf)
    if reader is None:
        sys.exit(f"{a.xdmf}: ParaView has no reader for it")
    reader.UpdatePipelineInformation()
    times = list(reader.TimestepValues) if reader.TimestepValues else [0.0]
    if a.state == "last":
        k = len(times) - 1
    elif a.state == "first":
        k = 0
    else:
        k = int(a.state)
    t = times[k]
    reader.UpdatePipeline(t)
    data = sm.Fetch(reader)
    if data.IsA("vtkMultiBlockDataSet"):
        data = data.GetBlock(0)
    cd, pd = data.GetCellData(), data.GetPointData()
    particle = cd.GetArray("particle")
    crack = cd.GetArray("crack")
    n = data.GetNumberOfCells()
    stones = sum(1 for c in range(n) if particle.GetValue(c) >= 0)
    cracks = [int(crack.GetValue(c)) for c in range(n) if crack.GetValue(c) >= 0]
    info = {
        "file": a.xdmf,
        "steps": len(times),
        "time": t,
        "points": data.GetNumberOfPoints(),
        "cells": n,
        "stones": stones,
        "cracks": len(cracks),
        "cracks_tension": cracks.count(0),
        "cracks_shear": cracks.count(1),
        "point_arrays": [pd.GetArrayName(i) for i in range(pd.GetNumberOfArrays())],
        "cell_arrays": [cd.GetArrayName(i) for i in range(cd.GetNumberOfArrays())],
        "polygon_cells": sum(1 for c in range(n) if data.GetCellType(c) == 7),  # VTK_POLYGON
        "line_cells": sum(1 for c in range(n) if data.GetCellType(c) in (3, 4)),  # VTK_LINE, VTK_POLY_LINE
    }
    print(json.dumps(info))
    if not a.out:
        return

    w, h = (int(x) for x in a.size.split("x"))
    view = pv.CreateView("RenderView")
    view.ViewSize = [w, h]
    view.Background = [1, 1, 1]
    view.OrientationAxesVisibility = 0
    view.ViewTime = t
    warp = pv.WarpByVector(Input=reader, Vectors=["POINTS", "displacement"], ScaleFactor=a.scale)
    stones_f = pv.Threshold(Input=warp, Scalars=["CELLS", "particle"], LowerThreshold=0, UpperThreshold=1e9)
    d = pv.Show(stones_f, view)
    d.SetRepresentationType("Surface With Edges")
    d.EdgeColor = [0.3, 0.3, 0.3]
    pv.ColorBy(d, ("CELLS", "rotation"))
    lut = pv.GetColorTransferFunction("rotation")
    lut.ApplyPreset("Cool to Warm", True)
    d.SetScalarBarVisibility(view, True)
    if cracks:
        for mode, colour in [(0, [0.85, 0.1, 0.1]), (1, [0.1, 0.25, 0.85])]:
            f = pv.Threshold(Input=warp, Scalars=["CELLS", "crack"], LowerThreshold=mode, UpperThreshold=mode)
            c = pv.Show(f, view)
            pv.ColorBy(c, None)
            c.AmbientColor = colour
            c.DiffuseColor = colour
            c.LineWidth = 4.0
    title = pv.Text(Text=f"state {int(t)} (x{a.scale:g} displacement): {len(cracks)} broken beams")
    td = pv.Show(title, view)
    td.FontSize = 14
    td.Color = [0, 0, 0]
    td.WindowLocation = "Upper Center"
    view.InteractionMode = "2D"
    pv.ResetCamera(view)
    pv.SaveScreenshot(a.out, view, ImageResolution=[w, h])


if __name__ == "__main__":
    main()
