#!/usr/bin/env pvpython
"""The pictures of a time history (a time_history or seismic_assessment job, a sweep member),
rendered with ParaView from its results folder (one process), for any model.

    scripts/with_display.sh pvpython scripts/pv_post.py results/template-building

Writes into `<results>/pictures/` (or --out):
  mesh.png                 the model coloured by group, the groups' names in the legend (from
                           --names: the job's Gmsh file or a groups.csv; default the folder's
                           groups.csv, which the time history writes)
  mode-1.png ... mode-K.png  when the folder has modes: mode K warped (largest translation 6 % of
                           the model's size), coloured by the magnitude of mode_translation, its
                           frequency (summary.json) in the title; the modes of modes-updated.xdmf
                           (an assessment's updated model) when the folder has it, else of
                           modes.xdmf
  damage-tension.png       d_t_max (largest over the layers / fibers) at the last step of
                           results.xdmf, colour map fixed to 0..1: from the south-west, from the
                           north-east, a section through the model's centre (y = --cut-y)
                           looking north, and from below
  damage-tension-gravity.png  the same at the first step of results.xdmf (t = 0: the state after
                           gravity, before the ground moves)
  damage-compression.png   d_c_max at the last step, the same views
  envelope-drift.png       the peak drift ratio of envelopes.xdmf (when the folder has it)
  damage-by-group.csv      per state ("gravity": the first step, "end": the last) and group of
                           shells: area, area share with d_t > 0.05 (cracking begun) and > 0.5
                           (more than half the tensile stiffness lost), largest d_t, area-weighted
                           mean d_t (printed as well), and last the convergence band of the share
                           above 0.5 at the end (from summary.json, when the job's [dynamics]
                           convergence applies; empty otherwise)
  views.json               for each picture: its title, its groups, and each view's name, title
                           and "extent", the largest |coordinate| of the shown model's bounding
                           box in the panel's normalized device coordinates (below 1: inside)

Needs results.xdmf (with its .h5); a missing one is an error (exit 1) that names it. The XDMF
files are read with ParaView's Xdmf3ReaderS. Frequencies: the list of objects with a
"frequency" key in summary.json (at "modes", or under another key, e.g.
`stages.modal_updated.modes` of an assessment for modes-updated.xdmf).
"""
import argparse
import csv
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import pv_church  # noqa: E402  (the rendering: views, framing, colour maps, legends)
from paraview import simple as pv  # noqa: E402

DAMAGE_VIEWS = ("southwest", "northeast", "section", "below")


def find_frequencies(summary, updated):
    """Mode frequencies [Hz] from a summary.json, and where they were found: the lists of objects
    with a "frequency" key. For an updated model's modes (`updated`), the list under a key
    containing "updated" (a pipeline's `stages.modal_updated.modes`); otherwise the list at "modes"
    (a modal run), else the first list under no such key (a pipeline's `stages.modal.modes`)."""
    found = []

    def walk(node, path):
        if isinstance(node, dict):
            for k, v in node.items():
                walk(v, path + [str(k)])
        elif isinstance(node, list):
            if node and all(isinstance(m, dict) and isinstance(m.get("frequency"), (int, float)) for m in node):
                found.append((path, [float(m["frequency"]) for m in node]))
            else:
                for i, v in enumerate(node):
                    walk(v, path + [str(i)])

    walk(summary, [])
    is_updated = [any("updated" in k for k in path) for path, _ in found]
    if updated:
        picks = [f for f, u in zip(found, is_updated) if u]
    else:
        picks = [f for f in found if f[0] == ["modes"]] or [f for f, u in zip(found, is_updated) if not u]
    if picks:
        path, f = picks[0]
        return f, ".".join(path)
    return [], None


def share_bands(summary):
    """The convergence band of each group's share with d_t > 0.5 at the end, from
    summary.json (time_history.damage_by_group[].share_dt_band, written when the job's
    [dynamics] convergence applies): {group: band}, empty when there is none."""
    try:
        with open(summary) as f:
            s = json.load(f)
    except (OSError, ValueError):
        return {}
    th = s.get("time_history") or s.get("stages", {}).get("time_history") or {}
    return {g["group"]: g["share_dt_band"] for g in th.get("damage_by_group", []) if "share_dt_band" in g}


