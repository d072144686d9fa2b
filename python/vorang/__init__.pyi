"""Type stubs of the vorang package."""

import os
from typing import Mapping, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

_Path = Union[str, "os.PathLike[str]"]
_Vec3 = Tuple[float, float, float]

class Volume:
    """A tetrahedral mesh with its fields."""

    def __init__(
        self,
        points: npt.ArrayLike,
        tets: npt.ArrayLike,
        point_data: Optional[Mapping[str, npt.ArrayLike]] = None,
        cell_data: Optional[Mapping[str, npt.ArrayLike]] = None,
    ) -> None: ...
    @staticmethod
    def read(path: _Path) -> "Volume": ...
    @staticmethod
    def from_meshio(mesh: object) -> "Volume": ...
    @staticmethod
    def from_pyvista(grid: object) -> "Volume": ...
    @property
    def n_points(self) -> int: ...
    @property
    def n_tets(self) -> int: ...
    @property
    def field_names(self) -> list[Optional[str]]: ...
    @property
    def points(self) -> npt.NDArray[np.float64]: ...
    @property
    def tets(self) -> npt.NDArray[np.int64]: ...
    def field_range(self, field: Union[int, str]) -> Tuple[float, float]: ...

class Series:
    """A collection or time series (.pvd, .series, .pvtu, .vtm, Exodus II, XDMF, VTKHDF): its steps as Volumes."""

    @staticmethod
    def read(path: _Path) -> "Series": ...
    @property
    def times(self) -> list[float]: ...
    @property
    def source(self) -> str: ...
    def __len__(self) -> int: ...
    def __getitem__(self, step: int) -> Volume: ...
    def nearest(self, time: float) -> int: ...
    def range(self, field: Union[int, str]) -> Tuple[float, float]: ...

class Image(np.ndarray):
    """A rendered image: float32 (h, w, 4), shown inline in notebooks."""

    transparent: bool
    def __new__(cls, array: npt.ArrayLike, transparent: bool = False) -> "Image": ...
    def _repr_png_(self) -> Optional[bytes]: ...
    def save(self, path: _Path) -> None: ...

class Colormap:
    text: str
    def __init__(self, text: str) -> None: ...
    def save(self, path: _Path) -> None: ...
    @classmethod
    def table(
        cls,
        values: Sequence[float],
        rgb: npt.ArrayLike,
        field: Union[int, str, None] = None,
        weighted: bool = False,
    ) -> "Colormap": ...
    @classmethod
    def constant(cls, rgb: Sequence[float], field: Union[int, str, None] = None) -> "Colormap": ...
    @classmethod
    def preset(
        cls,
        name: str,
        lo: float,
        hi: float,
        field: Union[int, str, None] = None,
        brightness: float = 1.0,
    ) -> "Colormap": ...

class Alphamap:
    text: str
    def __init__(self, text: str) -> None: ...
    def save(self, path: _Path) -> None: ...
    @classmethod
    def table(
        cls, values: Sequence[float], chi: npt.ArrayLike, field: Union[int, str, None] = None
    ) -> "Alphamap": ...
    @classmethod
    def constant(cls, chi: float) -> "Alphamap": ...

def render(
    volume: Union[Volume, Series],
    *,
    size: Tuple[int, int] = (512, 512),
    colormap: Union[None, str, _Path, Colormap] = None,
    alphamap: Union[None, str, _Path, Alphamap] = None,
    method: str = "exact linear 0",
    persp: Optional[Tuple[float, float, float, float]] = None,
    ortho: Optional[Tuple[float, float, float, float, float, float]] = None,
    look_at: Optional[Tuple[_Vec3, _Vec3, _Vec3]] = None,
    rotate: Sequence[Tuple[float, float, float, float]] = (),
    scale: Optional[_Vec3] = None,
    translate: Optional[_Vec3] = None,
    background: Union[str, _Vec3, _Path, None] = "white",
    linedraw: str = "off",
    lights: Sequence[Tuple[float, float, float, float, float, float]] = (),
    view_all: bool = True,
    zoom: float = 1.0,
    legend: Optional[str] = None,
    brightness: Optional[float] = None,
    label: Optional[str] = None,
    step: Optional[int] = None,
    time: Optional[float] = None,
    progress: Optional[object] = None,
    backend: str = "cpu",
) -> Image: ...
def animate(
    series: Series,
    path: _Path,
    *,
    fps: float = 10,
    label: Optional[str] = None,
    progress: Optional[object] = None,
    **render_kwargs: object,
) -> str: ...
def plot(
    data: object,
    *,
    scalars: Union[int, str, None] = None,
    cmap: object = "viridis",
    clim: Optional[Tuple[float, float]] = None,
    opacity: Union[str, Sequence[float], None] = None,
    opacity_unit_distance: Optional[float] = None,
    size: Tuple[int, int] = (512, 512),
    method: str = "exact linear 0",
    time: Optional[float] = None,
    **render_kwargs: object,
) -> Image: ...
def show(data: object, **plot_kwargs: object) -> object: ...
def save(image: npt.ArrayLike, path: _Path, *, transparent: bool = False) -> None: ...
def run_script(path_or_text: Union[str, _Path]) -> None: ...
