"""Tests of the Python package: renders equal the CLI's PFM output bit for bit, array edge
cases, and clear errors. The CLI binary is $VORANG_BIN, else target/release/vorang or
target/debug/vorang of the repository (built with `cargo build --release` if neither exists)."""

import os
import pathlib
import subprocess
import warnings

import numpy as np
import pytest

import vorang

ROOT = pathlib.Path(__file__).resolve().parents[2]
INCLUSION = ROOT / "examples" / "inclusion"
FORMATS = ROOT / "tests" / "data" / "formats"


def cli():
    env = os.environ.get("VORANG_BIN")
    if env:
        return env
    for kind in ("release", "debug"):
        p = ROOT / "target" / kind / "vorang"
        if p.is_file():
            return str(p)
    subprocess.run(["cargo", "build", "--release", "--bin", "vorang"], cwd=ROOT, check=True)
    return str(ROOT / "target" / "release" / "vorang")


def read_pfm(path):
    data = pathlib.Path(path).read_bytes()
    parts = data.split(b"\n", 3)
    assert parts[0] == b"PF"
    w, h = (int(x) for x in parts[1].split())
    assert float(parts[2]) < 0  # little-endian
    rgb = np.frombuffer(parts[3], dtype="<f4").reshape(h, w, 3)
    return rgb[::-1]  # PFM rows run bottom to top


def cli_render(tmp_path, volume_path, commands):
    script = tmp_path / "scene.tcl"
    script.write_text(
        f"volume {{{volume_path}}}\noutput {{{tmp_path / 'out.pfm'}}}\n"
        + "\n".join(commands)
        + "\nrender_btf\n"
    )
    subprocess.run([cli(), str(script)], check=True, capture_output=True)
    return read_pfm(tmp_path / "out.0001.pfm")


def fmt(xs):
    return " ".join(repr(float(x)) for x in xs)


SCENES = [
    # (kwargs, script commands)
    (
        dict(
            size=(64, 40),
            colormap=str(INCLUSION / "temperature.cmap"),
            alphamap=str(INCLUSION / "material.amap"),
            ortho=(-1.3, 1.3, -0.8125, 0.8125, -10, 10),
            rotate=[(1, 0, 0, -25), (0, 1, 0, 20)],
            method="exact linear 0 1.5",
            linedraw="off",
        ),
        [
            f"colormap {{{INCLUSION / 'temperature.cmap'}}}",
            f"alphamap {{{INCLUSION / 'material.amap'}}}",
            "ortho_camera -1.3 1.3 -0.8125 0.8125 -10 10",
            "vol_rotate 1 0 0 -25",
            "vol_rotate 0 1 0 20",
            "method exact linear 0 1.5",
            "linedraw off",
            "imagesize 64 40",
        ],
    ),
    (
        dict(
            size=(48, 48),
            persp=(40, 1, 0.5, 20),
            look_at=((0.3, 0.2, 5), (0, 0, 0), (0, 1, 0)),
            scale=(1, 1.5, 1),
            rotate=[(0, 0, 1, 30)],
            translate=(0.1, 0, 0),
            background=(0, 0, 0.2),
        ),
        [
            "imagesize 48 48",
            "persp_camera 40 1 0.5 20",
            "look_at 0.3 0.2 5 0 0 0 0 1 0",
            "vol_scale 1 1.5 1",
            "vol_rotate 0 0 1 30",
            "vol_translate 0.1 0 0",
            "background 0 0 0.2",
        ],
    ),
    (
        dict(size=(30, 20), background="none", method="exact linear 0 1.0", rotate=[(0, 1, 0, 90)]),
        ["imagesize 30 20", "background none", "method exact linear 0 1.0", "vol_rotate 0 1 0 90"],
    ),
    (
        dict(size=(30, 20), persp=(30, 1.5, 1, 30), background="clear"),
        ["imagesize 30 20", "persp_camera 30 1.5 1 30", "background clear"],
    ),
]


def with_maps(kwargs, commands):
    """A scene with the inclusion's maps, the test method and grid lines where it names none
    (the Python defaults differ from the script's), and `view_all` where Python frames the
    volume (no camera given)."""
    kwargs, commands = dict(kwargs), list(commands)
    if "colormap" not in kwargs:
        kwargs["colormap"] = str(INCLUSION / "temperature.cmap")
        kwargs["alphamap"] = str(INCLUSION / "material.amap")
        commands += [
            f"colormap {{{INCLUSION / 'temperature.cmap'}}}",
            f"alphamap {{{INCLUSION / 'material.amap'}}}",
        ]
    if "method" not in kwargs:
        kwargs["method"] = "test 0.5"
    if "linedraw" not in kwargs:
        kwargs["linedraw"] = "on"
        commands.append("linedraw on")
    if "persp" not in kwargs and "ortho" not in kwargs:
        commands.append("view_all")
    return kwargs, commands


