"""`vorang.plot`, `vorang.Image` and `vorang.show`: one line from data to a picture, checked
against the CLI rendering the equivalent map files."""

import time
import warnings

import numpy as np
import pytest

import vorang
from test_vorang import INCLUSION, cli, read_pfm

VTU = INCLUSION / "inclusion.vtu"


def box():
    """A jittered 3 × 3 × 3 box of tetrahedra with a smooth point field and a cell field."""
    rng = np.random.default_rng(1)
    g = np.stack(np.meshgrid(*[np.arange(4.0)] * 3, indexing="ij"), -1).reshape(-1, 3)
    g[:, :] += rng.uniform(-0.1, 0.1, g.shape) * ((g > 0) & (g < 3))
    idx = np.arange(64).reshape(4, 4, 4)
    tets = []
    for i in range(3):
        for j in range(3):
            for k in range(3):
                c = [idx[i + a, j + b, k + d] for d in (0, 1) for b in (0, 1) for a in (0, 1)]
                # Kuhn's six tetrahedra of a cube (x fastest in c).
                for p in [(0, 1, 3, 7), (0, 1, 5, 7), (0, 2, 3, 7), (0, 2, 6, 7), (0, 4, 5, 7), (0, 4, 6, 7)]:
                    tets.append([c[q] for q in p])
    t = np.sin(g[:, 0]) + g[:, 1] * 0.3 + g[:, 2] ** 2 * 0.1
    return g, np.array(tets), {"t": t}


class _Block:
    def __init__(self, type, data):
        self.type, self.data = type, data


class _Meshio:
    def __init__(self, points, tets, point_data):
        self.points, self.cells = points, [_Block("tetra", tets)]
        self.point_data, self.cell_data = point_data, {}


class _PyVista:
    def __init__(self, points, tets, point_data):
        self.points = points
        self.celltypes = np.full(len(tets), 10, dtype=np.uint8)
        self.cells = np.column_stack([np.full(len(tets), 4), tets]).ravel()
        self.point_data, self.cell_data = point_data, {}


def test_plot_of_every_kind_of_data_gives_the_same_image():
    points, tets, data = box()
    kw = dict(size=(48, 40), rotate=[(1, 1, 0, 30)])
    ref = vorang.plot(vorang.Volume(points, tets, point_data=data), **kw)
    assert isinstance(ref, vorang.Image) and ref.shape == (40, 48, 4)
    for other in (_Meshio(points, tets, data), _PyVista(points, tets, data)):
        assert np.array_equal(vorang.plot(other, **kw), ref), type(other).__name__
    assert np.array_equal(
        vorang.plot(str(VTU), size=(48, 40)), vorang.plot(vorang.Volume.read(str(VTU)), size=(48, 40))
    )
    assert ref[:, :, :3].min() < 0.9, "something is drawn"


def test_plot_equals_the_cli_with_the_equivalent_maps(tmp_path):
    vol = vorang.Volume.read(str(VTU))
    kw = dict(scalars="temperature", clim=(0.1, 0.6), opacity=[0.0, 0.3, 0.9], opacity_unit_distance=0.5)
    img = vorang.plot(vol, size=(64, 40), **kw)
    cmap, amap, brightness = vorang._plot.transfer_function(vol, **kw)
    # opacity a over clim, per 0.5 length units: χ = −ln(1 − a) / 0.5.
    assert "ABSORPTION_WEIGHTED" in cmap.text
    rows = [l.split() for l in amap.text.splitlines()[4:] if l.strip()]
    assert [float(r[1]) for r in rows] == [0.1, 0.35, 0.6]
    np.testing.assert_allclose([float(r[0]) for r in rows], -np.log1p(-np.array([0, 0.3, 0.9])) / 0.5)
    (tmp_path / "c.cmap").write_text(cmap.text)
    (tmp_path / "a.amap").write_text(amap.text)
    script = tmp_path / "s.tcl"
    script.write_text(
        f"volume {{{VTU}}}\nimagesize 64 40\nview_all\nlinedraw off\nlegend on\n"
        f"colormap {{{tmp_path / 'c.cmap'}}}\nalphamap {{{tmp_path / 'a.amap'}}}\n"
        f"method exact linear 0 {brightness}\noutput {{{tmp_path / 'o.pfm'}}}\nrender_btf\n"
    )
    import subprocess

    subprocess.run([cli(), str(script)], check=True, capture_output=True)
    assert np.array_equal(read_pfm(tmp_path / "o.0001.pfm"), img[:, :, :3])
    # clim and opacity change the picture.
    assert not np.array_equal(vorang.plot(vol, size=(64, 40), **{**kw, "clim": (0.0, 0.7)}), img)
    assert not np.array_equal(vorang.plot(vol, size=(64, 40), **{**kw, "opacity": "sigmoid"}), img)


