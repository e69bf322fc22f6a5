#!/usr/bin/env bash
# DEM benchmark: (a) 32 tension tests of the paper's wall as one batch on 2 ranks (the paper:
# about 2 hours); (b) compression of random samples: seconds, events/s, peak memory.
# One JSON line per case. Run through scripts/bench.sh (which builds first).
set -euo pipefail
cd "$(dirname "$0")/../.."
source scripts/env.sh
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
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
