#!/usr/bin/env python3
"""tabula from Python against the Python library it replaces, on the same data, in one
process (CPU time, medians): stable poses against trimesh, FK against pinocchio, IK on
the Panda against TRAC-IK (pytracik), plane + clusters on real frames against Open3D.

    tabula bench stable-poses --dir target/spm     # writes the test objects as OBJ
    python3 python/bench/side_by_side.py target/spm

Needs `pip install ./python trimesh scipy networkx pin pytracik open3d`: measurement
only, never a dependency of the package (a section whose library is missing is
skipped)."""
import os
import statistics
import sys
import time
from pathlib import Path

import numpy as np

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
    import trimesh

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
    import pinocchio as pin

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


def thread_us(f):
    t0 = time.process_time_ns()
    out = f()
    return (time.process_time_ns() - t0) * 1e-3, out


def ik(poses=2000):
    """The Panda (MotionBenchMaker's URDF), panda_link0 → panda_link8: targets from FK of
    random joints within the limits, each solver seeded with the same random joints;
    TRAC-IK as its defaults (Speed, 5 ms, 1e-5), called with the quaternion ready so
    its time is its solve. A solution counts when FK puts the tip within 1e-4 m and
    1e-3 rad of the target."""
    import pytracik

    urdf = ROOT / "data" / "mbm" / "panda" / "panda.urdf"
    base, tip = "panda_link0", "panda_link8"
    robot = tabula.Robot(urdf)
    trac = pytracik.TRAC_IK(base, tip, urdf.read_text(), 0.005, 1e-5, pytracik.SolveType.Speed)
    limits = robot.limits(base, tip)
    # pytracik reads this URDF's joint limits as 0 (every solve then fails with -3):
    # they are set from the URDF's values, as a user would.
    pytracik.set_joint_limits(trac, list(limits[:, 0]), list(limits[:, 1]))
    rng = np.random.default_rng(1)
    targets_q = rng.uniform(limits[:, 0], limits[:, 1], (poses, len(limits)))
    seeds = rng.uniform(limits[:, 0], limits[:, 1], (poses, len(limits)))
    targets = [robot.fk(q, base, tip) for q in targets_q]

    def reached(q, T):
        if q is None:
            return False
        F = robot.fk(np.asarray(q, dtype=np.float64), base, tip)
        angle = np.arccos(np.clip((np.trace(F[:3, :3].T @ T[:3, :3]) - 1) / 2, -1, 1))
        return np.linalg.norm(F[:3, 3] - T[:3, 3]) < 1e-4 and angle < 1e-3

    rows = {"TRAC-IK (pytracik)": ([], 0), "tabula": ([], 0)}
    for T, seed in zip(targets, seeds):
        x, y, z, w = quat_xyzw(T[:3, :3])
        p = T[:3, 3]
        t, r = thread_us(lambda: pytracik.ik(trac, seed, p[0], p[1], p[2], x, y, z, w))
        ok = r[0] >= 0 and reached(r[1:], T)
        rows["TRAC-IK (pytracik)"][0].append(t)
        rows["TRAC-IK (pytracik)"] = (rows["TRAC-IK (pytracik)"][0], rows["TRAC-IK (pytracik)"][1] + ok)
        t, sols = thread_us(lambda: robot.ik(T, base, tip, seed=seed))
        ok = bool(sols) and reached(sols[0], T)
        rows["tabula"][0].append(t)
        rows["tabula"] = (rows["tabula"][0], rows["tabula"][1] + ok)
    medians = {}
    for name, (times, solved) in rows.items():
        medians[name] = statistics.median(times)
        print(f"IK Panda {name:<20} solved {solved / poses:7.2%}  median {medians[name]:8.1f} µs"
              f"  mean {statistics.fmean(times):8.1f} µs  p95 {np.percentile(times, 95):8.1f} µs")
    print(f"IK median ratio {medians['TRAC-IK (pytracik)'] / medians['tabula']:.1f}× TRAC-IK")


def plane_clusters(reps=7):
    """Real 640×480 Kinect frames (PCL's, `data/real/`) and the simulator's clutter frame:
    `tabula.perceive` on the organized grid (the whole tabletop pipeline: support plane,
    objects on it with their boxes, hulls and tops, every surface, free space) against
    Open3D's `segment_plane` (1 cm, 3 points, 1000 iterations) then `cluster_dbscan`
    (ε 2 cm, 10 points) of what is off the plane, on the same points. CPU time of the
    process (Open3D runs threads), median of `reps`."""
    import open3d as o3d

    frames = [(f.stem, tabula.read_pcd(f), None) for f in sorted((ROOT / "data" / "real").glob("*.pcd"))]
    scene = tabula.Scene(ROOT / "scenes" / "clutter.toml")
    scene.settle()
    points, world_from_camera = scene.capture()
    frames.append(("simulated clutter.toml", points, world_from_camera))
    print(f"{'frame':<30} {'Open3D ms':>9} {'tabula ms':>9} {'ratio':>7}  clusters ≥ 200 pts / objects")
    ratios = []
    for name, grid, pose in frames:
        flat = grid.reshape(-1, 3)
        finite = np.ascontiguousarray(flat[np.isfinite(flat).all(axis=1)])
        cloud = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(finite))

        def theirs():
            _, inliers = cloud.segment_plane(0.01, 3, 1000)
            rest = cloud.select_by_index(inliers, invert=True)
            return np.asarray(rest.cluster_dbscan(eps=0.02, min_points=10))

        def ours():
            return tabula.perceive(grid, world_from_camera=pose)

        t_theirs, t_ours = cpu_ms(theirs, reps), cpu_ms(ours, reps)
        labels = theirs()
        clusters = sum(1 for k in set(labels.tolist()) if k >= 0 and (labels == k).sum() >= 200)
        ratios.append(t_theirs / t_ours)
        print(f"{name:<30} {t_theirs:>9.1f} {t_ours:>9.1f} {t_theirs / t_ours:>6.1f}×  "
              f"Open3D {clusters}, tabula {len(ours()['objects'])}")
    print(f"plane + clusters median ratio {statistics.median(ratios):.1f}× Open3D")


def quat_xyzw(R):
    """A rotation matrix's unit quaternion (x, y, z, w), w ≥ 0 (Shepperd's method)."""
    t = np.trace(R)
    if t > 0:
        s = np.sqrt(t + 1.0) * 2
        q = [(R[2, 1] - R[1, 2]) / s, (R[0, 2] - R[2, 0]) / s, (R[1, 0] - R[0, 1]) / s, s / 4]
    else:
        i = int(np.argmax(np.diag(R)))
        j, k = (i + 1) % 3, (i + 2) % 3
        s = np.sqrt(1.0 + R[i, i] - R[j, j] - R[k, k]) * 2
        q = [0.0, 0.0, 0.0, (R[k, j] - R[j, k]) / s]
        q[i] = s / 4
        q[j] = (R[j, i] + R[i, j]) / s
        q[k] = (R[k, i] + R[i, k]) / s
    q = np.array(q)
    return q if q[3] >= 0 else -q


if __name__ == "__main__":
    folder = sys.argv[1] if len(sys.argv) > 1 else "target/spm"
    for section in (lambda: stable(folder), fk, ik, plane_clusters):
        try:
            section()
        except ImportError as e:
            print(f"skipped {section.__name__}: {e}")
