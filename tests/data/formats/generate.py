#!/usr/bin/env python3
"""Writes the small mesh files that tests/formats.rs reads, in every format and encoding VoRANG
reads. The files are committed, so `cargo test` needs no Python; run this again only after a
deliberate change:

    python3 -m venv /tmp/fmtvenv
    /tmp/fmtvenv/bin/pip install meshio==5.3.5 numpy==1.26.4 lz4==4.4.5 gmsh==4.13.1
    /tmp/fmtvenv/bin/python tests/data/formats/generate.py

Two meshes:

- `cube`: a 2x2x2 Kuhn box (27 nodes, 48 tetrahedra) with dyadic coordinates and values (exact
  in every encoding, float32 included), point arrays `temperature` (scalar) and `velocity`
  (3 components), cell arrays `material` (integer 1/2) and `pressure` (float). Written as
  HyperMesh (by hand), .vtu by meshio (its real writer: ascii, base64 + zlib/lzma) and by the
  hand-written VTK XML writer below in every encoding (ascii; inline base64; appended raw and
  base64; no compression, zlib, lz4, lzma; UInt32/UInt64 headers; little/big endian; several
  compressed blocks per array), legacy .vtk by meshio (4.2 and 5.1, ascii and binary) and by
  hand (SCALARS/LOOKUP_TABLE, VECTORS), and .msh by meshio (2.2 and 4.1, ascii and binary).
- `mixed`: a bar of one hexahedron, two wedges, six pyramids and a cube of tetrahedra with the
  affine point field `f = 1 + x/2 - y/4 + z/8`, and the same mesh split into tetrahedra by
  another conforming rule (diagonals from the *largest* node index) as `mixed_split.vtu`.
  Plus `quadratic.vtu` (two quadratic tetrahedra) for the HigherOrder path.
"""

import base64
import lzma
import os
import struct
import sys
import zlib

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))


def out(name):
    return os.path.join(HERE, name)


# ------------------------------------------------------------------------------------------
# The cube mesh

def kuhn_box(n):
    pts = []
    index = {}
    for k in range(n + 1):
        for j in range(n + 1):
            for i in range(n + 1):
                index[(i, j, k)] = len(pts)
                # Dyadic jitter keeps every coordinate exact in float32.
                jit = ((i * 3 + j * 5 + k * 7) % 4) / 64.0 if 0 < i < n and 0 < j < n and 0 < k < n else 0.0
                pts.append([i / 2.0 + jit, j / 2.0 - jit, k / 2.0 + jit / 2])
    tets = []
    paths = [(0, 1, 2), (0, 2, 1), (1, 0, 2), (1, 2, 0), (2, 0, 1), (2, 1, 0)]
    for k in range(n):
        for j in range(n):
            for i in range(n):
                for p in paths:
                    c = [i, j, k]
                    v = [index[tuple(c)]]
                    for axis in p:
                        c[axis] += 1
                        v.append(index[tuple(c)])
                    tets.append(v)
    return np.array(pts, dtype=np.float64), np.array(tets, dtype=np.int64)


points, tets = kuhn_box(2)
temperature = np.array([1.0 + p[0] * 2 - p[1] + 0.25 * p[2] * p[2] for p in points])
velocity = np.array([[p[1], -p[0], 0.5] for p in points])
centroids = points[tets].mean(axis=1)
material = np.where(centroids[:, 0] < 0.5, 1, 2).astype(np.int32)
pressure = np.array([float(i % 5) / 4.0 for i in range(len(tets))])


def write_hmesh():
    lines = ["# HyperMesh 3D ASCII 0.7",
             f"nNodes = {len(points)}", f"nTetrahedra = {len(tets)}",
             "Nodes { double[3] Coordinates } = @1",
             "Tetrahedra { int[4] Nodes } = @2",
             "NodeData { double } = @3",
             "NodeData { double[3] } = @4",
             "TetrahedronData { byte } = @5",
             "TetrahedronData { double } = @6",
             'Field "temperature" { double } = Linear(@3)',
             'Field "velocity" { double[3] } = Linear(@4)',
             'Field "material" { byte } = Constant(@5)',
             'Field "pressure" { double } = Constant(@6)',
             "@1"]
    lines += [" ".join(repr(float(c)) for c in p) for p in points]
    lines += ["@2"] + [" ".join(str(i + 1) for i in t) for t in tets]
    lines += ["@3"] + [repr(float(v)) for v in temperature]
    lines += ["@4"] + [" ".join(repr(float(c)) for c in v) for v in velocity]
    lines += ["@5"] + [str(int(m)) for m in material]
    lines += ["@6"] + [repr(float(v)) for v in pressure]
    with open(out("cube.hmesh"), "w") as f:
        f.write("\n".join(lines) + "\n")


def cube_meshio():
    import meshio
    return meshio.Mesh(
        points, [("tetra", tets)],
        point_data={"temperature": temperature, "velocity": velocity},
        cell_data={"material": [material], "pressure": [pressure]},
    )


# ------------------------------------------------------------------------------------------
# A VTK XML writer for every encoding meshio does not write


def compress(data, compressor, block):
    import lz4.block

    blocks = [data[i:i + block] for i in range(0, len(data), block)] or []
    if compressor == "zlib":
        comp = [zlib.compress(b) for b in blocks]
    elif compressor == "lz4":
        comp = [lz4.block.compress(b, store_size=False) for b in blocks]
    elif compressor == "lzma":
        comp = [lzma.compress(b) for b in blocks]
    else:
        raise ValueError(compressor)
    last = len(blocks[-1]) if blocks else 0
    header = [len(blocks), block, 0 if last == block else last] + [len(c) for c in comp]
    return header, b"".join(comp)


def encode_array(arr, fmt, compressor, header_type, big, block):
    """Header bytes and data bytes of one array (uncompressed or compressed)."""
    order = ">" if big else "<"
    raw = np.ascontiguousarray(arr).astype(arr.dtype.newbyteorder(order)).tobytes()
    hcode = order + ("Q" if header_type == "UInt64" else "I")
    if compressor is None:
        header = struct.pack(hcode, len(raw))
        return header, raw
    words, comp = compress(raw, compressor, block)
    header = b"".join(struct.pack(hcode, w) for w in words)
    return header, comp


