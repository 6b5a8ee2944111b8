#!/usr/bin/env bash
# Loads published robot descriptions from their own repositories and checks them:
# cold-load wall time of `tabula ik info`, and forward kinematics against pinocchio on
# a URDF expanded independently by ROS's Python xacro (scripts/fk_vs_pinocchio.py).
#
#   scripts/real_robots.sh DIR
#
# DIR holds clones of: frankaemika/franka_description, UniversalRobots/
# Universal_Robots_ROS2_Description, Kinovarobotics/ros2_kortex, ZebraDevs/fetch_ros,
# PR2/pr2_common, moveit/moveit_resources, ICube-Robotics/iiwa_ros2.
# Needs `pip install pin xacro` (measuring tools, not dependencies of tabula). Python
# xacro finds packages through ament_index_python, which is not on PyPI: a 10-line
# stand-in is written to a temporary folder and the packages are linked into a fake
# AMENT_PREFIX_PATH.
set -euo pipefail
dir=$(cd "${1:?folder of robot repositories}" && pwd)
cd "$(dirname "$0")/.."
T=target/release/tabula
work=$(mktemp -d)
mkdir -p "$work/shim/ament_index_python" "$work/ament/share/ament_index/resource_index/packages"
touch "$work/shim/ament_index_python/__init__.py"
cat >"$work/shim/ament_index_python/packages.py" <<'EOF'
import os
class PackageNotFoundError(KeyError):
    pass
def get_package_share_directory(name, print_warning=True):
    p = os.path.join(os.environ["AMENT_PREFIX_PATH"], "share", name)
    if not os.path.isdir(p):
        raise PackageNotFoundError(name)
    return p
EOF
for p in franka_description:franka_description ur_description:Universal_Robots_ROS2_Description \
         kortex_description:ros2_kortex/kortex_description fetch_description:fetch_ros/fetch_description \
         pr2_description:pr2_common/pr2_description iiwa_description:iiwa_ros2/iiwa_description; do
  ln -sfn "$dir/${p#*:}" "$work/ament/share/${p%%:*}"
  touch "$work/ament/share/ament_index/resource_index/packages/${p%%:*}"
done
# name | file | xacro args | base | tip (empty: tabula's default)
while IFS='|' read -r name file args base tip; do
  xargs_tabula=(); for a in $args; do xargs_tabula+=(--xacro-arg "$a"); done
  ref="$work/$name.urdf"
  if [[ $file == *.xacro ]]; then
    PYTHONPATH="$work/shim" AMENT_PREFIX_PATH="$work/ament" xacro "$dir/$file" $args >"$ref"
  else
    cp "$dir/$file" "$ref"
  fi
  start=$(date +%s.%N)
  $T ik info --robot "$dir/$file" "${xargs_tabula[@]}" >/dev/null 2>&1
  wall=$(echo "$(date +%s.%N) - $start" | bc)
  fk=$(python3 scripts/fk_vs_pinocchio.py --robot "$dir/$file" "${xargs_tabula[@]}" \
        --reference-urdf "$ref" --base "$base" ${tip:+--tip "$tip"} --samples 50)
  echo "$name | load ${wall}s | $fk"
done <<'ROBOTS'
panda+hand|franka_description/robots/fer/fer.urdf.xacro|hand:=true|fer_link0|
ur5e|Universal_Robots_ROS2_Description/urdf/ur.urdf.xacro|ur_type:=ur5e name:=ur|base_link|
ur5|Universal_Robots_ROS2_Description/urdf/ur.urdf.xacro|ur_type:=ur5 name:=ur|base_link|
gen3|ros2_kortex/kortex_description/robots/gen3.xacro|dof:=7|base_link|
iiwa14|iiwa_ros2/iiwa_description/config/iiwa.config.xacro||iiwa_base|tool0
fetch|fetch_ros/fetch_description/robots/fetch.urdf||base_link|gripper_link
pr2|pr2_common/pr2_description/robots/pr2.urdf.xacro||torso_lift_link|r_gripper_tool_frame
panda (moveit_resources)|moveit_resources/panda_description/urdf/panda.urdf||panda_link0|
ROBOTS
rm -rf "$work"
