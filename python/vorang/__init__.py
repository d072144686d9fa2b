"""VoRANG: direct volume rendering of tetrahedral meshes, from Python.

    import numpy as np, vorang
    vol = vorang.Volume.read("inclusion.vtu")
    img = vorang.render(vol, size=(320, 200), colormap="temperature.cmap",
                        ortho=(-1.3, 1.3, -0.8125, 0.8125, -10, 10))
    vorang.save(img, "inclusion.png")

`render` returns a float32 array of shape (h, w, 4), first row at the top; its RGB values are
exactly those the PFM output of the equivalent script holds.

A time series (ParaView's .pvd, .series, an Exodus II, XDMF or VTKHDF file, or a .pvtu / .vtm)
is a `Series`; `animate` renders every step into a movie with one scene:

    flow = vorang.Series.read("flow.pvd")
    vorang.animate(flow, "flow.gif", label="t = %.3g s", rotate=[(0, 1, 0, 30)])
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path
from typing import Sequence

from . import _vorang
from ._image import Image
from ._vorang import Series, Volume, save

__all__ = [
    "Volume",
    "Series",
    "animate",
    "Image",
    "render",
    "plot",
    "show",
    "save",
    "run_script",
    "Colormap",
    "Alphamap",
]


def render(
    volume,
    *,
    size=(512, 512),
    colormap=None,
    alphamap=None,
    method="exact linear 0",
    persp=None,
    ortho=None,
    look_at=None,
    rotate=(),
    scale=None,
    translate=None,
    background="white",
    linedraw="off",
    lights=(),
    view_all=True,
    zoom=1.0,
    legend=None,
    brightness=None,
    label=None,
    step=None,
    time=None,
    progress=None,
    backend="cpu",
) -> Image:
    """Renders `volume` (a `Volume`, or a `Series` at `step` or `time`) back to front; returns a `vorang.Image`: a float32 numpy array of shape
    (h, w, 4) that shows itself in notebooks.

    The first row is the top of the image. RGB is exactly what the PFM output of the equivalent
    script holds; the fourth channel is alpha (the volume's opacity 1 - T).

    The defaults give a good first picture: without maps, the first picture `vorang info`
    suggests (the viridis preset and an absorption ramp over the first scalar field's range,
    χ rising to 4 / the bounding box's diagonal), the exact method, no grid lines, and the
    volume framed undistorted.

    size: (w, h) (`imagesize`, default 512 x 512). colormap / alphamap: a map-file path, map
    text (starting with "# VoRANG"), a `Colormap` / `Alphamap`, or for colormap a preset name
    ("viridis", "magma", "inferno", "plasma", "cividis", "coolwarm", "grey": that table over
    the first field's range, with the absorption ramp unless an alphamap is given); both None:
    the viridis preset and the ramp. method: the script's method string, e.g. "exact linear 0
    1.0"; its last parameter may be left out ("exact linear 0"): the brightness is then the
    ramp's χ_max with the preset maps (opaque parts show the table's colours), else 1.
    persp=(fovy, aspect, near, far) (`persp_camera`), ortho=(l, r, b, t, front, back)
    (`ortho_camera`), look_at=(eye, ref, up) (`look_at`). view_all (default True): without
    persp or ortho, frame the transformed volume with the image's aspect ratio (`view_all`);
    False: the script's default camera (the grid's x/y extent stretched to the image). The
    volume transforms are applied like the script commands in this order: `vol_scale scale`,
    `vol_rotate x y z degrees` for each of `rotate` in order, `vol_translate translate`.
    background: "white" (= "clear"), "none" (no background light, transparent), an (r, g, b)
    tuple or an image path (`background`). linedraw: "off" (default), "on" (all grid lines,
    the script's default), or "field {values}". zoom: > 1 moves closer (the camera's window or
    field of view shrinks by the factor about the image centre). legend: None, or where the
    colour legend goes ("right", "left", "top", "bottom"; `legend on`). brightness: the
    brightness when the method string leaves it out (default: the preset's χ_max with the
    preset maps, else 1).
    lights: (r, g, b, dx, dy, dz) tuples, each an `addlight` (a light of that colour at infinity
    in direction (dx, dy, dz), world coordinates); they shade `LIT_EMITTER` colormaps. None
    given: one white light at the camera.

    A `Series`: `step` picks a step by number (negative from the end), `time` the step nearest
    that time (the earlier on a tie); default step 0. Without maps, the preset spans the field's
    range over all steps, so that a colour means the same value in every step. label: the
    step's time printed into the image, a printf format ("t = %.3g s"; %d: the step number;
    `label` in scripts).

    backend: "cpu" (default) or "gpu" (`backend gpu`: the exact method on a Vulkan adapter with
    64-bit floats, in a module built with the `gpu` feature; a ValueError names what is
    missing, the CPU is never used instead).

    progress: called as progress(done, total) as screen tiles finish, or a tqdm-like object
    (with `update`): its `total` is set and update(1) called per tile.

    Raises ValueError (bad arguments, maps that do not fit the volume) or OSError (files),
    with the CLI's messages. The GIL is released while rendering; an exception raised by
    `progress` (e.g. KeyboardInterrupt) stops the render at the next tile and is raised here.
    Ctrl-C is checked while rendering, but at present only takes effect when the render ends.
    """
    image = _vorang.render(
        volume,
        **_scene(
            size=size,
            colormap=colormap,
            alphamap=alphamap,
            method=method,
            persp=persp,
            ortho=ortho,
            look_at=look_at,
            rotate=rotate,
            scale=scale,
            translate=translate,
            background=background,
            linedraw=linedraw,
            lights=lights,
            view_all=view_all,
            zoom=zoom,
            legend=legend,
            brightness=brightness,
            label=label,
        ),
        step=None if step is None else int(step),
        time=None if time is None else float(time),
        progress=progress,
        backend=backend,
    )
    transparent = isinstance(background, str) and background in ("none", "transparent")
    return Image(image, transparent=transparent)


def _scene(**kw):
    """render's scene keywords in the types the extension takes (tuples, floats)."""
    tuples = {
        "size": tuple,
        "persp": tuple,
        "ortho": tuple,
        "scale": tuple,
        "translate": tuple,
        "look_at": lambda v: tuple(tuple(x) for x in v),
        "rotate": lambda v: [tuple(r) for r in v],
        "lights": lambda v: [tuple(l) for l in v],
        "view_all": bool,
        "zoom": float,
        "brightness": float,
    }
    return {k: (v if v is None or k not in tuples else tuples[k](v)) for k, v in kw.items()}


