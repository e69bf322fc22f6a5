#!/usr/bin/env python3
"""Writes the parametric model of Notre-Dame de la Gorge (Les Contamines-Montjoie, 1699-1701) as
a Gmsh MSH 4.1 mesh of shells (3-node triangles, 4-node quads) and beams (2-node lines).

Run from the repository root (Python 3 with `gmsh` from PyPI, `scripts/setup.sh` installs it):

    python3 scripts/make_church_mesh.py                       # meshes/church.msh (coarse default)
    python3 scripts/make_church_mesh.py --fine                # meshes/church-fine.msh (clusters)
    python3 scripts/make_church_mesh.py --size 0.5 -o /tmp/church-h05.msh   # any element size
    python3 scripts/make_church_mesh.py --check meshes/church.msh            # only the checks

The script builds the geometry with the OpenCASCADE kernel, glues every surface and curve with
one `fragment` (so walls, vaults, the tribune, the tower and the beams share nodes at every
junction), meshes it (quads by recombination, structured quads on the vaults), writes it and
then reads the written file back and checks it (see `check()`): no duplicate nodes, no hanging
nodes on element edges, one connected piece, no node outside the elements, beam ends attached,
flat enough quads for the shell element (warping ratio below the solver's 0.05), the expected
physical groups. It prints the statistics and exits non-zero if a check fails.

Deterministic: fixed options, one thread, nodes and elements renumbered; the same arguments
and the same gmsh version (GMSH_VERSION, pinned by scripts/setup.sh) give the same bytes (a test
regenerates the coarse mesh and compares).

Axes: x along the nave axis from the entrance facade (x = 0) to the east end, y across (+y is
the tower side, north), z up from the nave floor. Metres. All dimensions are those of the wall
MID-SURFACES (the shells' reference planes), not of the clear interior.

ASSUMED DIMENSIONS. The paper (and paper §4) publishes none; they are assumed from the paper's
description, typical Savoyard baroque churches of this size and the site's photographs:

  Nave (single nave, four bays)
    NAVE_LENGTH     = 20.0   facade axis to the nave-choir (triumphal arch) wall axis; ~20 m long
    NAVE_WIDTH      = 10.8   wall axis to wall axis: ~9.9 m clear + one 0.9 m wall thickness
    NAVE_EAVES      =  9.0   top of the side walls (eaves), ~9 m
    BAYS            =  4     four 5 m bays, separated by transverse arches on pilasters
    NAVE_SPRINGING  =  7.5   the barrel vault springs 1.5 m below the eaves (haunch walls above)
    NAVE_RISE       =  3.0   segmental vault: crown at 10.5 m (inside the roof space)
    NAVE_RIDGE      = 13.5   facade and east gables; roof pitch ~40° (4.5 m over 5.4 m)
    OVERHANG        =  1.5   the roof's cantilever over the entrance (purlins beyond the facade)
  Tribune (gallery) over the first bay
    TRIBUNE_DEPTH   =  5.0   the first bay; slab at TRIBUNE_Z = 3.5 (under the windows)
  Choir and sacristy: 3.5 m narrower than the nave, three steps (0.5 m) higher, lower roof
    CHOIR_WIDTH     =  7.3   NAVE_WIDTH - 3.5 (the paper: "3.5 m narrower")
    CHOIR_FLOOR     =  0.5   three steps of ~0.17 m; the choir walls' base (the ground rises
                             >15 % towards the choir)
    CHOIR_LENGTH    =  7.0   triumphal arch wall to the choir-sacristy wall
    SACRISTY_LENGTH =  4.0   behind the choir, same width, under the same roof
    CHOIR_EAVES     =  7.0   lower walls than the nave's
    CHOIR_SPRINGING =  5.5, CHOIR_RISE = 2.5 (crown at 8.0 m, 1 m below the nave's eaves: the
                             choir opening fits under the nave vault's end arch)
    CHOIR_RIDGE     = 10.0   lower roof than the nave's (ridge 3.5 m below)
  Bell tower along the nave, north side, against the last bay
    TOWER_X0        = 15.0   TOWER_SIDE = 5.0 (square, wall axis to wall axis), its east wall in
                             the plane of the triumphal-arch wall; the nave's north wall is its
                             south wall up to the eaves
    TOWER_TOP       = 22.0   top of the masonry; belfry posts 3 m, onion to TOWER_SPIRE = 29.5
  Openings
    door 2.0 x 3.0 in the facade; a round window (r = 0.7 m) in the facade at z = 5.8;
    nave windows 1.2 x 2.0 (sill 4.5) in every bay (not under the tower); choir windows
    1.0 x 2.0 (sill 2.5); a sacristy window 0.8 x 1.2; a door 1.0 x 2.2 between choir and
    sacristy; belfry openings 1.4 x 2.5 (sill 18.0) in the four tower walls.
  Beams
    arches      transverse arches at the bay divisions (x = 5, 10, 15) along the vault and the
                triumphal arch around the choir opening (x = 20);
    pilasters   under the arches, floor to springing, on both nave walls, and the two jambs of
                the triumphal arch;
    buttresses  the facade corners, the nave's south-east corner and the sacristy's east corners
                (vertical, on the wall corner edges);
    timber, in three kinds of groups:
    trusses     the roof trusses (rafters at x = 5, 10, 15 over the nave, 23.5 and 27 over the
                choir);
    nave_purlins, choir_purlins
                the purlins (ridge and mid-slope) of the nave roof (with the overhang) and of
                the choir-sacristy roof: they carry the roof covering, whose mass the jobs give
                them per length (the two roofs' purlins carry different widths of roof, hence
                two groups; see jobs/church.toml);
    belfry      the belfry posts and ring and the onion's ribs.
  The thrust path of the nave vault (ASSUMED, as the usual construction of such vaults; the
  paper describes none): the masonry alone cannot carry a 10.8 m vault's thrust of about 24 kN
  per metre of wall (jobs/church.toml's header) by the walls' bending:
    nave_ties   iron tie rods across the nave at the springing (TIE_Z = NAVE_SPRINGING) of the
                three transverse arches (x = 5, 10, 15), each one 2-node element from wall axis
                to wall axis, anchored in the walls at the arches' springing nodes (the jobs give
                their section: 40 x 40 mm wrought iron);
    nave_haunches  the vault's two bands from the springings up to HAUNCH_FILL_TOP =
                NAVE_SPRINGING + NAVE_RISE / 2 = 9.0 m: the fill (rinfianco) over the haunches
                reaches half the rise, up to the eaves; the bands are the vault (the same shell),
                as a group of their own so that the jobs can give them the fill's mass (between
                the extrados and the walls' inner face: 0.209 m^2 per metre per side).
  Wall thicknesses (used by the jobs, not by the mesh): facade 1.0, nave walls 0.9, choir
  walls 0.8, sacristy 0.6, tower 1.0, vaults 0.25 (nave) 0.2 (choir), tribune 0.3.

Physical groups: surfaces facade, nave_walls, choir_walls, sacristy, tower, nave_vault,
choir_vault, tribune, nave_haunches; curves arches, pilasters, buttresses, nave_purlins,
choir_purlins, trusses, belfry, nave_ties; curves "supports" (the wall bases at the foundation,
z = 0 for the nave and tower, z = 0.5 for the choir and sacristy). The physical tags number SURFACE_GROUPS, then
CURVE_GROUPS, in their order (supports = 14); the jobs and the scripts refer to groups by name.

Roof geometry the jobs need for the covering's mass (the purlins' tributary widths): nave roof
slope length sqrt(5.4^2 + 4.5^2) = 7.03 m per side over 21.5 m (with the overhang), three
purlins sharing the two slopes (4.69 m each); choir-sacristy roof sqrt(3.65^2 + 3.0^2) = 4.72 m
per side over 11 m, three purlins (3.15 m each).
Every mesh entity is in at most one group, so a job maps each group to one part.

Mesh: element size SIZE (coarse 0.85 m, fine 0.22 m); vaults structured (quads between two
generators of the cylinder are exactly flat); walls unstructured, recombined into quads (a few
triangles remain). The coarse mesh (3,218 nodes, 19,308 DOF) is sized for a 22 s nonlinear
earthquake run on 2 cores; the fine one (36,688 nodes, 220,128 DOF, 2.8 MB) for clusters.
"""
import argparse
import math
import os
import sys
import time

