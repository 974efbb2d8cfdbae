#!/usr/bin/env python3
"""Writes the small mesh files the mesh-import tests read (tests/sim/io/mesh_import_test.cpp,
tests/cli, tests/server): a crate as binary glTF and as OBJ, plus two broken OBJ crates.

    python3 tests/assets/make_crates.py tests/assets

The crate is a box of 1.0 x 0.6 x 0.8 m. Each face has its own four vertices with the face's
normal, as exporters write flat-shaded meshes, so the importer must join vertices by position.
crate.glb holds two nodes: "Crate" (translated to x = 5 m, so taking the node drops its own
placement) and "Pallet" (a 1.2 x 0.1 x 1.0 m slab below it, at y = -0.45 m).
"""
import json
import struct
import sys
from pathlib import Path

CRATE_SIZE = (1.0, 0.6, 0.8)
PALLET_SIZE = (1.2, 0.1, 1.0)


def box_faces(size, centre=(0.0, 0.0, 0.0)):
    """Six quads, each (normal, four corners counter-clockwise seen from outside)."""
    hx, hy, hz = (s / 2 for s in size)
    cx, cy, cz = centre
    faces = []
    for axis in range(3):
        for sign in (1.0, -1.0):
            normal = [0.0, 0.0, 0.0]
            normal[axis] = sign
            u, v = (axis + 1) % 3, (axis + 2) % 3
            corners = []
            for a, b in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
                p = [0.0, 0.0, 0.0]
                p[axis] = sign
                p[u] = a
                p[v] = b if sign > 0 else -b
                corners.append(p)
            half = (hx, hy, hz)
            corners = [tuple(c + p[i] * half[i] for i, c in enumerate((cx, cy, cz))) for p in corners]
            faces.append((tuple(normal), corners))
    return faces


def glb(path):
    def mesh_arrays(size):
        positions, normals, indices = [], [], []
        for normal, corners in box_faces(size):
            base = len(positions)
            positions += corners
            normals += [normal] * 4
            indices += [base, base + 1, base + 2, base, base + 2, base + 3]
        return positions, normals, indices

    binary = bytearray()
    views, accessors, meshes = [], [], []

    def add(data, fmt, count, kind, component, target, minmax=None):
        while len(binary) % 4:
            binary.append(0)
        offset = len(binary)
        for item in data:
            binary.extend(struct.pack(fmt, *(item if isinstance(item, tuple) else (item,))))
        views.append({"buffer": 0, "byteOffset": offset, "byteLength": len(binary) - offset,
                      "target": target})
        accessor = {"bufferView": len(views) - 1, "componentType": component, "count": count,
                    "type": kind}
        if minmax:
            accessor["min"], accessor["max"] = minmax
        accessors.append(accessor)
        return len(accessors) - 1

    for name, size in (("Crate", CRATE_SIZE), ("Pallet", PALLET_SIZE)):
        positions, normals, indices = mesh_arrays(size)
        lo = [min(p[i] for p in positions) for i in range(3)]
        hi = [max(p[i] for p in positions) for i in range(3)]
        pos = add(positions, "<3f", len(positions), "VEC3", 5126, 34962, (lo, hi))
        nor = add(normals, "<3f", len(normals), "VEC3", 5126, 34962)
        idx = add(indices, "<H", len(indices), "SCALAR", 5123, 34963)
        meshes.append({"name": name, "primitives": [
            {"attributes": {"POSITION": pos, "NORMAL": nor}, "indices": idx}]})
    while len(binary) % 4:
        binary.append(0)
    document = {
        "asset": {"version": "2.0", "generator": "brisance tests/assets/make_crates.py"},
        "scene": 0,
        "scenes": [{"nodes": [0, 1]}],
        "nodes": [{"name": "Crate", "mesh": 0, "translation": [5.0, 0.0, 0.0]},
                  {"name": "Pallet", "mesh": 1, "translation": [0.0, -0.45, 0.0]}],
        "meshes": meshes,
        "accessors": accessors,
        "bufferViews": views,
        "buffers": [{"byteLength": len(binary)}],
    }
    text = json.dumps(document, separators=(",", ":")).encode()
    text += b" " * (-len(text) % 4)
    total = 12 + 8 + len(text) + 8 + len(binary)
    out = struct.pack("<4sII", b"glTF", 2, total)
    out += struct.pack("<I4s", len(text), b"JSON") + text
    out += struct.pack("<I4s", len(binary), b"BIN\0") + bytes(binary)
    path.write_bytes(out)


def obj(path, drop_faces=0, fin=False):
    lines = ["# " + path.name + ", written by tests/assets/make_crates.py", "o Crate"]
    normals = []
    vertex = 0
    faces = box_faces(CRATE_SIZE)
    faces = faces[: len(faces) - drop_faces]
    for n, (normal, corners) in enumerate(faces):
        for c in corners:
            lines.append("v %.6f %.6f %.6f" % c)
        lines.append("vn %.1f %.1f %.1f" % normal)
        normals.append(n + 1)
        lines.append("f " + " ".join("%d//%d" % (vertex + k + 1, n + 1) for k in range(4)))
        vertex += 4
    if fin:
        # Two triangles hung on the crate's top front edge (y = 0.3, z = 0.4): that edge then
        # joins four triangles.
        lines.append("v -0.5 0.3 0.4")
        lines.append("v 0.5 0.3 0.4")
        lines.append("v 0.0 0.8 0.4")
        lines.append("f %d %d %d" % (vertex + 1, vertex + 2, vertex + 3))
        lines.append("f %d %d %d" % (vertex + 2, vertex + 1, vertex + 3))
    path.write_text("\n".join(lines) + "\n")


def main():
    folder = Path(sys.argv[1] if len(sys.argv) > 1 else Path(__file__).parent)
    glb(folder / "crate.glb")
    obj(folder / "crate.obj")
    obj(folder / "open_crate.obj", drop_faces=1)
    obj(folder / "finned_crate.obj", fin=True)


if __name__ == "__main__":
    main()
