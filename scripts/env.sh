# Sourced by the project's scripts: MPI settings for running as root and on small machines.
if [ "$(id -u)" -eq 0 ]; then
  export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
fi
# Allow more ranks than cores (CI machines have 2 cores) and do not pin ranks to cores.
export OMPI_MCA_rmaps_base_oversubscribe=1
export OMPI_MCA_hwloc_base_binding_policy=none
# cargo may not be on PATH in a non-login shell.
[ -d "$HOME/.cargo/bin" ] && export PATH="$HOME/.cargo/bin:$PATH"
# OpenBLAS (scripts/setup.sh) picks its kernels from the CPU model; a model newer than its release
# (Debian 12's 0.3.21 does not know Sapphire/Emerald Rapids) falls back to the SSE3 "Prescott"
# kernels (dgemm was 48 % of the fine church's profile with them, 17 % with the AVX-512 ones).
# Name the kernel family from the CPU's flags unless the user chose one.
if [ -z "${OPENBLAS_CORETYPE:-}" ] && [ -r /proc/cpuinfo ]; then
  if grep -qm1 '^flags.* avx512f' /proc/cpuinfo; then export OPENBLAS_CORETYPE=SkylakeX
  elif grep -qm1 '^flags.* avx2' /proc/cpuinfo; then export OPENBLAS_CORETYPE=Haswell
  fi
fi
# The first Python with matplotlib (the pictures of the comparison and post-processing scripts):
# a pyenv or venv python3 on PATH may lack it where Debian's /usr/bin/python3 has it
# (scripts/setup.sh --paraview). Prints nothing when there is none.
matplotlib_python() {
  local p
  for p in python3 /usr/bin/python3; do
    if command -v "$p" >/dev/null 2>&1 && "$p" -c "import matplotlib" 2>/dev/null; then echo "$p"; return; fi
  done
}
