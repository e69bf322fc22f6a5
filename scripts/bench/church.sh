#!/usr/bin/env bash
# Church benchmark (jobs/church.toml, the main job). One JSON line per case:
#   church-coarse-full     the whole job on the coarse mesh (19,308 equations): modal, updating, gravity,
#                          22 s of record; on 1 and 2 ranks: wall-clock seconds, seconds per time
#                          step, the speedup of 2 ranks over 1, peak memory per rank (VmHWM)
#   church-fine-segment    the fine mesh (meshes/church-fine.msh, 220,128 DOF) without updating,
#                          gravity then STEPS time steps (default 5), on 2 ranks: seconds per step,
#                          peak memory per rank
#   church-fine-full       the whole main job on the fine mesh, as the cluster scripts run it
#                          (modal updating, gravity, the 22 s record), on 2 ranks: about an hour
#                          of both cores, so only when asked for (CASES="fine-full")
# Every line carries the load average at the start and end of the case (`uptime`): the machine
# may be shared, which inflates the timings. Run through scripts/bench.sh (which builds first).
# CASES="coarse" or CASES="fine" runs one of the two; STEPS sets the fine segment's length;
# RANKS="2" runs the coarse job on 2 ranks only (then no speedup is reported).
# BASELINE=<commit> also runs that commit's main job (its jobs/church.toml: the solver settings
# of the time, on the same mesh and law files) with that commit's binary (built once, kept in
# target/baseline/), each rank count first with it and then with the current one, and adds to
# the current one's line its speed-up over the baseline ("speedup_vs_baseline").
set -euo pipefail
cd "$(dirname "$0")/../.."
source scripts/env.sh
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cp -r jobs/records "$work/records"
root=$(pwd)
bin=$root/target/release/masonry-hpc
baseline=""
if [ -n "${BASELINE:-}" ]; then
  source scripts/bench/baseline.sh
  baseline=$(baseline_binary "$BASELINE")
fi
cases="${CASES:-coarse fine}"   # fine-full only when named
steps="${STEPS:-5}"
ranks="${RANKS:-1 2}"
loadavg() { cut -d' ' -f1 /proc/loadavg; }

# Runs `mpirun -n $1 $3 $2` ($3: the binary, default the current one), sampling VmHWM of every rank's process each second.
# Writes $work/run.wall (seconds) and $work/run.mem (peak MB per rank, space separated).
measure() {
  local np=$1 job=$2 exe=${3:-$bin}
  local start end
  start=$(date +%s.%N)
  OMPI_MCA_mpi_yield_when_idle=1 mpirun -n "$np" "$exe" -q "$job" >"$work/run.log" 2>&1 &
  local launcher=$!
  declare -A peak=()
  while kill -0 "$launcher" 2>/dev/null; do
    for pid in $(pgrep -P "$launcher" -f masonry-hpc 2>/dev/null || true); do
      local hwm
      hwm=$(awk '/VmHWM/ {print $2}' "/proc/$pid/status" 2>/dev/null || echo 0)
      if [ -n "$hwm" ] && [ "${peak[$pid]:-0}" -lt "$hwm" ]; then peak[$pid]=$hwm; fi
    done
    sleep 1
  done
  wait "$launcher" || { echo "error: the run failed, log:" >&2; tail -20 "$work/run.log" >&2; exit 1; }
  end=$(date +%s.%N)
  python3 -c "print($end - $start)" > "$work/run.wall"
  local mem=""
  for pid in "${!peak[@]}"; do mem="$mem $(( ${peak[$pid]} / 1024 ))"; done
  echo "$mem" > "$work/run.mem"
}

# The BLAS under MUMPS (the factorizations' dense kernels) and OpenBLAS's kernel family (env.sh).
blas_lib=$(ldd target/release/masonry-hpc 2>/dev/null | awk '/libblas|libopenblas|mkl_core|libblis/ {print $3; exit}')
blas="${blas_lib:+$(readlink -f "$blas_lib")}${OPENBLAS_CORETYPE:+ ($OPENBLAS_CORETYPE)}"

emit() { # case np summary.json load_before [binary label]
  python3 - "$1" "$2" "$3" "$4" "$(cat "$work/run.wall")" "$(cat "$work/run.mem")" "$(loadavg)" "$blas" "${5:-current}" <<'PY'
import json, sys
case, np_, summ, load0, wall, mem, load1, blas, binary = sys.argv[1], int(sys.argv[2]), sys.argv[3], sys.argv[4], float(sys.argv[5]), sys.argv[6], sys.argv[7], sys.argv[8], sys.argv[9]
s = json.load(open(summ))
th = s["time_history"]
mem = sorted(int(x) for x in mem.split())
out = {
    "case": case, "size": th["equations"], "elements": th["elements"], "ranks": np_,
    "steps": th["steps"] - th["first_step"], "seconds": round(wall, 2), "seconds_per_step": round(th["seconds_per_step"], 4),
    "seconds_stages": {k: round(x, 2) for k, x in s["stages"]["seconds"].items()}, "seconds_gravity": round(th["seconds"]["gravity"], 2),
    "iterations": th["iterations"], "factorizations": th["factorizations"], "substepped_steps": th["substepped_steps"],
    "max_damage": th["max_damage"], "peak_drift_ratio": th["peak_drift_ratio"],
    "system_seconds": {k: round(v, 2) for k, v in th.get("system_seconds", {}).items()},
    "peak_memory_mb_per_rank": mem, "load_average": [float(load0), float(load1)], "blas": blas, "binary": binary,
}
print(json.dumps(out))
PY
}

