"""`vorang.Image`: a rendered picture that is a numpy array and shows itself in notebooks."""

from __future__ import annotations

import numpy as np

from . import _vorang


class Image(np.ndarray):
    """A rendered image: a float32 numpy array of shape (h, w, 4), first row at the top, RGB as
    the PFM output of the equivalent script holds it, plus alpha (the volume's opacity 1 - T).

    In Jupyter it displays itself (`_repr_png_`: the 8-bit PNG the CLI writes for the same
    image); `.save(path)` writes any image format by extension. `transparent` is True after
    `background="none"` (straight alpha where the format has alpha).
    """

    transparent: bool

    def __new__(cls, array, transparent: bool = False):
        obj = np.asarray(array, dtype=np.float32).view(cls)
        obj.transparent = bool(transparent)
        return obj

    def __array_finalize__(self, obj):
        self.transparent = getattr(obj, "transparent", False)

    def _repr_png_(self) -> bytes | None:
        if self.ndim != 3 or self.shape[2] not in (3, 4) or 0 in self.shape[:2]:
            return None
        return bytes(_vorang._encode(np.asarray(self), "png", transparent=self.transparent))

    def save(self, path) -> None:
        """Writes the image to `path`, the format chosen by the extension (.png, .tiff, .exr,
        .pfm, …), exactly as the script's render commands write it."""
        _vorang.save(np.asarray(self), path, transparent=self.transparent)

    def __repr__(self) -> str:
        if self.ndim == 3:
            h, w = self.shape[:2]
            return f"vorang.Image({w}×{h}{', transparent' if self.transparent else ''})"
        return np.ndarray.__repr__(np.asarray(self))
