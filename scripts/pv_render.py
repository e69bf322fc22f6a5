#!/usr/bin/env pvpython
"""Render a masonry-hpc result (XDMF) to PNG with ParaView.

    scripts/with_display.sh pvpython scripts/pv_render.py results/tower/results.xdmf \
        --field displacement --warp 20 --out tower.png

Opens the XDMF index with ParaView's XDMF reader, takes the last time step, optionally warps the
mesh by the displacement field (scale factor --warp), colours it by --field (node or cell field;
vectors by magnitude) and saves a PNG. Needs `scripts/setup.sh --paraview` (ParaView + Xvfb).
"""
import argparse
import sys

from paraview.simple import (ColorBy, GetActiveViewOrCreate, GetAnimationScene, OpenDataFile,
                             ResetCamera, SaveScreenshot, Show, WarpByVector, GetColorTransferFunction,
                             UpdatePipeline)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("xdmf")
    ap.add_argument("--field", default="displacement")
    ap.add_argument("--warp", type=float, default=0.0, help="displacement scale factor (0: undeformed)")
    ap.add_argument("--warp-field", default="displacement", help="node vector field to warp by")
    ap.add_argument("--time", type=float, default=None, help="time step to show (default: the last)")
    ap.add_argument("--out", default="render.png")
    ap.add_argument("--size", default="1200x900")
    ap.add_argument("--view", default="iso", choices=["iso", "x", "y", "z"])
    a = ap.parse_args()

    src = OpenDataFile(a.xdmf)
    if src is None:
        sys.exit(f"ParaView cannot open {a.xdmf}")
    scene = GetAnimationScene()
    scene.UpdateAnimationUsingDataTimeSteps()
    times = list(getattr(src, "TimestepValues", []) or [0.0])
    t = times[-1] if a.time is None else min(times, key=lambda x: abs(x - a.time))
    UpdatePipeline(time=t, proxy=src)
    shown = src
    if a.warp:
        shown = WarpByVector(Input=src)
        shown.Vectors = ["POINTS", a.warp_field]
        shown.ScaleFactor = a.warp
    view = GetActiveViewOrCreate("RenderView")
    view.ViewTime = t
    w, h = (int(x) for x in a.size.split("x"))
    view.ViewSize = [w, h]
    view.Background = [1, 1, 1]
    try:
        view.OrientationAxesVisibility = 1
    except AttributeError:
        pass
    disp = Show(shown, view)
    info = shown.GetDataInformation()
    point_names = [shown.PointData.GetArray(i).GetName() for i in range(shown.PointData.GetNumberOfArrays())]
    cell_names = [shown.CellData.GetArray(i).GetName() for i in range(shown.CellData.GetNumberOfArrays())]
    if a.field in point_names:
        ColorBy(disp, ("POINTS", a.field, "Magnitude"))
    elif a.field in cell_names:
        ColorBy(disp, ("CELLS", a.field))
    else:
        sys.exit(f"no field '{a.field}'; node fields: {point_names}; cell fields: {cell_names}")
    disp.RescaleTransferFunctionToDataRange(True, False)
    disp.SetScalarBarVisibility(view, True)
    lut = GetColorTransferFunction(a.field)
    lut.ApplyPreset("Turbo", True)
    try:
        disp.LineWidth = 2.0
    except AttributeError:
        pass
    cam = view.GetActiveCamera()
    if a.view == "iso":
        cam.SetPosition(1, -1, 0.6)
        cam.SetViewUp(0, 0, 1)
    elif a.view == "x":
        cam.SetPosition(1, 0, 0)
        cam.SetViewUp(0, 0, 1)
    elif a.view == "y":
        cam.SetPosition(0, -1, 0)
        cam.SetViewUp(0, 0, 1)
    else:
        cam.SetPosition(0, 0, 1)
        cam.SetViewUp(0, 1, 0)
    cam.SetFocalPoint(0, 0, 0)
    ResetCamera(view)
    SaveScreenshot(a.out, view, ImageResolution=[w, h])
    print(f"{a.out}: {info.GetNumberOfPoints()} points, {info.GetNumberOfCells()} cells, "
          f"time {t}, coloured by {a.field}")


if __name__ == "__main__":
    main()
