#!/usr/bin/env python3
"""Generates the URDFs in this folder (golem3.urdf, wam.urdf, pr2.urdf).

Run `python3 robots/generate.py` from the repository root after changing a parameter.
The product reads only the .urdf files; this script is how they were made, kept so a
reviewer can check every number against its source (SPEC.md section 2.1 for Golem-III,
Barrett's published DH table for the WAM, pr2_description for the PR2).

Golem-III is built from the standard DH table of SPEC 2.1,
A_i = Rot_z(theta_i + offset_i) Trans_z(d_i) Trans_x(a_i) Rot_x(alpha_i).
URDF joint i rotates about its own z after the origin
Static_{i-1} * Rot_z(offset_i) with Static_j = Trans_z(d_j) Trans_x(a_j) Rot_x(alpha_j),
so the URDF link frame i is DH frame i-1 turned by theta_i + offset_i.
The left arm is the right arm mirrored in the robot's x-z plane (M = diag(1, -1, 1)):
origins are conjugated by M and the arm joints turn about -z, so the same joint values
give the mirror image; the torso rotation is shared and keeps +z.
"""
import math
import os

HERE = os.path.dirname(os.path.abspath(__file__))


# ---------------------------------------------------------------- 4x4 helpers
def mat_mul(a, b):
    return [[sum(a[i][k] * b[k][j] for k in range(4)) for j in range(4)] for i in range(4)]


def chain(*ms):
    out = ident()
    for m in ms:
        out = mat_mul(out, m)
    return out


def ident():
    return [[1.0 if i == j else 0.0 for j in range(4)] for i in range(4)]


def trans(x, y, z):
    m = ident()
    m[0][3], m[1][3], m[2][3] = x, y, z
    return m


def rot_x(a):
    c, s = math.cos(a), math.sin(a)
    return [[1, 0, 0, 0], [0, c, -s, 0], [0, s, c, 0], [0, 0, 0, 1.0]]


def rot_y(a):
    c, s = math.cos(a), math.sin(a)
    return [[c, 0, s, 0], [0, 1, 0, 0], [-s, 0, c, 0], [0, 0, 0, 1.0]]


def rot_z(a):
    c, s = math.cos(a), math.sin(a)
    return [[c, -s, 0, 0], [s, c, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1.0]]


MIRROR = [[1, 0, 0, 0], [0, -1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1.0]]


def mirror(m):
    return chain(MIRROR, m, MIRROR)


def rpy_of(m):
    """URDF rpy: R = Rz(yaw) Ry(pitch) Rx(roll)."""
    pitch = math.atan2(-m[2][0], math.hypot(m[0][0], m[1][0]))
    if abs(math.cos(pitch)) < 1e-12:
        roll = 0.0
        yaw = math.atan2(-m[0][1], m[1][1])
    else:
        roll = math.atan2(m[2][1], m[2][2])
        yaw = math.atan2(m[1][0], m[0][0])
    return roll, pitch, yaw


def fmt(v):
    v = 0.0 if abs(v) < 1e-15 else v
    return repr(float(v))


def origin(m):
    r, p, y = rpy_of(m)
    return '<origin xyz="%s %s %s" rpy="%s %s %s"/>' % tuple(
        fmt(v) for v in (m[0][3], m[1][3], m[2][3], r, p, y)
    )


def origin_xyz_rpy(xyz, rpy=(0.0, 0.0, 0.0)):
    return '<origin xyz="%s %s %s" rpy="%s %s %s"/>' % tuple(fmt(v) for v in (*xyz, *rpy))