@pytest.mark.parametrize("kwargs,commands", SCENES)
def test_render_equals_cli_pfm(tmp_path, kwargs, commands):
    kwargs, commands = with_maps(kwargs, commands)
    vol = vorang.Volume.read(str(INCLUSION / "inclusion.vtu"))
    img = vorang.render(vol, **kwargs)
    w, h = kwargs["size"]
    assert img.shape == (h, w, 4) and img.dtype == np.float32
    ref = cli_render(tmp_path, INCLUSION / "inclusion.vtu", commands)
    assert np.array_equal(img[:, :, :3], ref), "RGB differs from the CLI's PFM"
    assert img[:, :, :3].max() > 0


def test_table_maps_equal_cli(tmp_path):
    cmap = vorang.Colormap.preset("viridis", 0.2, 3.0, field="temperature")
    amap = vorang.Alphamap.table([0.2, 3.0], [0.1, 1.5], field="temperature")
    (tmp_path / "c.cmap").write_text(cmap.text)
    (tmp_path / "a.amap").write_text(amap.text)
    vol = vorang.Volume.read(str(INCLUSION / "inclusion.vtu"))
    img = vorang.render(
        vol, size=(40, 30), colormap=cmap, alphamap=amap, method="exact linear 0 1.0"
    )
    ref = cli_render(
        tmp_path,
        INCLUSION / "inclusion.vtu",
        [
            f"colormap {{{tmp_path / 'c.cmap'}}}",
            f"alphamap {{{tmp_path / 'a.amap'}}}",
            "imagesize 40 30",
            "method exact linear 0 1.0",
            "linedraw off",
            "view_all",
        ],
    )
    assert np.array_equal(img[:, :, :3], ref)
    # Map text works as well as map objects and paths.
    img2 = vorang.render(
        vol, size=(40, 30), colormap=cmap.text, alphamap=str(tmp_path / "a.amap"),
        method="exact linear 0 1.0",
    )
    assert np.array_equal(img, img2)


def test_lights_equal_cli(tmp_path):
    cmap = (
        "# VoRANG Colormap 1.0\nDataField \"temperature\"\nLIT_EMITTER @1\n@1\n"
        "0.2 0.8 0.5 10\n0 0 1 0.2\n1 1 0 3\n"
    )
    (tmp_path / "lit.cmap").write_text(cmap)
    vol = vorang.Volume.read(str(INCLUSION / "inclusion.vtu"))
    kwargs = dict(size=(32, 24), colormap=cmap, method="exact linear 0 1.0", linedraw="off")
    img = vorang.render(vol, lights=[(1, 0.9, 0.8, 1, 1, 1), (0, 0, 1, -1, 0, 0)], **kwargs)
    ref = cli_render(
        tmp_path,
        INCLUSION / "inclusion.vtu",
        [
            f"colormap {{{tmp_path / 'lit.cmap'}}}",
            "imagesize 32 24",
            "view_all",
            "method exact linear 0 1.0",
            "linedraw off",
            "addlight 1 0.9 0.8 1 1 1",
            "addlight 0 0 1 -1 0 0",
        ],
    )
    assert np.array_equal(img[:, :, :3], ref)
    # The lights matter: the default light at the camera gives another image.
    assert not np.array_equal(vorang.render(vol, **kwargs), img)


def test_save_and_run_script(tmp_path):
    vol = vorang.Volume.read(str(INCLUSION / "inclusion.vtu"))
    cmap = INCLUSION / "temperature.cmap"
    img = vorang.render(vol, size=(20, 10), colormap=str(cmap), method="test 0.5",
                        linedraw="on", view_all=False)
    vorang.save(img, str(tmp_path / "x.pfm"))
    assert np.array_equal(read_pfm(tmp_path / "x.pfm"), img[:, :, :3])
    vorang.save(img, tmp_path / "x.png")
    assert (tmp_path / "x.png").stat().st_size > 0
    vorang.run_script(
        f"volume {{{INCLUSION / 'inclusion.vtu'}}}\nimagesize 20 10\ncolormap {{{cmap}}}\n"
        f"output {{{tmp_path / 's.pfm'}}}\nrender_btf\n"
    )
    assert np.array_equal(read_pfm(tmp_path / "s.0001.pfm"), img[:, :, :3])
    with pytest.raises(OSError):
        vorang.run_script(str(tmp_path / "missing.tcl"))
    with pytest.raises(RuntimeError, match="no_such_command"):
        vorang.run_script("imagesize 2 2\nno_such_command 1\n")


