//! The motions every manipulation is made of, run through the driver: one planned
//! phase, the way home, the arm's current joint values.

use super::SkillError;
use tabula_motion::{MoveGroup, Plan};
use tabula_robot::driver::RobotDriver;
use tabula_robot::robots::NamedRobot;

/// The group's arm joint values as the driver reports them now.
pub fn current_arm(
    driver: &mut impl RobotDriver,
    group: &MoveGroup,
) -> Result<Vec<f64>, SkillError> {
    Ok(group.arm_values(&driver.joint_state()?))
}

/// Executes one planned phase (`phase` names it in the debug log).
pub fn run_phase(
    driver: &mut impl RobotDriver,
    plan: &Plan,
    phase: &str,
) -> Result<(), SkillError> {
    if tracing::enabled!(tracing::Level::DEBUG) {
        let t = driver.joint_state().map(|s| s.stamp).unwrap_or(f64::NAN);
        tracing::debug!(
            "exec {phase} from t = {t:.2} s ({:.2} s)",
            plan.trajectory.duration()
        );
    }
    Ok(driver.execute(&plan.trajectory)?)
}

/// Plans from where the arm is to `home` (joint values) and goes there.
pub fn go_home(
    driver: &mut impl RobotDriver,
    robot: &NamedRobot,
    group: &mut MoveGroup,
    home: &[f64],
) -> Result<(), SkillError> {
    let state = driver.joint_state()?;
    group.set_state(robot, &state)?;
    let q = group.arm_values(&state);
    let plan = group.plan_to_joints(&q, &[home.to_vec()])?;
    run_phase(driver, &plan, "home")
}
