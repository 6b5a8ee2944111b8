#!/usr/bin/env python3
"""Does the object tabula placed rest in another physics engine too? (issue 32)

Usage:
    tabula bench place --suite complex-grips --trials 100 --json \
        --save-failures DIR > rows.json
    python3 scripts/mujoco_rest.py rows.json DIR/meshes [--seconds 2]

For every placed trial (`success`), MuJoCo (pip `mujoco`, not a dependency of tabula)
gets the table as a box and the object as the scene gives it (box, cylinder, or the
OBJ mesh — MuJoCo collides with a mesh's convex hull, its mass is the mesh's own
volume's), at the pose tabula's physics
left it in, with the scene's density (500 kg/m³) and friction 0.8; then simulates
`--seconds` and reports how far the object slid and turned. It agrees that the object
rests when it moved < 1 cm and turned < 5° (the placing judge's limits).

`--tilt DEG` turns every end pose by DEG about a horizontal axis first (lifted 2 cm so
it starts clear of the table; the fall is then not counted): a check that can tell a
resting object from one that is not — it must topple back.
"""
import argparse
import json
import math
import sys

import numpy as np

try:
    import mujoco
except ImportError:  # pragma: no cover
    sys.exit("needs MuJoCo: pip install mujoco")


def quat_wxyz(q):
    x, y, z, w = q
    return f"{w} {x} {y} {z}"


def shape_xml(shape, mesh_dir):
    """The object's geom and the assets it needs."""
    if "box" in shape:
        sx, sy, sz = shape["box"]
        return f'<geom type="box" size="{sx / 2} {sy / 2} {sz / 2}"/>', ""
    if "cylinder" in shape:
        c = shape["cylinder"]
        return f'<geom type="cylinder" size="{c["radius"]} {c["height"] / 2}"/>', ""
    if "mesh" in shape:
        m = shape["mesh"]
        path = m["path"]
        if not path.startswith("/"):
            path = f"{mesh_dir}/{path.split('/')[-1]}"
        scale = " ".join(str(s) for s in m.get("scale", [1, 1, 1]))
        # Mass and inertia from the mesh's own volume (`exact`), not its convex
        # hull's: a door handle's hull fills the space between lever and rose and puts
        # the centre of mass centimetres off. Contact still uses the hull, which is
        # exact for resting on a flat table (only the hull touches a plane).
        asset = f'<mesh name="held" file="{path}" scale="{scale}" inertia="exact"/>'
        return '<geom type="mesh" mesh="held"/>', asset
    raise ValueError(f"shape not checked: {shape}")


def tilted(pose, deg):
    """`pose` turned by `deg` about the world x axis, 2 cm higher."""
    x, y, z, qx, qy, qz, qw = pose
    h = math.radians(deg) / 2
    a = np.array([math.cos(h), math.sin(h), 0.0, 0.0])  # w x y z
    b = np.array([qw, qx, qy, qz])
    w = a[0] * b[0] - a[1:] @ b[1:]
    v = a[0] * b[1:] + b[0] * a[1:] + np.cross(a[1:], b[1:])
    return [x, y, z + 0.02, v[0], v[1], v[2], w]


def model_of(rest, mesh_dir):
    geom, asset = shape_xml(rest["shape"], mesh_dir)
    cx, cy = rest["table_center"]
    sx, sy, sz = rest["table_size"]
    yaw = rest["table_yaw"]
    p = rest["final_pose"]
    xml = f"""
<mujoco>
  <compiler angle="radian"/>
  <option timestep="0.001"/>
  <default><geom friction="0.8 0.005 0.0001" density="500"/></default>
  <asset>{asset}</asset>
  <worldbody>
    <geom type="plane" size="10 10 0.1"/>
    <geom type="box" pos="{cx} {cy} {sz / 2}" euler="0 0 {yaw}"
          size="{sx / 2} {sy / 2} {sz / 2}"/>
    <body name="held" pos="{p[0]} {p[1]} {p[2]}" quat="{quat_wxyz(p[3:])}">
      <freejoint/>
      {geom}
    </body>
  </worldbody>
</mujoco>"""
    return mujoco.MjModel.from_xml_string(xml)


def lowest_z(model, data):
    """Lowest point of the object's geom in the world (its mesh's vertices)."""
    g = model.body_geomadr[model.body("held").id]
    if model.geom_type[g] == mujoco.mjtGeom.mjGEOM_MESH:
        m = model.geom_dataid[g]
        a, n = model.mesh_vertadr[m], model.mesh_vertnum[m]
        v = model.mesh_vert[a : a + n]
        w = v @ data.geom_xmat[g].reshape(3, 3).T + data.geom_xpos[g]
        return w[:, 2].min()
    return None


def angle_deg(q0, q1):
    d = abs(float(np.dot(q0, q1)))
    return math.degrees(2 * math.acos(min(1.0, d)))


def check(row, mesh_dir, seconds, tilt):
    rest = dict(row["rest"])
    if tilt:
        rest["final_pose"] = tilted(rest["final_pose"], tilt)
    model = model_of(rest, mesh_dir)
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    body = model.body("held").id
    start_pos = data.xpos[body].copy()
    start_quat = data.xquat[body].copy()
    gap = lowest_z(model, data)
    gap = None if gap is None else gap - rest["table_size"][2]
    for _ in range(int(seconds / model.opt.timestep)):
        mujoco.mj_step(model, data)
    moved = float(np.linalg.norm((data.xpos[body] - start_pos)[:2]))
    fell = float(start_pos[2] - data.xpos[body][2])
    turned = angle_deg(start_quat, data.xquat[body])
    return moved, fell, turned, gap


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("rows")
    ap.add_argument("mesh_dir")
    ap.add_argument("--seconds", type=float, default=2.0)
    ap.add_argument("--tilt", type=float, default=0.0)
    a = ap.parse_args()
    rows = json.load(open(a.rows))
    placed = [r for r in rows if r["success"] and r.get("rest")]
    agree = 0
    for r in placed:
        moved, fell, turned, gap = check(r, a.mesh_dir, a.seconds, a.tilt)
        ok = moved < 0.01 and (a.tilt or fell < 0.01) and turned < 5.0
        agree += ok
        gap_s = "" if gap is None else f" start gap {gap * 1e3:+.1f} mm"
        print(
            f"seed {r['seed']:4} {r['object']:14} moved {moved * 1e3:6.1f} mm "
            f"fell {fell * 1e3:6.1f} mm turned {turned:5.1f}°{gap_s}"
            f"  {'rests' if ok else 'DOES NOT REST'}"
        )
    print(f"MuJoCo {mujoco.__version__}: {agree} of {len(placed)} placed objects rest")


if __name__ == "__main__":
    main()
