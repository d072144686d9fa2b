"""Small finite-element helpers shared by the example generators (hyperthermia, teapot):
Gmsh's tetrahedra as arrays, and a P1 (linear tetrahedron) solver for steady heat conduction
with a perfusion term and Robin (convective) boundaries, checked against a closed form.
"""

import math

import gmsh
import numpy as np
import skfem
from skfem.helpers import dot, grad


def tetrahedra():
    """All tetrahedra with their physical group, node indices renumbered 0..n−1."""
    tags, coords, _ = gmsh.model.mesh.getNodes()
    points = coords.reshape(-1, 3)
    tets, mats = [], []
    for d, t in gmsh.model.getEntities(3):
        material = gmsh.model.getPhysicalGroupsForEntity(3, t)[0]
        types, _, nodes = gmsh.model.mesh.getElements(3, t)
        for ty, n in zip(types, nodes):
            assert ty == 4, f"element type {ty}: expected linear tetrahedra"
            tets.append(n.reshape(-1, 4))
            mats.append(np.full(len(n) // 4, material, dtype=np.uint8))
    tets = np.concatenate(tets).astype(np.int64)
    mats = np.concatenate(mats)
    used, inverse = np.unique(tets, return_inverse=True)
    index = {int(tag): i for i, tag in enumerate(tags)}
    points = points[[index[int(u)] for u in used]]
    return points, inverse.reshape(-1, 4), mats


def solve_pennes(points, tets, k, w, q_cell, q_node, robin, t_a):
    """P1 finite elements for −∇·(k∇T) + W(T − T_a) = q_cell·q_node (Pennes 1948) with
    −k ∂T/∂n = h (T − T_ext) on each `(facets, h, T_ext)` of `robin`; the rest of the boundary
    is insulated. k, w (W = ω ρ_b c_b) and q_cell are per cell, q_node per node (interpolated
    linearly); w = 0 gives plain heat conduction."""
    mesh = skfem.MeshTet(points.T.copy(), tets.T.copy())
    basis = skfem.Basis(mesh, skfem.ElementTetP1(), intorder=3)
    b0 = basis.with_element(skfem.ElementTetP0())

    @skfem.BilinearForm
    def bilinear(u, v, p):
        return p["k"] * dot(grad(u), grad(v)) + p["w"] * u * v

    @skfem.LinearForm
    def linear(v, p):
        return (p["w"] * t_a + p["qc"] * p["qn"]) * v

    A = bilinear.assemble(basis, k=b0.interpolate(k), w=b0.interpolate(w))
    b = linear.assemble(
        basis, w=b0.interpolate(w), qc=b0.interpolate(q_cell), qn=basis.interpolate(q_node)
    )

    @skfem.BilinearForm
    def film(u, v, p):
        return p["h"] * u * v

    @skfem.LinearForm
    def outside(v, p):
        return p["h"] * p["t"] * v

    for facets, h, t_ext in robin:
        fb = skfem.FacetBasis(mesh, skfem.ElementTetP1(), facets=facets)
        A = A + film.assemble(fb, h=h)
        b = b + outside.assemble(fb, h=h, t=t_ext)
    return skfem.solve(A, b)


def check_against_sphere():
    """The solver against the closed-form Pennes solution on a homogeneous sphere:
    T = T_a + Q/W + C·sinh(mr)/r, m = √(W/k), C from the Robin condition. The error must stay
    under 2 % of the temperature span and fall about 4× when the mesh size halves."""
    R, k, W, Q, Ta, h, Tb = 0.05, 0.5, 2000.0, 2e4, 37.0, 45.0, 25.0
    m = math.sqrt(W / k)

    def exact(r):
        f = lambda r: math.sinh(m * r) / r  # noqa: E731
        df = (m * R * math.cosh(m * R) - math.sinh(m * R)) / R**2
        C = -h * (Ta + Q / W - Tb) / (k * df + h * f(R))
        r = np.maximum(r, 1e-12)
        return Ta + Q / W + C * np.sinh(m * r) / r

    errors, spans = [], []
    for size in (0.01, 0.005):
        gmsh.model.add(f"sphere{size}")
        gmsh.model.occ.addSphere(0, 0, 0, R)
        gmsh.model.occ.synchronize()
        gmsh.model.addPhysicalGroup(3, [1], 1)
        gmsh.option.setNumber("Mesh.MeshSizeMax", size)
        gmsh.option.setNumber("Mesh.MeshSizeMin", size)
        gmsh.model.mesh.generate(3)
        points, tets, _ = tetrahedra()
        n = len(tets)
        mesh = skfem.MeshTet(points.T.copy(), tets.T.copy())
        T = solve_pennes(
            points,
            tets,
            np.full(n, k),
            np.full(n, W),
            np.full(n, Q),
            np.ones(len(points)),
            [(mesh.boundary_facets(), h, Tb)],
            Ta,
        )
        ref = exact(np.linalg.norm(points, axis=1))
        err = np.abs(T - ref).max()
        errors.append(err)
        spans.append(np.ptp(ref))
        print(
            f"sphere check: h = {size * 1000:.0f} mm, {n} tets, "
            f"T {ref.min():.3f} … {ref.max():.3f} °C, max nodal error {err:.4f} K"
        )
        gmsh.model.remove()
    gmsh.option.setNumber("Mesh.MeshSizeMax", 1e22)
    gmsh.option.setNumber("Mesh.MeshSizeMin", 0)
    ratio = errors[0] / errors[1]
    print(f"sphere check: error ratio {ratio:.2f} (second order: about 4)")
    # Nodal errors of P1 on a polyhedral sphere: under 2 % of the span, and second order.
    assert errors[1] < 0.02 * spans[1] and ratio > 3, "the Pennes solver disagrees with the sphere"
