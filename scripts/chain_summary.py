#!/usr/bin/env python3
"""The chain's one summary: each stage's numbers side by side (scripts/chain.sh calls it).

    python3 scripts/chain_summary.py [--identify results/identify-wall] [--church results/church]
                                     [--material materials/rubble-identified.toml]
                                     [--timings results/chain/timings.json]
                                     [--church-log results/chain/church.log]
                                     [--comparison results/church-comparison-assumed] [--out results/chain]

Writes <out>/summary.md and <out>/summary.json:
  1. calibration against Table 1   <identify>/calibration.json: target, DEM mean +- std (n), error
  2. the identified law            <identify>/summary.json: parameters, the law's peaks against the
                                   DEM's (mean curves and samples), the fit's errors
  3. frequencies                   <church>/stages.json: modes as given, the updating's targets,
                                   the moduli it changed, modes of the updated model
  4. gravity                       <church>/summary.json (its gravity entry, when it has one), else
                                   the church log's gravity lines: load factor reached, iterations
  5. damage per substructure       <church>/pictures/damage-by-substructure.csv, after gravity
                                   and at the end of the record
  6. the assumed law beside it    <comparison>/comparison.csv (scripts/compare_laws.sh), if run
  7. wall times                    <timings> (written by chain.sh)
A missing input is reported in its section ("not available: ...") rather than stopping the
summary: the chain reports how far it got. Standard library only.
"""
import argparse
import csv
import json
import math
import os
import re
import sys


def load_json(path):
    try:
        with open(path) as f:
            return json.load(f), None
    except FileNotFoundError:
        return None, f"not available: {path} (stage not run or failed)"
    except (OSError, json.JSONDecodeError) as e:
        return None, f"not readable: {path}: {e}"


def fmt(x, digits=4):
    """A number with `digits` significant digits (None and NaN as '-')."""
    if x is None or (isinstance(x, float) and math.isnan(x)):
        return "-"
    if isinstance(x, bool):
        return "yes" if x else "no"
    if isinstance(x, int):
        return str(x)
    if x == 0:
        return "0"
    a = abs(x)
    if 1e-3 <= a < 1e5:
        return f"{x:.{digits}g}"
    return f"{x:.{digits - 1}e}"


def pct(x):
    return "-" if x is None else f"{100.0 * x:+.2f} %"


def table(header, rows):
    out = ["| " + " | ".join(header) + " |", "|" + "|".join("---" for _ in header) + "|"]
    for r in rows:
        out.append("| " + " | ".join(str(c) for c in r) + " |")
    return "\n".join(out)


# ---------------------------------------------------------------------------------------------
# 1-2. identification

QUANTITIES = [("young_modulus", "E", 1e9, "GPa"), ("poisson", "nu", 1.0, ""),
              ("first_crack_stress", "first crack", 1e6, "MPa"), ("peak_stress", "peak", 1e6, "MPa")]


def calibration_section(ident_dir):
    cal, err = load_json(os.path.join(ident_dir, "calibration.json"))
    if cal is None:
        return {"error": err}, f"_{err}_"
    t = cal["targets"]
    rows, data = [], {}
    for k, (key, name, scale, unit) in enumerate(QUANTITIES):
        st = cal["stats"][key]
        e = cal["relative_errors"][key]
        data[key] = {"target": t[key], "mean": st["mean"], "std": st["std"], "n": st["n"], "relative_error": e}
        u = f" {unit}" if unit else ""
        rows.append([name, f"{fmt(t[key] / scale)}{u}", f"{fmt(st['mean'] / scale)} ± {fmt(st['std'] / scale, 2)}{u} ({st['n']})", pct(e)])
    p = cal["parameters"]
    params = ", ".join(f"{k} = {fmt(v)}" for k, v in p.items() if v is not None)
    md = table(["quantity (Table 1)", "target", "calibrated DEM: mean ± std (n)", "error"], rows)
    md += f"\n\nCalibrated DEM ({cal.get('strategy', '?')}): {params}; objective J = {fmt(cal.get('objective'))} after {cal.get('evaluations', '?')} evaluations."
    return {"quantities": data, "parameters": p, "objective": cal.get("objective")}, md


