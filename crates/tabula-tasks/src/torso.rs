//! Seed 000 §1.6 (its Module 0): a run starts by raising the torso, as Willow Garage
//! advises for the PR2 — the shoulders rise above the tables, the arms reach down onto
//! them, and the head sees more of the room.

use tabula_robot::driver::{DriverError, JointTrajectory, RobotDriver};
use tabula_robot::model::JointKind;
use tabula_robot::robots::NamedRobot;

/// Raises the robot's torso lift (the prismatic joint among its description's
/// `torso_joints`) to the top of its range at the joint's velocity limit. Only ever up:
/// the upper body rises away from the base, so the move cannot run into the robot.
/// Returns the height reached, or `None` for a robot without a lift.
pub fn raise_torso(
    driver: &mut impl RobotDriver,
    robot: &NamedRobot,
) -> Result<Option<f64>, DriverError> {
    let Some(j) = robot
        .description
        .torso_joints
        .iter()
        .filter_map(|n| robot.model.joint(n))
        .find(|&j| robot.model.joints[j].kind == JointKind::Prismatic)
    else {
        return Ok(None);
    };
    let joint = &robot.model.joints[j];
    let limits = joint.limits;
    let state = driver.joint_state()?;
    let now = state
        .get(&joint.name)
        .unwrap_or_else(|| robot.model.mid_configuration()[j]);
    if !limits.upper.is_finite() || now >= limits.upper - 1e-6 {
        return Ok(Some(now));
    }
    let speed = if limits.velocity.is_finite() && limits.velocity > 0.0 {
        limits.velocity
    } else {
        0.05
    };
    driver.execute(&JointTrajectory {
        joint_names: vec![joint.name.clone()],
        times: vec![0.0, (limits.upper - now) / speed],
        positions: vec![vec![now], vec![limits.upper]],
    })?;
    Ok(Some(limits.upper))
}
