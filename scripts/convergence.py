#!/usr/bin/env python3
"""Convergence of what the church job reports: time step, mesh and ranks (scripts/convergence.sh).

    python3 scripts/convergence.py [--job jobs/church.toml] [--out results/convergence]
                                   [--only CASE ...] [--rerun] [--table-only] [--set KEY=VALUE]

Two loadings of the same model, each run as derived job files (results/convergence/jobs/):
  code     the job as given (its record, its duration);
  member   the job under record 01 of the EC8 record set (results/record-set-ec8/, made by
           jobs/record-set-ec8.toml) scaled to 1.5 times the sweep's code level
           (jobs/church-sweep.toml: a_g S = 1.6 m/s^2, so PGA 2.4 m/s^2), its first 4 s (the
           rise and 2 s of the strong part; a sweep member runs the record whole).
For each: the job's dt, dt/2 and dt/4 on 2 ranks, and dt on 1 rank (the member also dt/2 on 1
rank). For the code loading also the
coarse and the fine mesh (meshes/church-fine.msh) through gravity and the first 4 s.

Reads each run's summary.json and writes into --out:
  convergence.csv   one row per case: settings, steps, iterations, seconds, peak drift ratio,
                    the energy terms, and the share of each substructure's area with d_t > 0.5
  convergence.md    the same as tables, and the comparisons with their verdicts:
                      dt/2 against dt/4 within 2 points of share (the time-step band),
                      1 against 2 ranks within 0.5 point (round-off),
                      dt against dt/4 (the error of the job's own step: the band it reports),
                      coarse against fine (reported, with what it shows)
  band.json         per loading, per substructure: |share(dt) - share(dt/4)| and |share(1 rank)
                    - share(2 ranks)|, with the settings they hold for; the job reads it through
                    [dynamics] convergence (--publish: jobs/church-convergence.json, and the
                    table as docs/convergence.md)
A case whose summary.json exists is not run again (--rerun runs it again). --set KEY=VALUE sets a
[dynamics] key in every case, to study a setting before the job takes it (with its own --out).
Needs the release build (cargo build --release). Time on 2 cores: about 2 hours in all, most of it
the dt/4 runs and the fine mesh. Exit 1 when a
comparison misses its band, 2 on bad input.
"""
import argparse
import datetime
import json
import os
import re
import subprocess
import sys
import tomllib

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
STEP_BAND = 2.0    # points of share: dt/2 against dt/4
RANK_BAND = 0.5    # points of share: 1 against 2 ranks
MEMBER_FACTOR = 1.5
# s: the member's length, the record's 2 s rise and 2 s of its strong part.
MEMBER_DURATION = 4.0


def fail(msg, code=2):
    print(f"convergence.py: {msg}", file=sys.stderr)
    sys.exit(code)


# --- derived job files -------------------------------------------------------------------------

def section_spans(lines):
    """(header, index) of every table header, in order."""
    out = []
    for i, l in enumerate(lines):
        m = re.match(r"^\s*(\[\[?[^\]]+\]\]?)\s*(#.*)?$", l)
        if m:
            out.append((m.group(1).replace(" ", ""), i))
    return out


def set_key(text, header, key, value, nth=None):
    """Set `key = value` (a TOML literal) in the table `header` ("[dynamics]" or, with nth, the
    nth "[[dynamics.ground_motion]]"); added after the header when the table lacks it."""
    lines = text.split("\n")
    spans = section_spans(lines)
    found = [k for k, (h, _) in enumerate(spans) if h == header]
    if not found:
        fail(f"no table {header} in the job")
    k = found[nth or 0] if nth is None or nth < len(found) else fail(f"no {header} number {nth + 1}")
    start = spans[k][1] + 1
    end = spans[k + 1][1] if k + 1 < len(spans) else len(lines)
    for i in range(start, end):
        if re.match(rf"^\s*{re.escape(key)}\s*=", lines[i]):
            lines[i] = f"{key} = {value}"
            # drop the continuation comments of the old value's line
            return "\n".join(lines)
    lines.insert(start, f"{key} = {value}")
    return "\n".join(lines)


