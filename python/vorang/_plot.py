"""`vorang.plot` and `vorang.show`: one line from data to a picture, with the transfer function
in the terms PyVista and matplotlib users know (cmap, clim, opacity)."""

from __future__ import annotations

import os
import threading

import numpy as np

from ._image import Image
from ._vorang import Volume

# PyVista's opacity presets over [0, 1] of the colour range (its `opacity=` names): the fraction
# of light absorbed per unit distance at each of `_N` evenly spaced field values.
_N = 33


def _opacity_preset(name: str) -> np.ndarray:
    x = np.linspace(0.0, 1.0, _N)
    presets = {
        "linear": x,
        "linear_r": x[::-1],
        "geom": np.geomspace(0.01, 1.0, _N),
        "geom_r": np.geomspace(0.01, 1.0, _N)[::-1],
        "sigmoid": 1.0 / (1.0 + np.exp(-10.0 * (x - 0.5))),
        "sigmoid_r": 1.0 / (1.0 + np.exp(10.0 * (x - 0.5))),
    }
    for k in range(3, 11):
        presets[f"sigmoid_{k}"] = 1.0 / (1.0 + np.exp(-k * (x - 0.5)))
    if name not in presets:
        raise ValueError(
            f"opacity: unknown preset {name!r}; expected one of {', '.join(sorted(presets))} "
            "or a sequence of values over clim"
        )
    return presets[name]


def _as_volume(data, time=None):
    """A path, a Volume, a meshio Mesh, a PyVista grid or a Series (at `time`) as a Volume."""
    if isinstance(data, Volume):
        return data
    if isinstance(data, (str, os.PathLike)):
        return Volume.read(os.fspath(data))
    if hasattr(data, "times") and hasattr(data, "__getitem__"):  # a vorang.Series
        times = list(data.times)
        step = 0 if time is None else min(range(len(times)), key=lambda i: (abs(times[i] - time), i))
        return data[step]
    if hasattr(data, "celltypes") or hasattr(data, "dimensions"):  # PyVista
        return Volume.from_pyvista(data)
    if hasattr(data, "cells") and hasattr(data, "points"):  # meshio
        return Volume.from_meshio(data)
    raise TypeError(
        f"plot: expected a file path, a vorang.Volume, a meshio Mesh, a PyVista grid or a "
        f"vorang.Series, found {type(data).__name__}"
    )


def _field(vol, scalars):
    """The field number and name `scalars` names (default: the first scalar field)."""
    names = list(vol.field_names)
    if scalars is None:
        for i in range(len(names)):
            try:
                vol.field_range(i)
                return i, names[i]
            except ValueError:
                continue
        raise ValueError("plot: the volume has no scalar field to colour by")
    if isinstance(scalars, str):
        if scalars not in names:
            raise ValueError(f"plot: no field named {scalars!r}; the fields are {names}")
        return names.index(scalars), scalars
    return int(scalars), names[int(scalars)]


def _colours(cmap, n=256):
    """(n, 3) RGB in [0, 1] of a colormap: a matplotlib name or Colormap, or any callable on
    [0, 1] → RGB(A)."""
    if isinstance(cmap, str):
        try:
            import matplotlib

            cmap = matplotlib.colormaps[cmap]
        except ImportError:
            # No matplotlib: VoRANG's own tables by name.
            from . import _PRESETS

            knots = _PRESETS.get(cmap.lower())
            if not knots:
                raise ValueError(
                    f"cmap: {cmap!r} is not one of VoRANG's tables ({', '.join(sorted(_PRESETS))}); "
                    "install matplotlib for its colormaps"
                ) from None
            return np.asarray(knots, dtype=float)
        except KeyError:
            raise ValueError(f"cmap: matplotlib knows no colormap {cmap!r}") from None
    if not callable(cmap):
        raise TypeError(
            "cmap: expected a colormap name, a matplotlib Colormap (or any callable on [0, 1]), "
            f"or a vorang.Colormap, found {type(cmap).__name__}"
        )
    rgba = np.asarray([cmap(float(t)) for t in np.linspace(0.0, 1.0, n)], dtype=float)
    return rgba[:, :3]


