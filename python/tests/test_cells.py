"""Cells beyond tetrahedra through Python: Lagrange cells (as dolfinx.plot.vtk_mesh hands
them to PyVista), voxels and polyhedra (PyVista's face stream, meshio's face lists) give the
same volumes as the file readers. Duck-typed grids always; real PyVista and meshio where
they are installed."""

import pathlib
import warnings

import numpy as np
import pytest

import vorang

FORMATS = pathlib.Path(__file__).resolve().parents[2] / "tests" / "data" / "formats"

CUBE = np.array([[x, y, z] for z in (0, 1) for y in (0, 1) for x in (0, 1)], dtype=float)
# The cube's faces (point ids of CUBE), some listed inwards.
CUBE_FACES = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]]


def linear(points):
    p = np.asarray(points)
    return 1 + p[:, 0] / 2 - p[:, 1] / 4 + p[:, 2] / 8


def render(vol):
    cmap = vorang.Colormap.table([0.5, 2.25], [[1, 0.2, 0], [0, 0.5, 1]], field="f")
    amap = vorang.Alphamap.table([0.5, 2.25], [0.3, 2.5], field="f")
    return vorang.render(
        vol,
        size=(32, 32),
        colormap=cmap,
        alphamap=amap,
        method="exact linear 0 1",
        linedraw="off",
        rotate=[(1, 2, 3, 70)],
    )


class _Grid:
    """What pyvista.UnstructuredGrid offers (duck-typed)."""

    def __init__(self, points, celltypes, cells, point_data=None, **extra):
        self.points = np.asarray(points, dtype=float)
        self.celltypes = np.asarray(celltypes, dtype=np.uint8)
        self.cells = np.asarray(cells)
        self.point_data = point_data or {}
        self.cell_data = {}
        for k, v in extra.items():
            setattr(self, k, v)


def p2_tet():
    """One Lagrange tetrahedron of degree 2 (VTK 71, 10 nodes, VTK's order) and its corners."""
    corners = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=float)
    edges = [(0, 1), (1, 2), (0, 2), (0, 3), (1, 3), (2, 3)]
    mids = np.array([(corners[a] + corners[b]) / 2 for a, b in edges])
    return corners, np.vstack([corners, mids])


def test_dolfinx_style_lagrange_tetrahedra_from_pyvista():
    corners, nodes = p2_tet()
    p1 = vorang.Volume.from_pyvista(
        _Grid(corners, [71], [4, 0, 1, 2, 3], {"f": linear(corners)})
    )
    p2 = vorang.Volume.from_pyvista(
        _Grid(nodes, [71], [10] + list(range(10)), {"f": linear(nodes)})
    )
    assert p1.n_tets == p2.n_tets == 1
    # The field is linear: the P2 volume renders bit for bit like the P1 one.
    assert np.array_equal(render(p1), render(p2))


def test_voxels_and_lagrange_hexahedra_from_meshio():
    class Block:
        def __init__(self, type, data):
            self.type, self.data = type, np.asarray(data)

    class Mesh:
        points = CUBE
        cells = [Block("VTK_LAGRANGE_HEXAHEDRON", [[0, 1, 3, 2, 4, 5, 7, 6]])]
        point_data = {"f": linear(CUBE)}
        cell_data = {}

    hexa = vorang.Volume.from_meshio(Mesh())
    voxel = vorang.Volume.from_pyvista(
        _Grid(CUBE, [11], [8, 0, 1, 2, 3, 4, 5, 6, 7], {"f": linear(CUBE)})
    )
    assert hexa.n_tets == voxel.n_tets == 6
    assert np.array_equal(render(hexa), render(voxel))


def face_stream(faces):
    stream = [len(faces)]
    for f in faces:
        stream += [len(f)] + f
    return stream


def legacy(lists):
    return np.array([v for l in lists for v in [len(l)] + l])


