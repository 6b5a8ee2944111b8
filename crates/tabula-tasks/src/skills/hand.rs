//! The hand: a parallel gripper's collision shapes in its tool frame, open to every
//! few millimetres of finger gap and closed, taken from the robot's URDF — what every
//! grasp and push is checked with — and the tool poses that point it.

use super::SkillError;
use tabula_geom::parry::shape::SharedShape;
use tabula_geom::{Mat3, Pose, Quat, Vec3};
use tabula_robot::description::Gripper;
use tabula_robot::robots::NamedRobot;

/// Pre-grasp openings are modelled every 5 mm of finger gap.
pub const OPENING_STEP: f64 = 0.005;

/// An arm that can take things: its name, its gripper and the gripper's hand.
pub struct HandArm {
    pub arm: String,
    pub gripper: Gripper,
    pub hand: Hand,
}

impl HandArm {
    /// The arm named `wanted`, else every arm of the robot that has a gripper.
    pub fn all(robot: &NamedRobot, wanted: Option<&str>) -> Result<Vec<HandArm>, SkillError> {
        let names: Vec<&str> = match wanted {
            Some(a) => vec![a],
            None => robot
                .description
                .arms
                .iter()
                .filter(|a| a.gripper.is_some())
                .map(|a| a.name.as_str())
                .collect(),
        };
        if names.is_empty() {
            return Err(SkillError::Robot(super::NO_GRIPPER.into()));
        }
        names
            .into_iter()
            .map(|name| {
                let (arm, gripper) = super::arm_with_gripper(robot, Some(name))?;
                let hand = Hand::new(robot, &gripper)?;
                Ok(HandArm {
                    arm: arm.name,
                    gripper,
                    hand,
                })
            })
            .collect()
    }

    /// This arm acting through `driver` with `group` (the arm's), `up` the table's up.
    pub fn manipulator<'a, D>(
        &'a self,
        (driver, robot): (&'a mut D, &'a NamedRobot),
        group: &'a mut tabula_motion::MoveGroup,
        up: tabula_geom::Vec3,
    ) -> super::pick::Manipulator<'a, D> {
        super::pick::Manipulator {
            driver,
            robot,
            group,
            hand: &self.hand,
            gripper: &self.gripper,
            up,
        }
    }
}

/// The gripper's collision shapes in its tool frame, open and closed, from the URDF.
#[derive(Clone)]
pub struct Hand {
    /// Palm and fingers opened to finger gaps every [`OPENING_STEP`] from closed to
    /// fully open, narrowest first (the last is fully open).
    pub openings: Vec<(f64, Vec<(SharedShape, Pose)>)>,
    pub closed: Vec<(SharedShape, Pose)>,
    /// Closed fingers only (what meets a pushed object).
    pub closed_fingers: Vec<(SharedShape, Pose)>,
    /// Open fingers only (what lands beside a grasped object).
    pub open_fingers: Vec<(SharedShape, Pose)>,
    /// The palm alone (what must stay outside an object the fingers reach around).
    pub palm: Vec<(SharedShape, Pose)>,
    /// Fingertips' distance from the tool origin along the approach (m).
    pub tip: f64,
    /// Finger length along the approach (m).
    pub finger_length: f64,
    /// How far the fingers reach beyond the palm along the approach (m): what can pass
    /// below an object's top while the palm stays above it.
    pub beyond_palm: f64,
    /// The tool frame's approach and closing axes (unit).
    pub approach: Vec3,
    pub closing: Vec3,
    /// Widest finger gap (m).
    pub open_width: f64,
    /// Finger gap when fully closed (m): nothing narrower can be held.
    pub closed_width: f64,
}

/// How much wider than the closed fingers an object must be for the fingers to meet
/// it before they stop (m): a tile on edge 1.2 cm thick between fingers that close to
/// 3 cm is never held.
pub const MIN_SQUEEZE: f64 = 0.002;

/// How much narrower than it is the camera may see an object (m): each silhouette edge
/// can lie up to a pixel's footprint past the last point seen (1.7 mm at 1 m for the
/// 640-pixel, 57° Kinect-like camera of SPEC §5), so a standing cylinder 3.24 cm
/// across is seen 3.1 cm wide and would otherwise be taken for one the closed fingers
/// pass.
pub const SEEN_SHORT: f64 = 0.002;

