//! The robot's body as placing measures it: arms and grippers, the base, the shoulder,
//! the protective shape of what the hand holds.

use super::PlaceError;
use tabula_geom::parry::shape::SharedShape;
use tabula_geom::{Pose, Vec3};
use tabula_perception::surfaces::Surface;
use tabula_robot::driver::{DriverError, JointState, RobotDriver};
use tabula_robot::robots::NamedRobot;

/// The surface as a 2 cm slab whose top is its plane lowered by `sunk`: its outline's
/// prism.
pub(super) fn surface_slab(surface: &Surface, sunk: f64) -> Option<SharedShape> {
    let n = surface.plane.normal;
    let offset = surface.centroid.dot(n) - sunk;
    let pts: Vec<Vec3> = surface
        .hull
        .iter()
        .flat_map(|q| {
            let on = *q - n * (q.dot(n) - offset);
            [on, on - n * 0.02]
        })
        .collect();
    SharedShape::convex_hull(&pts)
}

/// Points the head at `at`; a robot without a head looks where it looks.
pub(super) fn look_at(driver: &mut impl RobotDriver, at: Vec3) -> Result<(), PlaceError> {
    match driver.look_at(at) {
        Ok(_) | Err(DriverError::Unsupported(_)) => Ok(()),
        Err(e) => Err(e.into()),
    }
}

/// The protective sphere (SPEC §1.1) around the first view of the held object (the
/// ball at `centre`, tool frame), cut by the plane the held object cannot reach behind:
/// the palm's front face (`palm_front` along the approach axis), else 3 cm behind the
/// deepest point seen. A whole ball around a long object held at one end reaches back
/// over the wrist, and then no view is free of the arm's own links (the palm and
/// fingers may touch it, the wrist may not).
pub(super) fn protective_shape(
    first: &[Vec3],
    approach: Vec3,
    palm_front: Option<f64>,
    centre: Vec3,
    radius: f64,
) -> SharedShape {
    let deepest = first
        .iter()
        .map(|q| q.dot(approach))
        .fold(f64::INFINITY, f64::min);
    let cut = match palm_front {
        Some(f) => f,
        None if first.len() >= 10 => deepest - 0.03,
        None => f64::NEG_INFINITY,
    } - centre.dot(approach);
    // No cut through the ball, or one in front of all of it (what was seen lies behind
    // the palm: something is off, keep the whole ball).
    if !cut.is_finite() || cut.abs() >= radius * 0.95 {
        return SharedShape::ball(radius);
    }
    // The ball's points, those behind the plane pressed onto it: their hull holds the
    // ball's part in front of the plane.
    let (u, v) = (
        approach.any_orthonormal_vector(),
        approach.cross(approach.any_orthonormal_vector()),
    );
    let grown = radius / (std::f64::consts::PI / 24.0).cos().powi(2);
    let mut points = Vec::new();
    for i in 0..=12 {
        let polar = std::f64::consts::PI * i as f64 / 12.0;
        for j in 0..24 {
            let azimuth = std::f64::consts::TAU * j as f64 / 24.0;
            let d = approach * polar.cos() + (u * azimuth.cos() + v * azimuth.sin()) * polar.sin();
            // The polygon's chords fall inside the ball: the points are pushed out
            // (`grown`) so the hull holds it.
            let q = d * grown;
            let along = q.dot(approach);
            points.push(q + approach * (cut - along).max(0.0));
        }
    }
    // And the rim where the plane cuts the (grown) ball.
    let rim = (grown * grown - cut * cut).max(0.0).sqrt();
    for j in 0..24 {
        let azimuth = std::f64::consts::TAU * j as f64 / 24.0;
        points
            .push(approach * cut + (u * azimuth.cos() + v * azimuth.sin()) * rim * grown / radius);
    }
    SharedShape::convex_hull(&points).unwrap_or_else(|| SharedShape::ball(radius))
}

/// The front face of a gripper's palm along its approach axis (tool frame): the front
/// of the rearmost of its self-filter boxes (axis-aligned in the tool frame), which
/// nothing the fingers hold can reach behind.
pub(super) fn palm_front(g: &tabula_robot::description::Gripper) -> Option<f64> {
    let a = g.approach();
    g.self_filter_boxes
        .iter()
        .map(|b| {
            let (c, h) = (Vec3::from_array(b.center), Vec3::from_array(b.size) / 2.0);
            (c.dot(a), c.dot(a) + h.dot(a.abs()))
        })
        .min_by(|x, y| x.0.total_cmp(&y.0))
        .map(|(_, front)| front)
}

/// Whether a failure means "nothing here": worth turning around for.
pub(super) fn retry_behind(e: &PlaceError) -> bool {
    matches!(
        e,
        PlaceError::NoSurface(_) | PlaceError::NoRoom(_) | PlaceError::Unreachable
    )
}

