#!/usr/bin/env bash
# The main job on the identified law against the same job on the assumed law, side by side.
#   1. jobs/church.toml with its law files switched to materials/rubble-masonry.toml (the
#      assumed alternative), on $NP ranks (default 2), into results/church-assumed/, and its
#      pictures (scripts/post_church.sh);
#   2. scripts/compare_church.py results/church results/church-assumed: the damage after gravity
#      and at the end of the record in both runs, and the shares per substructure, in
#      results/church-comparison/ (damage-side-by-side.png, comparison.csv).
# results/church must hold the main job's results and pictures (scripts/run.sh).
#
# Usage: scripts/compare_laws.sh [--reuse]
#   --reuse   keep results/church-assumed when it holds a finished run (summary.json)
# Time on 2 cores: about 4 min for the assumed-law run and its pictures.
set -euo pipefail
cd "$(dirname "$0")/.."
usage() { sed -n '2,13p' "$0" | sed 's/^# \{0,1\}//'; }
reuse=0
for a in "$@"; do
  case "$a" in
    --reuse) reuse=1 ;;
    -h|--help) usage; exit 0 ;;
    *) echo "compare_laws.sh: unknown option '$a'" >&2; usage >&2; exit 2 ;;
  esac
done
[ -f results/church/pictures/damage-by-substructure.csv ] || {
  echo "compare_laws.sh: results/church/pictures/damage-by-substructure.csv missing: run scripts/run.sh first" >&2; exit 1; }
source scripts/env.sh
cargo build --release --quiet

if [ "$reuse" = 1 ] && [ -f results/church-assumed/summary.json ]; then
  echo "compare_laws: reusing results/church-assumed"
else
  # The job beside jobs/church.toml, so that its relative paths hold; removed on exit.
  job=jobs/.church-assumed-$$.toml
  trap 'rm -f "$job"' EXIT
  sed -e 's#law_file = "../materials/rubble-identified.toml"#law_file = "../materials/rubble-masonry.toml"#' \
      -e 's#dir = "../results/church"#dir = "../results/church-assumed"#' jobs/church.toml > "$job"
  grep -q 'rubble-masonry.toml' "$job" && grep -q 'results/church-assumed' "$job" || {
    echo "compare_laws.sh: jobs/church.toml's law_file or [output] dir changed: cannot derive the assumed-law job" >&2; exit 2; }
  echo "compare_laws: jobs/church.toml on materials/rubble-masonry.toml, $NP rank(s) -> results/church-assumed"
  OMPI_MCA_mpi_yield_when_idle=1 mpirun -n "${NP:-2}" target/release/masonry-hpc "$job"
fi
bash scripts/post_church.sh results/church-assumed
py=""
for p in python3 /usr/bin/python3; do
  if command -v "$p" >/dev/null 2>&1 && "$p" -c "import matplotlib" 2>/dev/null; then py="$p"; break; fi
done
[ -n "$py" ] || { echo "compare_laws.sh: no Python with matplotlib (scripts/setup.sh --paraview)" >&2; exit 1; }
"$py" scripts/compare_church.py results/church results/church-assumed \
  --labels "identified law" "assumed law" --out results/church-comparison
