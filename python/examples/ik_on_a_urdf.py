"""IK on a URDF from Python: every solution for a pose the arm reaches, checked by FK.
Usage: python ik_on_a_urdf.py [ROBOT_URDF_OR_NAME]"""
import sys

import numpy as np

import tabula

robot = tabula.Robot(sys.argv[1] if len(sys.argv) > 1 else "wam")
names = robot.joint_names()
q = np.full(len(names), 0.4)
T = robot.fk(q)
print(f"{robot.name}: {len(names)} joints; tool at {np.round(T[:3, 3], 4)}")
for s in robot.ik(T, seed=np.zeros(len(names))):
    print(np.round(s, 4), "FK error", np.abs(robot.fk(s) - T).max())