def damage_table(src, field, names, path):
    """Rows (group, area, share > 0.05, share > 0.5, max, mean) of a shell cell field."""
    from paraview import servermanager
    from vtkmodules.util.numpy_support import vtk_to_numpy
    import numpy as np

    sizes = pv.CellSize(Input=src)
    sizes.ComputeArea = 1
    sizes.ComputeLength = sizes.ComputeVolume = sizes.ComputeVertexCount = 0
    grid = servermanager.Fetch(sizes)
    pv.Delete(sizes)
    if grid.IsA("vtkMultiBlockDataSet"):
        grid = grid.GetBlock(0)
    cd = grid.GetCellData()
    for want in (field, "group", "Area"):
        if cd.GetArray(want) is None:
            raise pv_church.InputError(f"{path}: no cell field '{want}' to tabulate")
    d = vtk_to_numpy(cd.GetArray(field)).astype(float)
    g = vtk_to_numpy(cd.GetArray("group")).astype(int)
    area = vtk_to_numpy(cd.GetArray("Area")).astype(float)
    rows = []
    shell = np.isfinite(d) & (area > 0)
    for tag in sorted(set(g[shell].tolist())):
        m = shell & (g == tag)
        a = area[m].sum()
        rows.append((names.get(tag, str(tag)), a, area[m & (d > 0.05)].sum() / a, area[m & (d > 0.5)].sum() / a,
                     float(d[m].max()), float((d[m] * area[m]).sum() / a)))
    a = area[shell].sum()
    if a > 0:
        rows.append(("all shells", a, area[shell & (d > 0.05)].sum() / a, area[shell & (d > 0.5)].sum() / a,
                     float(d[shell].max()), float((d[shell] * area[shell]).sum() / a)))
    return rows


def group_names(path):
    """{physical tag: name} from a Gmsh file or a results folder's groups.csv (dimension,tag,name);
    where two dimensions share a tag, the surfaces' name wins (the shells carry the damage), then
    the curves'."""
    if path.lower().endswith(".msh"):
        return pv_church.read_msh_names(path)
    with open(path, newline="") as fh:
        rows = [r for r in csv.DictReader(fh)]
    names = {}
    for r in sorted(rows, key=lambda r: int(r["dimension"])):
        if r["name"]:
            names[int(r["tag"])] = r["name"]
    return names


def draw_modes(res, out, size, count):
    """mode-1.png ... of the folder's modes (modes-updated.xdmf first); the render reports."""
    updated = os.path.isfile(os.path.join(res, "modes-updated.xdmf"))
    path = os.path.join(res, "modes-updated.xdmf" if updated else "modes.xdmf")
    if not (os.path.isfile(path) and os.path.isfile(path[:-4] + "h5")):
        print(f"no modes in {res}: no mode pictures")
        return []
    freqs, where = [], None
    summary = os.path.join(res, "summary.json")
    if os.path.isfile(summary):
        try:
            with open(summary) as f:
                freqs, where = find_frequencies(json.load(f), updated)
        except (OSError, ValueError) as e:
            print(f"warning: {summary}: {e}; mode titles without frequencies")
    if not where:
        print(f"warning: no mode frequencies for {path} in {summary}; mode titles without frequencies")
    modes, _, _ = pv_church.open_input(path)
    drawn = []
    for k in range(1, min(count, len(pv_church.times_of(modes))) + 1):
        t = pv_church.pick_time(modes, path, mode=k)
        pv_church.association(modes, "mode_translation", path)
        scale = pv_church.auto_warp_scale(modes, "mode_translation", 0.06)
        freq = f": {freqs[k - 1]:.3f} Hz" if k <= len(freqs) else ""
        model = "updated model, " if updated else ""
        drawn.append(pv_church.render(
            modes, os.path.join(out, f"mode-{k}.png"), field="mode_translation", assoc="POINTS", t=t,
            views=("southwest", "northeast", "south", "top"),
            title=f"mode {k}{freq} ({model}shape warped x{scale:.3g}; colour: translation of the mass-normalized mode)",
            warp_field="mode_translation", scale=scale, size=size, bar_title="translation"))
    return drawn


def write_table(out, res, gravity_rows, rows, t0, t):
    """damage-by-group.csv (both states), printed too."""
    f = os.path.join(out, "damage-by-group.csv")
    bands = share_bands(os.path.join(res, "summary.json"))
    with open(f, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["state", "group", "area_m2", "share_dt_above_0.05", "share_dt_above_0.5",
                    "max_dt", "mean_dt", "share_dt_above_0.5_band"])
        for state, table in (("gravity", gravity_rows), ("end", rows)):
            for r in table:
                band = f"{bands[r[0]]:.4f}" if state == "end" and r[0] in bands else ""
                w.writerow([state, r[0], f"{r[1]:.4g}", f"{r[2]:.4f}", f"{r[3]:.4f}",
                            f"{r[4]:.4f}", f"{r[5]:.4f}", band])
    print("tensile damage by group (area share with d_t > 0.05 / > 0.5, max, area mean), "
          f"after gravity (t = {t0:g} s) | at t = {t:g} s:")
    for g, r in zip(gravity_rows, rows):
        print(f"  {r[0]:<14} {r[1]:9.1f} m²  {100 * g[2]:5.1f} % {100 * g[3]:5.1f} % max {g[4]:.3f} mean {g[5]:.3f}"
              f"  |  {100 * r[2]:5.1f} % {100 * r[3]:5.1f} % max {r[4]:.3f} mean {r[5]:.3f}")
    return f