def mean_edge_length(vol) -> float:
    """The mean length of the tetrahedra's edges (each edge counted once per cell)."""
    p = np.asarray(vol.points)
    t = np.asarray(vol.tets)
    pairs = [(0, 1), (1, 2), (0, 2), (0, 3), (1, 3), (2, 3)]
    lengths = [np.linalg.norm(p[t[:, a]] - p[t[:, b]], axis=1) for a, b in pairs]
    return float(np.mean(np.concatenate(lengths)))


def transfer_function(
    vol, *, scalars=None, cmap="viridis", clim=None, opacity=None, opacity_unit_distance=None
):
    """The (Colormap, Alphamap, brightness) that `plot` renders with.

    Opacity values a ∈ [0, 1] are the fraction of light absorbed over `opacity_unit_distance`
    (default: the mesh's mean edge length d): the absorption coefficient is
    χ = −ln(1 − a) / d (a = 1 is taken as 0.999). The brightness is the largest χ, so that
    emission η = colour · χ_max makes opaque parts show the colormap's colours.
    """
    from . import Alphamap, Colormap

    i, name = _field(vol, scalars)
    field = name if name else i
    lo, hi = (vol.field_range(i) if clim is None else (float(clim[0]), float(clim[1])))
    if not hi > lo:
        hi = lo + (abs(lo) or 1.0) * 1e-6
    if opacity is None:
        opacity = "linear"
    a = _opacity_preset(opacity) if isinstance(opacity, str) else np.asarray(opacity, float)
    if a.ndim != 1 or len(a) < 1 or not np.all((a >= 0) & (a <= 1)):
        raise ValueError("opacity: expected values in [0, 1] (fractions absorbed per unit distance)")
    d = mean_edge_length(vol) if opacity_unit_distance is None else float(opacity_unit_distance)
    if not d > 0:
        raise ValueError("opacity_unit_distance: expected a length > 0")
    chi = -np.log1p(-np.minimum(a, 0.999)) / d
    values = np.linspace(lo, hi, len(chi)) if len(chi) > 1 else np.array([lo])
    if len(chi) == 1:
        values, chi = np.array([lo, hi]), np.repeat(chi, 2)
    alphamap = Alphamap.table(values, chi, field=field)
    if isinstance(cmap, Colormap):
        return cmap, alphamap, 1.0
    rgb = _colours(cmap)
    colormap = Colormap.table(np.linspace(lo, hi, len(rgb)), rgb, field=field, weighted=True)
    return colormap, alphamap, 1.0


def plot(
    data,
    *,
    scalars=None,
    cmap="viridis",
    clim=None,
    opacity=None,
    opacity_unit_distance=None,
    size=(512, 512),
    method="exact linear 0",
    time=None,
    **render_kwargs,
) -> Image:
    """One line from data to a picture: `vorang.plot("result.vtu", scalars="T")`.

    data: a file path (any format VoRANG reads), a `vorang.Volume`, a meshio `Mesh`, a PyVista
    grid or a `vorang.Series` (`time`: the step nearest that time; default the first).
    scalars: the field to colour by (a name or number; point or cell data — cell data stays cell
    data); default the first scalar field. cmap: a matplotlib colormap name or object (anything
    callable on [0, 1] → RGBA), or a `vorang.Colormap`; without matplotlib, VoRANG's preset
    names. clim=(lo, hi): the colour and opacity range, default the field's range. opacity:
    "linear" (default), "linear_r", "geom", "sigmoid" (PyVista's names) or a sequence of values
    evenly spaced over clim, each the fraction of light absorbed per `opacity_unit_distance`
    (default the mesh's mean edge length): χ = −ln(1 − a) / distance.

    It frames the data (`view_all`), draws a legend and no grid lines; other keywords go to
    `vorang.render` (camera, rotate, background, lights, progress, …). Returns a `vorang.Image`,
    which shows itself in notebooks.
    """
    vol = _as_volume(data, time)
    if clim is None and hasattr(data, "range") and hasattr(data, "times"):
        # A series: the range over all steps, so that colours mean the same in every frame.
        _, name = _field(vol, scalars)
        clim = data.range(name if name else _field(vol, scalars)[0])
    colormap, alphamap, brightness = transfer_function(
        vol,
        scalars=scalars,
        cmap=cmap,
        clim=clim,
        opacity=opacity,
        opacity_unit_distance=opacity_unit_distance,
    )
    from . import render

    render_kwargs.setdefault("legend", "right")
    render_kwargs.setdefault("brightness", brightness)
    return render(
        vol, size=size, colormap=colormap, alphamap=alphamap, method=method, **render_kwargs
    )


