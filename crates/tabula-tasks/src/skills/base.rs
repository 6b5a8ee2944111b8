//! Where a mobile robot's base stands: its pose in the world (a planar base is three
//! joints of the model) and its heading.

use super::SkillError;
use tabula_geom::{Pose, Vec3};
use tabula_robot::driver::{JointState, RobotDriver};
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