def law_section(ident_dir, material):
    s, err = load_json(os.path.join(ident_dir, "summary.json"))
    if s is None or not s.get("law"):
        e = err or f"no law in {ident_dir}/summary.json"
        return {"error": e}, f"_{e}_", s
    law = s["law"]
    p = law["params"]
    md = []
    names = [("E", "E [Pa]"), ("nu", "nu"), ("eps0_t", "eps0_t"), ("eps0_c", "eps0_c"), ("gf_t", "G_f [J/m²]"),
             ("a_c", "A_c"), ("b_c", "B_c"), ("gf_c", "G_c [J/m²]")]
    rows = [[label, fmt(p[k], 5)] for k, label in names if p.get(k) is not None]
    reg = p.get("regularization")
    rows.append(["regularization", reg if isinstance(reg, str) else json.dumps(reg)])
    if "softening_energy" in law:
        rows.append(["softening energy f_t h/B_t [J/m²]", fmt(law["softening_energy"], 4)])
    e, et = p.get("E"), p.get("eps0_t")
    if e and et:
        rows.append(["f_t = E eps0_t [MPa]", fmt(e * et / 1e6)])
    md.append(table(["parameter", "value"], rows))
    if material:
        md.append(f"\nMaterial file: `{material}`" + (" (present)" if os.path.exists(material) else " (missing)"))
    peaks = []
    sp = law.get("dem_sample_peaks") or {}
    for side, err_key in [("tension", "tension_peak_error"), ("compression", "compression_peak_error")]:
        samples = sp.get(side)
        sm = f"{fmt(samples['mean'] / 1e6)} ± {fmt(samples['std'] / 1e6, 2)} ({samples['n']})" if samples else "-"
        peaks.append([side, fmt(law["dem_peaks"][side] / 1e6), sm, fmt(law["law_peaks"][side] / 1e6), pct(law[err_key])])
    md.append("\n" + table(["peak [MPa]", "DEM mean curve", "DEM samples: mean ± std (n)", "law", "law vs DEM"], peaks))
    meas = []
    for m in law.get("measures", []):
        v = lambda e: fmt(e["value"]) if e else "-"
        meas.append([m["measure"], v(m.get("tension")), v(m.get("compression"))])
    if meas:
        md.append("\n" + table(["error measure at the law", "tension", "compression"], meas))
    data = {"params": p, "dem_peaks": law["dem_peaks"], "law_peaks": law["law_peaks"],
            "peak_errors": {"tension": law["tension_peak_error"], "compression": law["compression_peak_error"]},
            "dem_sample_peaks": law.get("dem_sample_peaks"), "measures": law.get("measures"),
            "softening_energy": law.get("softening_energy"), "material_file": material,
            "seconds": s.get("seconds")}
    return data, "\n".join(md), s


# ---------------------------------------------------------------------------------------------
# 3. frequencies

def modes_of(modal):
    if not isinstance(modal, dict):
        return []
    return [(m.get("mode"), m.get("frequency")) for m in modal.get("modes", [])]


def frequency_section(church_dir):
    st, err = load_json(os.path.join(church_dir, "stages.json"))
    if st is None:
        return {"error": err}, f"_{err}_"
    before = dict(modes_of(st.get("modal")))
    after = dict(modes_of(st.get("modal_updated")))
    targets = {}
    upd = st.get("updating")
    if isinstance(upd, dict):
        for t in upd.get("targets", []):
            targets[t["mode"]] = t
    rows = []
    for mode in sorted(set(before) | set(after)):
        t = targets.get(mode)
        rows.append([mode, fmt(before.get(mode), 5), fmt(t["target"], 5) if t else "", fmt(after.get(mode), 5),
                     f"{fmt(t['mac'])} (mode {t['paired_mode']})" if t else ""])
    md = [table(["mode", "as given [Hz]", "target [Hz]", "updated [Hz]", "MAC (paired)"], rows)]
    mods = []
    for m in st.get("moduli", []):
        if m.get("factor", 1.0) != 1.0:
            ft = m.get("f_t")
            mods.append([m["group"], fmt(m["factor"]), fmt(m["e_before"] / 1e9), fmt(m["e_after"] / 1e9),
                         f"{fmt(ft['before'] / 1e6)} → {fmt(ft['after'] / 1e6)}" if ft else "-"])
    if mods:
        md.append("\n" + table(["updated group", "factor on E", "E before [GPa]", "E after [GPa]", "f_t [MPa]"], mods))
    if isinstance(upd, dict):
        rms = lambda x: "-" if x is None else f"{100.0 * x:.2f} %"
        md.append(f"\nUpdating: RMS frequency error {rms(upd.get('rms_error_before'))} → {rms(upd.get('rms_error_after'))}, "
                  f"{upd.get('iterations')} iteration(s), converged: {fmt(upd.get('converged'))}.")
    data = {"as_given": before, "updated": after, "targets": list(targets.values()),
            "moduli": st.get("moduli"), "updating": {k: upd.get(k) for k in ("rms_error_before", "rms_error_after", "iterations", "converged")} if isinstance(upd, dict) else None}
    return data, "\n".join(md)


