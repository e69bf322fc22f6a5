#!/usr/bin/env bash
# Identification benchmark: the whole chain of jobs/identify-wall.toml (DEM calibration of the
# paper's wall against Table 1, virtual tension and compression tests, damage-law identification,
# material file) on 2 ranks, against the paper's figure for the law identification alone
# ("32 combinations, about 2 hours for the tensile test"). One JSON line per case: the chain,
# and each phase. Run through scripts/bench.sh (which builds first).
set -euo pipefail
cd "$(dirname "$0")/../.."
source scripts/env.sh
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
sed -e "s#\"../results/identify-wall\"#\"$work/out\"#" -e "s#\"../materials/wall-identified.toml\"#\"$work/material.toml\"#" \
    jobs/identify-wall.toml > "$work/chain.toml"
start=$(date +%s.%N)
mpirun -n 2 target/release/masonry-hpc -q "$work/chain.toml" > "$work/log" 2>&1 || true
end=$(date +%s.%N)
python3 - "$work/out/summary.json" "$start" "$end" "$work/log" <<'PY'
import json, os, sys
path, wall = sys.argv[1], float(sys.argv[3]) - float(sys.argv[2])
paper = 7200.0
if not os.path.exists(path):
    print(json.dumps({"case": "identify-chain-paper-wall", "ranks": 2, "seconds": round(wall, 3), "completed": False,
                      "error": open(sys.argv[4]).read()[-300:]}))
    sys.exit(0)
s = json.load(open(path))
sec = s["seconds"]
cal, law = s.get("calibration") or {}, s.get("law") or {}
line = {"case": "identify-chain-paper-wall", "ranks": 2, "seconds": round(wall, 3), "completed": True,
        "dem_evaluations": cal.get("evaluations"), "law_evaluations": len(law.get("history", [])),
        "paper_seconds": paper, "ratio_paper_over_ours": round(paper / wall, 2)}
if s.get("calibration_within_5_percent") is not None:
    line["calibration_within_5_percent"] = s["calibration_within_5_percent"]
    line["calibration_relative_errors"] = [round(e, 4) for e in cal["relative_errors"]]
if law:
    line["law_peak_errors"] = [round(law["tension_peak_error"], 4), round(law["compression_peak_error"], 4)]
print(json.dumps(line))
for phase in ["calibration", "virtual_tests", "law"]:
    print(json.dumps({"case": f"identify-{phase}", "ranks": 2, "seconds": round(sec[phase], 3)}))
PY
