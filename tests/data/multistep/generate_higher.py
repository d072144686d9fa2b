#!/usr/bin/env python3
"""Writes the higher-order Exodus II and XDMF files that tests/multistep.rs reads, and the
.vtu files their steps are compared with. The files are committed, so `cargo test` needs no
Python; run this again only after a deliberate change (the same venv as generate.py):

    /tmp/vexo/bin/python tests/data/multistep/generate_higher.py

Four cells apart from each other along x, each on nodes of its own: a HEX27, a WEDGE18, a
PYRAMID14 and a HEX20, with a point field `T` that is no polynomial of degree 2 on them (two
time steps), so that a node put in the wrong place changes the image.

- `higher.e` (netCDF-4) and `higher_classic.e` (CDF-2) by netCDF4-python in the Exodus layout
  (MOOSE/libMesh write the same variables): one block per cell (ids 1 … 4), the connectivity
  in Exodus II's node order, which places each node as the Exodus II manual's element figures
  do (`EXODUS` below).
- `higher_ref_K.vtu` by VTK: the same points, the HEX27 a Lagrange hexahedron (72), the
  WEDGE18 a Lagrange wedge (73), the PYRAMID14 a Lagrange pyramid (74), the HEX20 VTK's
  quadratic hexahedron (25); VTK's node order is taken from VTK's own cells (their
  parametric coordinates), the pyramid's from
  crates/vorang/src/formats/lagrange.rs (VTK numbers no 14-node Lagrange pyramid).
- `higher_wrong_0.vtu`: the Exodus connectivity written as if it were in VTK's order — its
  image must differ from the reference, or the test could not see a wrong permutation.
- `higher.xdmf`: the HEX27 and the WEDGE18 as `Hexahedron_27` and `Wedge_18` cells of a Mixed
  topology (XDMF numbers them as VTK does), the data in the XML; reference
  `higher_xdmf_ref.vtu`.
"""

import os

import netCDF4
import numpy as np
import vtk
from vtk.util.numpy_support import numpy_to_vtk

HERE = os.path.dirname(os.path.abspath(__file__))
TIMES = [0.0, 1.0]


def out(name):
    return os.path.join(HERE, name)


# Each element's nodes on its unit cell, times 2, in Exodus II's order (the manual's figures).
EXODUS = {
    "HEX27": [
        (0, 0, 0), (2, 0, 0), (2, 2, 0), (0, 2, 0), (0, 0, 2), (2, 0, 2), (2, 2, 2), (0, 2, 2),
        (1, 0, 0), (2, 1, 0), (1, 2, 0), (0, 1, 0),  # bottom edges
        (0, 0, 1), (2, 0, 1), (2, 2, 1), (0, 2, 1),  # vertical edges
        (1, 0, 2), (2, 1, 2), (1, 2, 2), (0, 1, 2),  # top edges
        (1, 1, 1),  # centre
        (1, 1, 0), (1, 1, 2),  # bottom, top
        (0, 1, 1), (2, 1, 1), (1, 0, 1), (1, 2, 1),  # faces 1-4-8-5, 2-3-7-6, 1-2-6-5, 3-4-8-7
    ],
    "WEDGE18": [
        (0, 0, 0), (2, 0, 0), (0, 2, 0), (0, 0, 2), (2, 0, 2), (0, 2, 2),
        (1, 0, 0), (1, 1, 0), (0, 1, 0),  # bottom edges
        (0, 0, 1), (2, 0, 1), (0, 2, 1),  # vertical edges
        (1, 0, 2), (1, 1, 2), (0, 1, 2),  # top edges
        (1, 0, 1), (1, 1, 1), (0, 1, 1),  # faces 1-2-5-4, 2-3-6-5, 3-1-4-6
    ],
    "PYRAMID14": [
        (0, 0, 0), (2, 0, 0), (2, 2, 0), (0, 2, 0), (1, 1, 2),
        (1, 0, 0), (2, 1, 0), (1, 2, 0), (0, 1, 0),  # base edges
        (0.5, 0.5, 1), (1.5, 0.5, 1), (1.5, 1.5, 1), (0.5, 1.5, 1),  # edges to the apex
        (1, 1, 0),  # base centre
    ],
    "HEX20": [
        (0, 0, 0), (2, 0, 0), (2, 2, 0), (0, 2, 0), (0, 0, 2), (2, 0, 2), (2, 2, 2), (0, 2, 2),
        (1, 0, 0), (2, 1, 0), (1, 2, 0), (0, 1, 0),
        (0, 0, 1), (2, 0, 1), (2, 2, 1), (0, 2, 1),
        (1, 0, 2), (2, 1, 2), (1, 2, 2), (0, 1, 2),
    ],
}
BLOCKS = ["HEX27", "WEDGE18", "PYRAMID14", "HEX20"]