pub(super) use crate::skills::base::heading;

pub(super) fn heading_vector(p: &Pose) -> Vec3 {
    let h = heading(p);
    Vec3::new(h.cos(), h.sin(), 0.0)
}

/// The gripper at the tip of `arm`.
pub(super) fn arm_gripper<'r>(
    robot: &'r NamedRobot,
    arm: &str,
) -> Option<&'r tabula_robot::description::Gripper> {
    let name = robot.description.arm(arm).ok()?.gripper.as_ref()?;
    robot.description.grippers.iter().find(|g| &g.name == name)
}

/// The arm whose gripper is closed the most (below 80 % of its opening).
pub(super) fn holding_arm(robot: &NamedRobot, state: &JointState) -> Option<String> {
    let mut best: Option<(f64, String)> = None;
    for a in &robot.description.arms {
        let Some(g) = arm_gripper(robot, &a.name) else {
            continue;
        };
        let (Some(j), Some(v)) = (
            robot.model.joint(&g.finger_joint),
            state.get(&g.finger_joint),
        ) else {
            continue;
        };
        let l = robot.model.joints[j].limits;
        let open = (v - l.lower) / (l.upper - l.lower).max(1e-9);
        if open < 0.8 && best.as_ref().is_none_or(|(o, _)| open < *o) {
            best = Some((open, a.name.clone()));
        }
    }
    best.map(|(_, n)| n)
}

/// The base's pose in the world (see [`crate::skills::base::world_from_base`]).
pub(super) fn world_from_base(
    robot: &NamedRobot,
    driver: &impl RobotDriver,
) -> Result<Pose, PlaceError> {
    crate::skills::base::world_from_base(robot, driver).map_err(|e| match e {
        crate::skills::SkillError::Driver(m) => PlaceError::Driver(m),
        other => PlaceError::Driver(other.to_string()),
    })
}

/// The world pose of a link at a joint state.
pub(super) fn tool_pose(
    robot: &NamedRobot,
    state: &JointState,
    root: Pose,
    link: &str,
) -> Result<Pose, PlaceError> {
    let l = robot
        .model
        .link(link)
        .map_err(|e| PlaceError::Driver(e.to_string()))?;
    let fk = robot
        .model
        .forward_kinematics(&state.model_values(&robot.model))
        .map_err(|e| PlaceError::Driver(e.to_string()))?;
    Ok(root * fk[l])
}

/// The arm's shoulder (the child link of its second joint, else its first) in the
/// world.
pub(super) fn shoulder_position(
    robot: &NamedRobot,
    arm: &str,
    state: &JointState,
    root: Pose,
) -> Result<Vec3, PlaceError> {
    let group = robot
        .description
        .arm(arm)
        .map_err(|e| PlaceError::Driver(e.to_string()))?;
    let chain = group
        .chain(&robot.model)
        .map_err(|e| PlaceError::Driver(e.to_string()))?;
    let fk = robot
        .model
        .forward_kinematics(&state.model_values(&robot.model))
        .map_err(|e| PlaceError::Driver(e.to_string()))?;
    let j = chain
        .joint_indices
        .get(1)
        .or(chain.joint_indices.first())
        .ok_or(PlaceError::Unreachable)?;
    Ok(root * fk[robot.model.joints[*j].child].translation)
}

/// The shoulder's lateral offset from the base's centre line (m, left positive), at
/// the robot's mid configuration.
pub(super) fn shoulder_lateral(robot: &NamedRobot, arm: &str) -> f64 {
    let state = JointState {
        names: robot.model.joints.iter().map(|j| j.name.clone()).collect(),
        positions: robot.model.mid_configuration(),
        ..Default::default()
    };
    shoulder_position(robot, arm, &state, Pose::IDENTITY)
        .map(|p| p.y)
        .unwrap_or(0.0)
}

pub(super) use crate::skills::base::base_half_extent;

pub(super) use crate::skills::base::forward_extent;

/// Points bounding `arm`'s gripper in its tool frame (the corners, edge midpoints and
/// face centres of its self-filter boxes): what must stay clear of a support plane.
pub fn gripper_points(robot: &NamedRobot, arm: &str) -> Vec<Vec3> {
    let Some(g) = arm_gripper(robot, arm) else {
        return vec![Vec3::ZERO];
    };
    let mut out = Vec::new();
    for b in &g.self_filter_boxes {
        let c = Vec3::from_array(b.center);
        let h = Vec3::from_array(b.size) / 2.0;
        for i in 0..27 {
            let s = Vec3::new(
                (i % 3) as f64 - 1.0,
                ((i / 3) % 3) as f64 - 1.0,
                (i / 9) as f64 - 1.0,
            );
            out.push(c + h * s);
        }
    }
    if out.is_empty() {
        out.push(Vec3::ZERO);
    }
    out
}
