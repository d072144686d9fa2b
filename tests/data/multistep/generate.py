#!/usr/bin/env python3
"""Writes the small Exodus II, XDMF + HDF5 and VTKHDF files that tests/multistep.rs reads,
each with time steps, and the .vtu files every step is compared with. The files are committed,
so `cargo test` needs no Python; run this again only after a deliberate change:

    python3 -m venv /tmp/vexo
    /tmp/vexo/bin/pip install netCDF4==1.7.2 h5py==3.16.0 meshio==5.3.5 numpy vtk==9.5.2
    /tmp/vexo/bin/python tests/data/multistep/generate.py

One grid, a 3x3x3 Kuhn box (64 points, 162 tetrahedra) with dyadic jitter, and three time
steps t = 0, 0.5, 1.25 of a point field `T`, a 3-component point field `velocity` and a cell
field `material` (0/1), as in tests/data/series. Written as:

- VTKHDF: `flow.vtkhdf` and `moving.vtkhdf` (the grid stretched at step 2) by VTK's own
  vtkHDFWriter (all time steps, the static grid written once); `parts.vtkhdf` by hand with
  h5py after the VTKHDF specification: two partitions (their shared points written twice, as
  a parallel writer does), the grid once, the arrays per step through `Steps/PointDataOffsets`.
- XDMF: `dolfinx.xdmf` + `dolfinx.h5` by hand with h5py in the layout dolfinx's XDMFFile
  writes (the mesh under /Mesh/mesh, one Temporal collection per function whose grids
  xi:include the mesh, P1 data per node and DG0 data per cell, all float64);
  `dolfinx_p2.xdmf` the same on a quadratic mesh (Tetrahedron_10, P2 data on its 10-node
  geometry); `meshio.xdmf` + `meshio.h5` by meshio's TimeSeriesWriter; `mixed.xdmf` by meshio
  with the data in the XML: a Mixed topology of hexahedra, wedges, pyramids and tetrahedra.
- Exodus II: `flow.exo` (netCDF-4) and `flow_classic.e` (CDF-2) by netCDF4-python in the
  Exodus layout: two element blocks (ids 10 and 20, the two materials) and a shell block that
  is skipped, nodal variables `T` and `vx` (`vals_nod_var1`, `vals_nod_var2`), the element
  variable `heat` per block (`elem_var_tab`), `time_whole`; `flow_cdf1.e` (CDF-1) with the
  older `vals_nod_var[time, var, node]`; `cont.e` (steps 0 and 1) with its continuation file
  `cont.e-s0002` (step 2 on the stretched grid); `meshio.e` by meshio's Exodus writer.

The references: `ref_K.vtu` (T float64, velocity float32, material int32),
`ref_moved_2.vtu`, `dolfinx_ref_K.vtu` (all float64), `dolfinx_p2_ref_K.vtu`, `mixed_ref.vtu`,
`exo_ref_K.vtu` and `exo_moved_2.vtu` (cells in block order, `block` and `heat` per cell) —
all by meshio. VTK's vtkHDFReader reads the VTKHDF files back as a check.
"""

import os

import h5py
import meshio
import netCDF4
import numpy as np
import vtk
from vtkmodules.util.vtkAlgorithm import VTKPythonAlgorithmBase
from vtk.util.numpy_support import numpy_to_vtk, numpy_to_vtkIdTypeArray, vtk_to_numpy

HERE = os.path.dirname(os.path.abspath(__file__))
TIMES = [0.0, 0.5, 1.25]


def out(name):
    return os.path.join(HERE, name)


def kuhn_box(n):
    pts, index = [], {}
    for k in range(n + 1):
        for j in range(n + 1):
            for i in range(n + 1):
                index[(i, j, k)] = len(pts)
                inner = 0 < i < n and 0 < j < n and 0 < k < n
                jit = ((i * 3 + j * 5 + k * 7) % 4) / 32.0 if inner else 0.0
                pts.append([i + jit, j - jit, k + jit / 2])
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
    pts = np.array(pts, dtype=np.float64)
    tets = np.array(tets, dtype=np.int64)
    a, b, c, d = (pts[tets[:, i]] for i in range(4))
    negative = np.einsum("ij,ij->i", np.cross(b - a, c - a), d - a) < 0
    tets[negative] = tets[negative][:, [0, 1, 3, 2]]
    return pts, tets


