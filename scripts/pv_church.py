#!/usr/bin/env pvpython
"""Render the church (a results XDMF, or the Gmsh mesh itself) to one PNG with four camera views.

    # the mesh coloured by substructure, straight from the Gmsh file
    xvfb-run -a pvpython scripts/pv_church.py meshes/church.msh --out church-mesh.png
    # a mode shape of a modal run ("time" = mode number), warped automatically
    xvfb-run -a pvpython scripts/pv_church.py results/church-modal/modes.xdmf --mode 1 --out mode1.png
    # the tensile damage at the last time of an earthquake run
    xvfb-run -a pvpython scripts/pv_church.py results/church/results.xdmf --field d_t_max --out damage.png
    # the substructures of any structural result (cell field "group"), named from the mesh
    xvfb-run -a pvpython scripts/pv_church.py results/church-modal/modes.xdmf --field group \
        --names meshes/church.msh --out groups.png

One PNG, four panels: from the south-west (entrance facade and south wall), from the north-east
(tower, choir and sacristy), the south elevation and the plan from above (vaults). Node vector
fields are shown by magnitude, cell fields as they are; `group` is drawn with one colour per
substructure and a legend of the physical names (read from the .msh: `--names`, or the input
itself when it is a .msh). A mode shape (`--mode K`, field `mode_translation` by default) is
warped so that its largest translation is `--warp-fraction` of the church's size; a static or
dynamic result is warped by `--warp` (scale factor, 0 = undeformed) along `--warp-field`.

Gmsh files are read by this script (ASCII MSH 4.1; ParaView has no reader for them): 2-node
lines, 3-node triangles and 4-node quads, with the physical tag of each element as the cell
field `group`; the `supports` group is left out (it lies on the wall bases). Cells where a field
is not defined (NaN: the beams in the shells' damage fields) are grey.
Needs `scripts/setup.sh --paraview` (ParaView 5.11 + xvfb).
"""
import argparse
import math
import os
import sys

from paraview import simple as pv

VIEWS = {
    # name: (direction from the focal point to the camera, view up, title)
    "southwest": ((-1.0, -1.25, 0.75), (0, 0, 1), "from the south-west (entrance)"),
    "northeast": ((1.0, 1.3, 0.75), (0, 0, 1), "from the north-east (tower, choir)"),
    "south": ((0.0, -1.0, 0.05), (0, 0, 1), "south elevation"),
    "top": ((0.0, 0.0, 1.0), (0, 1, 0), "plan, from above"),
    "west": ((-1.0, 0.0, 0.05), (0, 0, 1), "entrance facade"),
    "north": ((0.0, 1.0, 0.05), (0, 0, 1), "north elevation"),
}

PALETTE = [  # colour-blind friendly categorical colours (Okabe-Ito + Tol), one per substructure
    (0.90, 0.62, 0.00), (0.34, 0.71, 0.91), (0.00, 0.62, 0.45), (0.94, 0.89, 0.26), (0.00, 0.45, 0.70),
    (0.84, 0.37, 0.00), (0.80, 0.47, 0.65), (0.47, 0.47, 0.47), (0.20, 0.13, 0.53), (0.53, 0.80, 0.93),
    (0.27, 0.67, 0.60), (0.60, 0.60, 0.20), (0.53, 0.13, 0.33), (0.87, 0.80, 0.47),
]


