#!/usr/bin/env python3
"""Mean shear curve of a DEM batch, as a small reference CSV for the finite-element overlay.

    scripts/dem_mean_curve.py results/wall-shear -o jobs/data/wall-shear-dem-mean.csv

Reads every `sample-KKK/curve.csv` of a DEM results folder (columns `displacement`, `stress`),
interpolates each sample linearly on a uniform displacement grid (--step, default 0.1 mm) up to
its own last state, and writes, per grid point, the mean and the sample standard deviation of the
stress over the samples that reach it, with their number. The first line is the column header (the
overlay reader needs it there); the lines after it that start with `#` say how the file was made.
"""
import argparse
import csv
import glob
import math
import os
import shlex
import sys


def read(path):
    xs, ys = [], []
    with open(path) as f:
        for row in csv.DictReader(f):
            xs.append(abs(float(row["displacement"])))
            ys.append(abs(float(row["stress"])))
    return xs, ys


def interp(xs, ys, x):
    for k in range(1, len(xs)):
        if xs[k] >= x:
            a, b = xs[k - 1], xs[k]
            t = 0.0 if b == a else (x - a) / (b - a)
            return ys[k - 1] + t * (ys[k] - ys[k - 1])
    return None


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("folder")
    p.add_argument("-o", "--output", required=True)
    p.add_argument("--step", type=float, default=1.0e-4, help="grid step [m]")
    p.add_argument("--note", action="append", default=[], help="extra header line (repeatable)")
    a = p.parse_args()
    files = sorted(glob.glob(os.path.join(a.folder, "sample-*", "curve.csv")))
    if not files:
        sys.exit(f"no sample-*/curve.csv under {a.folder}")
    curves = [read(f) for f in files]
    end = max(c[0][-1] for c in curves)
    n = int(end / a.step + 1e-9)
    out = ["displacement,stress,stress_std,samples"]
    out.append(f"# mean DEM shear curve over {len(curves)} samples of {os.path.normpath(a.folder)} "
               f"(displacement of the top platen [m], shear stress on the 1 m wide wall [Pa])")
    out.append("# made by: " + shlex.join(["scripts/dem_mean_curve.py"] + sys.argv[1:]))
    out += [f"# {line}" for line in a.note]
    for k in range(n + 1):
        x = k * a.step
        v = [y for y in (interp(c[0], c[1], x) for c in curves) if y is not None]
        if len(v) < max(2, (len(curves) + 1) // 2):
            break
        mean = sum(v) / len(v)
        std = math.sqrt(sum((y - mean) ** 2 for y in v) / (len(v) - 1)) if len(v) > 1 else 0.0
        out.append(f"{x:.6e},{mean:.6e},{std:.6e},{len(v)}")
    with open(a.output, "w") as f:
        f.write("\n".join(out) + "\n")
    print(f"{a.output}: {len(out) - 3 - len(a.note)} points from {len(curves)} samples")


if __name__ == "__main__":
    main()