POINTS, TETS = kuhn_box(3)
STRETCHED = POINTS * np.array([1.25, 1.0, 1.0])
MATERIAL = np.where(POINTS[TETS].mean(axis=1)[:, 0] < 1.5, 0, 1).astype(np.int32)


def fields(t, points=POINTS):
    x, y, z = points[:, 0], points[:, 1], points[:, 2]
    temperature = 1.0 + x / 3.0 * np.cos(t) + y / 3.0 * np.sin(t) + z / 6.0
    velocity = np.stack([-y * t, x * t, np.full_like(x, 0.5)], axis=1).astype(np.float32)
    return temperature, velocity


def points_of(k):
    return STRETCHED if k == 2 else POINTS


def write_reference(name, points, cells, point_data, cell_data):
    mesh = meshio.Mesh(points, cells, point_data=point_data, cell_data=cell_data)
    meshio.write(out(name), mesh, binary=True, compression="zlib")


# ---------------------------------------------------------------- VTKHDF


def grid(points, t, shared=None):
    """A vtkUnstructuredGrid of step t; `shared` (points, cells) keeps the very same VTK
    objects, so that vtkHDFWriter sees a static grid and writes it once."""
    temperature, velocity = fields(t, points)
    ug = vtk.vtkUnstructuredGrid()
    if shared is None:
        pts = vtk.vtkPoints()
        pts.SetData(numpy_to_vtk(points, deep=True))
        cells = vtk.vtkCellArray()
        flat = np.hstack([np.full((len(TETS), 1), 4), TETS]).ravel()
        cells.SetCells(len(TETS), numpy_to_vtkIdTypeArray(flat.astype(np.int64), deep=True))
        shared = (pts, cells)
    ug.SetPoints(shared[0])
    ug.SetCells(vtk.VTK_TETRA, shared[1])
    for name, values in (("T", temperature), ("velocity", velocity)):
        a = numpy_to_vtk(values, deep=True)
        a.SetName(name)
        ug.GetPointData().AddArray(a)
    m = numpy_to_vtk(MATERIAL, deep=True)
    m.SetName("material")
    ug.GetCellData().AddArray(m)
    return ug, shared


class Steps(VTKPythonAlgorithmBase):
    """A source with time steps: the grid of each time."""

    def __init__(self, grids):
        super().__init__(nInputPorts=0, nOutputPorts=1, outputType="vtkUnstructuredGrid")
        self.grids = grids

    def RequestInformation(self, request, in_info, out_info):
        info = out_info.GetInformationObject(0)
        sddp = vtk.vtkStreamingDemandDrivenPipeline
        info.Set(sddp.TIME_STEPS(), TIMES, len(TIMES))
        info.Set(sddp.TIME_RANGE(), [TIMES[0], TIMES[-1]], 2)
        return 1

    def RequestData(self, request, in_info, out_info):
        info = out_info.GetInformationObject(0)
        sddp = vtk.vtkStreamingDemandDrivenPipeline
        t = info.Get(sddp.UPDATE_TIME_STEP()) if info.Has(sddp.UPDATE_TIME_STEP()) else 0.0
        k = int(np.argmin([abs(t - s) for s in TIMES]))
        vtk.vtkUnstructuredGrid.GetData(out_info).ShallowCopy(self.grids[k])
        return 1


def write_vtkhdf_with_vtk(name, moving):
    grids, shared = [], None
    for k, t in enumerate(TIMES):
        if moving and k == 2:
            g, _ = grid(STRETCHED, t)
        else:
            g, shared = grid(POINTS, t, shared)
        grids.append(g)
    source = Steps(grids)  # kept alive until the writer is done
    w = vtk.vtkHDFWriter()
    w.SetInputConnection(source.GetOutputPort())
    w.SetFileName(out(name))
    w.SetWriteAllTimeSteps(True)
    w.SetChunkSize(128)  # the default (25000 rows) makes a 2 MB file of this tiny grid
    w.SetCompressionLevel(4)
    w.Write()