VTK_TYPES = {np.dtype("float64"): "Float64", np.dtype("float32"): "Float32",
             np.dtype("int64"): "Int64", np.dtype("int32"): "Int32", np.dtype("uint8"): "UInt8",
             np.dtype("int16"): "Int16"}


def write_vtu(name, pts, cells, ctypes, point_data, cell_data, fmt="appended", encoding="raw",
              compressor=None, header_type="UInt32", big=False, block=96, one_stream=False):
    conn = np.concatenate([np.asarray(c, dtype=np.int64) for c in cells])
    offsets = np.cumsum([len(c) for c in cells]).astype(np.int64)
    types = np.asarray(ctypes, dtype=np.uint8)
    arrays = []  # (section, name, ncomp, array)
    for k, v in point_data.items():
        arrays.append(("PointData", k, 1 if v.ndim == 1 else v.shape[1], v))
    for k, v in cell_data.items():
        arrays.append(("CellData", k, 1 if v.ndim == 1 else v.shape[1], v))
    arrays.append(("Points", "Points", 3, pts))
    arrays.append(("Cells", "connectivity", 1, conn))
    arrays.append(("Cells", "offsets", 1, offsets))
    arrays.append(("Cells", "types", 1, types))
    appended = b""
    decls = {"PointData": [], "CellData": [], "Points": [], "Cells": []}
    for section, aname, ncomp, arr in arrays:
        arr = np.asarray(arr)
        attrs = f'type="{VTK_TYPES[arr.dtype]}" Name="{aname}" NumberOfComponents="{ncomp}"'
        if fmt == "ascii":
            text = " ".join(repr(x.item()) if arr.dtype.kind == "f" else str(x.item()) for x in arr.flatten())
            decls[section].append(f'<DataArray {attrs} format="ascii">\n{text}\n</DataArray>')
            continue
        header, data = encode_array(arr.flatten(), fmt, compressor, header_type, big, block)
        if fmt == "binary":
            if one_stream:
                text = base64.b64encode(header + data).decode()
            else:
                text = base64.b64encode(header).decode() + base64.b64encode(data).decode()
            decls[section].append(f'<DataArray {attrs} format="binary">\n{text}\n</DataArray>')
        else:
            offset = len(appended)
            if encoding == "raw":
                appended += header + data
            else:
                if one_stream:
                    appended += base64.b64encode(header + data)
                else:
                    appended += base64.b64encode(header) + base64.b64encode(data)
            decls[section].append(f'<DataArray {attrs} format="appended" offset="{offset}"/>')
    comp_attr = {None: "", "zlib": ' compressor="vtkZLibDataCompressor"',
                 "lz4": ' compressor="vtkLZ4DataCompressor"',
                 "lzma": ' compressor="vtkLZMADataCompressor"'}[compressor]
    order = "BigEndian" if big else "LittleEndian"
    xml = ['<?xml version="1.0"?>',
           f'<VTKFile type="UnstructuredGrid" version="1.0" byte_order="{order}" header_type="{header_type}"{comp_attr}>',
           "  <UnstructuredGrid>",
           f'    <Piece NumberOfPoints="{len(pts)}" NumberOfCells="{len(cells)}">']
    for section in ["PointData", "CellData", "Points", "Cells"]:
        xml.append(f"      <{section}>")
        xml += ["        " + d for d in decls[section]]
        xml.append(f"      </{section}>")
    xml += ["    </Piece>", "  </UnstructuredGrid>"]
    body = ("\n".join(xml) + "\n").encode()
    if fmt == "appended":
        body += f'  <AppendedData encoding="{encoding}">\n   _'.encode() + appended + b"\n  </AppendedData>\n"
    body += b"</VTKFile>\n"
    with open(out(name), "wb") as f:
        f.write(body)


def write_cube_variants():
    import meshio
    pd = {"temperature": temperature, "velocity": velocity}
    cd = {"material": material, "pressure": pressure}
    cells = list(tets)
    ctypes = [10] * len(tets)
    variants = {
        "cube_ascii.vtu": dict(fmt="ascii"),
        "cube_binary.vtu": dict(fmt="binary"),
        "cube_binary_onestream.vtu": dict(fmt="binary", one_stream=True),
        "cube_binary_zlib.vtu": dict(fmt="binary", compressor="zlib"),
        "cube_binary_lz4.vtu": dict(fmt="binary", compressor="lz4", header_type="UInt64"),
        "cube_binary_lzma.vtu": dict(fmt="binary", compressor="lzma"),
        "cube_binary_be.vtu": dict(fmt="binary", big=True, header_type="UInt64"),
        "cube_raw.vtu": dict(fmt="appended", encoding="raw"),
        "cube_raw_zlib.vtu": dict(fmt="appended", encoding="raw", compressor="zlib", header_type="UInt64"),
        "cube_raw_lz4.vtu": dict(fmt="appended", encoding="raw", compressor="lz4"),
        "cube_raw_lzma.vtu": dict(fmt="appended", encoding="raw", compressor="lzma", header_type="UInt64"),
        "cube_raw_zlib_be.vtu": dict(fmt="appended", encoding="raw", compressor="zlib", big=True),
        "cube_raw_be64.vtu": dict(fmt="appended", encoding="raw", big=True, header_type="UInt64"),
        "cube_b64.vtu": dict(fmt="appended", encoding="base64"),
        "cube_b64_zlib.vtu": dict(fmt="appended", encoding="base64", compressor="zlib", header_type="UInt64"),
        "cube_b64_lz4_be.vtu": dict(fmt="appended", encoding="base64", compressor="lz4", big=True),
    }
    for name, kw in variants.items():
        write_vtu(name, points, cells, ctypes, pd, cd, **kw)
    # float32 coordinates (exact: the coordinates are dyadic)
    write_vtu("cube_float32.vtu", points.astype(np.float32), cells, ctypes, pd, cd,
              fmt="appended", compressor="zlib")
    # meshio's own writer
    m = cube_meshio()
    meshio.vtu.write(out("cube_meshio_ascii.vtu"), m, binary=False)
    meshio.vtu.write(out("cube_meshio_zlib.vtu"), m, binary=True, compression="zlib")
    meshio.vtu.write(out("cube_meshio_lzma.vtu"), m, binary=True, compression="lzma")
    meshio.vtu.write(out("cube_meshio_raw.vtu"), m, binary=True, compression=None)
    # legacy VTK
    meshio.vtk.write(out("cube_42_ascii.vtk"), m, binary=False, fmt_version="4.2")
    meshio.vtk.write(out("cube_42_binary.vtk"), m, binary=True, fmt_version="4.2")
    meshio.vtk.write(out("cube_51_ascii.vtk"), m, binary=False, fmt_version="5.1")
    meshio.vtk.write(out("cube_51_binary.vtk"), m, binary=True, fmt_version="5.1")
    write_legacy_by_hand()
    # Gmsh
    mg = meshio.Mesh(
        points, [("tetra", tets)],
        point_data={"temperature": temperature, "velocity": velocity},
        cell_data={"gmsh:physical": [material], "gmsh:geometrical": [np.ones(len(tets), dtype=np.int32)],
                   "material": [material.astype(np.float64)], "pressure": [pressure]},
    )
    meshio.gmsh.write(out("cube_22_ascii.msh"), mg, fmt_version="2.2", binary=False)
    meshio.gmsh.write(out("cube_22_binary.msh"), mg, fmt_version="2.2", binary=True)
    meshio.gmsh.write(out("cube_41_ascii.msh"), mg, fmt_version="4.1", binary=False)
    meshio.gmsh.write(out("cube_41_binary.msh"), mg, fmt_version="4.1", binary=True)


