#!/usr/bin/env python3
"""Writes portal_binary.msh (and portal_binary_be.msh, big-endian): portal.msh as binary MSH 4.1.

    python3 tests/data/msh/make_binary_fixture.py            # from the repository root

The mesh (a 2D portal frame in the xz plane, two columns and a beam, each curve split in two
2-node lines; physical groups "beams" on the curves and "base" on the two foot points) is
written out here as Python data, independently of portal.msh, and encoded with `struct`
following the Gmsh reference manual, "MSH file format" (version 4.1, binary): section headers
and end markers are text lines; bodies hold size_t (8 bytes) tags and counts, int (4 bytes)
dimensions / entity tags / types, and double coordinates, in the writer's byte order
(little-endian, and big-endian for the second file); $MeshFormat carries the int 1 so a reader
can tell the byte order; $PhysicalNames stays text.

A $NodeData section with binary values (including the bytes of "\n" and "$") follows
$Elements so the reader's skipping of unknown sections is tested on binary data.

If the `gmsh` Python module is installed, also writes portal_gmsh_binary.msh: portal.msh
re-saved in binary by Gmsh itself, an independent check of the layout.
"""
import os
import struct

HERE = os.path.dirname(os.path.abspath(__file__))

PHYSICAL_NAMES = [(0, 2, "base"), (1, 1, "beams")]
# (tag, x, y, z, physical tags)
POINTS = [(1, 0, 0, 0, [2]), (2, 0, 0, 3, []), (3, 4, 0, 3, []), (4, 4, 0, 0, [2])]
# (tag, bounding box, physical tags, bounding points)
CURVES = [
    (1, (0, 0, 0, 0, 0, 3), [1], [1, -2]),
    (2, (0, 0, 3, 4, 0, 3), [1], [2, -3]),
    (3, (4, 0, 0, 4, 0, 3), [1], [3, -4]),
]
# (entity dim, entity tag, [(node tag, (x, y, z))])
NODE_BLOCKS = [
    (0, 1, [(1, (0, 0, 0))]),
    (0, 2, [(2, (0, 0, 3))]),
    (0, 3, [(3, (4, 0, 3))]),
    (0, 4, [(4, (4, 0, 0))]),
    (1, 1, [(101, (0, 0, 1.5))]),
    (1, 2, [(102, (2, 0, 3))]),
    (1, 3, [(103, (4, 0, 1.5))]),
]
# (entity dim, entity tag, element type, [(element tag, node tags)])
ELEMENT_BLOCKS = [
    (0, 1, 15, [(1, [1])]),
    (0, 4, 15, [(2, [4])]),
    (1, 1, 1, [(3, [1, 101]), (4, [101, 2])]),
    (1, 2, 1, [(5, [2, 102]), (6, [102, 3])]),
    (1, 3, 1, [(7, [3, 103]), (8, [103, 4])]),
]


ORDER = "<"  # byte order of the file being written: "<" little-endian, ">" big-endian


def size_t(*v):
    return struct.pack("%s%dQ" % (ORDER, len(v)), *v)


def int_(*v):
    return struct.pack("%s%di" % (ORDER, len(v)), *v)


def double(*v):
    return struct.pack("%s%dd" % (ORDER, len(v)), *v)


def binary_msh():
    out = bytearray()
    out += b"$MeshFormat\n4.1 1 8\n" + int_(1) + b"\n$EndMeshFormat\n"

    out += b"$PhysicalNames\n%d\n" % len(PHYSICAL_NAMES)
    for dim, tag, name in PHYSICAL_NAMES:
        out += b'%d %d "%s"\n' % (dim, tag, name.encode())
    out += b"$EndPhysicalNames\n"

    out += b"$Entities\n" + size_t(len(POINTS), len(CURVES), 0, 0)
    for tag, x, y, z, phys in POINTS:
        out += int_(tag) + double(x, y, z) + size_t(len(phys)) + int_(*phys)
    for tag, box, phys, bound in CURVES:
        out += int_(tag) + double(*box) + size_t(len(phys)) + int_(*phys)
        out += size_t(len(bound)) + int_(*bound)
    out += b"\n$EndEntities\n"

    tags = [t for _, _, nodes in NODE_BLOCKS for t, _ in nodes]
    out += b"$Nodes\n" + size_t(len(NODE_BLOCKS), len(tags), min(tags), max(tags))
    for dim, tag, nodes in NODE_BLOCKS:
        out += int_(dim, tag, 0) + size_t(len(nodes))
        out += size_t(*[t for t, _ in nodes])
        for _, xyz in nodes:
            out += double(*xyz)
    out += b"\n$EndNodes\n"

    etags = [t for _, _, _, elems in ELEMENT_BLOCKS for t, _ in elems]
    out += b"$Elements\n" + size_t(len(ELEMENT_BLOCKS), len(etags), min(etags), max(etags))
    for dim, tag, etype, elems in ELEMENT_BLOCKS:
        out += int_(dim, tag, etype) + size_t(len(elems))
        for etag, nodes in elems:
            out += size_t(etag, *nodes)
    out += b"\n$EndElements\n"

    # A node data view whose binary values hold the bytes of "\n" (10) and "$" (36).
    out += b'$NodeData\n1\n"temperature"\n1\n0\n3\n0\n1\n2\n'
    out += int_(1) + double(20.0) + int_(4) + bytes([10, 36, 10, 36, 0, 0, 0, 0])
    out += b"\n$EndNodeData\n"
    return bytes(out)


def main():
    global ORDER
    for order, name in [("<", "portal_binary.msh"), (">", "portal_binary_be.msh")]:
        ORDER = order
        with open(os.path.join(HERE, name), "wb") as f:
            f.write(binary_msh())
    try:
        import gmsh  # optional: an independent writer of the same layout
    except ImportError:
        return
    gmsh.initialize()
    gmsh.option.setNumber("General.Verbosity", 2)
    gmsh.option.setNumber("Mesh.Binary", 1)
    gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
    gmsh.open(os.path.join(HERE, "portal.msh"))
    gmsh.write(os.path.join(HERE, "portal_gmsh_binary.msh"))
    gmsh.finalize()


if __name__ == "__main__":
    main()
