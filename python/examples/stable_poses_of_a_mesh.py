"""How a mesh rests on a table: pass an OBJ/STL/PLY path (read with trimesh if it is
installed), or get a 10 × 6 × 4 cm box. Usage: python stable_poses_of_a_mesh.py [MESH]"""
import sys

import numpy as np

import tabula

if len(sys.argv) > 1:
    import trimesh

    mesh = trimesh.load(sys.argv[1], force="mesh")
    v, f = np.asarray(mesh.vertices), np.asarray(mesh.faces)
else:
    x, y, z = 0.05, 0.03, 0.02
    v = np.array([[i * x, j * y, k * z] for i in (-1, 1) for j in (-1, 1) for k in (-1, 1)])
    f = np.array([[0, 2, 1], [1, 2, 3], [4, 5, 6], [5, 7, 6], [0, 1, 4], [1, 5, 4],
                  [2, 6, 3], [3, 6, 7], [0, 4, 2], [2, 4, 6], [1, 3, 5], [3, 7, 5]])
transforms, probabilities, margins = tabula.stable_poses(v, f)
for T, p, m in zip(transforms, probabilities, margins):
    up = T[:3, :3].T @ [0, 0, 1]
    print(f"p = {p:.3f}, margin {m * 1000:.1f} mm, the mesh's {np.round(up, 3)} points up")
