#!/usr/bin/env bash
# The main job: installs what is missing, builds (release) and runs the bundled default job on
# 2 MPI ranks.  Usage: scripts/run.sh [JOB.toml] [PETSc options...]   (NP=4 scripts/run.sh to change ranks)
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
source scripts/env.sh
[ -f meshes/tower.msh ] || python3 scripts/make_tower_mesh.py -o meshes/tower.msh
cargo build --release --quiet
job="${1:-jobs/tower.toml}"
shift || true
mpirun -n "${NP:-2}" target/release/masonry-hpc "$job" "$@"
