#!/usr/bin/env python3
"""The church's damage and energy on two material laws, side by side (scripts/compare_laws.sh runs it).

    python3 scripts/compare_church.py results/church results/church-trace \\
        --labels "spectral split" "trace split" --out results/church-comparison-trace

Reads each folder's pictures/damage-by-substructure.csv (scripts/post_church.sh: per state,
"gravity" and "end", and substructure: area, shares with d_t > 0.05 and > 0.5, max, mean) and
pictures/damage-tension-gravity.png, damage-tension.png, and writes into --out:
  damage-side-by-side.png   the tensile damage after gravity (top) and at the end of the record
                            (middle), one column per folder, and the share of each
                            substructure's area with d_t > 0.5 as bars (bottom)
  comparison.csv            state, substructure, then per folder: share d_t > 0.05, share
                            d_t > 0.5, max d_t
  energy.csv                the energy terms of each run's time history [J] (summary.json:
                            input, kinetic, strain, damping, damage, unilateral; the balance
                            error's largest relative value), one column per folder
and prints the tables; the picture's bottom row draws the shares (left) and the energy terms
(right). Needs matplotlib (scripts/setup.sh --paraview brings it to the system Python). A missing file is an error (exit 1) that names it.
"""
import argparse
import csv
import json
import os
import sys


def read_table(folder):
    path = os.path.join(folder, "pictures", "damage-by-substructure.csv")
    if not os.path.isfile(path):
        sys.exit(f"{path}: missing (run scripts/post_church.sh {folder} first)")
    with open(path, newline="") as fh:
        rows = list(csv.DictReader(fh))
    if not rows or "state" not in rows[0]:
        sys.exit(f"{path}: expected columns state, substructure, ... (written by scripts/post_church.sh)")
    return {(r["state"], r["substructure"]): r for r in rows}


# (name in this table, key of summary.json's time_history.energy)
ENERGY_TERMS = (("input", "input"), ("kinetic", "kinetic"), ("strain", "strain"), ("damping", "damping"),
                ("damage", "dissipated_damage"), ("unilateral", "unilateral"))


def read_energy(folder):
    """The time history's energy terms [J] and largest relative balance error, from summary.json."""
    path = os.path.join(folder, "summary.json")
    try:
        with open(path) as fh:
            th = json.load(fh)["time_history"]
        terms = {name: th["energy"][key] for name, key in ENERGY_TERMS}
        terms["max_balance_error"] = th["max_balance_error"]
        return terms
    except (OSError, ValueError, KeyError) as e:
        sys.exit(f"{path}: no time history's energy ({e}): did the job finish?")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("folders", nargs=2, help="two church results folders (with pictures/)")
    ap.add_argument("--labels", nargs=2, default=None, help="a name for each folder")
    ap.add_argument("--out", required=True, help="output folder")
    a = ap.parse_args()
    labels = a.labels or [os.path.basename(os.path.normpath(f)) for f in a.folders]
    tables = [read_table(f) for f in a.folders]
    pictures = [[os.path.join(f, "pictures", n) for n in ("damage-tension-gravity.png", "damage-tension.png")]
                for f in a.folders]
    for p in sum(pictures, []):
        if not os.path.isfile(p):
            sys.exit(f"{p}: missing (run scripts/post_church.sh on its folder)")
    os.makedirs(a.out, exist_ok=True)

    # The substructures of either run, in the first run's order.
    keys = list(tables[0]) + [k for k in tables[1] if k not in tables[0]]
    path = os.path.join(a.out, "comparison.csv")
    with open(path, "w", newline="") as fh:
        w = csv.writer(fh)
        head = ["state", "substructure"]
        for lab in labels:
            head += [f"{lab}: share_dt_above_0.05", f"{lab}: share_dt_above_0.5", f"{lab}: max_dt"]
        w.writerow(head)
        print(f"{'state':8} {'substructure':14} " + "  ".join(f"{lab:>30}" for lab in labels))
        for k in keys:
            row = list(k)
            shown = []
            for t in tables:
                r = t.get(k)
                vals = [r["share_dt_above_0.05"], r["share_dt_above_0.5"], r["max_dt"]] if r else ["", "", ""]
                row += vals
                shown.append(f"{100 * float(vals[0]):5.1f} % {100 * float(vals[1]):5.1f} % max {float(vals[2]):.2f}" if r else "-")
            w.writerow(row)
            print(f"{k[0]:8} {k[1]:14} " + "  ".join(f"{s:>30}" for s in shown))
    print(f"{path}")
    energies = [read_energy(f) for f in a.folders]
    path = os.path.join(a.out, "energy.csv")
    with open(path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["term"] + labels)
        print(f"{'energy [J]':18} " + "  ".join(f"{lab:>22}" for lab in labels))
        for k in [name for name, _ in ENERGY_TERMS] + ["max_balance_error"]:
            w.writerow([k] + [f"{e[k]:.6g}" for e in energies])
            print(f"{k:18} " + "  ".join(f"{e[k]:22.4g}" for e in energies))
    print(path)

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import matplotlib.image as mpimg

    colours_energy = ("#08519c", "#a63603")
    fig = plt.figure(figsize=(16, 15))
    grid = fig.add_gridspec(3, 2, height_ratios=[1, 1, 0.55])
    for c, (lab, pics) in enumerate(zip(labels, pictures)):
        for r, (p, when) in enumerate(zip(pics, ("after gravity", "at the end of the record"))):
            ax = fig.add_subplot(grid[r, c])
            ax.imshow(mpimg.imread(p))
            ax.set_axis_off()
            ax.set_title(f"{lab}: tensile damage {when}", fontsize=12)
    ax = fig.add_subplot(grid[2, 1])
    shown = ("input", "damping", "damage", "unilateral")
    for i, (lab, e) in enumerate(zip(labels, energies)):
        xs = [x + (i - 0.5) * 0.35 for x in range(len(shown))]
        ax.bar(xs, [e[k] / 1e3 for k in shown], 0.35, color=colours_energy[i], label=lab)
    ax.axhline(0.0, color="k", lw=0.8)
    ax.set_xticks(range(len(shown)))
    ax.set_xticklabels(shown)
    ax.set_ylabel("energy over the record [kJ]")
    ax.grid(axis="y", alpha=0.3)
    ax.legend(fontsize=10)
    ax = fig.add_subplot(grid[2, 0])
    names = [k[1] for k in keys if k[0] == "end" and k[1] != "all shells"]
    width = 0.2
    colours = [("#9ecae1", "#08519c"), ("#fdae6b", "#a63603")]
    for i, (lab, t) in enumerate(zip(labels, tables)):
        for j, state in enumerate(("gravity", "end")):
            vals = [100 * float(t[(state, n)]["share_dt_above_0.5"]) if (state, n) in t else 0.0 for n in names]
            xs = [x + (2 * i + j - 1.5) * width for x in range(len(names))]
            ax.bar(xs, vals, width, color=colours[i][j], label=f"{lab}, {'after gravity' if state == 'gravity' else 'end of record'}")
    ax.set_xticks(range(len(names)))
    ax.set_xticklabels(names, rotation=20, ha="right")
    ax.set_ylabel("area with d_t > 0.5 [%]")
    ax.grid(axis="y", alpha=0.3)
    ax.legend(fontsize=10)
    fig.tight_layout()
    path = os.path.join(a.out, "damage-side-by-side.png")
    fig.savefig(path, dpi=80)
    print(path)


if __name__ == "__main__":
    main()
