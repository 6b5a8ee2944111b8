//! Placing an unknown object stably (seed 000, SPEC §1): the robot holds an object it
//! has no model of. It scans the object in its gripper before the head camera (Alg. 1),
//! finds how the scan rests stably with the gripper clear of the surface (Algs 2–7),
//! sweeps its head for surfaces (Alg. 9), finds a free spot where the resting
//! footprint fits away from edges and objects, drives its base to the surface when
//! it is out of reach (Alg. 10), and puts the object down (Algs 11–12): candidates are
//! free spots × roll angles, the first whose IK and motion plans all succeed is
//! executed, the gripper opens a few millimetres above the surface and backs away
//! along its approach.
//!
//! Stages report their time and, on failure, a typed reason, as MoveIt Task
//! Constructor's stages do.

mod body;
mod carry;
mod model;
mod outline;
mod params;
mod run;
mod sequence;
mod spot;
mod surfaces;
#[cfg(test)]
mod tests;
mod views;

pub use body::gripper_points;
pub use params::PlaceParams;

use crate::skills::Phase;
use crate::stable::StablePose;
use run::Run;
use tabula_geom::{Pose, Vec3};
use tabula_motion::MoveError;
use tabula_perception::freespace::FreeSpaceMap;
use tabula_robot::driver::{DriverError, RobotDriver};
use tabula_robot::robots::NamedRobot;

/// What to do: which arm holds the object (`None`: the one whose gripper is closed),
/// and surfaces not to put it on.
#[derive(Debug, Clone, Default)]
pub struct PlaceRequest {
    pub arm: Option<String>,
    /// A surface that has one of these points (world) over its outline, within 10 cm
    /// of its height, is not a target (where the object came from, say).
    pub not_on: Vec<Vec3>,
    /// Surfaces nearest this point (world) are tried first (`None`: nearest the robot).
    pub near: Option<Vec3>,
}

/// Why placing failed (typed, for `--json`'s `error`).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PlaceError {
    #[error("no arm holds an object")]
    NotHolding,
    #[error("the object could not be modelled: {0}")]
    Model(String),
    #[error("no stable pose leaves the gripper clear of the surface: {0}")]
    NoStablePose(String),
    #[error("no surface found: {0}")]
    NoSurface(String),
    #[error("no free spot fits the object: {0}")]
    NoRoom(String),
    #[error("the base could not get to the surface: {0}")]
    ApproachBlocked(String),
    #[error("unreachable: no spot the arm reaches")]
    Unreachable,
    #[error("no collision-free path: {0}")]
    NoPath(String),
    #[error("robot: {0}")]
    Driver(String),
}

impl PlaceError {
    /// The short type name in JSON.
    pub fn kind(&self) -> &'static str {
        match self {
            Self::NotHolding => "not holding",
            Self::Model(_) => "model",
            Self::NoStablePose(_) => "no stable pose",
            Self::NoSurface(_) => "no surface",
            Self::NoRoom(_) => "no room",
            Self::ApproachBlocked(_) => "approach blocked",
            Self::Unreachable => "unreachable",
            Self::NoPath(_) => "no collision-free path",
            Self::Driver(_) => "driver",
        }
    }
}

impl From<DriverError> for PlaceError {
    fn from(e: DriverError) -> Self {
        Self::Driver(e.to_string())
    }
}

impl From<MoveError> for PlaceError {
    fn from(e: MoveError) -> Self {
        match e {
            MoveError::Unreachable => Self::Unreachable,
            MoveError::World(w) => Self::Driver(w),
            other => Self::NoPath(other.to_string()),
        }
    }
}

/// The scanned model.
#[derive(Debug, Clone, Default, serde::Serialize)]
pub struct ModelReport {
    /// Views captured (of those tried).
    pub views: usize,
    pub views_tried: usize,
    /// Points of the model after downsampling.
    pub points: usize,
    pub hull_volume_m3: f64,
    /// Extent of the model in the tool frame (m).
    pub size: [f64; 3],
}

/// The surface chosen.
#[derive(Debug, Clone, serde::Serialize)]
pub struct SurfaceReport {
    /// Height of the surface at its centroid (m).
    pub height: f64,
    pub centroid: [f64; 3],
    pub area_m2: f64,
    pub tilt_deg: f64,
}

/// What a placement did.
#[derive(Debug, Clone, Default, serde::Serialize)]
pub struct PlaceReport {
    pub arm: Option<String>,
    pub model: Option<ModelReport>,
    /// Stable poses of the scanned model, and the one used.
    pub poses_found: usize,
    pub stable_pose: Option<StablePose>,
    pub surfaces_found: usize,
    pub surface: Option<SurfaceReport>,
    /// Where the base drove to (x, y, θ), when it did.
    pub base_goal: Option<[f64; 3]>,
    /// The tool's planned pose with the object resting on the surface (world): the
    /// object's predicted pose is this times its pose in the tool.
    pub planned_world_from_tool: Option<[f64; 7]>,
    pub phases: Vec<Phase>,
    /// CPU ms of every decision: modelling's processing, stable poses, surface search,
    /// free space, IK and motion planning — not the time the robot moves or the camera
    /// renders.
    pub decision_ms: f64,
    /// CPU ms of the scan's processing (self-filter, crop, accumulate, its motions).
    pub scan_cpu_ms: f64,
    pub candidates_tried: usize,
    pub rejected: Vec<String>,
    /// The model in the tool frame (for tests and reports).
    #[serde(skip)]
    pub model_points: Vec<Vec3>,
    /// The last surface's free-space map as the decision saw it (for reports).
    #[serde(skip)]
    pub top_view: Option<PlaceTopView>,
}

/// What the placement saw of the surface it chose: its free-space map and outline, the
/// objects on it (their points), and the footprint of the object resting where it was
/// planned to go (world, on the surface).
#[derive(Debug, Clone)]
pub struct PlaceTopView {
    pub map: FreeSpaceMap,
    pub outline: Vec<Vec3>,
    pub objects: Vec<Vec<Vec3>>,
    pub spot: Option<Vec<Vec3>>,
}

/// A placement's report and, when it failed, why.
#[derive(Debug, Clone)]
pub struct PlaceOutcome {
    pub report: PlaceReport,
    pub error: Option<PlaceError>,
}

/// Places the held object through `driver`.
pub fn place(
    driver: &mut impl RobotDriver,
    robot: &NamedRobot,
    request: &PlaceRequest,
    params: &PlaceParams,
) -> PlaceOutcome {
    let mut run = Run {
        robot,
        params,
        report: PlaceReport::default(),
        decision_cpu: 0.0,
        scan_cpu: 0.0,
        trace: tracing::enabled!(tracing::Level::DEBUG),
        template: None,
        scene_keys: Default::default(),
        near: Vec::new(),
        near_keys: Default::default(),
        held_reach: params.protective_radius,
        prefer_near: request.near,
    };
    let error = run.run(driver, request).err();
    let mut report = run.report;
    report.decision_ms = (run.decision_cpu - run.scan_cpu) * 1e3;
    report.scan_cpu_ms = run.scan_cpu * 1e3;
    PlaceOutcome { report, error }
}

fn pose_array(p: &Pose) -> [f64; 7] {
    let (t, q) = (p.translation, p.rotation);
    [t.x, t.y, t.z, q.x, q.y, q.z, q.w]
}
