#!/usr/bin/env bash
# Install what masonry-hpc needs to build, run and test, when it is missing.
#
#   scripts/setup.sh            # system packages + Python test readers
#   scripts/setup.sh --paraview # also ParaView (pvpython) for post-processing
#
# Idempotent and quiet: a machine that already has everything spends well under a second here.
# Debian packages (STACK.md): compilers, MPI, PETSc/SLEPc, parallel HDF5, METIS, libclang for bindgen.
set -euo pipefail

want_paraview=0
for a in "$@"; do
  case "$a" in
    --paraview) want_paraview=1 ;;
    -h|--help) sed -n '2,8p' "$0"; exit 0 ;;
    *) echo "setup.sh: unknown option '$a'" >&2; exit 2 ;;
  esac
done

debs=(build-essential pkg-config libclang-dev libopenmpi-dev openmpi-bin
      petsc-dev slepc-dev libhdf5-openmpi-dev libmetis-dev
      # CHOLMOD (the DEM solver's factor updated in place, src/dem/solver/cholmod.rs)
      libsuitesparse-dev
      # an optimized BLAS/LAPACK under MUMPS's and SLEPc's dense kernels: petsc-dev brings only the
      # reference libblas3 (with it the fine church's gravity step had not ended after 13 min on 2
      # ranks; with OpenBLAS it takes 224 s); this single-threaded OpenBLAS (one thread per MPI
      # rank) takes over the libblas.so.3 alternative on install
      libopenblas0-serial
      # shared libraries the PyPI gmsh wheel loads (the church mesh script)
      libglu1-mesa libgl1 libxrender1 libxcursor1 libxft2 libxinerama1 libgomp1)
[ "$want_paraview" = 1 ] && debs+=(paraview python3-paraview xvfb)

missing=()
for p in "${debs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

if [ "${#missing[@]}" -gt 0 ]; then
  echo "setup: installing Debian packages: ${missing[*]}"
  sudo_cmd=()
  [ "$(id -u)" -ne 0 ] && sudo_cmd=(sudo)
  export DEBIAN_FRONTEND=noninteractive
  "${sudo_cmd[@]}" apt-get update -qq >/dev/null
  "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

# Independent readers used by the tests to check HDF5/XDMF output; gmsh (its Python API ships
# the library) for the church mesh script.
py_missing=()
python3 -c "import meshio" 2>/dev/null || py_missing+=(meshio)
python3 -c "import h5py" 2>/dev/null || py_missing+=(h5py)
python3 -c "import gmsh" 2>/dev/null || py_missing+=(gmsh==4.15.2)   # the version of meshes/church*.msh
if [ "${#py_missing[@]}" -gt 0 ]; then
  echo "setup: installing Python packages: ${py_missing[*]}"
  python3 -m pip install -q --disable-pip-version-check --root-user-action=ignore "${py_missing[@]}"
fi
# rustfmt and clippy, which the test command runs (scripts/test.sh), when rustup manages Rust.
if command -v rustup >/dev/null 2>&1; then
  for c in rustfmt clippy; do
    rustup component list --installed 2>/dev/null | grep -q "^$c" || { echo "setup: rustup component add $c"; rustup component add "$c" >/dev/null; }
  done
fi
exit 0
