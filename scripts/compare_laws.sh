#!/usr/bin/env bash
# The main job on its law against the same job on another law, side by side.
#   1. jobs/church.toml with its law files switched to the other law, on $NP ranks (default 2),
#      into results/church-<other>/, and its pictures (scripts/post_church.sh):
#        --against trace     materials/rubble-identified.toml: the same identification under the
#                            paper's unilateral split (split "trace"), which creates energy when
#                            a crack closes under shear (the default)
#        --against assumed   materials/rubble-masonry.toml: the assumed law (its header)
#   2. scripts/compare_church.py results/church results/church-<other>: the damage after gravity
#      and at the end of the record in both runs, the shares per substructure and the energy
#      terms, in results/church-comparison-<other>/ (damage-side-by-side.png, comparison.csv,
#      energy.csv).
# results/church must hold the main job's results and pictures (scripts/run.sh).
#
# Usage: scripts/compare_laws.sh [--against trace|assumed] [--reuse]
#   --reuse   keep results/church-<other> when it holds a finished run (summary.json)
# Time on 2 cores: about 4 min for the other law's run and its pictures.
set -euo pipefail
cd "$(dirname "$0")/.."
usage() { sed -n '2,18p' "$0" | sed 's/^# \{0,1\}//'; }
reuse=0 against=trace
while [ $# -gt 0 ]; do
  case "$1" in
    --reuse) reuse=1 ;;
    --against) shift; against="${1:-}" ;;
    -h|--help) usage; exit 0 ;;
    *) echo "compare_laws.sh: unknown option '$1'" >&2; usage >&2; exit 2 ;;
  esac
  shift
done
case "$against" in
  trace) law=materials/rubble-identified.toml label="paper's split (trace)" ;;
  assumed) law=materials/rubble-masonry.toml label="assumed law" ;;
  *) echo "compare_laws.sh: --against expects trace or assumed, got '$against'" >&2; exit 2 ;;
esac
main_law=materials/rubble-identified-spectral.toml
other=results/church-$against
[ -f results/church/pictures/damage-by-substructure.csv ] || {
  echo "compare_laws.sh: results/church/pictures/damage-by-substructure.csv missing: run scripts/run.sh first" >&2; exit 1; }
source scripts/env.sh
cargo build --release --quiet

if [ "$reuse" = 1 ] && [ -f "$other/summary.json" ]; then
  echo "compare_laws: reusing $other"
else
  # The job beside jobs/church.toml, so that its relative paths hold; removed on exit.
  job=jobs/.church-$against-$$.toml
  trap 'rm -f "$job"' EXIT
  sed -e "s#law_file = \"../$main_law\"#law_file = \"../$law\"#" \
      -e "s#dir = \"../results/church\"#dir = \"../$other\"#" \
      -e '/^convergence = /d' jobs/church.toml > "$job"
  grep -q "$law" "$job" && grep -q "$other" "$job" || {
    echo "compare_laws.sh: jobs/church.toml's law_file ($main_law) or [output] dir changed: cannot derive the other law's job" >&2; exit 2; }
  echo "compare_laws: jobs/church.toml on $law, ${NP:-2} rank(s) -> $other"
  OMPI_MCA_mpi_yield_when_idle=1 mpirun -n "${NP:-2}" target/release/masonry-hpc "$job"
fi
bash scripts/post_church.sh "$other"
py=$(matplotlib_python)
[ -n "$py" ] || { echo "compare_laws.sh: no Python with matplotlib (scripts/setup.sh --paraview)" >&2; exit 1; }
"$py" scripts/compare_church.py results/church "$other" \
  --labels "spectral split (main job)" "$label" --out "results/church-comparison-$against"