def animate(series, path, *, fps=10, label=None, progress=None, **render_kwargs) -> str:
    """Renders every step of a `Series` into the movie `path` and returns its path.

    The format follows the extension: .gif (256 colours a frame), .apng or .png (animated PNG),
    and .mp4, .webm, .mkv, .mov through the ffmpeg program (on the PATH). fps: frames per
    second. label: each step's time printed into its frame, a printf format ("t = %.3g s";
    %d: the step number). progress: called as progress(done, total) after each frame, or a
    tqdm-like object (update(1) per frame).

    Every other keyword is `render`'s (size, colormap, alphamap, method, camera, rotate, …):
    one scene for all frames, as a script's loop over `timestep` keeps it — the camera frames
    step 0, and without maps the preset spans each field's range over all steps, so that
    colours mean the same value in every frame. A step with the same points and cells as the
    one before shares its mesh (only its fields are loaded).

        flow = vorang.Series.read("flow.pvd")
        vorang.animate(flow, "flow.gif", label="t = %.3g s", size=(400, 300))
    """
    for key in ("step", "time"):
        if key in render_kwargs:
            raise TypeError(f"animate renders every step; {key}= is render's keyword")
    return _vorang.animate(
        series,
        os.fspath(path),
        fps=float(fps),
        label=label,
        progress=progress,
        **_scene(**render_kwargs),
    )


