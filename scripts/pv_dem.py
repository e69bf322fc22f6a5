#!/usr/bin/env pvpython
"""Open a DEM sample's particle states (sample-KKK/particles.xdmf) in ParaView, print what the
reader sees as one JSON line, and optionally render the deformed stones and the cracks to a PNG.

    scripts/with_display.sh pvpython scripts/pv_dem.py results/wall-cyclic-shear/sample-000/particles.xdmf
    scripts/with_display.sh pvpython scripts/pv_dem.py results/wall-shear/sample-000/particles.xdmf \
        --state last --scale 50 --out stones.png

JSON: the number of time steps (recorded states), and at the chosen state the points, the cells,
the stones (cells with particle >= 0), the cracks present (crack >= 0, tension 0 / shear 1) and
the point and cell arrays (crushing 2 counted too). The picture: stones warped by
`displacement` x `--scale`, filled in the crack SVGs' stone colour (or coloured by their rotation
with `--rotation`), each with its outline; broken beams as thick lines coloured by failure mode
as in the crack SVGs (tension red, shear/rotation blue, crushing orange), with a legend of the
counts; white background.
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
    ap.add_argument("--rotation", action="store_true", help="colour the stones by their rotation")
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
        "cracks_crushing": cracks.count(2),
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
    if hasattr(view, "UseColorPaletteForBackground"):
        view.UseColorPaletteForBackground = 0  # ParaView >= 5.10: else the palette's grey wins
    view.Background = [1, 1, 1]
    view.OrientationAxesVisibility = 0
    view.ViewTime = t
    warp = pv.WarpByVector(Input=reader, Vectors=["POINTS", "displacement"], ScaleFactor=a.scale)
    # Thresholds on half-integer windows: ParaView 5.11 keeps every cell for [0, 0].
    stones_f = pv.Threshold(Input=warp, Scalars=["CELLS", "particle"], LowerThreshold=-0.5, UpperThreshold=1e9)
    # The stones filled as in the crack SVGs (dem::sample::svg: #ebe3d3), or coloured by their
    # rotation (--rotation, a colour map over the state's range), and each stone's outline drawn
    # on top (#4a4a4a): the polygons' edges as their own wireframe, so outlines show whatever
    # the fill.
    d = pv.Show(stones_f, view)
    d.SetRepresentationType("Surface")
    if a.rotation:
        pv.ColorBy(d, ("CELLS", "rotation"))
        d.RescaleTransferFunctionToDataRange(False, True)
        pv.GetColorTransferFunction("rotation").ApplyPreset("Cool to Warm", True)
        d.SetScalarBarVisibility(view, True)
    else:
        pv.ColorBy(d, None)
        d.AmbientColor = d.DiffuseColor = rgb("#ebe3d3")
        d.Ambient, d.Diffuse = 1.0, 0.0  # flat: the SVGs' colour, unshaded
    outline = pv.Show(pv.ExtractEdges(Input=stones_f), view)
    outline.SetRepresentationType("Wireframe")
    pv.ColorBy(outline, None)
    outline.AmbientColor = outline.DiffuseColor = rgb("#4a4a4a")
    outline.LineWidth = 1.5
    # Cracks by failure mode, the SVGs' colours: tension, shear/rotation, crushing.
    modes = [(0, "tension", "#d62728"), (1, "shear", "#1f77b4"), (2, "crushing", "#ff7f0e")]
    legend = []
    for mode, name, colour in modes:
        count = cracks.count(mode)
        if count == 0:
            continue
        f = pv.Threshold(Input=warp, Scalars=["CELLS", "crack"], LowerThreshold=mode - 0.5, UpperThreshold=mode + 0.5)
        c = pv.Show(f, view)
        pv.ColorBy(c, None)
        c.AmbientColor = c.DiffuseColor = rgb(colour)
        c.LineWidth = 4.0
        legend.append((name, colour, count))
    title = pv.Text(Text=f"state {int(t)} (x{a.scale:g} displacement): {len(cracks)} broken beams")
    td = pv.Show(title, view)
    td.FontSize = 14
    td.Color = [0, 0, 0]
    td.WindowLocation = "Upper Center"
    for k, (name, colour, count) in enumerate(legend):
        lt = pv.Text(Text=f"{name}: {count}")
        ld = pv.Show(lt, view)
        ld.FontSize = 13
        ld.Bold = 1
        ld.Color = rgb(colour)
        ld.WindowLocation = "Any Location"
        ld.Position = [0.02, 0.96 - 0.035 * k]
    view.InteractionMode = "2D"
    pv.ResetCamera(view)
    pv.SaveScreenshot(a.out, view, ImageResolution=[w, h], TransparentBackground=0)


def rgb(hex_colour):
    """'#rrggbb' as ParaView's [r, g, b] in 0..1."""
    return [int(hex_colour[i : i + 2], 16) / 255.0 for i in (1, 3, 5)]

if __name__ == "__main__":
    main()
