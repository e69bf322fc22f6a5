#!/usr/bin/env bash
# Platform benchmark: assembly and solve time of the demo tower at two sizes, on 1 and 2 ranks,
# with a direct (MUMPS Cholesky) and an iterative (CG + GAMG) solver; and the modal analysis
# (6 modes, block shift-and-invert Lanczos with MUMPS) of the same two towers.
# One JSON line per case. Run through scripts/bench.sh (which builds first).
set -euo pipefail
cd "$(dirname "$0")/../.."
source scripts/env.sh
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
python3 scripts/make_tower_mesh.py -o "$work/small.msh" >/dev/null
python3 scripts/make_tower_mesh.py --storeys 50 --divisions 9 -o "$work/large.msh" >/dev/null
declare -A solvers=(
  [direct]="-ksp_type preonly -pc_type cholesky -pc_factor_mat_solver_type mumps"
  [cg_gamg]="-ksp_type cg -pc_type gamg -ksp_rtol 1e-10 -ksp_max_it 5000"
)
for size in small large; do
  sed -e "s#\"../meshes/tower.msh\"#\"$work/$size.msh\"#" -e "s#\"../results/tower\"#\"out\"#" \
      -e 's/existing = "backup"/existing = "overwrite"/' jobs/tower.toml > "$work/$size.toml"
  for solver in direct cg_gamg; do
    declare -A total=()
    for np in 1 2; do
      start=$(date +%s.%N)
      mpirun -n $np target/release/masonry-hpc -q "$work/$size.toml" ${solvers[$solver]} >/dev/null
      end=$(date +%s.%N)
      total[$np]=$(python3 -c "print($end - $start)")
      cp "$work/out/summary.json" "$work/$size-$solver-$np.json"
    done
    for np in 1 2; do
      python3 - "$work/$size-$solver-$np.json" "$work/$size-$solver-1.json" "$size" "$solver" "$np" "${total[$np]}" <<'PY'
import json, sys
s, s1 = json.load(open(sys.argv[1])), json.load(open(sys.argv[2]))
size, solver, np_, wall = sys.argv[3], sys.argv[4], int(sys.argv[5]), float(sys.argv[6])
t, t1 = s["seconds"], s1["seconds"]
print(json.dumps({
    "case": f"tower-{size}-{solver}", "size": s["equations"], "elements": s["elements"], "ranks": np_,
    "seconds": round(t["assemble"] + t["solve"], 4),
    "seconds_assemble": round(t["assemble"], 4), "seconds_solve": round(t["solve"], 4),
    "seconds_run": round(wall, 3), "iterations": s["iterations"],
    "speedup_vs_1_rank": round((t1["assemble"] + t1["solve"]) / max(t["assemble"] + t["solve"], 1e-12), 3),
    "ksp": s["ksp"],
}))
PY
    done
  done
done

# Modal analysis: 6 modes.
for size in small large; do
  sed -e "s#\"../meshes/tower.msh\"#\"$work/$size.msh\"#" -e "s#\"../results/tower-modal\"#\"out\"#" \
      -e 's/existing = "backup"/existing = "overwrite"/' jobs/tower-modal.toml > "$work/$size-modal.toml"
  for np in 1 2; do
    mpirun -n $np target/release/masonry-hpc -q "$work/$size-modal.toml" >/dev/null
    cp "$work/out/summary.json" "$work/$size-modal-$np.json"
  done
  for np in 1 2; do
    python3 - "$work/$size-modal-$np.json" "$work/$size-modal-1.json" "$size" "$np" <<'PY'
import json, sys
s, s1 = json.load(open(sys.argv[1])), json.load(open(sys.argv[2]))
t, t1 = s["seconds"], s1["seconds"]
print(json.dumps({
    "case": f"tower-{sys.argv[3]}-modal6", "size": s["equations"], "elements": s["elements"], "ranks": int(sys.argv[4]),
    "seconds": round(t["assembly"] + t["eigensolve"], 4), "seconds_assemble": round(t["assembly"], 4), "seconds_eigensolve": round(t["eigensolve"], 4),
    "speedup_vs_1_rank": round((t1["assembly"] + t1["eigensolve"]) / max(t["assembly"] + t["eigensolve"], 1e-12), 3),
    "first_frequency_hz": s["modes"][0]["frequency"],
    "eigensolver": "block Lanczos (blocks of 2), shift-and-invert sigma=0, cholesky/mumps, residual tol 1e-8",
}))
PY
  done
done

