"""Tests of vorang.Series and vorang.animate: a time series' steps load lazily as Volumes,
render (by step or time) what the CLI renders for the same step bit for bit, its ranges span
all steps, and animate writes one movie frame per step, with the label. The data are
tests/data/series (made by tests/data/series/generate.py)."""

import warnings

import numpy as np
import pytest

import vorang
from test_vorang import ROOT, cli, read_pfm

SERIES = ROOT / "tests" / "data" / "series"
SCENE = dict(
    size=(48, 40),
    colormap="# VoRANG Colormap 1.0\nDataField \"T\"\nSIMPLE_EMITTER @1\n@1\n0 0.2 1 1\n1 0.5 0 2.9\n",
    alphamap="# VoRANG Alphamap 1.0\nDataField \"T\"\nSIMPLE_ABSORBER @1\n@1\n0 1\n0.8 2.9\n",
    method="exact linear 0 1",
    rotate=[(1, 1, 0, 30)],
)


def cli_steps(tmp_path, path, steps):
    """The CLI's images of the given steps: the same scene set once, `timestep K` each."""
    (tmp_path / "c.map").write_text(SCENE["colormap"])
    (tmp_path / "a.map").write_text(SCENE["alphamap"])
    lines = [
        f"volume {{{path}}}",
        "imagesize 48 40",
        f"output {{{tmp_path / 'cli.pfm'}}}",
        f"colormap {{{tmp_path / 'c.map'}}}",
        f"alphamap {{{tmp_path / 'a.map'}}}",
        "method exact linear 0 1",
        "vol_rotate 1 1 0 30",
        "linedraw off",
        "view_all",
    ]
    for k in steps:
        lines += [f"timestep {k}", "render_btf"]
    script = tmp_path / "steps.tcl"
    script.write_text("\n".join(lines) + "\n")
    import subprocess

    subprocess.run([cli(), str(script)], check=True, capture_output=True)
    return [read_pfm(tmp_path / f"cli.{n + 1:04d}.pfm") for n in range(len(steps))]


def test_series_reads_times_and_steps_lazily():
    s = vorang.Series.read(str(SERIES / "flow.pvd"))
    assert s.times == [0.0, 0.5, 1.25]
    assert len(s) == 3
    assert "3 time steps" in repr(s)
    v = s[1]
    assert isinstance(v, vorang.Volume)
    assert v.n_tets == 162 and v.field_names == ["T", "velocity", "material"]
    assert s[-1].field_range("T") == vorang.Volume.read(str(SERIES / "flow_2.vtu")).field_range("T")
    assert s.nearest(0.25) == 0 and s.nearest(0.3) == 1 and s.nearest(99) == 2
    with pytest.raises(IndexError, match=r"step 3 is out of range: .*flow.pvd has 3 time steps \(0 … 2\)"):
        s[3]
    for name in ("flow.vtu.series", "flow_p.pvd", "flow_m.vtm.series"):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            other = vorang.Series.read(str(SERIES / name))
            assert other.times == s.times
            assert other[2].field_range("T") == s[2].field_range("T")
    one = vorang.Series.read(str(SERIES / "flow_p_0.pvtu"))
    assert one.times == [0.0] and one[0].n_points == 64


def test_files_with_their_own_steps_are_series(tmp_path):
    """Exodus II, XDMF and VTKHDF files (tests/data/multistep) read as a Series: their
    times, their steps as Volumes, and a step renders what the CLI renders."""
    multi = ROOT / "tests" / "data" / "multistep"
    for name in ("flow.exo", "flow_classic.e", "dolfinx.xdmf", "flow.vtkhdf"):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # Exodus: the shell block is skipped
            s = vorang.Series.read(str(multi / name))
            assert s.times == [0.0, 0.5, 1.25], name
            assert s[2].n_tets == 162 and s[2].field_names[0] == "T", name
            ref = cli_steps(tmp_path, multi / name, [2])[0]
            assert np.array_equal(vorang.render(s, step=2, **SCENE)[:, :, :3], ref), name


