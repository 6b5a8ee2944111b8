#!/usr/bin/env python3
"""Forward kinematics of `tabula ik fk --json` against pinocchio on random joints.

The robot file is loaded by tabula as given (xacro expanded by tabula itself); pinocchio
reads a URDF expanded independently (ROS's Python `xacro`), so the check covers the
expansion too. Prints the largest position and rotation differences.

    python3 scripts/fk_vs_pinocchio.py --robot ROBOT.urdf.xacro --xacro-arg hand:=true \
        --reference-urdf expanded.urdf --base fer_link0 --tip fer_hand_tcp --samples 50

Needs `pip install pin numpy`; a measuring tool, never a dependency of tabula.
"""
import argparse
import json
import subprocess

import numpy as np
import pinocchio as pin


def tabula_fk(args, q):
    cmd = [args.tabula, "ik", "fk", "--robot", args.robot, "--json", "--joints", *map(str, q)]
    for a in args.xacro_arg:
        cmd += ["--xacro-arg", a]
    if args.base:
        cmd += ["--base", args.base]
    if args.tip:
        cmd += ["--tip", args.tip]
    out = json.loads(subprocess.run(cmd, check=True, capture_output=True, text=True).stdout)
    return out


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--robot", required=True)
    p.add_argument("--xacro-arg", action="append", default=[])
    p.add_argument("--reference-urdf", required=True)
    p.add_argument("--base")
    p.add_argument("--tip")
    p.add_argument("--samples", type=int, default=50)
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--tabula", default="target/release/tabula")
    args = p.parse_args()

    model = pin.buildModelFromUrdf(args.reference_urdf)
    data = model.createData()
    # One call at zero joints gives the chain's joint names, base and tip.
    probe = subprocess.run(
        [args.tabula, "ik", "fk", "--robot", args.robot, "--json"]
        + sum((["--xacro-arg", a] for a in args.xacro_arg), [])
        + (["--base", args.base] if args.base else [])
        + (["--tip", args.tip] if args.tip else []),
        check=True, capture_output=True, text=True)
    chain = json.loads(probe.stdout)
    names, base, tip = chain["joint_names"], chain["base"], chain["tip"]
    rng = np.random.default_rng(args.seed)
    worst_pos, worst_rot = 0.0, 0.0
    for _ in range(args.samples):
        q_chain = []
        q = pin.neutral(model)
        for n in names:
            jid = model.getJointId(n)
            lo, hi = model.lowerPositionLimit[model.idx_qs[jid]], model.upperPositionLimit[model.idx_qs[jid]]
            lo, hi = max(lo, -np.pi), min(hi, np.pi)
            v = rng.uniform(lo, hi)
            q_chain.append(v)
            if model.nqs[jid] == 2:  # continuous joints: cos, sin
                q[model.idx_qs[jid]] = np.cos(v)
                q[model.idx_qs[jid] + 1] = np.sin(v)
            else:
                q[model.idx_qs[jid]] = v
        pin.framesForwardKinematics(model, data, q)
        T_base = data.oMf[model.getFrameId(base)]
        T_tip = data.oMf[model.getFrameId(tip)]
        ref = T_base.inverse() * T_tip
        ours = tabula_fk(args, q_chain)
        xyz = np.array(ours["xyz"])
        qx, qy, qz, qw = ours["quat_xyzw"]
        R = pin.Quaternion(qw, qx, qy, qz).toRotationMatrix()
        worst_pos = max(worst_pos, float(np.linalg.norm(xyz - ref.translation)))
        worst_rot = max(worst_rot, float(np.linalg.norm(pin.log3(R.T @ ref.rotation))))
    print(json.dumps({"robot": args.robot, "base": base, "tip": tip, "dof": len(names),
                      "samples": args.samples, "max_position_error_m": worst_pos,
                      "max_rotation_error_rad": worst_rot}))


if __name__ == "__main__":
    main()