def read_msh(path):
    """(points, cells [(vtk type, node indices)], physical tag per cell, {tag: name}) of an ASCII
    MSH 4.1 file; the elements of each entity take the entity's first physical tag."""
    with open(path, "rb") as f:
        data = f.read()
    if b"$MeshFormat" not in data[:64]:
        sys.exit(f"{path}: not a Gmsh file")
    lines = data.decode("latin-1").splitlines()
    fmt = lines[1].split()
    if fmt[0] != "4.1" or fmt[1] != "0":
        sys.exit(f"{path}: MSH {fmt[0]} {'binary' if fmt[1] != '0' else 'ASCII'}: this reader needs ASCII MSH 4.1 "
                 "(write it with scripts/make_church_mesh.py without --binary)")
    i = 0
    names, ent_phys, node_index, points, cells, tags = {}, {}, {}, [], [], []
    while i < len(lines):
        s = lines[i].strip()
        if s == "$PhysicalNames":
            n = int(lines[i + 1])
            for k in range(n):
                parts = lines[i + 2 + k].split(maxsplit=2)
                names[(int(parts[0]), int(parts[1]))] = parts[2].strip().strip('"')
            i += n + 2
        elif s == "$Entities":
            counts = [int(x) for x in lines[i + 1].split()]
            j = i + 2
            for dim, count in enumerate(counts):
                for _ in range(count):
                    v = lines[j].split()
                    j += 1
                    if dim == 0:
                        nphys, off = int(v[4]), 5
                    else:
                        nphys, off = int(v[7]), 8
                    phys = [int(x) for x in v[off:off + nphys]]
                    ent_phys[(dim, int(v[0]))] = phys[0] if phys else -1
            i = j
        elif s == "$Nodes":
            nblocks = int(lines[i + 1].split()[0])
            j = i + 2
            for _ in range(nblocks):
                n = int(lines[j].split()[3])
                ids = [int(lines[j + 1 + k]) for k in range(n)]
                for k in range(n):
                    node_index[ids[k]] = len(points)
                    points.append(tuple(float(x) for x in lines[j + 1 + n + k].split()))
                j += 1 + 2 * n
            i = j
        elif s == "$Elements":
            nblocks = int(lines[i + 1].split()[0])
            j = i + 2
            vtk_type = {1: (3, 2), 2: (5, 3), 3: (9, 4)}  # gmsh type -> (VTK type, nodes)
            for _ in range(nblocks):
                dim, ent, gtype, n = (int(x) for x in lines[j].split())
                for k in range(n):
                    if gtype in vtk_type:
                        v = lines[j + 1 + k].split()
                        cells.append((vtk_type[gtype][0], [node_index[int(x)] for x in v[1:]]))
                        tags.append(ent_phys.get((dim, ent), -1))
                j += 1 + n
            i = j
        else:
            i += 1
    return points, cells, tags, {t: n for (d, t), n in names.items()}


def msh_source(path, skip):
    """A ParaView source holding the Gmsh mesh as an unstructured grid with cell field `group`."""
    from vtkmodules.vtkCommonCore import vtkIdList, vtkIntArray, vtkPoints
    from vtkmodules.vtkCommonDataModel import vtkUnstructuredGrid

    points, cells, tags, names = read_msh(path)
    skip_tags = {t for t, n in names.items() if n in skip}
    grid = vtkUnstructuredGrid()
    pts = vtkPoints()
    for p in points:
        pts.InsertNextPoint(*p)
    grid.SetPoints(pts)
    group = vtkIntArray()
    group.SetName("group")
    for (ty, nodes), tag in zip(cells, tags):
        if tag in skip_tags:
            continue
        ids = vtkIdList()
        for n in nodes:
            ids.InsertNextId(n)
        grid.InsertNextCell(ty, ids)
        group.InsertNextValue(tag)
    grid.GetCellData().AddArray(group)
    src = pv.TrivialProducer()
    src.GetClientSideObject().SetOutput(grid)
    return src, names


def read_msh_names(path):
    """Only the $PhysicalNames of a Gmsh file (ASCII or binary: that section is text in both)."""
    names = {}
    with open(path, "rb") as f:
        head = f.read(1 << 16).decode("latin-1").splitlines()
    for k, line in enumerate(head):
        if line.strip() == "$PhysicalNames":
            for row in head[k + 2:k + 2 + int(head[k + 1])]:
                parts = row.split(maxsplit=2)
                names[int(parts[1])] = parts[2].strip().strip('"')
            break
    return names