# ---------------------------------------------------------------- URDF writer
class Urdf:
    def __init__(self, name):
        self.name = name
        self.parts = []

    def material(self, name, rgba):
        self.parts.append(
            '  <material name="%s"><color rgba="%s"/></material>' % (name, " ".join(map(str, rgba)))
        )

    def link(self, name, shapes=(), mass=0.0, material=None):
        """shapes: list of (geometry_xml, origin_xml)."""
        out = ['  <link name="%s">' % name]
        if mass > 0.0:
            i = mass * 0.01
            out.append(
                '    <inertial><origin xyz="0 0 0" rpy="0 0 0"/><mass value="%s"/>'
                '<inertia ixx="%s" ixy="0" ixz="0" iyy="%s" iyz="0" izz="%s"/></inertial>'
                % (fmt(mass), fmt(i), fmt(i), fmt(i))
            )
        for geom, orig in shapes:
            mat = '<material name="%s"/>' % material if material else ""
            out.append("    <visual>%s<geometry>%s</geometry>%s</visual>" % (orig, geom, mat))
            out.append("    <collision>%s<geometry>%s</geometry></collision>" % (orig, geom))
        out.append("  </link>")
        self.parts.append("\n".join(out))

    def joint(self, name, kind, parent, child, orig, axis=None, limit=None, mimic=None):
        out = ['  <joint name="%s" type="%s">' % (name, kind), "    " + orig]
        out.append('    <parent link="%s"/>' % parent)
        out.append('    <child link="%s"/>' % child)
        if axis is not None:
            out.append('    <axis xyz="%s %s %s"/>' % tuple(fmt(v) for v in axis))
        if limit is not None:
            lower, upper, velocity, effort = limit
            if lower is None:
                out.append('    <limit effort="%s" velocity="%s"/>' % (fmt(effort), fmt(velocity)))
            else:
                out.append(
                    '    <limit lower="%s" upper="%s" effort="%s" velocity="%s"/>'
                    % (fmt(lower), fmt(upper), fmt(effort), fmt(velocity))
                )
        if mimic is not None:
            out.append('    <mimic joint="%s" multiplier="%s" offset="0"/>' % (mimic[0], fmt(mimic[1])))
        out.append("  </joint>")
        self.parts.append("\n".join(out))

    def write(self, filename, header):
        text = '<?xml version="1.0"?>\n<!-- %s\n     Generated by robots/generate.py; edit that, not this file. -->\n' % header
        text += '<robot name="%s">\n' % self.name + "\n".join(self.parts) + "\n</robot>\n"
        with open(os.path.join(HERE, filename), "w") as f:
            f.write(text)


def box(x, y, z):
    return '<box size="%s %s %s"/>' % (fmt(x), fmt(y), fmt(z))


def cylinder(radius, length):
    return '<cylinder radius="%s" length="%s"/>' % (fmt(radius), fmt(length))


def sphere(radius):
    return '<sphere radius="%s"/>' % fmt(radius)


def segment(t, radius):
    """A cylinder from the link origin to point t (in the link frame), or a sphere."""
    length = math.sqrt(sum(v * v for v in t))
    if length < 1e-9:
        return (sphere(radius), origin_xyz_rpy((0, 0, 0)))
    d = [v / length for v in t]
    pitch = math.acos(max(-1.0, min(1.0, d[2])))
    yaw = math.atan2(d[1], d[0])
    return (cylinder(radius, length), origin_xyz_rpy([v / 2 for v in t], (0.0, pitch, yaw)))


def translation(m):
    return (m[0][3], m[1][3], m[2][3])


def camera(u, parent, prefix, xyz):
    """A camera body plus its optical frame (z forward, x right, y down)."""
    u.link(prefix + "_link", [(box(0.06, 0.28, 0.06), origin_xyz_rpy((0, 0, 0)))], 0.3, "dark")
    u.joint(prefix + "_joint", "fixed", parent, prefix + "_link", origin_xyz_rpy(xyz))
    u.link(prefix + "_optical_frame")
    u.joint(
        prefix + "_optical_joint",
        "fixed",
        prefix + "_link",
        prefix + "_optical_frame",
        origin_xyz_rpy((0, 0, 0), (-math.pi / 2, 0.0, -math.pi / 2)),
    )


# ---------------------------------------------------------------- Golem-III
GOLEM_H = 1.283
GOLEM_L1, GOLEM_L2, GOLEM_L4, GOLEM_L5, GOLEM_L6 = 0.1225, 0.212, 0.256, 0.034, 0.4
GOLEM_RHO = math.radians(13.43)
GOLEM_LIMITS = [(-1.14, 1.75), (-3.00, 3.00), (-1.55, 1.55), (-1.67, 1.67), (-1.50, 1.50)]
DEG90 = math.pi / 2


# Golem-III's two-finger grippers (seed 001: two motors per hand, here one finger joint
# and a mimic). The tool frame (x = approach, y = closing direction) sits between the
# fingertips, so the DH tool point of SPEC 2.1 is the grasp point.
GOLEM_HAND = 0.13          # palm back to tool point along the approach
GOLEM_PALM = (0.03, 0.14, 0.05)
GOLEM_FINGER = (0.12, 0.01, 0.03)  # along approach, across (thickness), height
GOLEM_FINGER_TIP = 0.02    # fingertips reach this far past the tool point
GOLEM_GRIP_MAX_GAP = 0.10  # widest opening between the fingers


