"""render(..., backend="gpu") and plot(..., backend="gpu"): the CPU's image (every channel within
1e-12, crates/vorang/tests/gpu.rs holds the backend to it), or a ValueError that names what is
missing (a module built without the `gpu` feature, no Vulkan adapter with 64-bit floats) — never
the CPU instead. Skipped where the GPU is missing, unless VORANG_GPU_TESTS=required."""

import os
import pathlib

import numpy as np
import pytest

import vorang

ROOT = pathlib.Path(__file__).resolve().parents[2]
HYPER = ROOT / "examples" / "hyperthermia"
VTU = ROOT / "examples" / "inclusion" / "inclusion.vtu"


def hyper():
    return vorang.Volume.read(str(HYPER / "hyperthermia.hmesh"))


def scene(method):
    return dict(
        colormap=str(HYPER / "red.cmap"),
        alphamap=str(HYPER / "heat.amap"),
        size=(48, 40),
        rotate=[(1, 1, 0, 30)],
        method=method,
        linedraw="off",
    )


def gpu_or_skip():
    try:
        vorang.render(hyper(), backend="gpu", **scene("exact linear 0 1"))
    except ValueError as e:
        assert "gpu" in str(e).lower()
        if os.environ.get("VORANG_GPU_TESTS") == "required":
            raise
        pytest.skip(f"no GPU backend here: {e}")


@pytest.mark.parametrize(
    "method", ["exact linear 0 1", "interpolateCoeff linear 2", "interpolateColor 2"]
)
def test_render_on_the_gpu_is_the_cpus_image(method):
    gpu_or_skip()
    vol = hyper()
    cpu = vorang.render(vol, **scene(method))
    gpu = vorang.render(vol, backend="gpu", **scene(method))
    assert gpu.shape == cpu.shape
    assert np.abs(gpu.astype(np.float64) - cpu.astype(np.float64)).max() <= 1e-12
    assert cpu[:, :, 3].max() > 0, "something is drawn"


def test_plot_on_the_gpu_is_the_cpus_image():
    # plot's maps sample the colormap at 256 knots, which cut each cell's interval many times
    # (lavapipe once cut such marches short, docs/gpu.md): the GPU's image is the CPU's.
    gpu_or_skip()
    kw = dict(size=(64, 48), scalars="temperature", clim=(0.1, 0.6))
    cpu = vorang.plot(str(VTU), **kw)
    gpu = vorang.plot(str(VTU), backend="gpu", **kw)
    cpu, gpu = np.asarray(cpu, dtype=np.float64), np.asarray(gpu, dtype=np.float64)
    assert gpu.shape == cpu.shape
    assert np.abs(gpu - cpu).max() <= 1e-12
    assert cpu[:, :, 3].max() > 0, "something is drawn"


def test_a_method_the_gpu_lacks_is_named():
    gpu_or_skip()
    with pytest.raises(ValueError, match="interpolateCoeff constEA"):
        vorang.render(hyper(), backend="gpu", **scene("interpolateCoeff constEA 1"))