# meshio cell type names → VTK cell types (the readers' numbering). meshio names VTK's
# Lagrange cells by their VTK names; "polyhedronN" (N points) are polyhedra.
_MESHIO_TYPES = {
    "vertex": 1,
    "line": 3,
    "triangle": 5,
    "quad": 9,
    "tetra": 10,
    "hexahedron": 12,
    "wedge": 13,
    "pyramid": 14,
    "tetra10": 24,
    "VTK_LAGRANGE_TETRAHEDRON": 71,
    "VTK_LAGRANGE_HEXAHEDRON": 72,
    "VTK_LAGRANGE_WEDGE": 73,
    "VTK_LAGRANGE_PYRAMID": 74,
}


def _face_stream(faces):
    """VTK's face stream of one polyhedron given as a list of faces (lists of point ids)."""
    stream = [len(faces)]
    for face in faces:
        face = [int(i) for i in face]
        stream += [len(face)] + face
    return stream


def _from_meshio(mesh) -> Volume:
    """A Volume from a meshio.Mesh (duck-typed: points, cells with .type/.data,
    point_data, cell_data). Hexahedra, wedges, pyramids, Lagrange cells and polyhedra are
    split into tetrahedra as the file readers split them; other cells are skipped with a
    warning."""
    import numpy as np

    blocks = []
    for block in mesh.cells:
        if block.type.startswith("polyhedron"):
            # One polyhedron per block row: its faces as point lists.
            for faces in block.data:
                blocks.append((42, np.array([_face_stream(faces)])))
            continue
        ty = _MESHIO_TYPES.get(block.type)
        if ty is None:
            raise ValueError(f"from_meshio: cell type {block.type!r} is not supported")
        blocks.append((ty, np.asarray(block.data)))
    cell_data = {}
    for name, per_block in dict(mesh.cell_data).items():
        cell_data[name] = np.concatenate([np.asarray(a) for a in per_block])
    return Volume._from_blocks(
        np.asarray(mesh.points), blocks, dict(mesh.point_data), cell_data
    )


# Nodes per cell of the VTK cell types with a fixed node count (the [n, ids…] cell layout can
# then be cut without a Python loop).
_FIXED_NODES = {1: 1, 3: 2, 5: 3, 9: 4, 10: 4, 11: 8, 12: 8, 13: 6, 14: 5, 24: 10}
# VTK_VOXEL's node order (x fastest, then y, then z) as a hexahedron's (counter-clockwise).
_VOXEL_AS_HEX = [0, 1, 3, 2, 4, 5, 7, 6]


def _structured_cells(dims):
    """Hexahedra of an nx × ny × nz point lattice (ImageData, RectilinearGrid, StructuredGrid:
    points x fastest), in VTK's cell order, as a (cells, 8) index array."""
    import numpy as np

    nx, ny, nz = (int(d) for d in dims)
    if min(nx, ny, nz) < 2:
        raise ValueError(
            f"from_pyvista: a structured grid of {nx} × {ny} × {nz} points has no volume cells "
            "(each dimension needs at least 2 points)"
        )
    i, j, k = np.meshgrid(
        np.arange(nx - 1), np.arange(ny - 1), np.arange(nz - 1), indexing="ij"
    )
    base = (i + nx * (j + ny * k)).transpose(2, 1, 0).reshape(-1)
    dx, dy, dz = 1, nx, nx * ny
    corners = np.array([0, dx, dx + dy, dy, dz, dx + dz, dx + dy + dz, dy + dz], dtype=np.int64)
    return base[:, None].astype(np.int64) + corners[None, :]


