#!/usr/bin/env bash
# Structural benchmark, one JSON line per case:
#  * shell assembly: a 60 x 60 MITC4 plate with the damage law at 7 layers (15 material points
#    through the thickness, 4 in-plane points), linear statics under self weight; the assembly
#    phase (stiffness + loads) per element, on 1 and 2 ranks;
#  * shell modal analysis: 6 modes of a simply supported 91 x 91 MITC4 plate (8464 nodes,
#    50 784 DOF), block shift-and-invert Lanczos with MUMPS, on 1 and 2 ranks; the largest relative
#    difference of the 6 frequencies between the two rank counts;
#  * the paper's wall as a shell (jobs/wall-shear-fe.toml) on five meshes, 14 increments to
#    2.8 mm, two laws, rate independent and viscous (below): peak and final force, dissipated
#    energy, where the compression damage sits, and the energy spread (max - min) / mean over the
#    meshes (issue 5 asks for < 5% over three meshes).
# The wall cases keep the local law (the job's nonlocal_radius and force_tolerance 1e-4 are
# taken out), as measured below; the nonlocal job's own figures are in its header.
# Run through scripts/bench.sh (which builds first). STRUCTURAL_PARTS="plate" or "wall" runs one
# part; STRUCTURAL_WORK=dir keeps the jobs and results there (default: a temporary folder).
set -euo pipefail
cd "$(dirname "$0")/../.."
source scripts/env.sh
if [ -n "${STRUCTURAL_WORK:-}" ]; then
  work=$STRUCTURAL_WORK
  mkdir -p "$work"
else
  work=$(mktemp -d)
  trap 'rm -rf "$work"' EXIT
fi
# STRUCTURAL_PARTS="plate wall" (default): the plate cases, the wall cases, or both.
parts=${STRUCTURAL_PARTS:-plate wall}
if [[ " $parts " == *" plate "* ]]; then

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
    "seconds": round(t["assembly"] + t["eigensolve"], 4), "seconds_assemble": round(t["assembly"], 4), "seconds_eigensolve": round(t["eigensolve"], 4),
    "speedup_vs_1_rank": round((t1["assembly"] + t1["eigensolve"]) / max(t["assembly"] + t["eigensolve"], 1e-12), 3),
    "first_frequency_hz": f[0],
    "max_rel_diff_vs_1_rank": max(abs(a - b) / b for a, b in zip(f, f1)),
}))
PY
done

fi