def golem_gripper(u, side):
    palm = "%s_gripper_palm_link" % side
    palm_x = -GOLEM_HAND + GOLEM_PALM[0] / 2
    u.link(palm, [(box(*GOLEM_PALM), origin_xyz_rpy((palm_x, 0, 0)))], 0.4, "dark")
    u.joint("%s_gripper_palm_joint" % side, "fixed", "%s_tool_link" % side, palm, origin_xyz_rpy((0, 0, 0)))
    finger_x = GOLEM_FINGER_TIP - GOLEM_FINGER[0] / 2
    for finger, fsign in (("l", 1.0), ("r", -1.0)):
        flink = "%s_gripper_%s_finger_link" % (side, finger)
        fbox = (box(*GOLEM_FINGER), origin_xyz_rpy((0, fsign * GOLEM_FINGER[1] / 2, 0)))
        u.link(flink, [fbox], 0.05, "grey")
        mimic = None if finger == "l" else ("%s_gripper_l_finger_joint" % side, 1.0)
        u.joint(
            "%s_gripper_%s_finger_joint" % (side, finger), "prismatic", palm, flink,
            origin_xyz_rpy((finger_x, 0, 0)), (0, fsign, 0),
            (0.0, GOLEM_GRIP_MAX_GAP / 2, 0.1, 40), mimic,
        )


def golem_static(a, d, alpha):
    return chain(trans(0, 0, d), trans(a, 0, 0), rot_x(alpha))


def golem3():
    u = Urdf("golem3")
    u.material("grey", (0.6, 0.6, 0.62, 1))
    u.material("dark", (0.15, 0.15, 0.17, 1))
    u.material("blue", (0.2, 0.35, 0.7, 1))
    u.link("base_link", [(cylinder(0.28, 0.9), origin_xyz_rpy((0, 0, 0.45)))], 40.0, "dark")
    u.link("torso_lift_link")
    u.joint(
        "torso_lift_joint", "prismatic", "base_link", "torso_lift_link",
        origin_xyz_rpy((0, 0, 0)), (0, 0, 1), (-0.10, 0.10, 0.05, 500),
    )
    u.link("torso_link", [(box(0.22, 0.36, 0.42), origin_xyz_rpy((0, 0, 1.14)))], 15.0, "grey")
    u.joint(
        "torso_yaw_joint", "revolute", "torso_lift_link", "torso_link",
        origin_xyz_rpy((0, 0, 0)), (0, 0, 1), (-1.00, 1.00, 1.0, 100),
    )
    # DH rows 1..6 and 6' of SPEC 2.1: (offset, a, d, alpha).
    rows = [
        (-DEG90, GOLEM_L1, GOLEM_H, 0.0),
        (0.0, GOLEM_L2, 0.0, 0.0),
        (DEG90, 0.0, 0.0, DEG90),
        (-DEG90 + GOLEM_RHO, GOLEM_L4, 0.0, 0.0),
        (-GOLEM_RHO, GOLEM_L5, 0.0, -DEG90),
        (-DEG90, 0.0, GOLEM_L6, DEG90),
    ]
    tool = rot_z(DEG90)
    for side, conj, axis in (("right", lambda m: m, (0, 0, 1)), ("left", mirror, (0, 0, -1))):
        # joint k (2..6) origin = Rz(offset_1) Static_1 ... for k = 2 the torso's own offset comes first.
        parent = "torso_link"
        origins = []
        for k in range(2, 7):
            off_prev, a, d, alpha = rows[k - 2]
            pre = rot_z(off_prev) if k == 2 else ident()
            origins.append(chain(pre, golem_static(a, d, alpha), rot_z(rows[k - 1][0])))
        tool_origin = chain(golem_static(0.0, GOLEM_L6, DEG90), tool)
        nexts = origins[1:] + [tool_origin]
        for idx, k in enumerate(range(2, 7)):
            link = "%s_arm_link%d" % (side, k)
            radius = 0.05 if k < 6 else 0.04
            end = translation(conj(nexts[idx]))
            if k == 6:
                # The wrist ends where the gripper's palm begins (the last GOLEM_HAND m
                # of l6 are the hand, modelled below).
                end = tuple(v * (GOLEM_L6 - GOLEM_HAND) / GOLEM_L6 for v in end)
            seg = segment(end, radius)
            u.link(link, [seg], 2.0, "blue" if k % 2 else "grey")
            lo, hi = GOLEM_LIMITS[k - 2]
            u.joint(
                "%s_arm_joint%d" % (side, k), "revolute", parent, link,
                origin(conj(origins[idx])), axis, (lo, hi, 1.0, 50),
            )
            parent = link
        u.link("%s_tool_link" % side)
        u.joint("%s_tool_joint" % side, "fixed", parent, "%s_tool_link" % side, origin(conj(tool_origin)))
        golem_gripper(u, side)
    u.link("head_pan_link", [(cylinder(0.04, 0.08), origin_xyz_rpy((0, 0, 0.04)))], 0.5, "dark")
    u.joint(
        "head_pan_joint", "revolute", "torso_link", "head_pan_link",
        origin_xyz_rpy((0.0, 0, 1.40)), (0, 0, 1), (-1.57, 1.57, 1.5, 10),
    )
    u.link("head_tilt_link", [(sphere(0.11), origin_xyz_rpy((0, 0, 0.1)))], 1.5, "grey")
    u.joint(
        "head_tilt_joint", "revolute", "head_pan_link", "head_tilt_link",
        origin_xyz_rpy((0, 0, 0.10)), (0, 1, 0), (-0.60, 0.90, 1.5, 10),
    )
    camera(u, "head_tilt_link", "head_camera", (0.10, 0, 0.12))
    u.write("golem3.urdf", "Golem-III: torso lift and rotation, two 5-DOF arms per the DH table of SPEC 2.1, pan/tilt head with a camera.")