def vtk_positions(cell, n):
    """VTK's node order of a degree-2 cell: the lattice point (times 2) of each node."""
    cell.GetPointIds().SetNumberOfIds(n)
    cell.GetPoints().SetNumberOfPoints(n)
    for i in range(n):
        cell.GetPointIds().SetId(i, i)
    cell.SetUniformOrderFromNumPoints(n)
    p = cell.GetParametricCoords()
    return [tuple(round(p[3 * i + k] * 2) for k in range(3)) for i in range(n)]


def vtk_order(name):
    """For each VTK node, the Exodus node at its place; and the VTK cell type."""
    if name == "HEX27":
        pos = vtk_positions(vtk.vtkLagrangeHexahedron(), 27)
        ty = 72
    elif name == "WEDGE18":
        pos = vtk_positions(vtk.vtkLagrangeWedge(), 18)
        ty = 73
    elif name == "PYRAMID14":
        return list(range(14)), 74
    else:
        # VTK's quadratic (serendipity) hexahedron, 25.
        p = vtk.vtkQuadraticHexahedron().GetParametricCoords()
        pos = [tuple(round(p[3 * i + k] * 2) for k in range(3)) for i in range(20)]
        ty = 25
    exo = [tuple(c) for c in EXODUS[name]]
    return [exo.index(p) for p in pos], ty


def mesh():
    """The points (each cell's own, in Exodus order, cell after cell) and the cells."""
    points, cells = [], []
    for b, name in enumerate(BLOCKS):
        lattice = np.array(EXODUS[name], dtype=float) / 2
        # A slightly sheared unit cell, 1.5 apart along x: straight edges (VoRANG's cells
        # are straight-sided), every node at its place on them.
        shear = np.array([[1.0, 0.1, 0.05], [0.0, 1.0, 0.1], [0.0, 0.0, 1.0]])
        pts = lattice @ shear + np.array([1.5 * b, 0.0, 0.0])
        start = len(points)
        points.extend(pts.tolist())
        cells.append(np.arange(start, start + len(pts)))
    return np.array(points), cells


def field(points, t):
    x, y, z = points.T
    if t == 0.0:
        return np.sin(2.0 * x) + y * y * z + 0.5 * np.cos(3.0 * z)
    return np.cos(1.5 * x) * y + z * z * x - 0.2 * y


def write_exodus(name, fmt, points, cells):
    d = netCDF4.Dataset(out(name), "w", format=fmt)
    d.api_version = np.float32(8.03)
    d.version = np.float32(8.03)
    d.floating_point_word_size = np.int32(8)
    d.file_size = np.int32(1)
    d.title = "VoRANG test: higher-order Exodus elements"
    for dim, size in (("len_string", 33), ("len_line", 81), ("four", 4), ("len_name", 33),
                      ("num_dim", 3), ("num_nodes", len(points)),
                      ("num_elem", len(cells)), ("num_el_blk", len(cells)),
                      ("num_nod_var", 1)):
        d.createDimension(dim, size)
    d.createDimension("time_step", None)
    for j, (conn, kind) in enumerate(zip(cells, BLOCKS), start=1):
        d.createDimension(f"num_el_in_blk{j}", 1)
        d.createDimension(f"num_nod_per_el{j}", len(conn))
        v = d.createVariable(f"connect{j}", "i4", (f"num_el_in_blk{j}", f"num_nod_per_el{j}"))
        v.elem_type = kind
        v[:] = conn[None, :] + 1
    prop = d.createVariable("eb_prop1", "i4", ("num_el_blk",))
    prop.setncattr("name", "ID")
    prop[:] = np.arange(1, len(cells) + 1)
    d.createVariable("eb_status", "i4", ("num_el_blk",))[:] = np.ones(len(cells))
    for axis, c in zip("xyz", points.T):
        d.createVariable(f"coord{axis}", "f8", ("num_nodes",))[:] = c
    time = d.createVariable("time_whole", "f8", ("time_step",))
    nv = d.createVariable("name_nod_var", "S1", ("num_nod_var", "len_name"))
    nv[:] = netCDF4.stringtochar(np.array(["T"], dtype="S33"))
    values = d.createVariable("vals_nod_var1", "f8", ("time_step", "num_nodes"))
    for s, t in enumerate(TIMES):
        time[s] = t
        values[s, :] = field(points, t)
    d.close()