def _polyhedron_streams(grid):
    """The face stream of every polyhedron (VTK 42) of a PyVista grid, by cell index:
    from `polyhedron_faces` / `polyhedron_face_locations` (PyVista 0.45 and later, VTK 9.4),
    else from `faces` / `face_locations` (earlier ones)."""
    import numpy as np

    def legacy_list(array):
        """[n, a, b, …, n, …] → list of lists."""
        out, pos, array = [], 0, [int(v) for v in np.asarray(array).ravel()]
        while pos < len(array):
            n = array[pos]
            out.append(array[pos + 1 : pos + 1 + n])
            pos += 1 + n
        return out

    if hasattr(grid, "polyhedron_faces") and hasattr(grid, "polyhedron_face_locations"):
        faces = legacy_list(grid.polyhedron_faces)
        per_cell = legacy_list(grid.polyhedron_face_locations)
        return {
            i: _face_stream([faces[f] for f in ids])
            for i, ids in enumerate(per_cell)
            if ids
        }
    if hasattr(grid, "faces") and hasattr(grid, "face_locations"):
        stream = [int(v) for v in np.asarray(grid.faces).ravel()]
        streams = {}
        for i, start in enumerate(np.asarray(grid.face_locations).ravel().tolist()):
            if start < 0:
                continue
            pos, n = start + 1, stream[start]
            for _ in range(n):
                pos += 1 + stream[pos]
            streams[i] = stream[start:pos]
        return streams
    raise ValueError(
        "from_pyvista: the grid has polyhedra (VTK type 42) but offers no face stream "
        "(neither polyhedron_faces and polyhedron_face_locations nor faces and "
        "face_locations)"
    )


def _unstructured_blocks(grid):
    """(blocks, order) of an UnstructuredGrid: one (VTK type, (k, n) connectivity) block per
    cell type and size (Lagrange cells of one type may differ in degree), one block per
    polyhedron (its face stream, see `_polyhedron_streams`), and the permutation of the cells
    that groups them so (for the cell data)."""
    import numpy as np

    types = np.asarray(grid.celltypes).astype(np.int64)
    kinds = np.unique(types)
    if len(kinds) == 1 and int(kinds[0]) in _FIXED_NODES:
        # One cell type (the common case): the connectivity is a plain (cells, n) array.
        ty, n = int(kinds[0]), _FIXED_NODES[int(kinds[0])]
        if hasattr(grid, "cell_connectivity"):
            block = np.asarray(grid.cell_connectivity).reshape(-1, n)
        else:
            rows = np.asarray(grid.cells).reshape(-1, n + 1)
            if not (rows[:, 0] == n).all():
                raise ValueError(
                    f"from_pyvista: cells of VTK type {ty} must have {n} points each"
                )
            block = rows[:, 1:]
        if ty == 11:  # VTK_VOXEL → hexahedron
            block, ty = block[:, _VOXEL_AS_HEX], 12
        return [(ty, block)], np.arange(len(types))
    if hasattr(grid, "offset") and hasattr(grid, "cell_connectivity"):
        offsets = np.asarray(grid.offset).astype(np.int64)
        conn = np.asarray(grid.cell_connectivity).astype(np.int64)
        starts, counts = offsets[:-1], np.diff(offsets)
    else:
        cells = np.asarray(grid.cells).astype(np.int64)
        lut = np.full(256, -1, dtype=np.int64)
        for t, n in _FIXED_NODES.items():
            lut[t] = n
        counts = lut[types]
        if (counts < 0).any():
            # Cells of variable size (Lagrange cells, polyhedra): the list says each size.
            counts = np.empty(len(types), dtype=np.int64)
            pos = 0
            for c in range(len(types)):
                counts[c] = cells[pos]
                pos += 1 + int(cells[pos])
        starts = np.concatenate([[0], np.cumsum(counts + 1)[:-1]]) + 1
        conn = cells
    streams = _polyhedron_streams(grid) if (types == 42).any() else {}
    order = np.lexsort((counts, types))
    change = (np.diff(types[order]) != 0) | (np.diff(counts[order]) != 0)
    blocks = []
    for pick in np.split(order, np.flatnonzero(change) + 1):
        if len(pick) == 0:
            continue
        ty, n = int(types[pick[0]]), int(counts[pick[0]])
        if ty == 42:
            for c in pick.tolist():
                if c not in streams:
                    raise ValueError(
                        f"from_pyvista: cell {c} is a polyhedron, but the grid gives no faces for it"
                    )
                blocks.append((42, np.array([streams[c]], dtype=np.int64)))
            continue
        block = conn[starts[pick][:, None] + np.arange(n)[None, :]]
        if ty == 11:  # VTK_VOXEL → hexahedron
            block, ty = block[:, _VOXEL_AS_HEX], 12
        blocks.append((ty, block))
    return blocks, order


