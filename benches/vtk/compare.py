#!/usr/bin/env python3
"""Side-by-side frame times of vorang and VTK on the benchmark scenes (docs/performance.md).

For each case (mesh size × image size) this script

1. generates the jittered Kuhn box with `vorang generate` (cached), reads the BINARY HyperMesh
   file exactly (big-endian doubles, ints, floats) and writes it as a .vtu with VTK's XML writer
   (same nodes, same tetrahedra, the same float node field "smooth");
2. renders N + 1 frames with vorang (`exact linear 0` and `interpolateColor`, the bench maps of
   `benches/render.rs`) and with VTK (`vtkUnstructuredGridVolumeRayCastMapper` and
   `vtkProjectedTetrahedraMapper`, offscreen through EGL or OSMesa), VTK reading the .vtu:
   frame 0 is the bench view (the box turned 30° about (1, 1, 0)) and counts as setup; frames
   1…N turn the volume 1° more about the vertical axis each;
3. runs vorang and VTK alternately frame by frame (one vorang session and one VTK process per
   round, each rendering a frame when asked and idle otherwise; `--rounds` rounds) and prints
   Markdown tables of the median frame times and the median ratio of paired frames;
4. saves frame 0 of every renderer as PNG and prints the mean absolute difference between the
   images (against vorang with the bench maps, and against vorang with an ABSORPTION_WEIGHTED
   colormap, which is VTK's optical model; see README.md).

VTK's volume model is "emission = colour × attenuation" (Moreland & Angel; the projected
tetrahedra blend colour with α = 1 − exp(−τ·d)); the attenuation per unit length is the scalar
opacity divided by the scalar opacity unit distance. So VTK gets the colormap's RGB rows as
colour knots and χ/χ_max as opacity knots at the same field values, with unit distance 1/χ_max:
its τ equals vorang's χ exactly. VTK's emission is then rgb·χ, which is vorang's
ABSORPTION_WEIGHTED colormap, not the bench's SIMPLE_EMITTER (emission rgb per unit length);
the timings use the bench maps for vorang (the speed targets in docs/performance.md are stated
for them) unless
`--vorang-maps weighted` is given.

Run `python compare.py --help` for the options; README.md has the setup.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import platform
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

# Transfer function of benches/render.rs: (field value, rgb, chi). Colour and opacity share
# their knots (VTK's ray caster ignores opacity knots that are not colour knots).
KNOTS = [
    (0.45, (0.0, 0.0, 1.0), 0.2),
    (0.55, (0.0, 1.0, 0.0), 3.0),
    (0.65, (1.0, 1.0, 0.0), 0.5),
    (0.75, (1.0, 0.0, 0.0), 6.0),
    (0.85, (1.0, 1.0, 1.0), 1.0),
]
CHI_MAX = max(k[2] for k in KNOTS)

BASE_AXIS, BASE_DEGREES = (1.0, 1.0, 0.0), 30.0  # the bench view
TURN_AXIS, TURN_DEGREES = (0.0, 1.0, 0.0), 1.0  # per timed frame

SIZES = {"20k": 20_000, "150k": 150_000, "1m": 1_000_000}

FRAME_LINE = re.compile(r"^(\S+)\s+(\d+)×(\d+)\s+(\d+) cells\s+([0-9.]+) s\b", re.M)


# --------------------------------------------------------------------------- maps and mesh


def colormap_text(kind: str) -> str:
    rows = "".join(f"{r:g} {g:g} {b:g} {v:g}\n" for v, (r, g, b), _ in KNOTS)
    return f"# VoRANG Colormap 1.0\n{kind} @1\n@1\n{rows}"


def alphamap_text() -> str:
    rows = "".join(f"{chi:g} {v:g}\n" for v, _, chi in KNOTS)
    return f"# VoRANG Alphamap 1.0\nSIMPLE_ABSORBER @1\n@1\n{rows}"


def read_hypermesh_binary(path: Path):
    """Nodes (n×3 float64), tetrahedra (m×4, 0-based) and the first Linear node field of a
    small-layout BINARY HyperMesh file as `vorang generate --binary` writes it."""
    import numpy as np

    data = path.read_bytes()
    pos = 0
    header: list[str] = []
    while True:
        end = data.index(b"\n", pos)
        line = data[pos:end].decode("ascii", "replace")
        if line.lstrip().startswith("@"):
            break
        header.append(line.split("#", 1)[0])
        pos = end + 1
    text = "\n".join(header)
    counts = {k: int(v) for k, v in re.findall(r"\b(n\w+)\s*=\s*(\d+)", text)}
    decls = {}
    for kind, ty, n, marker in re.findall(
        r"\b(Nodes|Tetrahedra|NodeData)\s*\{\s*(\w+)(?:\[(\d+)\])?[^}]*\}\s*=\s*@(\w+)", text
    ):
        decls[marker] = (kind, ty, int(n or 1))
    field = re.search(r"Field\b[^{]*\{\s*(\w+)[^}]*\}\s*=\s*Linear\(\s*@(\w+)\s*\)", text)
    if not field:
        sys.exit(f"{path}: no Linear node field")
    dtypes = {"double": ">f8", "float": ">f4", "int": ">i4", "long": ">i4"}
    rows = {"Nodes": counts["nNodes"], "Tetrahedra": counts["nTetrahedra"],
            "NodeData": counts["nNodes"]}
    blocks = {}
    while pos < len(data):
        end = data.index(b"\n", pos)
        marker = data[pos:end].decode().strip()
        pos = end + 1
        if not marker:
            continue
        kind, ty, n = decls[marker.lstrip("@")]
        dt = np.dtype(dtypes[ty])
        size = rows[kind] * n * dt.itemsize
        blocks[marker.lstrip("@")] = np.frombuffer(data, dt, rows[kind] * n, pos).reshape(-1, n)
        pos += size
        if pos < len(data) and data[pos:pos + 1] == b"\n":
            pos += 1
    by_kind = {decls[m][0]: m for m in blocks}
    nodes = blocks[by_kind["Nodes"]].astype(np.float64)
    tets = blocks[by_kind["Tetrahedra"]].astype(np.int64) - 1  # HyperMesh indices are 1-based
    values = blocks[field.group(2)][:, 0].astype(np.float32)
    return nodes, tets, values


def write_vtu(nodes, tets, values, path: Path) -> None:
    import numpy as np
    from vtkmodules.util import numpy_support as ns
    from vtkmodules.vtkCommonCore import vtkPoints
    from vtkmodules.vtkCommonDataModel import VTK_TETRA, vtkCellArray, vtkUnstructuredGrid
    from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridWriter

    pts = vtkPoints()
    pts.SetData(ns.numpy_to_vtk(np.ascontiguousarray(nodes), deep=True))
    cells = vtkCellArray()
    offsets = np.arange(0, 4 * len(tets) + 1, 4, dtype=np.int64)
    cells.SetData(ns.numpy_to_vtkIdTypeArray(offsets, deep=True),
                  ns.numpy_to_vtkIdTypeArray(np.ascontiguousarray(tets.ravel()), deep=True))
    grid = vtkUnstructuredGrid()
    grid.SetPoints(pts)
    grid.SetCells(VTK_TETRA, cells)
    field = ns.numpy_to_vtk(values, deep=True)
    field.SetName("smooth")
    grid.GetPointData().SetScalars(field)
    w = vtkXMLUnstructuredGridWriter()
    w.SetFileName(str(path))
    w.SetInputData(grid)
    w.SetDataModeToAppended()
    w.SetCompressorTypeToNone()
    if not w.Write():
        sys.exit(f"could not write {path}")


def prepare_mesh(vorang: str, cache: Path, size: str) -> tuple[Path, Path]:
    """The cached BINARY HyperMesh file and .vtu of one bench size."""
    cache.mkdir(parents=True, exist_ok=True)
    bin_path = cache / f"box{size}.bin"
    vtu_path = cache / f"box{size}.vtu"
    if not bin_path.exists():
        subprocess.run([vorang, "generate", str(bin_path), "--tets", str(SIZES[size]), "--binary"],
                       check=True, stdout=subprocess.DEVNULL)
    if not vtu_path.exists() or vtu_path.stat().st_mtime < bin_path.stat().st_mtime:
        nodes, tets, values = read_hypermesh_binary(bin_path)
        write_vtu(nodes, tets, values, vtu_path)
    return bin_path, vtu_path


# --------------------------------------------------------------------------- vorang


def vorang_script(bin_path: Path, maps: dict, pixels: int, method: str, out_dir: Path) -> str:
    """A session that renders one frame per line on standard input: `first` (the bench view)
    or `turn` (1° more), answering `done` after each, so frames alternate with VTK's."""
    ax, deg = " ".join(f"{c:g}" for c in BASE_AXIS), f"{BASE_DEGREES:g}"
    tx, tdeg = " ".join(f"{c:g}" for c in TURN_AXIS), f"{TURN_DEGREES:g}"
    return "\n".join([
        f"imagesize {pixels} {pixels}",
        f"volume {{{bin_path}}}",
        f"colormap {{{maps['cmap']}}}",
        f"alphamap {{{maps['amap']}}}",
        "linedraw off",
        f"output {{{out_dir / 'frame.pfm'}}}",
        f"vol_rotate {ax} {deg}",
        f"method {method}",
        "puts ready; flush stdout",
        "while {[gets stdin cmd] >= 0} {",
        f"    if {{$cmd eq \"turn\"}} {{ vol_rotate {tx} {tdeg} }}",
        "    render_btf",
        "    puts done; flush stdout",
        "}",
        "",
    ])