def write_vtkhdf_parts(name):
    """Two partitions by hand (each with its own points, connectivity 0-based within it), the
    grid written once for all steps, the point arrays per step."""
    half = len(TETS) // 2
    pieces = []
    for cells in (TETS[:half], TETS[half:]):
        used = np.unique(cells)
        local = np.searchsorted(used, cells)
        pieces.append((used, local))
    with h5py.File(out(name), "w") as f:
        root = f.create_group("VTKHDF")
        root.attrs["Version"] = np.array([2, 2], dtype=np.int64)
        root.attrs.create("Type", np.bytes_("UnstructuredGrid"),
                          dtype=h5py.string_dtype("ascii", len("UnstructuredGrid")))
        root["NumberOfPoints"] = np.array([len(u) for u, _ in pieces], dtype=np.int64)
        root["NumberOfCells"] = np.array([len(c) for _, c in pieces], dtype=np.int64)
        root["NumberOfConnectivityIds"] = np.array([c.size for _, c in pieces], dtype=np.int64)
        root.create_dataset("Points", data=np.vstack([POINTS[u] for u, _ in pieces]),
                            chunks=(32, 3), compression="gzip", shuffle=True)
        root["Types"] = np.full(len(TETS), vtk.VTK_TETRA, dtype=np.uint8)
        root["Connectivity"] = np.concatenate([c.ravel() for _, c in pieces]).astype(np.int64)
        root["Offsets"] = np.concatenate(
            [np.arange(len(c) + 1, dtype=np.int64) * 4 for _, c in pieces])
        pd = root.create_group("PointData")
        temps, vels = [], []
        for t in TIMES:
            temperature, velocity = fields(t)
            temps.append(np.concatenate([temperature[u] for u, _ in pieces]))
            vels.append(np.vstack([velocity[u] for u, _ in pieces]))
        pd.create_dataset("T", data=np.concatenate(temps), chunks=(50,), compression="gzip")
        pd.create_dataset("velocity", data=np.vstack(vels), chunks=(50, 3),
                          compression="gzip")
        root.create_group("CellData")["material"] = MATERIAL
        steps = root.create_group("Steps")
        steps.attrs["NSteps"] = len(TIMES)
        steps["Values"] = np.array(TIMES)
        zeros = np.zeros(len(TIMES), dtype=np.int64)
        steps["PartOffsets"] = zeros
        steps["NumberOfParts"] = np.full(len(TIMES), 2, dtype=np.int64)
        steps["PointOffsets"] = zeros
        steps["CellOffsets"] = zeros.reshape(-1, 1)
        steps["ConnectivityIdOffsets"] = zeros.reshape(-1, 1)
        n = sum(len(u) for u, _ in pieces)
        offsets = steps.create_group("PointDataOffsets")
        offsets["T"] = np.arange(len(TIMES), dtype=np.int64) * n
        offsets["velocity"] = np.arange(len(TIMES), dtype=np.int64) * n
        steps.create_group("CellDataOffsets")["material"] = zeros


def check_vtkhdf(name, steps):
    r = vtk.vtkHDFReader()
    r.SetFileName(out(name))
    r.UpdateInformation()
    for k in range(steps):
        r.UpdateTimeStep(TIMES[k])
        o = r.GetOutputDataObject(0)
        parts = ([o.GetPartition(i) for i in range(o.GetNumberOfPartitions())]
                 if o.IsA("vtkPartitionedDataSet") else [o])
        assert sum(p.GetNumberOfCells() for p in parts) == len(TETS), (name, k)
        for p in parts:
            temps = vtk_to_numpy(p.GetPointData().GetArray("T"))
            pts = vtk_to_numpy(p.GetPoints().GetData())
            expect, _ = fields(TIMES[k], pts)
            assert np.allclose(temps, expect), (name, k)


# ---------------------------------------------------------------- XDMF

XDMF_HEAD = """<?xml version="1.0"?>
<!DOCTYPE Xdmf SYSTEM "Xdmf.dtd" []>
<Xdmf Version="3.0" xmlns:xi="https://www.w3.org/2001/XInclude">
  <Domain>
"""
INCLUDE = ("<xi:include xpointer=\"xpointer(/Xdmf/Domain/Grid[@GridType='Uniform'][1]"
           "/*[self::Topology or self::Geometry])\" />")


def time_key(t):
    return repr(float(t)).rstrip("0").rstrip(".").replace(".", "_") or "0"


