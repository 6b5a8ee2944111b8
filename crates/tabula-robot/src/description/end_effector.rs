//! A parallel gripper read off an SRDF end effector and the URDF's geometry, so a robot
//! brought with its MoveIt configuration (the Panda's `hand`) can grasp without a
//! hand-written description: the finger joint is the group's one driving joint, the
//! fingers are what it and its mimic move, the widths are the gap between the fingers'
//! collision geometry at the joint's limits, and the grasp frame sits between the pads.

use super::Gripper;
use crate::RobotModel;
use crate::model::{Geometry, JointKind};
use crate::srdf::{EndEffector, Srdf};
use tabula_geom::{Pose, Vec3};

/// How far the grasp frame sits in from the fingertips: the middle of a pad as long as
/// seed 002's (SPEC §6: WAM fingers 6 cm long, the tool 2.25 cm in from their tips),
/// never deeper than 40 % of the finger.
const PAD_CENTER_FROM_TIP: f64 = 0.0225;
const PAD_CENTER_MAX_SHARE: f64 = 0.4;
/// A frame the URDF already has counts as the grasp frame when it lies this close to
/// the line between the fingers (m).
const TCP_OFF_AXIS: f64 = 0.01;

/// The gripper of `ee`, when its group is a parallel gripper: one driving joint that is
/// prismatic, a second finger mimicking it from the same palm. `Err` says why not (the
/// caller warns: the arm is then without a gripper, as before). The grasp frame is a
/// fixed frame the URDF has between the pads (`fer_hand_tcp`), else one added to the
/// model as `<end effector>_tcp`.
pub fn gripper_from_end_effector(
    model: &mut RobotModel,
    srdf: &Srdf,
    ee: &EndEffector,
) -> Result<Gripper, String> {
    let links = srdf.group_links(&ee.group, model);
    let driving: Vec<usize> = (0..model.joints.len())
        .filter(|&j| {
            let joint = &model.joints[j];
            links.contains(&joint.child) && joint.kind.is_single_axis() && joint.mimic.is_none()
        })
        .collect();
    let [finger_joint] = driving.as_slice() else {
        return Err(format!(
            "group `{}` has {} driving joints, not one",
            ee.group,
            driving.len()
        ));
    };
    let finger_joint = *finger_joint;
    let joint = &model.joints[finger_joint];
    if joint.kind != JointKind::Prismatic {
        return Err(format!(
            "finger joint `{}` is not prismatic (describe the gripper in the robot's TOML)",
            joint.name
        ));
    }
    let palm = joint.parent;
    let mimic = (0..model.joints.len()).find(|&j| {
        let m = &model.joints[j];
        m.parent == palm && m.mimic.as_ref().is_some_and(|x| x.master == finger_joint)
    });
    let Some(mimic) = mimic else {
        return Err(format!(
            "no second finger mimics `{}` from `{}`",
            joint.name, model.links[palm].name
        ));
    };
    let fingers = [joint.child, model.joints[mimic].child];
    let shape = FingerShape::measure(model, finger_joint, fingers)?;
    let (tool, palm_from_tool) = shape.grasp_frame(model, palm, &ee.name)?;
    let tool_from_palm = palm_from_tool.inverse();
    let in_tool = |v: Vec3| tool_from_palm.rotation * v;
    Ok(Gripper {
        name: ee.name.clone(),
        tool_link: model.links[tool].name.clone(),
        palm: model.links[palm].name.clone(),
        finger_joint: model.joints[finger_joint].name.clone(),
        fingers: fingers.map(|f| model.links[f].name.clone()),
        closed_width: shape.closed_width,
        open_width: shape.open_width,
        approach_axis: in_tool(shape.approach).to_array(),
        closing_axis: in_tool(shape.closing).to_array(),
        self_filter_boxes: Vec::new(),
    })
}

/// The fingers measured in the palm's frame.
struct FingerShape {
    approach: Vec3,
    closing: Vec3,
    closed_width: f64,
    open_width: f64,
    /// Where the pads' middle is: on the line between the fingers, in from the tips.
    palm_from_pad_center: Vec3,
}

