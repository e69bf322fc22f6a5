#!/usr/bin/env python3
"""Macroscopic E and nu of the DEM lattice against the beam inertia coefficient alpha.

    python3 scripts/dem_nu_alpha.py [--bin target/debug/masonry-hpc] [--alphas 0.2,0.4,...]
                                    [--out results/nu-alpha] [--np 2]

For every alpha it writes two DEM jobs and runs them with the program itself:
  * "random": Poisson-disk stones in a 1 m x 1 m square, 2000 stones, 4 samples (seeds 11..14);
  * "paper wall": the paper's coursed wall (1.0 x 1.2 m, 10 courses x 6 stones, jitter 0.2,
    size variability 0.2), 16 samples (seeds 1..16);
both compressed between bonded platens by eps = 1e-6 in one step (far below the first crack, so
the response is linear and E = sigma/eps, nu = -eps_lat/eps exactly; Table 1 lattice parameters
otherwise). It prints a Markdown table (mean +- sample std over the samples) and writes
<out>/nu_alpha.csv. E scales with E_bar; nu depends on alpha and the stone layout only.
"""
import argparse
import csv
import json
import os
import subprocess
import sys

RANDOM = 'layout = { type = "random", width = 1.0, height = 1.0, n_particles = 2000 }'
WALL = ('layout = { type = "coursed", width = 1.0, height = 1.2, n_courses = 10, n_per_course = 6, '
        'jitter = 0.2, size_variability = 0.2 }')


def job_text(layout, seed, samples, alpha, out):
    return f"""[analysis]
type = "dem"
samples = {samples}
particle_states = "none"
[sample]
seed = {seed}
alpha = {alpha!r}
{layout}
[test]
type = "compression"
max_strain = 1.0e-6
steps = 1
[output]
dir = "{out}"
existing = "overwrite"
"""


def run(bin_path, np, job):
    cmd = [bin_path, "-q", job] if np == 1 else ["mpirun", "-n", str(np), bin_path, "-q", job]
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"error: {' '.join(cmd)} failed:\n{r.stdout}\n{r.stderr}")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    default_bin = os.path.join(root, "target", "release", "masonry-hpc")
    if not os.path.exists(default_bin):
        default_bin = os.path.join(root, "target", "debug", "masonry-hpc")
    ap.add_argument("--bin", default=default_bin)
    ap.add_argument("--alphas", default="0.2,0.4,0.6,0.8,1.0,1.2")
    ap.add_argument("--out", default=os.path.join(root, "results", "nu-alpha"))
    ap.add_argument("--np", type=int, default=2)
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    rows = []
    for alpha in [float(x) for x in a.alphas.split(",")]:
        row = {"alpha": alpha}
        for name, layout, seed, samples in [("random", RANDOM, 11, 4), ("wall", WALL, 1, 16)]:
            out = os.path.join(a.out, f"{name}-alpha{alpha:g}")
            job = out + ".toml"
            with open(job, "w") as f:
                f.write(job_text(layout, seed, samples, alpha, out))
            run(a.bin, a.np, job)
            s = json.load(open(os.path.join(out, "summary.json")))
            e, nu = s["young_modulus"], s["poisson"]
            row.update({f"{name}_E_GPa": e["mean"] / 1e9, f"{name}_E_std_GPa": e["std"] / 1e9,
                        f"{name}_nu": nu["mean"], f"{name}_nu_std": nu["std"], f"{name}_n": e["n"]})
        rows.append(row)
        print(f"alpha {alpha:g} done", file=sys.stderr)
    with open(os.path.join(a.out, "nu_alpha.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    print("| α | random 2000: E [GPa] | random 2000: ν | paper wall: E [GPa] | paper wall: ν |")
    print("|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['alpha']:g} | {r['random_E_GPa']:.3f} ± {r['random_E_std_GPa']:.3f} | {r['random_nu']:.3f} ± {r['random_nu_std']:.3f} "
              f"| {r['wall_E_GPa']:.3f} ± {r['wall_E_std_GPa']:.3f} | {r['wall_nu']:.3f} ± {r['wall_nu_std']:.3f} |")


if __name__ == "__main__":
    main()