# ---------------------------------------------------------------- WAM
# Barrett WAM 7-DOF, standard DH (a, alpha, d) from Barrett's published kinematics.
WAM_DH = [
    (0.0, -DEG90, 0.0),
    (0.0, DEG90, 0.0),
    (0.045, -DEG90, 0.55),
    (-0.045, DEG90, 0.0),
    (0.0, -DEG90, 0.3),
    (0.0, DEG90, 0.0),
    (0.0, 0.0, 0.06),
]
WAM_LIMITS = [(-2.6, 2.6), (-2.0, 2.0), (-2.8, 2.8), (-0.9, 3.1), (-4.76, 1.24), (-1.6, 1.6), (-3.0, 3.0)]
WAM_VELOCITY = [2.0, 2.0, 2.0, 2.0, 2.5, 2.5, 2.5]
WAM_BASE_HEIGHT = 0.346

# Seed-002 gripper (SPEC 6): opening 0.07, closing 0.03, finger width 0.03,
# finger depth 0.06, gripper height 0.10, closing-region height 0.045.
GRIP_OPEN, GRIP_CLOSED, FINGER_W, FINGER_DEPTH, GRIP_HEIGHT, CLOSING_H = 0.07, 0.03, 0.03, 0.06, 0.10, 0.045
FINGER_THICK = 0.01


def wam():
    u = Urdf("wam")
    u.material("grey", (0.8, 0.8, 0.82, 1))
    u.material("dark", (0.15, 0.15, 0.17, 1))
    u.link("base_link", [(box(0.25, 0.25, WAM_BASE_HEIGHT), origin_xyz_rpy((0, 0, WAM_BASE_HEIGHT / 2)))], 10.0, "dark")
    parent = "base_link"
    joint_origin = trans(0, 0, WAM_BASE_HEIGHT)
    for i, (a, alpha, d) in enumerate(WAM_DH):
        link = "wam_link%d" % (i + 1)
        static = chain(trans(0, 0, d), trans(a, 0, 0), rot_x(alpha))
        seg = segment(translation(static), 0.06 if i < 4 else 0.045)
        u.link(link, [seg], 2.0, "grey")
        lo, hi = WAM_LIMITS[i]
        u.joint("wam_joint%d" % (i + 1), "revolute", parent, link, origin(joint_origin), (0, 0, 1), (lo, hi, WAM_VELOCITY[i], 30))
        parent, joint_origin = link, static
    palm_h = GRIP_HEIGHT - FINGER_DEPTH
    u.link("wam_gripper_palm", [(box(GRIP_OPEN + 2 * FINGER_THICK, FINGER_W + 0.02, palm_h), origin_xyz_rpy((0, 0, palm_h / 2)))], 0.5, "dark")
    u.joint("wam_gripper_mount", "fixed", parent, "wam_gripper_palm", origin(joint_origin))
    half_open, half_closed = GRIP_OPEN / 2, GRIP_CLOSED / 2
    for side, sign in (("left", 1.0), ("right", -1.0)):
        finger = "wam_gripper_%s_finger" % side
        u.link(finger, [(box(FINGER_THICK, FINGER_W, FINGER_DEPTH), origin_xyz_rpy((sign * FINGER_THICK / 2, 0, FINGER_DEPTH / 2)))], 0.1, "grey")
        mimic = None if side == "left" else ("wam_gripper_left_finger_joint", 1.0)
        u.joint(
            finger + "_joint", "prismatic", "wam_gripper_palm", finger,
            origin_xyz_rpy((0, 0, palm_h)), (sign, 0, 0), (half_closed, half_open, 0.1, 20), mimic,
        )
    u.link("wam_tool")
    u.joint("wam_tool_joint", "fixed", "wam_gripper_palm", "wam_tool", origin_xyz_rpy((0, 0, GRIP_HEIGHT - CLOSING_H / 2)))
    u.write("wam.urdf", "A 7-DOF Barrett WAM-like arm (published DH and limits) on a fixed base, with the seed-002 parallel gripper.")


