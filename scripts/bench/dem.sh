#!/usr/bin/env bash
# DEM benchmark, one JSON line per case. Run through scripts/bench.sh (which builds first).
#  (a) 32 tension tests of the paper's wall as one batch on 2 ranks (the paper: about 2 hours
#      for 32): seconds and the ratio paper/ours (target: under 10 s);
#  (b) compression of random samples of 1k, 10k and 50k stones on one core to the maximum
#      strain (the paper's model has no compressive peak for random samples; see below):
#      seconds, events, events per second, peak memory (VmHWM), how the test ended, the solver's
#      profile (examples/dem_profile.rs), or how far it got when the time limit stopped it;
#      beside it one sparse factorization of the same operator alone
#      (examples/dem_factorization.rs), and the cost of an event in factorizations (target: 10k
#      under 300 CPU-s, the goal 60; the cost per event growing no faster than a factorization);
#  (t) tension of random samples of 10k and 50k stones on one core to loss of load (past the
#      peak: the sample splits), the same fields as (b); from 50k stones with the residual
#      tolerance 1e-7 (DEM_TOL): at 1e-8 the 50k run stalls near break 500 on the chatter of
#      loose stones in the open crack (src/dem/solver/equilibrium.rs, module docs);
#  (c) the scaling: log-log slopes of seconds per event and of the factorization against size;
#  (r) before (b): the 1k sample against its stored reference run (below);
#  (m) before (b): several breaks per equilibrium (an opt-in approximation) against the exact path;
#  (k) before (b): the contact-free phase at 10k stones against its bound (issue 25);
#  (u) before (b): the factor's Woodbury path against its updates in place, side by side;
#  (s) before (b): the preconditioner's tangential terms of sliding contacts, side by side.
# Every line carries the load average and `uptime` (the machine may be shared) and, for (b), the
# CPU seconds of the run beside its wall seconds (on a loaded machine the CPU time is the cost),
# and the peak memory twice: the maximum RSS from /usr/bin/time, VmHWM from the run itself.
#
# Fields common to (a) and (b): case, size, seconds (wall), cpu_seconds (user + sys of the
# process and its children, /usr/bin/time), events, events_per_second (over the wall seconds of
# the test itself), peak_rss_mb (largest resident set of one process); (a) adds
# ratio_paper_over_ours, (b) factorization_seconds and event_cost_in_factorizations (the CPU
# cost of an event over one numeric factorization of the same operator, measured alone), and
# `capped_events` when a size is run for a fixed number of events only.
#
# Environment: BIN (default target/release/masonry-hpc; target/debug works, its dependencies,
# faer included, are optimized), DEM_BENCH_SIZES (default "1000 10000 50000:300", empty: none; a size, or
# size:N to stop after N beam breaks, reported as "capped_events": N; the full 50k run is
# projected at well over an hour on one core), DEM_BENCH_TIMEOUT (seconds per case of (b),
# default 3600), DEM_BENCH_TENSION_SIZES (default "10000 50000", empty: none) the sizes of (t),
# DEM_BENCH_SKIP_BATCH=1 skips (a). The DEM_* switches of examples/dem_profile.rs
# pass through to (b) and (r): DEM_UPDOWN=0 keeps the factor by Woodbury columns and
# refactorizations, DEM_UPDOWN=1 by CHOLMOD's updates in place (unset: the solver's default, in
# place for every sample here: from 1,000 unknowns).
set -euo pipefail
cd "$(dirname "$0")/../.."
source scripts/env.sh
BIN=${BIN:-target/release/masonry-hpc}
profile=$(basename "$(dirname "$BIN")")
FACTOR_BIN="$(dirname "$BIN")/examples/dem_factorization"
PROFILE_BIN="$(dirname "$BIN")/examples/dem_profile"
if [ "$profile" = release ]; then cargo build --release --quiet --example dem_factorization --example dem_profile >&2
else cargo build --quiet --example dem_factorization --example dem_profile >&2; fi
SIZES=${DEM_BENCH_SIZES-"1000 10000 50000:300"}
TENSION_SIZES=${DEM_BENCH_TENSION_SIZES-"10000 50000"}
TIMEOUT=${DEM_BENCH_TIMEOUT:-3600}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
load() { cut -d' ' -f1-3 /proc/loadavg; }

