#!/usr/bin/env python3
"""How far MuJoCo rolls a lying can set rolling without slipping, beside tabula's
rolling resistance (`cargo test --release -p tabula-sim --lib rolling_tests --
--nocapture`). The can: radius 2.5 cm, 9 cm long, 400 kg/m³, on a plane, friction 0.8,
rolling friction c_rr · r (MuJoCo's rolling friction is a torque ≤ μ_roll · N, the same
Coulomb model). Usage: python3 scripts/mujoco_roll.py [c_rr]
"""
import sys

import mujoco
import numpy as np

C_RR = float(sys.argv[1]) if len(sys.argv) > 1 else 0.01
R, HALF_LENGTH = 0.025, 0.045

XML = f"""
<mujoco>
  <option timestep="0.001" cone="elliptic" impratio="10"/>
  <worldbody>
    <geom type="plane" size="5 5 0.1" friction="0.8 0.005 {C_RR * R}" condim="6"/>
    <body name="can" pos="0 0 {R}" euler="90 0 0">
      <freejoint/>
      <geom type="cylinder" size="{R} {HALF_LENGTH}" density="400"
            friction="0.8 0.005 {C_RR * R}" condim="6"/>
    </body>
  </worldbody>
</mujoco>
"""


def roll(speed, seconds=10.0):
    model = mujoco.MjModel.from_xml_string(XML)
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    for _ in range(int(0.5 / model.opt.timestep)):
        mujoco.mj_step(model, data)
    start = data.qpos[:3].copy()
    data.qvel[:] = 0.0
    data.qvel[0] = speed
    data.qvel[4] = speed / R  # about world y: rolling along +x
    for _ in range(int(seconds / model.opt.timestep)):
        mujoco.mj_step(model, data)
    return data.qpos[0] - start[0], float(np.linalg.norm(data.qvel[:3]))


for v in [0.03, 0.05, 0.1, 0.2, 0.4]:
    d, end = roll(v)
    coulomb = v * v / (2.0 * 2.0 / 3.0 * C_RR * 9.81)
    print(f"from {v} m/s: MuJoCo rolled {d:.4f} m, end speed {end:.4f} (Coulomb {coulomb:.4f} m)")
