//! Pick and place by coordinates — seed 001's integral test (SPEC §2.5): given the
//! approximate world position of an object and a target position, look at both with
//! the head camera, find the object and the surfaces, choose an arm and a grasp (side
//! or top; shelf boards leave only side grasps), plan every motion — approach, grasp,
//! lift, retreat, transfer, place, release, retreat, home — without touching anything
//! but the object, then execute it through the driver.
//!
//! The shape follows MoveIt Task Constructor's pick/place: the grasp generator proposes
//! candidates, each candidate is planned stage by stage, the first that plans whole is
//! executed, and every stage reports its time and, on failure, why.
//!
//! The loop (`run`): `look` around with the head (what other hands `held` is
//! taken out), perceive the object, the target and the occupancy (`scene`), propose
//! `grasps` per arm, plan each candidate's `sequence` of stages, execute the first
//! that plans whole.

mod grasps;
mod held;
mod look;
mod params;
mod run;
mod scene;
mod sequence;

pub use crate::skills::{GraspKind, Phase};
pub use params::PickPlaceParams;

use tabula_geom::Vec3;
use tabula_motion::MoveError;
use tabula_robot::driver::{DriverError, RobotDriver};
use tabula_robot::robots::NamedRobot;

/// What to do: an arm (`None`: whichever can), where the object is, where it goes —
/// both approximate world positions (the object's centre; the surfaces are found
/// under them).
#[derive(Debug, Clone)]
pub struct PickPlaceRequest {
    pub arm: Option<String>,
    pub pick: Vec3,
    pub place: Vec3,
}

/// Why a pick and place failed (typed, for `--json`'s `error`).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PickPlaceError {
    #[error("the object was not found: {0}")]
    ObjectNotFound(String),
    #[error("no surface at the target: {0}")]
    NoSurface(String),
    #[error("the target is occupied: {points} points stand there, around ({:.3}, {:.3}, {:.3})", at[0], at[1], at[2])]
    TargetOccupied { points: usize, at: [f64; 3] },
    #[error("the object ({0:.3} m across) is wider than the gripper opens")]
    TooWide(f64),
    #[error("unreachable: no arm reaches a grasp and a placement")]
    Unreachable,
    #[error("no collision-free path: {0}")]
    NoPath(String),
    #[error("grasp slipped: the gripper closed on nothing")]
    GraspSlipped,
    #[error("the {0} arm's gripper already holds something")]
    HandFull(String),
    #[error("robot: {0}")]
    Driver(String),
}

impl PickPlaceError {
    /// The short type name in JSON (`unreachable`, `no collision-free path`, …).
    pub fn kind(&self) -> &'static str {
        match self {
            Self::ObjectNotFound(_) => "object not found",
            Self::NoSurface(_) => "no surface",
            Self::TargetOccupied { .. } => "target occupied",
            Self::TooWide(_) => "too wide",
            Self::Unreachable => "unreachable",
            Self::NoPath(_) => "no collision-free path",
            Self::GraspSlipped => "grasp slipped",
            Self::HandFull(_) => "hand full",
            Self::Driver(_) => "driver",
        }
    }
}

impl From<DriverError> for PickPlaceError {
    fn from(e: DriverError) -> Self {
        Self::Driver(e.to_string())
    }
}

/// The object as perceived.
#[derive(Debug, Clone, serde::Serialize)]
pub struct ObjectReport {
    /// Footprint centre at the object's bottom (world).
    pub position: [f64; 3],
    /// Footprint sides and height (m).
    pub size: [f64; 3],
    pub points: usize,
}

/// What a pick and place did.
#[derive(Debug, Clone, Default, serde::Serialize)]
pub struct PickPlaceReport {
    pub arm: Option<String>,
    pub grasp: Option<GraspKind>,
    pub object: Option<ObjectReport>,
    /// Height of the target surface (m).
    pub target_surface: Option<f64>,
    /// Where the object's bottom centre was planned to be released (world).
    pub planned_object_position: Option<[f64; 3]>,
    pub phases: Vec<Phase>,
    /// CPU ms from the first frame to the last motion plan (perceive → grasp choice →
    /// every plan), not counting the one-off allowed-collision sampling.
    pub decision_cpu_ms: f64,
    /// Grasp candidates planned before one planned whole.
    pub candidates_tried: usize,
    /// Why each rejected candidate failed (arm, grasp, stage, reason), as MoveIt Task
    /// Constructor's stages explain their failures.
    pub rejected: Vec<String>,
    /// Grippers found holding something at the start; it stays held, and planning
    /// carries it with them.
    pub held_elsewhere: Vec<String>,
    /// Every motion executed, in order (for replays and checks).
    #[serde(skip)]
    pub trajectories: Vec<tabula_robot::driver::JointTrajectory>,
}

/// A pick and place's report and, when it failed, why.
#[derive(Debug, Clone)]
pub struct PickPlaceOutcome {
    pub report: PickPlaceReport,
    pub error: Option<PickPlaceError>,
}

/// Runs a pick and place through `driver`.
pub fn pick_place(
    driver: &mut impl RobotDriver,
    robot: &NamedRobot,
    request: &PickPlaceRequest,
    params: &PickPlaceParams,
) -> PickPlaceOutcome {
    let mut report = PickPlaceReport::default();
    let error = run::run(driver, robot, request, params, &mut report).err();
    PickPlaceOutcome { report, error }
}

fn motion_error(e: MoveError) -> PickPlaceError {
    match e {
        MoveError::Unreachable => PickPlaceError::Unreachable,
        MoveError::GoalInCollision(why) => {
            PickPlaceError::NoPath(format!("every IK solution collides: {why}"))
        }
        other => PickPlaceError::NoPath(other.to_string()),
    }
}