if [ "${DEM_BENCH_SKIP_BATCH:-0}" != 1 ]; then
  sed -e 's/^samples = 16/samples = 32/' -e "s#\"../results/wall-tension\"#\"$work/dem-out\"#" \
      -e 's/^existing = .*//' jobs/wall-tension.toml > "$work/tension32.toml"
  sed -i 's/^type = "dem"/type = "dem"\nparticle_states = "none"/' "$work/tension32.toml"
  l0=$(load)
  u0=$(uptime)
  start=$(date +%s.%N)
  /usr/bin/time -o "$work/a.time" -f "rss_kb=%M cpu_user=%U cpu_sys=%S" \
    mpirun -n 2 "$BIN" -q "$work/tension32.toml" >/dev/null 2>&1 || true
  end=$(date +%s.%N)
  python3 - "$work/dem-out/summary.json" "$start" "$end" "$l0" "$BIN" "$u0" "$(cat "$work/a.time")" <<'PY'
import json, re, sys
s = json.load(open(sys.argv[1])); wall = float(sys.argv[3]) - float(sys.argv[2])
ok = sum(1 for x in s["samples"] if "Ok" in x["result"])
events = sum(x.get("events", 0) for x in s["samples"])
t = sys.argv[7]
rss = re.search(r"rss_kb=(\d+)", t)
cpu = re.search(r"cpu_user=(\S+) cpu_sys=(\S+)", t)
print(json.dumps({"case": "dem-paper-wall-tension-batch", "size": 32, "ranks": 2, "seconds": round(wall, 3),
                  "cpu_seconds": round(float(cpu.group(1)) + float(cpu.group(2)), 2) if cpu else None,
                  "events": events, "events_per_second": round(s["events_per_second"], 1),
                  "peak_rss_mb": round(int(rss.group(1)) / 1024, 1) if rss else None,
                  "samples_completed": ok, "paper_seconds": 7200, "ratio_paper_over_ours": round(7200 / wall, 1),
                  "target_seconds": 10, "meets_target": wall < 10, "load_average": sys.argv[4],
                  "uptime": sys.argv[6].strip(), "binary": sys.argv[5]}))
PY
fi

# (r) the regression check: the 1k sample's run (with and without contacts) against the reference
#     recorded before the linear phase (tests/data/dem-random-1k): the same breaks in the same
#     order, the stresses at the regular load points within 1e-8 of the peak
#     (scripts/bench/dem_compare.py). One JSON line
#     each; DEM_BENCH_SKIP_REFERENCE=1 skips it.
if [ "${DEM_BENCH_SKIP_REFERENCE:-0}" != 1 ]; then
  ref=tests/data/dem-random-1k
  for variant in "" "-no-contacts"; do
    contacts=1
    [ -n "$variant" ] && contacts=0
    DEM_CONTACTS=$contacts DEM_BROKEN_CSV="$work/broken$variant.csv" "$PROFILE_BIN" 1000 2e-3 40 "$work/curve$variant.csv" \
      > /dev/null 2>&1 || true
    python3 scripts/bench/dem_compare.py "$ref/curve$variant.csv" "$ref/broken$variant.csv" \
      "$work/curve$variant.csv" "$work/broken$variant.csv" \
      | sed "s/^{/{\"case\": \"dem-reference-1k$variant\", /" || true
  done
fi

# (k) the contact-free phase at 10k stones (the lattice alone, DEM_CONTACTS=0; updates in place):
#     1,500 breaks with the sparse right-hand sides of contact-free steps (the default) and
#     without, side by side; the cost per break against issue 25's bound, twice one dense solve
#     plus one failure scan, both measured in the dense run (its solve seconds per solve, its
#     scan seconds per scan). DEM_BENCH_SKIP_CONTACT_FREE=1 skips it.
if [ "${DEM_BENCH_SKIP_CONTACT_FREE:-0}" != 1 ]; then
  for sp in 1 0; do
    DEM_CONTACTS=0 DEM_UPDOWN=1 DEM_SPARSE_RHS=$sp DEM_MAX_EVENTS=1500 "$PROFILE_BIN" 10000 2e-3 40 \
      > "$work/contact-free-$sp.json" 2>/dev/null || true
  done
  python3 - "$work/contact-free-1.json" "$work/contact-free-0.json" "$(load)" <<'PY' || true