# ---------------------------------------------------------------- assumed dimensions (see above)
NAVE_LENGTH = 20.0
NAVE_WIDTH = 10.8
NAVE_EAVES = 9.0
BAYS = 4
NAVE_SPRINGING = 7.5
NAVE_RISE = 3.0
NAVE_RIDGE = 13.5
OVERHANG = 1.5
TRIBUNE_DEPTH = 5.0
TRIBUNE_Z = 3.5
CHOIR_WIDTH = NAVE_WIDTH - 3.5
CHOIR_FLOOR = 0.5
CHOIR_LENGTH = 7.0
SACRISTY_LENGTH = 4.0
CHOIR_EAVES = 7.0
CHOIR_SPRINGING = 5.5
CHOIR_RISE = 2.5
CHOIR_RIDGE = 10.0
TOWER_X0 = 15.0
TOWER_SIDE = 5.0
TOWER_TOP = 22.0
BELFRY_POSTS = 3.0
TOWER_SPIRE = 29.5
DOOR = (2.0, 3.0)                 # width, height
ROUND_WINDOW = (5.8, 0.7)         # centre height, radius
NAVE_WINDOW = (1.2, 4.5, 6.5)     # width, sill, head
CHOIR_WINDOW = (1.0, 2.5, 4.5)
SACRISTY_WINDOW = (0.8, 2.5, 3.7)
SACRISTY_DOOR = (1.0, 2.2, 2.0)   # width, height, centre y
BELFRY_OPENING = (1.4, 18.0, 20.5)

# The thrust path (see the module docs): ASSUMED
TIE_Z = NAVE_SPRINGING            # tie rods at the springing of each transverse arch
HAUNCH_FILL_TOP = NAVE_SPRINGING + NAVE_RISE / 2   # the haunch fill (rinfianco) up to half the rise

# The gmsh version that wrote the committed meshes (another version may mesh differently).
GMSH_VERSION = "4.15.2"

COARSE_SIZE = 0.85
FINE_SIZE = 0.22

SURFACE_GROUPS = ["facade", "nave_walls", "choir_walls", "sacristy", "tower", "nave_vault", "choir_vault", "tribune",
                  "nave_haunches"]
