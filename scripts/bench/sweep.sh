#!/usr/bin/env bash
# Sweep benchmark: members per hour of the church's intensity sweep (jobs/church-sweep.toml,
# shortened) on 2 ranks, as 2 groups of 1 rank against 1 group of 2 ranks, side by side in one
# run. One JSON line per arrangement, then one with the ratio:
#   sweep-church-groups-of-1, sweep-church-group-of-2   members, seconds of the members' phase,
#       members per hour, seconds of the gravity state (modal updating included: done once)
#   sweep-church-throughput   members per hour of groups of 1 over one group of 2
#   sweep-member-<integration>  one member as the church's sweep runs it: EC8 record 01 whole
#       (MEMBER_SECONDS, default 20 s) at 1.5 times the code level (PGA 2.4 m/s^2), the main
#       job's law, on 1 rank, with `integration = "implicit"` and `"implex"` (INTEGRATIONS; implex
#       with the main job's IMPL-EX settings, its corrections):
#       seconds of the member, Newton iterations, those in failed attempts, factorizations,
#       substepped steps, the system's phases (assemble, factorize, solve, internal_force: s),
#       and the members per hour of 2 such members side by side on 2 cores
#       (2 x 3600 / seconds, the sweep's arrangement)
#   sweep-church-demo         only with DEMO=1: jobs/church-sweep.toml itself on 2 ranks, as
#       committed (hours): its wall-clock time, members, members per hour
# The sweep: the coarse church, the identified law, the EC8 record set (7 records) on a grid of
# PGA 0.8 and 2.4 m/s^2 (14 members; the job's hunt replaced by the grid), each DURATION s long
# (default 2.5). CASES="throughput member" picks the parts (default: both). Every line carries the machine (CPU, BLAS) and
# the load average at its start and end. Run through scripts/bench.sh (which builds first).
set -euo pipefail
cd "$(dirname "$0")/../.."
source scripts/env.sh
work=$(mktemp -d)
trap '[ -n "${KEEP_WORK:-}" ] || rm -rf "$work"' EXIT
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

cases="${CASES:-throughput member}"
for g in $([[ " $cases " == *" throughput "* ]] && echo 1 2); do
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
[[ " $cases " == *" throughput "* ]] && python3 - "$work/line-1" "$work/line-2" <<'PY'
import json, sys
a, b = (json.loads(open(f).read()) for f in sys.argv[1:3])
print(json.dumps({"case": "sweep-church-throughput", "groups_of_1_over_group_of_2": round(a["members_per_hour"] / b["members_per_hour"], 3)}))
PY

# One member as the sweep runs it, per integration: a sweep of one record, one intensity, the
# main job's law (no variants), one group of 1 rank.
member_seconds="${MEMBER_SECONDS:-20}"
for integration in $([[ " $cases " == *" member "* ]] && echo "${INTEGRATIONS:-implicit implex}"); do
  # The implicit step takes none of the IMPL-EX keys the main job may set (its corrections).
  drop_implex=$([ "$integration" = implicit ] && echo '/^implex_/d' || echo '')
  sed -e "s#^integration = .*#integration = \"$integration\"#" ${drop_implex:+-e "$drop_implex"} \
    jobs/church.toml > "$work/base-$integration.toml"
  grep -q "^integration = \"$integration\"" "$work/base-$integration.toml" \
    || sed -i "s#^\[dynamics\]\$#[dynamics]\nintegration = \"$integration\"#" "$work/base-$integration.toml"
  sed -i -e "s#\"\.\./#\"$root/#g" -e "s#\"records/#\"$root/jobs/records/#g" \
      -e "s#\"church-convergence.json\"#\"$root/jobs/church-convergence.json\"#" "$work/base-$integration.toml"
  sed -e "s#^job = \"church.toml\"#job = \"$work/base-$integration.toml\"#" \
      -e "s#^group_size = .*#group_size = 1#" \
      -e "s#^record_set = .*##" \
      -e "s#^scale_by = \(.*\)#scale_by = \1\nintensities = [2.4]#" \
      -e "s#^duration = .*#duration = $member_seconds#" \
      -e '/^\[sweep.hunt\]/,/^$/d' \
      -e '/^materials = /d' \
      -e "s#^dir = .*#dir = \"$work/member-$integration\"#" jobs/church-sweep.toml > "$work/member-$integration.toml"
  python3 - "$work/member-$integration.toml" "$work/set/record-01.txt" <<'PY'