import json, sys
sparse, dense = (json.load(open(p)) for p in sys.argv[1:3])
ms = lambda r: 1000 * r["seconds"] / r["events"]
p = dense["profile"]
solve = 1000 * p["solve_seconds"] / max(dense["solves"], 1)
scan = 1000 * p["failure_seconds"] / max(p["failure_scans"], 1)
bound = 2 * (solve + scan)
ps = sparse["profile"]
print(json.dumps({"case": "dem-contact-free-10k", "size": 10000, "ranks": 1, "events": sparse["events"],
                  "ms_per_break": round(ms(sparse), 2), "ms_per_break_dense_solves": round(ms(dense), 2),
                  "solves_per_break": round(sparse["solves"] / sparse["events"], 3),
                  "sparse_solves": ps["sparse_solves"],
                  "forward_columns_fraction": round(ps["sparse_columns"] / max(ps["sparse_solves"], 1) / sparse["equations"], 3),
                  "dense_solve_ms": round(solve, 2), "failure_scan_ms": round(scan, 2), "bound_ms": round(bound, 2),
                  "meets_bound": ms(sparse) <= bound, "same_peak_rel": abs(sparse["peak_stress_pa"] / dense["peak_stress_pa"] - 1),
                  "load_average": sys.argv[3]}))
PY
fi

