#!/usr/bin/env python3
"""The OpenSees side of scripts/bench/peer.sh: the same shell model as the masonry-hpc jobs,
built from the same Gmsh file, in OpenSeesPy.

    peer_opensees.py case.json out.json

case.json: {"mesh": path, "E", "nu", "rho", "thickness", "support": point group clamped,
"modes": n, "dt", "steps", "record": two-column file (t, a [m/s²]), "ground_motion":
[[direction 0/1/2, scale], ...], "rayleigh": [alpha, beta], "monitors": {name: node tag},
"eigen_solver": "-genBandArpack" | ...}. out.json: the frequencies, the monitored nodes'
displacement histories, and the seconds of each timed call.

The model: one ShellMITC4 per quadrangle with an ElasticMembranePlateSection (E, ν, thickness,
ρ: OpenSees lumps ρ t over the nodes' translations, no rotary inertia), the support group's
nodes fixed in all 6 DOFs. Mode shapes and response are not written to disk: the timed calls are
the eigen call and the analyze calls alone (the model's Python set-up and the start-up of the
interpreter are outside them; the caller times the whole command as well).
"""
import json
import sys
import time

import openseespy.opensees as ops


def read_msh(path):
    """Nodes {tag: (x, y, z)}, quads [(tag, n1..n4)], point groups {name: [node tags]} of a
    Gmsh 4.1 ASCII file (as written by scripts/make_quad_mesh.py)."""
    lines = open(path).read().split("\n")
    sec = {}
    i = 0
    while i < len(lines):
        if lines[i].startswith("$") and not lines[i].startswith("$End"):
            name = lines[i][1:]
            j = lines.index("$End" + name, i)
            sec[name] = lines[i + 1 : j]
            i = j
        i += 1
    names = {}
    for l in sec["PhysicalNames"][1:]:
        dim, tag, name = l.split(maxsplit=2)
        names[(int(dim), int(tag))] = name.strip('"')
    ent = sec["Entities"]
    n_pts = int(ent[0].split()[0])
    point_group = {}
    for l in ent[1 : 1 + n_pts]:
        f = l.split()
        if int(f[4]) > 0:
            point_group[int(f[0])] = names[(0, int(f[5]))]
    nodes = {}
    lines_n = sec["Nodes"]
    n_blocks = int(lines_n[0].split()[0])
    k = 1
    for _ in range(n_blocks):
        n = int(lines_n[k].split()[3])
        tags = [int(t) for t in lines_n[k + 1 : k + 1 + n]]
        for t, xyz in zip(tags, lines_n[k + 1 + n : k + 1 + 2 * n]):
            nodes[t] = tuple(float(v) for v in xyz.split())
        k += 1 + 2 * n
    quads, groups = [], {}
    el = sec["Elements"]
    n_blocks = int(el[0].split()[0])
    k = 1
    for _ in range(n_blocks):
        dim, etag, etype, n = (int(v) for v in el[k].split())
        rows = [[int(v) for v in r.split()] for r in el[k + 1 : k + 1 + n]]
        if etype == 15 and etag in point_group:
            groups.setdefault(point_group[etag], []).extend(r[1] for r in rows)
        elif etype == 3:
            quads.extend(tuple(r) for r in rows)
        k += 1 + n
    return nodes, quads, groups


def main():
    case = json.load(open(sys.argv[1]))
    nodes, quads, groups = read_msh(case["mesh"])
    out = {"nodes": len(nodes), "elements": len(quads), "dof": 6 * len(nodes)}

    t0 = time.perf_counter()
    ops.wipe()
    ops.model("basic", "-ndm", 3, "-ndf", 6)
    for t, (x, y, z) in nodes.items():
        ops.node(t, x, y, z)
    for t in sorted(set(groups[case["support"]])):
        ops.fix(t, 1, 1, 1, 1, 1, 1)
    ops.section("ElasticMembranePlateSection", 1, case["E"], case["nu"], case["thickness"], case["rho"])
    for q in quads:
        ops.element("ShellMITC4", q[0], *q[1:5], 1)
    out["seconds_model"] = time.perf_counter() - t0
    out["fixed_dof"] = 6 * len(set(groups[case["support"]]))

    # (a) The lowest modes. The numberer orders the equations for the band eigen solvers
    # (reverse Cuthill-McKee: the bandwidth of the U's rows of nodes).
    ops.constraints("Plain")
    ops.numberer("RCM")
    t0 = time.perf_counter()
    lam = ops.eigen(case["eigen_solver"], case["modes"])
    out["seconds_eigen"] = time.perf_counter() - t0
    out["frequencies"] = [l**0.5 / (2.0 * 3.141592653589793) for l in lam]

    # (b) Newmark, average acceleration, on the linear model: the effective stiffness factored
    # once (Linear -factorOnce) by the sparse symmetric solver chosen (`system`).
    ops.wipeAnalysis()
    dt, steps = case["dt"], case["steps"]
    acc = [float(l.split()[1]) for l in open(case["record"]) if l.strip() and not l.startswith("#")]
    for k, (d, scale) in enumerate(case["ground_motion"]):
        ops.timeSeries("Path", 10 + k, "-dt", dt, "-values", *acc, "-factor", scale)
        ops.pattern("UniformExcitation", 10 + k, d + 1, "-accel", 10 + k)
    alpha, beta = case["rayleigh"]
    # C = alpha M + beta K_init (the same as beta K on this linear model; with K_init the elements
    # reuse their stored initial stiffness instead of forming the tangent again for the damping
    # forces of every step: 2.8 times faster per step on a 4.7k-DOF U than with beta K).
    ops.rayleigh(alpha, 0.0, beta, 0.0)
    ops.constraints("Plain")
    ops.numberer("RCM")
    ops.system(*case["system"])
    ops.algorithm("Linear", "-factorOnce")
    ops.integrator("Newmark", 0.5, 0.25)
    ops.analysis("Transient")
    mon = case["monitors"]
    hist = {name: [] for name in mon}
    seconds = 0.0
    for _ in range(steps):
        t0 = time.perf_counter()
        ok = ops.analyze(1, dt)
        seconds += time.perf_counter() - t0
        if ok != 0:
            raise SystemExit(f"peer_opensees.py: analyze failed at t = {ops.getTime()}")
        for name, tag in mon.items():
            hist[name].append(ops.nodeDisp(tag)[:3])
    out["seconds_transient"] = seconds
    out["seconds_per_step"] = seconds / steps
    out["monitors"] = hist
    json.dump(out, open(sys.argv[2], "w"))


if __name__ == "__main__":
    main()
