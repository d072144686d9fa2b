#!/usr/bin/env python3
"""Writes the small collections and time series that tests/series.rs reads. The files are
committed, so `cargo test` needs no Python; run this again only after a deliberate change:

    python3 -m venv /tmp/seriesvenv
    /tmp/seriesvenv/bin/pip install vtk==9.3.1 meshio==5.3.5 numpy==1.26.4
    /tmp/seriesvenv/bin/python tests/data/series/generate.py

One grid, a 3x3x3 Kuhn box (64 points, 162 tetrahedra) with dyadic jitter, and three time
steps t = 0, 0.5, 1.25 of a point field `T` (scalar), a point field `velocity` (3 components)
and a cell field `material` (0/1). Written as:

- `flow_K.vtu` (meshio, one file per step): the reference every collection is compared with,
  and the steps of `flow.pvd` and `flow.vtu.series` (both by hand, in ParaView's layout);
- `flow_p_K.pvtu` with `flow_p_K/flow_p_K_{0,1}.vtu` (VTK's vtkXMLPUnstructuredGridWriter,
  2 pieces cut by vtkExtractUnstructuredGridPiece, ghost level 1: each piece carries copies of
  its neighbour's cells marked in vtkGhostType), listed by `flow_p.pvd`;
- `flow_m_K.vtm` with `flow_m_K/…` (VTK's vtkXMLMultiBlockDataWriter: the two pieces without
  ghosts as an unstructured block and a nested block, plus a polydata block that VoRANG skips),
  listed by `flow_m.vtm.series`;
- `parts.pvd`: step 0 as two parts (the pieces of `flow_m_0`), step 1 as `flow_1.vtu`;
- `moving.pvd`: steps 0 and 1 on the grid, step 2 on the grid stretched (`moved_2.vtu`).

The pieces are read back with VTK's own readers as a check (VTK has no .pvd reader: the
collections' files are checked to exist).
"""

import json
import os
import shutil
from xml.etree import ElementTree

import meshio
import numpy as np
import vtk
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
    # Positively oriented, as VoRANG stores them (so that no step warns about re-orienting).
    a, b, c, d = (pts[tets[:, i]] for i in range(4))
    negative = np.einsum("ij,ij->i", np.cross(b - a, c - a), d - a) < 0
    tets[negative] = tets[negative][:, [0, 1, 3, 2]]
    return pts, tets


POINTS, TETS = kuhn_box(3)
CENTROIDS = POINTS[TETS].mean(axis=1)
MATERIAL = np.where(CENTROIDS[:, 0] < 1.5, 0, 1).astype(np.int32)


def fields(t, points=POINTS):
    x, y, z = points[:, 0], points[:, 1], points[:, 2]
    temperature = 1.0 + x / 3.0 * np.cos(t) + y / 3.0 * np.sin(t) + z / 6.0
    velocity = np.stack([-y * t, x * t, np.full_like(x, 0.5)], axis=1).astype(np.float32)
    return temperature, velocity


def write_vtu(name, t, points=POINTS):
    temperature, velocity = fields(t, points)
    mesh = meshio.Mesh(
        points, [("tetra", TETS)],
        point_data={"T": temperature, "velocity": velocity},
        cell_data={"material": [MATERIAL]},
    )
    meshio.write(out(name), mesh, binary=True, compression="zlib")


def grid(t):
    """The step as a vtkUnstructuredGrid (double points, the same arrays as write_vtu)."""
    temperature, velocity = fields(t)
    ug = vtk.vtkUnstructuredGrid()
    pts = vtk.vtkPoints()
    pts.SetData(numpy_to_vtk(POINTS, deep=True))
    ug.SetPoints(pts)
    cells = vtk.vtkCellArray()
    flat = np.hstack([np.full((len(TETS), 1), 4), TETS]).ravel()
    cells.SetCells(len(TETS), numpy_to_vtkIdTypeArray(flat.astype(np.int64), deep=True))
    ug.SetCells(vtk.VTK_TETRA, cells)
    for name, values in (("T", temperature), ("velocity", velocity)):
        a = numpy_to_vtk(values, deep=True)
        a.SetName(name)
        ug.GetPointData().AddArray(a)
    m = numpy_to_vtk(MATERIAL, deep=True)
    m.SetName("material")
    ug.GetCellData().AddArray(m)
    return ug


def pieces(t, ghost_level):
    """The two pieces of step t as vtkExtractUnstructuredGridPiece cuts them."""
    ex = vtk.vtkExtractUnstructuredGridPiece()
    ex.SetInputData(grid(t))
    result = []
    for piece in range(2):
        ex.UpdatePiece(piece, 2, ghost_level)
        copy = vtk.vtkUnstructuredGrid()
        copy.DeepCopy(ex.GetOutput())
        result.append(copy)
    return result


def write_pvtu(stem, t):
    if os.path.isdir(out(stem)):
        shutil.rmtree(out(stem))
    ex = vtk.vtkExtractUnstructuredGridPiece()
    ex.SetInputData(grid(t))
    w = vtk.vtkXMLPUnstructuredGridWriter()
    w.SetInputConnection(ex.GetOutputPort())
    w.SetFileName(out(stem + ".pvtu"))
    w.SetNumberOfPieces(2)
    w.SetStartPiece(0)
    w.SetEndPiece(1)
    w.SetGhostLevel(1)
    w.SetUseSubdirectory(True)
    w.Write()


