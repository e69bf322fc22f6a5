#!/usr/bin/env bash
# The main job: installs what is missing, builds (release) and runs the bundled default job
# (jobs/church.toml: the church's modal updating, gravity and the 22 s earthquake) on 2 MPI ranks,
# then draws the church's pictures into results/church/pictures/. Another job's time history
# (e.g. jobs/template-building.toml) gets its pictures from scripts/post.sh.
# Usage: scripts/run.sh [JOB.toml] [PETSc options...]   (NP=4 scripts/run.sh to change ranks)
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh --paraview           # ParaView + xvfb for the church pictures
source scripts/env.sh
[ -f meshes/tower.msh ] || python3 scripts/make_tower_mesh.py -o meshes/tower.msh
[ -f meshes/church.msh ] || python3 scripts/make_church_mesh.py
[ -f meshes/house.msh ] || python3 scripts/make_house_mesh.py
cargo build --release --quiet
job="${1:-jobs/church.toml}"
shift || true
# OpenMPI yields the core while a rank waits: on a machine shared with other work its busy
# polling otherwise slows 2-rank runs several times.
OMPI_MCA_mpi_yield_when_idle=1 mpirun -n "${NP:-2}" target/release/masonry-hpc "$job" "$@"
if [ "$job" = "jobs/church.toml" ]; then
  # The record's spectrum against EC8 (the same record file as the church job's, scale 1).
  target/release/masonry-hpc jobs/spectrum-vallorcine.toml
  cp results/spectrum-vallorcine/spectrum.png results/church/spectrum.png
  # Mesh, modes, damage at the end, drift envelope, monitors (skipped, with the reason, without ParaView).
  bash scripts/post_church.sh results/church
else
  # A time history's pictures, in the job's results folder (as `check` names it).
  dir="$(target/release/masonry-hpc check "$job" 2>/dev/null | sed -n 's/.*results would go to //p' | tail -n 1)"
  if [ -n "$dir" ] && [ -f "$dir/results.xdmf" ] && [ -f "$dir/monitors.csv" ]; then
    bash scripts/post.sh "$dir"
  fi
fi
