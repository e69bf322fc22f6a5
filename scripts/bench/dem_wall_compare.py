#!/usr/bin/env python3
"""Compares two output directories of the same DEM batch job (e.g. jobs/wall-tension.toml run
by two builds of the solver): the same physics within round-off.

    scripts/bench/dem_wall_compare.py REF_DIR NEW_DIR [--tol 1e-8]

For every sample of REF_DIR's summary.json: the same end and the same number of breaks, and in
`sample-KKK/curve.csv` stresses within `tol` times the sample's peak |stress| at the states both
runs recorded (the same kind and broken beams, strains within 1e-9 of the largest: a load step
cut back in one run only records a state the other has not; those are counted, not compared).
Prints one JSON line (the largest stress difference over the peak among the samples, the states
compared and left out, the samples that differ) and exits 1 when a sample differs.
"""
import argparse
import csv
import json
import os
import sys


def curve(d, k):
    with open(os.path.join(d, f"sample-{k:03d}", "curve.csv")) as f:
        return list(csv.DictReader(f))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("ref")
    ap.add_argument("new")
    ap.add_argument("--tol", type=float, default=1e-8)
    a = ap.parse_args()
    ref = {x["sample"]: x for x in json.load(open(os.path.join(a.ref, "summary.json")))["samples"]}
    new = {x["sample"]: x for x in json.load(open(os.path.join(a.new, "summary.json")))["samples"]}
    problems, worst, breaks, matched, unmatched = [], 0.0, 0, 0, 0
    for k, r in sorted(ref.items()):
        n = new.get(k)
        if n is None:
            problems.append(f"sample {k}: missing")
            continue
        if r.get("end") != n.get("end") or r.get("events") != n.get("events"):
            problems.append(f"sample {k}: end/breaks {r.get('end')}/{r.get('events')} vs {n.get('end')}/{n.get('events')}")
            continue
        breaks += r.get("events", 0)
        rc, nc = curve(a.ref, k), curve(a.new, k)
        keys = ["kind", "broken", "broken_tension", "broken_shear", "broken_crushing"]
        scale = max(abs(float(x["strain"])) for x in rc) or 1.0
        peak = max(abs(float(x["stress"])) for x in rc) or 1.0
        d, j = 0.0, 0
        for x in rc:
            # The next state of the other run with the same kind, breaks and strain.
            m = next((i for i in range(j, len(nc)) if all(nc[i][c] == x[c] for c in keys)
                      and abs(float(nc[i]["strain"]) - float(x["strain"])) <= 1e-9 * scale), None)
            if m is None:
                unmatched += 1
                continue
            j = m + 1
            matched += 1
            d = max(d, abs(float(x["stress"]) - float(nc[m]["stress"])) / peak)
        worst = max(worst, d)
        if d > a.tol:
            problems.append(f"sample {k}: stress differs by {d:.3e} of the peak")
    print(json.dumps({"samples": len(ref), "breaks": breaks, "max_stress_difference_over_peak": worst,
                      "states_compared": matched, "states_left_out": unmatched,
                      "tolerance": a.tol, "passed": not problems, "problems": problems}))
    sys.exit(0 if not problems else 1)


if __name__ == "__main__":
    main()
