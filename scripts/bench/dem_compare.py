#!/usr/bin/env python3
"""Compares a DEM compression run against a reference run of examples/dem_profile.rs.

    scripts/bench/dem_compare.py REF_CURVE REF_BROKEN CURVE BROKEN [--tol 1e-8]

CURVE files: `state,strain,stress,broken` (dem_profile's fourth argument); BROKEN files:
`event,beam,mode,state` (DEM_BROKEN_CSV). Passes (exit 0) when the beams break in the same order
in the same modes at the same states, the two runs record the same number of states, and the
stresses at the regular load points (the ends of the `steps` load steps, strains at whole
multiples of max_strain/steps) agree within `tol` times the reference's peak |stress|. Prints
one JSON line with the largest differences: at the regular points, and over all states (the
states at the breaks, whose strains come from a load fraction known to Newton's tolerance,
10⁻⁸ of the step: reported, not checked).
"""
import argparse
import csv
import json
import sys


def rows(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("ref_curve")
    ap.add_argument("ref_broken")
    ap.add_argument("curve")
    ap.add_argument("broken")
    ap.add_argument("--tol", type=float, default=1e-8)
    ap.add_argument("--steps", type=int, default=40, help="load steps of the runs (regular points)")
    a = ap.parse_args()
    rc, c = rows(a.ref_curve), rows(a.curve)
    rb, b = rows(a.ref_broken), rows(a.broken)
    problems = []
    key = lambda r: (r["beam"], r["mode"], r["state"])
    first = next((k for k, (x, y) in enumerate(zip(rb, b)) if key(x) != key(y)), None)
    if len(rb) != len(b) or first is not None:
        problems.append(f"breaks differ: {len(rb)} vs {len(b)}, first difference at event {first}")
    if len(rc) != len(c):
        problems.append(f"recorded states differ: {len(rc)} vs {len(c)}")
    peak = max(abs(float(r["stress"])) for r in rc)
    emax = max(abs(float(r["strain"])) for r in rc)
    step = emax / a.steps
    d_all, d_reg, d_strain, n_reg = 0.0, 0.0, 0.0, 0
    for x, y in zip(rc, c):
        ex, ey = float(x["strain"]), float(y["strain"])
        d_strain = max(d_strain, abs(ex - ey))
        d = abs(float(x["stress"]) - float(y["stress"]))
        d_all = max(d_all, d)
        if abs(ex / step - round(ex / step)) < 1e-9:
            d_reg = max(d_reg, d)
            n_reg += 1
    if n_reg != a.steps + 1:
        problems.append(f"{n_reg} regular load points, expected {a.steps + 1}")
    if d_reg > a.tol * peak:
        problems.append(f"stress at a regular point differs by {d_reg / peak:.3e} of the peak (tolerance {a.tol:g})")
    print(json.dumps({"events": [len(rb), len(b)], "states": [len(rc), len(c)], "regular_points": n_reg,
                      "peak_stress_pa": peak, "max_stress_difference_over_peak": d_all / peak,
                      "max_stress_difference_over_peak_regular_points": d_reg / peak,
                      "max_strain_difference": d_strain, "tolerance": a.tol, "passed": not problems,
                      "problems": problems}))
    sys.exit(1 if problems else 0)


if __name__ == "__main__":
    main()
