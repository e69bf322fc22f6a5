#!/usr/bin/env bash
# Structural benchmark, one JSON line per case:
#  * shell assembly: a 60 x 60 MITC4 plate with the damage law at 7 layers (15 material points
#    through the thickness, 4 in-plane points), linear statics under self weight; the assembly
#    phase (stiffness + loads) per element, on 1 and 2 ranks;
#  * shell modal analysis: 6 modes of a simply supported 91 x 91 MITC4 plate (8464 nodes,
#    50 784 DOF), SLEPc shift-and-invert with MUMPS, on 1 and 2 ranks; the largest relative
#    difference of the 6 frequencies between the two rank counts;
#  * the paper's wall as a shell (jobs/wall-shear-fe.toml) on 5 x 6, 10 x 12 and 20 x 24 meshes,
#    14 increments to 2.8 mm, five variants of the law and the solver (below): peak and final
#    force, settlement, dissipated energy at 1.75 mm and at the end, and their spread
#    (max - min) / mean over the three meshes (issue 5 asks for < 5%).
# Run through scripts/bench.sh (which builds first).
set -euo pipefail
cd "$(dirname "$0")/../.."
source scripts/env.sh
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

python3 scripts/make_quad_mesh.py plate --nx 60 --ny 60 -o "$work/plate60.msh" >/dev/null
python3 scripts/make_quad_mesh.py plate --nx 91 --ny 91 -o "$work/plate91.msh" >/dev/null

common='[[supports]]
group = "all"
dofs = ["ux", "uy", "rz"]
[[supports]]
group = "x_edges"
dofs = ["uz", "rx"]
[[supports]]
group = "y_edges"
dofs = ["uz", "ry"]
[output]
dir = "out"
existing = "overwrite"'

cat > "$work/assembly.toml" <<EOF
[analysis]
type = "linear_static"
[mesh]
file = "plate60.msh"
[materials.masonry]
type = "damage"
density = 2000.0
[materials.masonry.law]
E = 2.885e9
nu = 0.19
eps0_t = 5.0e-5
eps0_c = 2.0e-4
gf_t = 20.0
a_c = 0.8
b_c = 1500.0
regularization = "hillerborg"
[sections.s]
type = "shell"
thickness = 0.5
layers = 7
[[parts]]
group = "plate"
section = "s"
material = "masonry"
[gravity]
acceleration = [0.0, 0.0, -9.81]
$common
EOF

cat > "$work/modal.toml" <<EOF
[analysis]
type = "modal"
modes = 6
[mesh]
file = "plate91.msh"
[materials.steel]
type = "elastic"
E = 2.1e11
nu = 0.3
density = 7800.0
[sections.s]
type = "shell"
thickness = 0.01
[[parts]]
group = "plate"
section = "s"
material = "steel"
$common
EOF

for np in 1 2; do
  mpirun -n $np target/release/masonry-hpc -q "$work/assembly.toml" >/dev/null
  cp "$work/out/summary.json" "$work/assembly-$np.json"
done
for np in 1 2; do
  python3 - "$work/assembly-$np.json" "$work/assembly-1.json" "$np" <<'PY'
import json, sys
s, s1 = json.load(open(sys.argv[1])), json.load(open(sys.argv[2]))
t, t1 = s["seconds"]["assemble"], s1["seconds"]["assemble"]
print(json.dumps({
    "case": "shell-assembly-7-layers", "size": s["elements"], "ranks": int(sys.argv[3]),
    "seconds": round(t, 4), "microseconds_per_element": round(1e6 * t / s["elements"], 2),
    "speedup_vs_1_rank": round(t1 / max(t, 1e-12), 3),
    "note": "MITC4, damage law at 4 x 15 points, stiffness + self-weight loads",
}))
PY
done

for np in 1 2; do
  mpirun -n $np target/release/masonry-hpc -q "$work/modal.toml" >/dev/null
  cp "$work/out/summary.json" "$work/modal-$np.json"
done
for np in 1 2; do
  python3 - "$work/modal-$np.json" "$work/modal-1.json" "$np" <<'PY'
import json, sys
s, s1 = json.load(open(sys.argv[1])), json.load(open(sys.argv[2]))
t, t1 = s["seconds"], s1["seconds"]
f = [m["frequency"] for m in s["modes"]]
f1 = [m["frequency"] for m in s1["modes"]]
print(json.dumps({
    "case": "shell-modal6", "size": s["equations"], "elements": s["elements"], "ranks": int(sys.argv[3]),
    "seconds": round(t[1] + t[2], 4), "seconds_assemble": round(t[1], 4), "seconds_eigensolve": round(t[2], 4),
    "speedup_vs_1_rank": round((t1[1] + t1[2]) / max(t[1] + t[2], 1e-12), 3),
    "first_frequency_hz": f[0],
    "max_rel_diff_vs_1_rank": max(abs(a - b) / b for a, b in zip(f, f1)),
}))
PY
done