def absolute_paths(text, job_dir):
    """Every relative file path of the job made absolute (mesh, law files, records, output)."""
    def fix(m):
        p = m.group(2)
        if os.path.isabs(p):
            return m.group(0)
        return f'{m.group(1)}"{os.path.normpath(os.path.join(job_dir, p))}"'
    return re.sub(r'^(\s*(?:file|law_file|dir|target_shapes|convergence)\s*=\s*)"([^"]+)"', fix, text, flags=re.M)


def toml_float(x):
    return repr(float(x))


def record_pga(path):
    peak = 0.0
    with open(path) as fh:
        for l in fh:
            if l.startswith("#") or not l.strip():
                continue
            peak = max(peak, abs(float(l.split()[1])))
    return peak


class Case:
    def __init__(self, name, loading, dt_div=1, ranks=2, mesh=None, duration=None):
        self.name, self.loading, self.dt_div, self.ranks = name, loading, dt_div, ranks
        self.mesh, self.duration = mesh, duration


def cases():
    """In the order they run: the member first (the strong shaking decides the step control)."""
    out = []
    for loading in ("member", "code"):
        for d in (1, 2, 4):
            out.append(Case(f"{loading}-dt{'' if d == 1 else '-' + str(d)}", loading, dt_div=d))
        out.append(Case(f"{loading}-1rank", loading, ranks=1))
    # Round-off at half the step, where the member's step error is within its band.
    out.append(Case("member-dt-2-1rank", "member", dt_div=2, ranks=1))
    out.append(Case("code-coarse-4s", "code", duration=4.0))
    out.append(Case("code-fine-4s", "code", mesh="meshes/church-fine.msh", duration=4.0))
    return out


def derive(base_text, base, case, out, member_record, member_factor, member_duration, sets=()):
    """The job text of `case`, with the [dynamics] keys `sets` ((key, TOML literal) pairs)."""
    job_dir = os.path.dirname(os.path.abspath(base["path"]))
    t = absolute_paths(base_text, job_dir)
    for k, v in sets:
        t = set_key(t, "[dynamics]", k, v)
    dyn = base["dynamics"]
    dt = dyn["dt"] / case.dt_div
    t = set_key(t, "[dynamics]", "dt", toml_float(dt))
    if "output_every" in dyn:
        t = set_key(t, "[dynamics]", "output_every", str(dyn["output_every"] * case.dt_div))
    ck = dyn.get("checkpoint", {})
    if "every_steps" in ck:
        t = set_key(t, "[dynamics.checkpoint]", "every_steps", str(ck["every_steps"] * case.dt_div))
    if case.mesh:
        t = set_key(t, "[mesh]", "file", json.dumps(os.path.join(ROOT, case.mesh)))
    duration = case.duration
    if case.loading == "member":
        duration = member_duration
        for k, g in enumerate(dyn["ground_motion"]):
            t = set_key(t, "[[dynamics.ground_motion]]", "file", json.dumps(member_record), nth=k)
            t = set_key(t, "[[dynamics.ground_motion]]", "format", '"two_column"', nth=k)
            t = set_key(t, "[[dynamics.ground_motion]]", "units", '"m/s2"', nth=k)
            t = set_key(t, "[[dynamics.ground_motion]]", "scale",
                        toml_float(g.get("scale", 1.0) * member_factor), nth=k)
    if duration is not None:
        t = set_key(t, "[dynamics]", "duration", toml_float(duration))
    t = set_key(t, "[output]", "dir", json.dumps(os.path.join(out, case.name)))
    t = set_key(t, "[output]", "existing", '"backup"')
    title = f"{base.get('title', 'job')} (convergence case {case.name})"
    t = re.sub(r'^title\s*=.*$', f"title = {json.dumps(title)}", t, count=1, flags=re.M)
    # read back: the edits took
    d = tomllib.loads(t)
    assert abs(d["dynamics"]["dt"] - dt) < 1e-15, case.name
    return t