class Session:
    """A child process that renders a frame per request line and answers with a line."""

    def __init__(self, cmd: list[str], name: str):
        self.name = name
        self.proc = subprocess.Popen(cmd, stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                     stderr=subprocess.STDOUT, text=True, bufsize=1)
        self.log: list[str] = []
        self.wait_for(("ready",))

    def wait_for(self, ends) -> list[str]:
        lines = []
        while True:
            line = self.proc.stdout.readline()
            if not line:
                self.proc.wait()
                sys.exit(f"{self.name} ended unexpectedly:\n" + "".join(self.log + lines))
            lines.append(line)
            if line.strip().split(" ", 1)[0] in ends:
                self.log += lines
                return lines

    def request(self, cmd: str, ends) -> list[str]:
        self.proc.stdin.write(cmd + "\n")
        self.proc.stdin.flush()
        return self.wait_for(ends)

    def close(self) -> str:
        """End the session (end of input); what it printed after its last frame."""
        self.proc.stdin.close()
        rest = self.proc.stdout.read()
        if self.proc.wait() != 0:
            sys.exit(f"{self.name} failed:\n" + "".join(self.log) + rest)
        return rest


def vorang_frame(session: Session, first: bool) -> float:
    """Render one frame; the time vorang prints for it (render only: no loading, no writing)."""
    out = "".join(session.request("first" if first else "turn", ("done",)))
    m = FRAME_LINE.findall(out)
    if len(m) != 1:
        sys.exit(f"no frame time in vorang's output:\n{out}")
    return float(m[0][4])


