#!/usr/bin/env bash
# Identification benchmark: the whole chain of jobs/identify-wall.toml (DEM calibration of the
# paper's wall against Table 1, virtual tension and compression tests, damage-law identification,
# material file) on 2 ranks (wall and CPU seconds), against the paper's figure for the law identification alone
# ("32 combinations, about 2 hours for the tensile test"). One JSON line per case: the chain,
# and each phase. Also the calibration machinery on a synthetic target: the DEM's own numbers on
# a small wall at the paper's parameters, to be recovered within 5% (sample means).
# Run through scripts/bench.sh (which builds first).
set -euo pipefail
cd "$(dirname "$0")/../.."
source scripts/env.sh
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
sed -e "s#\"../results/identify-wall\"#\"$work/out\"#" -e "s#\"../results/materials/wall-identified.toml\"#\"$work/material.toml\"#" \
    jobs/identify-wall.toml > "$work/chain.toml"
start=$(date +%s.%N)
/usr/bin/time -f "%U %S" -o "$work/cpu" mpirun -n 2 target/release/masonry-hpc -q "$work/chain.toml" > "$work/log" 2>&1 || true
end=$(date +%s.%N)
python3 - "$work/out/summary.json" "$start" "$end" "$work/log" "$work/cpu" <<'PY'
import json, os, sys
path, wall = sys.argv[1], float(sys.argv[3]) - float(sys.argv[2])
# CPU seconds (user + sys of mpirun and its ranks): the machine may be shared, wall time is not.
try:
    cpu = round(sum(float(x) for x in open(sys.argv[5]).read().split()[-2:]), 2)
except (OSError, ValueError):
    cpu = None
paper = 7200.0
if not os.path.exists(path):
    print(json.dumps({"case": "identify-chain-paper-wall", "ranks": 2, "seconds": round(wall, 3), "completed": False,
                      "error": open(sys.argv[4]).read()[-300:]}))
    sys.exit(0)
s = json.load(open(path))
sec = s["seconds"]
cal, law = s.get("calibration") or {}, s.get("law") or {}
line = {"case": "identify-chain-paper-wall", "ranks": 2, "seconds": round(wall, 3), "cpu_seconds": cpu, "completed": True,
        "strategy": cal.get("strategy"),
        "dem_evaluations": cal.get("evaluations"), "law_evaluations": len(law.get("history", [])),
        "paper_seconds": paper, "ratio_paper_over_ours": round(paper / wall, 2)}
if s.get("calibration_within_5_percent") is not None:
    line["calibration_within_5_percent"] = s["calibration_within_5_percent"]
    line["calibration_relative_errors"] = {k: round(e, 4) for k, e in cal["relative_errors"].items()}
    line["calibration_mean_std_n"] = {k: [st["mean"], st["std"], st["n"]] for k, st in cal["stats"].items()}
if law:
    line["law_peak_errors"] = [round(law["tension_peak_error"], 4), round(law["compression_peak_error"], 4)]
print(json.dumps(line))
for phase in ["calibration", "virtual_tests", "law"]:
    print(json.dumps({"case": f"identify-{phase}", "ranks": 2, "seconds": round(sec[phase], 3)}))
PY

# Synthetic calibration: targets = the DEM's own sample means at alpha 0.8, E_bar 2.5 GPa,
# eps_cr 1e-4, theta_cr 7e-4 on a 4 x 3-stone wall (same sample seeds as the calibration).
wall='layout = { type = "coursed", width = 0.4, height = 0.48, n_courses = 4, n_per_course = 3, jitter = 0.2, size_variability = 0.2 }'
cat > "$work/truth.toml" <<TOML
[analysis]
type = "dem"
samples = 4
[sample]
seed = 1
$wall
[test]
type = "compression"
max_strain = 3.0e-3
steps = 30
[output]
dir = "$work/truth-out"
TOML
target/release/masonry-hpc -q "$work/truth.toml" >/dev/null 2>&1
targets=$(python3 -c "
import json; s = json.load(open('$work/truth-out/summary.json'))
print('\n'.join(f'{k} = {s[k][\"mean\"]!r}' for k in ['young_modulus', 'poisson', 'first_crack_stress', 'peak_stress']))")
cat > "$work/synthetic.toml" <<TOML
[analysis]
type = "identification"
seed = 1
[sample]
seed = 1
$wall
[experiment]
$targets
[calibration]
samples = 4
design_points = 16
iterations = 16
batch = 2
test = { type = "compression", max_strain = 3.0e-3, steps = 30 }
bounds = { alpha = [0.5, 1.2], e_bar = [1.5e9, 3.5e9], eps_cr = [5e-5, 2e-4], theta_cr = [3e-4, 1.5e-3] }
[output]
dir = "$work/synthetic-out"
TOML
start=$(date +%s.%N)
mpirun -n 2 target/release/masonry-hpc -q "$work/synthetic.toml" > "$work/synthetic.log" 2>&1 || true
end=$(date +%s.%N)
python3 - "$work/synthetic-out/summary.json" "$start" "$end" <<'PY'
import json, os, sys
wall = float(sys.argv[3]) - float(sys.argv[2])
if not os.path.exists(sys.argv[1]):
    print(json.dumps({"case": "identify-calibration-synthetic", "ranks": 2, "seconds": round(wall, 3), "completed": False})); sys.exit(0)
s = json.load(open(sys.argv[1])); c = s["calibration"]; p = c["parameters"]
print(json.dumps({"case": "identify-calibration-synthetic", "size": c["evaluations"], "ranks": 2, "seconds": round(wall, 3),
                  "within_5_percent": s["calibration_within_5_percent"],
                  "relative_errors": {k: round(e, 4) for k, e in c["relative_errors"].items()},
                  "identified": {k: p[k] for k in ["alpha", "e_bar", "eps_cr", "theta_cr"]},
                  "true": {"alpha": 0.8, "e_bar": 2.5e9, "eps_cr": 1e-4, "theta_cr": 7e-4}}))
PY
