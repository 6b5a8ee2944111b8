"""A MotionBenchMaker problem planned from Python: the Panda, a MoveIt planning scene and
motion plan request (YAML), the timed trajectory out.
Usage: python plan_a_motion.py [SCENE.yaml REQUEST.yaml]"""
import sys
from pathlib import Path

import tabula

panda = Path(__file__).resolve().parents[2] / "data" / "mbm" / "panda"
scene = sys.argv[1] if len(sys.argv) > 2 else panda / "problems" / "box_panda" / "scene0001.yaml"
request = sys.argv[2] if len(sys.argv) > 2 else panda / "problems" / "box_panda" / "request0001.yaml"

robot = tabula.Robot(panda / "panda.urdf")  # its SRDF (panda.srdf) beside it: groups, named states
motion = tabula.plan_motion(robot, scene, request=request)
if not motion["solved"]:
    sys.exit(f"no motion ({motion['reason']}): {motion['message']}")
print(f"{len(motion['path'])} waypoints, {motion['path_length']:.3f} rad, "
      f"{motion['duration']:.2f} s, planned in {motion['planning_us'] / 1e3:.1f} ms")
for point in motion["points"][:: max(1, len(motion["points"]) // 5)]:
    print(f"t = {point['time']:.2f} s  q = {[round(v, 3) for v in point['positions']]}")
