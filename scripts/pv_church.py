#!/usr/bin/env pvpython
"""Render a model (a results XDMF, or the Gmsh mesh itself) to one PNG with up to four views: the
renderer of scripts/pv_post.py (any building) and of the church's pictures.

    # the mesh coloured by substructure, straight from the Gmsh file
    scripts/with_display.sh pvpython scripts/pv_church.py meshes/church.msh --out church-mesh.png
    # a mode shape of a modal run ("time" = mode number), warped automatically
    scripts/with_display.sh pvpython scripts/pv_church.py results/church-modal/modes.xdmf --mode 1 --out mode1.png
    # the tensile damage at the last time of an earthquake run
    scripts/with_display.sh pvpython scripts/pv_church.py results/church/results.xdmf --field d_t_max --out damage.png
    # the substructures of any structural result (cell field "group"), named from the mesh
    scripts/with_display.sh pvpython scripts/pv_church.py results/church-modal/modes.xdmf --field group \
        --names meshes/church.msh --out groups.png

One PNG, one to four panels named by direction (x east, y north): by default from the
south-west, from the north-east, the south elevation and the plan from above. The title and the
colour bar have a row above the panels; each panel is framed so that the whole model is inside
it; an elevation shows the half of the model nearer its camera (openings show the background),
the "section" the half beyond y = --cut-y (default: the model's centre). Node vector fields are
shown by magnitude, cell fields as they are; `group` is drawn with one colour per group and a
legend of the physical names (read from the .msh: `--names`, or the input itself when it is a
.msh). A mode shape (`--mode K`, field `mode_translation` by default) is warped so that its
largest translation is `--warp-fraction` of the model's size; a static or dynamic result is
warped by `--warp` (scale factor, 0 = undeformed) along `--warp-field`.

Gmsh files are read by this script (ASCII MSH 4.1; ParaView has no reader for them): 2-node
lines, 3-node triangles and 4-node quads, with the physical tag of each element as the cell
field `group`; the `supports` group is left out (it lies on the wall bases). Cells where a field
is not defined (NaN: the beams in the shells' damage fields) are grey.
Needs `scripts/setup.sh --paraview` (ParaView 5.11 + Xvfb).
"""
import argparse
import math
import os
import sys

from paraview import simple as pv

VIEWS = {
    # name: (direction from the focal point to the camera, view up, title); x is east, y north
    "southwest": ((-1.0, -1.25, 0.75), (0, 0, 1), "from the south-west"),
    "northeast": ((1.0, 1.3, 0.75), (0, 0, 1), "from the north-east"),
    "southeast": ((1.0, -1.25, 0.75), (0, 0, 1), "from the south-east"),
    "northwest": ((-1.0, 1.3, 0.75), (0, 0, 1), "from the north-west"),
    "south": ((0.0, -1.0, 0.05), (0, 0, 1), "south elevation"),
    "north": ((0.0, 1.0, 0.05), (0, 0, 1), "north elevation"),
    "west": ((-1.0, 0.0, 0.05), (0, 0, 1), "west elevation"),
    "east": ((1.0, 0.0, 0.05), (0, 0, 1), "east elevation"),
    "top": ((0.0, 0.0, 1.0), (0, 1, 0), "plan, from above"),
    "below": ((0.0, 0.0, -1.0), (0, -1, 0), "from below (north at the bottom)"),
    # the half beyond the plane y = cut_y (default: the model's centre), from the south and a
    # little from below
    "section": ((0.1, -1.0, -0.45), (0, 0, 1), "section at y = {cut:.3g} m, looking north"),
}

# An elevation shows the half of the model nearer its camera (cut at the model's centre), so that
# openings show the background and not the far wall through them.
ELEVATIONS = ("south", "north", "west", "east")

PALETTE = [  # colour-blind friendly categorical colours (Okabe-Ito + Tol), one per substructure
    (0.90, 0.62, 0.00), (0.34, 0.71, 0.91), (0.00, 0.62, 0.45), (0.94, 0.89, 0.26), (0.00, 0.45, 0.70),
    (0.84, 0.37, 0.00), (0.80, 0.47, 0.65), (0.47, 0.47, 0.47), (0.20, 0.13, 0.53), (0.53, 0.80, 0.93),
    (0.27, 0.67, 0.60), (0.60, 0.60, 0.20), (0.53, 0.13, 0.33), (0.87, 0.80, 0.47),
]


