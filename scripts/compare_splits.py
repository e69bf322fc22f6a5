#!/usr/bin/env python3
"""The lab's cyclic tests against the damage law's two unilateral splits, point by point.

Usage: scripts/compare_splits.py RESULTS   (scripts/compare_splits.sh runs the jobs first)

RESULTS holds lab-tc/ and lab-shear/ (the DEM jobs jobs/lab-cyclic-*.toml: per sample curve.csv)
and law-<split>-tc/, law-<split>-shear/ (material-point jobs on the same paths: curve.csv). Writes
RESULTS/splits.csv (one row per law and measure), RESULTS/splits.md (the same as a table) and
RESULTS/splits.png (the loops side by side). Needs matplotlib for the picture.

Measures (each DEM figure is the mean over its samples, with the standard deviation):
* tension-compression, per cycle k (amplitude a_k): the stress at the tensile end +a_k, the
  secant stiffness of the compressive half from zero strain to -a_k relative to the first
  loading's modulus (the stiffness recovered once the crack has closed), and the residual strain
  where the unloading from +a_k crosses zero stress;
* shear under compression, per cycle: the energy dissipated, the closed loop integral of
  tau dgamma from the cycle's start to its end (J/m^3), and the peak shear stress;
* for each test, the whole-path error of the law: the RMS over the DEM's states of the stress
  difference at the same point of the path (interpolated on the cumulative strain travelled),
  relative to the DEM's largest |stress|, over the part of the path the law follows; and that
  part's share (a law that finds no equilibrium under the held compression stops early).
"""
import csv
import math
import sys
from pathlib import Path

SPLITS = ["trace", "spectral"]