def write_vtu(name, points, cells, t, kinds=BLOCKS, block=True, permute=True):
    grid = vtk.vtkUnstructuredGrid()
    p = vtk.vtkPoints()
    p.SetDataTypeToDouble()
    p.SetData(numpy_to_vtk(points, deep=True))
    grid.SetPoints(p)
    for conn, kind in zip(cells, kinds):
        order, ty = vtk_order(kind)
        ids = conn[order] if permute else conn[: len(order)]
        grid.InsertNextCell(ty, len(ids), [int(i) for i in ids])
    values = numpy_to_vtk(field(points, t), deep=True)
    values.SetName("T")
    grid.GetPointData().AddArray(values)
    if block:
        ids = numpy_to_vtk(np.arange(1, len(cells) + 1, dtype=np.int32), deep=True)
        ids.SetName("block")
        grid.GetCellData().AddArray(ids)
    w = vtk.vtkXMLUnstructuredGridWriter()
    w.SetFileName(out(name))
    w.SetDataModeToAscii()
    w.SetInputData(grid)
    w.Write()


def write_xdmf(points, cells):
    """The HEX27 and the WEDGE18 as a Mixed topology (XDMF codes 50 and 41, VTK's order)."""
    topo = []
    for conn, kind, code in zip(cells[:2], BLOCKS[:2], (50, 41)):
        order, _ = vtk_order(kind)
        topo += [code] + [int(i) for i in conn[order]]
    used = np.concatenate(cells[:2])
    pts = points[: used.max() + 1]
    t = field(pts, 0.0)
    xyz = "\n".join(" ".join(repr(float(c)) for c in p) for p in pts)
    with open(out("higher.xdmf"), "w") as f:
        f.write(f"""<?xml version="1.0"?>
<Xdmf Version="3.0">
  <Domain>
    <Grid Name="higher" GridType="Uniform">
      <Topology TopologyType="Mixed" NumberOfElements="2">
        <DataItem Dimensions="{len(topo)}" NumberType="Int" Format="XML">
{" ".join(map(str, topo))}
        </DataItem>
      </Topology>
      <Geometry GeometryType="XYZ">
        <DataItem Dimensions="{len(pts)} 3" NumberType="Float" Precision="8" Format="XML">
{xyz}
        </DataItem>
      </Geometry>
      <Attribute Name="T" AttributeType="Scalar" Center="Node">
        <DataItem Dimensions="{len(pts)}" NumberType="Float" Precision="8" Format="XML">
{" ".join(repr(float(v)) for v in t)}
        </DataItem>
      </Attribute>
    </Grid>
  </Domain>
</Xdmf>
""")
    write_vtu("higher_xdmf_ref.vtu", pts, cells[:2], 0.0, kinds=BLOCKS[:2], block=False)


def main():
    points, cells = mesh()
    write_exodus("higher.e", "NETCDF4", points, cells)
    write_exodus("higher_classic.e", "NETCDF3_64BIT_OFFSET", points, cells)
    for k, t in enumerate(TIMES):
        write_vtu(f"higher_ref_{k}.vtu", points, cells, t)
    write_vtu("higher_wrong_0.vtu", points, cells, 0.0, permute=False)
    write_xdmf(points, cells)


if __name__ == "__main__":
    main()