# ---------------------------------------------------------------------------------------------
# 4. gravity

def find_key(obj, key):
    """The first value under `key` anywhere in a JSON tree."""
    if isinstance(obj, dict):
        if key in obj:
            return obj[key]
        for v in obj.values():
            r = find_key(v, key)
            if r is not None:
                return r
    elif isinstance(obj, list):
        for v in obj:
            r = find_key(v, key)
            if r is not None:
                return r
    return None


GRAVITY_STEP = re.compile(r"gravity: λ = ([0-9.eE+-]+), (\d+) iteration")
GRAVITY_FAILED = re.compile(r"gravity: step towards λ = [0-9.eE+-]+ failed after (\d+) iteration")
GRAVITY_STOP = re.compile(r"(?:stopped at|At the last equilibrium,) λ = ([0-9.eE+-]+)")


def gravity_section(church_dir, log):
    s, err = load_json(os.path.join(church_dir, "summary.json"))
    data = {"source": None}
    g = find_key(s, "gravity") if s is not None else None
    if isinstance(g, dict):
        data.update(g)
        data["source"] = "summary.json"
    lines = []
    if log and os.path.exists(log):
        with open(log, errors="replace") as f:
            lines = f.readlines()
    steps = [(float(m.group(1)), int(m.group(2))) for m in (GRAVITY_STEP.search(l) for l in lines) if m]
    stops = [float(m.group(1)) for m in (GRAVITY_STOP.search(l) for l in lines) if m]
    failed = [int(m.group(1)) for m in (GRAVITY_FAILED.search(l) for l in lines) if m]
    if steps or stops:
        data["log"] = {"load_factor": stops[-1] if stops else steps[-1][0],
                       "iterations": sum(n for _, n in steps) + sum(failed), "increments": len(steps),
                       "failed_attempts": len(failed),
                       "carried": not stops and bool(steps) and abs(steps[-1][0] - 1.0) < 1e-9}
        data["source"] = data["source"] or "church log"
    if data["source"] is None:
        return {"error": err or "no gravity entry"}, f"_not available: no gravity entry in {church_dir}/summary.json and no gravity lines in {log}_"
    rows = []
    if data["source"] == "summary.json":
        for k, v in g.items():
            if not isinstance(v, (dict, list)):
                rows.append([k, fmt(v) if isinstance(v, (int, float)) else v])
    if "log" in data:
        lg = data["log"]
        rows.append(["load factor reached (log)", fmt(lg["load_factor"], 6)])
        rows.append(["Newton iterations, failed attempts included (log)", lg["iterations"]])
        rows.append(["load increments accepted, attempts cut back (log)", f"{lg['increments']}, {lg['failed_attempts']}"])
        rows.append(["full self-weight carried", "yes" if lg["carried"] else "NO"])
    return data, table(["gravity", "value"], rows)


# ---------------------------------------------------------------------------------------------
# 5. damage

def damage_section(church_dir):
    f = os.path.join(church_dir, "pictures", "damage-by-substructure.csv")
    try:
        with open(f, newline="") as fh:
            rows = list(csv.reader(fh))
    except FileNotFoundError:
        return {"error": f"not available: {f}"}, f"_not available: {f} (post_church.sh needs ParaView)_"
    if not rows:
        return {"error": f"empty: {f}"}, f"_empty: {f}_"
    header, body = rows[0], rows[1:]
    data = [dict(zip(header, r)) for r in body]
    return data, table(header, body)


