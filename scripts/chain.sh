#!/usr/bin/env bash
# The whole chain, Table 1 to the church, in one command:
#   1. jobs/identify-wall.toml: Table 1 -> staged DEM calibration -> virtual tension and
#      compression -> damage-law fit -> materials/rubble-identified.toml (results/identify-wall/;
#      the virtual tests' sample curves copied to tests/data/identify-wall/ for tests/identify.rs),
#      then jobs/identify-wall-spectral.toml: the same fit under the spectral split from those
#      curves -> materials/rubble-identified-spectral.toml, the law the church uses
#   2. jobs/church.toml: modal analysis, modal updating, gravity, the 22 s record (results/church/)
#   3. scripts/post_church.sh results/church: the pictures (results/church/pictures/)
#   4. scripts/chain_summary.py: results/chain/summary.md and summary.json, each stage's numbers
#      side by side (calibration against Table 1, the law's peaks against the DEM's, frequencies,
#      gravity, damage per substructure after gravity and at the end), with the stages' wall times.
#   With --compare, then scripts/compare_laws.sh --against assumed: the church on the assumed law
#      (materials/rubble-masonry.toml), its damage beside the identified law's
#      (results/church-comparison-assumed/damage-side-by-side.png, comparison.csv; about 4 min more).
# Stages 1-3 run through scripts/run.sh (setup, release build, env, mpirun; run.sh draws the
# church's pictures itself). Logs: results/chain/identify.log, church.log.
#
# Usage: scripts/chain.sh [--skip-identify] [--skip-church] [--compare]
#   NP=4 scripts/chain.sh     ranks (default 2)
#   --skip-identify           keep results/identify-wall and the material file as they are
#   --skip-church             stop after the identification (summary of what exists)
#   --compare                 the assumed law's run beside the identified law's (above)
# Reproducible: the identification from its seeds writes both material files and the
# sample curves again byte for byte; the summary says whether they equal the committed files.
# Time on 2 cores (measured): identification 5-8 min, church and pictures 5 min, --compare
# 3.6 min more; 13 min 36 s in all with --compare (2026-11-26, before the spectral
# identification joined the chain: about 30 s more).
set -euo pipefail
cd "$(dirname "$0")/.."
usage() { sed -n '2,25p' "$0" | sed 's/^# \{0,1\}//'; }

skip_identify=0 skip_church=0 compare=0
for a in "$@"; do
  case "$a" in
    --skip-identify) skip_identify=1 ;;
    --skip-church) skip_church=1 ;;
    --compare) compare=1 ;;
    -h|--help) usage; exit 0 ;;
    *) echo "chain.sh: unknown option '$a'" >&2; usage >&2; exit 2 ;;
  esac
done

export NP="${NP:-2}"
out=results/chain
mkdir -p "$out"
material=materials/rubble-identified.toml
spectral=materials/rubble-identified-spectral.toml
stages_json=""   # the timings' stage entries, comma-separated
t_chain=$(date +%s)

say() { echo "[chain $(date +%H:%M:%S), $(( $(date +%s) - t_chain )) s] $*"; }
record() {  # name status seconds
  stages_json="${stages_json:+$stages_json, }{\"name\": \"$1\", \"status\": \"$2\", \"seconds\": $3}"
}
# Runs "$@" with its output on the terminal and in the log $1 (shifted); sets rc and secs.
run_logged() {
  local log=$1; shift
  local t0; t0=$(date +%s)
  set +e
  "$@" 2>&1 | tee "$log"
  rc=${PIPESTATUS[0]}
  set -e
  secs=$(( $(date +%s) - t0 ))
}

church_rc=0
if [ "$skip_identify" = 0 ]; then
  say "1/4 identification on $NP rank(s): jobs/identify-wall.toml (log $out/identify.log)"
  run_logged "$out/identify.log" bash scripts/run.sh jobs/identify-wall.toml
  if [ "$rc" -ne 0 ]; then
    record identification failed "$secs"
    say "identification failed (exit $rc): see $out/identify.log"
    printf '{"ranks": %s, "stages": [%s]}\n' "$NP" "$stages_json" > "$out/timings.json"
    python3 scripts/chain_summary.py --out "$out" || true
    exit "$rc"
  fi
  record identification ok "$secs"
  # The virtual tests' sample curves beside the law they gave: tests/identify.rs refits the law
  # from them and checks it against the material file.
  mkdir -p tests/data/identify-wall
  cp results/identify-wall/dem_tension_samples.csv results/identify-wall/dem_compression_samples.csv tests/data/identify-wall/
  say "identification done in $secs s: $material, tests/data/identify-wall/dem_*_samples.csv"
  run_logged "$out/identify-spectral.log" bash scripts/run.sh jobs/identify-wall-spectral.toml
  if [ "$rc" -ne 0 ]; then
    record "identification (spectral split)" failed "$secs"
    say "identification under the spectral split failed (exit $rc): see $out/identify-spectral.log"
    printf '{"ranks": %s, "stages": [%s]}\n' "$NP" "$stages_json" > "$out/timings.json"
    python3 scripts/chain_summary.py --out "$out" || true
    exit "$rc"
  fi
  record "identification (spectral split)" ok "$secs"
  say "identification under the spectral split done in $secs s: $spectral"
else
  say "1/4 identification skipped (--skip-identify)"
fi

reproduced=null
committed=("$material" "$spectral" tests/data/identify-wall/dem_tension_samples.csv tests/data/identify-wall/dem_compression_samples.csv)
if git rev-parse --is-inside-work-tree >/dev/null 2>&1 && git ls-files --error-unmatch "${committed[@]}" >/dev/null 2>&1; then
  if git diff --quiet -- "${committed[@]}"; then reproduced=true; else reproduced=false; fi
  say "$material, $spectral and the sample curves: $([ "$reproduced" = true ] && echo 'identical to the committed versions' || echo 'DIFFER from the committed versions (git diff materials/ tests/data/identify-wall/)')"
fi

if [ "$skip_church" = 0 ]; then
  say "2/4 and 3/4 church on $NP rank(s): jobs/church.toml, then scripts/post_church.sh results/church (log $out/church.log)"
  run_logged "$out/church.log" bash scripts/run.sh jobs/church.toml
  church_rc=$rc
  record "church and pictures" "$([ "$rc" -eq 0 ] && echo ok || echo "failed (exit $rc)")" "$secs"
  if [ "$rc" -ne 0 ]; then
    say "church job failed (exit $rc): see $out/church.log; the summary reports how far it got"
  else
    say "church and pictures done in $secs s"
  fi
else
  say "2/4 and 3/4 church skipped (--skip-church)"
fi

if [ "$compare" = 1 ] && [ "$skip_church" = 0 ] && [ "$church_rc" -eq 0 ]; then
  say "the assumed law's run beside the identified law's: scripts/compare_laws.sh (log $out/compare.log)"
  run_logged "$out/compare.log" bash scripts/compare_laws.sh --against assumed
  record "assumed-law comparison" "$([ "$rc" -eq 0 ] && echo ok || echo "failed (exit $rc)")" "$secs"
fi

say "4/4 summary"
printf '{"ranks": %s, "material_reproduced": %s, "stages": [%s]}\n' "$NP" "$reproduced" "$stages_json" > "$out/timings.json"
python3 scripts/chain_summary.py --out "$out"
say "done: $out/summary.md"
exit "$church_rc"
