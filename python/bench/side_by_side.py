#!/usr/bin/env python3
"""tabula from Python against the Python library it replaces, on the same data, in one
process (CPU time, medians): stable poses against trimesh, FK against pinocchio.

    tabula bench stable-poses --dir target/spm     # writes the test objects as OBJ
    python3 python/bench/side_by_side.py target/spm

Needs `pip install ./python trimesh scipy networkx pin`: measurement only, never a
dependency of the package."""
import os
import statistics
import sys
import time
from pathlib import Path

import numpy as np
import pinocchio as pin
import trimesh

import tabula

ROOT = Path(__file__).resolve().parents[2]


def cpu_ms(f, reps):
    times = []
    for _ in range(reps):
        t0 = time.process_time()
        f()
        times.append((time.process_time() - t0) * 1e3)
    return statistics.median(times)


def stable(folder, reps=7):
    print(f"{'object':<14} {'trimesh ms':>10} {'tabula ms':>10} {'ratio':>7}  most likely pose (angle)")
    ratios = []
    for name in sorted(os.listdir(folder)):
        if not name.endswith(".obj"):
            continue
        mesh = trimesh.load(os.path.join(folder, name), process=False, force="mesh")
        v, f = np.asarray(mesh.vertices), np.asarray(mesh.faces)

        def theirs():
            mesh._cache.clear()
            return trimesh.poses.compute_stable_poses(mesh)

        t_theirs = cpu_ms(theirs, reps)
        t_ours = cpu_ms(lambda: tabula.stable_poses(v, f), reps)
        tt, tp = theirs()
        ot, op, _ = tabula.stable_poses(v, f)
        # The mesh's downward direction in a pose; tabula's most likely pose is trimesh's
        # when trimesh gives that pose its top probability (symmetric objects tie).
        down = lambda T: T[:3, :3].T @ np.array([0.0, 0.0, -1.0])
        ours_down = down(ot[0])
        in_theirs = [p for T, p in zip(tt, tp) if down(T) @ ours_down > 0.999]
        same = bool(in_theirs) and abs(in_theirs[0] - tp.max()) <= 1e-3 * tp.max() + 1e-6
        ratios.append(t_theirs / t_ours)
        print(f"{name[:-4]:<14} {t_theirs:>10.2f} {t_ours:>10.2f} {t_theirs / t_ours:>6.1f}×  "
              f"{'same' if same else 'DIFFERENT'} (p {op[0]:.3f}; trimesh's top {tp.max():.3f})")
    print(f"median ratio {statistics.median(ratios):.1f}×")


def fk(calls=20000):
    urdf = str(ROOT / "robots" / "wam.urdf")
    model = pin.buildModelFromUrdf(urdf)
    data = model.createData()
    tip = model.getFrameId("wam_tool")
    robot = tabula.Robot("wam")
    n = len(robot.joint_names())
    rng = np.random.default_rng(1)
    qs = rng.uniform(-1.0, 1.0, (calls, n))
    # Pinocchio's q holds every joint of the URDF (the arm's 7, then the fingers').
    names = [model.names[i] for i in range(1, model.njoints)]
    assert names[:n] == robot.joint_names(), (names, robot.joint_names())
    full = np.zeros((calls, model.nq))
    full[:, :n] = qs

    def pinocchio_fk():
        for q in full:
            pin.framesForwardKinematics(model, data, q)
            data.oMf[tip].homogeneous

    def tabula_fk():
        for q in qs:
            robot.fk(q)

    pin.framesForwardKinematics(model, data, full[0])
    err = np.abs(data.oMf[tip].homogeneous - robot.fk(qs[0])).max()
    tp = cpu_ms(pinocchio_fk, 5) / calls * 1e3
    tt = cpu_ms(tabula_fk, 5) / calls * 1e3
    print(f"FK of the WAM from Python, per call: pinocchio {tp:.2f} µs, tabula {tt:.2f} µs "
          f"({tp / tt:.2f}× pinocchio's speed); largest difference {err:.1e}")


if __name__ == "__main__":
    stable(sys.argv[1] if len(sys.argv) > 1 else "target/spm")
    fk()