def write_legacy_by_hand():
    """SCALARS with LOOKUP_TABLE, VECTORS, the classic CELLS list; ASCII and big-endian BINARY."""
    for binary in (False, True):
        parts = [b"# vtk DataFile Version 3.0\n", b"cube by hand\n",
                 b"BINARY\n" if binary else b"ASCII\n", b"DATASET UNSTRUCTURED_GRID\n"]

        def block(arr, fmt_char):
            arr = np.asarray(arr).flatten()
            if binary:
                return np.asarray(arr).astype(">" + fmt_char).tobytes() + b"\n"
            return (" ".join(repr(x.item()) if arr.dtype.kind == "f" else str(x.item()) for x in arr) + "\n").encode()

        parts.append(f"POINTS {len(points)} double\n".encode())
        parts.append(block(points, "f8"))
        cell_list = np.concatenate([[4] + list(t) for t in tets]).astype(np.int32)
        parts.append(f"CELLS {len(tets)} {len(cell_list)}\n".encode())
        parts.append(block(cell_list, "i4"))
        parts.append(f"CELL_TYPES {len(tets)}\n".encode())
        parts.append(block(np.full(len(tets), 10, dtype=np.int32), "i4"))
        parts.append(f"POINT_DATA {len(points)}\n".encode())
        parts.append(b"SCALARS temperature double 1\nLOOKUP_TABLE default\n")
        parts.append(block(temperature, "f8"))
        parts.append(b"VECTORS velocity double\n")
        parts.append(block(velocity, "f8"))
        parts.append(f"CELL_DATA {len(tets)}\n".encode())
        parts.append(b"SCALARS material int\nLOOKUP_TABLE default\n")
        parts.append(block(material, "i4"))
        parts.append(b"FIELD FieldData 1\npressure 1 %d double\n" % len(tets))
        parts.append(block(pressure, "f8"))
        name = "cube_hand_binary.vtk" if binary else "cube_hand_ascii.vtk"
        with open(out(name), "wb") as f:
            f.write(b"".join(parts))


# ------------------------------------------------------------------------------------------
# The mixed mesh


def mixed_mesh():
    """Cubes [0,1], [1,2], [2,3], [3,4] x [0,1]^2: hexahedron, two wedges, six pyramids about the
    centre, six tetrahedra (the cone from the cube's smallest node, so its faces match the
    neighbours' smallest-node diagonals)."""
    idx = {}
    pts = []

    def node(x, y, z):
        key = (x, y, z)
        if key not in idx:
            idx[key] = len(pts)
            pts.append([float(x), float(y), float(z)])
        return idx[key]

    # Number the nodes in a scrambled order so the smallest-node rule is exercised.
    for x in [2, 0, 4, 1, 3]:
        for z in [1, 0]:
            for y in [0, 1]:
                node(x, y, z)
    node(2.5, 0.5, 0.5)

    def cube(x):
        return [node(x, 0, 0), node(x + 1, 0, 0), node(x + 1, 1, 0), node(x, 1, 0),
                node(x, 0, 1), node(x + 1, 0, 1), node(x + 1, 1, 1), node(x, 1, 1)]

    cells, types = [], []
    cells.append(cube(0)); types.append(12)
    c = cube(1)
    # Wedges extruded along z: triangles (0,1,2) and (0,2,3) of the bottom face.
    cells.append([c[0], c[1], c[2], c[4], c[5], c[6]]); types.append(13)
    cells.append([c[0], c[2], c[3], c[4], c[6], c[7]]); types.append(13)
    c = cube(2)
    apex = node(2.5, 0.5, 0.5)
    faces = [[0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7]]
    for f in faces:
        cells.append([c[k] for k in f] + [apex]); types.append(14)
    c = cube(3)
    for t in split(12, c, min):
        cells.append(t); types.append(10)
    return np.array(pts), cells, types


HEX_FACES = [[0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7]]
WEDGE_FACES = [[0, 1, 2], [3, 5, 4], [0, 3, 4, 1], [1, 4, 5, 2], [2, 5, 3, 0]]
PYR_FACES = [[0, 3, 2, 1], [0, 1, 4], [1, 2, 4], [2, 3, 4], [3, 0, 4]]


def split(ty, g, pick):
    """Cone from the cell's pick (min or max) node over the faces without it; quads cut along
    the diagonal through their own pick node. Conforming for either pick."""
    faces = {12: HEX_FACES, 13: WEDGE_FACES, 14: PYR_FACES}.get(ty)
    if faces is None:
        return [list(g)]
    v = min(range(len(g)), key=lambda i: g[i]) if pick is min else max(range(len(g)), key=lambda i: g[i])
    out = []
    for f in faces:
        if v in f:
            continue
        if len(f) == 3:
            out.append([g[v]] + [g[k] for k in f])
        else:
            ks = [g[k] for k in f]
            k = ks.index(pick(ks))
            a, b, c, d = ks[k], ks[(k + 1) % 4], ks[(k + 2) % 4], ks[(k + 3) % 4]
            out.append([g[v], a, b, c])
            out.append([g[v], a, c, d])
    return out