def read_rows(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def dem_curves(folder):
    """Every recorded state of every sample, in order: (platen strain, stress in Pa) lists."""
    curves = []
    for sample in sorted(Path(folder).glob("sample-*")):
        rows = read_rows(sample / "curve.csv")
        curves.append([(float(r["strain"]), float(r["stress"])) for r in rows])
    return curves


def law_curve(folder, comp):
    rows = read_rows(Path(folder) / "curve.csv")
    return [(float(r[f"strain_{comp}"]), float(r[f"stress_{comp}"])) for r in rows]


def travelled(pts):
    s, out = 0.0, [0.0]
    for (a, _), (b, _) in zip(pts, pts[1:]):
        s += abs(b - a)
        out.append(s)
    return out


def interp(xs, ys, x):
    if x <= xs[0]:
        return ys[0]
    for i in range(1, len(xs)):
        if x <= xs[i]:
            t = 0.0 if xs[i] == xs[i - 1] else (x - xs[i - 1]) / (xs[i] - xs[i - 1])
            return ys[i - 1] + t * (ys[i] - ys[i - 1])
    return ys[-1]


def path_error(dem, law):
    """RMS of σ_law − σ_DEM at the DEM's states, matched on the strain travelled, over max |σ_DEM|."""
    sd, sl = travelled(dem), travelled(law)
    scale = max(abs(p[1]) for p in dem)
    diffs = [interp(sl, [p[1] for p in law], s) - p[1] for s, p in zip(sd, dem) if s <= sl[-1]]
    return math.sqrt(sum(d * d for d in diffs) / len(diffs)) / scale


def segments(pts, targets):
    """Split a path at its turning points: the index where each target strain is reached."""
    idx, k = [], 0
    for i, (e, _) in enumerate(pts):
        if k < len(targets) and abs(e - targets[k]) <= 1e-9 * max(abs(t) for t in targets):
            idx.append(i)
            k += 1
    return idx


def zero_crossing(branch):
    """Strain where a branch's stress crosses zero (linear interpolation), None if it does not."""
    for (e0, s0), (e1, s1) in zip(branch, branch[1:]):
        if s0 > 0.0 >= s1 or s0 < 0.0 <= s1:
            return e0 + (e1 - e0) * s0 / (s0 - s1)
    return None


def tc_measures(pts, amps):
    targets = [t for a in amps for t in (a, -a)] + [0.0]
    idx = segments(pts, targets)
    first = [p for p in pts[: idx[0] + 1] if 0.0 < p[0] <= 0.2 * amps[0]]
    e0 = first[-1][1] / first[-1][0] if first else float("nan")
    out = {}
    for k, a in enumerate(amps):
        if 2 * k + 1 >= len(idx):
            break
        top, bottom = idx[2 * k], idx[2 * k + 1]
        out[f"tension end {k + 1} [MPa]"] = pts[top][1] / 1e6
        out[f"closure stiffness {k + 1} [E0]"] = pts[bottom][1] / pts[bottom][0] / e0
        res = zero_crossing(pts[top: bottom + 1])
        out[f"residual strain {k + 1} [1e-6]"] = res * 1e6 if res is not None else float("nan")
    return out


def shear_measures(pts, gammas):
    """Per cycle: the work of τ dγ between the upward zero crossings of γ that bracket it (the
    start of the test and the return to zero after the last cycle included), and the peak |τ|."""
    cum = [0.0]
    for (e0, s0), (e1, s1) in zip(pts, pts[1:]):
        cum.append(cum[-1] + 0.5 * (s0 + s1) * (e1 - e0))
    cuts = [(0.0, 0)]
    tol = 1e-9 * max(abs(e) for e, _ in pts)  # the path's own round-off at γ = 0
    for i, ((e0, _), (e1, _)) in enumerate(zip(pts, pts[1:])):
        if e0 < -tol and e1 >= -tol:
            t = min(1.0, -e0 / (e1 - e0))
            cuts.append((cum[i] + t * (cum[i + 1] - cum[i]), i + 1))
    out = {}
    for k in range(min(len(gammas), len(cuts) - 1)):
        (w0, i0), (w1, i1) = cuts[k], cuts[k + 1]
        out[f"work of cycle {k + 1} [kJ/m3]"] = (w1 - w0) / 1e3
        out[f"peak shear {k + 1} [MPa]"] = max(abs(s) for _, s in pts[i0: i1 + 1]) / 1e6
    return out


def mean_std(values):
    v = [x for x in values if not math.isnan(x)]
    if not v:
        return float("nan"), float("nan"), 0
    m = sum(v) / len(v)
    s = math.sqrt(sum((x - m) ** 2 for x in v) / (len(v) - 1)) if len(v) > 1 else 0.0
    return m, s, len(v)


def main():
    if len(sys.argv) != 2:
        print(__doc__)
        sys.exit(2)
    res = Path(sys.argv[1])
    amps = [0.5e-4, 1.0e-4, 2.0e-4, 4.0e-4]
    gammas = [a / 1.2 for a in (0.5e-3, 1.0e-3, 2.0e-3)]
    tests = {
        "tension-compression": ("tc", "xx", lambda p: tc_measures(p, amps)),
        "shear under 1 MPa": ("shear", "xy", lambda p: shear_measures(p, gammas)),
    }
    rows, curves = [], {}
    for name, (tag, comp, measure) in tests.items():
        dem = dem_curves(res / f"lab-{tag}")
        per_sample = [measure(c) for c in dem]
        keys = list(per_sample[0].keys())
        laws = {s: law_curve(res / f"law-{s}-{tag}", comp) for s in SPLITS}
        curves[name] = (dem, laws)
        for k in keys:
            m, sd, n = mean_std([ps.get(k, float("nan")) for ps in per_sample])
            row = {"test": name, "measure": k, "dem": m, "dem_std": sd, "dem_n": n}
            for s in SPLITS:
                row[s] = measure(laws[s]).get(k, float("nan"))
            rows.append(row)
        reach = {s: travelled(laws[s])[-1] / mean_std([travelled(c)[-1] for c in dem])[0] for s in SPLITS}
        rows.append({"test": name, "measure": "share of the path the law follows [%]", "dem": 100.0, "dem_std": 0.0,
                     "dem_n": len(dem), **{s: 100.0 * min(reach[s], 1.0) for s in SPLITS}})
        for s in SPLITS:
            errs = [path_error(c, laws[s]) for c in dem]
            m, sd, n = mean_std(errs)
            rows.append({"test": name, "measure": f"path error of the law, {s} [-]", "dem": m, "dem_std": sd, "dem_n": n,
                         "trace": m if s == "trace" else float("nan"), "spectral": m if s == "spectral" else float("nan")})
    with open(res / "splits.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=["test", "measure", "dem", "dem_std", "dem_n"] + SPLITS)
        w.writeheader()
        w.writerows(rows)
    lines = ["| test | measure | DEM (mean ± std, n) | trace | spectral |", "|---|---|---|---|---|"]
    for r in rows:
        if r["measure"].startswith("path error"):
            lines.append(f"| {r['test']} | {r['measure']} | | {r['trace']:.3g} | {r['spectral']:.3g} |".replace("nan", ""))
        else:
            lines.append(f"| {r['test']} | {r['measure']} | {r['dem']:.4g} ± {r['dem_std']:.2g} ({r['dem_n']}) "
                         f"| {r['trace']:.4g} | {r['spectral']:.4g} |")
    (res / "splits.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))
    plot(res, curves)


def plot(res, curves):
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("compare_splits: matplotlib is missing, no picture (pip install matplotlib)")
        return
    fig, axes = plt.subplots(1, 2, figsize=(14, 5.5))
    colours = {"trace": "tab:red", "spectral": "tab:green"}
    for ax, (name, (dem, laws)) in zip(axes, curves.items()):
        for i, c in enumerate(dem):
            ax.plot([p[0] * 1e3 for p in c], [p[1] / 1e6 for p in c], color="tab:blue", lw=0.8, alpha=0.6,
                    label="DEM samples" if i == 0 else None)
        for s, c in laws.items():
            ax.plot([p[0] * 1e3 for p in c], [p[1] / 1e6 for p in c], color=colours[s], lw=1.6,
                    label=f"law, {s} split")
        ax.set_title(name)
        ax.set_xlabel("strain [‰]" if "tension" in name else "shear strain γ = u/h [‰]")
        ax.set_ylabel("stress [MPa]" if "tension" in name else "shear stress τ [MPa]")
        ax.grid(alpha=0.3)
        ax.legend(loc="best", fontsize=9)
    fig.suptitle("The calibrated lab's cyclic tests against the identified laws (material point, h = 1.2 m)")
    fig.tight_layout()
    fig.savefig(res / "splits.png", dpi=110)
    print(f"picture: {res / 'splits.png'}")


if __name__ == "__main__":
    main()