def read_pfm(path: Path):
    import numpy as np

    with open(path, "rb") as f:
        if f.readline().strip() != b"PF":
            sys.exit(f"{path}: not an RGB PFM")
        w, h = (int(x) for x in f.readline().split())
        scale = float(f.readline())
        a = np.frombuffer(f.read(), "<f4" if scale < 0 else ">f4").reshape(h, w, 3)
    return a[::-1].copy()  # PFM rows run bottom to top; return top row first


# --------------------------------------------------------------------------- VTK


def rotation(axis, degrees):
    import numpy as np

    a = np.asarray(axis, float)
    a = a / np.linalg.norm(a)
    t = math.radians(degrees)
    k = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return np.eye(3) + math.sin(t) * k + (1 - math.cos(t)) * (k @ k)  # right-handed


def vtk_worker(args) -> None:
    """Render frames 0…N with one VTK mapper and print a JSON line with the times."""
    os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", args.vtk_window)
    import numpy as np
    from vtkmodules.util import numpy_support as ns
    import vtkmodules.vtkRenderingOpenGL2  # noqa: F401  (the OpenGL factory)
    import vtkmodules.vtkRenderingVolumeOpenGL2  # noqa: F401
    from vtkmodules.vtkCommonCore import vtkMultiThreader, vtkVersion
    from vtkmodules.vtkCommonMath import vtkMatrix4x4
    from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader
    from vtkmodules.vtkRenderingCore import (
        vtkColorTransferFunction, vtkRenderer, vtkRenderWindow, vtkVolume, vtkVolumeProperty,
        vtkWindowToImageFilter)
    from vtkmodules.vtkCommonDataModel import vtkPiecewiseFunction
    from vtkmodules.vtkRenderingVolume import (
        vtkUnstructuredGridPartialPreIntegration, vtkUnstructuredGridVolumeRayCastMapper)
    from vtkmodules.vtkRenderingVolumeOpenGL2 import vtkOpenGLProjectedTetrahedraMapper

    reader = vtkXMLUnstructuredGridReader()
    reader.SetFileName(args.vtu)
    reader.Update()
    grid = reader.GetOutput()
    grid.GetPointData().SetActiveScalars("smooth")
    bounds = grid.GetBounds()
    centre = np.array([(bounds[0] + bounds[1]) / 2, (bounds[2] + bounds[3]) / 2,
                       (bounds[4] + bounds[5]) / 2])

    color = vtkColorTransferFunction()
    color.SetColorSpaceToRGB()
    opacity = vtkPiecewiseFunction()
    for v, (r, g, b), chi in KNOTS:
        color.AddRGBPoint(v, r, g, b)
        opacity.AddPoint(v, chi / CHI_MAX)
    prop = vtkVolumeProperty()
    prop.SetColor(color)
    prop.SetScalarOpacity(opacity)
    prop.SetScalarOpacityUnitDistance(1.0 / CHI_MAX)  # attenuation = opacity / unit = chi
    prop.SetInterpolationTypeToLinear()
    prop.ShadeOff()

    if args.mapper == "raycast":
        mapper = vtkUnstructuredGridVolumeRayCastMapper()
        mapper.SetAutoAdjustSampleDistances(0)  # one ray per pixel, whatever a frame costs
        mapper.SetImageSampleDistance(1.0)
        if args.vtk_integrator == "partial":
            mapper.SetRayIntegrator(vtkUnstructuredGridPartialPreIntegration())
        threads = mapper.GetNumberOfThreads()
    else:
        mapper = vtkOpenGLProjectedTetrahedraMapper()
        threads = None
    mapper.SetInputData(grid)
    volume = vtkVolume()
    volume.SetMapper(mapper)
    volume.SetProperty(prop)

    ren = vtkRenderer()
    ren.SetBackground(1.0, 1.0, 1.0)  # vorang's default background: white
    ren.AddVolume(volume)
    win = vtkRenderWindow()
    win.SetOffScreenRendering(1)
    win.SetMultiSamples(0)
    win.AddRenderer(ren)
    win.SetSize(args.pixels, args.pixels)

    # vorang's default orthographic camera: x/y extents of the centred, untransformed box.
    cam = ren.GetActiveCamera()
    cam.ParallelProjectionOn()
    cam.SetFocalPoint(0.0, 0.0, 0.0)
    cam.SetPosition(0.0, 0.0, 10.0)
    cam.SetViewUp(0.0, 1.0, 0.0)
    cam.SetParallelScale((bounds[3] - bounds[2]) / 2)
    cam.SetClippingRange(5.0, 15.0)
    if abs((bounds[1] - bounds[0]) - (bounds[3] - bounds[2])) > 1e-9:
        sys.exit("the comparison assumes equal x and y extents (square pixels)")

    grab = vtkWindowToImageFilter()
    grab.SetInput(win)
    grab.SetInputBufferTypeToRGB()
    grab.ReadFrontBufferOff()
    grab.ShouldRerenderOff()

    base = rotation(BASE_AXIS, BASE_DEGREES)
    turn = rotation(TURN_AXIS, TURN_DEGREES)
    rot = base
    png = Path(args.png)
    print("ready", flush=True)
    for line in sys.stdin:
        cmd = line.strip()
        rot = base if cmd == "first" else turn @ rot
        m = np.eye(4)
        m[:3, :3] = rot
        m[:3, 3] = -rot @ centre  # centre the box, then turn it about its centre
        vm = vtkMatrix4x4()
        for i in range(4):
            for j in range(4):
                vm.SetElement(i, j, m[i, j])
        volume.SetUserMatrix(vm)
        t0 = time.perf_counter()
        win.Render()
        grab.Modified()
        grab.Update()  # reads the pixels back: the frame is complete
        img = grab.GetOutput()
        dt = time.perf_counter() - t0
        if cmd == "first":
            w, h, _ = img.GetDimensions()
            arr = ns.vtk_to_numpy(img.GetPointData().GetScalars()).reshape(h, w, -1)
            rgb = arr[::-1, :, :3].copy()  # top row first
            np.save(png.with_suffix(".npy"), rgb)
            write_png(rgb, png)
        print(f"done {dt!r}", flush=True)
    info = {
        "threads": threads,
        "integrator": (mapper.GetRayIntegrator().GetClassName()
                       if args.mapper == "raycast" and mapper.GetRayIntegrator() else
                       "vtkUnstructuredGridPreIntegration (chosen by the mapper)"
                       if args.mapper == "raycast" else None),
        "window": win.GetClassName(),
        "gl": " ".join(l.split(":", 1)[1].strip() for l in win.ReportCapabilities().splitlines()
                       if l.startswith("OpenGL renderer string")),
        "vtk": vtkVersion.GetVTKVersion(),
        "multithreader_default": vtkMultiThreader.GetGlobalDefaultNumberOfThreads(),
        "llvmpipe_threads": os.environ.get("LP_NUM_THREADS", "unset (Mesa: one per CPU)"),
    }
    print("VTKJSON " + json.dumps(info))