def write_dolfinx(stem, points, topology, topology_type, functions):
    """dolfinx's layout: functions is a list of (name, center, values per time)."""
    h5 = stem + ".h5"
    with h5py.File(out(h5), "w") as f:
        mesh = f.create_group("Mesh").create_group("mesh")
        mesh["geometry"] = points
        mesh["topology"] = topology.astype(np.int64)
        fn = f.create_group("Function")
        for name, _, per_time in functions:
            g = fn.create_group(name)
            for t, values in zip(TIMES, per_time):
                g[time_key(t)] = values.reshape(len(values), -1).astype(np.float64)
    lines = [XDMF_HEAD,
             '    <Grid Name="mesh" GridType="Uniform">\n',
             f'      <Topology TopologyType="{topology_type}" NumberOfElements="{len(topology)}"'
             f' NodesPerElement="{topology.shape[1]}">\n',
             f'        <DataItem Dimensions="{len(topology)} {topology.shape[1]}" '
             f'NumberType="Int" Format="HDF">{h5}:/Mesh/mesh/topology</DataItem>\n',
             "      </Topology>\n",
             '      <Geometry GeometryType="XYZ">\n',
             f'        <DataItem Dimensions="{len(points)} 3" Format="HDF">'
             f"{h5}:/Mesh/mesh/geometry</DataItem>\n",
             "      </Geometry>\n",
             "    </Grid>\n"]
    for name, center, per_time in functions:
        lines.append(f'    <Grid Name="{name}" GridType="Collection" CollectionType="Temporal">\n')
        for t, values in zip(TIMES, per_time):
            v = values.reshape(len(values), -1)
            kind = "Scalar" if v.shape[1] == 1 else "Vector"
            lines += [f'      <Grid Name="{name}" GridType="Uniform">\n',
                      f"        {INCLUDE}\n",
                      f'        <Time Value="{t!r}" />\n',
                      f'        <Attribute Name="{name}" AttributeType="{kind}" Center="{center}">\n',
                      f'          <DataItem Dimensions="{v.shape[0]} {v.shape[1]}" Format="HDF">'
                      f"{h5}:/Function/{name}/{time_key(t)}</DataItem>\n",
                      "        </Attribute>\n",
                      "      </Grid>\n"]
        lines.append("    </Grid>\n")
    lines += ["  </Domain>\n", "</Xdmf>\n"]
    with open(out(stem + ".xdmf"), "w") as f:
        f.write("".join(lines))


def quadratic(points, tets):
    """The 10-node tetrahedra of the Kuhn box (VTK's node order) with their mid-edge nodes."""
    edges, mid = {}, []
    pairs = [(0, 1), (1, 2), (0, 2), (0, 3), (1, 3), (2, 3)]
    cells = []
    for t in tets:
        row = list(t)
        for a, b in pairs:
            key = tuple(sorted((t[a], t[b])))
            if key not in edges:
                edges[key] = len(points) + len(mid)
                m = (points[key[0]] + points[key[1]]) / 2
                # Bend the edges a little so that the quadratic geometry is not linear.
                m = m + np.array([0.0, 0.0, 0.03125 * np.sin(m[0])])
                mid.append(m)
            row.append(edges[key])
        cells.append(row)
    return np.vstack([points, mid]), np.array(cells, dtype=np.int64)


def write_xdmf_files():
    temps, vels = zip(*(fields(t) for t in TIMES))
    material = MATERIAL.astype(np.float64)
    write_dolfinx("dolfinx", POINTS, TETS, "Tetrahedron",
                  [("T", "Node", temps),
                   ("velocity", "Node", [v.astype(np.float64) for v in vels]),
                   ("material", "Cell", [material] * 3)])
    for k, t in enumerate(TIMES):
        write_reference(f"dolfinx_ref_{k}.vtu", POINTS, [("tetra", TETS)],
                        {"T": temps[k], "velocity": vels[k].astype(np.float64)},
                        {"material": [material]})
    p2_points, p2_cells = quadratic(POINTS, TETS)
    p2_temps = [fields(t, p2_points)[0] for t in TIMES]
    write_dolfinx("dolfinx_p2", p2_points, p2_cells, "Tetrahedron_10",
                  [("T", "Node", p2_temps)])
    for k in range(len(TIMES)):
        write_reference(f"dolfinx_p2_ref_{k}.vtu", p2_points, [("tetra10", p2_cells)],
                        {"T": p2_temps[k]}, {})
    with meshio.xdmf.TimeSeriesWriter(out("meshio.xdmf")) as w:
        w.write_points_cells(POINTS, [("tetra", TETS)])
        for k, t in enumerate(TIMES):
            w.write_data(t, point_data={"T": temps[k], "velocity": vels[k]},
                         cell_data={"material": [MATERIAL]})
    write_mixed()