def write_mixed():
    pts, cells, types = mixed_mesh()
    f = np.array([1 + p[0] / 2 - p[1] / 4 + p[2] / 8 for p in pts])
    cid = np.arange(len(cells), dtype=np.int32) % 3 + 1
    write_vtu("mixed.vtu", pts, cells, types, {"f": f}, {"part": cid},
              fmt="appended", compressor="zlib")
    tcells, tparts = [], []
    for c, t, p in zip(cells, types, cid):
        for s in split(t, c, max):
            tcells.append(s)
            tparts.append(p)
    write_vtu("mixed_split.vtu", pts, tcells, [10] * len(tcells), {"f": f},
              {"part": np.array(tparts, dtype=np.int32)}, fmt="ascii")
    # The same mesh with a triangle and a line that must be skipped with a warning.
    write_vtu("mixed_with_faces.vtu", pts, cells + [[0, 1, 2], [0, 1]], types + [5, 3], {"f": f},
              {"part": np.concatenate([cid, [7, 7]]).astype(np.int32)}, fmt="ascii")


def write_quadratic():
    pts = [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [1, 1, 1]]
    # Mid-edge nodes, VTK order (0,1) (1,2) (2,0) (0,3) (1,3) (2,3), for two tets sharing 1 2 3.
    tets = [[0, 1, 2, 3], [1, 2, 3, 4]]
    index = {}
    cells = []
    for t in tets:
        mids = []
        for a, b in [(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)]:
            key = tuple(sorted((t[a], t[b])))
            if key not in index:
                index[key] = len(pts)
                pa, pb = pts[t[a]], pts[t[b]]
                pts.append([(pa[i] + pb[i]) / 2 for i in range(3)])
            mids.append(index[key])
        cells.append(t + mids)
    pts = np.array(pts, dtype=np.float64)
    # q = x^2 + y z: quadratic, exactly represented by P2.
    q = np.array([p[0] * p[0] + p[1] * p[2] for p in pts])
    write_vtu("quadratic.vtu", pts, cells, [24, 24], {"q": q}, {"id": np.array([3, 4], dtype=np.int32)},
              fmt="ascii")


def write_msh41_with_entities():
    """Gmsh 4.1 ASCII as Gmsh itself writes it: $PhysicalNames, $Entities (two volumes with
    physical tags 1 and 2), element blocks per entity (runs of equal material), $NodeData."""
    lines = ["$MeshFormat", "4.1 0 8", "$EndMeshFormat",
             "$PhysicalNames", "2", '3 1 "left"', '3 2 "right"', "$EndPhysicalNames",
             "$Entities", "0 0 0 2",
             "1 0 0 0 1 1 1 1 1 0", "2 0 0 0 1 1 1 1 2 0", "$EndEntities",
             "$Nodes", f"1 {len(points)} 1 {len(points)}", f"3 1 0 {len(points)}"]
    lines += [str(i + 1) for i in range(len(points))]
    lines += [" ".join(repr(float(c)) for c in p) for p in points]
    lines += ["$EndNodes"]
    runs = []
    for i, m in enumerate(material):
        if runs and runs[-1][0] == m:
            runs[-1][1].append(i)
        else:
            runs.append((m, [i]))
    lines += ["$Elements", f"{len(runs)} {len(tets)} 1 {len(tets)}"]
    for m, ids in runs:
        lines.append(f"3 {int(m)} 4 {len(ids)}")
        lines += [f"{i + 1} " + " ".join(str(n + 1) for n in tets[i]) for i in ids]
    lines += ["$EndElements",
              "$NodeData", "1", '"temperature"', "1", "0.0", "3", "0", "1", str(len(points))]
    lines += [f"{i + 1} {repr(float(v))}" for i, v in enumerate(temperature)]
    lines += ["$EndNodeData"]
    with open(out("cube_41_entities.msh"), "w") as f:
        f.write("\n".join(lines) + "\n")


def write_gmsh_native():
    """Files written by Gmsh itself (the gmsh module): a block with a spherical inclusion, two
    physical volumes (1 matrix, 2 inclusion) and physical surfaces, in 4.1 ASCII, 4.1 binary
    and 2.2 binary. Their 2D elements must be skipped with a warning."""
    import gmsh
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.model.add("native")
    box = gmsh.model.occ.addBox(0, 0, 0, 2, 1, 1)
    ball = gmsh.model.occ.addSphere(0.8, 0.5, 0.5, 0.3)
    gmsh.model.occ.fragment([(3, box)], [(3, ball)])
    gmsh.model.occ.synchronize()
    vols = [t for d, t in gmsh.model.getEntities(3)]
    masses = {t: gmsh.model.occ.getMass(3, t) for t in vols}
    inner = min(masses, key=masses.get)
    gmsh.model.addPhysicalGroup(3, [t for t in vols if t != inner], 1, "matrix")
    gmsh.model.addPhysicalGroup(3, [inner], 2, "inclusion")
    surfs = [t for d, t in gmsh.model.getBoundary([(3, inner)], oriented=False)]
    gmsh.model.addPhysicalGroup(2, surfs, 3, "interface")
    gmsh.option.setNumber("Mesh.MeshSizeMax", 0.35)
    gmsh.model.mesh.generate(3)
    for name, version, binary in [("gmsh_41_ascii.msh", 4.1, 0), ("gmsh_41_binary.msh", 4.1, 1),
                                  ("gmsh_22_binary.msh", 2.2, 1), ("gmsh_22_ascii.msh", 2.2, 0)]:
        gmsh.option.setNumber("Mesh.MshFileVersion", version)
        gmsh.option.setNumber("Mesh.Binary", binary)
        gmsh.write(out(name))
    gmsh.finalize()


