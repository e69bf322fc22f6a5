#!/usr/bin/env python3
"""Writes the demo mesh: a square steel lattice tower of 2-node beams, as Gmsh MSH 4.1.

Run from the repository root (Python 3, standard library only):

    python3 scripts/make_tower_mesh.py                     # the demo: meshes/tower.msh
    python3 scripts/make_tower_mesh.py --binary -o /tmp/tower_bin.msh

Benchmark sizes (not committed; write them outside the repository or delete them after use):

    # ~10x the demo: 23,400 lines, 21,654 nodes (300 m tall)
    python3 scripts/make_tower_mesh.py --storeys 50 --divisions 9 -o /tmp/tower_10x.msh
    # ~100x the demo: 240,000 lines, 233,304 nodes (600 m tall)
    python3 scripts/make_tower_mesh.py --storeys 100 --panels 4 --divisions 24 -o /tmp/tower_100x.msh

Geometry (metres; z up; defaults in brackets):

    plan: a square of side W [3.0] between leg axes, constant over the height, legs at
          (0,0) (W,0) (W,W) (0,W); height N storeys [15] of H [6.0] each (90 m by default);
          each storey is split into P panels [2] of height h = H/P (3 m: square 3 m x 3 m faces).

        z ^   face view (one of 4)        plan at a storey level
          |   +-------+  girt             +-------+
          |   | \\   / |                   | \\   / |
          |   |  \\ /  |  X-brace,         |  \\ /  |  plan bracing:
          |   |   X   |  crossing at      |   X   |  both diagonals,
          |   |  / \\  |  a shared node    |  / \\  |  crossing at a
          |   | /   \\ |                   | /   \\ |  centre node
          |   +-------+  girt             +-------+
          |   leg     leg

Members (each a Gmsh curve entity, meshed into D [3] equal 2-node line elements):
    legs    the 4 corner legs, one member per panel;
    girts   horizontal members along the 4 faces at every panel level above the ground;
    braces  in each face and panel, the two diagonals, each split in two at their crossing
            (a shared joint); plus, at every storey level, the two plan diagonals from the
            corners to a centre joint.

Physical groups: curves "legs" (1), "girts" (2), "braces" (3); points "base" (4, the 4 leg
feet at z = 0: fixed supports) and "top" (5, the 4 leg heads at the top: where loads go).
Each point group's points carry a 1-node point element, so the groups hold cells.

Numbering: point entities (joints) first, by level; node tags = point tags for joints, then
the interior nodes of each curve in curve order; element tags: the 8 point elements, then the
lines curve by curve. The output is deterministic: the same arguments give the same bytes.
The script prints the node and element counts (the reader's test checks them).
"""
import argparse
import struct
import sys

PHYS = [(1, 1, "legs"), (1, 2, "girts"), (1, 3, "braces"), (0, 4, "base"), (0, 5, "top")]
LEGS, GIRTS, BRACES, BASE, TOP = 1, 2, 3, 4, 5


class Tower:
    """Joints (point entities) and members (curve entities) of the tower."""

    def __init__(self, storeys, panels, width, storey_height):
        self.points = []  # (x, y, z, [physical tags])
        self.curves = []  # (start point tag, end point tag, physical tag)
        levels = storeys * panels
        corners = [(0.0, 0.0), (width, 0.0), (width, width), (0.0, width)]
        # corner[k][c]: point tag of corner c at level k
        corner = []
        for k in range(levels + 1):
            z = k * storey_height / panels
            row = []
            for x, y in corners:
                phys = [BASE] if k == 0 else ([TOP] if k == levels else [])
                row.append(self.point(x, y, z, phys))
            corner.append(row)
        # face_centre[k][f]: crossing of the X-braces of face f in panel k (between levels k, k+1)
        face_centre = []
        for k in range(levels):
            z = (k + 0.5) * storey_height / panels
            row = []
            for f in range(4):
                (x0, y0), (x1, y1) = corners[f], corners[(f + 1) % 4]
                row.append(self.point((x0 + x1) / 2, (y0 + y1) / 2, z, []))
            face_centre.append(row)
        plan_centre = {}
        for s in range(1, storeys + 1):
            k = s * panels
            plan_centre[k] = self.point(width / 2, width / 2, k * storey_height / panels, [])

        for k in range(levels):
            for c in range(4):
                self.curves.append((corner[k][c], corner[k + 1][c], LEGS))
        for k in range(1, levels + 1):
            for f in range(4):
                self.curves.append((corner[k][f], corner[k][(f + 1) % 4], GIRTS))
        for k in range(levels):
            for f in range(4):
                a, b = f, (f + 1) % 4
                m = face_centre[k][f]
                self.curves.append((corner[k][a], m, BRACES))
                self.curves.append((m, corner[k + 1][b], BRACES))
                self.curves.append((corner[k][b], m, BRACES))
                self.curves.append((m, corner[k + 1][a], BRACES))
        for k in sorted(plan_centre):
            for c in range(4):
                self.curves.append((corner[k][c], plan_centre[k], BRACES))

    def point(self, x, y, z, phys):
        self.points.append((x, y, z, phys))
        return len(self.points)


