//! The motions every manipulation is made of, run through the driver: one planned
//! phase, the way home, the arm's current joint values.

use super::SkillError;
use tabula_geom::Pose;
use tabula_geom::parry::shape::SharedShape;
use tabula_motion::{MoveGroup, Plan};
use tabula_robot::driver::{JointState, RobotDriver};
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

/// Brings each of `arms` back to its values in `ready` (planned with `template`'s
/// settings, around `table` when one is given) before the base drives: an arm left low
/// beside the body sweeps into tables. An arm that cannot get there stays where it is.
pub fn arms_to(
    driver: &mut impl RobotDriver,
    robot: &NamedRobot,
    (template, arms): (&MoveGroup, &[super::hand::HandArm]),
    ready: &JointState,
    table: Option<&SharedShape>,
) {
    let Ok(state) = driver.joint_state() else {
        return;
    };
    for arm in arms {
        let Ok(mut g) = template.for_arm(robot, &arm.arm) else {
            continue;
        };
        if g.set_state(robot, &state).is_err() {
            continue;
        }
        if let Some(table) = table {
            let _ = g.add_object("table", table.clone(), Pose::IDENTITY);
        }
        let (now, goal) = (g.arm_values(&state), g.arm_values(ready));
        if now.iter().zip(&goal).all(|(a, b)| (a - b).abs() < 0.05) {
            continue;
        }
        if let Ok(plan) = g.plan_to_joints(&now, &[goal]) {
            let _ = run_phase(driver, &plan, "arm in");
        }
    }
}