def write_png(rgb8, path: Path) -> None:
    import numpy as np
    from vtkmodules.util import numpy_support as ns
    from vtkmodules.vtkCommonDataModel import vtkImageData
    from vtkmodules.vtkIOImage import vtkPNGWriter

    h, w, _ = rgb8.shape
    img = vtkImageData()
    img.SetDimensions(w, h, 1)
    arr = ns.numpy_to_vtk(np.ascontiguousarray(rgb8[::-1]).reshape(-1, 3), deep=True)
    img.GetPointData().SetScalars(arr)
    wr = vtkPNGWriter()
    wr.SetFileName(str(path))
    wr.SetInputData(img)
    wr.Write()


def vtk_session(args, mapper: str, vtu: Path, pixels: int, png: Path) -> Session:
    return Session([sys.executable, __file__, "--vtk-worker", "--mapper", mapper,
                    "--vtu", str(vtu), "--pixels", str(pixels), "--png", str(png),
                    "--vtk-window", args.vtk_window, "--vtk-integrator", args.vtk_integrator],
                   f"VTK ({mapper})")


def vtk_frame(session: Session, first: bool) -> float:
    line = session.request("first" if first else "turn", ("done",))[-1]
    return float(line.split()[1])


def vtk_info(session: Session) -> dict:
    rest = session.close()
    line = [l for l in rest.splitlines() if l.startswith("VTKJSON ")]
    if not line:
        sys.exit(f"no report from {session.name}:\n{rest}")
    return json.loads(line[-1][len("VTKJSON "):])


