#!/usr/bin/env python3
"""Rectangular structured quadrangle meshes (Gmsh MSH 4.1 ASCII) for shell jobs and benchmarks.

    scripts/make_quad_mesh.py plate --nx 90 --ny 90 -o plate.msh
        a x b plate in the x-y plane; physical groups: surface "plate"; points "all",
        "x_edges" (x = 0 and x = a), "y_edges" (y = 0 and y = b), "clamped" (x = 0).
    scripts/make_quad_mesh.py wall --nx 10 --ny 12 -o wall.msh
        the paper's wall (1.0 m wide along x, 1.2 m high along z, in the x-z plane); groups:
        surface "wall", curve "platen" (2-node lines along the top edge), points "base", "top",
        "all".
    scripts/make_quad_mesh.py uwalls --nx 54 --ny 34 --nz 68 -o u.msh
        three walls in a U on a fixed base, of height --height (10 m) along z: the back wall
        along x at y = 0, --a long (8 m), and two side walls along y at x = 0 and x = a, --b long
        (5 m), open at y = b; --nx divisions along the back wall, --ny along each side wall, --nz
        up the height; groups: surface "walls", points "base" (z = 0), "top" (z = height), "all".
        The nodes run along the U (from (0, b) to (0, 0), (a, 0), (a, b)), row by row up z.

Node tags are 1-based in row-major order (x fastest); element tags follow the points, then the
lines, then the quadrangles. No Gmsh is needed.
"""
import argparse


def write(path, nodes, surfaces, curves, points):
    ns, nc = len(surfaces), len(curves)
    out = ["$MeshFormat", "4.1 0 8", "$EndMeshFormat", "$PhysicalNames", str(ns + nc + len(points))]
    for g, (name, _) in enumerate(surfaces):
        out.append(f'2 {g + 1} "{name}"')
    for g, (name, _) in enumerate(curves):
        out.append(f'1 {ns + g + 1} "{name}"')
    for g, (name, _) in enumerate(points):
        out.append(f'0 {ns + nc + g + 1} "{name}"')
    out.append("$EndPhysicalNames")
    pts = [(g, n) for g, (_, ns_) in enumerate(points) for n in ns_]
    out += ["$Entities", f"{len(pts)} {nc} {ns} 0"]
    for k, (g, n) in enumerate(pts):
        x = nodes[n]
        out.append(f"{k + 1} {x[0]} {x[1]} {x[2]} 1 {ns + nc + g + 1}")
    for g in range(nc):
        out.append(f"{g + 1} -1e9 -1e9 -1e9 1e9 1e9 1e9 1 {ns + g + 1} 0")
    for g in range(ns):
        out.append(f"{g + 1} -1e9 -1e9 -1e9 1e9 1e9 1e9 1 {g + 1} 0")
    out += ["$EndEntities", "$Nodes", f"1 {len(nodes)} 1 {len(nodes)}", f"2 1 0 {len(nodes)}"]
    out += [str(i + 1) for i in range(len(nodes))]
    out += [f"{x[0]:.17e} {x[1]:.17e} {x[2]:.17e}" for x in nodes]
    out.append("$EndNodes")
    n_el = len(pts) + sum(len(c) for _, c in curves) + sum(len(q) for _, q in surfaces)
    out += ["$Elements", f"{ns + nc + len(pts)} {n_el} 1 {n_el}"]
    tag = 1
    for k, (_, n) in enumerate(pts):
        out += [f"0 {k + 1} 15 1", f"{tag} {n + 1}"]
        tag += 1
    for g, (_, lines) in enumerate(curves):
        out.append(f"1 {g + 1} 1 {len(lines)}")
        for a, b in lines:
            out.append(f"{tag} {a + 1} {b + 1}")
            tag += 1
    for g, (_, quads) in enumerate(surfaces):
        out.append(f"2 {g + 1} 3 {len(quads)}")
        for q in quads:
            out.append(f"{tag} {q[0] + 1} {q[1] + 1} {q[2] + 1} {q[3] + 1}")
            tag += 1
    out.append("$EndElements")
    with open(path, "w") as f:
        f.write("\n".join(out) + "\n")


def grid(nx, ny, place):
    idx = lambda i, j: j * (nx + 1) + i
    nodes = [place(i / nx, j / ny) for j in range(ny + 1) for i in range(nx + 1)]
    quads = [(idx(i, j), idx(i + 1, j), idx(i + 1, j + 1), idx(i, j + 1)) for j in range(ny) for i in range(nx)]
    return idx, nodes, quads


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("kind", choices=["plate", "wall", "uwalls"])
    p.add_argument("--nx", type=int, default=10)
    p.add_argument("--ny", type=int, default=12)
    p.add_argument("--a", type=float, default=None, help="length along x [m] (plate 1.0, wall 1.0)")
    p.add_argument("--b", type=float, default=None, help="length along y (plate) or z (wall) [m] (1.0 / 1.2)")
    p.add_argument("--nz", type=int, default=68, help="divisions up the height (uwalls)")
    p.add_argument("--height", type=float, default=10.0, help="height along z [m] (uwalls)")
    p.add_argument("-o", "--output", required=True)
    args = p.parse_args()
    nx, ny = args.nx, args.ny
    if args.kind == "plate":
        a, b = args.a or 1.0, args.b or 1.0
        idx, nodes, quads = grid(nx, ny, lambda s, t: (a * s, b * t, 0.0))
        points = [
            ("all", list(range(len(nodes)))),
            ("x_edges", [idx(i, j) for j in range(ny + 1) for i in (0, nx)]),
            ("y_edges", [idx(i, j) for i in range(nx + 1) for j in (0, ny)]),
            ("clamped", [idx(0, j) for j in range(ny + 1)]),
        ]
        write(args.output, nodes, [("plate", quads)], [], points)
    elif args.kind == "uwalls":
        a, b, h, nz = args.a or 8.0, args.b or 5.0, args.height, args.nz
        # Arc length along the U -> plan position: side wall x = 0 (y from b to 0), back wall
        # y = 0 (x from 0 to a), side wall x = a (y from 0 to b).
        path = [(0.0, b - b * k / ny) for k in range(ny)] + [(a * k / nx, 0.0) for k in range(nx)]
        path += [(a, b * k / ny) for k in range(ny + 1)]
        n_s = len(path) - 1
        idx, nodes, quads = grid(n_s, nz, lambda s, t: (*path[round(s * n_s)], h * t))
        points = [
            ("base", [idx(i, 0) for i in range(n_s + 1)]),
            ("top", [idx(i, nz) for i in range(n_s + 1)]),
            ("all", list(range(len(nodes)))),
        ]
        write(args.output, nodes, [("walls", quads)], [], points)
    else:
        a, b = args.a or 1.0, args.b or 1.2
        idx, nodes, quads = grid(nx, ny, lambda s, t: (a * s, 0.0, b * t))
        platen = [(idx(i, ny), idx(i + 1, ny)) for i in range(nx)]
        points = [
            ("base", [idx(i, 0) for i in range(nx + 1)]),
            ("top", [idx(i, ny) for i in range(nx + 1)]),
            ("all", list(range(len(nodes)))),
        ]
        write(args.output, nodes, [("wall", quads)], [("platen", platen)], points)
    print(f"{args.output}: {len(nodes)} nodes, {len(quads)} quadrangles")


if __name__ == "__main__":
    main()