PTS = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1], [1, 1, 1]], dtype=np.float64)
TETS = np.array([[0, 1, 2, 3], [1, 2, 3, 4]], dtype=np.int64)


def reference():
    return vorang.render(
        vorang.Volume(PTS, TETS, point_data={"t": np.arange(5.0)}),
        size=(16, 12),
        colormap=vorang.Colormap.table([0, 4], [[0, 0, 1], [1, 1, 0]]),
        method="exact linear 0 1.0",
    )


@pytest.mark.parametrize("pdtype", [np.float32, np.float64])
@pytest.mark.parametrize("tdtype", [np.int32, np.int64, np.uint32])
def test_dtypes(pdtype, tdtype):
    vol = vorang.Volume(PTS.astype(pdtype), TETS.astype(tdtype), point_data={"t": np.arange(5.0)})
    assert vol.n_points == 5 and vol.n_tets == 2 and vol.field_names == ["t"]
    img = vorang.render(
        vol,
        size=(16, 12),
        colormap=vorang.Colormap.table([0, 4], [[0, 0, 1], [1, 1, 0]]),
        method="exact linear 0 1.0",
    )
    # The coordinates are exactly representable in float32: same image.
    assert np.array_equal(img, reference())


def test_non_contiguous_inputs():
    big = np.zeros((5, 6))
    big[:, ::2] = PTS
    pts = big[:, ::2]
    assert not pts.flags["C_CONTIGUOUS"]
    tets = np.asfortranarray(TETS)
    t = np.zeros(10)
    t[::2] = np.arange(5.0)
    vol = vorang.Volume(pts, tets, point_data={"t": t[::2]})
    img = vorang.render(
        vol,
        size=(16, 12),
        colormap=vorang.Colormap.table([0, 4], [[0, 0, 1], [1, 1, 0]]),
        method="exact linear 0 1.0",
    )
    assert np.array_equal(img, reference())
    # Lists work too.
    vorang.Volume(PTS.tolist(), TETS.tolist())


def test_fields_and_materials():
    vol = vorang.Volume(
        PTS,
        TETS,
        point_data={"t": np.arange(5.0), "v": np.ones((5, 3))},
        cell_data={"material": np.array([1, 2], dtype=np.int32), "q": np.array([0.5, 1.5])},
    )
    assert vol.field_names == ["t", "v", "material", "q"]
    cmap = (
        "# VoRANG Colormap 1.0\nCategoryField \"material\"\n"
        "CONST_CELL field:\"material\" @1\n@1\n1 0 0 1\n0 1 0 2\n"
    )
    img = vorang.render(vol, size=(16, 12), colormap=cmap)
    assert img.shape == (12, 16, 4)


@pytest.mark.parametrize(
    "args,kwargs,exc,match",
    [
        ((PTS[:, :2], TETS), {}, ValueError, r"points: expected shape \(N, 3\), found \(5, 2\)"),
        ((PTS, TETS[:, :3]), {}, ValueError, r"tets: expected shape \(M, 4\)"),
        ((PTS, TETS.astype(float)), {}, ValueError, "tets: expected integers"),
        ((PTS, TETS + 1), {}, ValueError, "refers to point 5 .0-based., but there are only 5 points"),
        ((PTS, TETS - 1), {}, ValueError, "negative"),
        ((PTS * np.nan, TETS), {}, ValueError, "non-finite coordinate"),
        ((PTS * [1, 1, 0], TETS), {}, ValueError, "degenerate"),
        ((PTS, TETS), {"point_data": {"t": np.zeros(4)}}, ValueError, r"point_data\[\"t\"\]: expected shape \(5,\)"),
        ((PTS, TETS), {"cell_data": {"m": np.zeros((3, 1))}}, ValueError, r"cell_data\[\"m\"\]: expected shape \(2,\)"),
        ((PTS, TETS), {"point_data": {"s": np.array(["a"] * 5)}}, ValueError, "expected numbers"),
        ((np.array(["x"] * 15).reshape(5, 3), TETS), {}, ValueError, "points: expected floats"),
    ],
)
def test_bad_arrays(args, kwargs, exc, match):
    with pytest.raises(exc, match=match):
        vorang.Volume(*args, **kwargs)


