#!/usr/bin/env bash
# The whole test suite: installs what is missing, checks formatting and clippy, builds, runs unit,
# verification, bad-input and MPI tests (1 and 2 ranks).  Usage: scripts/test.sh [extra cargo test args]
# Time: 1,851 s on a clean clone in CI, build included (2026-11-28, the landing before the
# spectral main job; 2 cores).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
source scripts/env.sh
[ -f meshes/tower.msh ] || python3 scripts/make_tower_mesh.py -o meshes/tower.msh
# The house rules first: formatting (rustfmt.toml) and clippy without warnings.
cargo fmt --all --check || { echo "test.sh: run 'cargo fmt --all' (the code is not formatted)" >&2; exit 1; }
cargo clippy --all-targets --quiet -- -D warnings
cargo build --all-targets --quiet
# Test binaries share 2 cores with the mpirun jobs they start: two at a time is enough.
cargo test --no-fail-fast -- --test-threads=2 "$@"
