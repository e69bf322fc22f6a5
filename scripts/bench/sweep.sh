#!/usr/bin/env bash
# Sweep benchmark: members per hour of the church's intensity sweep (jobs/church-sweep.toml,
# shortened) on 2 ranks, as 2 groups of 1 rank against 1 group of 2 ranks, side by side in one
# run. One JSON line per arrangement, then one with the ratio:
#   sweep-church-groups-of-1, sweep-church-group-of-2   members, seconds of the members' phase,
#       members per hour, seconds of the gravity state (modal updating included: done once)
#   sweep-church-throughput   members per hour of groups of 1 over one group of 2
# The sweep: the coarse church, the identified law, the EC8 record set (7 records) on a grid of
# PGA 0.8 and 2.4 m/s^2 (14 members; the job's hunt replaced by the grid), each DURATION s long
# (default 2.5). Every line carries the machine (CPU, BLAS) and
# the load average at its start and end. Run through scripts/bench.sh (which builds first).
set -euo pipefail
cd "$(dirname "$0")/../.."
source scripts/env.sh
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
root=$(pwd)
bin=$root/target/release/masonry-hpc
duration="${DURATION:-2.5}"
loadavg() { cut -d' ' -f1 /proc/loadavg; }
cpu=$(awk -F': ' '/model name/ {print $2; exit}' /proc/cpuinfo)
blas_lib=$(ldd "$bin" 2>/dev/null | awk '/libblas|libopenblas|mkl_core|libblis/ {print $3; exit}')
blas="${blas_lib:+$(readlink -f "$blas_lib")}${OPENBLAS_CORETYPE:+ ($OPENBLAS_CORETYPE)}"

# The records: the committed record-set job, its results in $work/set.
sed -e "s#\"../results/record-set-ec8\"#\"$work/set\"#" jobs/record-set-ec8.toml > "$work/set.toml"
"$bin" -q "$work/set.toml" >/dev/null

for g in 1 2; do
  sed -e "s#^job = \"church.toml\"#job = \"$root/jobs/church.toml\"#" \
      -e "s#^group_size = .*#group_size = $g#" \
      -e "s#^record_set = .*#record_set = \"$work/set\"#" \
      -e "s#^scale_by = \(.*\)#scale_by = \1\nintensities = [0.8, 2.4]#" \
      -e "s#^duration = .*#duration = $duration#" \
      -e '/^\[sweep.hunt\]/,/^$/d' \
      -e '/^materials = /d' \
      -e "s#^dir = .*#dir = \"$work/out-$g\"#" jobs/church-sweep.toml > "$work/sweep-$g.toml"
  load0=$(loadavg)
  OMPI_MCA_mpi_yield_when_idle=1 mpirun -n 2 "$bin" -q "$work/sweep-$g.toml" > "$work/log-$g" 2>&1 \
    || { echo "error: the sweep failed, log:" >&2; tail -20 "$work/log-$g" >&2; exit 1; }
  python3 - "$work/out-$g/summary.json" "$g" "$load0" "$(loadavg)" "$cpu" "$blas" "$duration" > "$work/line-$g" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
t = s["timing"]
g = int(sys.argv[2])
print(json.dumps({
    "case": "sweep-church-groups-of-1" if g == 1 else "sweep-church-group-of-2",
    "ranks": 2, "groups": t["groups"], "group_size": t["group_size"],
    "members": t["members_run"], "completed": s["completed"], "record_seconds": float(sys.argv[7]),
    "seconds_members": round(t["seconds_members"], 2), "members_per_hour": round(t["members_per_hour"], 2),
    "seconds_gravity": round(t["seconds_gravity"], 2),
    "load_average": [float(sys.argv[3]), float(sys.argv[4])], "cpu": sys.argv[5], "blas": sys.argv[6],
}))
PY
  cat "$work/line-$g"
done
python3 - "$work/line-1" "$work/line-2" <<'PY'
import json, sys
a, b = (json.loads(open(f).read()) for f in sys.argv[1:3])
print(json.dumps({"case": "sweep-church-throughput", "groups_of_1_over_group_of_2": round(a["members_per_hour"] / b["members_per_hour"], 3)}))
PY