# ------------------------------------------------------------------------------------------
# Lagrange cells, voxels and polyhedra, written by VTK itself (`generate.py cells`)


def linear_f(p):
    return 1 + p[0] / 2 - p[1] / 4 + p[2] / 8


def vtk_grid(points, cells, point_data=None, cell_data=None):
    """A vtkUnstructuredGrid: double points, cells as (VTK type, ids or face stream)."""
    import vtk
    from vtk.util import numpy_support as ns

    pts = vtk.vtkPoints()
    pts.SetDataTypeToDouble()
    for p in points:
        pts.InsertNextPoint(*[float(c) for c in p])
    grid = vtk.vtkUnstructuredGrid()
    grid.SetPoints(pts)
    for ty, ids in cells:
        idl = vtk.vtkIdList()
        for i in ids:
            idl.InsertNextId(int(i))
        grid.InsertNextCell(ty, idl)
    for name, values in (point_data or {}).items():
        a = ns.numpy_to_vtk(np.ascontiguousarray(values), deep=True)
        a.SetName(name)
        grid.GetPointData().AddArray(a)
    for name, values in (cell_data or {}).items():
        a = ns.numpy_to_vtk(np.ascontiguousarray(values), deep=True)
        a.SetName(name)
        grid.GetCellData().AddArray(a)
    return grid


def vtk_write(name, grid, ascii=False):
    import vtk

    w = vtk.vtkXMLUnstructuredGridWriter()
    w.SetFileName(out(name))
    w.SetInputData(grid)
    if ascii:
        w.SetDataModeToAscii()
    assert w.Write() == 1, name


def write_lagrange_tets():
    """The cube mesh as dolfinx writes P1 and P2 functions: Lagrange tetrahedra (71)."""
    pts, tets = kuhn_box(2)
    pts = [list(p) for p in pts]
    corners = len(pts)
    index = {}
    p2 = []
    for t in tets:
        mids = []
        for a, b in [(0, 1), (1, 2), (0, 2), (0, 3), (1, 3), (2, 3)]:
            key = tuple(sorted((int(t[a]), int(t[b]))))
            if key not in index:
                index[key] = len(pts)
                pts.append([(pts[t[a]][c] + pts[t[b]][c]) / 2 for c in range(3)])
            mids.append(index[key])
        p2.append(list(t) + mids)
    cid = {"material": np.array([1 + i % 2 for i in range(len(tets))], dtype=np.int32)}
    f = np.array([linear_f(p) for p in pts])
    q = np.array([p[0] * p[0] + p[1] * p[2] for p in pts])
    vtk_write("lagrange_p1.vtu",
              vtk_grid(pts[:corners], [(71, t) for t in tets], {"f": f[:corners]}, cid),
              ascii=True)
    vtk_write("lagrange_p2.vtu",
              vtk_grid(pts, [(71, t) for t in p2], {"f": f, "q": q}, cid), ascii=True)


def bar_corners():
    """The corners of a 2 x 2 x 1 bar of unit cubes, numbered in a scrambled order."""
    order = [(x, y, z) for z in (1, 0) for x in (2, 0, 1) for y in (1, 0, 2)]
    return {c: k for k, c in enumerate(order)}, [list(map(float, c)) for c in order]


CUBES = [(0, 0), (1, 0), (0, 1), (1, 1)]


def write_lagrange_hexahedra():
    import vtk

    H = vtk.vtkLagrangeHexahedron
    idx, pts = bar_corners()
    hex_order = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)]
    linear = [[idx[(x + a, y + b, c)] for a, b, c in hex_order] for x, y in CUBES]
    half = {}

    def node(p):
        if p[0] == int(p[0]) and p[1] == int(p[1]) and p[2] == int(p[2]):
            return idx[tuple(int(c) for c in p)]
        if p not in half:
            half[p] = len(pts) + len(half)
        return half[p]

    quadratic = []
    for x, y in CUBES:
        conn = [0] * 27
        for k in range(3):
            for j in range(3):
                for i in range(3):
                    conn[H.PointIndexFromIJK(i, j, k, [2, 2, 2])] = node((x + i / 2, y + j / 2, k / 2))
        quadratic.append(conn)
    pts2 = pts + [list(p) for p, _ in sorted(half.items(), key=lambda kv: kv[1])]
    f1 = np.array([linear_f(p) for p in pts])
    f2 = np.array([linear_f(p) for p in pts2])
    part = {"part": np.array([3, 4, 5, 6], dtype=np.int32)}
    vtk_write("lagrange_hex_p1.vtu", vtk_grid(pts, [(72, c) for c in linear], {"f": f1}, part))
    vtk_write("lagrange_hex_p2.vtu", vtk_grid(pts2, [(72, c) for c in quadratic], {"f": f2}, part))
    vtk_write("hexahedra_bar.vtu", vtk_grid(pts, [(12, c) for c in linear], {"f": f1}, part))
    voxel = [[c[k] for k in (0, 1, 3, 2, 4, 5, 7, 6)] for c in linear]
    vtk_write("voxels.vtu", vtk_grid(pts, [(11, c) for c in voxel], {"f": f1}, part))
    # VTK 8's order: the nodes of the vertical edges from vertices 2 and 3 change places.
    old = [c[:18] + [c[19], c[18]] + c[20:] for c in quadratic]
    write_vtu("lagrange_hex_p2_vtk8.vtu", np.array(pts2), old, [72] * 4, {"f": f2},
              {"part": part["part"]}, fmt="ascii")


def parametric_coords(cls, n):
    c = cls()
    c.GetPointIds().SetNumberOfIds(n)
    c.GetPoints().SetNumberOfPoints(n)
    c.Initialize()
    if hasattr(c, "SetUniformOrderFromNumPoints"):
        c.SetUniformOrderFromNumPoints(n)
    pc = c.GetParametricCoords()
    return [pc[3 * i:3 * i + 3] for i in range(n)]