def test_bad_files_and_options(tmp_path):
    with pytest.raises(OSError, match="no such file"):
        vorang.Volume.read(str(tmp_path / "missing.vtu"))
    (tmp_path / "junk.vtu").write_text("not a mesh\n")
    with pytest.raises(ValueError):
        vorang.Volume.read(str(tmp_path / "junk.vtu"))
    vol = vorang.Volume(PTS, TETS, point_data={"t": np.arange(5.0)})
    with pytest.raises(OSError):
        vorang.render(vol, colormap=str(tmp_path / "missing.cmap"))
    with pytest.raises(ValueError, match="Colormap"):
        vorang.render(vol, colormap="# VoRANG Alphamap 1.0\nCONSTANT @1\n@1\n1\n")
    with pytest.raises(ValueError, match="method"):
        vorang.render(vol, size=(4, 4), method="bogus")
    with pytest.raises(ValueError, match="size"):
        vorang.render(vol, size=(0, 4))
    with pytest.raises(ValueError, match="not both"):
        vorang.render(vol, persp=(40, 1, 1, 10), ortho=(-1, 1, -1, 1, -1, 1))
    with pytest.raises(ValueError):
        vorang.render(vol, rotate=[(0, 0, 0, 30)], size=(4, 4))
    with pytest.raises(ValueError):
        vorang.Colormap.preset("nope", 0, 1)
    with pytest.raises(ValueError, match="image"):
        vorang.save(np.zeros((4, 4)), str(tmp_path / "x.png"))


@pytest.mark.parametrize(
    "name",
    sorted(p.name for p in FORMATS.glob("cube*") if p.is_file()),
)
def test_read_every_format(name):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        vol = vorang.Volume.read(str(FORMATS / name))
    assert vol.n_tets > 0


class _Block:
    def __init__(self, type, data):
        self.type, self.data = type, data


class _Mesh:
    """What meshio.Mesh offers (duck-typed)."""

    def __init__(self):
        self.points = np.array(
            [[x, y, z] for z in (0, 1) for y in (0, 1) for x in (0, 1)], dtype=float
        )
        self.cells = [
            _Block("hexahedron", np.array([[0, 1, 3, 2, 4, 5, 7, 6]])),
            _Block("triangle", np.array([[0, 1, 2]])),
        ]
        self.point_data = {"t": np.arange(8.0)}
        self.cell_data = {"material": [np.array([3]), np.array([1])]}


def test_from_meshio_splits_hexahedra():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        vol = vorang.Volume.from_meshio(_Mesh())
    assert isinstance(vol, vorang.Volume)
    assert vol.n_points == 8 and vol.n_tets >= 5
    assert vol.field_names == ["t", "material"]


class _Grid:
    """What pyvista.UnstructuredGrid offers (duck-typed)."""

    def __init__(self):
        self.points = PTS
        self.celltypes = np.array([10, 10], dtype=np.uint8)
        self.cells = np.array([4, 0, 1, 2, 3, 4, 1, 2, 3, 4])
        self.point_data = {"t": np.arange(5.0)}
        self.cell_data = {}


def test_from_pyvista():
    vol = vorang.Volume.from_pyvista(_Grid())
    assert vol.n_tets == 2 and vol.field_names == ["t"]


class _ImageData:
    """What pyvista.ImageData (and RectilinearGrid, StructuredGrid) offers (duck-typed):
    points x fastest, dimensions in points."""

    def __init__(self, nx, ny, nz):
        z, y, x = np.meshgrid(np.arange(nz), np.arange(ny), np.arange(nx), indexing="ij")
        self.points = np.column_stack([x.ravel(), y.ravel(), z.ravel()]).astype(float)
        self.dimensions = (nx, ny, nz)
        self.point_data = {"x": self.points[:, 0].copy()}
        self.cell_data = {"id": np.arange((nx - 1) * (ny - 1) * (nz - 1), dtype=np.int64)}


class _Voxels:
    """An UnstructuredGrid of voxels (VTK type 11: x fastest, then y, then z) with offsets."""

    def __init__(self, image):
        cells = vorang._structured_cells(image.dimensions)
        self.points = image.points
        self.celltypes = np.full(len(cells), 11, dtype=np.uint8)
        self.cell_connectivity = cells[:, vorang._VOXEL_AS_HEX].ravel()
        self.offset = np.arange(len(cells) + 1) * 8
        self.point_data = image.point_data
        self.cell_data = image.cell_data