# New groups go at the ends of the lists.
CURVE_GROUPS = ["arches", "pilasters", "buttresses", "nave_purlins", "supports", "choir_purlins", "trusses", "belfry",
                "nave_ties"]

# Derived positions
HW = NAVE_WIDTH / 2          # nave half width (wall axes at y = ±HW)
CW = CHOIR_WIDTH / 2         # choir half width
XE = NAVE_LENGTH             # triumphal-arch wall
XS = XE + CHOIR_LENGTH       # choir-sacristy wall
XEND = XS + SACRISTY_LENGTH  # east end wall
TY0, TY1 = HW, HW + TOWER_SIDE
TX0, TX1 = TOWER_X0, TOWER_X0 + TOWER_SIDE


def segmental_arc(half_span, springing, rise):
    """Radius and centre height of the circular arc through (±half_span, springing) and the crown
    (0, springing + rise): R = (c² + f²) / (2 f), centre at crown − R."""
    r = (half_span ** 2 + rise ** 2) / (2 * rise)
    return r, springing + rise - r


class Builder:
    """Collects the OCC entities of each group before the fragment."""

    def __init__(self, occ):
        self.occ = occ
        self.inputs = []  # (dim, tag, group)

    def point(self, p):
        return self.occ.addPoint(*p)

    def polyline_loop(self, pts):
        tags = [self.point(p) for p in pts]
        lines = [self.occ.addLine(tags[i], tags[(i + 1) % len(tags)]) for i in range(len(tags))]
        return self.occ.addCurveLoop(lines)

    def polygon(self, pts):
        return self.occ.addPlaneSurface([self.polyline_loop(pts)])

    def wall(self, group, outline, holes=(), round_holes=()):
        """A plane wall: outline polygon minus rectangular/polygonal holes and disks."""
        face = self.polygon(outline)
        tools = [(2, self.polygon(h)) for h in holes]
        for centre, r, normal in round_holes:
            tools.append((2, self.occ.addDisk(*centre, r, r, zAxis=normal, xAxis=_perp(normal))))
        if tools:
            out, _ = self.occ.cut([(2, face)], tools)
            for d, t in out:
                self.inputs.append((d, t, group))
        else:
            self.inputs.append((2, face, group))

    def face(self, group, tag):
        self.inputs.append((2, tag, group))

    def line(self, group, a, b):
        self.inputs.append((1, self.occ.addLine(self.point(a), self.point(b)), group))

    def polyline(self, group, pts):
        for a, b in zip(pts, pts[1:]):
            self.line(group, a, b)

    def arc(self, group, a, centre, b):
        t = self.occ.addCircleArc(self.point(a), self.point(centre), self.point(b))
        self.inputs.append((1, t, group))
        return t


def _perp(n):
    return [0.0, 1.0, 0.0] if abs(n[1]) < 0.9 else [1.0, 0.0, 0.0]


def rect_yz(x, y0, y1, z0, z1):
    return [(x, y0, z0), (x, y1, z0), (x, y1, z1), (x, y0, z1)]


def rect_xz(y, x0, x1, z0, z1):
    return [(x0, y, z0), (x1, y, z0), (x1, y, z1), (x0, y, z1)]


def vault(b, group, x0, x1, half, springing, rise, n_pieces, haunches=None):
    """A segmental barrel vault over x0..x1 in n_pieces extrusions; returns, for each piece end
    (x0, ..., x1), the tags of the arcs there, so arches can be placed on them. With
    `haunches = (group, z)`, the vault's two bands below the height z (from the springings up)
    are that group's, the crown between them `group`'s."""
    occ = b.occ
    r, zc = segmental_arc(half, springing, rise)
    c = occ.addPoint(x0, 0, zc)
    if haunches is None:
        ys, groups = [-half, half], [group]
    else:
        y_split = math.sqrt(r * r - (haunches[1] - zc) ** 2)
        ys, groups = [-half, -y_split, y_split, half], [haunches[0], group, haunches[0]]
    pts = [occ.addPoint(x0, y, zc + math.sqrt(r * r - y * y)) for y in ys]
    station = [occ.addCircleArc(pts[i], c, pts[i + 1]) for i in range(len(groups))]
    stations = [station]
    dx = (x1 - x0) / n_pieces
    for _ in range(n_pieces):
        nxt = []
        for arc, g in zip(station, groups):
            out = occ.extrude([(1, arc)], dx, 0, 0)
            b.face(g, [t for d, t in out if d == 2][0])
            nxt.append(out[0][1])  # the top (translated) curve comes first
        station = nxt
        stations.append(station)
    return stations


