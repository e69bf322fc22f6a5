#!/usr/bin/env python3
"""JSON lines of the wall runs of scripts/bench/structural.sh (called by it with its work folder).

Per run (`wall-times`: variant, nx, nz, seconds, 1-minute load average at the start):
where it ended, the peak force and its displacement, the final force, the dissipated energy at
1.75 mm and at the end (2.8 mm), the top's largest settlement, and where the compression damage
d_c (largest over the layers, per cell, last converged step) sits:
  dc_xz_correlation   the d_c-weighted Pearson correlation of the cells' centroid x and z in
                      the rows between the top and bottom rows: -1 for damage on the loaded
                      diagonal (top-left to bottom-right corner), 0 for horizontal bands or a
                      uniform field;
  dc_share_end_rows   the share of the sum of d_c in the top and bottom cell rows;
  dt_share_end_rows   the same for the tensile damage d_t.
Per variant: the spread (max - min) / mean of the energy at the end over the three finest meshes
(15 x 18, 20 x 24, 25 x 30) and over all five, None when a run stopped before 2.8 mm.
"""
import csv
import json
import math
import os
import sys

import h5py
import numpy as np

TARGET = 2.8e-3
W, H = 1.0, 1.2


def energy_at(rows, x):
    """Dissipated energy at control displacement x (linear interpolation), None if not reached."""
    pts = [(r["d"], r["e"]) for r in rows]
    for (x0, e0), (x1, e1) in zip(pts, pts[1:]):
        if x0 <= x <= x1:
            return e0 + (e1 - e0) * (x - x0) / (x1 - x0) if x1 > x0 else e1
    return None


def damage_location(path, nx, nz):
    """(d_c correlation, d_c share in the end rows, d_t share there, top settlement) at the last step."""
    with h5py.File(path) as h:
        steps = [int(k) for k in h["steps"].keys() if k.isdigit()]
        if not steps:
            return None, None, None, None
        last = h[f"steps/{max(steps)}"]
        types = h["mesh/cell_types"][:]
        ids = h["mesh/cell_ids"][:]
        quads = np.where(types == 3)[0]
        # make_quad_mesh.py numbers the quads row by row (x fastest): their tags in that order.
        order = quads[np.argsort(ids[quads])]
        dc = last["d_c_max"][:][order]
        dt = last["d_t_max"][:][order]
        settle = -float(last["displacement"][:, 2].min())
    i = np.arange(nx * nz) % nx
    k = np.arange(nx * nz) // nx
    x = (i + 0.5) * W / nx
    z = (k + 0.5) * H / nz
    ends = (k == 0) | (k == nz - 1)
    corr = None
    if dc[~ends].sum() > 0:
        w = np.where(ends, 0.0, dc) / dc[~ends].sum()
        mx, mz = (w * x).sum(), (w * z).sum()
        cxz = (w * (x - mx) * (z - mz)).sum()
        sx, sz = math.sqrt((w * (x - mx) ** 2).sum()), math.sqrt((w * (z - mz) ** 2).sum())
        corr = cxz / (sx * sz) if sx > 0 and sz > 0 else None
    share = lambda d: float(d[ends].sum() / d.sum()) if d.sum() > 0 else None
    return corr, share(dc), share(dt), settle


def main(work):
    runs = [l.split() for l in open(os.path.join(work, "wall-times")) if l.strip()]
    ends = {}
    for v, nx, nz, seconds, load in runs:
        nx, nz = int(nx), int(nz)
        out = os.path.join(work, f"wall-out-{v}-{nx}")
        rows = []
        if os.path.exists(os.path.join(out, "curve.csv")):
            rows = [
                {"d": float(r["control_displacement"]), "f": float(r["control_force"]), "e": float(r["dissipated_energy"])}
                for r in csv.DictReader(open(os.path.join(out, "curve.csv")))
                if r["stage"] == "control"
            ]
        err = open(os.path.join(work, f"wall-{v}-{nx}.err")).read().strip()
        line = {"case": f"wall-shear-fe-{v}", "size": f"{nx}x{nz}", "seconds": round(float(seconds), 2), "load_average_at_start": float(load)}
        if rows:
            k = max(range(len(rows)), key=lambda j: rows[j]["f"])
            reached = rows[-1]["d"] >= TARGET - 1e-9
            loc = damage_location(os.path.join(out, "results.h5"), nx, nz) if os.path.exists(os.path.join(out, "results.h5")) else (None,) * 4
            line.update({
                "final_displacement": rows[-1]["d"], "peak_force": rows[k]["f"], "peak_displacement": rows[k]["d"],
                "final_force": rows[-1]["f"], "dissipated_energy": rows[-1]["e"], "dissipated_energy_at_1.75mm": energy_at(rows, 1.75e-3),
                "top_settlement_m": loc[3], "dc_xz_correlation": loc[0], "dc_share_end_rows": loc[1], "dt_share_end_rows": loc[2],
            })
            ends.setdefault(v, {})[(nx, nz)] = rows[-1]["e"] if reached else None
        else:
            ends.setdefault(v, {})[(nx, nz)] = None
        if err:
            line["stopped"] = err.splitlines()[-1][:400]
        print(json.dumps(line))
    for v, e in ends.items():
        if len(e) < 3:
            continue
        def spread(keys):
            vals = [e.get(m) for m in keys]
            if any(x is None for x in vals):
                return None
            return round((max(vals) - min(vals)) / (sum(vals) / len(vals)), 4)
        finest = [(15, 18), (20, 24), (25, 30)]
        print(json.dumps({
            "case": f"wall-shear-fe-{v}-energy-spread", "size": "15x18,20x24,25x30", "seconds": 0.0,
            "energy_spread_over_mean_at_end": spread(finest),
            "energy_spread_over_mean_at_end_all_five": spread(sorted(e)), "target": 0.05,
        }))


if __name__ == "__main__":
    main(sys.argv[1])
