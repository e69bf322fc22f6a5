#!/usr/bin/env bash
# Benchmark of the platform: assembly and solve time of the demo tower at two sizes, on 1 and 2
# ranks, with a direct (MUMPS Cholesky) and an iterative (CG + GAMG) solver; and the modal
# analysis (6 modes, SLEPc shift-and-invert with MUMPS) of the same two towers.
# Prints one JSON line per case: case, size (equations), ranks, seconds (assembly, solve, total
# run), the speed-up of 2 ranks over 1, and the KSP settings used.
#
#   scripts/bench.sh            # sizes: the demo mesh and one about 10x larger
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
source scripts/env.sh
cargo build --release --quiet
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
    "seconds": round(t[1] + t[2], 4), "seconds_assemble": round(t[1], 4), "seconds_eigensolve": round(t[2], 4),
    "speedup_vs_1_rank": round((t1[1] + t1[2]) / max(t[1] + t[2], 1e-12), 3),
    "first_frequency_hz": s["modes"][0]["frequency"],
    "eps": "krylovschur, shift-and-invert sigma=0, st: cholesky/mumps, tol 1e-10",
}))
PY
  done
done

# DEM: (a) 32 tension tests of the paper's wall as one batch on 2 ranks (the paper: ~2 hours);
# (b) compression of random samples (1k and 10k stones): seconds, events/s, peak memory per rank.
sed -e 's/^samples = 16/samples = 32/' -e "s#\"../results/wall-tension\"#\"$work/dem-out\"#" \
    -e 's/^existing = .*//' jobs/wall-tension.toml > "$work/tension32.toml"
start=$(date +%s.%N)
mpirun -n 2 target/release/masonry-hpc -q "$work/tension32.toml" >/dev/null 2>&1 || true
end=$(date +%s.%N)
python3 - "$work/dem-out/summary.json" "$start" "$end" <<'PY'
import json, sys
s = json.load(open(sys.argv[1])); wall = float(sys.argv[3]) - float(sys.argv[2])
ok = sum(1 for x in s["samples"] if "Ok" in x["result"])
print(json.dumps({"case": "dem-paper-wall-tension-batch", "size": 32, "ranks": 2, "seconds": round(wall, 3),
                  "samples_completed": ok, "paper_seconds": 7200, "ratio_paper_over_ours": round(7200 / wall, 1),
                  "events_per_second": round(s["events_per_second"], 1)}))
PY
for n in 1000 10000; do
  cat > "$work/random-$n.toml" <<TOML
[analysis]
type = "dem"
samples = 1
[sample]
seed = 7
layout = { type = "random", width = 1.0, height = 1.0, n_particles = $n }
[test]
type = "compression"
max_strain = 2.0e-3
steps = 40
[output]
dir = "$work/random-$n-out"
existing = "overwrite"
TOML
  t0=$(date +%s.%N)
  out=$( { /usr/bin/time -f "rss_kb=%M" target/release/masonry-hpc "$work/random-$n.toml" 2>&1 >/dev/null; } 2>&1 || true )
  t1=$(date +%s.%N)
  python3 - "$work/random-$n-out/summary.json" "$n" "$t0" "$t1" "$out" <<'PY'
import json, os, re, sys
n, wall, out = int(sys.argv[2]), float(sys.argv[4]) - float(sys.argv[3]), sys.argv[5]
rss = re.search(r"rss_kb=(\d+)", out)
line = {"case": "dem-random-compression", "size": n, "ranks": 1, "seconds": round(wall, 3),
        "peak_memory_mb": round(int(rss.group(1)) / 1024, 1) if rss else None}
if os.path.exists(sys.argv[1]):
    smp = json.load(open(sys.argv[1]))["samples"][0]
    line.update({"completed": True, "events": smp["events"], "events_per_second": round(smp["events"] / max(smp["seconds"], 1e-9), 1)})
else:
    ev = re.search(r"event (\d+)\)", out)
    line.update({"completed": False, "events_before_failure": int(ev.group(1)) if ev else None,
                 "events_per_second": round(int(ev.group(1)) / wall, 1) if ev else None,
                 "error": (re.search(r"warning: (.*)", out) or re.search(r"error: (.*)", out)).group(1)[:200]})
print(json.dumps(line))
PY
done