impl FingerShape {
    fn measure(
        model: &RobotModel,
        finger_joint: usize,
        fingers: [usize; 2],
    ) -> Result<Self, String> {
        let limits = model.joints[finger_joint].limits;
        let at = |q: f64| -> Result<[Vec<Vec3>; 2], String> {
            let mut values = vec![0.0; model.joints.len()];
            values[finger_joint] = q;
            let mut out = [Vec::new(), Vec::new()];
            for (k, &f) in fingers.iter().enumerate() {
                let j = model.links[f].parent_joint.ok_or("a finger has no joint")?;
                let palm_from_finger =
                    model.joints[j].parent_from_child(model.joint_value(&values, j));
                out[k] = link_points(model, f)
                    .into_iter()
                    .map(|p| palm_from_finger.transform_point(p))
                    .collect();
                if out[k].is_empty() {
                    return Err(format!(
                        "finger `{}` has no collision geometry to measure",
                        model.links[f].name
                    ));
                }
            }
            Ok(out)
        };
        let open = at(limits.upper)?;
        let closed = at(limits.lower)?;
        let mean = |p: &[Vec3]| p.iter().copied().sum::<Vec3>() / p.len() as f64;
        let (a, b) = (mean(&open[0]), mean(&open[1]));
        // The fingers slide along the joint's axis; it points from the second to the first.
        let joint = &model.joints[finger_joint];
        let axis = tidy(joint.parent_from_joint.rotation * joint.axis);
        let closing = if axis.dot(a - b) < 0.0 { -axis } else { axis };
        let middle = (a + b) * 0.5;
        let approach = tidy(middle - closing * middle.dot(closing));
        if (a - b).dot(closing) <= 0.0 || approach == Vec3::ZERO {
            return Err("the fingers do not open apart, away from the palm".into());
        }
        let gap = |p: &[Vec<Vec3>; 2]| {
            let inner_a = p[0]
                .iter()
                .map(|v| v.dot(closing))
                .fold(f64::INFINITY, f64::min);
            let inner_b = p[1]
                .iter()
                .map(|v| v.dot(closing))
                .fold(f64::NEG_INFINITY, f64::max);
            (inner_a - inner_b).max(0.0)
        };
        let along = open.iter().flatten().map(|v| v.dot(approach));
        let (base, tip) = along.fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), d| {
            (lo.min(d), hi.max(d))
        });
        let depth = tip - PAD_CENTER_FROM_TIP.min(PAD_CENTER_MAX_SHARE * (tip - base));
        // The third axis's middle and the closing axis's middle come from the fingers.
        let palm_from_pad_center = middle + approach * (depth - middle.dot(approach));
        Ok(Self {
            approach,
            closing,
            closed_width: gap(&closed),
            open_width: gap(&open),
            palm_from_pad_center,
        })
    }

    /// A fixed frame under the palm at the pads (the URDF's TCP), else a new one.
    fn grasp_frame(
        &self,
        model: &mut RobotModel,
        palm: usize,
        ee_name: &str,
    ) -> Result<(usize, Pose), String> {
        let mut stack = vec![(palm, Pose::IDENTITY)];
        while let Some((link, palm_from_link)) = stack.pop() {
            for &j in &model.links[link].child_joints {
                let joint = &model.joints[j];
                if joint.kind != JointKind::Fixed {
                    continue;
                }
                let palm_from_child = palm_from_link * joint.parent_from_joint;
                let offset = palm_from_child.translation - self.palm_from_pad_center;
                let off_axis = offset - self.approach * offset.dot(self.approach);
                let frame_only = model.links[joint.child].collision.is_empty();
                if frame_only
                    && off_axis.length() < TCP_OFF_AXIS
                    && offset.dot(self.approach).abs() < 2.0 * PAD_CENTER_FROM_TIP
                {
                    return Ok((joint.child, palm_from_child));
                }
                stack.push((joint.child, palm_from_child));
            }
        }
        let mut name = format!("{ee_name}_tcp");
        while model.link(&name).is_ok() {
            name.push('_');
        }
        let palm_from_tcp = Pose::from_translation(self.palm_from_pad_center);
        let tcp = model
            .add_fixed_frame(palm, &name, palm_from_tcp)
            .map_err(|e| e.to_string())?;
        Ok((tcp, palm_from_tcp))
    }
}