def build(occ):
    b = Builder(occ)
    nr, nzc = segmental_arc(HW, NAVE_SPRINGING, NAVE_RISE)
    cr, czc = segmental_arc(CW, CHOIR_SPRINGING, CHOIR_RISE)

    # --- facade (x = 0): pentagon with its gable, the door and the round window
    dw, dh = DOOR
    b.wall(
        "facade",
        [(0, -HW, 0), (0, -dw / 2, 0), (0, -dw / 2, dh), (0, dw / 2, dh), (0, dw / 2, 0), (0, HW, 0),
         (0, HW, NAVE_EAVES), (0, 0, NAVE_RIDGE), (0, -HW, NAVE_EAVES)],
        round_holes=[((0, 0, ROUND_WINDOW[0]), ROUND_WINDOW[1], [1.0, 0.0, 0.0])],
    )
    # --- nave side walls (y = ±HW), windows in each bay (none under the tower)
    ww, ws, wh = NAVE_WINDOW
    bay = NAVE_LENGTH / BAYS
    for side in (-1, 1):
        holes = []
        for k in range(BAYS):
            xc = (k + 0.5) * bay
            if side > 0 and TX0 <= xc <= TX1:
                continue
            holes.append(rect_xz(side * HW, xc - ww / 2, xc + ww / 2, ws, wh))
        b.wall("nave_walls", rect_xz(side * HW, 0, NAVE_LENGTH, 0, NAVE_EAVES), holes)
    # --- triumphal-arch wall (x = XE) with its gable; the choir opening (vault profile) cut out
    east = b.polyline_loop([(XE, -HW, 0), (XE, HW, 0), (XE, HW, NAVE_EAVES), (XE, 0, NAVE_RIDGE), (XE, -HW, NAVE_EAVES)])
    q = [b.point(p) for p in [(XE, -CW, CHOIR_FLOOR), (XE, CW, CHOIR_FLOOR), (XE, CW, CHOIR_SPRINGING), (XE, -CW, CHOIR_SPRINGING)]]
    qc = b.point((XE, 0, czc))
    hole = occ.addCurveLoop([occ.addLine(q[0], q[1]), occ.addLine(q[1], q[2]), occ.addCircleArc(q[2], qc, q[3]), occ.addLine(q[3], q[0])])
    b.face("nave_walls", occ.addPlaneSurface([east, hole]))
    # --- nave vault, four bays; transverse arches at the bay divisions
    stations = vault(b, "nave_vault", 0.0, NAVE_LENGTH, HW, NAVE_SPRINGING, NAVE_RISE, BAYS,
                     haunches=("nave_haunches", HAUNCH_FILL_TOP))
    for station in stations[1:-1]:
        for a in station:
            b.inputs.append((1, a, "arches"))
    # --- iron tie rods across the nave at the springing of each transverse arch
    for k in range(1, BAYS):
        b.line("nave_ties", (k * bay, -HW, TIE_Z), (k * bay, HW, TIE_Z))
    # --- tribune over the first bay
    b.face("tribune", b.polygon([(0, -HW, TRIBUNE_Z), (TRIBUNE_DEPTH, -HW, TRIBUNE_Z), (TRIBUNE_DEPTH, HW, TRIBUNE_Z), (0, HW, TRIBUNE_Z)]))
    # --- choir walls: the two side walls and the wall to the sacristy (door, top = vault profile)
    cw, cs, ch = CHOIR_WINDOW
    for side in (-1, 1):
        xc = (XE + XS) / 2
        b.wall("choir_walls", rect_xz(side * CW, XE, XS, CHOIR_FLOOR, CHOIR_EAVES), [rect_xz(side * CW, xc - cw / 2, xc + cw / 2, cs, ch)])
    pw = [b.point(p) for p in [(XS, -CW, CHOIR_FLOOR), (XS, CW, CHOIR_FLOOR), (XS, CW, CHOIR_SPRINGING), (XS, -CW, CHOIR_SPRINGING)]]
    pc = b.point((XS, 0, czc))
    loop = occ.addCurveLoop([occ.addLine(pw[0], pw[1]), occ.addLine(pw[1], pw[2]), occ.addCircleArc(pw[2], pc, pw[3]), occ.addLine(pw[3], pw[0])])
    part = occ.addPlaneSurface([loop])
    sw, sh, sy = SACRISTY_DOOR
    door = b.polygon(rect_yz(XS, sy - sw / 2, sy + sw / 2, CHOIR_FLOOR, CHOIR_FLOOR + sh))
    out, _ = occ.cut([(2, part)], [(2, door)])
    for d, t in out:
        b.face("choir_walls", t)
    # choir vault; the triumphal arch around the opening
    cstations = vault(b, "choir_vault", XE, XS, CW, CHOIR_SPRINGING, CHOIR_RISE, 1)
    b.inputs.append((1, cstations[0][0], "arches"))
    # --- sacristy: side walls, east wall with gable, its vault
    xw, xs_, xh = SACRISTY_WINDOW
    for side in (-1, 1):
        holes = [rect_xz(side * CW, (XS + XEND) / 2 - xw / 2, (XS + XEND) / 2 + xw / 2, xs_, xh)] if side < 0 else []
        b.wall("sacristy", rect_xz(side * CW, XS, XEND, CHOIR_FLOOR, CHOIR_EAVES), holes)
    b.wall("sacristy", [(XEND, -CW, CHOIR_FLOOR), (XEND, CW, CHOIR_FLOOR), (XEND, CW, CHOIR_EAVES), (XEND, 0, CHOIR_RIDGE), (XEND, -CW, CHOIR_EAVES)])
    vault(b, "sacristy", XS, XEND, CW, CHOIR_SPRINGING, CHOIR_RISE, 1)
    # --- tower: west, north, east walls from the ground; south wall above the nave eaves
    bw, bs, bh = BELFRY_OPENING
    txc, tyc = (TX0 + TX1) / 2, (TY0 + TY1) / 2
    b.wall("tower", rect_yz(TX0, TY0, TY1, 0, TOWER_TOP), [rect_yz(TX0, tyc - bw / 2, tyc + bw / 2, bs, bh)])
    b.wall("tower", rect_yz(TX1, TY0, TY1, 0, TOWER_TOP), [rect_yz(TX1, tyc - bw / 2, tyc + bw / 2, bs, bh)])
    b.wall("tower", rect_xz(TY1, TX0, TX1, 0, TOWER_TOP), [rect_xz(TY1, txc - bw / 2, txc + bw / 2, bs, bh)])
    b.wall("tower", rect_xz(TY0, TX0, TX1, NAVE_EAVES, TOWER_TOP), [rect_xz(TY0, txc - bw / 2, txc + bw / 2, bs, bh)])

    # --- pilasters (floor to springing) under the arches; the triumphal arch's jambs
    for k in range(1, BAYS):
        for side in (-1, 1):
            b.line("pilasters", (k * bay, side * HW, 0), (k * bay, side * HW, NAVE_SPRINGING))
    for side in (-1, 1):
        b.line("pilasters", (XE, side * CW, CHOIR_FLOOR), (XE, side * CW, CHOIR_SPRINGING))
    # --- buttresses on the corner edges
    for side in (-1, 1):
        b.line("buttresses", (0, side * HW, 0), (0, side * HW, NAVE_EAVES))
        b.line("buttresses", (XEND, side * CW, CHOIR_FLOOR), (XEND, side * CW, CHOIR_EAVES))
    b.line("buttresses", (XE, -HW, 0), (XE, -HW, NAVE_EAVES))
    # --- timber: nave trusses (rafters) and purlins (which carry the covering) with the overhang
    def rafter_z(y, half, eaves, ridge):
        return eaves + (ridge - eaves) * (1 - abs(y) / half)
    for k in range(1, BAYS):
        x = k * bay
        for side in (-1, 1):
            b.polyline("trusses", [(x, side * HW, NAVE_EAVES), (x, side * HW / 2, rafter_z(HW / 2, HW, NAVE_EAVES, NAVE_RIDGE)), (x, 0, NAVE_RIDGE)])
    for y in (-HW / 2, 0.0, HW / 2):
        z = rafter_z(y, HW, NAVE_EAVES, NAVE_RIDGE)
        b.line("nave_purlins", (-OVERHANG, y, z), (NAVE_LENGTH, y, z))
    # choir-sacristy roof: trusses at mid-choir and on the choir-sacristy wall, purlins to the end gable
    for x in ((XE + XS) / 2, XS):
        for side in (-1, 1):
            b.polyline("trusses", [(x, side * CW, CHOIR_EAVES), (x, side * CW / 2, rafter_z(CW / 2, CW, CHOIR_EAVES, CHOIR_RIDGE)), (x, 0, CHOIR_RIDGE)])
    for y in (-CW / 2, 0.0, CW / 2):
        z = rafter_z(y, CW, CHOIR_EAVES, CHOIR_RIDGE)
        b.line("choir_purlins", (XE, y, z), (XEND, y, z))
    # belfry: posts on the tower corners, a ring, the onion's ribs (bulge, neck, spire)
    corners = [(TX0, TY0), (TX1, TY0), (TX1, TY1), (TX0, TY1)]
    top = TOWER_TOP + BELFRY_POSTS
    z_bulge, z_neck = top + 1.2, top + 3.0
    for i, (x, y) in enumerate(corners):
        xn, yn = corners[(i + 1) % 4]
        b.line("belfry", (x, y, TOWER_TOP), (x, y, top))
        b.line("belfry", (x, y, top), (xn, yn, top))
        bulge = lambda px, py: (txc + 1.2 * (px - txc), tyc + 1.2 * (py - tyc), z_bulge)
        b.line("belfry", bulge(x, y), bulge(xn, yn))
        b.polyline("belfry", [(x, y, top), bulge(x, y), (txc + 0.3 * (x - txc), tyc + 0.3 * (y - tyc), z_neck), (txc, tyc, TOWER_SPIRE)])
    # --- supports: the wall bases at the foundation
    b.line("supports", (0, -HW, 0), (0, -dw / 2, 0))
    b.line("supports", (0, dw / 2, 0), (0, HW, 0))
    for side in (-1, 1):
        b.line("supports", (0, side * HW, 0), (NAVE_LENGTH, side * HW, 0))
        b.line("supports", (XE, side * CW, CHOIR_FLOOR), (XEND, side * CW, CHOIR_FLOOR))
    b.line("supports", (XE, -HW, 0), (XE, HW, 0))
    b.line("supports", (XS, -CW, CHOIR_FLOOR), (XS, SACRISTY_DOOR[2] - SACRISTY_DOOR[0] / 2, CHOIR_FLOOR))
    b.line("supports", (XS, SACRISTY_DOOR[2] + SACRISTY_DOOR[0] / 2, CHOIR_FLOOR), (XS, CW, CHOIR_FLOOR))
    b.line("supports", (XEND, -CW, CHOIR_FLOOR), (XEND, CW, CHOIR_FLOOR))
    b.line("supports", (TX0, TY0, 0), (TX0, TY1, 0))
    b.line("supports", (TX0, TY1, 0), (TX1, TY1, 0))
    b.line("supports", (TX1, TY1, 0), (TX1, TY0, 0))
    return b