def write_lagrange_orders():
    """One Lagrange cell of each shape and degree 1 … 4 (and the 21-node wedge), each placed
    by an affine map of VTK's parametric coordinates of its nodes."""
    import vtk

    shapes = [(71, vtk.vtkLagrangeTetra, [4, 10, 20, 35]),
              (72, vtk.vtkLagrangeHexahedron, [8, 27, 64, 125]),
              (73, vtk.vtkLagrangeWedge, [6, 18, 21, 40, 75])]
    pts, cells = [], []
    shift = 0.0
    for ty, cls, counts in shapes:
        for n in counts:
            start = len(pts)
            for r, s_, t in parametric_coords(cls, n):
                pts.append([shift + 2 * r + 0.5 * s_, 1.5 * s_ - 0.25 * t, 1.25 * t + 0.125 * r])
            cells.append((ty, list(range(start, len(pts)))))
            shift += 3.0
    f = np.array([linear_f(p) for p in pts])
    vtk_write("lagrange_orders.vtu", vtk_grid(pts, cells, {"f": f}), ascii=True)


def cube_faces(x, y, idx):
    """The six faces of the unit cube at (x, y, 0), some listed inwards, starting anywhere."""
    c = lambda a, b, z: idx[(x + a, y + b, z)]
    faces = [
        [c(0, 0, 0), c(0, 1, 0), c(1, 1, 0), c(1, 0, 0)],
        [c(0, 0, 1), c(1, 0, 1), c(1, 1, 1), c(0, 1, 1)],
        [c(0, 0, 0), c(1, 0, 0), c(1, 0, 1), c(0, 0, 1)],
        [c(0, 1, 1), c(1, 1, 1), c(1, 1, 0), c(0, 1, 0)],
        [c(0, 0, 0), c(0, 0, 1), c(0, 1, 1), c(0, 1, 0)],
        [c(1, 0, 0), c(1, 1, 0), c(1, 1, 1), c(1, 0, 1)],
    ]
    # Vary the orientation and the first point from cell to cell.
    turn = (x + 2 * y) % 4
    faces = [f[turn:] + f[:turn] for f in faces]
    if (x + y) % 2:
        faces = [f[::-1] for f in faces]
    return faces


def write_polyhedra():
    import meshio

    idx, pts = bar_corners()
    polys = [cube_faces(x, y, idx) for x, y in CUBES]
    streams = []
    for faces in polys:
        stream = [len(faces)]
        for fc in faces:
            stream += [len(fc)] + fc
        streams.append(stream)
    f = np.array([linear_f(p) for p in pts])
    part = {"part": np.array([3, 4, 5, 6], dtype=np.int32)}
    grid = vtk_grid(pts, [(42, s_) for s_ in streams], {"f": f}, part)
    vtk_write("polyhedra.vtu", grid)
    vtk_write("polyhedra_ascii.vtu", grid, ascii=True)
    import vtk

    w = vtk.vtkUnstructuredGridWriter()
    w.SetFileName(out("polyhedra.vtk"))
    w.SetInputData(grid)
    assert w.Write() == 1
    # The layout before VTK 9.4, as VTK wrote it: `faces` (each cell's face stream) and
    # `faceoffsets` (where each cell's stream ends).
    conn = [sorted({n for fc in faces for n in fc}) for faces in polys]
    offsets = np.cumsum([len(c) for c in conn])
    face_ends = np.cumsum([len(s_) for s_ in streams])
    txt = lambda a: " ".join(str(v) for v in a)
    body = f"""<?xml version="1.0"?>
<VTKFile type="UnstructuredGrid" version="1.0" byte_order="LittleEndian" header_type="UInt64">
  <UnstructuredGrid>
    <Piece NumberOfPoints="{len(pts)}" NumberOfCells="{len(polys)}">
      <PointData>
        <DataArray type="Float64" Name="f" format="ascii">{txt(repr(float(v)) for v in f)}</DataArray>
      </PointData>
      <CellData>
        <DataArray type="Int32" Name="part" format="ascii">{txt(part["part"])}</DataArray>
      </CellData>
      <Points>
        <DataArray type="Float64" Name="Points" NumberOfComponents="3" format="ascii">
          {txt(repr(c) for p in pts for c in p)}
        </DataArray>
      </Points>
      <Cells>
        <DataArray type="Int64" Name="connectivity" format="ascii">{txt(n for c in conn for n in c)}</DataArray>
        <DataArray type="Int64" Name="offsets" format="ascii">{txt(offsets)}</DataArray>
        <DataArray type="UInt8" Name="types" format="ascii">{txt([42] * len(polys))}</DataArray>
        <DataArray type="Int64" Name="faces" format="ascii">{txt(n for s_ in streams for n in s_)}</DataArray>
        <DataArray type="Int64" Name="faceoffsets" format="ascii">{txt(face_ends)}</DataArray>
      </Cells>
    </Piece>
  </UnstructuredGrid>
</VTKFile>
"""
    with open(out("polyhedra_old.vtu"), "w") as fh:
        fh.write(body)
    # Two parts of two cubes each, each with only its own points (numbered anew), and a
    # ParaView collection of two time steps, each the two parts (merged when read).
    for k, part_cells in enumerate([[0, 1], [2, 3]]):
        used = sorted({n for c in part_cells for fc in polys[c] for n in fc})
        local = {g: i for i, g in enumerate(used)}
        part_streams = []
        for c in part_cells:
            stream = [len(polys[c])]
            for fc in polys[c]:
                stream += [len(fc)] + [local[n] for n in fc]
            part_streams.append(stream)
        vtk_write(f"polyhedra_part_{k}.vtu",
                  vtk_grid([pts[g] for g in used], [(42, s_) for s_ in part_streams],
                           {"f": f[used]}, {"part": part["part"][part_cells]}))
    datasets = "\n".join(
        f'    <DataSet timestep="{t}" group="" part="{k}" file="polyhedra_part_{k}.vtu"/>'
        for t in (0, 1) for k in (0, 1))
    with open(out("polyhedra_parts.pvd"), "w") as fh:
        fh.write(f"""<?xml version="1.0"?>
<VTKFile type="Collection" version="0.1" byte_order="LittleEndian">
  <Collection>
{datasets}
  </Collection>
</VTKFile>
""")
    mesh = meshio.Mesh(np.array(pts), [("polyhedron8", [[np.array(fc) for fc in faces] for faces in polys])],
                       point_data={"f": f}, cell_data={"part": [part["part"]]})
    meshio.vtu.write(out("polyhedra_meshio.vtu"), mesh, binary=False)