def test_polyhedra_from_pyvista_face_streams():
    f = {"f": linear(CUBE)}
    # PyVista 0.45 and later (VTK 9.4): faces, and each cell's face ids.
    new = _Grid(
        CUBE,
        [42],
        [8] + list(range(8)),
        f,
        polyhedron_faces=legacy(CUBE_FACES),
        polyhedron_face_locations=legacy([list(range(6))]),
    )
    # Earlier: one face stream per cell, and where it starts.
    old = _Grid(
        CUBE,
        [42],
        [8] + list(range(8)),
        f,
        faces=np.array(face_stream(CUBE_FACES)),
        face_locations=np.array([0]),
    )
    a, b = vorang.Volume.from_pyvista(new), vorang.Volume.from_pyvista(old)
    # A cell centre and six face centres join the cube's points; 6 faces × 4 tetrahedra.
    assert a.n_points == b.n_points == 8 + 1 + 6
    assert a.n_tets == b.n_tets == 24
    hexa = vorang.Volume.from_pyvista(
        _Grid(CUBE, [12], [8, 0, 1, 3, 2, 4, 5, 7, 6], f)
    )
    assert np.abs(render(a) - render(hexa)).max() < 1e-5
    with pytest.raises(ValueError, match="face stream"):
        vorang.Volume.from_pyvista(_Grid(CUBE, [42], [8] + list(range(8)), f))


def test_polyhedra_from_meshio_and_bad_face_streams():
    class Block:
        type = "polyhedron8"
        data = [[np.array(face) for face in CUBE_FACES]]

    class Mesh:
        points = CUBE
        cells = [Block()]
        point_data = {"f": linear(CUBE)}
        cell_data = {}

    assert vorang.Volume.from_meshio(Mesh()).n_tets == 24
    bad = face_stream(CUBE_FACES)
    bad[0] = 7  # one face more than the stream holds
    with pytest.raises(ValueError, match="face stream"):
        vorang.Volume._from_blocks(CUBE, [(42, np.array([bad]))])
    bad = face_stream(CUBE_FACES)
    bad[2] = 99  # a point that does not exist
    with pytest.raises(ValueError, match="99"):
        vorang.Volume._from_blocks(CUBE, [(42, np.array([bad]))])


def test_real_pyvista_dolfinx_style_and_polyhedra():
    pv = pytest.importorskip("pyvista")
    corners, nodes = p2_tet()
    # What pyvista.UnstructuredGrid(*dolfinx.plot.vtk_mesh(V)) holds for a P2 space.
    grid = pv.UnstructuredGrid(np.array([10] + list(range(10))), np.array([71], np.uint8), nodes)
    grid.point_data["f"] = linear(nodes)
    assert vorang.Volume.from_pyvista(grid).n_tets == 1
    cells = np.array([len(face_stream(CUBE_FACES))] + face_stream(CUBE_FACES))
    poly = pv.UnstructuredGrid(cells, np.array([42], np.uint8), CUBE)
    poly.point_data["f"] = linear(CUBE)
    assert vorang.Volume.from_pyvista(poly).n_tets == 24
    for name in ["polyhedra.vtu", "lagrange_p2.vtu", "lagrange_orders.vtu"]:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            ours = vorang.Volume.read(str(FORMATS / name))
            theirs = vorang.Volume.from_pyvista(pv.read(str(FORMATS / name)))
        assert (theirs.n_points, theirs.n_tets) == (ours.n_points, ours.n_tets), name


def test_real_meshio_polyhedra():
    meshio = pytest.importorskip("meshio")
    mesh = meshio.read(str(FORMATS / "polyhedra_meshio.vtu"))
    vol = vorang.Volume.from_meshio(mesh)
    ours = vorang.Volume.read(str(FORMATS / "polyhedra_meshio.vtu"))
    assert (vol.n_points, vol.n_tets) == (ours.n_points, ours.n_tets) == (42, 96)
