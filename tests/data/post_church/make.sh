#!/usr/bin/env bash
# Rebuilds the fixture of tests/post_church.rs from its jobs (about 5 minutes with a debug build).
#   tests/data/post_church/make.sh [path/to/masonry-hpc]     (default target/release/masonry-hpc)
set -euo pipefail
cd "$(dirname "$0")"
root=../../..
exe="${1:-$root/target/release/masonry-hpc}"
source "$root/scripts/env.sh"
python3 "$root/scripts/make_church_mesh.py" --size 3.0 -o church-3.0.msh
mpirun -n 2 "$exe" modal.toml
mpirun -n 2 "$exe" earthquake.toml
cp out-modal/modes.xdmf out-modal/modes.h5 .
cp out-earthquake/{results.xdmf,results.h5,envelopes.xdmf,envelopes.h5,monitors.csv} .
# One summary.json with the modes under a stage key, as a pipeline run writes it.
python3 - <<'PY'
import json
modal = json.load(open("out-modal/summary.json"))
quake = json.load(open("out-earthquake/summary.json"))
json.dump({"modal": modal, "earthquake": quake}, open("summary.json", "w"), indent=1)
PY
rm -rf out-modal out-earthquake church-3.0.msh
ls -la
