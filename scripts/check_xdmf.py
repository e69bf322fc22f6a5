#!/usr/bin/env python3
"""Reads a masonry-hpc results pair (<stem>.xdmf + <stem>.h5) with meshio and h5py and prints JSON.

Usage: python3 scripts/check_xdmf.py RESULTS.xdmf

Printed keys:
  n_nodes, n_cells          from meshio
  cells_meshio              {meshio type: count}; 1-node point cells are stored as zero-length
                            lines (see src/io/output_mesh.rs) so they count as "line" here
  cells_gmsh                {point|line|triangle|quad: count} from /mesh/cell_types (true kinds)
  times                     step times from the XDMF via meshio (JSON floats round-trip exactly)
  h5_times                  /steps/times from h5py
  steps                     per step: time, point_data / cell_data {name: {shape, min, max, and max_norm (largest row norm) for vectors}}
  fields                    {name: {center, n_comp}} over all steps (mesh attributes included)
  h5_matches_meshio         every field meshio returned equals /steps/<k>/<name> bit for bit
Exit status 0 when both readers succeeded, 1 otherwise (the error is printed as JSON "error").
"""
import json
import pathlib
import sys

import h5py
import meshio
import numpy as np

GMSH_NAMES = {15: "point", 1: "line", 2: "triangle", 3: "quad"}
MESH_ATTRS = {"node_id", "cell_id", "group", "gmsh_type"}


def summary(a):
    a = np.asarray(a)
    out = {"shape": list(a.shape), "min": float(a.min()) if a.size else None,
           "max": float(a.max()) if a.size else None}
    if a.ndim == 2 and a.size:
        out["max_norm"] = float(np.sqrt((a * a).sum(axis=1)).max())
    return out


def main(path):
    path = pathlib.Path(path)
    h5 = h5py.File(path.with_suffix(".h5"), "r")
    out = {"xdmf": str(path)}
    cell_types = h5["mesh/cell_types"][()]
    out["cells_gmsh"] = {GMSH_NAMES.get(int(t), str(int(t))): int((cell_types == t).sum())
                         for t in np.unique(cell_types)}
    out["h5_times"] = h5["steps/times"][()].tolist()

    steps = []
    fields = {}
    matches = True
    try:
        reader = meshio.xdmf.TimeSeriesReader(str(path))
        points, cells = reader.read_points_cells()
        for k in range(reader.num_steps):
            t, pdata, cdata = reader.read_data(k)
            step = {"time": t, "point_data": {}, "cell_data": {}}
            for name, a in pdata.items():
                step["point_data"][name] = summary(a)
                fields[name] = {"center": "node", "n_comp": 1 if a.ndim == 1 else int(a.shape[1])}
                if name not in MESH_ATTRS:
                    matches &= bool(np.array_equal(a, h5[f"steps/{k}/{name}"][()]))
            for name, blocks in cdata.items():
                a = np.concatenate(blocks)
                step["cell_data"][name] = summary(a)
                fields[name] = {"center": "cell", "n_comp": 1 if a.ndim == 1 else int(a.shape[1])}
                if name not in MESH_ATTRS:
                    matches &= bool(np.array_equal(a, h5[f"steps/{k}/{name}"][()]))
            steps.append(step)
    except meshio.ReadError:
        # No step completed yet: the index is a single Uniform grid holding the mesh.
        m = meshio.read(str(path))
        points, cells = m.points, m.cells
    out["n_nodes"] = int(len(points))
    counts = {}
    for block in cells:
        counts[block.type] = counts.get(block.type, 0) + int(len(block.data))
    out["cells_meshio"] = counts
    out["n_cells"] = int(sum(counts.values()))
    out["times"] = [s["time"] for s in steps]
    out["steps"] = steps
    out["fields"] = fields
    out["h5_matches_meshio"] = matches
    out["points_match_h5"] = bool(np.array_equal(points, h5["mesh/coordinates"][()]))
    return out


if __name__ == "__main__":
    if len(sys.argv) != 2:
        print(__doc__, file=sys.stderr)
        sys.exit(2)
    try:
        print(json.dumps(main(sys.argv[1]), indent=1))
    except Exception as e:  # report any reader failure as JSON for the calling test
        print(json.dumps({"error": f"{type(e).__name__}: {e}"}))
        sys.exit(1)
