#!/usr/bin/env python3
"""The `inclusion` example: a genuine Gmsh geometry with physical groups and a finite-element
solution, saved as .vtu — what a user of VoRANG typically has in hand.

A 2x1x1 block of matrix material (physical volume 1, "matrix") holding a spherical inclusion
(physical volume 2, "inclusion") that is heated uniformly; the block's faces are held at 0.
scikit-fem solves the steady heat equation -div(k grad T) = q with k = 1 in the matrix and
k = 10 in the inclusion (P1 elements), and meshio writes the mesh with the point array
`temperature` and the cell array `material` (the physical group) as binary, zlib-compressed
VTK XML.

    python3 -m venv /tmp/fmtvenv
    /tmp/fmtvenv/bin/pip install meshio==5.3.5 numpy==1.26.4 gmsh==4.13.1 scikit-fem==10.0.2
    /tmp/fmtvenv/bin/python examples/inclusion/generate.py
"""

import os

import gmsh
import meshio
import numpy as np
import skfem
from skfem.helpers import dot, grad

HERE = os.path.dirname(os.path.abspath(__file__))

gmsh.initialize()
gmsh.option.setNumber("General.Terminal", 0)
gmsh.model.add("inclusion")
box = gmsh.model.occ.addBox(0, 0, 0, 2, 1, 1)
ball = gmsh.model.occ.addSphere(0.8, 0.5, 0.5, 0.3)
out, _ = gmsh.model.occ.fragment([(3, box)], [(3, ball)])
gmsh.model.occ.synchronize()
vols = [t for d, t in gmsh.model.getEntities(3)]
# The fragment with the smallest volume is the sphere.
masses = {t: gmsh.model.occ.getMass(3, t) for t in vols}
inner = min(masses, key=masses.get)
outer = [t for t in vols if t != inner]
gmsh.model.addPhysicalGroup(3, outer, 1, "matrix")
gmsh.model.addPhysicalGroup(3, [inner], 2, "inclusion")
gmsh.option.setNumber("Mesh.MeshSizeMax", 0.16)
gmsh.option.setNumber("Mesh.MeshSizeMin", 0.08)
gmsh.model.mesh.generate(3)
msh_path = os.path.join(HERE, "inclusion.msh")
gmsh.option.setNumber("Mesh.Binary", 1)
gmsh.write(msh_path)
gmsh.finalize()

m = meshio.read(msh_path)
os.remove(msh_path)
tets = m.cells_dict["tetra"]
phys = m.cell_data_dict["gmsh:physical"]["tetra"].astype(np.int32)
pts = m.points

mesh = skfem.MeshTet(pts.T.copy(), tets.T.copy())
basis = skfem.Basis(mesh, skfem.ElementTetP1())
kappa = np.where(phys == 2, 10.0, 1.0)
source = np.where(phys == 2, 50.0, 0.0)
b0 = basis.with_element(skfem.ElementTetP0())
kq = b0.interpolate(kappa)
sq = b0.interpolate(source)


@skfem.BilinearForm
def conduction(u, v, w):
    return w["kappa"] * dot(grad(u), grad(v))


@skfem.LinearForm
def heat(v, w):
    return w["q"] * v


A = conduction.assemble(basis, kappa=kq)
b = heat.assemble(basis, q=sq)
T = skfem.solve(*skfem.condense(A, b, D=basis.get_dofs()))

meshio.Mesh(
    pts, [("tetra", tets)],
    point_data={"temperature": T},
    cell_data={"material": [phys]},
).write(os.path.join(HERE, "inclusion.vtu"), compression="zlib")
print(f"{len(pts)} nodes, {len(tets)} tetrahedra, T in [{T.min():.3f}, {T.max():.3f}]")