def build(tower, divisions):
    """Nodes, point elements and line elements in file order."""
    # node blocks: (dim, entity tag, [(node tag, (x, y, z))])
    node_blocks = [(0, i + 1, [(i + 1, p[:3])]) for i, p in enumerate(tower.points)]
    next_node = len(tower.points) + 1
    curve_nodes = []  # per curve: node tags from start to end
    for ci, (a, b, _) in enumerate(tower.curves):
        pa, pb = tower.points[a - 1], tower.points[b - 1]
        inner = []
        for i in range(1, divisions):
            t = i / divisions
            xyz = tuple(pa[j] + (pb[j] - pa[j]) * t for j in range(3))
            inner.append((next_node, xyz))
            next_node += 1
        node_blocks.append((1, ci + 1, inner))
        curve_nodes.append([a] + [n for n, _ in inner] + [b])
    # element blocks: (dim, entity tag, type, [(element tag, [node tags])])
    elem_blocks = []
    tag = 1
    for i, p in enumerate(tower.points):
        if p[3]:
            elem_blocks.append((0, i + 1, 15, [(tag, [i + 1])]))
            tag += 1
    for ci, nodes in enumerate(curve_nodes):
        elems = []
        for i in range(divisions):
            elems.append((tag, [nodes[i], nodes[i + 1]]))
            tag += 1
        elem_blocks.append((1, ci + 1, 1, elems))
    return node_blocks, elem_blocks


def bbox(tower, a, b):
    pa, pb = tower.points[a - 1], tower.points[b - 1]
    return [min(pa[j], pb[j]) for j in range(3)] + [max(pa[j], pb[j]) for j in range(3)]


def num(v):
    """Shortest round-trip text of a float (deterministic), integers without '.0'."""
    return str(int(v)) if float(v).is_integer() and abs(v) < 1e15 else repr(float(v))


def write_ascii(f, tower, node_blocks, elem_blocks):
    w = f.write
    w("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n")
    w("$PhysicalNames\n%d\n" % len(PHYS))
    for dim, tag, name in PHYS:
        w('%d %d "%s"\n' % (dim, tag, name))
    w("$EndPhysicalNames\n")
    w("$Entities\n%d %d 0 0\n" % (len(tower.points), len(tower.curves)))
    for i, (x, y, z, phys) in enumerate(tower.points):
        w(" ".join([str(i + 1), num(x), num(y), num(z), str(len(phys))] + [str(p) for p in phys]) + "\n")
    for i, (a, b, phys) in enumerate(tower.curves):
        fields = [str(i + 1)] + [num(v) for v in bbox(tower, a, b)] + ["1", str(phys), "2", str(a), str(-b)]
        w(" ".join(fields) + "\n")
    w("$EndEntities\n")
    n_nodes = sum(len(nodes) for _, _, nodes in node_blocks)
    w("$Nodes\n%d %d 1 %d\n" % (len(node_blocks), n_nodes, n_nodes))
    for dim, tag, nodes in node_blocks:
        w("%d %d 0 %d\n" % (dim, tag, len(nodes)))
        for t, _ in nodes:
            w("%d\n" % t)
        for _, xyz in nodes:
            w(" ".join(num(v) for v in xyz) + "\n")
    w("$EndNodes\n")
    n_elems = sum(len(e) for _, _, _, e in elem_blocks)
    w("$Elements\n%d %d 1 %d\n" % (len(elem_blocks), n_elems, n_elems))
    for dim, tag, etype, elems in elem_blocks:
        w("%d %d %d %d\n" % (dim, tag, etype, len(elems)))
        for t, nodes in elems:
            w(" ".join(str(v) for v in [t] + nodes) + "\n")
    w("$EndElements\n")