def show(data, **plot_kwargs):
    """An interactive view in Jupyter (ipywidgets): sliders for azimuth, elevation and zoom, and
    for `clim` and a series' time; a fast interpolateColor preview while a slider moves, the
    chosen method once it rests, rendered off the kernel's main thread. Without ipywidgets it
    returns the static `plot` image with a one-line hint."""
    try:
        import ipywidgets as widgets
    except ImportError:
        import warnings

        warnings.warn("vorang.show: pip install ipywidgets for the interactive view; showing a static image")
        return plot(data, **plot_kwargs)
    return _Viewer(widgets, data, plot_kwargs).box


class _Viewer:
    """The widgets of `show` and their renders: a preview at a quarter of the pixels while a
    control moves, the chosen method once it has rested for `settle` seconds."""

    settle = 0.3

    def __init__(self, widgets, data, plot_kwargs):
        self.data, self.kwargs = data, dict(plot_kwargs)
        self.size = tuple(self.kwargs.pop("size", (512, 512)))
        vol = _as_volume(data, self.kwargs.get("time"))
        i, _ = _field(vol, self.kwargs.get("scalars"))
        lo, hi = vol.field_range(i)
        self.azimuth = widgets.FloatSlider(value=0, min=-180, max=180, description="azimuth")
        self.elevation = widgets.FloatSlider(value=0, min=-90, max=90, description="elevation")
        self.zoom = widgets.FloatLogSlider(value=1, base=2, min=-2, max=3, description="zoom")
        self.clim = widgets.FloatRangeSlider(
            value=self.kwargs.pop("clim", (lo, hi)), min=lo, max=hi, step=(hi - lo) / 200 or 1,
            description="clim",
        )
        controls = [self.azimuth, self.elevation, self.zoom, self.clim]
        self.time = None
        if hasattr(data, "times") and len(list(data.times)) > 1:
            times = list(data.times)
            self.time = widgets.SelectionSlider(options=times, description="time")
            controls.append(self.time)
        self.image = widgets.Image(format="png")
        self.status = widgets.Label()
        self.box = widgets.VBox([self.image, *controls, self.status])
        self.generation = 0
        self.lock = threading.Lock()
        self.timer = None
        for c in controls:
            c.observe(self._changed, names="value")
        self._render(refined=True, generation=0)

    def _kwargs(self, refined):
        kw = dict(self.kwargs)
        kw["clim"] = tuple(self.clim.value)
        if self.time is not None:
            kw["time"] = self.time.value
        rotate = [(0, 1, 0, self.azimuth.value), (1, 0, 0, -self.elevation.value)]
        kw["rotate"] = list(kw.get("rotate", ())) + rotate
        kw["zoom"] = self.zoom.value
        w, h = self.size
        if not refined:
            kw["method"] = "interpolateColor"
            w, h = max(1, w // 2), max(1, h // 2)
        kw["size"] = (w, h)
        return kw

    def _render(self, refined, generation):
        img = plot(self.data, **self._kwargs(refined))
        with self.lock:
            if generation != self.generation:
                return  # a newer view is on its way
            png = img._repr_png_()
            self.image.value = png
            self.status.value = "refined" if refined else "preview"

    def _changed(self, _change):
        with self.lock:
            self.generation += 1
            generation = self.generation
            if self.timer is not None:
                self.timer.cancel()
        threading.Thread(target=self._render, args=(False, generation), daemon=True).start()
        self.timer = threading.Timer(self.settle, self._render, args=(True, generation))
        self.timer.daemon = True
        self.timer.start()


__all__ = ["plot", "show", "transfer_function", "mean_edge_length"]