def write_polyhedra_prisms():
    """Two pentagonal prisms sharing a pentagon, a pentagonal pyramid on top (triangular
    faces), and a tetrahedron sharing one of the pyramid's triangles."""
    import math

    ring = [(math.cos(2 * math.pi * k / 5), math.sin(2 * math.pi * k / 5)) for k in range(5)]
    pts = [[x, y, z] for z in (0.0, 1.0, 2.0) for x, y in ring]
    apex, outside = len(pts), len(pts) + 1
    pts += [[0.0, 0.0, 3.0], [2.0, 0.5, 3.0]]
    level = lambda z: [5 * z + k for k in range(5)]
    polys = []
    for z in (0, 1):
        lo, hi = level(z), level(z + 1)
        polys.append([lo[::-1], hi] + [[lo[k], lo[(k + 1) % 5], hi[(k + 1) % 5], hi[k]] for k in range(5)])
    top = level(2)
    polys.append([top[::-1]] + [[top[k], top[(k + 1) % 5], apex] for k in range(5)])
    cells = []
    for faces in polys:
        stream = [len(faces)]
        for fc in faces:
            stream += [len(fc)] + fc
        cells.append((42, stream))
    cells.append((10, [top[1], top[0], outside, apex]))
    f = np.array([linear_f(p) for p in pts])
    vtk_write("polyhedra_prisms.vtu", vtk_grid(pts, cells, {"f": f}), ascii=True)


def write_serendipity():
    """VTK's quadratic hexahedra, wedges and a pyramid (25, 26, 27) on curved cells, and the
    same cells as Lagrange cells (72, 73, 74) whose face and cell centres VTK itself places
    and fills: its own serendipity interpolation (EvaluateLocation's weights) at those
    parametric points. Two hexahedra share a face, the two wedges a quadrilateral face."""
    import vtk

    def warp(p):
        x, y, z = p
        return [x + 0.08 * np.sin(2 * y + z), y + 0.04 * np.cos(x + z), z + 0.04 * np.sin(x + 2 * y)]

    def f_of(p):
        x, y, z = p
        return np.sin(1.3 * x) + y * y * z + 0.5 * np.cos(2.0 * z)

    index, pts = {}, []

    def node(p):
        key = tuple(round(c * 2) for c in p)
        if key not in index:
            index[key] = len(pts)
            pts.append(warp(p))
        return index[key]

    def pcoords(cls, n):
        c = cls()
        pc = c.GetParametricCoords()
        return [pc[3 * i:3 * i + 3] for i in range(n)]

    cells = []
    hex_pc = pcoords(vtk.vtkQuadraticHexahedron, 20)
    for x0 in (0.0, 1.0):
        cells.append((25, [node((x0 + r, s_, t)) for r, s_, t in hex_pc]))
    wedge_pc = pcoords(vtk.vtkQuadraticWedge, 15)
    for flip in (False, True):
        ids = []
        for r, s_, t in wedge_pc:
            x, y = (1 - s_, 1 - r) if flip else (r, s_)
            ids.append(node((3.0 + x, y, t)))
        if flip:
            # The mirrored wedge's nodes in VTK's order of its own corners.
            ids = [ids[k] for k in (1, 0, 2, 4, 3, 5, 6, 8, 7, 9, 11, 10, 13, 12, 14)]
        cells.append((26, ids))
    pyr_pc = pcoords(vtk.vtkQuadraticPyramid, 13)
    # VTK places the apex edges' nodes at (x, y, 0.5) of the corner; in space they are the
    # midpoints of the edges to the apex.
    base = [(0, 0), (1, 0), (1, 1), (0, 1)]
    pyr = [node((5.0 + x, y, 0.0)) for x, y in base] + [node((5.5, 0.5, 1.0))]
    for a, b in [(0, 1), (1, 2), (2, 3), (3, 0)]:
        (xa, ya), (xb, yb) = base[a], base[b]
        pyr.append(node((5.0 + (xa + xb) / 2, (ya + yb) / 2, 0.0)))
    for x, y in base:
        pyr.append(node((5.0 + (x + 0.5) / 2, (y + 0.5) / 2, 0.5)))
    cells.append((27, pyr))
    f = np.array([f_of(p) for p in pts])
    grid = vtk_grid(pts, cells, {"f": f})
    vtk_write("serendipity.vtu", grid, ascii=True)

    # The Lagrange cells: VTK's serendipity cells evaluated at the missing lattice points.
    lag_pts, lag_f = [list(p) for p in pts], list(f)
    centres = {}
    lagrange = []
    lag_pc = {72: pcoords_lagrange(vtk.vtkLagrangeHexahedron, 27),
              73: pcoords_lagrange(vtk.vtkLagrangeWedge, 18)}
    for c, (ty, ids) in enumerate(cells):
        cell = grid.GetCell(c)
        own = {25: hex_pc, 26: wedge_pc, 27: pyr_pc}[ty]
        at = {tuple(round(v * 2) for v in q): ids[k] for k, q in enumerate(own)}
        n = len(ids)

        def centre(q, corners):
            key = tuple(sorted(corners))
            if key in centres:
                return centres[key]
            x = [0.0, 0.0, 0.0]
            w = [0.0] * n
            cell.EvaluateLocation(vtk.mutable(0), list(q), x, w)
            centres[key] = len(lag_pts)
            lag_pts.append(x)
            lag_f.append(sum(wk * f[ids[k]] for k, wk in enumerate(w)))
            return centres[key]

        if ty == 27:
            conn = ids + [centre((0.5, 0.5, 0.0), ids[:4])]
            lagrange.append((74, conn))
            continue
        lty = {25: 72, 26: 73}[ty]
        conn = []
        for q in lag_pc[lty]:
            key = tuple(round(v * 2) for v in q)
            if key in at:
                conn.append(at[key])
            else:
                corners = own[:8 if ty == 25 else 6]
                if ty == 26 and abs(q[0] + q[1] - 1) < 1e-9:
                    # The wedge's slanted face r + s = 1.
                    on = [ids[k] for k, p in enumerate(corners) if abs(p[0] + p[1] - 1) < 1e-9]
                else:
                    on = [ids[k] for k, p in enumerate(corners)
                          if all(abs(p[d] - q[d]) < 1e-9 for d in range(3) if round(q[d] * 2) != 1)]
                conn.append(centre(q, on if len(on) == 4 else ids[:8] + [-c - 1]))
        lagrange.append((lty, conn))
    vtk_write("serendipity_lagrange.vtu",
              vtk_grid(lag_pts, lagrange, {"f": np.array(lag_f)}), ascii=True)


