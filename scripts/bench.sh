#!/usr/bin/env bash
# Benchmarks: one JSON line per case (case, size, ranks, seconds, and the ratio each area reports).
# Each area has its own script under scripts/bench/; this one installs, builds and runs them.
#
#   scripts/bench.sh              # every area
#   scripts/bench.sh dem platform # only these areas (file names under scripts/bench/)
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh >&2
source scripts/env.sh
cargo build --release --quiet
if [ $# -eq 0 ]; then
  set -- $(ls scripts/bench/*.sh | xargs -n1 basename | sed 's/\.sh$//')
fi
for area in "$@"; do
  [ -f "scripts/bench/$area.sh" ] || { echo "error: no benchmark area '$area' (scripts/bench/*.sh)" >&2; exit 2; }
  bash "scripts/bench/$area.sh"
done
