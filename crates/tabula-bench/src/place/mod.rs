//! Placing (seed 000) judged in the simulator: one run's outcome and verdict together
//! (what `tabula place --json` prints), and the suites' trials (`bench place`).

mod trial;
mod truth;

pub use trial::{BenchRow, Suite, suite_of, task_of, trial, trial_of, worker_mesh_dir};

use crate::judged::run_in;
use serde::Serialize;
use tabula_sim::judge::StablePlaceVerdict;
use tabula_sim::{SimDriver, SimWorld};
use tabula_tasks::pick_place::Phase;
use tabula_tasks::place::{PlaceOutcome, PlaceParams, PlaceReport, PlaceRequest};
use tabula_tasks::stable::StablePose;
use tabula_tasks::task::Place;

/// A typed failure: its kind and its message.
#[derive(Debug, Clone, Serialize)]
pub struct TypedError {
    pub kind: String,
    pub message: String,
}

/// A placing run: the task's report and the judged outcome (`place --json`).
#[derive(Debug, Clone, Serialize)]
pub struct PlaceRun {
    pub success: bool,
    /// The furniture the object rests on (physics), and the surface perceived.
    pub surface: Option<String>,
    pub stable_pose: Option<StablePose>,
    /// Poses as x y z qx qy qz qw (world).
    pub predicted_pose: Option<[f64; 7]>,
    pub final_pose: [f64; 7],
    pub orientation_error_deg: f64,
    pub phases: Vec<Phase>,
    pub decision_ms: f64,
    pub error: Option<TypedError>,
    pub report: PlaceReport,
    pub verdict: StablePlaceVerdict,
    /// Run with `--dry-run`: no physics judged the verdict.
    pub dry_run: bool,
}

impl PlaceRun {
    /// The run from the task's outcome and the judge's verdict.
    pub fn of(outcome: PlaceOutcome, verdict: StablePlaceVerdict, dry_run: bool) -> Self {
        let error = outcome.error.as_ref().map(|e| TypedError {
            kind: e.kind().into(),
            message: e.to_string(),
        });
        Self {
            success: verdict.success && error.is_none(),
            surface: verdict.surface.clone(),
            stable_pose: outcome.report.stable_pose.clone(),
            predicted_pose: verdict.predicted_pose,
            final_pose: verdict.final_pose,
            orientation_error_deg: verdict.orientation_error_deg,
            phases: outcome.report.phases.clone(),
            decision_ms: outcome.report.decision_ms,
            error,
            report: outcome.report,
            verdict,
            dry_run,
        }
    }
}

/// One placement in `world` by its robot (`robot`, or the first), judged by physics;
/// `on_start` sees the driver first. The run and the world after.
pub fn place_in(
    world: SimWorld,
    robot: Option<&str>,
    (request, params): (&PlaceRequest, &PlaceParams),
    seed: u64,
    on_start: impl FnOnce(&mut SimDriver),
) -> anyhow::Result<(PlaceRun, SimWorld)> {
    let dry_run = world.kinematic_only;
    let (outcome, verdict, world) =
        run_in::<Place>(world, robot, (request, params, &()), seed, on_start)?;
    Ok((PlaceRun::of(outcome, verdict, dry_run), world))
}

/// The arm holding the scene's held object (the scene's `hold` says which gripper):
/// the task's precondition, as a user would state it.
pub fn held_by(world: &SimWorld, robot: &str) -> Option<String> {
    let r = world.robot(robot).ok()?;
    let object = world.held_objects(robot).into_iter().next()?;
    let at = world.pose(&object).ok()?.translation;
    r.description
        .arms
        .iter()
        .filter_map(|a| {
            let g = r
                .description
                .grippers
                .iter()
                .find(|g| Some(&g.name) == a.gripper.as_ref())?;
            let tool = world.link_pose(robot, &g.tool_link).ok()?;
            Some((tool.translation.distance(at), a.name.clone()))
        })
        .min_by(|a, b| a.0.total_cmp(&b.0))
        .map(|(_, n)| n)
}