/// `v` normalised with rounding noise (below 1e-9) zeroed, so an axis of the palm reads
/// as one; zero when `v` is.
fn tidy(v: Vec3) -> Vec3 {
    let v = v.normalize_or(Vec3::ZERO);
    let clean = |c: f64| if c.abs() < 1e-9 { 0.0 } else { c };
    Vec3::new(clean(v.x), clean(v.y), clean(v.z)).normalize_or(Vec3::ZERO)
}

/// Points of a link's collision geometry in its frame: mesh vertices, box corners, the
/// extremes of round shapes along their axes and across.
fn link_points(model: &RobotModel, link: usize) -> Vec<Vec3> {
    let mut out = Vec::new();
    for shape in &model.links[link].collision {
        let local: Vec<Vec3> = match &shape.geometry {
            Geometry::Mesh { .. } => shape.geometry.hull_points().unwrap_or_default(),
            Geometry::Box { half_extents } => (0..8)
                .map(|i| {
                    let s = |b: usize| if i & b == 0 { -1.0 } else { 1.0 };
                    Vec3::new(s(1), s(2), s(4)) * *half_extents
                })
                .collect(),
            Geometry::Sphere { radius } => round_points(*radius, *radius),
            Geometry::Cylinder { radius, length } => round_points(*radius, length / 2.0),
            Geometry::Capsule { radius, length } => round_points(*radius, length / 2.0 + radius),
        };
        out.extend(
            local
                .into_iter()
                .map(|p| shape.link_from_shape.transform_point(p)),
        );
    }
    out
}

/// Eight points bounding a round shape standing on z: its extremes across at
/// ±`half_height` (a sphere's and a capsule's caps are bounded by their cylinder).
fn round_points(radius: f64, half_height: f64) -> Vec<Vec3> {
    let mut out = Vec::new();
    for z in [-half_height, half_height] {
        for (x, y) in [(radius, 0.0), (-radius, 0.0), (0.0, radius), (0.0, -radius)] {
            out.push(Vec3::new(x, y, z));
        }
    }
    out
}

/// Gives every arm without a gripper the SRDF end effector on it (its `parent_group`,
/// or its tip as `parent_link`) when that is a parallel gripper; the arm's tip becomes
/// the grasp frame, as the tasks plan for it. An end effector that is not a parallel
/// gripper leaves its arm without one, logged (info) with why.
pub fn attach_grippers(
    model: &mut RobotModel,
    srdf: &Srdf,
    description: &mut super::RobotDescription,
) {
    for a in 0..description.arms.len() {
        let arm = &description.arms[a];
        if arm.gripper.is_some() {
            continue;
        }
        let Some(ee) = srdf.end_effectors.iter().find(|e| {
            e.parent_group.as_deref() == Some(arm.name.as_str()) || e.parent_link == arm.tip
        }) else {
            continue;
        };
        let gripper = match description.grippers.iter().find(|g| g.name == ee.name) {
            Some(g) => g.clone(),
            None => match gripper_from_end_effector(model, srdf, ee) {
                Ok(g) => {
                    description.grippers.push(g.clone());
                    g
                }
                Err(why) => {
                    // Not a warning: a rigid tool or a linkage hand is a normal robot
                    // (MotionBenchMaker's Panda has its fingers fixed); a task that needs
                    // a gripper says there is none, and `-v` says why.
                    tracing::info!(
                        "SRDF end effector `{}` of arm `{}` is not used as a gripper: {why}",
                        ee.name,
                        arm.name
                    );
                    continue;
                }
            },
        };
        let arm = &mut description.arms[a];
        if crate::Chain::new(model, &arm.base, &gripper.tool_link).is_ok() {
            arm.tip = gripper.tool_link.clone();
        }
        arm.gripper = Some(gripper.name);
    }
}
