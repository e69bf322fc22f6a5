#!/usr/bin/env bash
# DEM benchmark, one JSON line per case. Run through scripts/bench.sh (which builds first).
#  (a) 32 tension tests of the paper's wall as one batch on 2 ranks (the paper: about 2 hours
#      for 32): seconds and the ratio paper/ours (target: under 10 s);
#  (b) compression to post-peak of random samples of 1k, 10k and 50k stones on one core:
#      seconds, events, events per second, peak memory (VmHWM), how the test ended; beside it one
#      sparse factorization of the same operator alone (examples/dem_factorization.rs), and the
#      cost of an event in factorizations (target: 10k under 60 s; the cost per event growing no
#      faster than a factorization);
#  (c) the scaling: log-log slopes of seconds per event and of the factorization against size.
# Every line carries the load average (the machine may be shared).
#
# Environment: BIN (default target/release/masonry-hpc; target/debug works, its dependencies,
# faer included, are optimized), DEM_BENCH_SIZES (default "1000 10000 50000"),
# DEM_BENCH_TIMEOUT (seconds per case of (b), default 3600), DEM_BENCH_SKIP_BATCH=1 skips (a).
set -euo pipefail
cd "$(dirname "$0")/../.."
source scripts/env.sh
BIN=${BIN:-target/release/masonry-hpc}
profile=$(basename "$(dirname "$BIN")")
FACTOR_BIN="target/$profile/examples/dem_factorization"
if [ ! -x "$FACTOR_BIN" ]; then
  if [ "$profile" = release ]; then cargo build --release --quiet --example dem_factorization >&2
  else cargo build --quiet --example dem_factorization >&2; fi
fi
SIZES=${DEM_BENCH_SIZES:-"1000 10000 50000"}
TIMEOUT=${DEM_BENCH_TIMEOUT:-3600}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
load() { cut -d' ' -f1-3 /proc/loadavg; }

if [ "${DEM_BENCH_SKIP_BATCH:-0}" != 1 ]; then
  sed -e 's/^samples = 16/samples = 32/' -e "s#\"../results/wall-tension\"#\"$work/dem-out\"#" \
      -e 's/^existing = .*//' jobs/wall-tension.toml > "$work/tension32.toml"
  sed -i 's/^type = "dem"/type = "dem"\nparticle_states = "none"/' "$work/tension32.toml"
  l0=$(load)
  start=$(date +%s.%N)
  mpirun -n 2 "$BIN" -q "$work/tension32.toml" >/dev/null 2>&1 || true
  end=$(date +%s.%N)
  python3 - "$work/dem-out/summary.json" "$start" "$end" "$l0" "$BIN" <<'PY'
import json, sys
s = json.load(open(sys.argv[1])); wall = float(sys.argv[3]) - float(sys.argv[2])
ok = sum(1 for x in s["samples"] if "Ok" in x["result"])
print(json.dumps({"case": "dem-paper-wall-tension-batch", "size": 32, "ranks": 2, "seconds": round(wall, 3),
                  "samples_completed": ok, "paper_seconds": 7200, "ratio_paper_over_ours": round(7200 / wall, 1),
                  "events_per_second": round(s["events_per_second"], 1), "load_average": sys.argv[4],
                  "binary": sys.argv[5]}))
PY
fi

lines="$work/b.jsonl"
: > "$lines"
for n in $SIZES; do
  cat > "$work/random-$n.toml" <<TOML
[analysis]
type = "dem"
samples = 1
particle_states = "none"
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
  fact=$("$FACTOR_BIN" "$n")
  l0=$(load)
  t0=$(date +%s.%N)
  out=$( { /usr/bin/time -f "rss_kb=%M" timeout "$TIMEOUT" "$BIN" "$work/random-$n.toml" 2>&1 >/dev/null; } 2>&1 || true )
  t1=$(date +%s.%N)
  python3 - "$work/random-$n-out/summary.json" "$n" "$t0" "$t1" "$out" "$fact" "$l0" "$TIMEOUT" "$BIN" <<'PY' | tee -a "$lines"
import json, os, re, sys
n, wall, out = int(sys.argv[2]), float(sys.argv[4]) - float(sys.argv[3]), sys.argv[5]
fact = json.loads(sys.argv[6])
rss = re.search(r"rss_kb=(\d+)", out)
line = {"case": "dem-random-compression", "size": n, "ranks": 1, "seconds": round(wall, 3),
        "peak_memory_mb": round(int(rss.group(1)) / 1024, 1) if rss else None,
        "equations": fact["equations"], "factorization_seconds": fact["numeric_factorization_seconds"],
        "first_factorization_seconds": fact["first_factorization_seconds"], "solve_seconds": fact["solve_seconds"],
        "load_average": sys.argv[7], "binary": sys.argv[9]}
if os.path.exists(sys.argv[1]):
    smp = json.load(open(sys.argv[1]))["samples"][0]
    ev, sec = smp["events"], max(smp["seconds"], 1e-9)
    line.update({"completed": True, "end": smp["end"], "events": ev, "test_seconds": round(sec, 3),
                 "events_per_second": round(ev / sec, 1)})
    if ev > 0:
        line["seconds_per_event"] = sec / ev
        line["event_cost_in_factorizations"] = round(sec / ev / max(fact["numeric_factorization_seconds"], 1e-9), 3)
    pk = json.load(open(sys.argv[1])).get("peak_stress") or {}
    line["peak_stress_mpa"] = round(pk.get("mean", 0.0) / 1e6, 4)
else:
    timed_out = wall >= float(sys.argv[8]) - 1
    err = re.search(r"error: (.*)", out)
    line.update({"completed": False, "timed_out": timed_out, "error": err.group(1)[:200] if err else None})
print(json.dumps(line))
PY
done
python3 - "$lines" <<'PY'
import json, math, sys
rows = [json.loads(l) for l in open(sys.argv[1]) if l.strip()]
rows = [r for r in rows if r.get("seconds_per_event")]
for a, b in zip(rows, rows[1:]):
    k = math.log(b["equations"] / a["equations"])
    print(json.dumps({"case": "dem-cost-scaling", "size": f"{a['size']}->{b['size']}",
                      "slope_seconds_per_event": round(math.log(b["seconds_per_event"] / a["seconds_per_event"]) / k, 2),
                      "slope_factorization": round(math.log(b["factorization_seconds"] / a["factorization_seconds"]) / k, 2),
                      "note": "log-log slopes against the number of equations; the event cost should not grow faster than the factorization"}))
PY