impl Hand {
    /// The hand of `gripper` on `robot`: its palm and finger links posed by forward
    /// kinematics at every opening.
    pub fn new(robot: &NamedRobot, gripper: &Gripper) -> Result<Self, SkillError> {
        let model = &robot.model;
        let err = |e: String| SkillError::Robot(e);
        let fj = model
            .joint(&gripper.finger_joint)
            .ok_or_else(|| err(format!("no finger joint `{}`", gripper.finger_joint)))?;
        let limits = model.joints[fj].limits;
        let tool = model
            .link(&gripper.tool_link)
            .map_err(|e| err(e.to_string()))?;
        let shapes_at =
            |finger: f64, links: &[&str]| -> Result<Vec<(SharedShape, Pose)>, SkillError> {
                let mut values = tabula_robot::driver::JointState::default().model_values(model);
                values[fj] = finger;
                let fk = model
                    .forward_kinematics(&values)
                    .map_err(|e| err(e.to_string()))?;
                let tool_from_root = fk[tool].inverse();
                let mut out = Vec::new();
                for name in links {
                    let l = model.link(name).map_err(|e| err(e.to_string()))?;
                    for s in &model.links[l].collision {
                        let (shape, shape_pose) = s.geometry.collision_shape(false).map_err(err)?;
                        out.push((
                            shape,
                            tool_from_root * fk[l] * s.link_from_shape * shape_pose,
                        ));
                    }
                }
                Ok(out)
            };
        let fingers = [gripper.fingers[0].as_str(), gripper.fingers[1].as_str()];
        let all = [
            gripper.palm.as_str(),
            gripper.fingers[0].as_str(),
            gripper.fingers[1].as_str(),
        ];
        let closed_fingers = shapes_at(limits.lower, &fingers)?;
        let approach = gripper.approach();
        let (lo, hi) = extent_along(&closed_fingers, approach);
        // A palm that wraps the fingers' roots (the Panda's hand) meets what the
        // fingers reach over before their roots do.
        let palm = shapes_at(limits.lower, &[gripper.palm.as_str()])?;
        let (_, palm_end) = extent_along(&palm, approach);
        // The gap is linear in the finger joint (see `Gripper::width_at`).
        let span = gripper.open_width - gripper.closed_width;
        let levels = (span / OPENING_STEP).ceil().max(0.0) as usize;
        let mut openings = Vec::with_capacity(levels + 1);
        for k in 0..=levels {
            let width = (gripper.closed_width + OPENING_STEP * k as f64).min(gripper.open_width);
            let share = if span > 1e-12 {
                (width - gripper.closed_width) / span
            } else {
                1.0
            };
            let value = limits.lower + (limits.upper - limits.lower) * share;
            openings.push((width, shapes_at(value, &all)?));
        }
        Ok(Self {
            openings,
            closed: shapes_at(limits.lower, &all)?,
            tip: hi,
            finger_length: hi - lo,
            beyond_palm: hi - lo.max(palm_end.min(hi)),
            closed_fingers,
            open_fingers: shapes_at(limits.upper, &fingers)?,
            palm,
            approach,
            closing: gripper.closing(),
            open_width: gripper.open_width,
            closed_width: gripper.closed_width,
        })
    }

    /// Whether something seen `width` across (m) fits between the open fingers with
    /// `margin` on each side and may be wide enough for the closing fingers to hold.
    pub fn holds(&self, width: f64, margin: f64) -> bool {
        width + 2.0 * margin <= self.open_width && !self.passes(width)
    }

    /// Whether the closing fingers pass something seen `width` across (m) without
    /// squeezing it, even allowing for what the camera misses ([`SEEN_SHORT`]).
    pub fn passes(&self, width: f64) -> bool {
        width + SEEN_SHORT < self.closed_width + MIN_SQUEEZE
    }

    /// The narrowest opening at least `width` wide (fully open when none is): its gap
    /// and the open palm and fingers.
    pub fn open_for(&self, width: f64) -> (f64, &[(SharedShape, Pose)]) {
        let (w, shapes) = self
            .openings
            .iter()
            .find(|(w, _)| *w >= width - 1e-9)
            .or(self.openings.last())
            .expect("a hand has at least its full opening");
        (*w, shapes)
    }

    /// `world_from_tool` with the approach pointing down (against the table normal
    /// `up`), the fingers closing along `closing` (world, horizontal) and the fingertips
    /// at `tips` (world).
    pub fn pose(&self, tips: Vec3, closing: Vec3, up: Vec3) -> Pose {
        let approach = -up;
        let closing = (closing - approach * closing.dot(approach)).normalize_or(Vec3::X);
        let rotation = tool_rotation(self.approach, self.closing, approach, closing);
        Pose::from_parts(tips - approach * self.tip, rotation)
    }
}

/// Lowest and highest extent of shapes (tool frame) along unit direction `d`.
pub fn extent_along(shapes: &[(SharedShape, Pose)], d: Vec3) -> (f64, f64) {
    let mut lo = f64::INFINITY;
    let mut hi = f64::NEG_INFINITY;
    for (s, p) in shapes {
        let b = s.compute_aabb(p);
        for i in 0..8 {
            let c = Vec3::new(
                if i & 1 == 0 { b.mins.x } else { b.maxs.x },
                if i & 2 == 0 { b.mins.y } else { b.maxs.y },
                if i & 4 == 0 { b.mins.z } else { b.maxs.z },
            );
            lo = lo.min(c.dot(d));
            hi = hi.max(c.dot(d));
        }
    }
    (lo, hi)
}

/// Rotation taking the gripper's own approach/closing axes (tool frame) onto world
/// directions `approach` and `closing` (orthonormal).
pub fn tool_rotation(
    tool_approach: Vec3,
    tool_closing: Vec3,
    approach: Vec3,
    closing: Vec3,
) -> Quat {
    let tool = Mat3::from_cols(
        tool_approach,
        tool_closing,
        tool_approach.cross(tool_closing),
    );
    let world = Mat3::from_cols(approach, closing, approach.cross(closing));
    Quat::from_mat3(&(world * tool.transpose())).normalize()
}
