"""Closed-form IK anchors side by side with `tabula ik bench` (issue 36): EAIK and IK-Geo
from PyPI on a URDF's 6R arm (UR-type or spherical wrist), 10,000 FK poses of uniform random joints, every pose
solved for all solutions. Times are per pose: EAIK's batched solve (its C++ loop, no
Python per call) and IK-Geo's per-call (Python call included, as it has no batch).

    pip install eaik ik-geo numpy
    python3 scripts/ik_anchors.py ROBOT.urdf [--poses 10000] [--seed 1]
"""

import argparse
import time

import numpy as np
from eaik.IK_URDF import UrdfRobot
from ik_geo import Robot


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("urdf")
    ap.add_argument("--poses", type=int, default=10000)
    ap.add_argument("--seed", type=int, default=1)
    args = ap.parse_args()
    eaik = UrdfRobot(args.urdf)
    print("EAIK family:", eaik.getKinematicFamily())
    rng = np.random.default_rng(args.seed)
    qs = rng.uniform(-np.pi, np.pi, size=(args.poses, 6))
    poses = [eaik.fwdKin(q) for q in qs]

    t0 = time.perf_counter()
    solutions = eaik.IK_batched(poses, num_worker_threads=1)
    batch_us = (time.perf_counter() - t0) / len(poses) * 1e6
    counts = [len(s.Q) for s in solutions]
    per_call = []
    for pose in poses[:2000]:
        t0 = time.perf_counter_ns()
        eaik.IK(pose)
        per_call.append((time.perf_counter_ns() - t0) / 1e3)
    errors = [
        max((np.abs(eaik.fwdKin(q) - pose).max() for q in s.Q), default=np.inf)
        for s, pose in zip(solutions[:2000], poses)
    ]
    solved = np.mean([e < 1e-6 for e in errors]) * 100
    print(
        f"EAIK batched (1 thread): {batch_us:.2f} µs/pose mean; per call median "
        f"{np.median(per_call):.2f} µs; solutions {np.mean(counts):.2f}; "
        f"all solutions within 1e-6 on {solved:.2f} % of the first 2,000"
    )

    # IK-Geo's constructor for EAIK's family (the two 6R families tabula solves).
    family = str(eaik.getKinematicFamily())
    if "THREE_INNER_PARALLEL" in family:
        make = Robot.three_parallel_two_intersecting
    elif "SPHERICAL" in family and "PARALLEL" in family:
        make = Robot.spherical_two_parallel
    elif "SPHERICAL" in family and "INTERSECTING" in family:
        make = Robot.spherical_two_intersecting
    else:
        make = Robot.spherical
    geo = make(eaik.getRemodeled_H().T.tolist(), eaik.getRemodeled_P().T.tolist())
    # IK-Geo takes EAIK's remodelled axes (points at the intersections) and reads rotation
    # matrices as lists of columns (EAIK's transposed).
    times, found = [], []
    for pose in poses:
        r, p = pose[:3, :3].T.tolist(), pose[:3, 3].tolist()
        t0 = time.perf_counter_ns()
        sols = geo.get_ik(r, p)
        times.append((time.perf_counter_ns() - t0) / 1e3)
        found.append(sols)
    exact = np.mean(
        [
            any(np.abs(eaik.fwdKin(np.array(q)) - pose).max() < 1e-6 for q, _ in sols)
            for sols, pose in zip(found[:2000], poses)
        ]
    ) * 100
    print(
        f"IK-Geo per call: median {np.median(times):.2f} µs, p95 {np.percentile(times, 95):.2f} µs; "
        f"solutions {np.mean([len(s) for s in found]):.2f}; a solution within 1e-6 on {exact:.2f} % "
        "of the first 2,000"
    )

if __name__ == "__main__":
    main()
