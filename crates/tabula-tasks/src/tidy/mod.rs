//! Tidying a table — a task made of the shared skills alone: a mobile robot takes every
//! object from one table (clearing's tabletop perception and top grasps) and puts each
//! one standing stably on another surface it finds by the surface search (placing's
//! scan, stable poses, free space and approach), then drives back for the next.

mod run;

pub use crate::task::Failure;

use crate::place::PlaceParams;
use crate::skills::grasp::TopGrasps;
use serde::Serialize;
use tabula_geom::Vec3;
use tabula_geom::input::{Validate, check_count, check_non_negative, nested};
use tabula_motion::MoveGroupParams;
use tabula_perception::tabletop::TabletopParams;
use tabula_robot::driver::RobotDriver;
use tabula_robot::robots::NamedRobot;

/// Parameters of tidying (defaults: clearing's and placing's seed values).
#[derive(Debug, Clone, serde::Deserialize, serde::Serialize)]
#[serde(default, deny_unknown_fields)]
pub struct TidyParams {
    /// The camera that looks at the table (the robot's head camera).
    pub camera: String,
    /// Frames decimated to every `decimate`-th pixel and row (as clearing's).
    pub decimate: usize,
    /// Self-filter padding (m), SPEC §1.1: 0.9 cm.
    pub self_filter_padding: f64,
    pub tabletop: TabletopParams,
    pub motion: MoveGroupParams,
    /// Top grasps (clearing's, SPEC §3.2, held by the top: the fingers' middle at the
    /// object's top).
    pub grasp: TopGrasps,
    /// Pre-grasp above the grasp and lift after it (m), SPEC §3.2: 10 and 20 cm.
    pub pregrasp: f64,
    pub lift: f64,
    /// Clearance the open hand keeps from other objects (m).
    pub clearance: f64,
    /// Placing the held object (seed 000).
    pub place: PlaceParams,
    /// Attempts per object before it is left where it is.
    pub max_attempts: usize,
}

impl Default for TidyParams {
    fn default() -> Self {
        let clear = crate::clear::ClearParams::default();
        Self {
            camera: "head".into(),
            decimate: clear.decimate,
            self_filter_padding: clear.self_filter_padding,
            tabletop: clear.tabletop.clone(),
            motion: MoveGroupParams::default(),
            // Held by its top: placing scans what hangs below the fingers, and the
            // hand's self-filter hides what is between them.
            grasp: TopGrasps {
                depth: 0.0,
                ..clear.grasp_planner().0
            },
            pregrasp: clear.pregrasp,
            lift: clear.lift,
            clearance: clear.clearance,
            place: PlaceParams::default(),
            max_attempts: 2,
        }
    }
}

impl Validate for TidyParams {
    fn check(&self, at: &str) -> Result<(), String> {
        self.tabletop.check(&nested(at, "tabletop"))?;
        self.motion.check(&nested(at, "motion"))?;
        self.place.check(&nested(at, "place"))?;
        self.grasp.check(&nested(at, "grasp"))?;
        check_count(at, "decimate", self.decimate, 1)?;
        check_count(at, "max_attempts", self.max_attempts, 1)?;
        for (name, v) in [
            ("self_filter_padding", self.self_filter_padding),
            ("pregrasp", self.pregrasp),
            ("lift", self.lift),
            ("clearance", self.clearance),
        ] {
            check_non_negative(at, name, v)?;
        }
        Ok(())
    }
}

/// What to tidy: the arm (`None`: the robot's first arm with a gripper), a point on the
/// table to clear (world; `None`: 0.8 m ahead of the robot at 0.75 m), and a point on
/// the surface to fill (`None`: whichever the search finds first).
#[derive(Debug, Clone, Default)]
pub struct TidyRequest {
    pub arm: Option<String>,
    pub from: Option<Vec3>,
    pub to: Option<Vec3>,
}

/// What a tidying run did.
#[derive(Debug, Clone, Default, Serialize)]
pub struct TidyReport {
    /// Objects seen on the table in the first frame.
    pub objects: usize,
    /// Objects the task put down on another surface (the judge says where they rest).
    pub placed: usize,
    /// Grasps and placements tried.
    pub actions: usize,
    pub failed: Vec<Failure>,
    /// CPU ms of each decision (perception → grasp choice; placing's own decisions).
    pub decision_ms: crate::clear::Stats,
    /// Why the loop ended.
    pub stop: String,
}

/// Why tidying could not start or had to stop.
pub type TidyError = crate::task::TaskError;

/// Tidies the table: see the module's documentation.
pub fn tidy<D: RobotDriver>(
    driver: &mut D,
    robot: &NamedRobot,
    request: &TidyRequest,
    params: &TidyParams,
) -> Result<TidyReport, TidyError> {
    params.check("").map_err(TidyError::Params)?;
    run::Run::new(driver, robot, request, params)?.run()
}

/// Tidying a table (the fourth task, from the skills alone).
pub struct Tidy;

impl crate::task::Task for Tidy {
    const NAME: &'static str = "tidy";
    type Request = TidyRequest;
    type Params = TidyParams;
    type Outcome = Result<TidyReport, TidyError>;

    fn run<D: RobotDriver>(
        driver: &mut D,
        robot: &NamedRobot,
        request: &Self::Request,
        params: &Self::Params,
        _watch: &mut dyn FnMut(&mut D, crate::task::Moment),
    ) -> Self::Outcome {
        tidy(driver, robot, request, params)
    }
}
