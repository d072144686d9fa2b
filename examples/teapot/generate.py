#!/usr/bin/env python3
"""The teapot data set (thesis appendix D.2, `teapot.script`; its data file is lost).

A solid, teapot-like body, tetrahedralised with Gmsh (OpenCASCADE): a body of revolution
(a spline profile turned about the z axis), a lid knob, a tapered spout and a handle (a torus
whose outer part stands out of the body, leaving a hole). The mesh is non-convex: the handle's
hole and the creases where the spout, the handle and the knob meet the pot are concave, so a
renderer must order cells that a convex-mesh sort (MPVO) gets wrong.

The field is a genuine steady temperature (°C): the teapot stands on a hot plate (its base
held near 95 °C through a large film coefficient) and cools into 20 °C air everywhere else,
so the heat conducts up the body and fades along the handle and the spout:

    −∇·(k ∇T) = 0,   −k ∂T/∂n = h (T − T_ext)   with h, T_ext = 500, 95 on the base,
                                                           10, 20 elsewhere,

k = 1.5 W/m/K (stoneware), in a teapot 24 cm across its body (coordinates in decimetres:
the mesh unit is 0.1 m). Solved with P1 finite elements (scikit-fem) by the solver that
examples/hyperthermia/fem.py checks against a closed form.

Output: `teapot.hmesh`, BINARY HyperMesh (thesis appendix B): `Field "Temperature" { float } =
Linear(…)` and `Field "Part" { byte Materials } = Constant(…)` (1 pot, 2 spout, 3 handle,
4 knob), with a Materials block naming the parts.

Run by hand (not in CI), from the repository root:

    python3 -m venv /tmp/hyper
    /tmp/hyper/bin/pip install -r examples/hyperthermia/requirements.txt
    /tmp/hyper/bin/python examples/teapot/generate.py
    cargo run --release -- info examples/teapot/teapot.hmesh
"""

import math
import os
import sys

import gmsh
import numpy as np
import skfem

HERE = os.path.dirname(os.path.abspath(__file__))
# The helpers beside the generator, without leaving __pycache__ in the repository.
sys.dont_write_bytecode = True
sys.path.insert(0, os.path.join(HERE, "..", "hyperthermia"))
from fem import solve_pennes, tetrahedra  # noqa: E402
from hypermesh import write_binary, write_summary  # noqa: E402

UNIT = 0.1  # metres per mesh unit
K = 1.5  # W/m/K
PLATE = (500.0, 95.0)  # h (W/m²/K), T (°C) at the base
AIR = (10.0, 20.0)  # elsewhere
PARTS = [
    dict(id=1, name="Pot"),
    dict(id=2, name="Spout"),
    dict(id=3, name="Handle"),
    dict(id=4, name="Knob"),
]
POT, SPOUT, HANDLE, KNOB = 1, 2, 3, 4

# The pot's profile (radius, height) from the base's rim up to the lid's centre.
PROFILE = [(0.75, 0.0), (1.0, 0.15), (1.2, 0.55), (1.15, 0.95), (0.9, 1.25), (0.6, 1.38)]
TOP = 1.42


