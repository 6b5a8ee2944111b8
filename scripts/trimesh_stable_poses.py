#!/usr/bin/env python3
"""Side-by-side anchor for `tabula bench stable-poses`: trimesh.poses.compute_stable_poses
on the same OBJ files, CPU time (median of repetitions, one process, one thread), and
whether tabula's most likely pose is trimesh's.

    tabula bench stable-poses --dir target/spm --json > target/spm/tabula.json
    python3 scripts/trimesh_stable_poses.py target/spm target/spm/tabula.json

Needs `pip install trimesh numpy scipy networkx`. Measurement only, never a runtime
dependency of tabula.
"""
import json
import os
import statistics
import sys
import time

import numpy as np
import trimesh


def main():
    folder, ours_path = sys.argv[1], sys.argv[2]
    reps = int(sys.argv[3]) if len(sys.argv) > 3 else 11
    ours = {r["object"]: r for r in json.load(open(ours_path))}
    print(f"{'object':<14} {'trimesh ms':>10} {'tabula ms':>10} {'speed-up':>9}  same most likely pose")
    for name, row in ours.items():
        mesh = trimesh.load(os.path.join(folder, name + ".obj"), process=False, force="mesh")
        times = []
        for _ in range(reps):
            mesh._cache.clear()
            t0 = time.process_time()
            transforms, probs = trimesh.poses.compute_stable_poses(mesh)
            times.append((time.process_time() - t0) * 1e3)
        t = statistics.median(times)
        # A transform's third row is minus the support normal (trimesh's convention:
        # the face normal turned onto −z).
        normals = [-tf[2, :3] for tf in transforms]
        top = probs[0]
        ml = np.array(row["most_likely_normal"])
        # tabula's most likely normal counts as trimesh's when trimesh gives it the top
        # probability (symmetric objects tie between several poses).
        mine = [p for n, p in zip(normals, probs) if np.dot(n, ml) > 0.999]
        same = bool(mine) and abs(mine[0] - top) <= 1e-3 * max(top, 1e-9) + 1e-6
        print(f"{name:<14} {t:>10.2f} {row['cpu_ms_median']:>10.3f} {t / row['cpu_ms_median']:>8.0f}×  "
              f"{'yes' if same else 'NO'} (trimesh top {top:.3f} at {np.round(normals[0], 3)}, "
              f"tabula's pose {mine[0] if mine else float('nan'):.3f} in trimesh)")


if __name__ == "__main__":
    main()