# --------------------------------------------------------------------------- main


def fmt(seconds: float) -> str:
    return f"{seconds * 1e3:.0f} ms" if seconds < 1 else f"{seconds:.2f} s"


def image_diff(vorang_rgb, vtk_rgb8) -> dict:
    """Mean and 99th-percentile absolute difference per channel value, in [0, 1]."""
    import numpy as np

    a = np.clip(vorang_rgb, 0.0, 1.0)
    b = vtk_rgb8.astype(np.float64) / 255.0
    d = np.abs(a - b)
    return {"mean": float(d.mean()), "p99": float(np.percentile(d, 99)), "max": float(d.max())}


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--vorang", default=shutil.which("vorang") or "target/release/vorang",
                   help="the vorang binary (default: vorang on PATH, else target/release/vorang)")
    p.add_argument("--sizes", nargs="+", default=["150k"], choices=sorted(SIZES),
                   help="mesh sizes (default 150k)")
    p.add_argument("--pixels", nargs="+", type=int, default=[512],
                   help="image sizes in pixels per side (default 512); every size × every mesh")
    p.add_argument("--cases", nargs="+", metavar="SIZE/PIXELS",
                   help="explicit cases instead of --sizes × --pixels, e.g. 150k/512 1m/1024")
    p.add_argument("--frames", type=int, default=5,
                   help="timed frames per run, each turned 1° more (default 5)")
    p.add_argument("--rounds", type=int, default=2,
                   help="alternating vorang/VTK runs per case and method (default 2)")
    p.add_argument("--methods", nargs="+", default=["exact", "color"],
                   choices=["exact", "color"],
                   help="exact: vorang `exact linear 0` vs VTK's ray caster; color: vorang "
                        "`interpolateColor` vs VTK's projected tetrahedra")
    p.add_argument("--vorang-maps", default="bench", choices=["bench", "weighted"],
                   help="vorang's colormap for the timings: the bench's SIMPLE_EMITTER "
                        "(default) or ABSORPTION_WEIGHTED (VTK's optical model)")
    p.add_argument("--vtk-integrator", default="default", choices=["default", "partial"],
                   help="the ray caster's integrator: the one VTK picks (pre-integration "
                        "table) or vtkUnstructuredGridPartialPreIntegration")
    p.add_argument("--vtk-window", default="vtkEGLRenderWindow",
                   help="VTK_DEFAULT_OPENGL_WINDOW for offscreen rendering "
                        "(vtkEGLRenderWindow or vtkOSOpenGLRenderWindow)")
    p.add_argument("--cache", type=Path, default=Path(tempfile.gettempdir()) / "vorang-vtk-cache",
                   help="where the generated meshes and .vtu files are kept")
    p.add_argument("--images", type=Path, default=Path(tempfile.gettempdir()) / "vorang-vtk",
                   help="where frame 0 of each renderer is saved as PNG")
    p.add_argument("--json", type=Path, help="also write all measurements to this file")
    # internal: one VTK run in a child process
    p.add_argument("--vtk-worker", action="store_true", help=argparse.SUPPRESS)
    p.add_argument("--mapper", help=argparse.SUPPRESS)
    p.add_argument("--vtu", help=argparse.SUPPRESS)
    p.add_argument("--png", help=argparse.SUPPRESS)
    args = p.parse_args()

    if args.vtk_worker:
        args.pixels = args.pixels[0]
        vtk_worker(args)
        return

    import numpy as np

    if args.cases:
        cases = []
        for c in args.cases:
            size, _, px = c.lower().partition("/")
            if size not in SIZES or not px.isdigit():
                p.error(f"bad case {c!r}: SIZE/PIXELS with SIZE in {sorted(SIZES)}")
            cases.append((size, int(px)))
    else:
        cases = [(s.lower(), px) for s in args.sizes for px in args.pixels]
    vorang = str(Path(args.vorang).resolve()) if os.sep in args.vorang else args.vorang

    cache = args.cache.resolve()
    cache.mkdir(parents=True, exist_ok=True)
    images = args.images.resolve()
    images.mkdir(parents=True, exist_ok=True)
    maps = {}
    for kind, name in [("SIMPLE_EMITTER", "bench"), ("ABSORPTION_WEIGHTED", "weighted")]:
        cmap = cache / f"five-{name}.cmap"
        cmap.write_text(colormap_text(kind))
        amap = cache / "five.amap"
        amap.write_text(alphamap_text())
        maps[name] = {"cmap": cmap, "amap": amap}
    pairs = {"exact": ("exact linear 0 1", "raycast"), "color": ("interpolateColor 1", "pt")}

    results = []
    meta = {}
    with tempfile.TemporaryDirectory(prefix="vorang-vtk-") as tmp:
        work = Path(tmp)
        for size, px in cases:
            bin_path, vtu = prepare_mesh(vorang, cache, size)
            tag = f"{size}-{px}"
            row = {"case": f"{size} / {px}²", "size": size, "pixels": px}
            for m in args.methods:
                method, mapper = pairs[m]
                v_times, k_times, v_first, k_first, ratios = [], [], [], [], []
                for rnd in range(args.rounds):
                    for old in work.glob("frame.*.pfm"):
                        old.unlink()
                    tcl = work / "session.tcl"
                    tcl.write_text(vorang_script(bin_path, maps[args.vorang_maps], px, method,
                                                 work))
                    png = images / f"{tag}-vtk-{mapper}.png"
                    vs = Session([vorang, str(tcl)], "vorang")
                    ks = vtk_session(args, mapper, vtu, px, png)
                    vt, kt = [], []
                    for f in range(args.frames + 1):
                        # vorang, VTK, VTK, vorang, vorang, …: each frame of one next to the
                        # same frame of the other, the order swapped every frame.
                        if f % 2 == 0:
                            vt.append(vorang_frame(vs, f == 0))
                            kt.append(vtk_frame(ks, f == 0))
                        else:
                            kt.append(vtk_frame(ks, f == 0))
                            vt.append(vorang_frame(vs, f == 0))
                    vs.close()
                    meta[mapper] = vtk_info(ks)
                    if rnd == 0:
                        shutil.copy(work / "frame.0001.pfm", work / f"{m}.pfm")
                    v_first.append(vt[0])
                    k_first.append(kt[0])
                    v_times += vt[1:]
                    k_times += kt[1:]
                    ratios += [k / v for k, v in zip(kt[1:], vt[1:])]
                    print(f"  {tag} {m} round {rnd + 1}: vorang {fmt(statistics.median(vt[1:]))}"
                          f" (first {fmt(vt[0])}), VTK {mapper} "
                          f"{fmt(statistics.median(kt[1:]))} (first {fmt(kt[0])}), load "
                          f"{os.getloadavg()[0]:.1f}", file=sys.stderr, flush=True)
                row[m] = {"vorang": statistics.median(v_times), "vtk": statistics.median(k_times),
                          "ratio": statistics.median(ratios),
                          "ratio_range": [min(ratios), max(ratios)],
                          "vorang_first": statistics.median(v_first),
                          "vtk_first": statistics.median(k_first),
                          "vorang_frames": v_times, "vtk_frames": k_times}
                # Images: frame 0 of vorang with the timed maps and, untimed, with the other.
                vtk_rgb = np.load((images / f"{tag}-vtk-{mapper}.png").with_suffix(".npy"))
                diffs = {}
                for maps_name in ["bench", "weighted"]:
                    if maps_name == args.vorang_maps:
                        pfm = work / f"{m}.pfm"
                    else:
                        for old in work.glob("frame.*.pfm"):
                            old.unlink()
                        tcl = work / "session.tcl"
                        tcl.write_text(vorang_script(bin_path, maps[maps_name], px, method, work))
                        one = Session([vorang, str(tcl)], "vorang")
                        vorang_frame(one, True)
                        one.close()
                        pfm = work / "frame.0001.pfm"
                    rgb = read_pfm(pfm)
                    write_png((np.clip(rgb, 0, 1) * 255 + 0.5).astype(np.uint8),
                              images / f"{tag}-vorang-{m}-{maps_name}.png")
                    diffs[maps_name] = image_diff(rgb, vtk_rgb)
                row[m]["diff"] = diffs
            results.append(row)

    print_report(args, results, meta)
    if args.json:
        args.json.write_text(json.dumps({"results": results, "vtk": meta}, indent=1))