def draw_damage(res, out, size, names, cut_y):
    """The model by group, the damage pictures and the table; the render reports and the table."""
    path = os.path.join(res, "results.xdmf")
    results, _, _ = pv_church.open_input(path)
    t0 = pv_church.pick_time(results, path, time=pv_church.times_of(results)[0])
    pv_church.association(results, "group", path)
    drawn = [pv_church.render(results, os.path.join(out, "mesh.png"), field="group", assoc="CELLS", t=t0,
                              names=names, views=DAMAGE_VIEWS, title="the model by group", edges=True,
                              size=size, cut_y=cut_y)]
    assoc = pv_church.association(results, "d_t_max", path)
    _, hi = pv_church.field_range(results, "d_t_max", assoc, 0)
    drawn.append(pv_church.render(
        results, os.path.join(out, "damage-tension-gravity.png"), field="d_t_max", assoc=assoc, t=t0,
        views=DAMAGE_VIEWS, value_range=(0.0, 1.0), size=size, bar_title="d_t_max", cut_y=cut_y,
        title=f"tensile damage d_t_max (largest over the layers) after gravity (t = {t0:g} s): max {hi:.3g}"))
    gravity_rows = damage_table(results, "d_t_max", names, path)
    t = pv_church.pick_time(results, path)
    for field, what, name in (("d_t_max", "tensile", "damage-tension.png"),
                              ("d_c_max", "compressive", "damage-compression.png")):
        assoc = pv_church.association(results, field, path)
        _, hi = pv_church.field_range(results, field, assoc, 0)
        drawn.append(pv_church.render(
            results, os.path.join(out, name), field=field, assoc=assoc, t=t, views=DAMAGE_VIEWS,
            title=f"{what} damage {field} (largest over the layers) at t = {t:g} s: max {hi:.3g}",
            value_range=(0.0, 1.0), size=size, bar_title=field, cut_y=cut_y))
    rows = damage_table(results, "d_t_max", names, path)
    return drawn, write_table(out, res, gravity_rows, rows, t0, t)


def draw_envelope(res, out, size):
    path = os.path.join(res, "envelopes.xdmf")
    if not (os.path.isfile(path) and os.path.isfile(os.path.join(res, "envelopes.h5"))):
        print(f"no {path}: no envelope picture")
        return []
    env, _, _ = pv_church.open_input(path)
    t = pv_church.pick_time(env, path)
    assoc = pv_church.association(env, "peak_drift_ratio", path)
    _, hi = pv_church.field_range(env, "peak_drift_ratio", assoc, 0)
    return [pv_church.render(
        env, os.path.join(out, "envelope-drift.png"), field="peak_drift_ratio", assoc=assoc, t=t,
        views=("southwest", "northeast", "south", "top"), size=size, bar_title="peak drift ratio",
        title=f"peak drift ratio (horizontal displacement / height above the model's lowest point): max {hi:.3g}")]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("results", help="a time history's results folder")
    ap.add_argument("--names", help="the job's Gmsh file or a groups.csv: group names for the legends and the "
                                    "table (default: the folder's groups.csv; else the tags)")
    ap.add_argument("--out", help="pictures folder (default <results>/pictures)")
    ap.add_argument("--modes", type=int, default=3, help="mode pictures to draw (default 3)")
    ap.add_argument("--size", default="1600x1200", help="image size in pixels (default 1600x1200)")
    ap.add_argument("--cut-y", type=float, default=None,
                    help="the section's plane y = CUT_Y (default: the model's centre)")
    a = ap.parse_args()

    res = a.results
    out = a.out or os.path.join(res, "pictures")
    try:
        width, height = (int(x) for x in a.size.lower().split("x"))
    except ValueError:
        sys.exit(f"--size: expected WIDTHxHEIGHT, got {a.size!r}")
    missing = [f for f in ("results.xdmf", "results.h5") if not os.path.isfile(os.path.join(res, f))]
    if missing:
        sys.exit(f"{res}: missing {', '.join(missing)} (a time history writes them; did the run start?)")
    names_file = a.names or os.path.join(res, "groups.csv")
    if a.names and not os.path.isfile(a.names):
        sys.exit(f"--names: no such file: {a.names}")
    names = group_names(names_file) if os.path.isfile(names_file) else {}
    if not names:
        print(f"no group names ({names_file} missing): groups shown by their tags")
    os.makedirs(out, exist_ok=True)
    size = (width, height)
    try:
        drawn = draw_modes(res, out, size, a.modes)
        damage, table = draw_damage(res, out, size, names, a.cut_y)
        drawn += damage + draw_envelope(res, out, size)
    except pv_church.InputError as e:
        sys.exit(str(e))
    with open(os.path.join(out, "views.json"), "w") as fh:
        json.dump(drawn, fh, indent=1)
    print(f"{len(drawn)} pictures, {os.path.basename(table)} and views.json in {out}")


if __name__ == "__main__":
    main()