import sys
p, rec = sys.argv[1], sys.argv[2]
s = open(p).read()
if "[[sweep.record]]" not in s:
    i = s.index("[[sweep.limit]]")
    s = s[:i] + f'[[sweep.record]]\nfile = "{rec}"\nformat = "two_column"\nunits = "m/s2"\n\n' + s[i:]
open(p, "w").write(s)
PY
  load0=$(loadavg)
  mpirun -n 1 "$bin" -q "$work/member-$integration.toml" > "$work/log-member-$integration" 2>&1 \
    || { echo "error: the $integration member failed, log:" >&2; tail -20 "$work/log-member-$integration" >&2; exit 1; }
  python3 - "$work/member-$integration" "$integration" "$load0" "$(loadavg)" "$cpu" "$blas" "$member_seconds" <<'PY'
import glob, json, os, sys
out, integration = sys.argv[1], sys.argv[2]
t = json.load(open(os.path.join(out, "summary.json")))["timing"]
(member,) = glob.glob(os.path.join(out, "members", "*", "summary.json"))
s = json.load(open(member))
th = s.get("time_history", s)  # a member writes its time history summary as the whole file
print(json.dumps({
    "case": f"sweep-member-{integration}", "ranks": 1, "record_seconds": float(sys.argv[7]), "pga": 2.4,
    "equations": th["equations"], "steps": th["steps"], "seconds": round(t["seconds_members"], 1),
    "iterations": th["iterations"], "failed_iterations": th.get("failed_iterations", 0),
    "factorizations": th.get("factorizations", 0), "substepped_steps": th.get("substepped_steps", 0),
    "members_per_hour_2_cores": round(2 * 3600 / t["seconds_members"], 2),
    "phases": {k: round(v, 1) for k, v in th.get("system_seconds", {}).items()},
    "load_average": [float(sys.argv[3]), float(sys.argv[4])], "cpu": sys.argv[5], "blas": sys.argv[6],
}))
PY
done

# The demo itself, only when asked for: hours of both cores.
if [ "${DEMO:-0}" = "1" ]; then
  [ -d results/record-set-ec8 ] || "$bin" -q jobs/record-set-ec8.toml >/dev/null
  load0=$(loadavg)
  start=$(date +%s.%N)
  sed -e "s#^dir = .*#dir = \"$work/demo\"#" -e "s#^job = \"church.toml\"#job = \"$root/jobs/church.toml\"#" \
      -e "s#\"\.\./#\"$root/#g" jobs/church-sweep.toml > "$work/demo.toml"
  mpirun -n 2 "$bin" -q "$work/demo.toml" > "$work/log-demo" 2>&1 \
    || { echo "error: the demo failed, log:" >&2; tail -20 "$work/log-demo" >&2; exit 1; }
  python3 - "$work/demo/summary.json" "$start" "$(date +%s.%N)" "$load0" "$(loadavg)" "$cpu" "$blas" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
t = s["timing"]
wall = float(sys.argv[3]) - float(sys.argv[2])
print(json.dumps({
    "case": "sweep-church-demo", "ranks": 2, "seconds": round(wall, 1), "members": s["members"],
    "completed": s["completed"], "members_per_hour": round(t["members_per_hour"], 2),
    "load_average": [float(sys.argv[4]), float(sys.argv[5])], "cpu": sys.argv[6], "blas": sys.argv[7],
}))
PY
fi