def write_gmsh_second_order():
    """Second-order hexahedra and prisms meshed by Gmsh (20- and 27-node hexahedra, 15- and
    18-node prisms, in Gmsh's own node order), a point field `f` added as a Gmsh view; and the
    same cells in VTK's order (`.vtu`, by VTK), each VTK node found by its place: VTK's
    parametric coordinates of the node, mapped by the (straight) cell's corners, matched to the
    Gmsh node there. Then every node moves by a smooth map (curved cells), so a node in the
    wrong place changes the image."""
    import gmsh
    import vtk

    def f_of(x, y, z):
        return np.sin(1.3 * x) + y * y * z + 0.5 * np.cos(2.0 * z)

    for name, prisms, incomplete in (("gmsh_hex20", False, 1), ("gmsh_hex27", False, 0),
                                     ("gmsh_prism15", True, 1), ("gmsh_prism18", True, 0)):
        gmsh.initialize()
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add(name)
        if prisms:
            gmsh.model.occ.addRectangle(0, 0, 0, 2, 1)
            gmsh.model.occ.synchronize()
            gmsh.option.setNumber("Mesh.MeshSizeMin", 0.6)
            gmsh.option.setNumber("Mesh.MeshSizeMax", 0.8)
            gmsh.model.occ.extrude([(2, 1)], 0, 0, 1, numElements=[2], recombine=True)
        else:
            gmsh.model.occ.addBox(0, 0, 0, 2, 1, 1)
            gmsh.model.occ.synchronize()
            for c in gmsh.model.getEntities(1):
                gmsh.model.mesh.setTransfiniteCurve(c[1], 3)
            for sfc in gmsh.model.getEntities(2):
                gmsh.model.mesh.setTransfiniteSurface(sfc[1])
                gmsh.model.mesh.setRecombine(2, sfc[1])
            gmsh.model.mesh.setTransfiniteVolume(1)
        gmsh.model.occ.synchronize()
        gmsh.option.setNumber("Mesh.SecondOrderIncomplete", incomplete)
        gmsh.model.mesh.generate(3)
        gmsh.model.mesh.setOrder(2)
        tags, coords, _ = gmsh.model.mesh.getNodes()
        coords = coords.reshape(-1, 3)
        at = {int(t): k for k, t in enumerate(tags)}
        cells = []
        for ety, _, enodes in zip(*gmsh.model.mesh.getElements(3)):
            _, _, _, n, _, _ = gmsh.model.mesh.getElementProperties(ety)
            cls, vty, corners = {20: (vtk.vtkQuadraticHexahedron, 25, 8),
                                 27: (vtk.vtkTriQuadraticHexahedron, 29, 8),
                                 15: (vtk.vtkQuadraticWedge, 26, 6),
                                 18: (vtk.vtkBiQuadraticQuadraticWedge, 32, 6)}[n]
            pc = cls().GetParametricCoords()
            for e in np.array(enodes, dtype=int).reshape(-1, n):
                own = [at[t] for t in e]
                c = coords[own[:corners]]
                conn = []
                for k in range(n):
                    r, s_, t = pc[3 * k:3 * k + 3]
                    if corners == 8:
                        w = [(1 - r if i in (0, 3, 4, 7) else r) * (1 - s_ if i in (0, 1, 4, 5) else s_)
                             * (1 - t if i < 4 else t) for i in range(8)]
                    else:
                        w = [(1 - r - s_, r, s_)[i % 3] * (1 - t if i < 3 else t) for i in range(6)]
                    p = np.dot(w, c)
                    d = [np.linalg.norm(coords[o] - p) for o in own]
                    assert min(d) < 1e-9, (name, k, min(d))
                    conn.append(own[int(np.argmin(d))])
                cells.append((vty, conn))
        moved = coords + 0.07 * np.stack([np.sin(2 * coords[:, 1] + coords[:, 2]),
                                          np.cos(coords[:, 0] + coords[:, 2]),
                                          np.sin(coords[:, 0] + 2 * coords[:, 1])], axis=1)
        for t, p in zip(tags, moved):
            gmsh.model.mesh.setNode(int(t), list(p), [])
        values = [f_of(*p) for p in moved]
        view = gmsh.view.add("f")
        gmsh.view.addHomogeneousModelData(view, 0, name, "NodeData", tags, values)
        gmsh.option.setNumber("Mesh.MshFileVersion", 4.1)
        gmsh.write(out(name + ".msh"))
        # Only the view's $NodeData after the mesh (not the mesh again).
        gmsh.option.setNumber("PostProcessing.SaveMesh", 0)
        gmsh.option.setNumber("PostProcessing.SaveInterpolationMatrices", 0)
        gmsh.view.write(view, out(name + ".msh"), append=True)
        gmsh.finalize()
        vtk_write(name + ".vtu", vtk_grid(moved, cells, {"f": np.array(values)}))


def pcoords_lagrange(cls, n):
    return parametric_coords(cls, n)


def write_cells():
    write_serendipity()
    write_gmsh_second_order()
    write_lagrange_tets()
    write_lagrange_hexahedra()
    write_lagrange_orders()
    write_polyhedra()
    write_polyhedra_prisms()


if __name__ == "__main__":
    if sys.argv[1:] == ["cells"]:
        write_cells()
        sys.exit(0)
    if sys.argv[1:] == ["serendipity"]:
        write_serendipity()
        write_gmsh_second_order()
        sys.exit(0)
    write_gmsh_native()
    write_hmesh()
    write_msh41_with_entities()
    write_cube_variants()
    write_mixed()
    write_quadratic()
    sizes = sum(os.path.getsize(out(f)) for f in os.listdir(HERE) if not f.endswith(".py"))
    print(f"wrote {len(os.listdir(HERE)) - 1} files, {sizes} bytes")
