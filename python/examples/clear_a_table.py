"""A cluttered table cleared into the bin from Python, judged by the simulator's physics.
Usage: python clear_a_table.py [SCENE_TOML]   (from the repository: scenes/clutter.toml)"""
import sys

import tabula

scene = tabula.Scene(sys.argv[1] if len(sys.argv) > 1 else "scenes/clutter.toml")
out = scene.clear()
v = out["verdict"]
print(f"{v['in_bin']} of {v['objects']} objects in the bin in {out['report']['actions']} actions; "
      f"decision median {out['report']['decision_ms']['median']:.1f} ms")
