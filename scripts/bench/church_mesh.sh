#!/usr/bin/env bash
# Church mesh benchmark: generation (and checks) of the coarse and fine Notre-Dame de la Gorge
# meshes by scripts/make_church_mesh.py, and the elastic modal job (jobs/church-modal.toml, 12
# modes) on the coarse mesh on 1 and 2 ranks and on the fine mesh on 2 ranks: seconds, DOF,
# first frequency, peak memory of the largest rank. One JSON line per case. Run through
# scripts/bench.sh (which builds first).
set -euo pipefail
cd "$(dirname "$0")/../.."
source scripts/env.sh
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
for variant in coarse fine; do
  flag=""; [ "$variant" = fine ] && flag="--fine"
  start=$(date +%s.%N)
  python3 scripts/make_church_mesh.py $flag --json -o "$work/church-$variant.msh" > "$work/mesh-$variant.log"
  end=$(date +%s.%N)
  python3 - "$work/mesh-$variant.log" "$start" "$end" "$variant" <<'PY'
import json, sys
s = json.loads(open(sys.argv[1]).read().strip().splitlines()[-1])
print(json.dumps({"case": f"church-mesh-{sys.argv[4]}", "size": s["nodes"], "dof": s["dof"], "ranks": 1,
                  "seconds": round(float(sys.argv[3]) - float(sys.argv[2]), 3),
                  "generation_seconds": round(s["seconds"], 3)}))
PY
done
for case in "coarse 1" "coarse 2" "fine 2"; do
  set -- $case
  variant=$1; np=$2
  sed -e "s#file = \"../meshes/church.msh\"#file = \"$work/church-$variant.msh\"#" \
      -e "s#dir = \"../results/church-modal\"#dir = \"$work/out-$variant-$np\"#" jobs/church-modal.toml > "$work/modal-$variant-$np.toml"
  start=$(date +%s.%N)
  /usr/bin/time -f "%M" -o "$work/rss" mpirun -n "$np" target/release/masonry-hpc -q "$work/modal-$variant-$np.toml" >/dev/null 2>&1
  end=$(date +%s.%N)
  python3 - "$work/out-$variant-$np/summary.json" "$start" "$end" "$variant" "$np" "$work/rss" <<'PY'
import json, sys
s = json.load(open(sys.argv[1])); wall = float(sys.argv[3]) - float(sys.argv[2])
rss_mb = int(open(sys.argv[6]).read().split()[-1]) / 1024
print(json.dumps({"case": f"church-modal-{sys.argv[4]}", "size": s["nodes"], "dof": s["equations"], "ranks": int(sys.argv[5]),
                  "seconds": round(wall, 3), "eigensolve_seconds": round(s["seconds"]["eigensolve"], 3),
                  "f1_hz": round(s["modes"][0]["frequency"], 4), "peak_rss_mb_largest_rank": round(rss_mb, 1)}))
PY
done