def generate(size, path, binary, glue=True):
    import gmsh

    if gmsh.__version__ != GMSH_VERSION:
        print(f"note: gmsh {gmsh.__version__}; the committed meshes were written by gmsh {GMSH_VERSION} "
              "(the mesh may differ from them)", file=sys.stderr)
    gmsh.initialize(readConfigFiles=False)
    try:
        for k, v in [("General.Terminal", 0), ("General.NumThreads", 1), ("Mesh.MaxNumThreads1D", 1),
                     ("Mesh.MaxNumThreads2D", 1), ("Geometry.OCCParallel", 0), ("Geometry.Tolerance", 1e-8),
                     ("Geometry.ToleranceBoolean", 1e-6)]:
            gmsh.option.setNumber(k, v)
        gmsh.model.add("ndg")
        occ = gmsh.model.occ
        b = build(occ)
        objects = [(d, t) for d, t, _ in b.inputs]
        if glue:
            _, children = occ.fragment(objects, [])
        else:  # each entity meshed on its own: only for showing that check() catches it
            children = [[dt] for dt in objects]
        occ.synchronize()
        # group of every output entity; an entity claimed by two groups is a modelling error
        owner = {}
        for (d, t, g), kids in zip(b.inputs, children):
            for dk, tk in kids:
                prev = owner.get((dk, tk))
                if prev is not None and prev != g:
                    raise SystemExit(f"entity {(dk, tk)} belongs to both '{prev}' and '{g}'")
                owner[(dk, tk)] = g
        for d, names in ((2, SURFACE_GROUPS), (1, CURVE_GROUPS)):
            for g in names:
                tags = sorted(t for (dk, t), gg in owner.items() if dk == d and gg == g)
                if not tags:
                    raise SystemExit(f"group '{g}' is empty")
                gmsh.model.addPhysicalGroup(d, tags, name=g)

        # mesh: structured vaults (4-sided patches), recombined walls
        mesh = gmsh.model.mesh
        for k, v in [("Mesh.MeshSizeMax", size), ("Mesh.MeshSizeMin", size / 5), ("Mesh.MeshSizeFromCurvature", 0),
                     ("Mesh.MeshSizeExtendFromBoundary", 1), ("Mesh.MeshSizeFromPoints", 0), ("Mesh.Algorithm", 8),
                     ("Mesh.RecombineAll", 1), ("Mesh.RecombinationAlgorithm", 1), ("Mesh.ElementOrder", 1),
                     ("Mesh.RandomSeed", 1), ("Mesh.MshFileVersion", 4.1), ("Mesh.Binary", 1 if binary else 0),
                     ("Mesh.SaveAll", 0)]:
            gmsh.option.setNumber(k, v)
        for (d, t), g in sorted(owner.items()):
            if d == 2 and g in ("nave_vault", "nave_haunches", "choir_vault", "sacristy") and _is_vault(gmsh, t):
                bnd = gmsh.model.getBoundary([(2, t)], oriented=False)
                if len(bnd) != 4:
                    continue
                for _, c in bnd:
                    n = max(1, round(_curve_length(gmsh, c) / size))
                    mesh.setTransfiniteCurve(c, n + 1)
                mesh.setTransfiniteSurface(t)
        # a tie rod is one 2-node element from anchor to anchor (its inner nodes would be free)
        for (d, t), g in sorted(owner.items()):
            if d == 1 and g == "nave_ties":
                mesh.setTransfiniteCurve(t, 2)
        mesh.generate(2)
        mesh.renumberNodes()
        mesh.renumberElements()
        os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
        gmsh.write(path)
    finally:
        gmsh.finalize()