def test_from_pyvista_structured_and_voxels_render_as_hexahedra():
    image = _ImageData(4, 3, 3)
    a = vorang.Volume.from_pyvista(image)
    assert a.n_points == 36 and a.n_tets == 3 * 2 * 2 * 6
    assert a.field_names == ["x", "id"]
    b = vorang.Volume.from_pyvista(_Voxels(image))
    assert b.n_tets == a.n_tets
    hexes = vorang.Volume._from_blocks(
        image.points, [(12, vorang._structured_cells(image.dimensions))], image.point_data,
        image.cell_data,
    )
    kw = dict(size=(32, 24), rotate=[(1, 1, 0, 30)])
    ref = vorang.render(hexes, **kw)
    assert np.array_equal(vorang.render(a, **kw), ref)
    assert np.array_equal(vorang.render(b, **kw), ref)
    # Cell data stays cell data, in VTK's cell order (grouping by type keeps it aligned).
    mixed = _Grid()
    mixed.celltypes = np.array([10, 5, 10], dtype=np.uint8)
    mixed.cells = np.array([4, 0, 1, 2, 3, 3, 0, 1, 2, 4, 1, 2, 3, 4])
    mixed.cell_data = {"c": np.array([7, 99, 8])}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        vol = vorang.Volume.from_pyvista(mixed)
    assert vol.n_tets == 2


def test_from_pyvista_messages_name_no_file():
    flat = _ImageData(4, 3, 1)
    with pytest.raises(ValueError, match="at least 2 points") as e:
        vorang.Volume.from_pyvista(flat)
    assert "this file" not in str(e.value)
    surface = _Grid()
    surface.celltypes = np.array([5], dtype=np.uint8)
    surface.cells = np.array([3, 0, 1, 2])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        with pytest.raises(ValueError, match="no volume cells") as e:
            vorang.Volume.from_pyvista(surface)
    assert "this file" not in str(e.value)


def test_signature_defaults():
    import inspect

    sig = inspect.signature(vorang.render)
    assert sig.parameters["background"].default == "white"
    assert sig.parameters["method"].default == "exact linear 0"
    assert sig.parameters["linedraw"].default == "off"
    assert sig.parameters["view_all"].default is True
    assert sig.parameters["rotate"].default == ()


def test_defaults_give_a_first_picture():
    """No maps, no camera, no method: the preset maps over the field's range, the exact
    method at the ramp's χ_max, no grid lines, the volume framed undistorted — and nothing to
    warn about."""
    vol = vorang.Volume.read(str(INCLUSION / "inclusion.vtu"))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        img = vorang.render(vol, size=(96, 60))
    assert [str(w.message) for w in caught] == []
    rgb = img[:, :, :3]
    # Coloured, not a red slab and not black lines: the viridis table's blues and greens.
    assert (np.abs(rgb - 1.0).sum(axis=2) > 0.05).mean() > 0.05
    assert rgb[:, :, 1].max() > rgb[:, :, 0].max() * 0.5
    # The preset by name is the default's table; another preset differs.
    assert np.array_equal(vorang.render(vol, size=(96, 60), colormap="viridis"), img)
    assert not np.array_equal(vorang.render(vol, size=(96, 60), colormap="magma"), img)
    # Grid lines and the stretching default camera are one keyword away.
    assert not np.array_equal(vorang.render(vol, size=(96, 60), linedraw="on"), img)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        vorang.render(vol, size=(96, 60), view_all=False)
    assert any("view_all" in str(w.message) for w in caught)
    # The method's last parameter may be left out: 1 (here, the preset's χ_max) is used.
    assert np.array_equal(vorang.render(vol, size=(96, 60), method="exact linear 0"), img)
    one = vorang.render(
        vol, size=(40, 30), colormap=str(INCLUSION / "temperature.cmap"), method="exact linear 0"
    )
    assert np.array_equal(
        one,
        vorang.render(
            vol,
            size=(40, 30),
            colormap=str(INCLUSION / "temperature.cmap"),
            method="exact linear 0 1",
        ),
    )


def test_progress_and_interrupt():
    vol = vorang.Volume.read(str(INCLUSION / "inclusion.vtu"))
    calls = []
    vorang.render(vol, size=(200, 150), progress=lambda d, t: calls.append((d, t)))
    assert calls and calls[-1][0] == calls[-1][1]

    class Bar:  # tqdm-like
        total = None
        n = 0

        def update(self, k):
            self.n += k

    bar = Bar()
    vorang.render(vol, size=(200, 150), progress=bar)
    assert bar.total and bar.n == bar.total

    raised = []

    def boom(d, t):
        raised.append((d, t))
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        vorang.render(vol, size=(400, 300), progress=boom)
    # Stopped promptly: the tiles not yet started were skipped (35 tiles of 64 px here; only
    # those already running when the first one finished report).
    assert 1 <= len(raised) <= (os.cpu_count() or 1) + 1, raised

    # The interpreter (and the renderer) are still usable.
    img = vorang.render(vol, size=(20, 10))
    assert img.shape == (10, 20, 4)