# --- the table ---------------------------------------------------------------------------------

def load(out, case):
    path = os.path.join(out, case.name, "summary.json")
    if not os.path.isfile(path):
        return None
    with open(path) as fh:
        s = json.load(fh)
    th = s.get("time_history")
    if th is None:
        return None
    groups = {g["group"]: g for g in th.get("damage_by_group", [])}
    e, sec = th["energy"], s.get("seconds")
    if isinstance(e, list):  # a summary written before "format": 2
        e = dict(zip(("input", "kinetic", "strain", "damping", "dissipated_damage", "unilateral"), e))
        sec = {"total": sec[-1]} if sec else None
    integration = th.get("integration", "implicit")
    if th.get("implex_split"):
        integration += f" ({th['implex_split']} split)"
    if th.get("max_damage_increment", 1.0) < 1.0:
        integration += f", max Δd {th['max_damage_increment']:g}"
    return {
        "case": case.name, "loading": case.loading, "ranks": s.get("ranks", case.ranks),
        "integration": integration,
        "dt": th["dt"], "time": th["time"], "steps": th["steps"], "iterations": th["iterations"],
        "substepped_steps": th.get("substepped_steps", 0), "factorizations": th.get("factorizations", 0),
        "seconds": sec["total"] if sec else float("nan"),
        "peak_drift_ratio": th["peak_drift_ratio"],
        "input": e["input"], "kinetic": e["kinetic"], "strain": e["strain"], "damping": e["damping"],
        "damage": e["dissipated_damage"], "unilateral": e["unilateral"],
        "max_balance_error": th["max_balance_error"],
        "shares": {g: 100.0 * v["share_dt"] for g, v in groups.items()},
        "dissipated": {g: v["dissipated"] for g, v in groups.items() if "dissipated" in v},
    }


def diff(a, b):
    """Largest |share difference| [points] and its group."""
    worst = (0.0, "-")
    for g in a["shares"]:
        if g in b["shares"]:
            x = abs(a["shares"][g] - b["shares"][g])
            if x > worst[0]:
                worst = (x, g)
    return worst


def cracked_cells(out, case):
    """Per cell of the final envelope (cells ordered by id): its group number, its peak d_t, its
    area; None without envelopes.h5 or h5py."""
    try:
        import h5py
        import numpy as np
    except ImportError:
        return None
    path = os.path.join(out, case, "envelopes.h5")
    if not os.path.isfile(path):
        return None
    with h5py.File(path, "r") as f:
        last = f["steps"][str(len(f["steps/times"]) - 1)]
        dt = last["d_t_max"] if "d_t_max" in last else last["max_d_t"]
        ids = f["mesh/cell_ids"][:]
        o = np.argsort(ids)
        xyz = f["mesh/coordinates"][:]
        topo, kinds = f["mesh/topology"][:], f["mesh/cell_types"][:]
        # XDMF mixed topology: a type code, a corner count for poly-vertices (1) and polylines
        # (2), then the corners; only triangles (4) and quads (5) have an area.
        areas, k = [], 0
        for _ in kinds:
            code = int(topo[k])
            if code in (1, 2):
                n, k = int(topo[k + 1]), k + 1
            else:
                n = {4: 3, 5: 4}.get(code)
                if n is None:
                    return None
            pts = xyz[topo[k + 1:k + 1 + n]]
            a = 0.0
            for j in range(1, n - 1) if code in (4, 5) else ():
                a += 0.5 * np.linalg.norm(np.cross(pts[j] - pts[0], pts[j + 1] - pts[0]))
            areas.append(a)
            k += 1 + n
        return ids[o], f["mesh/cell_group"][:][o], dt[:][o], np.array(areas)[o]