def write_binary(f, tower, node_blocks, elem_blocks):
    """The same content in binary MSH 4.1 (little-endian; size_t 8 bytes, int 4 bytes)."""

    def size_t(*v):
        return struct.pack("<%dQ" % len(v), *v)

    def int_(*v):
        return struct.pack("<%di" % len(v), *v)

    def double(*v):
        return struct.pack("<%dd" % len(v), *v)

    w = f.write
    w(b"$MeshFormat\n4.1 1 8\n" + int_(1) + b"\n$EndMeshFormat\n")
    w(b"$PhysicalNames\n%d\n" % len(PHYS))
    for dim, tag, name in PHYS:
        w(b'%d %d "%s"\n' % (dim, tag, name.encode()))
    w(b"$EndPhysicalNames\n")
    w(b"$Entities\n" + size_t(len(tower.points), len(tower.curves), 0, 0))
    for i, (x, y, z, phys) in enumerate(tower.points):
        w(int_(i + 1) + double(x, y, z) + size_t(len(phys)) + int_(*phys))
    for i, (a, b, phys) in enumerate(tower.curves):
        w(int_(i + 1) + double(*bbox(tower, a, b)) + size_t(1) + int_(phys) + size_t(2) + int_(a, -b))
    w(b"\n$EndEntities\n")
    n_nodes = sum(len(nodes) for _, _, nodes in node_blocks)
    w(b"$Nodes\n" + size_t(len(node_blocks), n_nodes, 1, n_nodes))
    for dim, tag, nodes in node_blocks:
        w(int_(dim, tag, 0) + size_t(len(nodes)))
        w(size_t(*[t for t, _ in nodes]))
        for _, xyz in nodes:
            w(double(*xyz))
    w(b"\n$EndNodes\n")
    n_elems = sum(len(e) for _, _, _, e in elem_blocks)
    w(b"$Elements\n" + size_t(len(elem_blocks), n_elems, 1, n_elems))
    for dim, tag, etype, elems in elem_blocks:
        w(int_(dim, tag, etype) + size_t(len(elems)))
        for t, nodes in elems:
            w(size_t(t, *nodes))
    w(b"\n$EndElements\n")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--storeys", type=int, default=15, help="number of storeys N [15]")
    ap.add_argument("--panels", type=int, default=2, help="panels per storey P [2]")
    ap.add_argument("--width", type=float, default=3.0, help="side W of the square plan, m [3.0]")
    ap.add_argument("--storey-height", type=float, default=6.0, help="storey height H, m [6.0]")
    ap.add_argument("--divisions", type=int, default=3, help="line elements per member D [3]")
    ap.add_argument("--binary", action="store_true", help="write binary MSH 4.1 instead of ASCII")
    ap.add_argument("-o", "--output", default="meshes/tower.msh", help="output file [meshes/tower.msh]")
    a = ap.parse_args(argv)
    for name in ["storeys", "panels", "divisions"]:
        if getattr(a, name) < 1:
            ap.error("--%s must be at least 1" % name)
    if not (a.width > 0 and a.storey_height > 0):
        ap.error("--width and --storey-height must be positive")

    tower = Tower(a.storeys, a.panels, a.width, a.storey_height)
    node_blocks, elem_blocks = build(tower, a.divisions)
    if a.binary:
        with open(a.output, "wb") as f:
            write_binary(f, tower, node_blocks, elem_blocks)
    else:
        with open(a.output, "w", newline="\n") as f:
            write_ascii(f, tower, node_blocks, elem_blocks)

    n_nodes = sum(len(nodes) for _, _, nodes in node_blocks)
    lines = sum(len(e) for _, _, t, e in elem_blocks if t == 1)
    points = sum(len(e) for _, _, t, e in elem_blocks if t == 15)
    members = {tag: sum(1 for c in tower.curves if c[2] == tag) for tag in (LEGS, GIRTS, BRACES)}
    print("wrote %s: %d nodes, %d elements (%d lines, %d points)" % (a.output, n_nodes, lines + points, lines, points))
    print("members: legs %d, girts %d, braces %d; height %s m" % (
        members[LEGS], members[GIRTS], members[BRACES], num(a.storeys * a.storey_height)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