# A rainbow that starts light: undamaged (or still) parts stay light grey-blue, so the shading
# shows the shape, and the colour runs through blue, green, yellow and orange to dark red.
LIGHT_RAINBOW = [  # (fraction of the range, r, g, b)
    (0.0, 0.82, 0.86, 0.92), (0.2, 0.35, 0.62, 0.95), (0.4, 0.25, 0.78, 0.45),
    (0.6, 1.00, 0.84, 0.10), (0.8, 0.95, 0.45, 0.05), (1.0, 0.65, 0.00, 0.00),
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


class InputError(Exception):
    """A missing file, time or field: the message says which."""


def open_input(path, names_path=None, skip=("supports",)):
    """(source, {physical tag: name}, is_msh) of a results XDMF or a Gmsh .msh."""
    for p in [path] + ([names_path] if names_path else []):
        if not os.path.isfile(p):
            raise InputError(f"no such file: {p}")
    if path.lower().endswith(".msh"):
        src, names = msh_source(path, skip=set(skip))
        return src, names, True
    src = pv.Xdmf3ReaderS(FileName=[path]) if path.lower().endswith(".xdmf") else pv.OpenDataFile(path)
    if src is None:
        raise InputError(f"ParaView cannot open {path}")
    return src, (read_msh_names(names_path) if names_path else {}), False


def times_of(src):
    """The source's time values (ParaView gives a bare number when there is one)."""
    v = getattr(src, "TimestepValues", None)
    if v is None:
        return []
    if isinstance(v, (int, float)):
        return [float(v)]
    return [float(x) for x in v]


def pick_time(src, path, mode=None, time=None):
    """The time to show: the mode number of a modal result, the nearest to `time`, or the last."""
    times = times_of(src)
    if mode is not None:
        if float(mode) not in times:
            raise InputError(f"{path} has no mode {mode} (its times: {times[:20]})")
        t = float(mode)
    elif time is not None and times:
        t = min(times, key=lambda x: abs(x - time))
    else:
        t = times[-1] if times else 0.0
    # The proxy's own UpdatePipeline: paraview.simple's skips a time of 0.0 (falsy) and keeps
    # the data of the time shown before.
    src.UpdatePipeline(t)
    return t


def association(src, field, path):
    """'POINTS' or 'CELLS' for a field of `src`; an InputError listing the fields otherwise."""
    points, cells = array_names(src, "POINTS"), array_names(src, "CELLS")
    if field in points:
        return "POINTS"
    if field in cells:
        return "CELLS"
    raise InputError(f"no field '{field}' in {path}; node fields: {points}; cell fields: {cells}")


def field_range(src, field, assoc, component=-1):
    data = src.PointData if assoc == "POINTS" else src.CellData
    return data[field].GetRange(component)


def bounds_of(src):
    b = src.GetDataInformation().GetBounds()
    size = math.dist(b[0::2], b[1::2])
    centre = [(b[2 * i] + b[2 * i + 1]) / 2 for i in range(3)]
    return b, size, centre


def auto_warp_scale(src, warp_field, fraction):
    """The scale that makes the largest translation `fraction` of the model's diagonal."""
    amax = src.PointData[warp_field].GetRange(-1)[1]
    return fraction * bounds_of(src)[1] / amax if amax > 0 else 0.0


def clip_half(src, origin, normal):
    """The cells of `src` on the side of the plane (`origin`, `normal`) the normal points to,
    whole (crinkle clip: no cut cells interpolating a cell field)."""
    c = pv.Clip(Input=src)
    c.ClipType = "Plane"
    c.ClipType.Origin = list(origin)
    c.ClipType.Normal = list(normal)
    c.Invert = 0
    c.Crinkleclip = 1
    return c


def panel_cells(layout, n):
    """Splits the layout's lower cell (2) into n panels (1: whole; 2: side by side; 3: two on
    the left, one on the right; 4: 2 x 2) and returns their cell indices and their fraction of the
    panel area's width and height (ParaView's binary tree: the children of cell i are 2i+1, 2i+2)."""
    if n == 1:
        return [2], [(1.0, 1.0)]
    layout.SplitHorizontal(2, 0.5)
    if n == 2:
        return [5, 6], [(0.5, 1.0)] * 2
    layout.SplitVertical(5, 0.5)
    if n == 3:
        return [11, 12, 6], [(0.5, 0.5), (0.5, 0.5), (0.5, 1.0)]
    layout.SplitVertical(6, 0.5)
    return [11, 13, 12, 14], [(0.5, 0.5)] * 4


def corners(b):
    return [(b[i], b[2 + j], b[4 + k]) for i in (0, 1) for j in (0, 1) for k in (0, 1)]


def ndc_extent(cam, b, aspect):
    """The largest |x|, |y| of the bounds `b`'s corners in the camera's normalized device
    coordinates (−1..1 across the panel) at the panel's `aspect` (width / height)."""
    m = cam.GetCompositeProjectionTransformMatrix(aspect, -1, 1)
    ext = 0.0
    for c in corners(b):
        q = m.MultiplyPoint((c[0], c[1], c[2], 1.0))
        if q[3] > 0:
            ext = max(ext, abs(q[0] / q[3]), abs(q[1] / q[3]))
    return ext


def fit_camera(view, cam, b, aspect, margin=0.88):
    """Zooms so that the bounds `b` fill `margin` of the panel in its tighter direction: the whole
    model inside the frame whatever the panel's shape. Returns the final extent (<= 1: inside)."""
    view.ResetCamera(False)
    for _ in range(4):
        ext = ndc_extent(cam, b, aspect)
        if ext <= 0:
            break
        cam.Zoom(margin / ext)
    return ndc_extent(cam, b, aspect)


def colour_map(src, field, assoc, names, value_range, colormap):
    """The colour map of `field`: categories with `names` for "group", else a range."""
    lut = pv.GetColorTransferFunction(field)
    groups_present, lo, hi = [], 0.0, 1.0
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
        lut.InterpretValuesAsCategories = 0
        lo, hi = value_range if value_range else field_range(src, field, assoc)
        if hi <= lo:
            hi = lo + 1.0
        if colormap == "light-rainbow":
            lut.ColorSpace = "RGB"
            lut.RGBPoints = [v for f, r, g, b in LIGHT_RAINBOW for v in (lo + f * (hi - lo), r, g, b)]
        else:
            lut.ApplyPreset(colormap, True)
        lut.NanColor = [0.55, 0.55, 0.55]  # cells without the field (beams for shell damage): grey
        lut.AutomaticRescaleRangeMode = "Never"
        lut.RescaleTransferFunction(lo, hi)
    return lut, groups_present, (lo, hi)


def white(view):
    view.Background = [1, 1, 1]
    try:
        view.UseColorPaletteForBackground = 0
    except AttributeError:
        pass


def render(src, out, *, field, assoc, t, names=None, views=("southwest", "northeast", "south", "top"),
           title="", warp_field=None, scale=0.0, value_range=None, edges=False, size=(1600, 1200),
           colormap="light-rainbow", bar_title=None, cut_y=None, quiet=False):
    """Renders `field` of `src` at time `t` in one to four views to the PNG `out`, and returns
    what it drew: {"file", "title", "groups", "views": [{"name", "title", "extent"}]}, "extent"
    the largest |coordinate| of the shown model's bounding box in the panel's normalized device
    coordinates (below 1: the whole model is inside the frame).

    Views are keys of VIEWS. "section" keeps the half beyond the plane y = `cut_y` (default: the
    model's centre) and looks at it from the south, slightly from below; an elevation keeps the
    half nearer its camera. Every view is framed to its panel's shape, and the title and the
    colour bar have a row of their own above the panels, clear of the model. `value_range` fixes
    the colour map's range (default: the data's). `field` "group" is drawn with one colour per
    group and a legend of `names`. Node vectors are coloured by magnitude; cells without the
    field (NaN) are grey. Views and filters are deleted afterwards, so one process can render
    many pictures."""
    names = names or {}
    width, height = size
    _, model_size, centre = bounds_of(src)
    cut = centre[1] if cut_y is None else cut_y
    made = []  # proxies to delete at the end
    shown = src
    if scale:
        shown = pv.WarpByVector(Input=src)
        shown.Vectors = ["POINTS", warp_field]
        shown.ScaleFactor = scale
        made.append(shown)
    lut, groups_present, (lo, hi) = colour_map(src, field, assoc, names, value_range, colormap)

    layout = pv.CreateLayout(os.path.basename(out))
    head_px = 118  # the title and, below it, the colour bar
    layout.SplitVertical(0, head_px / height)
    cells, fractions = panel_cells(layout, len(views))
    view_proxies, drawn = [], []
    for k, name in enumerate(views):
        view = pv.CreateView("RenderView")
        view_proxies.append(view)
        pv.AssignViewToLayout(view=view, layout=layout, hint=cells[k])
        view.ViewTime = t
        white(view)
        view.OrientationAxesVisibility = 1
        d, up, label_text = VIEWS[name]
        this = shown
        if name == "section":
            this = clip_half(shown, (centre[0], cut, centre[2]), (0.0, 1.0, 0.0))
        elif name in ELEVATIONS:
            this = clip_half(shown, centre, (d[0], d[1], 0.0))
        if this is not shown:
            made.append(this)
        disp = pv.Show(this, view)
        pv.ColorBy(disp, (assoc, field, "Magnitude") if assoc == "POINTS" else (assoc, field))
        if field != "group":
            lut.RescaleTransferFunction(lo, hi)  # ColorBy may have rescaled it to the data
        disp.SetScalarBarVisibility(view, False)
        disp.LineWidth = 3.0
        if edges:
            disp.SetRepresentationType("Surface With Edges")
            disp.EdgeColor = [0.25, 0.25, 0.25]
            disp.LineWidth = 1.5  # the element edges too: thinner, or they hide the colours
        disp.Ambient = 0.25
        disp.Diffuse = 0.8
        label = pv.Text(Text=label_text.format(cut=cut))
        made.append(label)
        ld = pv.Show(label, view)
        ld.Color = [0.1, 0.1, 0.1]
        ld.FontSize = 15
        ld.WindowLocation = "Upper Center"
        cam = view.GetActiveCamera()
        this.UpdatePipeline(t)
        b = this.GetDataInformation().GetBounds()
        focus = [(b[2 * i] + b[2 * i + 1]) / 2 for i in range(3)]
        cam.SetFocalPoint(*focus)
        cam.SetPosition(*[focus[i] + d[i] * model_size for i in range(3)])
        cam.SetViewUp(*up)
        fw, fh = fractions[k]
        aspect = (fw * width) / (fh * (height - head_px))
        extent = fit_camera(view, cam, b, aspect)
        drawn.append({"name": name, "title": label_text.format(cut=cut), "extent": round(extent, 4)})
    if not quiet:
        print(f"{out}: {title}; {src.GetDataInformation().GetNumberOfPoints()} points, "
              f"{src.GetDataInformation().GetNumberOfCells()} cells; views {', '.join(views)}"
              + (f"; groups {', '.join(names.get(g, str(g)) for g in groups_present)}" if groups_present else ""))
    head = pv.CreateView("RenderView")
    view_proxies.append(head)
    pv.AssignViewToLayout(view=head, layout=layout, hint=1)
    white(head)
    head.OrientationAxesVisibility = 0
    banner = pv.Text(Text=title)
    made.append(banner)
    bd = pv.Show(banner, head)
    bd.Color = [0, 0, 0]
    bd.FontSize = 18
    bd.WindowLocation = "Upper Center"
    bar = pv.GetScalarBar(lut, head)
    bar.Visibility = 1
    bar.Title = bar_title or (field if field != "group" else "group")
    bar.ComponentTitle = ""
    bar.TitleColor = bar.LabelColor = [0, 0, 0]
    bar.TitleFontSize = 14
    bar.LabelFontSize = 13
    bar.Orientation = "Horizontal"
    bar.WindowLocation = "Any Location"
    bar.ScalarBarThickness = 14
    if field == "group":
        # The groups' names are written below their colours: room for them in the row.
        bar.Position = [0.15, 0.32]
        bar.ScalarBarLength = 0.7
        bar.DrawTickMarks = 0
    else:
        bar.Position = [0.3, 0.04]
        bar.ScalarBarLength = 0.4
        bar.RangeLabelFormat = "%-#.3g"
    layout.SetSize(width, height)
    pv.SaveScreenshot(out, layout, ImageResolution=[width, height], TransparentBackground=0)
    for v in view_proxies:
        pv.Delete(v)
    pv.RemoveLayout(layout)
    for p in reversed(made):
        pv.Delete(p)
    return {"file": os.path.basename(out), "title": title, "views": drawn,
            "groups": [names.get(g, str(g)) for g in groups_present]}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("input", help="results XDMF (modes.xdmf, results.xdmf) or a Gmsh .msh")
    ap.add_argument("--field", help="node or cell field (default: group for a .msh, mode_translation with --mode, "
                                     "else displacement)")
    ap.add_argument("--mode", type=int, help="mode number of a modal result (its time value)")
    ap.add_argument("--frequency", type=float, help="the mode's frequency [Hz], shown in the title")
    ap.add_argument("--time", type=float, help="time to show (default: the last)")
    ap.add_argument("--warp", type=float, help="warp scale factor (default: 0, or automatic with --mode)")
    ap.add_argument("--warp-field", help="node vector field to warp by (default mode_translation / displacement)")
    ap.add_argument("--warp-fraction", type=float, default=0.06,
                    help="automatic warp: largest translation as a fraction of the model's size (default 0.06)")
    ap.add_argument("--names", help="Gmsh file whose physical names label the field 'group'")
    ap.add_argument("--views", default="southwest,northeast,south,top",
                    help=f"up to four of {','.join(VIEWS)} (default: southwest,northeast,south,top)")
    ap.add_argument("--cut-y", type=float, default=None, help="the 'section' view's cutting plane y = CUT_Y (default: the model's centre)")
    ap.add_argument("--range", help="colour range 'min,max' (default: the data's)")
    ap.add_argument("--colormap", default="light-rainbow",
                    help="ParaView colour preset, or light-rainbow (default: light grey-blue to dark red)")
    ap.add_argument("--title", help="text below the first panel")
    ap.add_argument("--edges", choices=["auto", "on", "off"], default="auto",
                    help="draw the element edges (auto: on for a .msh, off for results)")
    ap.add_argument("--out", default="model.png")
    ap.add_argument("--size", default="1600x1200", help="image size in pixels")
    a = ap.parse_args()

    views = [v.strip() for v in a.views.split(",") if v.strip()]
    bad = [v for v in views if v not in VIEWS]
    if bad or not 1 <= len(views) <= 4:
        sys.exit(f"--views: one to four of {', '.join(VIEWS)}; got {a.views}")
    try:
        width, height = (int(x) for x in a.size.lower().split("x"))
        value_range = tuple(float(x) for x in a.range.split(",")) if a.range else None
    except ValueError:
        sys.exit(f"--size WxH and --range min,max: got {a.size!r}, {a.range!r}")
    try:
        src, names, is_msh = open_input(a.input, a.names)
        t = 0.0 if is_msh else pick_time(src, a.input, a.mode, a.time)
        field = a.field or ("group" if is_msh else ("mode_translation" if a.mode is not None else "displacement"))
        assoc = association(src, field, a.input)
        warp_field = a.warp_field or ("mode_translation" if a.mode is not None else "displacement")
        scale = a.warp if a.warp is not None else 0.0
        if scale or (a.warp is None and a.mode is not None):
            association(src, warp_field, a.input)
        if a.warp is None and a.mode is not None:
            scale = auto_warp_scale(src, warp_field, a.warp_fraction)
    except InputError as e:
        sys.exit(str(e))
    title = a.title
    if title is None:
        if a.mode is not None:
            freq = f", {a.frequency:.3g} Hz" if a.frequency is not None else ""
            title = f"mode {a.mode}{freq} (warp x{scale:.3g}), coloured by the magnitude of {field}"
        elif field == "group":
            title = "the model by group"
        else:
            title = f"{field}" + (f" at t = {t:g}" if not is_msh else "")
    render(src, a.out, field=field, assoc=assoc, t=t, names=names, views=views, title=title,
           warp_field=warp_field, scale=scale, value_range=value_range,
           edges=a.edges == "on" or (a.edges == "auto" and is_msh), size=(width, height),
           colormap=a.colormap, cut_y=a.cut_y)


if __name__ == "__main__":
    main()
