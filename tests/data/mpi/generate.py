#!/usr/bin/env python3
"""Writes the `.pvtu` grids that tests/mpi.rs and tests/distributed.rs render on ranks: pieces
written by VTK's own parallel writer, as a solver's output would be. The files are committed,
so `cargo test` needs no Python; run this again only after a deliberate change:

    python3 -m venv /tmp/vtkvenv
    /tmp/vtkvenv/bin/pip install vtk==9.3.1 numpy==1.26.4
    /tmp/vtkvenv/bin/python tests/data/mpi/generate.py

One grid, a 6x6x6 Kuhn box (343 points, 1296 tetrahedra) with dyadic jitter inside (exact in
Float32, the type VTK's piece filter writes points in), a point field `T` (Float64), a cell
field `material` (Int32) and the `GlobalNodeIds` point array (Int64: each point's number in
the whole grid; a plain array, as vtkExtractUnstructuredGridPiece drops the global-ids
attribute but keeps the arrays). Written by
vtkXMLPUnstructuredGridWriter, pieces cut by vtkExtractUnstructuredGridPiece:

- `box_g3.pvtu` with `box_g3/box_g3_{0,1,2}.vtu`: 3 pieces, ghost level 1 (each piece carries
  copies of its neighbours' cells, marked in vtkGhostType);
- `box_p5.pvtu` with `box_p5/box_p5_{0..4}.vtu`: 5 pieces, no ghost cells;
- `box.vtu`: the whole grid (vtkXMLUnstructuredGridWriter), the one-process reference.

The pieces are read back with VTK's own reader as a check: the cells without the ghost flag
are the whole grid's, and every piece has the global ids.
"""

import os
import shutil

import numpy as np
import vtk
from vtk.util.numpy_support import numpy_to_vtk, numpy_to_vtkIdTypeArray, vtk_to_numpy

HERE = os.path.dirname(os.path.abspath(__file__))
N = 6


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
    pts = np.array(pts, dtype=np.float64) / n
    tets = np.array(tets, dtype=np.int64)
    a, b, c, d = (pts[tets[:, i]] for i in range(4))
    negative = np.einsum("ij,ij->i", np.cross(b - a, c - a), d - a) < 0
    tets[negative] = tets[negative][:, [0, 1, 3, 2]]
    return pts, tets


POINTS, TETS = kuhn_box(N)


def grid():
    ug = vtk.vtkUnstructuredGrid()
    pts = vtk.vtkPoints()
    pts.SetDataTypeToFloat()
    pts.SetData(numpy_to_vtk(POINTS.astype(np.float32), deep=True))
    ug.SetPoints(pts)
    cells = vtk.vtkCellArray()
    flat = np.hstack([np.full((len(TETS), 1), 4), TETS]).ravel()
    cells.SetCells(len(TETS), numpy_to_vtkIdTypeArray(flat.astype(np.int64), deep=True))
    ug.SetCells(vtk.VTK_TETRA, cells)
    x, y, z = POINTS[:, 0], POINTS[:, 1], POINTS[:, 2]
    t = numpy_to_vtk(0.2 + 0.8 * np.sin(3 * x) * np.cos(2 * y) ** 2 + 0.3 * z, deep=True)
    t.SetName("T")
    ug.GetPointData().AddArray(t)
    ids = numpy_to_vtkIdTypeArray(np.arange(len(POINTS), dtype=np.int64), deep=True)
    ids.SetName("GlobalNodeIds")
    # A plain array: the piece filter drops the global-ids attribute, not the array.
    ug.GetPointData().AddArray(ids)
    centroids = POINTS[TETS].mean(axis=1)
    m = numpy_to_vtk((centroids[:, 2] > 0.5).astype(np.int32), deep=True)
    m.SetName("material")
    ug.GetCellData().AddArray(m)
    return ug


def write_pvtu(stem, pieces, ghost_level):
    if os.path.isdir(out(stem)):
        shutil.rmtree(out(stem))
    ex = vtk.vtkExtractUnstructuredGridPiece()
    ex.SetInputData(grid())
    w = vtk.vtkXMLPUnstructuredGridWriter()
    w.SetInputConnection(ex.GetOutputPort())
    w.SetFileName(out(stem + ".pvtu"))
    w.SetNumberOfPieces(pieces)
    w.SetStartPiece(0)
    w.SetEndPiece(pieces - 1)
    w.SetGhostLevel(ghost_level)
    w.SetUseSubdirectory(True)
    w.Write()


def check(stem, ghosts):
    r = vtk.vtkXMLPUnstructuredGridReader()
    r.SetFileName(out(stem + ".pvtu"))
    r.Update()
    g = r.GetOutput()
    flags = g.GetCellData().GetArray("vtkGhostType")
    kept = g.GetNumberOfCells() if flags is None else int((vtk_to_numpy(flags) == 0).sum())
    assert kept == len(TETS), (stem, kept, len(TETS))
    assert (g.GetNumberOfCells() > len(TETS)) == ghosts, stem
    ids = g.GetPointData().GetArray("GlobalNodeIds")
    assert ids is not None and ids.GetNumberOfTuples() == g.GetNumberOfPoints(), stem


def main():
    w = vtk.vtkXMLUnstructuredGridWriter()
    w.SetInputData(grid())
    w.SetFileName(out("box.vtu"))
    w.Write()
    write_pvtu("box_g3", 3, 1)
    write_pvtu("box_p5", 5, 0)
    check("box_g3", True)
    check("box_p5", False)


if __name__ == "__main__":
    main()
