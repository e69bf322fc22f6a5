#!/usr/bin/env python3
"""Writes the template building's mesh: a two-storey masonry house with a timber floor, meshed
with gmsh's Python API into quadrangles (MSH 4.1, ASCII). The mesh of jobs/template-building.toml;
a starting point for your own building (docs/own-building.md).

Run from the repository root (gmsh, installed by scripts/setup.sh):

    python3 scripts/make_house_mesh.py                          # meshes/house.msh
    python3 scripts/make_house_mesh.py --size 0.5 -o /tmp/h.msh # finer
    python3 scripts/make_house_mesh.py --length 10 --width 6 --storey 3.5   # other dimensions

Geometry (metres, z up; defaults in brackets): the walls' mid-planes on a rectangle of L [8.0]
along x by W [6.0] along y, two storeys of H [3.0]; a timber floor at z = H over the whole plan.

        y ^ north (y = W)                       south elevation (y = 0)
          +-------------------+                 +-------------------+  z = 2H
          |                   |                 |  [w]    [w]   [w] |
     west |      floor        | east            +-------------------+  z = H  (floor)
   (x = 0)|    (z = H)        | (x = L)         |  [w]  [door]  [w] |
          +-------------------+--> x            +-------------------+  z = 0  (base)
            south (y = 0)

Openings: the south facade has a door (1.0 x 2.1 m, a notch in the wall: no support under it)
in the middle of the ground floor and
windows (1.0 x 1.2 m, sill 0.9 m above each storey's floor) at a quarter and three quarters of
its length on both storeys, and the middle upper one; the north facade the same windows without
the door; each gable (east, west) one window per storey in its middle.

Physical groups (the names are free: the job file refers to them):
    surfaces  "south", "north", "east", "west" (the walls, both storeys), "floor";
    curves    "base" (the walls' feet at z = 0: the supports; a curve group works as supports).
The floor's edges are shared with the walls (the surfaces are fragmented), so the floor is
connected to the walls along its whole perimeter.
"""
import argparse
import math
import os
import sys


def parse():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("-o", "--out", default="meshes/house.msh", help="output file [meshes/house.msh]")
    ap.add_argument("--length", type=float, default=8.0, help="plan length along x [m]")
    ap.add_argument("--width", type=float, default=6.0, help="plan width along y [m]")
    ap.add_argument("--storey", type=float, default=3.0, help="storey height [m]")
    ap.add_argument("--size", type=float, default=0.75, help="element size [m]")
    return ap.parse_args()


def openings(facade, length, h):
    """(s, z, width, height) of the openings of a facade, s along its length from its start."""
    win = lambda s, level: (s - 0.5, level * h + 0.9, 1.0, 1.2)
    if facade in ("south", "north"):
        out = [win(length / 4, k) for k in (0, 1)] + [win(3 * length / 4, k) for k in (0, 1)]
        out.append(win(length / 2, 1))
        if facade == "south":
            out.append((length / 2 - 0.5, 0.0, 1.0, 2.1))
        return out
    return [win(length / 2, k) for k in (0, 1)]


def wall(occ, start, direction, length, h, holes):
    """A vertical wall surface from `start` along the unit `direction` (x or y), 2h high, with
    rectangular openings (s, z, w, height): a window is a hole, a door (z = 0) a notch in the
    outline (no wall, and so no support, under it); returns its surface tag."""
    def point(s, z):
        return occ.addPoint(start[0] + s * direction[0], start[1] + s * direction[1], z)

    def loop(corners):
        pts = [point(s, z) for s, z in corners]
        lines = [occ.addLine(pts[k], pts[(k + 1) % len(pts)]) for k in range(len(pts))]
        return occ.addCurveLoop(lines)

    doors = sorted((s, w, ht) for s, z, w, ht in holes if z == 0)
    outline = [(0, 0)]
    for s, w, ht in doors:
        outline += [(s, 0), (s, ht), (s + w, ht), (s + w, 0)]
    outer = loop(outline + [(length, 0), (length, 2 * h), (0, 2 * h)])
    inner = [loop([(s, z), (s + w, z), (s + w, z + ht), (s, z + ht)]) for s, z, w, ht in holes if z > 0]
    return occ.addPlaneSurface([outer] + inner)


def main():
    a = parse()
    try:
        import gmsh
    except ImportError:
        sys.exit("make_house_mesh.py needs gmsh's Python API: scripts/setup.sh installs it (pip install gmsh)")
    L, W, H = a.length, a.width, a.storey
    gmsh.initialize(["-noenv"])
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.model.add("house")
    occ = gmsh.model.occ
    walls = {
        "south": wall(occ, (0, 0), (1, 0), L, H, openings("south", L, H)),
        "north": wall(occ, (0, W), (1, 0), L, H, openings("north", L, H)),
        "west": wall(occ, (0, 0), (0, 1), W, H, openings("west", W, H)),
        "east": wall(occ, (L, 0), (0, 1), W, H, openings("east", W, H)),
    }
    floor = occ.addRectangle(0, 0, H, L, W)
    occ.fragment([(2, t) for t in walls.values()] + [(2, floor)], [])
    occ.synchronize()

    # Classify the fragments by their centre of mass.
    groups = {name: [] for name in ["south", "north", "west", "east", "floor"]}
    eps = 1e-6
    for _, tag in gmsh.model.getEntities(2):
        x, y, z = occ.getCenterOfMass(2, tag)
        xmin, ymin, zmin, xmax, ymax, zmax = gmsh.model.getBoundingBox(2, tag)
        if zmax - zmin < eps:
            groups["floor"].append(tag)
        elif ymax - ymin < eps:
            groups["south" if abs(y) < eps else "north"].append(tag)
        else:
            groups["west" if abs(x) < eps else "east"].append(tag)
    base = []
    for _, tag in gmsh.model.getEntities(1):
        xmin, ymin, zmin, xmax, ymax, zmax = gmsh.model.getBoundingBox(1, tag)
        if zmax < eps:
            base.append(tag)
    for k, (name, tags) in enumerate(groups.items()):
        gmsh.model.addPhysicalGroup(2, tags, k + 1, name)
    gmsh.model.addPhysicalGroup(1, base, len(groups) + 1, "base")

    gmsh.option.setNumber("Mesh.MeshSizeMin", a.size)
    gmsh.option.setNumber("Mesh.MeshSizeMax", a.size)
    gmsh.option.setNumber("Mesh.Algorithm", 8)          # frontal-Delaunay for quads
    gmsh.option.setNumber("Mesh.RecombineAll", 1)
    gmsh.option.setNumber("Mesh.RecombinationAlgorithm", 1)  # blossom
    gmsh.option.setNumber("Mesh.Smoothing", 5)
    gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
    gmsh.option.setNumber("Mesh.Binary", 0)
    gmsh.model.mesh.generate(2)
    os.makedirs(os.path.dirname(os.path.abspath(a.out)), exist_ok=True)
    gmsh.write(a.out)
    types, tags, _ = gmsh.model.mesh.getElements(2)
    counts = {gmsh.model.mesh.getElementProperties(t)[0]: len(e) for t, e in zip(types, tags)}
    nodes = len(gmsh.model.mesh.getNodes()[0])
    gmsh.finalize()
    area = 2 * (L + W) * 2 * H + L * W
    print(f"{a.out}: {nodes} nodes, " + ", ".join(f"{n} {k}" for k, n in counts.items())
          + f"; {L} x {W} m, 2 storeys of {H} m, about {area:.0f} m^2 of walls and floor")


if __name__ == "__main__":
    main()