def comparison_section(folder):
    """The identified and the assumed law's damage side by side (compare_laws.sh), when run."""
    f = os.path.join(folder, "comparison.csv")
    if not os.path.isfile(f):
        return None, ""
    with open(f, newline="") as fh:
        rows = list(csv.reader(fh))
    if not rows:
        return None, ""
    header, body = rows[0], rows[1:]
    picture = os.path.join(folder, "damage-side-by-side.png")
    md = table(header, body) + (f"\n\nPicture: `{picture}`" if os.path.isfile(picture) else "")
    return [dict(zip(header, r)) for r in body], md


def time_history_line(church_dir):
    s, _ = load_json(os.path.join(church_dir, "summary.json"))
    th = s.get("time_history") if isinstance(s, dict) else None
    if not isinstance(th, dict):
        return None, ""
    keep = {k: th.get(k) for k in ("time", "steps", "iterations", "max_damage", "peak_drift_ratio", "max_balance_error")}
    md = (f"Time history: {fmt(th.get('time'))} s reached ({th.get('steps')} steps, {th.get('iterations')} Newton iterations); "
          f"largest d_t {fmt((th.get('max_damage') or {}).get('d_t'))}, d_c {fmt((th.get('max_damage') or {}).get('d_c'))}; "
          f"peak drift ratio {fmt(th.get('peak_drift_ratio'))}; energy balance error {fmt(th.get('max_balance_error'))}.")
    return keep, md


# ---------------------------------------------------------------------------------------------

def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--identify", default="results/identify-wall")
    ap.add_argument("--church", default="results/church")
    ap.add_argument("--material", default="materials/rubble-identified.toml")
    ap.add_argument("--timings", default="results/chain/timings.json")
    ap.add_argument("--church-log", default="results/chain/church.log")
    ap.add_argument("--comparison", default="results/church-comparison-assumed")
    ap.add_argument("--out", default="results/chain")
    a = ap.parse_args()

    os.makedirs(a.out, exist_ok=True)
    summary = {}
    md = ["# The chain: Table 1 → DEM → damage law → church", ""]
    timings, _ = load_json(a.timings)
    if timings:
        md.append("Stages and wall times (2 cores shared; " + f"{timings.get('ranks', '?')} rank(s)):")
        for st in timings.get("stages", []):
            md.append(f"* {st['name']}: {st['status']}, {fmt(st.get('seconds'))} s")
        rep = timings.get("material_reproduced")
        if rep is not None:
            md.append(f"* `{a.material}` {'identical to' if rep else 'DIFFERS from'} the committed version (git diff)")
        md.append("")
        summary["timings"] = timings

    cal, cal_md = calibration_section(a.identify)
    md += ["## 1. DEM calibration against Table 1", "", cal_md, ""]
    summary["calibration"] = cal

    law, law_md, _ = law_section(a.identify, a.material)
    md += ["## 2. The identified damage law and its peaks against the DEM's", "", law_md, ""]
    summary["law"] = law

    fr, fr_md = frequency_section(a.church)
    md += ["## 3. Frequencies: as given, targets, updated", "", fr_md, ""]
    summary["frequencies"] = fr

    gr, gr_md = gravity_section(a.church, a.church_log)
    md += ["## 4. Gravity", "", gr_md, ""]
    summary["gravity"] = gr

    th, th_md = time_history_line(a.church)
    dm, dm_md = damage_section(a.church)
    md += ["## 5. Damage per substructure after gravity and at the end", ""]
    if th_md:
        md += [th_md, ""]
    md += [dm_md, ""]
    summary["time_history"] = th
    summary["damage"] = dm

    cmp_data, cmp_md = comparison_section(a.comparison)
    if cmp_data is not None:
        md += ["## 6. The same church on the assumed law (scripts/compare_laws.sh)", "", cmp_md, ""]
        summary["comparison"] = cmp_data

    with open(os.path.join(a.out, "summary.md"), "w") as f:
        f.write("\n".join(md))
    with open(os.path.join(a.out, "summary.json"), "w") as f:
        json.dump(summary, f, indent=2, ensure_ascii=False)
        f.write("\n")
    print(f"chain summary: {os.path.join(a.out, 'summary.md')} and summary.json")
    return 0


if __name__ == "__main__":
    sys.exit(main())
