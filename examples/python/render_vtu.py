"""Render a .vtu file from Python and save a PNG (and a transfer-function sweep).

    pip install ./python
    python examples/python/render_vtu.py        # writes examples/python/out/*.png
"""

import pathlib

import vorang

here = pathlib.Path(__file__).resolve().parent
inclusion = here.parent / "inclusion"
out = here / "out"
out.mkdir(exist_ok=True)

vol = vorang.Volume.read(inclusion / "inclusion.vtu")
print(vol, vol.field_names)

# The scene of examples/inclusion/inclusion.tcl, as keyword arguments.
img = vorang.render(
    vol,
    size=(320, 200),
    colormap=inclusion / "temperature.cmap",
    alphamap=inclusion / "material.amap",
    ortho=(-1.3, 1.3, -0.8125, 0.8125, -10, 10),
    rotate=[(1, 0, 0, -25), (0, 1, 0, 20)],
    method="exact linear 0 1.5",
    linedraw="off",
)
print("image", img.shape, img.dtype, "largest channel", float(img[..., :3].max()))
vorang.save(img, out / "inclusion.png")

# A transfer-function sweep: the absorption of the hot region grows from frame to frame.
for i, chi in enumerate([0.2, 0.8, 2.0]):
    img = vorang.render(
        vol,
        size=(160, 100),
        colormap=vorang.Colormap.preset("magma", 0.0, 2.0, field="temperature", brightness=2.0),
        alphamap=vorang.Alphamap.table([0.0, 2.0], [0.05, chi], field="temperature"),
        ortho=(-1.3, 1.3, -0.8125, 0.8125, -10, 10),
        rotate=[(1, 0, 0, -25)],
        method="exact linear 0 1.0",
        linedraw="off",
        background=(0, 0, 0),
    )
    vorang.save(img, out / f"sweep_{i}.png")
print("wrote", sorted(p.name for p in out.glob("*.png")))