def _from_pyvista(grid) -> Volume:
    """A Volume from a PyVista grid (duck-typed, vectorised with numpy):
    UnstructuredGrid (points, celltypes, cells / offset + cell_connectivity; hexahedra, voxels,
    wedges, pyramids, quadratic tetrahedra and Lagrange cells — as
    `pyvista.UnstructuredGrid(*dolfinx.plot.vtk_mesh(V))` holds them — split as the readers
    split them, polyhedra through the grid's face stream), and ImageData, RectilinearGrid and
    StructuredGrid (their hexahedra). Point and cell data keep their names; cell data stays
    cell data."""
    import numpy as np

    points = np.asarray(grid.points)
    point_data = {k: np.asarray(grid.point_data[k]) for k in grid.point_data.keys()}
    cell_data = {k: np.asarray(grid.cell_data[k]) for k in grid.cell_data.keys()}
    if hasattr(grid, "celltypes"):
        blocks, order = _unstructured_blocks(grid)
        cell_data = {k: v[order] for k, v in cell_data.items()}
    elif hasattr(grid, "dimensions"):
        blocks = [(12, _structured_cells(grid.dimensions))]
    else:
        raise ValueError(
            f"from_pyvista: expected a PyVista UnstructuredGrid, ImageData, RectilinearGrid or "
            f"StructuredGrid, found {type(grid).__name__}"
        )
    return Volume._from_blocks(points, blocks, point_data, cell_data)


def _rows(values, columns, what):
    import numpy as np

    v = np.asarray(values, dtype=float).reshape(-1)
    c = np.asarray(columns, dtype=float)
    if c.ndim == 1:
        c = c.reshape(-1, 1)
    if c.shape[0] != v.shape[0]:
        raise ValueError(
            f"{what}: {v.shape[0]} values but {c.shape[0]} rows; give one row per value"
        )
    if v.shape[0] < 1:
        raise ValueError(f"{what}: at least one value is needed")
    return v, c


def _field_line(field):
    if field is None:
        return ""
    if isinstance(field, str):
        return f'DataField "{field}"\n'
    return f"DataField {int(field)}\n"


class Colormap:
    """A colormap (data → emission η) as map-file text ("# VoRANG Colormap 1.0").

    Pass it as `colormap=` to `render`; `str(cmap)` / `cmap.text` is the map file.
    """

    def __init__(self, text: str):
        self.text = text

    def __str__(self) -> str:
        return self.text

    def __repr__(self) -> str:
        return f"vorang.Colormap({self.text!r})"

    def save(self, path) -> None:
        """Writes the map file."""
        with open(path, "w", encoding="utf-8") as f:
            f.write(self.text)

    @classmethod
    def table(cls, values: Sequence[float], rgb, field=None, weighted=False) -> "Colormap":
        """SIMPLE_EMITTER: emission rgb[i] at data value values[i] (strictly increasing),
        linear in between, clamped outside. `field`: a field number or name (default: the
        map's default DataField 0). weighted=True: ABSORPTION_WEIGHTED, the colour times the
        alphamap's χ at the same point, so that a part shows its table colour once opaque
        and fades with its opacity (the emission–absorption model of most volume renderers)."""
        v, c = _rows(values, rgb, "Colormap.table")
        if c.shape[1] != 3:
            raise ValueError(f"Colormap.table: rgb needs 3 columns, found {c.shape[1]}")
        rows = "".join(f"{r!r} {g!r} {b!r} {x!r}\n" for (r, g, b), x in zip(c.tolist(), v.tolist()))
        method = "ABSORPTION_WEIGHTED" if weighted else "SIMPLE_EMITTER"
        return cls(f"# VoRANG Colormap 1.0\n{_field_line(field)}{method} @1\n@1\n{rows}")

    @classmethod
    def constant(cls, rgb, field=None) -> "Colormap":
        """CONSTANT emission (r, g, b) everywhere."""
        r, g, b = (float(x) for x in rgb)
        return cls(f"# VoRANG Colormap 1.0\n{_field_line(field)}CONSTANT @1\n@1\n{r!r} {g!r} {b!r}\n")

    @classmethod
    def preset(cls, name: str, lo: float, hi: float, field=None, brightness: float = 1.0) -> "Colormap":
        """A matplotlib-style colormap (viridis, magma, plasma, inferno, coolwarm, grey/gray,
        hot) spread over [lo, hi] as a SIMPLE_EMITTER table of a few knots."""
        key = name.lower()
        if key.endswith("_r"):
            knots = list(reversed(_PRESETS.get(key[:-2], [])))
        else:
            knots = _PRESETS.get(key)
        if not knots:
            raise ValueError(
                f"Colormap.preset: unknown name {name!r}; known: {', '.join(sorted(_PRESETS))}"
            )
        if not hi > lo:
            raise ValueError(f"Colormap.preset: need lo < hi, found {lo} and {hi}")
        n = len(knots)
        values = [lo + (hi - lo) * i / (n - 1) for i in range(n)]
        rgb = [[brightness * c for c in k] for k in knots]
        return cls.table(values, rgb, field=field)