# ---------------------------------------------------------------- PR2
# pr2_description kinematics: (name, parent, xyz, axis, lower, upper, velocity); None limits = continuous.
PR2_ARM = [
    ("shoulder_pan", (0.0, -0.188, 0.0), (0, 0, 1), (-2.2854, 0.714602), 2.088),
    ("shoulder_lift", (0.1, 0.0, 0.0), (0, 1, 0), (-0.5236, 1.3963), 2.082),
    ("upper_arm_roll", (0.0, 0.0, 0.0), (1, 0, 0), (-3.9, 0.8), 3.27),
    ("elbow_flex", (0.4, 0.0, 0.0), (0, 1, 0), (-2.3213, 0.0), 3.3),
    ("forearm_roll", (0.0, 0.0, 0.0), (1, 0, 0), None, 3.6),
    ("wrist_flex", (0.321, 0.0, 0.0), (0, 1, 0), (-2.094, 0.0), 3.078),
    ("wrist_roll", (0.0, 0.0, 0.0), (1, 0, 0), None, 3.6),
]
# Collision shapes kept clear of each other at the joints, so only real contacts count.
PR2_LINK_SHAPES = {
    "shoulder_pan": [(cylinder(0.07, 0.25), origin_xyz_rpy((0, 0, -0.1)))],
    "shoulder_lift": [(sphere(0.07), origin_xyz_rpy((0.02, 0, 0)))],
    "upper_arm_roll": [(cylinder(0.06, 0.2), origin_xyz_rpy((0.2, 0, 0), (0, DEG90, 0)))],
    "elbow_flex": [(sphere(0.06), origin_xyz_rpy((0, 0, 0)))],
    "forearm_roll": [(cylinder(0.05, 0.16), origin_xyz_rpy((0.16, 0, 0), (0, DEG90, 0)))],
    "wrist_flex": [(sphere(0.04), origin_xyz_rpy((0, 0, 0)))],
    "wrist_roll": [],
}
PR2_TOOL_FROM_WRIST = 0.18
# Seed-000 self-filter boxes (SPEC 6), given in the gripper (tool) frame.
PR2_GRIPPER_BOXES = [((0.098, 0.16, 0.061), -0.095), ((0.02, 0.11, 0.052), -0.042)]
PR2_FINGER_BOX = (0.105, 0.02, 0.03)
PR2_FINGER_CENTER_X = -0.03
PR2_GRIPPER_MAX_GAP = 0.09