def write_vtm(stem, t):
    if os.path.isdir(out(stem)):
        shutil.rmtree(out(stem))
    a, b = pieces(t, 0)
    for p in (a, b):
        p.GetCellData().RemoveArray("vtkGhostType")
        p.GetPointData().RemoveArray("vtkGhostType")
    sphere = vtk.vtkSphereSource()
    sphere.SetThetaResolution(6)
    sphere.SetPhiResolution(4)
    sphere.Update()
    inner = vtk.vtkMultiBlockDataSet()
    inner.SetBlock(0, b)
    inner.SetBlock(1, sphere.GetOutput())
    inner_meta = inner.GetMetaData(1)
    inner_meta.Set(vtk.vtkCompositeDataSet.NAME(), "probe")
    mb = vtk.vtkMultiBlockDataSet()
    mb.SetBlock(0, a)
    mb.GetMetaData(0).Set(vtk.vtkCompositeDataSet.NAME(), "left")
    mb.SetBlock(1, inner)
    mb.GetMetaData(1).Set(vtk.vtkCompositeDataSet.NAME(), "right")
    w = vtk.vtkXMLMultiBlockDataWriter()
    w.SetInputData(mb)
    w.SetFileName(out(stem + ".vtm"))
    w.Write()


def write_pvd(name, datasets):
    """datasets: (time, part, file) triples."""
    lines = ['<?xml version="1.0"?>',
             '<VTKFile type="Collection" version="0.1" byte_order="LittleEndian">',
             "  <Collection>"]
    for t, part, f in datasets:
        lines.append(f'    <DataSet timestep="{t!r}" group="" part="{part}" file="{f}"/>')
    lines += ["  </Collection>", "</VTKFile>", ""]
    with open(out(name), "w") as f:
        f.write("\n".join(lines))


def write_series(name, files):
    entries = ",\n".join(f'    {{ "name" : "{f}", "time" : {t!r} }}' for t, f in files)
    with open(out(name), "w") as f:
        f.write('{\n  "file-series-version" : "1.0",\n  "files" : [\n' + entries + "\n  ]\n}\n")


def check():
    """VTK's readers read what was written: the same number of cells in every form."""
    def cells_of(reader_class, name):
        r = reader_class()
        r.SetFileName(out(name))
        r.Update()
        return r.GetOutput()

    whole = cells_of(vtk.vtkXMLUnstructuredGridReader, "flow_0.vtu").GetNumberOfCells()
    p = cells_of(vtk.vtkXMLPUnstructuredGridReader, "flow_p_0.pvtu")
    ghosts = vtk_to_numpy(p.GetCellData().GetArray("vtkGhostType"))
    assert (ghosts == 0).sum() == whole, ((ghosts == 0).sum(), whole)
    assert ghosts.size > whole  # ghost level 1 carried copies
    mb = cells_of(vtk.vtkXMLMultiBlockDataReader, "flow_m_0.vtm")
    n = mb.GetBlock(0).GetNumberOfCells() + mb.GetBlock(1).GetBlock(0).GetNumberOfCells()
    assert n == whole, (n, whole)
    # VTK has no .pvd reader (ParaView's vtkPVDReader is not in its wheel): the XML parses
    # and every file it names exists.
    for name in ("flow.pvd", "flow_p.pvd", "parts.pvd", "moving.pvd"):
        for ds in ElementTree.parse(out(name)).getroot().iter("DataSet"):
            assert os.path.isfile(out(ds.get("file"))), (name, ds.get("file"))
    for name in ("flow.vtu.series", "flow_m.vtm.series"):
        with open(out(name)) as f:
            for entry in json.load(f)["files"]:
                assert os.path.isfile(out(entry["name"])), (name, entry)


def main():
    for k, t in enumerate(TIMES):
        write_vtu(f"flow_{k}.vtu", t)
        write_pvtu(f"flow_p_{k}", t)
        write_vtm(f"flow_m_{k}", t)
    stretched = POINTS * np.array([1.25, 1.0, 1.0])
    write_vtu("moved_2.vtu", TIMES[2], stretched)
    write_pvd("flow.pvd", [(t, 0, f"flow_{k}.vtu") for k, t in enumerate(TIMES)])
    write_series("flow.vtu.series", [(t, f"flow_{k}.vtu") for k, t in enumerate(TIMES)])
    write_pvd("flow_p.pvd", [(t, 0, f"flow_p_{k}.pvtu") for k, t in enumerate(TIMES)])
    write_series("flow_m.vtm.series", [(t, f"flow_m_{k}.vtm") for k, t in enumerate(TIMES)])
    write_pvd("parts.pvd", [(0.0, 0, "flow_m_0/flow_m_0_0.vtu"),
                            (0.0, 1, "flow_m_0/flow_m_0_1.vtu"),
                            (0.5, 0, "flow_1.vtu")])
    write_pvd("moving.pvd", [(0.0, 0, "flow_0.vtu"), (0.5, 0, "flow_1.vtu"),
                             (1.25, 0, "moved_2.vtu")])
    check()


if __name__ == "__main__":
    main()