class Alphamap:
    """An alphamap (data → absorption χ) as map-file text ("# VoRANG Alphamap 1.0")."""

    def __init__(self, text: str):
        self.text = text

    def __str__(self) -> str:
        return self.text

    def __repr__(self) -> str:
        return f"vorang.Alphamap({self.text!r})"

    def save(self, path) -> None:
        """Writes the map file."""
        with open(path, "w", encoding="utf-8") as f:
            f.write(self.text)

    @classmethod
    def table(cls, values: Sequence[float], chi, field=None) -> "Alphamap":
        """SIMPLE_ABSORBER: absorption chi[i] at data value values[i] (strictly increasing),
        linear in between, clamped outside."""
        v, c = _rows(values, chi, "Alphamap.table")
        if c.shape[1] != 1:
            raise ValueError(f"Alphamap.table: chi needs one value per row, found {c.shape[1]}")
        rows = "".join(f"{a!r} {x!r}\n" for a, x in zip(c[:, 0].tolist(), v.tolist()))
        return cls(f"# VoRANG Alphamap 1.0\n{_field_line(field)}SIMPLE_ABSORBER @1\n@1\n{rows}")

    @classmethod
    def constant(cls, chi: float) -> "Alphamap":
        """CONSTANT absorption χ everywhere."""
        return cls(f"# VoRANG Alphamap 1.0\nCONSTANT @1\n@1\n{float(chi)!r}\n")