# The paper's wall as a shell (jobs/wall-shear-fe.toml: 1 MPa, then the shear pushover of the
# top platen), 14 increments to 2.8 mm, on the 5 x 6, 10 x 12, 15 x 18, 20 x 24 and 25 x 30 meshes,
# with two laws, each rate independent and with the viscous damage of
# [analysis] damage_relaxation_time = 0.002 (of the control stage's pseudo-time):
#   job        the job file's law before issue 5's acceptance case: A_c = 0.8, B_c = 1500, no gf_c
#              (residual compressive strength (1 − A_c) f_c = 0.43 MPa, below the 1 MPa preload);
#   ac03       A_c = 0.3 (residual 1.5 MPa, above the preload) and G_c = 264.6 J/m² (the post-peak
#              slope of B_c = 1500 at h = 0.1 m); with τ (ac03_tau) the acceptance case of issue 5
#              (jobs/wall-shear-fe.toml, tests/wall_shear.rs: spread < 5% over the three finest);
#   ac03_tau2, ac03_tau4   ac03 with τ = 0.001 and 0.0005 on the 20 x 24 mesh (τ → 0).
# Measured: the job's law stops after the peak on 15 x 18 (2.0 mm; 2.1 mm with τ: a crushed row
# cannot carry the preload); ac03 without τ stops where the diagonal band snaps back (10 x 12 at
# 2.1 mm, 15 x 18 at 1.8 mm; 20 x 24 gets through).
# Per run: where it ended, the peak force and its displacement, the final force, the dissipated
# energy at 1.75 mm and at the end, the top's settlement, where the compression damage sits (the
# d_c-weighted correlation of the cells' x and z in the rows between the top and bottom rows: −1
# along the loaded diagonal from the top-left to the bottom-right corner, 0 for horizontal bands;
# the share of Σd_c in the top and bottom rows), the 1-minute load average when the run started (the machine is shared). Per variant:
# the energy spread (max − min) / mean over the three finest meshes and over all five (issue 5
# asks for < 5% over three meshes).
[[ " $parts " == *" wall "* ]] || exit 0
[ -n "${WALL_RUNS:-}" ] || : > "$work/wall-times"   # WALL_RUNS adds to an earlier table
run_wall() { # variant nx nz a_c gf_c tau
  local v=$1 nx=$2 nz=$3 ac=$4 gfc=$5 tau=$6
  [ -f "$work/wall-$nx.msh" ] || python3 scripts/make_quad_mesh.py wall --nx "$nx" --ny "$nz" -o "$work/wall-$nx.msh" >/dev/null
  local per_node law="" an=""
  per_node=$(python3 -c "print(-1.0e6 * 1.0 * 0.5 / ($nx + 1))")
  [ "$gfc" = - ] || law="gf_c = $gfc"
  [ "$tau" = - ] || an="damage_relaxation_time = $tau"
  sed -e "s#^file = \"../meshes/wall-fe-[0-9x]*.msh\"#file = \"wall-$nx.msh\"#" \
      -e "s#^force = \[0.0, 0.0, [^]]*\]#force = [0.0, 0.0, $per_node]#" \
      -e "s#^target = .*#target = 2.8e-3#" -e "s#^steps = [0-9]*\$#steps = 14#" \
      -e '/^\[analysis.control.overlay\]/,/^label/d' -e '/^gf_c = /d' -e '/^damage_relaxation_time = /d' \
      -e '/^nonlocal_radius = /d' -e 's#^force_tolerance = .*#force_tolerance = 1e-5#' \
      -e "s#^b_c = \(.*\)#b_c = \1\n$law#" -e "s#^a_c = .*#a_c = $ac#" \
      -e "s#^energy_tolerance = \(.*\)#energy_tolerance = \1\n$an#" \
      -e "s#../results/wall-shear-fe#wall-out-$v-$nx#" jobs/wall-shear-fe.toml > "$work/wall-$v-$nx.toml"
  grep -q '^target = 2.8e-3' "$work/wall-$v-$nx.toml" && grep -q '^steps = 14' "$work/wall-$v-$nx.toml" \
    && grep -q "^file = \"wall-$nx.msh\"" "$work/wall-$v-$nx.toml" && grep -q "^force = \[0.0, 0.0, $per_node\]" "$work/wall-$v-$nx.toml" \
    || { echo "structural.sh: could not rewrite jobs/wall-shear-fe.toml for $v $nx" >&2; exit 2; }
  local load start end
  load=$(cut -d' ' -f1 /proc/loadavg)
  start=$(date +%s.%N)
  timeout 1800 target/release/masonry-hpc -q "$work/wall-$v-$nx.toml" >/dev/null 2>"$work/wall-$v-$nx.err" || true
  end=$(date +%s.%N)
  echo "$v $nx $nz $(python3 -c "print($end - $start)") $load" >> "$work/wall-times"
}
# WALL_RUNS="variant nx nz a_c gf_c tau; ..." (- for none) runs only these; default: the table below.
if [ -n "${WALL_RUNS:-}" ]; then
  IFS=';' read -ra runs <<< "$WALL_RUNS"
  for r in "${runs[@]}"; do run_wall $r; done
else
  for m in "5 6" "10 12" "15 18" "20 24" "25 30"; do
    set -- $m
    run_wall job "$1" "$2" 0.8 - -
    run_wall job_tau "$1" "$2" 0.8 - 0.002
    run_wall ac03 "$1" "$2" 0.3 264.6 -
    run_wall ac03_tau "$1" "$2" 0.3 264.6 0.002
  done
  run_wall ac03_tau2 20 24 0.3 264.6 0.001
  run_wall ac03_tau4 20 24 0.3 264.6 0.0005
fi
python3 scripts/bench/wall_table.py "$work"