def write_mixed():
    """A hexahedron, a wedge, a pyramid and two tetrahedra sharing faces, in the XML."""
    p = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0],
                  [0, 0, 1], [1, 0, 1], [1, 1, 1], [0, 1, 1],
                  [2, 0, 0], [2, 1, 0], [2, 0, 1], [2, 1, 1],
                  [0.5, 0.5, -0.75], [0.5, 0.5, 1.75]], dtype=np.float64)
    cells = [("hexahedron", np.array([[0, 1, 2, 3, 4, 5, 6, 7]])),
             ("wedge", np.array([[1, 8, 9, 5, 10, 11]])),
             ("pyramid", np.array([[0, 3, 2, 1, 12]])),
             ("tetra", np.array([[4, 5, 6, 13], [4, 6, 7, 13]]))]
    value = p[:, 0] + 2 * p[:, 1] - p[:, 2]
    cell_id = [np.array([1.0]), np.array([2.0]), np.array([3.0]), np.array([4.0, 5.0])]
    mesh = meshio.Mesh(p, cells, point_data={"value": value}, cell_data={"id": cell_id})
    meshio.write(out("mixed.xdmf"), mesh, data_format="XML")
    write_reference("mixed_ref.vtu", p, cells, {"value": value}, {"id": cell_id})


# ---------------------------------------------------------------- Exodus II

SHELL = np.array([[1, 2, 18, 17]])  # a boundary face at z = 0 (1-based), skipped


def exodus_cells():
    """The tetrahedra by block: material 0 (block 10) first, then material 1 (block 20)."""
    return [TETS[MATERIAL == m] for m in (0, 1)]


def heat(t, cells, points):
    return points[cells].mean(axis=1)[:, 1] * (1 + t)


def write_exodus(name, fmt, steps, points_per_step, combined=False):
    d = netCDF4.Dataset(out(name), "w", format=fmt)
    d.api_version = np.float32(8.03)
    d.version = np.float32(8.03)
    d.floating_point_word_size = np.int32(8)
    d.file_size = np.int32(1)
    d.title = "VoRANG test: a Kuhn box in two blocks"
    blocks = exodus_cells()
    n = len(POINTS)
    for dim, size in (("len_string", 33), ("len_line", 81), ("four", 4), ("len_name", 33),
                      ("num_dim", 3), ("num_nodes", n), ("num_elem", len(TETS) + 1),
                      ("num_el_blk", 3), ("num_nod_var", 2), ("num_elem_var", 1)):
        d.createDimension(dim, size)
    d.createDimension("time_step", None)
    for j, cells in enumerate(blocks + [SHELL - 1], start=1):
        d.createDimension(f"num_el_in_blk{j}", len(cells))
        d.createDimension(f"num_nod_per_el{j}", cells.shape[1])
        v = d.createVariable(f"connect{j}", "i4", (f"num_el_in_blk{j}", f"num_nod_per_el{j}"))
        v.elem_type = ["TETRA", "tetra4", "SHELL4"][j - 1]
        v[:] = cells + 1
    prop = d.createVariable("eb_prop1", "i4", ("num_el_blk",))
    prop.setncattr("name", "ID")
    prop[:] = [10, 20, 30]
    d.createVariable("eb_status", "i4", ("num_el_blk",))[:] = [1, 1, 1]
    names = d.createVariable("eb_names", "S1", ("num_el_blk", "len_name"))
    names[:] = netCDF4.stringtochar(np.array(["left", "right", "skin"], dtype="S33"))
    pts = points_per_step[0]
    for axis, c in zip("xyz", pts.T):
        d.createVariable(f"coord{axis}", "f8", ("num_nodes",))[:] = c
    time = d.createVariable("time_whole", "f8", ("time_step",))
    nv = d.createVariable("name_nod_var", "S1", ("num_nod_var", "len_name"))
    nv[:] = netCDF4.stringtochar(np.array(["T", "vx"], dtype="S33"))
    ev = d.createVariable("name_elem_var", "S1", ("num_elem_var", "len_name"))
    ev[:] = netCDF4.stringtochar(np.array(["heat"], dtype="S33"))
    d.createVariable("elem_var_tab", "i4", ("num_el_blk", "num_elem_var"))[:] = [[1], [1], [0]]
    if combined:
        d.createDimension("num_nodes_x", n)
        nodal = d.createVariable("vals_nod_var", "f8", ("time_step", "num_nod_var", "num_nodes"))
    else:
        nodal = [d.createVariable(f"vals_nod_var{i}", "f8", ("time_step", "num_nodes"))
                 for i in (1, 2)]
    elem = [d.createVariable(f"vals_elem_var1eb{j}", "f8", ("time_step", f"num_el_in_blk{j}"))
            for j in (1, 2)]
    for s, k in enumerate(steps):
        t = TIMES[k]
        time[s] = t
        temperature, velocity = fields(t, pts)
        if combined:
            nodal[s, 0, :] = temperature
            nodal[s, 1, :] = velocity[:, 0]
        else:
            nodal[0][s, :] = temperature
            nodal[1][s, :] = velocity[:, 0]
        for v, cells in zip(elem, blocks):
            v[s, :] = heat(t, cells, pts)
    d.close()


