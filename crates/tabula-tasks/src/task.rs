//! One shape for every task (MoveIt Task Constructor's: a task is a named thing with a
//! request, parameters and a report, run against the robot's interfaces only): the CLI,
//! the benchmarks, the judges and the ROS services run any of them the same way.

use crate::skills::SkillError;
use tabula_geom::Vec3;
use tabula_geom::input::Validate;
use tabula_robot::driver::{DriverError, RobotDriver};
use tabula_robot::robots::NamedRobot;

/// What a watcher of a run is told, so a judge of the run can tell what the robot meant
/// to touch from what it touched by accident.
#[derive(Debug, Clone, PartialEq)]
pub enum Moment {
    /// An action is about to handle the object seen at `target` (world) and push
    /// along those seen at `shoved`.
    Acting { target: Vec3, shoved: Vec<Vec3> },
    /// The action ran.
    Done,
}

impl Moment {
    /// `Some((target, shoved))` while acting, `None` when done: the shape the
    /// simulator's clearing judge takes.
    pub fn judged(self) -> Option<(Vec3, Vec<Vec3>)> {
        match self {
            Moment::Acting { target, shoved } => Some((target, shoved)),
            Moment::Done => None,
        }
    }
}

/// Nobody watches.
pub fn unwatched<D>(_: &mut D, _: Moment) {}

/// A job the robot does.
pub trait Task {
    /// The name users call it by: the CLI command, the benchmark, the ROS service.
    const NAME: &'static str;
    /// What to do.
    type Request;
    /// How (seed defaults, loadable from TOML, checked before a run).
    type Params: Default + Clone + serde::de::DeserializeOwned + Validate;
    /// What happened: the task's report, and why it failed when it did.
    type Outcome;

    /// Runs the task through `driver`; `watch` is told the moments a judge needs.
    fn run<D: RobotDriver>(
        driver: &mut D,
        robot: &NamedRobot,
        request: &Self::Request,
        params: &Self::Params,
        watch: &mut dyn FnMut(&mut D, Moment),
    ) -> Self::Outcome;
}

/// Why a task could not start or had to stop, for tasks that need no kinds of their own.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum TaskError {
    #[error("driver: {0}")]
    Driver(String),
    #[error("robot: {0}")]
    Robot(String),
    #[error("perception: {0}")]
    Perception(String),
    #[error("parameter {0}")]
    Params(String),
}

impl TaskError {
    /// The typed reason reports and JSON carry.
    pub fn kind(&self) -> &'static str {
        match self {
            TaskError::Driver(_) => "driver",
            TaskError::Robot(_) => "robot",
            TaskError::Perception(_) => "perception",
            TaskError::Params(_) => "params",
        }
    }
}

impl From<DriverError> for TaskError {
    fn from(e: DriverError) -> Self {
        TaskError::Driver(e.to_string())
    }
}

impl From<SkillError> for TaskError {
    fn from(e: SkillError) -> Self {
        match e {
            SkillError::Robot(m) => TaskError::Robot(m),
            SkillError::Driver(m) => TaskError::Driver(m),
            other => TaskError::Driver(other.to_string()),
        }
    }
}

impl From<crate::scene::SceneError> for TaskError {
    fn from(e: crate::scene::SceneError) -> Self {
        match e {
            crate::scene::SceneError::Perception(m) => TaskError::Perception(m),
            crate::scene::SceneError::Driver(m) => TaskError::Driver(m),
        }
    }
}

/// An object a task did not get done, and why.
#[derive(Debug, Clone, serde::Serialize)]
pub struct Failure {
    /// Where it was seen (world, footprint centre at mid-height).
    pub object: [f64; 3],
    /// The typed reason (`no grasp`, `grasp slipped`, a placing error's kind, …).
    pub reason: String,
    pub message: String,
}

/// Clearing a cluttered table (seed 002).
pub struct Clear;

impl Task for Clear {
    const NAME: &'static str = "clear";
    type Request = crate::clear::ClearRequest;
    type Params = crate::clear::ClearParams;
    type Outcome = Result<crate::clear::ClearReport, crate::clear::ClearError>;

    fn run<D: RobotDriver>(
        driver: &mut D,
        robot: &NamedRobot,
        request: &Self::Request,
        params: &Self::Params,
        watch: &mut dyn FnMut(&mut D, Moment),
    ) -> Self::Outcome {
        crate::clear::clear(driver, robot, request, params, &mut |d, e| {
            watch(d, e.moment())
        })
    }
}

/// Placing a held, unknown object stably (seed 000).
pub struct Place;

impl Task for Place {
    const NAME: &'static str = "place";
    type Request = crate::place::PlaceRequest;
    type Params = crate::place::PlaceParams;
    type Outcome = crate::place::PlaceOutcome;

    fn run<D: RobotDriver>(
        driver: &mut D,
        robot: &NamedRobot,
        request: &Self::Request,
        params: &Self::Params,
        _watch: &mut dyn FnMut(&mut D, Moment),
    ) -> Self::Outcome {
        crate::place::place(driver, robot, request, params)
    }
}

/// Pick and place by coordinates (seed 001).
pub struct PickPlace;

impl Task for PickPlace {
    const NAME: &'static str = "pick-place";
    type Request = crate::pick_place::PickPlaceRequest;
    type Params = crate::pick_place::PickPlaceParams;
    type Outcome = crate::pick_place::PickPlaceOutcome;

    fn run<D: RobotDriver>(
        driver: &mut D,
        robot: &NamedRobot,
        request: &Self::Request,
        params: &Self::Params,
        _watch: &mut dyn FnMut(&mut D, Moment),
    ) -> Self::Outcome {
        crate::pick_place::pick_place(driver, robot, request, params)
    }
}
