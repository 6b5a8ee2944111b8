//! Where a mobile robot's base stands: its pose in the world (a planar base is three
//! joints of the model) and its heading.

use super::SkillError;
use tabula_geom::{Pose, Vec3};
use tabula_robot::driver::RobotDriver;
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