# A few knots of matplotlib's colormaps (sampled at equal steps).
_PRESETS = {
    "viridis": [
        (0.267004, 0.004874, 0.329415),
        (0.282623, 0.140926, 0.457517),
        (0.253935, 0.265254, 0.529983),
        (0.206756, 0.371758, 0.553117),
        (0.163625, 0.471133, 0.558148),
        (0.127568, 0.566949, 0.550556),
        (0.134692, 0.658636, 0.517649),
        (0.266941, 0.748751, 0.440573),
        (0.477504, 0.821444, 0.318195),
        (0.741388, 0.873449, 0.149561),
        (0.993248, 0.906157, 0.143936),
    ],
    "magma": [
        (0.001462, 0.000466, 0.013866),
        (0.078815, 0.054184, 0.211667),
        (0.232077, 0.059889, 0.437695),
        (0.390384, 0.100379, 0.501864),
        (0.550287, 0.161158, 0.505719),
        (0.716387, 0.214982, 0.47529),
        (0.868793, 0.287728, 0.409303),
        (0.967671, 0.439703, 0.35981),
        (0.994738, 0.62435, 0.427397),
        (0.99568, 0.812706, 0.572645),
        (0.987053, 0.991438, 0.749504),
    ],
    "inferno": [
        (0.001462, 0.000466, 0.013866),
        (0.087411, 0.044556, 0.224813),
        (0.258234, 0.038571, 0.406485),
        (0.416331, 0.090203, 0.432943),
        (0.578304, 0.148039, 0.404411),
        (0.735683, 0.215906, 0.330245),
        (0.865006, 0.316822, 0.226055),
        (0.954506, 0.468744, 0.099874),
        (0.987622, 0.64532, 0.039886),
        (0.964394, 0.843848, 0.273391),
        (0.988362, 0.998364, 0.644924),
    ],
    "plasma": [
        (0.050383, 0.029803, 0.527975),
        (0.254627, 0.013882, 0.615419),
        (0.417642, 0.000564, 0.65839),
        (0.562738, 0.051545, 0.641509),
        (0.69284, 0.165141, 0.564522),
        (0.798216, 0.280197, 0.469538),
        (0.881443, 0.392529, 0.383229),
        (0.949217, 0.517763, 0.295662),
        (0.98826, 0.652325, 0.211364),
        (0.988648, 0.809579, 0.145357),
        (0.940015, 0.975158, 0.131326),
    ],
    "coolwarm": [
        (0.229806, 0.298718, 0.753683),
        (0.354901, 0.473246, 0.881098),
        (0.486282, 0.630739, 0.956852),
        (0.62202, 0.750657, 0.999269),
        (0.752746, 0.821898, 0.977733),
        (0.865395, 0.86541, 0.86539),
        (0.956834, 0.798069, 0.719216),
        (0.968203, 0.682739, 0.576094),
        (0.937077, 0.532315, 0.42068),
        (0.851695, 0.373814, 0.287004),
        (0.705673, 0.015556, 0.150233),
    ],
    "grey": [(0.0, 0.0, 0.0), (1.0, 1.0, 1.0)],
    "gray": [(0.0, 0.0, 0.0), (1.0, 1.0, 1.0)],
    "hot": [
        (0.0416, 0.0, 0.0),
        (1.0, 0.0, 0.0),
        (1.0, 1.0, 0.0),
        (1.0, 1.0, 1.0),
    ],
}


from ._plot import plot, show  # noqa: E402  (they use render, defined above)


def _vorang_program():
    """The `vorang` program run_script runs: $VORANG_BIN, else `vorang` on the PATH."""
    program = os.environ.get("VORANG_BIN") or shutil.which("vorang")
    if not program:
        raise RuntimeError(
            "run_script runs scripts with the vorang program, which was not found: install it "
            "(cargo install --path . in the VoRANG repository) or set VORANG_BIN to its path; "
            "everything else in this package works without it"
        )
    return program


def run_script(path_or_text):
    """Runs a VoRANG (Tcl) script file, or script text, as `vorang script.tcl` / `vorang -e` do;
    messages go to stdout/stderr.

    Raises OSError for a missing script file and RuntimeError ("file:line: message") when the
    script fails. The script language is real Tcl: the package itself does not link libtcl, so
    scripts run in the `vorang` program ($VORANG_BIN or `vorang` on the PATH), unless the
    extension was built with the `script` feature, which runs them in-process.
    """
    if hasattr(_vorang, "run_script"):
        return _vorang.run_script(path_or_text)
    if isinstance(path_or_text, os.PathLike) or (
        isinstance(path_or_text, str) and "\n" not in path_or_text
        and (Path(path_or_text).is_file() or path_or_text.rstrip().endswith(".tcl"))
    ):
        path = Path(path_or_text)
        if not path.is_file():
            raise OSError(f"{path}: no such script file")
        args = [_vorang_program(), str(path)]
    else:
        args = [_vorang_program(), "-e", str(path_or_text)]
    done = subprocess.run(args, capture_output=True, text=True)
    if done.stdout:
        sys.stdout.write(done.stdout)
    if done.stderr:
        sys.stderr.write(done.stderr)
    if done.returncode != 0:
        lines = [l for l in done.stderr.splitlines() if l.strip()]
        raise RuntimeError(lines[0] if lines else f"vorang exited with status {done.returncode}")