def machine() -> str:
    model = ""
    try:
        for line in open("/proc/cpuinfo"):
            if line.startswith("model name"):
                model = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    mem = ""
    try:
        for line in open("/proc/meminfo"):
            if line.startswith("MemTotal"):
                mem = f", {int(line.split()[1]) / 2**20:.0f} GiB RAM"
                break
    except OSError:
        pass
    return (f"{os.cpu_count()} logical CPUs ({model or platform.processor()}){mem}, "
            f"{platform.system()} {platform.release()}")


def print_report(args, results, meta) -> None:
    print()
    print(f"Date: {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}; machine: {machine()}")
    print("Command: " + " ".join(sys.argv))
    for mapper, info in meta.items():
        extra = (f": ray caster with {info['threads']} threads (vtkMultiThreader default "
                 f"{info['multithreader_default']}), {info['integrator']}"
                 if mapper == "raycast" else
                 f": projected tetrahedra rasterised by the OpenGL driver, "
                 f"LP_NUM_THREADS {info['llvmpipe_threads']}")
        print(f"VTK {info['vtk']} ({info['window']}, {info['gl']}){extra}")
    print(f"Median of {args.frames} frames × {args.rounds} runs, each frame turned 1° more, vorang "
          f"and VTK alternating frame by frame; vorang maps: {args.vorang_maps}; ratio = median "
          f"of VTK / vorang over the pairs of the same frame (> 1: vorang faster), in brackets "
          f"the smallest and largest pair.")
    print()
    head = ["case"]
    if "exact" in args.methods:
        head += ["vorang `exact linear 0`", "VTK ray cast", "ratio"]
    if "color" in args.methods:
        head += ["vorang `interpolateColor`", "VTK projected tetrahedra", "ratio"]
    print("| " + " | ".join(head) + " |")
    print("|" + "---|" * len(head))
    for r in results:
        cells = [r["case"]]
        for m in ["exact", "color"]:
            if m in r:
                lo, hi = r[m]["ratio_range"]
                cells += [fmt(r[m]["vorang"]), fmt(r[m]["vtk"]),
                          f"{r[m]['ratio']:.2f}× ({lo:.2f}–{hi:.2f})"]
        print("| " + " | ".join(cells) + " |")
    print()
    print("First frame (setup included), median over the runs:")
    print()
    print("| case | method | vorang | VTK |")
    print("|---|---|---|---|")
    for r in results:
        for m, name in [("exact", "exact / ray cast"), ("color", "interpolateColor / PT")]:
            if m in r:
                print(f"| {r['case']} | {name} | {fmt(r[m]['vorang_first'])} | "
                      f"{fmt(r[m]['vtk_first'])} |")
    print()
    print("Images (frame 0): mean / 99th percentile / largest absolute difference per channel")
    print("(0…1) between VTK's image and vorang's with the bench colormap (SIMPLE_EMITTER) and")
    print("with ABSORPTION_WEIGHTED. VTK's model is emission = colour × attenuation: for `exact`")
    print("that is ABSORPTION_WEIGHTED; `interpolateColor` composites colour with its opacity as")
    print("VTK's projected tetrahedra do, so there the bench colormap is the matching one.")
    print()
    print("| case | pair | vs SIMPLE_EMITTER (bench) | vs ABSORPTION_WEIGHTED |")
    print("|---|---|---|---|")
    for r in results:
        for m, name in [("exact", "ray cast vs `exact linear 0`"),
                        ("color", "PT vs `interpolateColor`")]:
            if m in r:
                d = r[m]["diff"]
                print(f"| {r['case']} | {name} | " + " | ".join(
                    f"{d[k]['mean']:.4f} / {d[k]['p99']:.3f} / {d[k]['max']:.2f}"
                    for k in ["bench", "weighted"]) + " |")
    print()
    print(f"PNG images in {args.images}")


if __name__ == "__main__":
    main()
