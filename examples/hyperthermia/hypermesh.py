"""A small, independent HyperMesh writer (thesis appendix B, docs/formats.md) for the example generators.

It is written from the format's description, not from VoRANG's own writer, so that reading its files
with `vorang info` checks the reader against a second implementation: BINARY encoding (ASCII
header, then after each `@marker` line the block as raw big-endian data and one newline),
1-based node indices, right-handed tetrahedra, a `Materials` block for byte material data.
"""

import numpy as np


def right_handed(points, tets):
    """Swap two nodes of every tetrahedron whose signed volume is negative (VoRANG's files
    have ((n1−n0)×(n2−n0))·(n3−n0) > 0, docs/formats.md); fails on degenerate cells rather than writing them."""
    p = points[tets]
    vol = np.einsum("ij,ij->i", np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), p[:, 3] - p[:, 0])
    if np.any(vol == 0):
        raise ValueError(f"{np.count_nonzero(vol == 0)} degenerate tetrahedra")
    tets = tets.copy()
    neg = vol < 0
    tets[neg, 2], tets[neg, 3] = tets[neg, 3].copy(), tets[neg, 2].copy()
    return tets


def _material_entry(m):
    parts = [f"id={m['id']}", f'name="{m["name"]}"']
    for key, value in m.items():
        if key not in ("id", "name"):
            parts.append(f"{key}={value}")
    return "  { " + ", ".join(parts) + " }"


def write_binary(path, points, tets, materials, node_fields, cell_materials, comments=()):
    """Write a BINARY HyperMesh file.

    points: (n, 3) coordinates, stored as float[3]; tets: (m, 4) 0-based node indices (written
    1-based, re-oriented right-handed); materials: list of dicts with `id`, `name` and any
    physical constants; node_fields: list of (name, (n,) values) written as float NodeData with
    a Linear field each; cell_materials: (name, (m,) byte values) written as
    `TetrahedronData { byte Materials }` with a Constant field.
    """
    points = np.asarray(points, dtype=np.float64)
    tets = right_handed(points, np.asarray(tets, dtype=np.int64))
    ids = {m["id"] for m in materials}
    mat_name, mat_values = cell_materials
    mat_values = np.asarray(mat_values)
    unknown = set(np.unique(mat_values).tolist()) - ids
    if unknown:
        raise ValueError(f"material values {sorted(unknown)} missing from the Materials block")

    lines = ["# HyperMesh 3D BINARY 0.7"]
    lines += [f"# {c}" for c in comments]
    lines.append("Materials {")
    lines.append(",\n".join(_material_entry(m) for m in materials))
    lines.append("}")
    lines.append(f"nNodes = {len(points)}")
    lines.append(f"nTetrahedra = {len(tets)}")
    lines.append("Nodes { float[3] Coordinates } = @1")
    lines.append("Tetrahedra { int[4] Nodes } = @2")
    blocks = [
        points.astype(">f4"),
        (tets + 1).astype(">i4"),
    ]
    for i, (_, values) in enumerate(node_fields):
        lines.append(f"NodeData {{ float }} = @{3 + i}")
        blocks.append(np.asarray(values).astype(">f4"))
    mat_marker = 3 + len(node_fields)
    lines.append(f"TetrahedronData {{ byte Materials }} = @{mat_marker}")
    blocks.append(mat_values.astype(np.uint8))
    for i, (name, _) in enumerate(node_fields):
        lines.append(f'Field "{name}" {{ float }} = Linear(@{3 + i})')
    lines.append(f'Field "{mat_name}" {{ byte Materials }} = Constant(@{mat_marker})')
    # A form-feed comment line ends the readable part (thesis B.2: `more` stops there).
    lines.append("#\f")
    with open(path, "wb") as f:
        f.write(("\n".join(lines) + "\n").encode("utf-8"))
        for i, b in enumerate(blocks):
            f.write(f"@{i + 1}\n".encode("ascii"))
            f.write(np.ascontiguousarray(b).tobytes())
            f.write(b"\n")


def write_summary(path, hmesh_name, points, tets, materials, node_fields, cell_materials):
    """What the HyperMesh file holds, computed here with numpy from the values as stored
    (float32 coordinates and fields), one fact a line: tests/examples.rs reads the file with
    VoRANG and checks every line, so the reader is tested against this independent writer."""
    p = np.asarray(points, dtype=np.float32).astype(np.float64)
    t = np.asarray(tets, dtype=np.int64)
    q = p[t]
    vol = (
        np.abs(
            np.einsum("ij,ij->i", np.cross(q[:, 1] - q[:, 0], q[:, 2] - q[:, 0]), q[:, 3] - q[:, 0])
        ).sum()
        / 6.0
    )
    name, values = cell_materials
    lines = [
        f"# What {hmesh_name} holds, computed by the generator with numpy (tests/examples.rs",
        "# checks that VoRANG reads the same).",
        f"file {hmesh_name}",
        f"nodes {len(p)}",
        f"tetrahedra {len(t)}",
        f"volume {vol!r}",
    ]
    for fname, v in node_fields:
        v = np.asarray(v, dtype=np.float32)
        lines.append(f"field {fname} {float(v.min())!r} {float(v.max())!r}")
    for m in materials:
        count = int(np.count_nonzero(np.asarray(values) == m["id"]))
        lines.append(f"material {name} {m['id']} {m['name']} {count}")
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")