def first_substeps(out, case):
    """The steps of `case` taken in substeps, from its log."""
    path = os.path.join(out, "jobs", f"{case}.log")
    if not os.path.isfile(path):
        return set()
    with open(path) as fh:
        return {int(m.group(1)) for m in re.finditer(r"step (\d+)/\d+ t = [^:]*: \d+ iteration\(s\) in \d+ substeps",
                                                         fh.read())}


def first_parting(out, a, b, rel=1e-6):
    """The first step at which the monitors of runs a and b differ by more than rel of each
    column's largest value, or None."""
    import csv
    rows = []
    for case in (a, b):
        path = os.path.join(out, case, "monitors.csv")
        if not os.path.isfile(path):
            return None
        with open(path) as fh:
            r = list(csv.reader(fh))
        rows.append((r[0], r[1:]))
    (ha, ra), (hb, rb) = rows
    cols = [c for c in ha if c in hb and c not in ("step", "time")]
    ia, ib = [ha.index(c) for c in cols], [hb.index(c) for c in cols]
    scale = [max(abs(float(x[i])) for x in ra) or 1.0 for i in ia]
    for xa, xb in zip(ra, rb):
        for k, (i, j) in enumerate(zip(ia, ib)):
            if abs(float(xa[i]) - float(xb[j])) > rel * scale[k]:
                return int(xa[0])
    return None


def physical_names(msh):
    """Surface physical tags of a Gmsh file: {tag: name}."""
    names, inside = {}, False
    try:
        with open(msh) as fh:
            for line in fh:
                if line.startswith("$PhysicalNames"):
                    inside = True
                    next(fh)
                elif line.startswith("$EndPhysicalNames"):
                    break
                elif inside:
                    dim, tag, name = line.split(maxsplit=2)
                    if dim == "2":
                        names[int(tag)] = name.strip().strip('"')
    except OSError:
        pass
    return names


def rank_cells(out, rows_by, groups_by_number):
    """Lines of the cell-by-cell comparison of each 1-rank run with its 2-rank twin."""
    md = []
    for one, two in (("code-1rank", "code-dt"), ("member-1rank", "member-dt"),
                     ("member-dt-2-1rank", "member-dt-2")):
        if one not in rows_by or two not in rows_by:
            continue
        a, b = cracked_cells(out, one), cracked_cells(out, two)
        if a is None or b is None or len(a[0]) != len(b[0]) or (a[0] != b[0]).any():
            continue
        parting = first_parting(out, one, two)
        subs = (first_substeps(out, one), first_substeps(out, two))
        where = "never (to 1e-6 of each monitor's largest value)" if parting is None else f"at step {parting}"
        if parting is not None:
            taken = [n for n, s in zip((one, two), subs) if parting in s]
            where += (f", a step {' and '.join(taken)} took in substeps and " if len(taken) == 1 else
                      ", a step both took in substeps" if taken else ", a step neither took in substeps")
            if len(taken) == 1:
                where += f"{two if taken[0] == one else one} did not"
        md.append(f"**{one} against {two}**: the monitors part {where}.\n")
        md.append("| substructure | cells | cracked (1 rank) | cracked (2 ranks) | cells that differ "
                  "| one cell [points] | largest cell d_t difference |")
        md.append("|---|---|---|---|---|---|---|")
        for g, name in groups_by_number.items():
            m = a[1] == g
            if not m.any():
                continue
            fa, fb = a[2][m] > 0.5, b[2][m] > 0.5
            if not (fa.any() or fb.any()):
                continue
            area = a[3][m]
            cell = 100.0 * area.max() / area.sum() if area.sum() > 0 else float("nan")
            dd = abs(a[2][m] - b[2][m]).max()
            md.append(f"| {name} | {m.sum()} | {fa.sum()} | {fb.sum()} | {(fa != fb).sum()} | {cell:.2f} | {dd:.3f} |")
        md.append("")
    return md