# The wall on three meshes (5 x 6, 10 x 12, 20 x 24; the last variant also on 15 x 18 and
# 25 x 30), 14 increments to 2.8 mm, in five variants:
#   b_c        the job's law (A_c = 0.8, B_c as given);
#   gf_c       with the post-peak compressive softening regularized by G_c (G_c = 705.5 J/m²
#              continues the b_c = 1500 curve's energy at h = 0.1 m);
#   gf_c_tau   the same with the viscous damage of [analysis] damage_relaxation_time = 0.002;
#   ac03_gf_c  A_c = 0.3: residual compressive strength (1 − A_c) f_c = 1.5 MPa above the 1 MPa
#              preload (G_c = 264.6 J/m², the same B_s at h = 0.1 m);
#   ac03_gf_c_tau  the same with damage_relaxation_time = 0.002.
# Per case: where the run ended, peak and final force, the top's largest settlement, the
# dissipated energy at 1.75 mm and at the end; per variant the spread (max − min) / mean over the
# three meshes at both (issue 5 asks for < 5% at the end), and for the last variant also over the
# three finest meshes (15 x 18, 20 x 24, 25 x 30).
for variant in b_c gf_c gf_c_tau ac03_gf_c ac03_gf_c_tau; do
  meshes=("5 6" "10 12" "20 24")
  [ "$variant" = ac03_gf_c_tau ] && meshes=("5 6" "10 12" "15 18" "20 24" "25 30")
  for m in "${meshes[@]}"; do
    set -- $m
    [ -f "$work/wall-$1.msh" ] || python3 scripts/make_quad_mesh.py wall --nx "$1" --ny "$2" -o "$work/wall-$1.msh" >/dev/null
    per_node=$(python3 -c "print(-1.0e6 * 1.0 * 0.5 / ($1 + 1))")
    case $variant in
      b_c) law=""; ac=0.8; an="" ;;
      gf_c) law="gf_c = 705.5"; ac=0.8; an="" ;;
      gf_c_tau) law="gf_c = 705.5"; ac=0.8; an="damage_relaxation_time = 0.002" ;;
      ac03_gf_c) law="gf_c = 264.6"; ac=0.3; an="" ;;
      ac03_gf_c_tau) law="gf_c = 264.6"; ac=0.3; an="damage_relaxation_time = 0.002" ;;
    esac
    sed -e "s#../meshes/wall-fe-10x12.msh#wall-$1.msh#" -e "s#-45454.545454545456#$per_node#" \
        -e "s#^target = 2.6e-3#target = 2.8e-3#" -e "s#^steps = 52#steps = 14#" \
        -e '/^\[analysis.control.overlay\]/,/^label/d' -e "s#^b_c = 1500.0#b_c = 1500.0\n$law#" \
        -e "s#^a_c = 0.8#a_c = $ac#" -e "s#^energy_tolerance = 1e-10#energy_tolerance = 1e-10\n$an#" \
        -e "s#../results/wall-shear-fe#wall-out-$variant-$1#" jobs/wall-shear-fe.toml > "$work/wall-$variant-$1.toml"
    start=$(date +%s.%N)
    target/release/masonry-hpc -q "$work/wall-$variant-$1.toml" >/dev/null 2>&1 || true
    end=$(date +%s.%N)
    echo "$variant-$1x$2 $(python3 -c "print($end - $start)")" >> "$work/wall-times"
  done
done
python3 - "$work" <<'PY'
import csv, json, os, sys
import h5py
work = sys.argv[1]
times = dict(l.split() for l in open(os.path.join(work, "wall-times")))
def at(rows, x):
    """Dissipated energy at control displacement x (linear interpolation), None if not reached."""
    pts = [(float(r["control_displacement"]), float(r["dissipated_energy"])) for r in rows]
    for (x0, e0), (x1, e1) in zip(pts, pts[1:]):
        if x0 <= x <= x1:
            return e0 + (e1 - e0) * (x - x0) / (x1 - x0) if x1 > x0 else e1
    return None
def spread(v):
    return round((max(v) - min(v)) / (sum(v) / len(v)), 4) if all(x is not None for x in v) else None
for variant in ["b_c", "gf_c", "gf_c_tau", "ac03_gf_c", "ac03_gf_c_tau"]:
    ends, mids = [], []
    meshes = [(5, 6), (10, 12), (20, 24)]
    if variant == "ac03_gf_c_tau":
        meshes = [(5, 6), (10, 12), (15, 18), (20, 24), (25, 30)]
    for nx, nz in meshes:
        out = os.path.join(work, f"wall-out-{variant}-{nx}")
        rows = [r for r in csv.DictReader(open(os.path.join(out, "curve.csv"))) if r["stage"] == "control"]
        f = [float(r["control_force"]) for r in rows]
        reached = float(rows[-1]["control_displacement"]) >= 2.8e-3 - 1e-9
        with h5py.File(os.path.join(out, "results.h5")) as h:
            last = max(int(k) for k in h["steps"].keys() if k.isdigit())
            settlement = -float(h[f"steps/{last}/displacement"][:, 2].min())
        e = float(rows[-1]["dissipated_energy"])
        ends.append(e if reached else None)
        mids.append(at(rows, 1.75e-3))
        print(json.dumps({
            "case": f"wall-shear-fe-{variant}", "size": f"{nx}x{nz}", "seconds": round(float(times[f"{variant}-{nx}x{nz}"]), 2),
            "final_displacement": float(rows[-1]["control_displacement"]), "peak_force": max(f),
            "final_over_peak": round(f[-1] / max(f), 4), "top_settlement_m": settlement,
            "dissipated_energy": e, "dissipated_energy_at_1.75mm": mids[-1],
            "note": "" if reached else "stopped before 2.8 mm",
        }))
    pick = [meshes.index(m) for m in [(5, 6), (10, 12), (20, 24)]]
    print(json.dumps({"case": f"wall-shear-fe-{variant}-energy-spread", "size": "5x6,10x12,20x24", "seconds": 0.0,
                      "energy_spread_over_mean_at_end": spread([ends[k] for k in pick]),
                      "energy_spread_over_mean_at_1.75mm": spread([mids[k] for k in pick]), "target": 0.05}))
    if len(meshes) == 5:
        print(json.dumps({"case": f"wall-shear-fe-{variant}-energy-spread", "size": "15x18,20x24,25x30", "seconds": 0.0,
                          "energy_spread_over_mean_at_end": spread(ends[2:]),
                          "energy_spread_over_mean_at_1.75mm": spread(mids[2:]), "target": 0.05}))
PY