def build_geometry():
    occ = gmsh.model.occ
    # Body of revolution: the face between the z axis and the profile, turned about z.
    axis_bottom = occ.addPoint(0, 0, 0)
    axis_top = occ.addPoint(0, 0, TOP)
    profile = [occ.addPoint(r, 0, z) for r, z in PROFILE]
    lid = occ.addPoint(0.3, 0, TOP)
    curves = [
        occ.addLine(axis_bottom, profile[0]),
        occ.addSpline(profile + [lid]),
        occ.addLine(lid, axis_top),
        occ.addLine(axis_top, axis_bottom),
    ]
    face = occ.addPlaneSurface([occ.addCurveLoop(curves)])
    pot = occ.revolve([(2, face)], 0, 0, 0, 0, 0, 1, 2 * math.pi)
    pot = [t for d, t in pot if d == 3][0]

    knob = occ.addSphere(0, 0, TOP + 0.08, 0.16)
    # The spout: a cone from inside the body, rising outwards at 40°, with a short flared lip.
    lean = math.radians(40)
    spout = occ.addCone(0.8, 0, 0.35, 1.15 * math.cos(lean), 0, 1.15 * math.sin(lean), 0.3, 0.09)
    # The handle: a torus about the y axis behind the pot; its inner part is cut away by the
    # pot, the rest is a loop with a hole.
    handle = occ.addTorus(-1.15, 0, 0.72, 0.42, 0.085, zAxis=[0, 1, 0])
    inside = occ.copy([(3, pot)])
    handle_out, _ = occ.cut([(3, handle)], inside)
    inside = occ.copy([(3, pot)])
    spout_out, _ = occ.cut([(3, spout)], inside)
    inside = occ.copy([(3, pot)])
    knob_out, _ = occ.cut([(3, knob)], inside)
    # A conforming mesh across the parts: fragment them with the pot.
    inputs = [[(3, pot)], spout_out, handle_out, knob_out]
    flat = [dt for group in inputs for dt in group]
    _, children = occ.fragment(flat[:1], flat[1:])
    occ.synchronize()
    owner = {}
    index = 0
    for part, group in zip([POT, SPOUT, HANDLE, KNOB], inputs):
        for _ in group:
            for d, t in children[index]:
                owner.setdefault(t, part)
            index += 1
    for part in (POT, SPOUT, HANDLE, KNOB):
        tags = [t for t, p in owner.items() if p == part]
        gmsh.model.addPhysicalGroup(3, tags, part, PARTS[part - 1]["name"])


def main():
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", int("--verbose" in sys.argv))
    gmsh.option.setNumber("General.NumThreads", 1)
    gmsh.option.setNumber("Mesh.RandomSeed", 1)
    gmsh.model.add("teapot")
    build_geometry()
    gmsh.option.setNumber("Mesh.MeshSizeMax", 0.11)
    gmsh.option.setNumber("Mesh.MeshSizeMin", 0.03)
    gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", 12)
    gmsh.model.mesh.generate(3)
    gmsh.model.mesh.optimize("Netgen")
    points, tets, parts = tetrahedra()
    gmsh.finalize()

    mesh = skfem.MeshTet(points.T.copy(), tets.T.copy())
    base = mesh.facets_satisfying(lambda x: x[2] < 1e-6, boundaries_only=True)
    rest = np.setdiff1d(mesh.boundary_facets(), base)
    n = len(tets)
    # In mesh units x' = x/UNIT the weak form ∫k∇T·∇v dV + ∫hTv dS, divided by UNIT², reads
    # ∫(k/UNIT)∇'T·∇'v dV' + ∫hTv dS': k becomes k/UNIT, h stays.
    T = solve_pennes(
        points,
        tets,
        np.full(n, K / UNIT),
        np.zeros(n),
        np.zeros(n),
        np.zeros(len(points)),
        [(base, *PLATE), (rest, *AIR)],
        0.0,
    )
    out = os.path.join(HERE, "teapot.hmesh")
    content = (points, tets, PARTS, [("Temperature", T)], ("Part", parts))
    write_summary(os.path.join(HERE, "teapot.summary"), "teapot.hmesh", *content)
    write_binary(
        out,
        *content,
        comments=[
            "A solid teapot on a hot plate: steady heat conduction (deg C) by P1 FEM;",
            "coordinates in decimetres; written by examples/teapot/generate.py",
        ],
    )
    print(f"{len(points)} nodes, {n} tetrahedra, {os.path.getsize(out)} bytes")
    for p in PARTS:
        sel = np.unique(tets[parts == p["id"]])
        print(
            f"  {p['name']:6s} {np.count_nonzero(parts == p['id']):6d} tets, "
            f"T {T[sel].min():.2f} … {T[sel].max():.2f} °C"
        )


if __name__ == "__main__":
    main()