def git_commit():
    try:
        r = subprocess.run(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"], capture_output=True, text=True)
        dirty = subprocess.run(["git", "-C", ROOT, "diff", "--quiet", "HEAD", "--", "src"]).returncode != 0
        return r.stdout.strip() + (" with uncommitted changes in src/" if dirty else "")
    except OSError:
        return "unknown"


def write_tables(out, rows, checks, machine, loadings, groups_by_number):
    groups = []
    for r in rows:
        for g in r["shares"]:
            if g not in groups:
                groups.append(g)
    cols = ["case", "loading", "ranks", "integration", "dt", "time", "steps", "iterations", "substepped_steps",
            "factorizations", "seconds", "peak_drift_ratio", "input", "kinetic", "strain", "damping",
            "damage", "unilateral", "max_balance_error"]
    with open(os.path.join(out, "convergence.csv"), "w") as fh:
        fh.write(",".join(cols + [f"share_dt_{g}" for g in groups]) + "\n")
        for r in rows:
            fh.write(",".join([str(r[c]) for c in cols] +
                              [f"{r['shares'][g]:.4f}" if g in r["shares"] else "" for g in groups]) + "\n")
    md = [f"# Convergence of the church job's answers\n",
          f"Written by `scripts/convergence.py` on {datetime.date.today()} (commit {git_commit()}), {machine}.",
          "Shares: % of each substructure's shell area with d_t > 0.5 at the end of the run; seconds: "
          "the whole job's wall time (modal analysis, updating, gravity, time history), as it ran, on a "
          "machine that may have been shared: speed is measured by scripts/bench (docs/benchmarks.md).\n"]
    for name, what in loadings.items():
        md.append(f"* **{name}**: {what}")
    md.append("")
    for loading in ("code", "member"):
        rs = [r for r in rows if r["loading"] == loading]
        if not rs:
            continue
        md.append(f"## {loading}\n")
        shown = [g for g in groups if any(r["shares"].get(g, 0) > 0 for r in rs)]
        md.append("| case | ranks | integration | dt [s] | t [s] | iterations | substepped | seconds | peak drift "
                  "| input [J] | damage [J] | unilateral [J] | balance (max) | " + " | ".join(shown) + " |")
        md.append("|" + "---|" * (13 + len(shown)))
        for r in rs:
            md.append(f"| {r['case']} | {r['ranks']} | {r['integration']} | {r['dt']:g} | {r['time']:g} | "
                      f"{r['iterations']} | "
                      f"{r['substepped_steps']} | {r['seconds']:.0f} | {r['peak_drift_ratio']:.3e} | "
                      f"{r['input']:.4g} | {r['damage']:.4g} | {r['unilateral']:.3g} | "
                      f"{r['max_balance_error']:.1e} | " +
                      " | ".join(f"{r['shares'].get(g, 0):.2f}" for g in shown) + " |")
        md.append("")
    md.append("## Comparisons\n")
    md.append("| loading | compared | largest share difference [points] | in | band | verdict |")
    md.append("|---|---|---|---|---|---|")
    for c in checks:
        band = "reported" if c["band"] is None else f"{c['band']:g}"
        verdict = "reported" if c["band"] is None else ("within" if c["diff"] <= c["band"] else "OUTSIDE")
        md.append(f"| {c['loading']} | {c['what']} | {c['diff']:.2f} | {c['group']} | {band} | {verdict} |")
    by = {r["case"]: r for r in rows}
    cells = rank_cells(out, by, groups_by_number)
    if cells:
        md.append("\n## 1 against 2 ranks, cell by cell\n")
        md.append("A share counts whole cells (a cell is cracked when its peak d_t over the layers passes 0.5), "
                  "so it moves in steps of one cell's area: \"one cell\" is the largest cell's share of its "
                  "substructure. The rank count changes the order of floating-point sums (assembly, the direct "
                  "solver's pivots), nothing else; where the runs part is read from their monitors, and whether "
                  "a step there was halved in one run and not in the other from their logs.\n")
        md.extend(cells)
    coarse, fine = by.get("code-coarse-4s"), by.get("code-fine-4s")
    if coarse and fine:
        md.append("\n## Coarse against fine mesh\n")
        # The energy each substructure dissipated (summaries that carry it): the crack band's measure.
        energy = bool(coarse["dissipated"]) and bool(fine["dissipated"])
        ratio = lambda f, c: f"{f / c:.2f}" if c > 0 else "-"
        md.append("| substructure | coarse share [%] | fine share [%] | fine / coarse |"
                  + (" coarse dissipated [J] | fine dissipated [J] | fine / coarse |" if energy else ""))
        md.append("|---|---|---|---|" + ("---|---|---|" if energy else ""))
        for g in coarse["shares"]:
            c, f = coarse["shares"][g], fine["shares"].get(g, 0.0)
            dc, df = coarse["dissipated"].get(g, 0.0), fine["dissipated"].get(g, 0.0)
            if c > 0 or f > 0 or dc > 0.01 or df > 0.01:
                md.append(f"| {g} | {c:.2f} | {f:.2f} | {ratio(f, c)} |"
                          + (f" {dc:.4g} | {df:.4g} | {ratio(df, dc)} |" if energy else ""))
        md.append("")
        md.append(f"Energy dissipated by damage: {coarse['damage']:.4g} J coarse, {fine['damage']:.4g} J fine "
                  f"({fine['damage'] / coarse['damage']:.2f}); peak drift ratio {coarse['peak_drift_ratio']:.3e} "
                  f"and {fine['peak_drift_ratio']:.3e}. The share of area with d_t > 0.5 is not objective: a "
                  "crack's damaged band is one element wide, so the area it covers shrinks with the element "
                  "size (the crack-band regularization aims at the energy per crack area, not at the cracked "
                  "area). The energy dissipated by damage differs too, so where and how much the meshes crack "
                  "differs as well, beyond the band width. Compare shares between runs on the same mesh "
                  "only; the bands of the tables above hold for the coarse mesh.")
    md.append("\n## The other integrations\n")
    md.append("[convergence-implicit.md](convergence-implicit.md): the same study with the implicit law "
              "(`integration = \"implicit\"`), and the remedies measured for its 1- against 2-rank "
              "difference under strong shaking; [convergence-implex.md](convergence-implex.md): IMPL-EX, "
              "with and without corrections, against it.")
    with open(os.path.join(out, "convergence.md"), "w") as fh:
        fh.write("\n".join(md) + "\n")
    print("\n".join(md))


def band_file(out, rows_by, base, base_path, pgas):
    bands = {}
    for loading in ("code", "member"):
        ref, one, two = rows_by.get(f"{loading}-dt-4"), rows_by.get(f"{loading}-dt"), rows_by.get(f"{loading}-1rank")
        if not (ref and one):
            continue
        groups = {}
        for g in one["shares"]:
            groups[g] = {
                "time_step": abs(one["shares"][g] - ref["shares"].get(g, 0.0)) / 100.0,
                "ranks": abs(one["shares"][g] - two["shares"].get(g, 0.0)) / 100.0 if two else None,
            }
        bands[loading] = {"reference": f"{loading}-dt-4", "pga": pgas[loading], "duration": one["time"],
                          "groups": groups,
                          "peak_drift_ratio": abs(one["peak_drift_ratio"] - ref["peak_drift_ratio"])
                          / ref["peak_drift_ratio"]}
    law = sorted({m.get("law_file", "") for m in base["materials"].values() if m.get("law_file")})
    doc = {
        "what": "share of each substructure's area with d_t > 0.5: |share at the job's dt - share at dt/4| "
                "(time_step) and |share on 1 rank - share on 2 ranks| (ranks), as fractions; "
                "peak_drift_ratio: relative difference at dt against dt/4",
        "written_by": "scripts/convergence.py",
        "date": str(datetime.date.today()),
        "job": os.path.relpath(base_path, ROOT),
        "settings": {"dt": base["dynamics"]["dt"], "mesh": os.path.basename(base["mesh"]["file"]),
                     "law_files": [os.path.basename(x) for x in law],
                     "max_damage_increment": base["dynamics"].get("max_damage_increment", 1.0),
                     "integration": base["dynamics"].get("integration", "implicit"),
                     "implex_corrections": base["dynamics"].get("implex_corrections", 0)},
        "loadings": bands,
    }
    with open(os.path.join(out, "band.json"), "w") as fh:
        json.dump(doc, fh, indent=1)
        fh.write("\n")


def machine():
    try:
        with open("/proc/cpuinfo") as fh:
            for l in fh:
                if l.startswith("model name"):
                    return f"{os.cpu_count()} cores, {l.split(':', 1)[1].strip()}"
    except OSError:
        pass
    return f"{os.cpu_count()} cores"


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--job", default="jobs/church.toml")
    ap.add_argument("--sweep", default="jobs/church-sweep.toml", help="its code_level and duration")
    ap.add_argument("--out", default="results/convergence")
    ap.add_argument("--only", nargs="*", help="run only these cases")
    ap.add_argument("--rerun", action="store_true", help="run cases whose summary.json exists again")
    ap.add_argument("--table-only", action="store_true", help="run nothing: tables from what exists")
    ap.add_argument("--binary", default="target/release/masonry-hpc")
    ap.add_argument("--publish", action="store_true",
                    help="copy the table to docs/convergence.md and band.json beside the job "
                         "(<job stem>-convergence.json, which the job names in [dynamics] convergence)")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                    help="a [dynamics] key set in every case (e.g. max_damage_increment=0.2): to study a "
                         "setting before it becomes the job's; use its own --out")
    a = ap.parse_args()
    os.chdir(ROOT)
    out = os.path.abspath(a.out)
    os.makedirs(os.path.join(out, "jobs"), exist_ok=True)
    try:
        with open(a.job) as fh:
            base_text = fh.read()
        base = tomllib.loads(base_text)
        with open(a.sweep) as fh:
            sweep = tomllib.loads(fh.read())["sweep"]
    except (OSError, tomllib.TOMLDecodeError, KeyError) as e:
        fail(f"{a.job} / {a.sweep}: {e}")
    base["path"] = a.job
    sets = []
    for kv in a.set:
        k, sep, v = kv.partition("=")
        if not sep or not k.strip():
            fail(f"--set {kv}: expected KEY=VALUE")
        try:
            base["dynamics"][k.strip()] = tomllib.loads(f"x = {v}")["x"]
        except tomllib.TOMLDecodeError:
            fail(f"--set {kv}: the value is not a TOML value")
        sets.append((k.strip(), v.strip()))
    if "dynamics" not in base:
        fail(f"{a.job}: no [dynamics]")
    record = os.path.join(ROOT, "results/record-set-ec8/record-01.txt")
    all_cases = cases()
    names = [c.name for c in all_cases]
    for n in a.only or []:
        if n not in names:
            fail(f"--only {n}: no such case (cases: {', '.join(names)})")
    todo = [c for c in all_cases if not a.only or c.name in a.only]
    if not a.table_only:
        if any(c.loading == "member" for c in todo) and not os.path.isfile(record):
            subprocess.run([a.binary, "jobs/record-set-ec8.toml"], check=True)
        level = MEMBER_FACTOR * sweep["code_level"]
        factor = level / record_pga(record) if os.path.isfile(record) else 1.0
        for c in todo:
            summary = os.path.join(out, c.name, "summary.json")
            if os.path.isfile(summary) and not a.rerun:
                print(f"convergence: {c.name}: done before ({summary})")
                continue
            text = derive(base_text, base, c, out, record, factor, MEMBER_DURATION, sets)
            path = os.path.join(out, "jobs", f"{c.name}.toml")
            with open(path, "w") as fh:
                fh.write(f"# Convergence case {c.name} of {a.job} (scripts/convergence.py); "
                         f"runs alone: mpirun -n {c.ranks} masonry-hpc {os.path.relpath(path, ROOT)}\n")
                if c.loading == "member":
                    fh.write(f"# record 01 of the EC8 set scaled by {factor:.6f} to PGA {level:g} m/s^2\n")
                fh.write(text)
            print(f"convergence: {c.name} on {c.ranks} rank(s) ...", flush=True)
            # Ranks yield the core while they wait (a machine shared with other work), unless the
            # caller says otherwise (0: they poll, and win the cores against niced work).
            env = dict(os.environ)
            env.setdefault("OMPI_MCA_mpi_yield_when_idle", "1")
            r = subprocess.run(["mpirun", "-n", str(c.ranks), a.binary, path], env=env,
                               stdout=open(os.path.join(out, "jobs", f"{c.name}.log"), "w"),
                               stderr=subprocess.STDOUT)
            print(f"convergence: {c.name}: exit {r.returncode}", flush=True)
    rows = [r for r in (load(out, c) for c in all_cases) if r]
    rows_by = {r["case"]: r for r in rows}
    checks = []
    for loading in ("code", "member"):
        pairs = [(f"{loading}-dt-2", f"{loading}-dt-4", "dt/2 against dt/4", STEP_BAND),
                 (f"{loading}-1rank", f"{loading}-dt", "1 against 2 ranks", RANK_BAND),
                 (f"{loading}-dt", f"{loading}-dt-4", "dt against dt/4 (the job's step)", None)]
        if loading == "member":
            pairs.append(("member-dt-2-1rank", "member-dt-2", "1 against 2 ranks at dt/2", None))
        if loading == "code":
            pairs.append(("code-coarse-4s", "code-fine-4s", "coarse against fine mesh, first 4 s", None))
        for x, y, what, band in pairs:
            if x in rows_by and y in rows_by:
                d, g = diff(rows_by[x], rows_by[y])
                checks.append({"loading": loading, "what": what, "diff": d, "group": g, "band": band})
    job_dir = os.path.dirname(os.path.abspath(a.job))
    code_pga = max(record_pga(os.path.join(job_dir, g["file"])) * g.get("scale", 1.0)
                   * (9.81 if g.get("units") == "g" else 1.0) for g in base["dynamics"]["ground_motion"])
    member_pga = MEMBER_FACTOR * sweep["code_level"] * max(g.get("scale", 1.0) for g in base["dynamics"]["ground_motion"])
    loadings = {
        "code": f"{a.job} as given: its record, PGA {code_pga:.3g} m/s^2, its duration",
        "member": f"EC8 record 01 (results/record-set-ec8/) scaled to PGA {member_pga:.3g} m/s^2, "
                  f"{MEMBER_FACTOR:g} times the code level of {a.sweep}, for its first "
                  f"{MEMBER_DURATION:g} s",
    }
    groups_by_number = physical_names(os.path.join(job_dir, base["mesh"]["file"]))
    write_tables(out, rows, checks, machine(), loadings, groups_by_number)
    band_file(out, rows_by, base, a.job, {"code": code_pga, "member": member_pga})
    missed = [c for c in checks if c["band"] is not None and c["diff"] > c["band"]]
    if a.publish:
        import shutil
        os.makedirs(os.path.join(ROOT, "docs"), exist_ok=True)
        shutil.copyfile(os.path.join(out, "convergence.md"), os.path.join(ROOT, "docs", "convergence.md"))
        stem = os.path.splitext(a.job)[0]
        shutil.copyfile(os.path.join(out, "band.json"), f"{stem}-convergence.json")
        print(f"convergence: published docs/convergence.md and {stem}-convergence.json")
    sys.exit(1 if missed else 0)


if __name__ == "__main__":
    main()