def array_names(proxy, where):
    data = proxy.PointData if where == "POINTS" else proxy.CellData
    return [data.GetArray(i).GetName() for i in range(data.GetNumberOfArrays())]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("input", help="results XDMF (modes.xdmf, results.xdmf) or a Gmsh .msh")
    ap.add_argument("--field", help="node or cell field (default: group for a .msh, mode_translation with --mode, "
                                     "else displacement)")
    ap.add_argument("--mode", type=int, help="mode number of a modal result (its time value)")
    ap.add_argument("--time", type=float, help="time to show (default: the last)")
    ap.add_argument("--warp", type=float, help="warp scale factor (default: 0, or automatic with --mode)")
    ap.add_argument("--warp-field", help="node vector field to warp by (default mode_translation / displacement)")
    ap.add_argument("--warp-fraction", type=float, default=0.06,
                    help="automatic warp: largest translation as a fraction of the model's size (default 0.06)")
    ap.add_argument("--names", help="Gmsh file whose physical names label the field 'group'")
    ap.add_argument("--views", default="southwest,northeast,south,top",
                    help=f"up to four of {','.join(VIEWS)} (default: southwest,northeast,south,top)")
    ap.add_argument("--range", help="colour range 'min,max' (default: the data's)")
    ap.add_argument("--title", help="text above the panels")
    ap.add_argument("--edges", choices=["auto", "on", "off"], default="auto",
                    help="draw the element edges (auto: on for a .msh, off for results)")
    ap.add_argument("--out", default="church.png")
    ap.add_argument("--size", default="1600x1200", help="image size in pixels")
    a = ap.parse_args()

    views = [v.strip() for v in a.views.split(",") if v.strip()]
    bad = [v for v in views if v not in VIEWS]
    if bad or not 1 <= len(views) <= 4:
        sys.exit(f"--views: one to four of {', '.join(VIEWS)}; got {a.views}")
    width, height = (int(x) for x in a.size.lower().split("x"))

    for path in [a.input] + ([a.names] if a.names else []):
        if not os.path.isfile(path):
            sys.exit(f"no such file: {path}")
    is_msh = a.input.lower().endswith(".msh")
    if is_msh:
        src, names = msh_source(a.input, skip={"supports"})
        t = 0.0
    else:
        src = pv.OpenDataFile(a.input)
        if src is None:
            sys.exit(f"ParaView cannot open {a.input}")
        names = read_msh_names(a.names) if a.names else {}
        times = list(getattr(src, "TimestepValues", []) or [])
        if a.mode is not None:
            if float(a.mode) not in times:
                sys.exit(f"{a.input} has no mode {a.mode} (its times: {times[:20]})")
            t = float(a.mode)
        elif a.time is not None and times:
            t = min(times, key=lambda x: abs(x - a.time))
        else:
            t = times[-1] if times else 0.0
        pv.UpdatePipeline(time=t, proxy=src)

    field = a.field or ("group" if is_msh else ("mode_translation" if a.mode is not None else "displacement"))
    points, cells_ = array_names(src, "POINTS"), array_names(src, "CELLS")
    if field in points:
        assoc = "POINTS"
    elif field in cells_:
        assoc = "CELLS"
    else:
        sys.exit(f"no field '{field}' in {a.input}; node fields: {points}; cell fields: {cells_}")

    bounds = src.GetDataInformation().GetBounds()
    size = math.dist(bounds[0::2], bounds[1::2])
    centre = [(bounds[2 * i] + bounds[2 * i + 1]) / 2 for i in range(3)]
    shown = src
    warp_field = a.warp_field or ("mode_translation" if a.mode is not None else "displacement")
    scale = a.warp if a.warp is not None else 0.0
    if a.warp is None and a.mode is not None:
        amax = src.PointData[warp_field].GetRange(-1)[1]
        scale = a.warp_fraction * size / amax if amax > 0 else 0.0
    if scale:
        if warp_field not in points:
            sys.exit(f"no node vector field '{warp_field}' to warp by; node fields: {points}")
        shown = pv.WarpByVector(Input=src)
        shown.Vectors = ["POINTS", warp_field]
        shown.ScaleFactor = scale

    lut = pv.GetColorTransferFunction(field)
    groups_present = []
    if field == "group":
        rng = src.CellData["group"].GetRange(0)
        groups_present = [g for g in sorted(names) if rng[0] <= g <= rng[1]] or list(range(int(rng[0]), int(rng[1]) + 1))
        lut.InterpretValuesAsCategories = 1
        ann, colours = [], []
        for k, g in enumerate(groups_present):
            ann += [str(g), names.get(g, str(g))]
            colours += list(PALETTE[k % len(PALETTE)])
        lut.Annotations = ann
        lut.IndexedColors = colours
    else:
        lut.ApplyPreset("Turbo" if a.mode is None else "Viridis (matplotlib)", True)
        lut.NanColor = [0.62, 0.62, 0.62]  # cells without the field (beams for shell damage): grey

    layout = pv.CreateLayout("church")
    n = len(views)
    # split the layout into up to 2 x 2 cells; cell indices follow ParaView's binary tree
    cells = [0]
    if n >= 2:
        layout.SplitHorizontal(0, 0.5)
        cells = [1, 2]
    if n >= 3:
        layout.SplitVertical(1, 0.5)
        cells = [3, 4, 2]
    if n == 4:
        layout.SplitVertical(2, 0.5)
        cells = [3, 5, 4, 6]
    pv.GetAnimationScene().UpdateAnimationUsingDataTimeSteps()
    for k, name in enumerate(views):
        view = pv.CreateView("RenderView")
        pv.AssignViewToLayout(view=view, layout=layout, hint=cells[k])
        view.ViewTime = t
        view.Background = [1, 1, 1]
        try:
            view.UseColorPaletteForBackground = 0
        except AttributeError:
            pass
        view.OrientationAxesVisibility = 1
        disp = pv.Show(shown, view)
        pv.ColorBy(disp, (assoc, field, "Magnitude") if assoc == "POINTS" else (assoc, field))
        if field != "group":
            if a.range:
                lo, hi = (float(x) for x in a.range.split(","))
                lut.RescaleTransferFunction(lo, hi)
            else:
                disp.RescaleTransferFunctionToDataRange(False, True)
        disp.LineWidth = 3.0
        if a.edges == "on" or (a.edges == "auto" and is_msh):
            disp.SetRepresentationType("Surface With Edges")
            disp.EdgeColor = [0.25, 0.25, 0.25]
            disp.LineWidth = 1.5  # the element edges too: thinner, or they hide the colours
        disp.Ambient = 0.25
        disp.Diffuse = 0.8
        if k == 0:
            disp.SetScalarBarVisibility(view, True)
            bar = pv.GetScalarBar(lut, view)
            bar.Title = field if field != "group" else "substructure"
            bar.ComponentTitle = ""
            bar.TitleColor = bar.LabelColor = [0, 0, 0]
            bar.TitleFontSize = 14
            bar.LabelFontSize = 13
        label = pv.Text(Text=VIEWS[name][2])
        ld = pv.Show(label, view)
        ld.Color = [0.1, 0.1, 0.1]
        ld.FontSize = 16
        ld.WindowLocation = "Upper Center"
        cam = view.GetActiveCamera()
        d, up, _ = VIEWS[name]
        cam.SetFocalPoint(*centre)
        cam.SetPosition(*[centre[i] + d[i] * size for i in range(3)])
        cam.SetViewUp(*up)
        view.ResetCamera(False)
        cam.Zoom(1.15)
    title = a.title
    if title is None:
        if a.mode is not None:
            title = f"mode {a.mode} (warp x{scale:.3g}), coloured by |{field}|"
        elif field == "group":
            title = "the church by substructure"
        else:
            title = f"{field}" + (f" at t = {t:g}" if not is_msh else "")
    print(f"{a.out}: {title}; {src.GetDataInformation().GetNumberOfPoints()} points, "
          f"{src.GetDataInformation().GetNumberOfCells()} cells; views {', '.join(views)}"
          + (f"; groups {', '.join(names.get(g, str(g)) for g in groups_present)}" if groups_present else ""))
    first = layout.GetViews()[0] if hasattr(layout, "GetViews") else None
    banner = pv.Text(Text=title)
    bd = pv.Show(banner, pv.GetActiveView() if first is None else first)
    bd.Color = [0, 0, 0]
    bd.FontSize = 18
    bd.WindowLocation = "Lower Center"
    layout.SetSize(width, height)
    pv.SaveScreenshot(a.out, layout, ImageResolution=[width, height], TransparentBackground=0)


if __name__ == "__main__":
    main()
