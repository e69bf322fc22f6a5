# Shared steps of the cluster job scripts (church-fine.slurm, church-fine.pbs; church-sweep-fine.slurm
# with SETUP_ONLY=1: steps 1-4); sourced, not run.
#
# Inputs (environment): NP (MPI ranks), LAUNCH (the MPI launcher command, e.g. "srun" or
# "mpirun -n $NP"), JOB_ID (the scheduler's job id), MODULES (site module names, may be empty).
# Steps: load modules → make pkg-config find MPI, PETSc, SLEPc, HDF5 → build once (release) →
# the fine mesh (regenerated if missing) → a job file for it derived from jobs/church.toml →
# validate → run on NP ranks.
set -euo pipefail

# 1. Site modules. The names differ between sites (`module avail petsc`); set MODULES in the
#    job script. Needs: a C compiler, an MPI, PETSc >= 3.18 (real, double, 32-bit PetscInt,
#    with MUMPS for the default direct solver; hypre/GAMG for iterative runs), SLEPc of the same
#    version, parallel HDF5 (>= 1.10), METIS 5, libclang (bindgen), Python 3 (+ gmsh only to
#    regenerate the mesh), and Rust (rustup in $HOME: https://rustup.rs).
if [ -n "${MODULES:-}" ] && command -v module >/dev/null 2>&1; then
  module purge
  # shellcheck disable=SC2086
  module load $MODULES
fi
[ -f "$HOME/.cargo/env" ] && source "$HOME/.cargo/env"

# 2. pkg-config: build.rs reads the include and link flags of `petsc`, `slepc` and `ompi-c`
#    (OpenMPI's C flags). Module systems usually export PKG_CONFIG_PATH; a PETSc built from
#    source keeps its .pc files in $PETSC_DIR/$PETSC_ARCH/lib/pkgconfig.
for d in "${PETSC_DIR:-}/${PETSC_ARCH:-}/lib/pkgconfig" "${PETSC_DIR:-}/lib/pkgconfig" \
         "${SLEPC_DIR:-}/${PETSC_ARCH:-}/lib/pkgconfig" "${SLEPC_DIR:-}/lib/pkgconfig"; do
  [ -d "$d" ] && export PKG_CONFIG_PATH="$d:${PKG_CONFIG_PATH:-}"
done
if ! pkg-config --exists ompi-c; then
  # Not OpenMPI (MPICH, Intel MPI, Cray MPICH): a stand-in `ompi-c.pc` carrying the MPI include
  # path that the site's compiler wrapper uses, so that bindgen sees the same mpi.h as rsmpi.
  inc=$(mpicc -show 2>/dev/null | tr ' ' '\n' | sed -n 's/^-I//p' | head -n 1)
  if [ -z "$inc" ]; then
    echo "cannot find the MPI include path (no ompi-c.pc and no -I in 'mpicc -show')" >&2
    exit 2
  fi
  pc="$HOME/.cache/masonry-hpc/pkgconfig"
  mkdir -p "$pc"
  printf 'Name: ompi-c\nDescription: MPI include path (stand-in)\nVersion: 0\nCflags: -I%s\n' "$inc" > "$pc/ompi-c.pc"
  export PKG_CONFIG_PATH="$pc:${PKG_CONFIG_PATH:-}"
fi
for p in petsc slepc; do
  pkg-config --exists "$p" || { echo "pkg-config cannot find '$p': load the module or set PETSC_DIR/SLEPC_DIR" >&2; exit 2; }
done
echo "MPI: $(mpirun --version 2>/dev/null | head -n 1)"
echo "PETSc $(pkg-config --modversion petsc), SLEPc $(pkg-config --modversion slepc)"
# parallel HDF5: hdf5-metno-sys looks at HDF5_DIR first (modules often export HDF5_ROOT instead)
[ -z "${HDF5_DIR:-}" ] && [ -n "${HDF5_ROOT:-}" ] && export HDF5_DIR="$HDF5_ROOT"

# 3. Build once (a clean release build is about a minute; better done on a login node first).
if [ ! -x target/release/masonry-hpc ] || [ -n "${REBUILD:-}" ]; then
  cargo build --release
fi
# The dense kernels of MUMPS's factorizations (most of a step's time on the fine mesh) run in the
# BLAS that PETSc links: a reference (netlib) libblas is several times slower than OpenBLAS, BLIS
# or MKL. Print which one the binary resolves, to be read in the log.
blas=$(ldd target/release/masonry-hpc 2>/dev/null | awk '/libblas|libopenblas|mkl_core|libblis/ {print $3; exit}')
echo "BLAS: ${blas:+$(readlink -f "$blas")}"

# 4. The fine mesh: meshes/church-fine.msh is committed (36,688 nodes, 220,128 DOF);
#    regenerate it if it is missing (needs `pip install --user gmsh`).
[ -f meshes/church-fine.msh ] || python3 scripts/make_church_mesh.py --fine

# A script that runs another job on the same model (church-sweep-fine.*) stops here.
if [ -n "${SETUP_ONLY:-}" ]; then
  return 0
fi

# 5. The job: jobs/church.toml (the main church job: modal updating, gravity, the 22 s
#    Vallorcine-like record) pointed at the fine mesh and its own results folder. The derived
#    file stays in jobs/ so that the job's relative paths (mesh, record, law file) still resolve.
JOB="jobs/church-fine-${JOB_ID}.toml"
sed -e 's#\(file *= *"[^"]*\)church\.msh"#\1church-fine.msh"#' \
    -e 's#\(dir *= *"[^"]*\)results/church"#\1results/church-fine-'"${JOB_ID}"'"#' \
    jobs/church.toml > "$JOB"
grep -q 'church-fine\.msh' "$JOB" || { echo "$JOB does not use meshes/church-fine.msh: edit its [mesh] file" >&2; exit 2; }
target/release/masonry-hpc check "$JOB"

# 6. Run. PETSc options after the job file override the job's [solver.petsc], e.g. an
#    iterative solver for large rank counts: -ksp_type cg -pc_type gamg -ksp_rtol 1e-10
echo "running $JOB on $NP ranks: $LAUNCH target/release/masonry-hpc $JOB ${PETSC_ARGS:-}"
# shellcheck disable=SC2086
$LAUNCH target/release/masonry-hpc "$JOB" ${PETSC_ARGS:-}
