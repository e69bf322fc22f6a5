#!/usr/bin/env bash
# Structural benchmark, one JSON line per case:
#  * shell assembly: a 60 x 60 MITC4 plate with the damage law at 7 layers (15 material points
#    through the thickness, 4 in-plane points), linear statics under self weight; the assembly
#    phase (stiffness + loads) per element, on 1 and 2 ranks;
#  * shell modal analysis: 6 modes of a simply supported 91 x 91 MITC4 plate (8464 nodes,
#    50 784 DOF), SLEPc shift-and-invert with MUMPS, on 1 and 2 ranks; the largest relative
#    difference of the 6 frequencies between the two rank counts.
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
