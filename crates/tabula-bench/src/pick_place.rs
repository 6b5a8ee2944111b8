//! Pick and place by coordinates (seed 001) judged in the simulator: one run's outcome
//! and verdict together (what `tabula pick-place --json` prints), and the generated
//! shelf tasks' trials (`bench pick-place`).

use crate::judged::run_in;
use anyhow::Result;
use serde::Serialize;
use tabula_geom::Vec3;
use tabula_sim::generate::{RobotMount, ShelfTask};
use tabula_sim::judge::PlaceVerdict;
use tabula_sim::{SimDriver, SimWorld};
use tabula_tasks::pick_place::{PickPlaceOutcome, PickPlaceParams, PickPlaceRequest};
use tabula_tasks::task::PickPlace;

/// A pick-and-place run: the task's report and the judged outcome.
#[derive(Serialize)]
pub struct PickPlaceRun {
    pub success: bool,
    pub error: Option<String>,
    pub error_message: Option<String>,
    #[serde(flatten)]
    pub report: tabula_tasks::pick_place::PickPlaceReport,
    pub verdict: PlaceVerdict,
    pub final_pose: [f64; 6],
    /// Run with `--dry-run`: no physics judged the verdict.
    pub dry_run: bool,
}

impl PickPlaceRun {
    /// The run from the task's outcome and the judge's verdict.
    pub fn of(outcome: PickPlaceOutcome, mut verdict: PlaceVerdict, dry_run: bool) -> Self {
        verdict.success &= outcome.error.is_none();
        Self {
            success: verdict.success,
            error: outcome.error.as_ref().map(|e| e.kind().to_string()),
            error_message: outcome.error.as_ref().map(|e| e.to_string()),
            report: outcome.report,
            final_pose: verdict.final_pose,
            verdict,
            dry_run,
        }
    }
}

/// A pick and place in `world` by its robot (`robot`, or the first), judged by physics;
/// `on_start` sees the driver first. The run and the world after.
pub fn pick_place_in(
    world: SimWorld,
    robot: Option<&str>,
    (request, params): (&PickPlaceRequest, &PickPlaceParams),
    seed: u64,
    on_start: impl FnOnce(&mut SimDriver),
) -> Result<(PickPlaceRun, SimWorld)> {
    let dry_run = world.kinematic_only;
    let params = &with_scene_camera(&world, params);
    let (outcome, verdict, world) =
        run_in::<PickPlace>(world, robot, (request, params, &()), seed, on_start)?;
    Ok((PickPlaceRun::of(outcome, verdict, dry_run), world))
}

/// `params` looking with the scene's one camera when it has none of the name asked (a
/// fixed arm under an overhead camera has no `head`); the name asked otherwise, so a
/// missing camera among several is still an error naming it.
fn with_scene_camera(world: &SimWorld, params: &PickPlaceParams) -> PickPlaceParams {
    let mut params = params.clone();
    if let ([only], Err(_)) = (world.cameras.as_slice(), world.camera(&params.camera)) {
        tracing::info!(
            "pick-place: no camera `{}` in the scene; looking with its only camera `{}`",
            params.camera,
            only.name.get_ref()
        );
        params.camera = only.name.get_ref().clone();
    }
    params
}

/// One generated shelf task's row (`bench pick-place`).
#[derive(Serialize)]
pub struct BenchRow {
    pub seed: u64,
    pub target: String,
    pub success: bool,
    pub arm: Option<String>,
    pub error: Option<String>,
    pub decision_cpu_ms: f64,
    pub target_error_cm: f64,
}

/// Generated shelf task `seed` moved by Golem-III and judged.
pub fn trial(seed: u64) -> Result<BenchRow> {
    run_task(seed, tabula_sim::generate::golem_shelf_task(seed))
}

/// Task `seed` of the table family with `mount`'s robot (`bench pick-place --robot`):
/// an object standing alone on the clearing cell's table taken to a free spot of it.
pub fn table_trial(seed: u64, mount: &RobotMount) -> Result<BenchRow> {
    let task = tabula_sim::generate::table_pick_place_task(seed, mount)
        .ok_or_else(|| anyhow::anyhow!("table task {seed}: no object stands alone"))?;
    run_task(seed, task)
}

/// One generated task moved by the scene's robot and judged.
fn run_task(seed: u64, task: ShelfTask) -> Result<BenchRow> {
    let scene = tabula_sim::Scene::parse(&task.scene, "generated")?;
    let world = SimWorld::from_scene(&scene, Default::default())?;
    let request = PickPlaceRequest {
        arm: None,
        pick: Vec3::from_array(task.pick),
        place: Vec3::from_array(task.place),
    };
    let params = PickPlaceParams::default();
    let (out, _) = pick_place_in(world, None, (&request, &params), seed, |_| {})?;
    Ok(BenchRow {
        seed,
        target: task.target,
        success: out.success,
        arm: out.report.arm.clone(),
        error: out
            .error_message
            .clone()
            .map(|e| match out.report.rejected.last() {
                Some(why) => format!("{e} (last: {why})"),
                None => e,
            })
            .or_else(|| (!out.success).then(|| format!("{:?}", out.verdict))),
        decision_cpu_ms: out.report.decision_cpu_ms,
        target_error_cm: out.verdict.target_error * 100.0,
    })
}