def _is_vault(gmsh, t):
    return gmsh.model.getType(2, t) != "Plane"


def _curve_length(gmsh, c):
    lo, hi = gmsh.model.getParametrizationBounds(1, c)
    n = 64
    ts = [lo[0] + (hi[0] - lo[0]) * i / n for i in range(n + 1)]
    xyz = gmsh.model.getValue(1, c, ts)
    return sum(math.dist(xyz[3 * i:3 * i + 3], xyz[3 * i + 3:3 * i + 6]) for i in range(n))


# ----------------------------------------------------------------------------------- the checks
def read_back(path):
    """Nodes and elements of the written file, by physical group (through gmsh's reader)."""
    import gmsh

    gmsh.initialize(readConfigFiles=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.open(path)
        tags, xyz, _ = gmsh.model.mesh.getNodes()
        coords = {int(t): tuple(xyz[3 * i:3 * i + 3]) for i, t in enumerate(tags)}
        groups = {}
        for d, p in gmsh.model.getPhysicalGroups():
            name = gmsh.model.getPhysicalName(d, p)
            cells = []
            for e in gmsh.model.getEntitiesForPhysicalGroup(d, p):
                types, etags, enodes = gmsh.model.mesh.getElements(d, e)
                for ty, et, en in zip(types, etags, enodes):
                    nn = gmsh.model.mesh.getElementProperties(ty)[3]
                    for i, tag in enumerate(et):
                        cells.append((int(tag), tuple(int(x) for x in en[nn * i:nn * (i + 1)])))
            groups[name] = (d, cells)
        return coords, groups
    finally:
        gmsh.finalize()


def check(path):
    """Checks the written mesh; returns (statistics, list of failures)."""
    coords, groups = read_back(path)
    fails = []
    expected = set(SURFACE_GROUPS) | set(CURVE_GROUPS)
    if set(groups) != expected:
        fails.append(f"physical groups {sorted(groups)} differ from {sorted(expected)}")
    for g in SURFACE_GROUPS:
        if g in groups and groups[g][0] != 2:
            fails.append(f"group {g} is not a surface group")
    for g in CURVE_GROUPS:
        if g in groups and groups[g][0] != 1:
            fails.append(f"group {g} is not a curve group")
    shells = [nodes for g in SURFACE_GROUPS if g in groups for _, nodes in groups[g][1]]
    beams = [nodes for g in CURVE_GROUPS if g in groups and g != "supports" for _, nodes in groups[g][1]]
    # an element in two groups
    seen = {}
    for g, (d, cells) in groups.items():
        for tag, _ in cells:
            if tag in seen:
                fails.append(f"element {tag} is in groups {seen[tag]} and {g}")
            seen[tag] = g
    # 1. duplicate nodes: two nodes closer than 1e-6 m
    tol = 1e-6
    grid = {}
    for t, x in coords.items():
        grid.setdefault(tuple(round(c / 1e-3) for c in x), []).append(t)
    dups = 0
    for key, ts in grid.items():
        cand = [u for dk in _neigh(key) for u in grid.get(dk, [])]
        for t in ts:
            for u in cand:
                if u > t and math.dist(coords[t], coords[u]) < tol:
                    dups += 1
    if dups:
        fails.append(f"{dups} pairs of duplicate nodes (closer than {tol} m)")
    # 2. every node in an element; no degenerate element
    used = set(n for c in shells + beams for n in c)
    orphans = set(coords) - used
    if orphans:
        fails.append(f"{len(orphans)} nodes belong to no shell or beam element (e.g. {sorted(orphans)[:5]})")
    for c in shells + beams:
        if len(set(c)) != len(c):
            fails.append(f"degenerate element with nodes {c}")
    # 3. hanging nodes: a node lying inside an element edge that is used by one shell only
    edge_count = {}
    for c in shells:
        for i in range(len(c)):
            e = tuple(sorted((c[i], c[(i + 1) % len(c)])))
            edge_count[e] = edge_count.get(e, 0) + 1
    free_edges = [e for e, k in edge_count.items() if k == 1]
    coarse = {}
    for t, x in coords.items():
        coarse.setdefault(tuple(math.floor(c) for c in x), []).append(t)
    hanging = 0
    for a, bb in free_edges + [tuple(sorted(c)) for c in beams]:
        pa, pb = coords[a], coords[bb]
        lo = [min(pa[i], pb[i]) - 1e-6 for i in range(3)]
        hi = [max(pa[i], pb[i]) + 1e-6 for i in range(3)]
        length = math.dist(pa, pb)
        for key in _box(lo, hi):
            for t in coarse.get(key, []):
                if t in (a, bb):
                    continue
                p = coords[t]
                if not all(lo[i] <= p[i] <= hi[i] for i in range(3)):
                    continue
                # distance from p to the segment
                u = [pb[i] - pa[i] for i in range(3)]
                w = [p[i] - pa[i] for i in range(3)]
                s = sum(u[i] * w[i] for i in range(3)) / (length * length)
                if 0 < s < 1:
                    d = math.dist(p, [pa[i] + s * u[i] for i in range(3)])
                    if d < 1e-6 * max(1.0, length):
                        hanging += 1
    if hanging:
        fails.append(f"{hanging} hanging nodes on element edges (non-conforming junctions)")
    # 4. one connected piece (shells and beams through shared nodes)
    parent = {n: n for n in used}

    def find(n):
        while parent[n] != n:
            parent[n] = parent[parent[n]]
            n = parent[n]
        return n

    for c in shells + beams:
        r0 = find(c[0])
        for n in c[1:]:
            r = find(n)
            if r != r0:
                parent[r] = r0
    pieces = len(set(find(n) for n in used))
    if pieces != 1:
        fails.append(f"the mesh is {pieces} disconnected pieces")
    # 5. beam ends: a node of one beam element only and of no shell is a free end; only the
    # purlins' overhang tips at the entrance (x = -OVERHANG) are expected
    shell_nodes = set(n for c in shells for n in c)
    beam_use = {}
    for c in beams:
        for n in c:
            beam_use[n] = beam_use.get(n, 0) + 1
    free_ends = sorted(n for n, k in beam_use.items() if k == 1 and n not in shell_nodes)
    unexpected = [n for n in free_ends if abs(coords[n][0] + OVERHANG) > 1e-9]
    if unexpected:
        fails.append("beam ends attached to nothing at " + ", ".join(_xyz(coords[n]) for n in unexpected[:5]))
    if len(free_ends) - len(unexpected) != 3:
        fails.append(f"expected the 3 purlin tips of the overhang as free beam ends, found {len(free_ends) - len(unexpected)}")
    # 6. supports: every support node is a wall-base node (a shell node at z = 0 or the choir floor)
    sup = set(n for _, c in groups.get("supports", (1, []))[1] for n in c)
    bad = [n for n in sup if n not in shell_nodes or min(abs(coords[n][2]), abs(coords[n][2] - CHOIR_FLOOR)) > 1e-9]
    if bad:
        fails.append(f"{len(bad)} support nodes are not wall-base nodes")
    # 7. quads flat enough for the shell element (warping ratio h / sqrt(area) < 0.05) and convex
    worst = 0.0
    for c in shells:
        if len(c) == 4:
            w, ok = _warping(*(coords[n] for n in c))
            worst = max(worst, w)
            if not ok:
                fails.append(f"non-convex or inverted quad {c}")
    if worst >= 0.05:
        fails.append(f"largest quad warping ratio {worst:.3g} >= 0.05 (the shell element's limit)")
    stats = {
        "nodes": len(coords),
        "dof": 6 * len(coords),
        "quads": sum(1 for c in shells if len(c) == 4),
        "triangles": sum(1 for c in shells if len(c) == 3),
        "lines": len(beams),
        "support_nodes": len(sup),
        "free_shell_edges": len(free_edges),
        "max_warping": worst,
        "per_group": {g: len(groups[g][1]) for g in SURFACE_GROUPS + CURVE_GROUPS if g in groups},
    }
    return stats, fails


def _xyz(p):
    return "(" + ", ".join(f"{float(c):.3f}" for c in p) + ")"


def _neigh(key):
    return [(key[0] + i, key[1] + j, key[2] + k) for i in (-1, 0, 1) for j in (-1, 0, 1) for k in (-1, 0, 1)]


def _box(lo, hi):
    """The 1 m grid cells meeting the box [lo, hi]."""
    a = [math.floor(v) for v in lo]
    b = [math.floor(v) for v in hi]
    return [(i, j, k) for i in range(a[0], b[0] + 1) for j in range(a[1], b[1] + 1) for k in range(a[2], b[2] + 1)]


def _warping(p1, p2, p3, p4):
    """Warping ratio of a quad (distance of the nodes from their mean plane over sqrt(area)) and
    whether it is convex with the nodes in order (all corner cross products point one way)."""
    c = [(p1[i] + p2[i] + p3[i] + p4[i]) / 4 for i in range(3)]
    d13 = [p3[i] - p1[i] for i in range(3)]
    d24 = [p4[i] - p2[i] for i in range(3)]
    n = _cross(d13, d24)
    area = 0.5 * math.sqrt(sum(x * x for x in n))
    nn = [x / (2 * area) for x in n]
    h = max(abs(sum((p[i] - c[i]) * nn[i] for i in range(3))) for p in (p1, p2, p3, p4))
    ps = (p1, p2, p3, p4)
    ok = True
    for i in range(4):
        a, b_, cc = ps[i - 1], ps[i], ps[(i + 1) % 4]
        cr = _cross([b_[k] - a[k] for k in range(3)], [cc[k] - b_[k] for k in range(3)])
        if sum(cr[k] * nn[k] for k in range(3)) <= 0:
            ok = False
    return h / math.sqrt(area), ok


def _cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def report(path, stats, fails, seconds=None):
    print(f"{path}: {stats['nodes']} nodes, {stats['dof']} DOF, {stats['quads']} quads, {stats['triangles']} triangles, "
          f"{stats['lines']} lines" + (f", generated in {seconds:.1f} s" if seconds is not None else ""))
    print("  elements per group: " + ", ".join(f"{g} {n}" for g, n in stats["per_group"].items()))
    print(f"  support nodes {stats['support_nodes']}, free shell edges {stats['free_shell_edges']}, "
          f"largest quad warping ratio {stats['max_warping']:.2e}")
    if fails:
        for f in fails:
            print(f"  CHECK FAILED: {f}", file=sys.stderr)
    else:
        print("  checks passed: no duplicate or orphan nodes, no hanging nodes, one connected piece, "
              "beam ends attached, supports at the wall bases, quads flat and convex")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0], formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("-o", "--output", help="output file (default meshes/church.msh, or meshes/church-fine.msh with --fine)")
    ap.add_argument("--fine", action="store_true", help=f"the cluster mesh (element size {FINE_SIZE} m)")
    ap.add_argument("--size", type=float, help=f"element size [m] (default {COARSE_SIZE}, fine {FINE_SIZE})")
    ap.add_argument("--binary", action="store_true", help="write binary MSH 4.1")
    ap.add_argument("--check", metavar="MSH", help="only check an existing mesh file")
    ap.add_argument("--no-fragment", action="store_true",
                    help="skip the fragment (non-conforming junctions): shows that the checks fail")
    ap.add_argument("--json", action="store_true", help="print the statistics as one JSON line as well")
    a = ap.parse_args()
    if a.check:
        stats, fails = check(a.check)
        report(a.check, stats, fails)
        _json(a, stats, None)
        sys.exit(1 if fails else 0)
    size = a.size or (FINE_SIZE if a.fine else COARSE_SIZE)
    if not size > 0:
        sys.exit(f"--size must be positive, got {size}")
    path = a.output or ("meshes/church-fine.msh" if a.fine else "meshes/church.msh")
    t0 = time.perf_counter()
    generate(size, path, a.binary, glue=not a.no_fragment)
    dt = time.perf_counter() - t0
    stats, fails = check(path)
    report(path, stats, fails, dt)
    _json(a, stats, dt)
    sys.exit(1 if fails else 0)


def _json(a, stats, dt):
    if a.json:
        import json
        print(json.dumps(dict(stats, seconds=dt)))


if __name__ == "__main__":
    main()