def pr2():
    u = Urdf("pr2")
    u.material("grey", (0.75, 0.75, 0.78, 1))
    u.material("dark", (0.15, 0.15, 0.17, 1))
    u.material("blue", (0.25, 0.4, 0.75, 1))
    u.link("odom")
    u.link("base_x_link")
    u.link("base_y_link")
    u.joint("base_x_joint", "prismatic", "odom", "base_x_link", origin_xyz_rpy((0, 0, 0)), (1, 0, 0), (-50.0, 50.0, 1.0, 1000))
    u.joint("base_y_joint", "prismatic", "base_x_link", "base_y_link", origin_xyz_rpy((0, 0, 0)), (0, 1, 0), (-50.0, 50.0, 1.0, 1000))
    u.link("base_footprint")
    u.joint("base_theta_joint", "continuous", "base_y_link", "base_footprint", origin_xyz_rpy((0, 0, 0)), (0, 0, 1), (None, None, 1.0, 1000))
    u.link("base_link", [(box(0.668, 0.668, 0.28), origin_xyz_rpy((0, 0, 0.14 - 0.051 + 0.02)))], 100.0, "dark")
    u.joint("base_footprint_joint", "fixed", "base_footprint", "base_link", origin_xyz_rpy((0, 0, 0.051)))
    # The torso column between the shoulders (the shoulder pan links carry the arms' width).
    u.link("torso_lift_link", [(box(0.25, 0.2, 0.7), origin_xyz_rpy((-0.1, 0, -0.3)))], 20.0, "grey")
    u.joint("torso_lift_joint", "prismatic", "base_link", "torso_lift_link", origin_xyz_rpy((-0.05, 0, 0.739675)), (0, 0, 1), (0.0, 0.33, 0.013, 10000))
    u.link("head_pan_link", [(cylinder(0.06, 0.1), origin_xyz_rpy((0, 0, 0.05)))], 1.0, "dark")
    u.joint("head_pan_joint", "revolute", "torso_lift_link", "head_pan_link", origin_xyz_rpy((-0.01707, 0, 0.38145)), (0, 0, 1), (-3.007, 3.007, 6.0, 2.6))
    u.link("head_tilt_link", [(box(0.2, 0.3, 0.12), origin_xyz_rpy((0.05, 0, 0.03)))], 1.5, "grey")
    u.joint("head_tilt_joint", "revolute", "head_pan_link", "head_tilt_link", origin_xyz_rpy((0.068, 0, 0)), (0, 1, 0), (-0.471238, 1.39626, 5.0, 15))
    camera(u, "head_tilt_link", "head_camera", (0.12, 0, 0.13))
    for side, sign in (("r", 1.0), ("l", -1.0)):
        parent = "torso_lift_link"
        for name, xyz, axis, limits, velocity in PR2_ARM:
            link = "%s_%s_link" % (side, name)
            xyz = (xyz[0], sign * xyz[1], xyz[2])
            if limits is not None and name in ("shoulder_pan", "upper_arm_roll") and side == "l":
                limits = (-limits[1], -limits[0])
            u.link(link, PR2_LINK_SHAPES[name], 2.0, "blue" if "roll" in name else "grey")
            lim = (limits[0], limits[1], velocity, 30) if limits else (None, None, velocity, 30)
            kind = "revolute" if limits else "continuous"
            u.joint("%s_%s_joint" % (side, name), kind, parent, link, origin_xyz_rpy(xyz), axis, lim)
            parent = link
        palm = "%s_gripper_palm_link" % side
        shapes = [(box(*size), origin_xyz_rpy((PR2_TOOL_FROM_WRIST + x, 0, 0))) for size, x in PR2_GRIPPER_BOXES]
        u.link(palm, shapes, 0.8, "dark")
        u.joint("%s_gripper_palm_joint" % side, "fixed", parent, palm, origin_xyz_rpy((0, 0, 0)))
        for finger, fsign in (("l", 1.0), ("r", -1.0)):
            flink = "%s_gripper_%s_finger_link" % (side, finger)
            fbox = (box(*PR2_FINGER_BOX), origin_xyz_rpy((0, fsign * PR2_FINGER_BOX[1] / 2, 0)))
            u.link(flink, [fbox], 0.1, "grey")
            mimic = None if finger == "l" else ("%s_gripper_l_finger_joint" % side, 1.0)
            u.joint(
                "%s_gripper_%s_finger_joint" % (side, finger), "prismatic", palm, flink,
                origin_xyz_rpy((PR2_TOOL_FROM_WRIST + PR2_FINGER_CENTER_X, 0, 0)), (0, fsign, 0),
                (0.0, PR2_GRIPPER_MAX_GAP / 2, 0.2, 100), mimic,
            )
        u.link("%s_gripper_tool_frame" % side)
        u.joint("%s_gripper_tool_joint" % side, "fixed", palm, "%s_gripper_tool_frame" % side, origin_xyz_rpy((PR2_TOOL_FROM_WRIST, 0, 0)))
    u.write("pr2.urdf", "A PR2-like mobile manipulator: planar base (x, y, theta), torso lift, two 7-DOF arms with PR2's published kinematics and limits, pan/tilt head with a camera, grippers from seed 000's boxes.")


if __name__ == "__main__":
    golem3()
    wam()
    pr2()