def test_cmap_by_name_or_object():
    matplotlib = pytest.importorskip("matplotlib")
    vol = vorang.Volume.read(str(VTU))
    by_name = vorang.plot(vol, size=(40, 30), cmap="magma")
    by_object = vorang.plot(vol, size=(40, 30), cmap=matplotlib.colormaps["magma"])
    assert np.array_equal(by_name, by_object)
    assert not np.array_equal(by_name, vorang.plot(vol, size=(40, 30), cmap="viridis"))
    with pytest.raises(ValueError, match="no colormap"):
        vorang.plot(vol, cmap="no_such_map")


def test_image_shows_the_clis_png(tmp_path):
    vol = vorang.Volume.read(str(VTU))
    cmap = INCLUSION / "temperature.cmap"
    img = vorang.render(vol, size=(50, 30), colormap=str(cmap), method="exact linear 0 1", view_all=False)
    assert isinstance(img, vorang.Image) and img.dtype == np.float32
    script = tmp_path / "s.tcl"
    script.write_text(
        f"volume {{{VTU}}}\nimagesize 50 30\nlinedraw off\ncolormap {{{cmap}}}\n"
        f"method exact linear 0 1\noutput {{{tmp_path / 'o.png'}}}\nrender_btf\n"
    )
    import subprocess

    subprocess.run([cli(), str(script)], check=True, capture_output=True)
    assert img._repr_png_() == (tmp_path / "o.0001.png").read_bytes()
    img.save(tmp_path / "again.png")
    assert (tmp_path / "again.png").read_bytes() == (tmp_path / "o.0001.png").read_bytes()
    # Transparent images keep straight alpha, as `background none` writes them.
    clear = vorang.render(vol, size=(20, 10), background="none")
    assert clear.transparent and clear[:, :1].transparent


def test_show_builds_its_widgets_and_refines():
    pytest.importorskip("ipywidgets")
    viewer = vorang._plot._Viewer(
        __import__("ipywidgets"), str(VTU), {"size": (48, 32)}
    )
    assert viewer.image.value[:8] == b"\x89PNG\r\n\x1a\n"
    first = viewer.image.value
    seen = []
    viewer.status.observe(lambda change: seen.append(change["new"]), names="value")
    viewer.settle = 0.05
    viewer.azimuth.value = 40.0  # a slider moves: a preview, then the refined frame
    deadline = time.time() + 60
    while time.time() < deadline and "refined" not in seen:
        time.sleep(0.02)
    assert seen[:1] == ["preview"] and "refined" in seen, seen
    assert viewer.image.value != first


def test_show_without_ipywidgets_is_the_static_image(monkeypatch):
    import builtins

    real = builtins.__import__

    def no_widgets(name, *a, **k):
        if name == "ipywidgets":
            raise ImportError(name)
        return real(name, *a, **k)

    monkeypatch.setattr(builtins, "__import__", no_widgets)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        img = vorang.show(str(VTU), size=(30, 20))
    assert isinstance(img, vorang.Image)
    assert any("ipywidgets" in str(w.message) for w in caught)


def test_plot_of_a_real_pyvista_grid_is_the_files_image():
    pv = pytest.importorskip("pyvista")
    grid = pv.read(str(VTU))
    kw = dict(size=(48, 32), scalars="temperature")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        assert np.array_equal(vorang.plot(grid, **kw), vorang.plot(str(VTU), **kw))
        image = pv.ImageData(dimensions=(5, 4, 3), spacing=(0.5, 0.5, 0.5))
        image.point_data["x"] = np.asarray(image.points)[:, 0]
        vol = vorang.Volume.from_pyvista(image)
    assert vol.n_tets == 4 * 3 * 2 * 6
