#!/usr/bin/env python3
"""The hyperthermia data set (thesis 7.3, appendix D.2: HyperRed, HyperGreen, HyperKombi).

The thesis showed a simulated temperature over a patient's pelvis during regional
hyperthermia: a tetrahedral model of the body region, finer at the tissue interfaces, with the
hottest spot in the tumour (the prostate) and secondary maxima in the groin. Its data are
lost; this script builds a genuine equivalent:

* Geometry (Gmsh, OpenCASCADE; metres): a 34 × 23 cm elliptic cylinder of trunk, 28 cm long
  (z from the thighs up to the lower spine), a 1.5 cm subcutaneous fat layer, a muscle core
  holding one bone body — a pelvic ring with the sacrum/lower spine behind and both femoral
  heads and shafts below — and an ellipsoidal tumour (about 6 × 5 × 5.6 cm) inside the ring.
  Physical groups are the materials; the mesh size grows from 6 mm at the bone and tumour
  surfaces to 22 mm in the bulk and stays under 9 mm in the fat layer (86100 tetrahedra). A
  run with all sizes times 0.7 (243167 tetrahedra) moved the tissue temperature ranges by at
  most 0.2 K (the coldest skin node), the groin maxima by 0.2 K.
* Temperature: the steady Pennes bioheat equation (Pennes 1948)

      −∇·(k ∇T) + ω ρ_b c_b (T − T_a) = Q        in the body,
      −k ∂T/∂n = h (T − T_bolus)                 on the skin (a cooling water bolus),
      ∂T/∂n = 0                                  on the two cut planes of the trunk,

  solved with linear (P1) finite elements (scikit-fem). The power Q = ½ σ |E|² is what the
  applicator's field deposits: |E|² is a Gaussian focus on the tumour plus two narrow
  Gaussian spots in the groin (the unwanted hot spots the thesis points out), σ the tissue's
  conductivity, so fat and bone absorb little. The field strength is scaled so that the
  tumour's hottest point is 43.5 °C, a typical therapeutic temperature.
* Tissue constants: k, ρ, c and perfusion from the IT'IS tissue database (Hasgall et al.,
  IT'IS Database for thermal and electromagnetic parameters of biological tissues, v4.1,
  2022): muscle k = 0.49 W/m/K, fat 0.21, cortical bone 0.32; perfusion muscle 37, fat 33,
  bone 10 ml/min/kg, muscle doubled for the heat-induced vasodilation seen under hyperthermia
  (Song 1984, Cancer Res. 44: 4721s); the tumour is given muscle-like constants with an
  assumed low perfusion of 12 ml/min/kg (a third of muscle's: tumours are often poorly
  perfused, ibid.). σ and ε at 100 MHz from Gabriel, Lau & Gabriel 1996 (tumour: muscle
  + 10 %, assumed). Blood ρ_b c_b = 1050 kg/m³ × 3617 J/kg/K, T_a = 37 °C; the bolus water at
  25 °C with h = 45 W/m²/K, assumed values of the order used in hyperthermia planning
  (e.g. Lang, Erdmann & Seebass 1999, IEEE Trans. Biomed. Eng. 46: 1129).

Output: `hyperthermia.hmesh`, BINARY HyperMesh (thesis appendix B) with a Materials block (id, name,
k, rho, c, perfusion, sigma, eps), `Field "Temperature" { float } = Linear(…)` in °C and
`Field "Material" { byte Materials } = Constant(…)` with 1 muscle, 2 fat, 3 bone, 4 tumour.

`--check` first solves a homogeneous sphere with the same code and compares it with the
closed-form radial Pennes solution (T = T_a + Q/W + C·sinh(mr)/r, m = √(W/k), C from the
Robin condition) at two mesh sizes: the error must stay under 2 % of the temperature span
and fall about 4× when h halves.

Run by hand (not in CI), from the repository root:

    python3 -m venv /tmp/hyper
    /tmp/hyper/bin/pip install -r examples/hyperthermia/requirements.txt
    /tmp/hyper/bin/python examples/hyperthermia/generate.py --check
    cargo run --release -- info examples/hyperthermia/hyperthermia.hmesh
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
sys.path.insert(0, HERE)
from fem import check_against_sphere, solve_pennes, tetrahedra  # noqa: E402
from hypermesh import write_binary, write_summary  # noqa: E402

RHO_C_BLOOD = 1050.0 * 3617.0  # J/m³/K
T_ARTERIAL = 37.0  # °C
T_BOLUS = 25.0  # °C
H_BOLUS = 45.0  # W/m²/K
T_TUMOUR_MAX = 43.5  # °C


def perfusion(ml_min_kg, rho):
    """Volumetric perfusion rate ω (1/s) from ml blood per minute per kg tissue."""
    return ml_min_kg * 1e-6 / 60.0 * rho


MATERIALS = [
    dict(
        id=1,
        name="Muscle",
        k=0.49,
        rho=1090,
        c=3421,
        perfusion=round(2 * perfusion(37, 1090), 6),
        sigma=0.71,
        eps=65.97,
    ),
    dict(
        id=2,
        name="Fat",
        k=0.21,
        rho=911,
        c=2348,
        perfusion=round(perfusion(33, 911), 6),
        sigma=0.068,
        eps=12.7,
    ),
    dict(
        id=3,
        name="Bone",
        k=0.32,
        rho=1908,
        c=1313,
        perfusion=round(perfusion(10, 1908), 6),
        sigma=0.064,
        eps=15.3,
    ),
    dict(
        id=4,
        name="Tumour",
        k=0.51,
        rho=1090,
        c=3421,
        perfusion=round(perfusion(12, 1090), 6),
        sigma=0.78,
        eps=70.0,
    ),
]
MUSCLE, FAT, BONE, TUMOUR = 1, 2, 3, 4

# Geometry (metres).
A, B, L = 0.17, 0.115, 0.28  # trunk semi-axes (x left-right, y back-front) and length (z)
FAT_LAYER = 0.015
TUMOUR_C = np.array([0.0, 0.0, 0.10])
TUMOUR_R = (0.03, 0.025, 0.028)
RING_C = (0.0, -0.005, 0.15)
GROIN = [np.array([s * 0.075, 0.085, 0.06]) for s in (-1, 1)]


def build_geometry():
    occ = gmsh.model.occ
    body = occ.extrude([(2, occ.addDisk(0, 0, 0, A, B))], 0, 0, L)
    body = [t for d, t in body if d == 3][0]
    core = occ.extrude([(2, occ.addDisk(0, 0, 0, A - FAT_LAYER, B - FAT_LAYER))], 0, 0, L)
    core = [t for d, t in core if d == 3][0]

    # Bone: a pelvic ring (a torus, tilted so that the pubis lies lower than the sacrum), the
    # sacrum and lower spine behind it, the femoral heads under its sides and the femoral
    # shafts down to the thighs' cut. (A torus stays a torus when rotated, while scaling it
    # makes a spline surface that Gmsh fails to mesh after the union; its seam is turned to
    # the front, away from the femoral heads, and the parts are fused one by one: OpenCASCADE
    # crashes on this union done at once or with a seam inside a femoral head.)
    ring = occ.addTorus(*RING_C, 0.07, 0.016)
    occ.rotate([(3, ring)], *RING_C, 0, 0, 1, math.pi / 2)
    occ.rotate([(3, ring)], *RING_C, 1, 0, 0, math.radians(-25))
    spine = occ.addCylinder(0, -0.07, 0.14, 0, 0, L - 0.14, 0.022)
    bone, _ = occ.fuse([(3, ring)], [(3, spine)])
    for s in (-1, 1):
        head = (s * 0.075, 0.0, 0.128)
        femur, _ = occ.fuse(
            [(3, occ.addSphere(*head, 0.026))],
            [(3, occ.addCylinder(*head, s * 0.03, 0.008, -head[2] - 0.05, 0.016))],
        )
        bone, _ = occ.fuse(bone, femur)
    # The femoral shafts run on below the trunk's lower cut: keep what lies inside the core.
    bone, _ = occ.intersect(bone, occ.copy([(3, core)]))
    bone = [t for d, t in bone]

    tumour = occ.addSphere(*TUMOUR_C, 1.0)
    occ.dilate([(3, tumour)], *TUMOUR_C, *TUMOUR_R)

    # Cut the pieces so that they share faces: the mesh is conforming across materials.
    inputs = [[body], [core], bone, [tumour]]
    flat = [(3, t) for group in inputs for t in group]
    _, children = occ.fragment(flat[:1], flat[1:])
    occ.synchronize()
    owner = {}
    index = 0
    # Later inputs win: tumour over bone over core (muscle) over body (fat).
    for material, group in zip([FAT, MUSCLE, BONE, TUMOUR], inputs):
        for _ in group:
            for d, t in children[index]:
                owner[t] = material
            index += 1
    for material in (MUSCLE, FAT, BONE, TUMOUR):
        tags = [t for t, m in owner.items() if m == material]
        name = MATERIALS[material - 1]["name"]
        gmsh.model.addPhysicalGroup(3, tags, material, name)
    return owner


def mesh_size_field():
    """The thesis's 'finer at the interfaces between tissue types': 6 mm at the bone and
    tumour surfaces, growing to 22 mm 5 cm away from them, and at most 9 mm in the fat layer
    (the steepest temperature gradient, from the cooled skin to the muscle)."""
    inner = set()
    for d, t in gmsh.model.getEntities(3):
        if gmsh.model.getPhysicalGroupsForEntity(3, t)[0] in (BONE, TUMOUR):
            inner.update(abs(s) for _, s in gmsh.model.getBoundary([(3, t)]))
    field = gmsh.model.mesh.field
    dist = field.add("Distance")
    field.setNumbers(dist, "SurfacesList", sorted(inner))
    field.setNumber(dist, "Sampling", 40)
    thr = field.add("Threshold")
    field.setNumber(thr, "InField", dist)
    field.setNumber(thr, "SizeMin", 0.006)
    field.setNumber(thr, "SizeMax", 0.022)
    field.setNumber(thr, "DistMin", 0.002)
    field.setNumber(thr, "DistMax", 0.05)
    fat = [
        t
        for d, t in gmsh.model.getEntities(3)
        if gmsh.model.getPhysicalGroupsForEntity(3, t)[0] == FAT
    ]
    layer = field.add("Constant")
    field.setNumbers(layer, "VolumesList", fat)
    field.setNumber(layer, "VIn", 0.009)
    field.setNumber(layer, "VOut", 1.0)
    field.setNumber(layer, "IncludeBoundary", 1)
    both = field.add("Min")
    field.setNumbers(both, "FieldsList", [thr, layer])
    field.setAsBackgroundMesh(both)
    gmsh.option.setNumber("Mesh.MeshSizeExtendFromBoundary", 0)
    gmsh.option.setNumber("Mesh.MeshSizeFromPoints", 0)
    gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", 0)


def main():
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", int("--verbose" in sys.argv))
    gmsh.option.setNumber("General.NumThreads", 1)
    gmsh.option.setNumber("Mesh.RandomSeed", 1)
    if "--check" in sys.argv:
        check_against_sphere()

    gmsh.model.add("pelvis")
    build_geometry()
    mesh_size_field()
    gmsh.model.mesh.generate(3)
    gmsh.model.mesh.optimize("Netgen")
    points, tets, mats = tetrahedra()
    gmsh.finalize()

    table = {m["id"]: m for m in MATERIALS}
    k = np.array([table[m]["k"] for m in mats])
    w = np.array([table[m]["perfusion"] for m in mats]) * RHO_C_BLOOD
    sigma = np.array([table[m]["sigma"] for m in mats])

    # |E|² of the applicator: a broad focus on the tumour and two narrow, stronger spots in the
    # groin, which the bolus and the perfusion cool down to about 40 °C.
    def gauss(c, width):
        return np.exp(-np.sum((points - c) ** 2, axis=1) / width**2)

    e2 = gauss(TUMOUR_C, 0.05) + sum(2.5 * gauss(g, 0.035) for g in GROIN)

    mesh = skfem.MeshTet(points.T.copy(), tets.T.copy())
    skin = mesh.facets_satisfying(lambda x: (x[2] > 1e-6) & (x[2] < L - 1e-6), boundaries_only=True)
    # The problem is linear in the power: solve without heating and for a unit ½σ|E|², then
    # scale the field so that the tumour's hottest node reaches T_TUMOUR_MAX.
    rest = solve_pennes(points, tets, k, w, 0 * sigma, e2, [(skin, H_BOLUS, T_BOLUS)], T_ARTERIAL)
    unit = solve_pennes(points, tets, k, w, 0.5 * sigma, e2, [(skin, H_BOLUS, 0.0)], 0.0)
    tumour_nodes = np.unique(tets[mats == TUMOUR])
    i = tumour_nodes[np.argmax(unit[tumour_nodes])]
    e0_sq = (T_TUMOUR_MAX - rest[i]) / unit[i]
    T = rest + e0_sq * unit

    out = os.path.join(HERE, "hyperthermia.hmesh")
    content = (points, tets, MATERIALS, [("Temperature", T)], ("Material", mats))
    write_summary(os.path.join(HERE, "hyperthermia.summary"), "hyperthermia.hmesh", *content)
    write_binary(
        out,
        *content,
        comments=[
            "Regional hyperthermia of a pelvis-like body region: steady Pennes bioheat",
            "temperature (deg C) by P1 FEM; written by examples/hyperthermia/generate.py",
            f"|E0| = {math.sqrt(e0_sq):.1f} V/m at the focus; "
            f"bolus {T_BOLUS} C, h = {H_BOLUS} W/m2/K",
        ],
    )
    print(f"{len(points)} nodes, {len(tets)} tetrahedra, {os.path.getsize(out)} bytes")
    for m in MATERIALS:
        sel = np.unique(tets[mats == m["id"]])
        print(
            f"  {m['name']:7s} {np.count_nonzero(mats == m['id']):6d} tets, "
            f"T {T[sel].min():.2f} … {T[sel].max():.2f} °C"
        )
    sar = 0.5 * e0_sq * sigma * e2[tets].mean(axis=1) / np.array([table[m]["rho"] for m in mats])
    print(f"  peak SAR {sar.max():.0f} W/kg, tumour mean SAR {sar[mats == TUMOUR].mean():.0f} W/kg")
    print(f"  T range {T.min():.2f} … {T.max():.2f} °C")


if __name__ == "__main__":
    main()