# (u) the factor's two update paths side by side (`[analysis] factor_updates`, default "auto":
#     in place from 1,000 unknowns): Woodbury columns with refactorizations against CHOLMOD's
#     updates in place, on the 1k sample in compression to 2e-3 and the 10k sample in tension to
#     loss of load; seconds, peak memory (VmHWM), and the peaks' relative difference (the same
#     breaks either way). DEM_BENCH_SKIP_UPDATES=1 skips it.
if [ "${DEM_BENCH_SKIP_UPDATES:-0}" != 1 ]; then
  for spec in 1000:2e-3 10000:-2e-3; do
    n=${spec%%:*}; strain=${spec#*:}
    for u in 0 1; do
      DEM_UPDOWN=$u "$PROFILE_BIN" "$n" "$strain" 40 > "$work/updates-$n-$u.json" 2>/dev/null || true
    done
    python3 - "$work/updates-$n-0.json" "$work/updates-$n-1.json" "$n" "$(load)" <<'PY' || true
import json, sys
w, u = (json.load(open(p)) for p in sys.argv[1:3])
print(json.dumps({"case": "dem-factor-updates", "size": int(sys.argv[3]), "ranks": 1,
                  "test": "tension" if "loss" in u["end"] else "compression", "events": [w["events"], u["events"]],
                  "seconds_woodbury": round(w["seconds"], 2), "seconds_in_place": round(u["seconds"], 2),
                  "ratio_woodbury_over_in_place": round(w["seconds"] / u["seconds"], 2),
                  "vm_hwm_mb": [round(w["vm_hwm_kb"] / 1024), round(u["vm_hwm_kb"] / 1024)],
                  "peak_rel_difference": abs(u["peak_stress_pa"] / w["peak_stress_pa"] - 1),
                  "load_average": sys.argv[4]}))
PY
  done
fi

# (s) the preconditioner's tangential terms (`SolverOptions::slip_terms`,
#     src/dem/solver/slip_terms.rs): every contact keeps k_t c cᵀ (the default, DEM_SLIP_TERMS=1)
#     against sliding contacts keeping 1 % of it, each flip an update or downdate of the factor
#     at once (0.01:0) or after 2 more Newton iterations (0.01:2), on the 1k sample in
#     compression to 2e-3: Newton iterations, GMRES iterations per Newton step, flips, the
#     seconds of preconditioner solves and of factor updates, and the peaks' relative difference.
#     DEM_BENCH_SKIP_SLIP=1 skips it.
if [ "${DEM_BENCH_SKIP_SLIP:-0}" != 1 ]; then
  for st in 1 0.01:0 0.01:2; do
    DEM_SLIP_TERMS=$st "$PROFILE_BIN" 1000 2e-3 40 > "$work/slip-$st.json" 2>/dev/null || true
  done
  python3 - "$work"/slip-{1,0.01:0,0.01:2}.json "$(load)" <<'PY' || true
import json, sys
runs = [json.load(open(p)) for p in sys.argv[1:4]]
full = runs[0]
for r in runs:
    p = r["profile"]
    print(json.dumps({"case": "dem-slip-terms-1k", "settings": r["settings"].split(" forcing")[0], "events": r["events"],
                      "seconds": round(r["seconds"], 2), "newton_iterations": p["newton_iterations"],
                      "gmres_per_newton_step": round(p["gmres_iterations"] / max(p["gmres_solves"], 1), 2),
                      "slip_flips": p["slip_flips"], "solve_seconds": round(p["solve_seconds"], 2),
                      "columns_seconds": round(p["columns_seconds"], 2),
                      "peak_rel_difference": abs(r["peak_stress_pa"] / full["peak_stress_pa"] - 1),
                      "load_average": sys.argv[4]}))
PY
fi

# (m) the opt-in approximation, several breaks per equilibrium (`[analysis]
#     breaks_per_equilibrium`), against the exact path: the 1k sample (dem_profile, DEM_BREAKS=4
#     and 16) and the paper's wall jobs (compression, tension, shear; n = 16, 2 ranks): peak,
#     strain at the peak, dissipated energy, means over the samples and the worst sample
#     (scripts/bench/dem_breaks_compare.py; fit: peak within 2 %, dissipated within 5 %).
#     About 4 minutes; DEM_BENCH_SKIP_APPROX=1 skips it, DEM_BENCH_APPROX_TESTS picks the wall
#     jobs (default "compression tension shear").
if [ "${DEM_BENCH_SKIP_APPROX:-0}" != 1 ]; then
  for nb in 1 4 16; do
    DEM_BREAKS=$nb "$PROFILE_BIN" 1000 2e-3 40 > "$work/approx-1k-$nb.json" 2>/dev/null || true
  done
  python3 - "$work"/approx-1k-{1,4,16}.json <<'PY' || true
import json, sys
runs = [json.load(open(p)) for p in sys.argv[1:]]
ex = runs[0]
rel = lambda a, b: (b - a) / abs(a)
for r in runs[1:]:
    pk = rel(ex["peak_stress_pa"], r["peak_stress_pa"])
    dj = rel(ex["dissipated_total_j"], r["dissipated_total_j"])
    print(json.dumps({"case": "dem-breaks-per-equilibrium-1k", "breaks_per_equilibrium": r["breaks_per_equilibrium"],
                      "events_exact": ex["events"], "events_approx": r["events"],
                      "seconds_exact": round(ex["seconds"], 2), "seconds_approx": round(r["seconds"], 2),
                      "peak_rel_diff": round(pk, 6),
                      "strain_at_peak_rel_diff": round(rel(ex["strain_at_peak"], r["strain_at_peak"]), 6),
                      "dissipated_rel_diff": round(dj, 6), "fit": abs(pk) <= 0.02 and abs(dj) <= 0.05}))
PY
  for t in ${DEM_BENCH_APPROX_TESTS-compression tension shear}; do
    for nb in 1 16; do
      sed -e "s#\"../results/wall-$t\"#\"$work/approx-$t-$nb\"#" -e 's/^existing = .*//' \
          -e "s/^type = \"dem\"/type = \"dem\"\nbreaks_per_equilibrium = $nb\nparticle_states = \"none\"/" jobs/wall-$t.toml > "$work/approx-$t-$nb.toml"
      mpirun -n 2 "$BIN" -q "$work/approx-$t-$nb.toml" > /dev/null 2>&1 || true
    done
    python3 scripts/bench/dem_breaks_compare.py "dem-breaks-per-equilibrium-wall-$t" \
      "$work/approx-$t-1" "$work/approx-$t-16" || true
  done
fi

lines="$work/b.jsonl"
: > "$lines"
for item in $(for s in $SIZES; do echo "compression:$s"; done; for s in $TENSION_SIZES; do echo "tension:$s"; done); do
  test=${item%%:*}
  spec=${item#*:}
  n=${spec%%:*}
  cap=""
  [ "$spec" != "$n" ] && cap=${spec#*:}
  # The same test as a job file `[test] type = "compression", max_strain = 2e-3, steps = 40` on
  # `layout = { type = "random", n_particles = N }` (seed 7), run by examples/dem_profile.rs so
  # the line carries the solver's profile and, when the time limit stops it, how far it got.
  # The paper's model has no compressive peak for random samples (no crushing): "post-peak" here
  # means the configured maximum strain, 2e-3, far past the first cracks (about 0.2e-3).
  # The tension test (`max_strain = 4e-4`, dem_profile's negative strain) has a peak: the
  # sample splits, and the run ends on loss of load (below 5 % of the peak) well before 4e-4.
  strain=2e-3
  [ "$test" = tension ] && strain=-4e-4
  tolenv=()
  if [ "$test" = tension ] && [ "$n" -ge 50000 ]; then tolenv=(DEM_TOL=1e-7); fi
  fact=$("$FACTOR_BIN" "$n")
  l0=$(load)
  u0=$(uptime)
  t0=$(date +%s.%N)
  out=$( { env "${tolenv[@]}" DEM_MAX_EVENTS=${cap:-1000000} /usr/bin/time -f "rss_kb=%M cpu_user=%U cpu_sys=%S" timeout "$TIMEOUT" "$PROFILE_BIN" "$n" $strain 40 > "$work/profile-$test-$n.json" 2> "$work/profile-$test-$n.err"; } 2>&1 || true )
  t1=$(date +%s.%N)
  l1=$(load)
  u1=$(uptime)
  python3 - "$work/profile-$test-$n.json" "$n" "$t0" "$t1" "$(cat "$work/profile-$test-$n.err") $out" "$fact" "$l0" "$TIMEOUT" "$PROFILE_BIN" "$l1" "$u0" "$u1" "$cap" "$test" <<'PY' | tee -a "$lines"
import json, os, re, sys
n, wall, out = int(sys.argv[2]), float(sys.argv[4]) - float(sys.argv[3]), sys.argv[5]
fact = json.loads(sys.argv[6])
rss = re.search(r"rss_kb=(\d+)", out)
cpu = re.search(r"cpu_user=(\S+) cpu_sys=(\S+)", out)
line = {"case": f"dem-random-{sys.argv[14]}", "size": n, "ranks": 1, "seconds": round(wall, 3),
        "cpu_seconds": round(float(cpu.group(1)) + float(cpu.group(2)), 2) if cpu else None,
        "peak_rss_mb": round(int(rss.group(1)) / 1024, 1) if rss else None,
        "equations": fact["equations"], "factorization_seconds": fact["numeric_factorization_seconds"],
        "factorization_cpu_seconds": fact["numeric_factorization_cpu_seconds"],
        "first_factorization_seconds": fact["first_factorization_seconds"], "solve_seconds": fact["solve_seconds"],
        "load_average_start": sys.argv[7], "load_average_end": sys.argv[10],
        "uptime_start": sys.argv[11].strip(), "uptime_end": sys.argv[12].strip(), "binary": sys.argv[9]}
cap = int(sys.argv[13]) if sys.argv[13] else None
if cap:
    line["capped_events"] = cap
text = open(sys.argv[1]).read().strip() if os.path.exists(sys.argv[1]) else ""
if text:
    r = json.loads(text)
    ev, sec = r["events"], max(r["seconds"], 1e-9)
    capped = cap is not None and ev > cap
    line.update({"completed": not r["end"].startswith("stopped") or capped, "end": "capped" if capped else r["end"],
                 "events": ev, "test_seconds": round(sec, 3),
                 "events_per_second": round(ev / sec, 2), "peak_stress_mpa": round(r["peak_stress_pa"] / 1e6, 4),
                 "young_modulus_gpa": round(r["e_pa"] / 1e9, 4), "settings": r.get("settings"),
                 "profile": r["profile"]})
    if r.get("vm_hwm_kb"):
        line["vm_hwm_mb"] = round(r["vm_hwm_kb"] / 1024, 1)
    if ev > 0:
        line["seconds_per_event"] = sec / ev
        # CPU seconds per event (the machine may be shared: wall seconds overstate the cost)
        # over the numeric factorization, both on one core.
        per = (line["cpu_seconds"] if line["cpu_seconds"] else sec) / ev
        line["cpu_seconds_per_event"] = per
        line["event_cost_in_factorizations"] = round(per / max(fact["numeric_factorization_cpu_seconds"], 1e-9), 3)
    if n == 10000 and not capped and sys.argv[14] == "compression":
        line.update({"target_cpu_seconds": 300, "goal_cpu_seconds": 60,
                     "meets_target": bool(line["cpu_seconds"] and line["cpu_seconds"] < 300)})
else:
    prog = re.findall(r"progress: state (\d+) strain (\S+) events (\d+) seconds (\S+)", out)
    line.update({"completed": False, "timed_out": wall >= float(sys.argv[8]) - 1})
    if prog:
        st, strain, ev, sec = prog[-1]
        line.update({"reached_strain": float(strain), "events": int(ev), "test_seconds": float(sec),
                     "events_per_second": round(int(ev) / max(float(sec), 1e-9), 2)})
        if int(ev) > 0:
            line["seconds_per_event"] = float(sec) / int(ev)
            line["event_cost_in_factorizations_wall"] = round(float(sec) / int(ev) / max(fact["numeric_factorization_seconds"], 1e-9), 3)
    err = re.search(r"(error|stopped): (.*)", out)
    if err:
        line["error"] = err.group(2)[:200]
# (events, wall seconds of the test) at every progress line: the scaling compares sizes over the
# same number of events (the first events of a run are cheaper than the late ones).
line["progress_events_seconds"] = [[int(e), float(t)] for _, _, e, t in
                                   re.findall(r"progress: state (\d+) strain (\S+) events (\d+) seconds (\S+)", out)]
print(json.dumps(line))
PY
done
python3 - "$lines" <<'PY'
import json, math, sys
rows = [json.loads(l) for l in open(sys.argv[1]) if l.strip()]
rows = [r for r in rows if r["case"] == "dem-random-compression" and r.get("events") and r.get("cpu_seconds")
        and r.get("progress_events_seconds")]
# CPU seconds to reach the first N events, N the fewest events any size reached: the wall seconds
# at N (interpolated between progress lines) times the run's CPU/wall ratio.
def cpu_at(r, n):
    pts = [(0, 0.0)] + [tuple(p) for p in r["progress_events_seconds"]]
    for (e0, t0), (e1, t1) in zip(pts, pts[1:]):
        if e1 >= n:
            t = t0 + (t1 - t0) * (n - e0) / max(e1 - e0, 1)
            return t * r["cpu_seconds"] / max(r["seconds"], 1e-9)
    return None
if len(rows) > 1:
    n = min(max(p[0] for p in r["progress_events_seconds"]) for r in rows)
    pts = [(r, cpu_at(r, n)) for r in rows]
    for (a, ca), (b, cb) in zip(pts, pts[1:]):
        if not (ca and cb):
            continue
        k = math.log(b["equations"] / a["equations"])
        print(json.dumps({"case": "dem-cost-scaling", "size": f"{a['size']}->{b['size']}", "events_compared": n,
                          "cpu_seconds_first_events": [round(ca, 2), round(cb, 2)],
                          "slope_cpu_seconds_per_event": round(math.log(cb / ca) / k, 2),
                          "slope_factorization": round(math.log(b["factorization_cpu_seconds"] / a["factorization_cpu_seconds"]) / k, 2),
                          "note": "log-log slopes against the number of equations over the first events_compared events (setup included); the event cost should not grow faster than the factorization"}))
PY