def test_volume_read_takes_exodus_xdmf_and_vtkhdf():
    """Volume.read of an Exodus II (netCDF-4, CDF-1, higher-order blocks), XDMF or VTKHDF
    file is its step 0: the volume of the same data read from its reference .vtu
    (tests/data/multistep/generate.py, generate_higher.py), image included; Series.read
    gives every step of the higher-order file."""
    multi = ROOT / "tests" / "data" / "multistep"
    pairs = [
        ("flow.exo", "exo_ref_0.vtu"),
        ("flow_cdf1.e", "exo_ref_0.vtu"),
        ("higher.e", "higher_ref_0.vtu"),
        ("dolfinx.xdmf", "dolfinx_ref_0.vtu"),
        ("higher.xdmf", "higher_xdmf_ref.vtu"),
        ("flow.vtkhdf", "ref_0.vtu"),
    ]
    scene = dict(SCENE, method="interpolateCoeff linear 1")
    for name, ref in pairs:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # skipped shells, re-oriented wedges
            v = vorang.Volume.read(str(multi / name))
            r = vorang.Volume.read(str(multi / ref))
        assert (v.n_points, v.n_tets) == (r.n_points, r.n_tets), name
        assert v.field_names == r.field_names, name
        for f in r.field_names:
            try:
                expected = r.field_range(f)
            except ValueError:  # a vector field has no single range
                continue
            assert v.field_range(f) == expected, (name, f)
        assert np.array_equal(vorang.render(v, **scene), vorang.render(r, **scene)), name
    # The warnings of a step come through Python's (the wedge's re-oriented tetrahedra).
    with pytest.warns(UserWarning, match="re-oriented"):
        s = vorang.Series.read(str(multi / "higher.e"))
        s[0]
    assert s.times == [0.0, 1.0]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        r = vorang.Volume.read(str(multi / "higher_ref_1.vtu"))
    assert np.array_equal(vorang.render(s, step=1, **scene), vorang.render(r, **scene))


def test_range_spans_all_steps():
    s = vorang.Series.read(str(SERIES / "flow.pvd"))
    lo = min(s[k].field_range("T")[0] for k in range(3))
    hi = max(s[k].field_range("T")[1] for k in range(3))
    assert s.range("T") == (lo, hi)
    assert s.range(0) == (lo, hi)
    assert s.range("material") == (0.0, 1.0)
    with pytest.raises(ValueError, match="3 components"):
        s.range("velocity")
    with pytest.raises(ValueError, match='no field named "nope"'):
        s.range("nope")


def test_render_a_step_equals_the_cli(tmp_path):
    s = vorang.Series.read(str(SERIES / "flow.pvd"))
    ref = cli_steps(tmp_path, SERIES / "flow.pvd", [0, 2, 1])
    for img, k in zip(ref, [0, 2, 1]):
        by_step = vorang.render(s, step=k, **SCENE)
        assert np.array_equal(by_step[:, :, :3], img), f"step {k}"
        by_time = vorang.render(s, time=s.times[k] + 0.01, **SCENE)
        assert np.array_equal(by_time, by_step)
    # The single file of a step renders the same.
    single = vorang.render(vorang.Volume.read(str(SERIES / "flow_2.vtu")), **SCENE)
    assert np.array_equal(single, vorang.render(s, step=-1, **SCENE))
    with pytest.raises(ValueError, match="step and time choose a step of a vorang.Series"):
        vorang.render(s[0], step=1)
    with pytest.raises(ValueError, match="not both"):
        vorang.render(s, step=1, time=0.5)


def test_the_label_and_preset_range(tmp_path):
    s = vorang.Series.read(str(SERIES / "flow.pvd"))
    plain = vorang.render(s, step=1, size=(64, 48))
    labelled = vorang.render(s, step=1, size=(64, 48), label="t = %.3g s")
    changed = np.argwhere((plain != labelled).any(axis=2))
    assert len(changed) and changed[:, 0].max() < 16, "the label is in the top rows"
    with pytest.raises(ValueError, match="unknown conversion '%s'"):
        vorang.render(s, label="%s")
    # Without maps the preset spans the range over all steps: step 0 rendered from the series
    # differs from step 0 rendered alone (whose range is its own).
    alone = vorang.render(s[0], size=(64, 48))
    assert not np.array_equal(vorang.render(s, step=0, size=(64, 48)), alone)


def test_animate(tmp_path):
    s = vorang.Series.read(str(SERIES / "moving.pvd"))
    done = []
    out = vorang.animate(
        s,
        tmp_path / "flow.apng",
        fps=5,
        label="t = %.2f",
        progress=lambda d, t: done.append((d, t)),
        size=(40, 32),
    )
    assert out.endswith("flow.apng")
    data = (tmp_path / "flow.apng").read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n" and b"acTL" in data
    # acTL: the number of frames, big-endian, right after the chunk type.
    at = data.index(b"acTL") + 4
    assert int.from_bytes(data[at : at + 4], "big") == 3
    assert done == [(1, 3), (2, 3), (3, 3)]
    with pytest.raises(TypeError, match="animate renders every step"):
        vorang.animate(s, tmp_path / "x.gif", step=1)
    with pytest.raises(ValueError, match="unknown movie format"):
        vorang.animate(s, tmp_path / "x.avi")
