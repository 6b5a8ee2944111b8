//! A mobile robot's base: where it stands (a planar base is three joints of the model),
//! its heading and extents, and the drives tasks share — back to where it started,
//! up to a support's edge.

use super::SkillError;
use tabula_geom::polygon::{distance_to_boundary, inside_convex};
use tabula_geom::{Pose, Vec2, Vec3};
use tabula_robot::driver::{DriverError, JointState, RobotDriver};
use tabula_robot::robots::NamedRobot;

/// `world_from_base`: the root's pose times the planar base joints' (the root's pose
/// alone for a robot without a base).
pub fn world_from_base(robot: &NamedRobot, driver: &impl RobotDriver) -> Result<Pose, SkillError> {
    let root = driver.world_from_root()?;
    let Some(base) = &robot.description.base else {
        return Ok(root);
    };
    let Some(j) = robot.model.joint(&base.theta_joint) else {
        return Ok(root);
    };
    let state = driver.joint_state()?;
    let fk = robot
        .model
        .forward_kinematics(&state.model_values(&robot.model))
        .map_err(|e| SkillError::Robot(e.to_string()))?;
    Ok(root * fk[robot.model.joints[j].child])
}

/// The heading (rad, about the world's z) of a pose's x axis.
pub fn heading(p: &Pose) -> f64 {
    let f = p.rotation * Vec3::X;
    f.y.atan2(f.x)
}

/// Half the base's footprint diagonal extent along its front (m): the base link's
/// collision box, else 0.35.
pub fn base_half_extent(robot: &NamedRobot) -> f64 {
    robot
        .model
        .link("base_link")
        .ok()
        .and_then(|l| {
            robot.model.links[l]
                .collision
                .iter()
                .find_map(|s| match &s.geometry {
                    tabula_robot::model::Geometry::Box { half_extents } => {
                        Some(half_extents.x.max(half_extents.y))
                    }
                    _ => None,
                })
        })
        .unwrap_or(0.35)
}

/// The robot's forward reach (m, along the base's x from its centre) of every
/// collision shape whose bottom is below `below` (world z).
pub fn forward_extent(
    robot: &NamedRobot,
    state: &JointState,
    root: Pose,
    base: Pose,
    below: f64,
) -> f64 {
    let Ok(fk) = robot
        .model
        .forward_kinematics(&state.model_values(&robot.model))
    else {
        return 0.0;
    };
    let base_from_world = base.inverse();
    let mut front: f64 = 0.0;
    for (l, link) in robot.model.links.iter().enumerate() {
        for s in &link.collision {
            let Ok((shape, shape_pose)) = s.geometry.collision_shape(false) else {
                continue;
            };
            let world = root * fk[l] * s.link_from_shape * shape_pose;
            if shape.compute_aabb(&world).mins.z >= below {
                continue;
            }
            let x = shape.compute_aabb(&(base_from_world * world)).maxs.x;
            if tracing::enabled!(tracing::Level::DEBUG) && x > 0.4 {
                tracing::debug!("link {} reaches {x:.2} m forward", link.name);
            }
            front = front.max(x);
        }
    }
    front
}

/// How far a base backs away from what it faces before driving back (m).
pub const BACK_OFF: f64 = 0.4;

/// Drives a mobile base back to `to` (world): when it is elsewhere it first backs
/// `back_off` away from whatever it faces, turns on the spot towards `to`, drives
/// straight, and turns to `to`'s heading — a base that turns while it drives sweeps its
/// corners into what it passes.
pub fn drive_back(
    driver: &mut impl RobotDriver,
    robot: &NamedRobot,
    to: &Pose,
    back_off: f64,
) -> Result<(), SkillError> {
    let base = world_from_base(robot, driver)?;
    let (h, h0) = (heading(&base), heading(to));
    let s = to.translation;
    let turned = (h - h0).sin().abs() > 0.03 || (h - h0).cos() < 0.0;
    if base.translation.truncate().distance(s.truncate()) <= 0.02 && !turned {
        return Ok(());
    }
    let back = base.translation - Vec3::new(h.cos(), h.sin(), 0.0) * back_off;
    driver.drive_to(back.x, back.y, h)?;
    let way = s - back;
    if way.truncate().length() > 0.05 {
        let toward = way.y.atan2(way.x);
        driver.drive_to(back.x, back.y, toward)?;
        driver.drive_to(s.x, s.y, toward)?;
    }
    driver.drive_to(s.x, s.y, h0)?;
    Ok(())
}

/// Steps the base straight ahead up to a support whose `outline` (world xy, convex)
/// has its top at `height`, until what reaches forward below that top stands `gap`
/// from the edge (a blocked drive stops where it stopped). Returns the base's pose
/// when it moved.
pub fn step_up_to(
    driver: &mut impl RobotDriver,
    robot: &NamedRobot,
    outline: &[Vec2],
    height: f64,
    gap: f64,
) -> Result<Option<Pose>, SkillError> {
    let base = world_from_base(robot, driver)?;
    let (state, root) = (driver.joint_state()?, driver.world_from_root()?);
    let centre = base.translation.truncate();
    // What reaches forward below the top (an elbow, a tucked arm) meets the edge, not
    // the base.
    let front =
        forward_extent(robot, &state, root, base, height + 0.05).max(base_half_extent(robot));
    let free = if inside_convex(outline, centre) {
        0.0
    } else {
        distance_to_boundary(outline, centre) - front
    };
    if free <= gap + 0.03 {
        return Ok(None);
    }
    let h = heading(&base);
    let to = base.translation + Vec3::new(h.cos(), h.sin(), 0.0) * (free - gap);
    match driver.drive_to(to.x, to.y, h) {
        Ok(()) | Err(DriverError::Blocked { .. }) => {}
        Err(e) => return Err(e.into()),
    }
    let moved = world_from_base(robot, driver)?;
    Ok((moved.translation.distance(base.translation) > 0.02).then_some(moved))
}
