#!/usr/bin/env python3
"""The monitored points of a time history in one picture (matplotlib), from `monitors.csv`.

    python3 scripts/plot_monitors.py results/church/monitors.csv --out results/church/pictures/monitors.png

One row per monitor (in the order of the CSV header, or of --names), sharing the time axis:
on the left the displacement relative to the base, u_x, u_y, u_z in mm; on the right the
absolute acceleration a_x, a_y, a_z in m/s². A last row: the base shear (reaction_x,
reaction_y in kN) on the left, the storey drifts (in %) on the right. Each panel states the
component's peak. The CSV is what the time-history driver writes: columns `step,time`, then
`<name>:ux,uy,uz,ax_abs,ay_abs,az_abs` per monitor, `reaction_x,reaction_y,reaction_z` and
`drift:<name>:x,y` per drift (src/analysis/time_history/step_output.rs). Needs matplotlib
(Debian python3-matplotlib, which ParaView's package pulls in).
"""
import argparse
import csv
import sys

QUANTITIES = ["ux", "uy", "uz", "ax_abs", "ay_abs", "az_abs"]
COLOURS = {"x": "#1f77b4", "y": "#d62728", "z": "#2ca02c"}


def read(path):
    """(time [s], {monitor: {quantity: [values]}}, monitor names in header order, {other column:
    [values]} for the base reactions and the drifts)."""
    try:
        with open(path, newline="") as f:
            rows = list(csv.reader(f))
    except OSError as e:
        raise SystemExit(f"{path}: {e.strerror}")
    if not rows or rows[0][:2] != ["step", "time"]:
        raise SystemExit(f"{path}: line 1: expected the header 'step,time,<name>:ux,...' of a monitors file")
    header = rows[0]
    names, columns, other = [], {}, {}
    for j, h in enumerate(header[2:], start=2):
        if h.startswith("reaction_") or h.startswith("drift:"):
            other[h] = j
            continue
        name, sep, q = h.rpartition(":")
        if not sep or q not in QUANTITIES:
            raise SystemExit(f"{path}: line 1, column {j + 1}: expected '<name>:<{'|'.join(QUANTITIES)}>', got '{h}'")
        if name not in columns:
            names.append(name)
            columns[name] = {}
        columns[name][q] = j
    time, values = [], {n: {q: [] for q in QUANTITIES} for n in names}
    extra = {h: [] for h in other}
    for i, r in enumerate(rows[1:], start=2):
        if len(r) != len(header):
            raise SystemExit(f"{path}: line {i}: {len(r)} values, the header has {len(header)}")
        try:
            time.append(float(r[1]))
            for n in names:
                for q, j in columns[n].items():
                    values[n][q].append(float(r[j]))
            for h, j in other.items():
                extra[h].append(float(r[j]))
        except ValueError as e:
            raise SystemExit(f"{path}: line {i}: {e}")
    if not time:
        raise SystemExit(f"{path}: no rows after the header (did the run make a step?)")
    return time, values, names, extra


def plot_extra(row, time, extra):
    """The base shear (kN) and the storey drifts (%) in the two panels of `row`."""
    shear, drift = row
    for d in "xy":
        y = [v / 1e3 for v in extra.get(f"reaction_{d}", [])]
        if y:
            shear.plot(time, y, color=COLOURS[d], lw=1.2, label=f"V_{d} (peak {max(abs(v) for v in y):.3g} kN)")
    shear.set_ylabel("base shear [kN]\n(reaction of the ground)")
    for h, v in extra.items():
        if h.startswith("drift:"):
            y = [100.0 * x for x in v]
            drift.plot(time, y, lw=1.2, label=f"{h[6:]} (peak {max(abs(x) for x in y):.3g} %)")
    drift.set_ylabel("storey drift [%]")
    for ax in row:
        ax.axhline(0.0, color="0.6", lw=0.6)
        ax.grid(True, color="0.9")
        if ax.get_legend_handles_labels()[0]:
            ax.legend(loc="best", fontsize=8, framealpha=0.85)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("csv", help="monitors.csv of a time-history run")
    ap.add_argument("--names", help="comma-separated monitors to draw, in this order (default: all)")
    ap.add_argument("--title", default=None, help="figure title")
    ap.add_argument("--out", default="monitors.png")
    a = ap.parse_args()
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        raise SystemExit("matplotlib is not installed (Debian: python3-matplotlib)")

    time, values, names, extra = read(a.csv)
    if a.names:
        wanted = [n.strip() for n in a.names.split(",") if n.strip()]
        missing = [n for n in wanted if n not in values]
        if missing:
            raise SystemExit(f"{a.csv}: no monitor {', '.join(missing)}; it has {', '.join(names)}")
        names = wanted
    rows = len(names) + (1 if extra else 0)
    if rows == 0:
        raise SystemExit(f"{a.csv}: no monitor and no base reaction to draw")
    fig, axes = plt.subplots(rows, 2, figsize=(13, 2.6 * rows + 0.9), sharex=True, squeeze=False)
    if extra:
        plot_extra(axes[-1], time, extra)
    for row, name in zip(axes, names):
        v = values[name]
        for ax, kind in zip(row, ("u", "a")):
            for d in "xyz":
                q = f"u{d}" if kind == "u" else f"a{d}_abs"
                y = [x * 1e3 for x in v[q]] if kind == "u" else v[q]
                peak = max(abs(x) for x in y)
                unit = "mm" if kind == "u" else "m/s²"
                ax.plot(time, y, color=COLOURS[d], lw=1.2, label=f"{kind}_{d} (peak {peak:.3g} {unit})")
            ax.axhline(0.0, color="0.6", lw=0.6)
            ax.grid(True, color="0.9")
            ax.legend(loc="best", fontsize=8, framealpha=0.85)
            if kind == "u":
                ax.set_ylabel(f"{name}\nrelative displacement [mm]")
            else:
                ax.set_ylabel("absolute acceleration [m/s²]")
    if names:
        axes[0][0].set_title("displacement relative to the base")
        axes[0][1].set_title("absolute acceleration")
    for ax in axes[-1]:
        ax.set_xlabel("time [s]")
    fig.suptitle(a.title or (f"monitored points: {', '.join(names)}" if names else "base shear and drifts"))
    fig.tight_layout()
    fig.savefig(a.out, dpi=100)
    print(f"{a.out}: {len(names)} monitor(s) ({', '.join(names)}), {len(time)} rows, t = {time[0]:g} .. {time[-1]:g} s")


if __name__ == "__main__":
    sys.exit(main())
