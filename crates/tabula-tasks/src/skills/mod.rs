//! Skills the tasks share (the shape of MoveIt Task Constructor's stages): the hand's
//! geometry, grasp planners behind one trait, the motions a manipulation is made of,
//! and one error type that task errors wrap.
//!
//! * [`base`]: where a mobile robot's base stands.
//! * [`jog`]: the tool stepped along or about an axis (tele-operation).
//! * [`hand`]: the gripper's collision shapes, open and closed, and tool poses.
//! * [`grasp`]: [`GraspPlanner`] and its planners.
//! * [`motion`]: running a planned phase, going home, the arm's current values.
//! * [`pick`]: taking an object off a tabletop and carrying it.
//! * [`phase`]: the phase recorder every task reports its stages with.
//! * [`reach`]: which object to pick with which hand.
//! * [`world`]: the seen objects in the planning world.

/// What a task says when the robot has no gripper to grasp with, and how to give it one.
pub const NO_GRIPPER: &str = "no arm with a gripper (an SRDF end effector counts when \
    its fingers are prismatic, one mimicking the other; otherwise describe the gripper in \
    a TOML beside the URDF: `tabula robot describe` prints a template)";

pub mod base;
pub mod carried;
pub mod grasp;
pub mod hand;
pub mod jog;
pub mod motion;
pub mod phase;
pub mod pick;
pub mod reach;
pub mod world;

pub use grasp::{GraspCandidate, GraspKind, GraspPlanner, GraspTarget};
pub use hand::Hand;
pub use phase::Phase;

use tabula_motion::MoveError;
use tabula_robot::description::{ArmGroup, Gripper};
use tabula_robot::driver::DriverError;
use tabula_robot::robots::NamedRobot;

/// The arm named `arm` (else the robot's first arm with a gripper) and its gripper.
pub fn arm_with_gripper(
    robot: &NamedRobot,
    arm: Option<&str>,
) -> Result<(ArmGroup, Gripper), SkillError> {
    let name = match arm {
        Some(a) => a.to_string(),
        None => robot
            .description
            .arms
            .iter()
            .find(|a| a.gripper.is_some())
            .map(|a| a.name.clone())
            .ok_or_else(|| SkillError::Robot(NO_GRIPPER.into()))?,
    };
    let arm = robot
        .description
        .arm(&name)
        .map_err(|e| SkillError::Robot(e.to_string()))?
        .clone();
    let gripper = robot
        .description
        .gripper_of(&arm)
        .cloned()
        .ok_or_else(|| SkillError::Robot(format!("arm `{name}` has no gripper")))?;
    Ok((arm, gripper))
}

/// Why a skill could not be set up or failed while it ran.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SkillError {
    /// The robot's description lacks what the skill needs (a finger joint, a link).
    #[error("robot: {0}")]
    Robot(String),
    /// No motion could be planned.
    #[error("motion: {0}")]
    Motion(String),
    /// The gripper closed and holds nothing.
    #[error("the gripper closed on nothing")]
    Slipped,
    /// After the lift the camera saw this many points hanging with the hand outside
    /// the held object: another object came up with it. It was put back down.
    #[error("lifted another object with it ({0} points seen hanging with the hand); put back")]
    CarriedAlong(usize),
    /// The robot (driver) refused or failed a command.
    #[error("driver: {0}")]
    Driver(String),
}

impl From<MoveError> for SkillError {
    fn from(e: MoveError) -> Self {
        SkillError::Motion(e.to_string())
    }
}

impl From<DriverError> for SkillError {
    fn from(e: DriverError) -> Self {
        SkillError::Driver(e.to_string())
    }
}
