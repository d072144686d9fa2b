"""Python shows the CLI's warnings for the same scene: both front ends call the same session,
which returns its warnings as values; the CLI prints them, Python raises them through the
`warnings` module. The texts agree after the command name ("render_btf: …" / "render: …")."""

import pathlib
import subprocess
import warnings

import numpy as np
import pytest

import vorang
from test_vorang import ROOT, cli

DATA = ROOT / "tests" / "data" / "two_tets_data.hmesh"

# Two tetrahedra that interpenetrate (no shared face): every ray through both meets cells that
# overlap, which the renderer reports.
OVERLAP_VTK = """# vtk DataFile Version 3.0
two overlapping tetrahedra
ASCII
DATASET UNSTRUCTURED_GRID
POINTS 8 double
0 0 0
1 0 0
0 1 0
0 0 1
0.2 0.2 0.2
1.2 0.2 0.2
0.2 1.2 0.2
0.2 0.2 1.2
CELLS 2 10
4 0 1 2 3
4 4 5 6 7
CELL_TYPES 2
10
10
POINT_DATA 8
SCALARS t double 1
LOOKUP_TABLE default
0 1 2 3 0 1 2 3
"""


def without_command(text):
    """ "render_btf: IDENTITY clamped …" → "IDENTITY clamped …"."""
    head, sep, rest = text.partition(": ")
    return rest if sep and " " not in head else text


def cli_warnings(tmp_path, volume, commands):
    script = tmp_path / "scene.tcl"
    script.write_text(
        f"volume {{{volume}}}\noutput {{{tmp_path / 'out.pfm'}}}\n" + "\n".join(commands) + "\nrender_btf\n"
    )
    done = subprocess.run([cli(), str(script)], capture_output=True, text=True, check=True)
    return [without_command(l) for l in done.stderr.splitlines() if l.strip()]


def python_warnings(volume, **kwargs):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        vol = vorang.Volume.read(str(volume))
        caught.clear()  # the reader's own warnings are not the render's
        vorang.render(vol, view_all=False, **kwargs)
    return [without_command(str(w.message)) for w in caught]


def test_identity_clamp_warning_is_the_clis(tmp_path):
    cmap = tmp_path / "identity.cmap"
    # Field 4 ("E", an edge-element field) has negative components: IDENTITY clamps them.
    cmap.write_text("# VoRANG Colormap 1.0\nDataField 4\nIDENTITY\n")
    expected = cli_warnings(
        tmp_path,
        DATA,
        ["imagesize 16 16", f"colormap {{{cmap}}}", "linedraw off", "method exact linear 0 1"],
    )
    got = python_warnings(
        DATA, size=(16, 16), colormap=str(cmap), linedraw="off", method="exact linear 0 1"
    )
    assert any("IDENTITY clamped" in w for w in expected), expected
    assert got == expected


def test_overlap_warning_is_the_clis(tmp_path):
    mesh = tmp_path / "overlap.vtk"
    mesh.write_text(OVERLAP_VTK)
    expected = cli_warnings(tmp_path, mesh, ["imagesize 24 24", "linedraw off", "method exact linear 0 1"])
    got = python_warnings(mesh, size=(24, 24), linedraw="off", method="exact linear 0 1")
    assert any("overlap" in w for w in expected), expected
    assert got == expected


def test_the_extension_does_not_link_tcl():
    """The package needs no Tcl: its extension module links no libtcl (Linux: ldd)."""
    ext = pathlib.Path(vorang._vorang.__file__)
    try:
        done = subprocess.run(["ldd", str(ext)], capture_output=True, text=True)
    except FileNotFoundError:
        pytest.skip("no ldd on this system")
    assert "libtcl" not in done.stdout, done.stdout
