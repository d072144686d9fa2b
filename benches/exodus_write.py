#!/usr/bin/env python3
"""Writes a .vtu of tetrahedra as Exodus II files in the layout MOOSE and libMesh write (one
element block `connect1` of TETRA4, `coordx/y/z`, point arrays as nodal variables, cell arrays
as element variables, each in its own number type; one time step), for benches/exodus.sh:

    exodus_write.py BOX.vtu STEM   # writes STEM.exo (netCDF-4), STEM_zlib.exo (netCDF-4,
                                   # deflate level 1, as MOOSE writes by default) and STEM.e (CDF-2)

Needs netCDF4, meshio and numpy (the venv of tests/data/multistep/generate.py).
"""

import sys

import meshio
import netCDF4
import numpy as np


def write(path, fmt, mesh, zlib=False):
    tets = mesh.cells_dict["tetra"]
    d = netCDF4.Dataset(path, "w", format=fmt)
    d.api_version = np.float32(8.03)
    d.version = np.float32(8.03)
    d.floating_point_word_size = np.int32(8)
    d.file_size = np.int32(1)
    d.title = "VoRANG benchmark"
    point_data = [(k, v) for k, v in mesh.point_data.items() if v.ndim == 1]
    cell_data = [(k, v[0]) for k, v in mesh.cell_data.items() if v[0].ndim == 1]
    for dim, size in (("len_string", 33), ("len_line", 81), ("four", 4), ("len_name", 33),
                      ("num_dim", 3), ("num_nodes", len(mesh.points)),
                      ("num_elem", len(tets)), ("num_el_blk", 1),
                      ("num_nod_var", max(len(point_data), 1)),
                      ("num_elem_var", max(len(cell_data), 1)),
                      ("num_el_in_blk1", len(tets)), ("num_nod_per_el1", 4)):
        d.createDimension(dim, size)
    d.createDimension("time_step", None)
    opts = dict(zlib=True, complevel=1) if zlib else {}
    conn = d.createVariable("connect1", "i4", ("num_el_in_blk1", "num_nod_per_el1"), **opts)
    conn.elem_type = "TETRA4"
    conn[:] = tets + 1
    d.createVariable("eb_prop1", "i4", ("num_el_blk",))[:] = [1]
    d.createVariable("eb_status", "i4", ("num_el_blk",))[:] = [1]
    for axis, c in zip("xyz", mesh.points.T):
        d.createVariable(f"coord{axis}", c.dtype, ("num_nodes",), **opts)[:] = c
    d.createVariable("time_whole", "f8", ("time_step",))[0] = 0.0
    if point_data:
        nv = d.createVariable("name_nod_var", "S1", ("num_nod_var", "len_name"))
        nv[:] = netCDF4.stringtochar(np.array([k for k, _ in point_data], dtype="S33"))
        for i, (_, v) in enumerate(point_data, start=1):
            d.createVariable(f"vals_nod_var{i}", v.dtype, ("time_step", "num_nodes"),
                             **opts)[0, :] = v
    if cell_data:
        ev = d.createVariable("name_elem_var", "S1", ("num_elem_var", "len_name"))
        ev[:] = netCDF4.stringtochar(np.array([k for k, _ in cell_data], dtype="S33"))
        for i, (_, v) in enumerate(cell_data, start=1):
            d.createVariable(f"vals_elem_var{i}eb1", v.dtype, ("time_step", "num_el_in_blk1"),
                             **opts)[0, :] = v
    d.close()


def main():
    mesh = meshio.read(sys.argv[1])
    stem = sys.argv[2]
    write(stem + ".exo", "NETCDF4", mesh)
    write(stem + "_zlib.exo", "NETCDF4", mesh, zlib=True)
    write(stem + ".e", "NETCDF3_64BIT_OFFSET", mesh)


if __name__ == "__main__":
    main()