coarse_job() { # the church job (text on stdin) pointed at the repository's files and $work/out
  sed -e "s#\"../meshes/church.msh\"#\"$root/meshes/church.msh\"#" -e "s#\"../materials/#\"$root/materials/#" -e "s#\"../results/church\"#\"out\"#" \
      -e 's/existing = "backup"/existing = "overwrite"/'
}
if [[ " $cases " == *" coarse "* ]]; then
  coarse_job < jobs/church.toml > "$work/coarse.toml"
  [ -z "$baseline" ] || git show "$BASELINE:jobs/church.toml" | coarse_job > "$work/baseline.toml"
  for np in $ranks; do
    if [ -n "$baseline" ]; then
      load0=$(loadavg)
      measure "$np" "$work/baseline.toml" "$baseline"
      cp "$work/out/summary.json" "$work/baseline-$np.json"
      emit church-coarse-full "$np" "$work/baseline-$np.json" "$load0" "baseline $BASELINE" > "$work/baseline-$np.line"
    fi
    load0=$(loadavg)
    measure "$np" "$work/coarse.toml"
    cp "$work/out/summary.json" "$work/coarse-$np.json"
    cp "$work/run.wall" "$work/coarse-$np.wall"
    emit church-coarse-full "$np" "$work/coarse-$np.json" "$load0" > "$work/coarse-$np.line"
  done
  if [ -f "$work/coarse-1.line" ] && [ -f "$work/coarse-2.line" ]; then
    python3 - "$work/coarse-1.line" "$work/coarse-2.line" <<'PY'
import json, sys
a, b = (json.loads(open(f).read()) for f in sys.argv[1:3])
for line in (a, b):
    line["speedup_vs_1_rank"] = round(a["seconds"] / line["seconds"], 3)
    open(sys.argv[1 if line is a else 2], "w").write(json.dumps(line))
PY
  fi
  for np in $ranks; do
    if [ -f "$work/baseline-$np.line" ]; then
      cat "$work/baseline-$np.line"
      python3 - "$work/baseline-$np.line" "$work/coarse-$np.line" <<'PY'
import json, sys
old, new = (json.loads(open(f).read()) for f in sys.argv[1:3])
new["speedup_vs_baseline"] = round(old["seconds"] / new["seconds"], 3)
new["stepping_speedup_vs_baseline"] = round(old["seconds_per_step"] / new["seconds_per_step"], 3)
print(json.dumps(new))
PY
    else
      cat "$work/coarse-$np.line"
    fi
  done
fi

if [[ " $cases " == *" fine "* ]]; then
  # The fine mesh, no updating (its stages cost eigensolves of 220k DOF), STEPS steps.
  python3 - "$root" "$work" "$steps" <<'PY'
import re, sys
root, work, steps = sys.argv[1], sys.argv[2], int(sys.argv[3])
t = open(f"{root}/jobs/church.toml").read()
t = t.replace('"../meshes/church.msh"', f'"{root}/meshes/church-fine.msh"').replace('"../results/church"', '"out"')
t = t.replace('existing = "backup"', 'existing = "overwrite"').replace('"../materials/', f'"{root}/materials/')
t = re.sub(r"\n\[analysis\.updating\].*?(?=\n\[mesh\])", "\n", t, flags=re.S)
t = re.sub(r"\nmodes = 12\n", "\nmodes = 1\n", t)
t = re.sub(r"\nduration = [0-9.]+", f"\nduration = {steps * 0.02:.2f}", t)
t = re.sub(r"\noutput_every = [0-9]+", "\noutput_every = 1000", t)
open(f"{work}/fine.toml", "w").write(t)
PY
  load0=$(loadavg)
  measure 2 "$work/fine.toml"
  emit church-fine-segment 2 "$work/out/summary.json" "$load0"
fi

if [[ " $cases " == *" fine-full "* ]]; then
  # The cluster scripts' job (jobs/cluster/common.sh): jobs/church.toml on the fine mesh, whole.
  coarse_job < jobs/church.toml | sed -e "s#$root/meshes/church.msh#$root/meshes/church-fine.msh#" > "$work/fine-full.toml"
  grep -q 'church-fine\.msh' "$work/fine-full.toml" || { echo "error: the fine job does not use church-fine.msh" >&2; exit 1; }
  load0=$(loadavg)
  measure 2 "$work/fine-full.toml"
  cp "$work/run.log" "${FINE_LOG:-/dev/null}" 2>/dev/null || true
  emit church-fine-full 2 "$work/out/summary.json" "$load0"
fi