def write_exodus_references():
    blocks = exodus_cells()
    cells = np.vstack(blocks)
    ids = np.concatenate([np.full(len(b), i) for b, i in zip(blocks, (10, 20))])
    for name, k, pts in [(f"exo_ref_{k}.vtu", k, POINTS) for k in range(3)] + [
            ("exo_moved_2.vtu", 2, STRETCHED)]:
        t = TIMES[k]
        temperature, velocity = fields(t, pts)
        h = np.concatenate([heat(t, b, pts) for b in blocks])
        write_reference(name, pts, [("tetra", cells)],
                        {"T": temperature, "vx": velocity[:, 0].astype(np.float64)},
                        {"block": [ids.astype(np.int32)], "heat": [h]})


def write_exodus_files():
    write_exodus("flow.exo", "NETCDF4", [0, 1, 2], [POINTS])
    write_exodus("flow_classic.e", "NETCDF3_64BIT_OFFSET", [0, 1, 2], [POINTS])
    write_exodus("flow_cdf1.e", "NETCDF3_CLASSIC", [0, 1, 2], [POINTS], combined=True)
    write_exodus("cont.e", "NETCDF4", [0, 1], [POINTS])
    write_exodus("cont.e-s0002", "NETCDF4", [2], [STRETCHED])
    write_exodus_references()
    temperature, _ = fields(0.0)
    meshio.write(out("meshio.e"),
                 meshio.Mesh(POINTS, [("tetra", TETS)], point_data={"T": temperature}))


def write_cyclic():
    """`cyclic.e`: a netCDF-4 (HDF5) file with Exodus's global attributes whose group `g`
    holds a hard link to itself — a hostile file: its groups are no tree."""
    import h5py

    with h5py.File(out("cyclic.e"), "w") as f:
        f.attrs["api_version"] = np.float32(8.03)
        f.attrs["floating_point_word_size"] = np.int32(8)
        g = f.create_group("g")
        g["self"] = g


def main():
    write_vtkhdf_with_vtk("flow.vtkhdf", moving=False)
    write_vtkhdf_with_vtk("moving.vtkhdf", moving=True)
    write_vtkhdf_parts("parts.vtkhdf")
    for k, t in enumerate(TIMES):
        temperature, velocity = fields(t)
        write_reference(f"ref_{k}.vtu", POINTS, [("tetra", TETS)],
                        {"T": temperature, "velocity": velocity}, {"material": [MATERIAL]})
    temperature, velocity = fields(TIMES[2], STRETCHED)
    write_reference("ref_moved_2.vtu", STRETCHED, [("tetra", TETS)],
                    {"T": temperature, "velocity": velocity}, {"material": [MATERIAL]})
    for name in ("flow.vtkhdf", "moving.vtkhdf", "parts.vtkhdf"):
        check_vtkhdf(name, len(TIMES))
    write_xdmf_files()
    write_exodus_files()
    write_cyclic()


if __name__ == "__main__":
    main()
