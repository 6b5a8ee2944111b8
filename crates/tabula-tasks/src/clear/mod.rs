//! Clearing a cluttered table — seed 002's system (SPEC §3): perceive the table, compute
//! the predicates from geometry, plan with the seed's PDDL domain in process, check IK
//! for the first action only (backtracking by `ik_unfeasible_*` facts), execute it
//! through the driver — a grasp that drops the object into the bin, or a push with the
//! closed gripper — and start again from a new frame.
//!
//! Beyond the seed (SPEC §3.7): a push is as long as it takes for the object's grasp to
//! become free (not k × its box), objects are tracked across frames so none is pushed
//! back where it came from, and every approach and transfer is planned collision-free
//! against the other objects' hulls and the workcell.
//!
//! The loop (`run`) goes frame by frame: [`crate::scene::tabletop`] → `track` → `predicates`
//! (with `push`) → `decide` (the planner, built by `problem`; `fallback` when it
//! is stuck) → `act` and `execute`.

mod act;
mod decide;
mod execute;
mod fallback;
mod first;
mod left;
mod params;
mod predicates;
mod problem;
mod push;
mod report;
mod run;
mod split;
#[cfg(test)]
mod tests;
mod track;

pub use crate::scene::SeenObject;
pub use first::AtRisk;
pub use left::LeftObject;
pub use params::ClearParams;
pub use report::{ActionRecord, ClearReport, FrameReport, Stats};
pub use run::clear;

use crate::scene::{Table, hits, hulls_collide, on_pairs, translated};
use crate::skills::SkillError;
use serde::Serialize;
use tabula_geom::Pose;
use tabula_geom::Vec3;
use tabula_geom::parry::shape::SharedShape;
use tabula_robot::driver::DriverError;

/// Seed 002's domain with `(not (removed ?o))` in every precondition (`pddl/README.md`).
const DOMAIN: &str = include_str!("../../../../pddl/tablewclear-domain-fixed.pddl");

/// The four push directions of SPEC §3.2, in the domain's order: along the object's
/// principal (longer) footprint axis, against it, along the other axis, against it.
const DIRECTIONS: [&str; 4] = ["dir1", "dir2", "dir3", "dir4"];

/// What to clear and where things go.
#[derive(Debug, Clone)]
pub struct ClearRequest {
    /// The arm to use (default: the robot's first arm with a gripper).
    pub arm: Option<String>,
    /// Where objects are let go (world): the centre of the bin's opening.
    pub drop_point: Vec3,
    /// Objects are let go over a square this far around `drop_point` (m), one spot after
    /// another, so they do not pile into a tower.
    pub drop_spread: f64,
    /// The workcell's fixed obstacles (world), as a planning scene knows them.
    pub obstacles: Vec<(String, SharedShape, Pose)>,
    /// Stop after this many actions (default: 3 per object seen first, plus 5).
    pub max_actions: Option<usize>,
}

/// An action of the domain on a tracked object.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ActionKind {
    Grasp,
    Push(usize),
}

impl ActionKind {
    pub(crate) fn pddl(self) -> String {
        match self {
            ActionKind::Grasp => "grasp".into(),
            ActionKind::Push(k) => format!("push_{}", DIRECTIONS[k]),
        }
    }
}

/// Why a run could not start or had to stop.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ClearError {
    #[error("driver: {0}")]
    Driver(String),
    #[error("robot: {0}")]
    Robot(String),
    #[error("perception: {0}")]
    Perception(String),
    #[error("planner: {0}")]
    Planner(String),
    #[error("parameter {0}")]
    Params(String),
}

impl ClearError {
    pub fn kind(&self) -> &'static str {
        match self {
            ClearError::Driver(_) => "driver",
            ClearError::Robot(_) => "robot",
            ClearError::Perception(_) => "perception",
            ClearError::Planner(_) => "planner",
            ClearError::Params(_) => "params",
        }
    }
}

impl From<DriverError> for ClearError {
    fn from(e: DriverError) -> Self {
        ClearError::Driver(e.to_string())
    }
}

impl From<SkillError> for ClearError {
    fn from(e: SkillError) -> Self {
        match e {
            SkillError::Robot(m) => ClearError::Robot(m),
            other => ClearError::Driver(other.to_string()),
        }
    }
}

/// What a watcher of the run is told (the simulator's harness counts collisions and
/// objects moved by accident with it).
#[derive(Debug, Clone, Copy)]
pub enum ClearEvent<'a> {
    /// An action is about to run on the object seen at `position`.
    Before(&'a ActionRecord),
    /// It ran.
    After(&'a ActionRecord),
}

impl ClearEvent<'_> {
    /// The moment a judge of the run is told: before an action, where the object it
    /// acts on and those it shoves along were seen.
    pub fn moment(&self) -> crate::task::Moment {
        match self {
            ClearEvent::Before(a) => crate::task::Moment::Acting {
                target: Vec3::from_array(a.position),
                shoved: a.shoves.iter().map(|p| Vec3::from_array(*p)).collect(),
            },
            ClearEvent::After(_) => crate::task::Moment::Done,
        }
    }

    /// Before an action: where the object it acts on and those it shoves along were
    /// seen; `None` after it (the shape the simulator's clearing judge takes).
    pub fn judged(&self) -> Option<(Vec3, Vec<Vec3>)> {
        self.moment().judged()
    }
}
