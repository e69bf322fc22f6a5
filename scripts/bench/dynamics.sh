#!/usr/bin/env bash
# Time-history benchmark: seconds per time step of the tower earthquake (jobs/tower-earthquake.toml,
# linear frames, modified Newton on average acceleration, MUMPS Cholesky factored once and reused)
# on 1 and 2 ranks, for the demo tower and a larger one, over the first 4 s of the record
# (400 steps, output every 10). One JSON line per case: seconds per step of the stepping loop
# (output and checkpoints excluded), the solver, the speedup and the parallel efficiency against
# 1 rank. Run through scripts/bench.sh (which builds first). OpenMPI is told to yield the core
# when it waits (mpi_yield_when_idle): on a machine shared with other work its busy polling
# otherwise makes 2-rank runs several times slower than they are.
set -euo pipefail
cd "$(dirname "$0")/../.."
source scripts/env.sh
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cp -r jobs/records "$work/records"
python3 scripts/make_tower_mesh.py -o "$work/small.msh" >/dev/null
python3 scripts/make_tower_mesh.py --storeys 50 --divisions 9 -o "$work/large.msh" >/dev/null
for size in small large; do
  sed -e "s#\"../meshes/tower.msh\"#\"$work/$size.msh\"#" -e "s#\"../results/tower-earthquake\"#\"out\"#" \
      -e 's/existing = "backup"/existing = "overwrite"/' -e 's/^duration = 22.0 /duration = 4.0 /' \
      jobs/tower-earthquake.toml > "$work/$size.toml"
  for np in 1 2; do
    start=$(date +%s.%N)
    OMPI_MCA_mpi_yield_when_idle=1 mpirun -n $np target/release/masonry-hpc -q "$work/$size.toml" >/dev/null
    end=$(date +%s.%N)
    cp "$work/out/summary.json" "$work/$size-$np.json"
    python3 -c "print($end - $start)" > "$work/$size-$np.wall"
  done
  for np in 1 2; do
    python3 - "$work/$size-$np.json" "$work/$size-1.json" "$size" "$np" "$(cat "$work/$size-$np.wall")" <<'PY'
import json, sys
s, s1 = json.load(open(sys.argv[1])), json.load(open(sys.argv[2]))
size, np_, wall = sys.argv[3], int(sys.argv[4]), float(sys.argv[5])
sp = s1["seconds_per_step"] / max(s["seconds_per_step"], 1e-12)
print(json.dumps({
    "case": f"tower-earthquake-{size}", "size": s["equations"], "elements": s["elements"], "ranks": np_,
    "steps": s["steps"], "seconds": round(s["seconds_per_step"], 6), "seconds_per_step": round(s["seconds_per_step"], 6),
    "iterations": s["iterations"], "factorizations": s["factorizations"], "solver": s["solver"],
    "seconds_output": round(s["seconds"]["output"], 3), "seconds_run": round(wall, 3),
    "speedup_vs_1_rank": round(sp, 3), "parallel_efficiency": round(sp / np_, 3),
}))
PY
  done
done
