//! Clearing (seed 002) judged in the simulator: one run's outcome and verdict together
//! (what `tabula clear --json` prints), and the suites' trials (`bench clear`).

use crate::judged::run_in;
use crate::spec::TrialSpec;
use crate::stats::wilson;
use anyhow::{Result, anyhow};
use serde::{Deserialize, Serialize};
use tabula_sim::generate::{ClearSuite, RobotMount, clearing_scene_with};
use tabula_sim::judge::{ClearSetup, ClearVerdict};
use tabula_sim::{SimDriver, SimWorld};
use tabula_tasks::clear::{ClearError, ClearParams, ClearReport, ClearRequest, Stats};
use tabula_tasks::task::Clear;

/// The furniture a clearing scene clears, and the bin it clears into.
pub const TABLE: &str = "table";
pub const BIN: &str = "bin";

/// A clearing run: the task's own metrics and the judged ones (`clear --json`).
#[derive(Serialize)]
pub struct ClearRun {
    /// Every object that stood on the table (if any) ended in the bin.
    pub success: bool,
    pub error: Option<String>,
    pub error_message: Option<String>,
    #[serde(flatten)]
    pub report: ClearReport,
    /// Arm–object contacts with objects the arm was not acting on (judged).
    pub collisions: usize,
    pub verdict: ClearVerdict,
}

impl ClearRun {
    /// The run from the task's outcome and the judge's verdict.
    pub fn of(outcome: Result<ClearReport, ClearError>, verdict: ClearVerdict) -> Self {
        let (report, error) = match outcome {
            Ok(r) => (r, None),
            Err(e) => (ClearReport::default(), Some(e)),
        };
        Self {
            success: error.is_none() && verdict.in_bin == verdict.objects,
            error: error.as_ref().map(|e| e.kind().to_string()),
            error_message: error.as_ref().map(|e| e.to_string()),
            report,
            collisions: verdict.collisions.len(),
            verdict,
        }
    }
}

/// What a clearing task is asked, from what the workcell tells it.
pub fn request(setup: &ClearSetup, max_actions: Option<usize>) -> ClearRequest {
    ClearRequest {
        arm: None,
        drop_point: setup.drop_point,
        drop_spread: setup.drop_spread,
        obstacles: setup.obstacles.clone(),
        max_actions,
    }
}

/// Clears the table of `world` with its robot (`robot`, or the first) into the bin,
/// judged by physics; `on_start` sees the driver first. The run and the world after.
pub fn clear_in(
    world: SimWorld,
    robot: Option<&str>,
    (params, max_actions): (&ClearParams, Option<usize>),
    seed: u64,
    on_start: impl FnOnce(&mut SimDriver),
) -> Result<(ClearRun, SimWorld)> {
    let request = request(&ClearSetup::of(&world, BIN)?, max_actions);
    let ground = (TABLE.to_string(), BIN.to_string());
    let (outcome, verdict, world) =
        run_in::<Clear>(world, robot, (&request, params, &ground), seed, on_start)?;
    Ok((ClearRun::of(outcome, verdict), world))
}

/// One scene's row in a clearing suite.
#[derive(Serialize, Deserialize)]
pub struct BenchRow {
    pub seed: u64,
    pub objects: usize,
    pub in_bin: usize,
    pub actions: usize,
    pub grasps: usize,
    pub failed_grasps: usize,
    pub pushes: usize,
    pub no_plan_frames: usize,
    pub ik_backtracks: usize,
    pub push_loops: usize,
    pub collisions: usize,
    pub disturbed: usize,
    /// Objects knocked or dropped off the table (neither in the bin nor on it).
    #[serde(default)]
    pub off_table: usize,
    pub decision_median_ms: f64,
    pub stop: String,
    /// Cleared without error (every object on the table in the bin).
    pub success: bool,
}

/// One scene of a clearing suite, cleared in the simulator and judged by physics: its
/// row and each frame's decision time and its parts (decision, perception,
/// predicates, planning, IK; ms).
#[derive(Serialize, Deserialize)]
pub struct Trial {
    pub row: BenchRow,
    pub frames: Vec<[f64; 5]>,
}

/// Scene `s` of `suite`, cleared and judged.
pub fn trial(suite: ClearSuite, s: u64, params: &ClearParams) -> Result<Trial> {
    trial_with(suite, s, params, None)
}

/// [`trial`] with another robot in the cell (`mount`, see [`crate::mount`]).
pub fn trial_with(
    suite: ClearSuite,
    s: u64,
    params: &ClearParams,
    mount: Option<&RobotMount>,
) -> Result<Trial> {
    let text = clearing_scene_with(suite, s, mount);
    let scene = tabula_sim::Scene::parse(&text, "generated")?;
    let world = SimWorld::from_scene(&scene, Default::default())?;
    let (out, _) = clear_in(world, None, (params, None), s, |_| {})?;
    let (r, v) = (&out.report, &out.verdict);
    let frames = r
        .frames
        .iter()
        .map(|f| {
            [
                f.decision_ms,
                f.perception_ms,
                f.predicates_ms,
                f.planning_ms,
                f.ik_ms,
            ]
        })
        .collect();
    let row = BenchRow {
        seed: s,
        objects: v.objects,
        in_bin: v.in_bin,
        actions: r.actions,
        grasps: r.grasps,
        failed_grasps: r.failed_grasps,
        pushes: r.pushes,
        no_plan_frames: r.no_plan_frames,
        ik_backtracks: r.ik_backtracks,
        push_loops: r.push_loops,
        collisions: out.collisions,
        disturbed: v.disturbed.len(),
        off_table: v.off_table,
        decision_median_ms: r.decision_ms.median,
        stop: match &out.error_message {
            Some(e) => e.clone(),
            None => r.stop.clone(),
        },
        success: out.success,
    };
    Ok(Trial { row, frames })
}

/// A clearing trial as a worker is asked it.
pub fn trial_of(spec: &TrialSpec) -> Result<Trial> {
    let suite: ClearSuite = spec.suite.parse().map_err(|e: String| anyhow!(e))?;
    let params: ClearParams = match &spec.params {
        Some(text) => tabula_geom::input::parse_params(text, "the bench's parameters")?,
        None => ClearParams::default(),
    };
    trial(suite, spec.seed, &params)
}

/// A suite's summary (`bench clear --json`; fields in the order JSON has always listed
/// them): completion with its 95 % interval, scenes cleared, objects per action, grasp
/// success, pushes, collisions, decision times and their parts, and every row.
#[derive(Serialize)]
pub struct Summary<'a> {
    pub actions: usize,
    pub collisions: usize,
    pub completion: f64,
    pub completion_95: [f64; 2],
    pub decision_ms: Stats,
    pub disturbed: usize,
    pub failed_grasps: usize,
    pub frames: usize,
    pub grasp_success: f64,
    pub grasps: usize,
    pub ik_backtracks: usize,
    pub ik_ms: f64,
    pub no_plan_frames: usize,
    pub objects: usize,
    pub objects_per_action: f64,
    pub off_table: usize,
    pub perception_ms: f64,
    pub planning_ms: f64,
    pub predicates_ms: f64,
    pub push_loops: usize,
    pub pushes: usize,
    pub removed: usize,
    pub rows: &'a [BenchRow],
    pub scenes: usize,
    pub scenes_cleared: usize,
    pub suite: &'a str,
}

impl<'a> Summary<'a> {
    /// The summary of `suite`'s rows and every frame's times (see [`Trial`]).
    pub fn of(suite: &'a str, rows: &'a [BenchRow], frames: &[[f64; 5]]) -> Self {
        let sum = |f: fn(&BenchRow) -> usize| rows.iter().map(f).sum::<usize>();
        let (objects, removed, actions) =
            (sum(|r| r.objects), sum(|r| r.in_bin), sum(|r| r.actions));
        let (grasps, failed_grasps) = (sum(|r| r.grasps), sum(|r| r.failed_grasps));
        let (lo, hi) = wilson(removed, objects);
        let col = |k: usize| Stats::of(&frames.iter().map(|f| f[k]).collect::<Vec<_>>());
        Self {
            actions,
            collisions: sum(|r| r.collisions),
            completion: removed as f64 / objects.max(1) as f64,
            completion_95: [lo, hi],
            decision_ms: col(0),
            disturbed: sum(|r| r.disturbed),
            failed_grasps,
            frames: frames.len(),
            grasp_success: (grasps - failed_grasps) as f64 / grasps.max(1) as f64,
            grasps,
            ik_backtracks: sum(|r| r.ik_backtracks),
            ik_ms: col(4).median,
            no_plan_frames: sum(|r| r.no_plan_frames),
            objects,
            objects_per_action: removed as f64 / actions.max(1) as f64,
            off_table: sum(|r| r.off_table),
            perception_ms: col(1).median,
            planning_ms: col(3).median,
            predicates_ms: col(2).median,
            push_loops: sum(|r| r.push_loops),
            pushes: sum(|r| r.pushes),
            removed,
            rows,
            scenes: rows.len(),
            scenes_cleared: rows
                .iter()
                .filter(|r| r.objects > 0 && r.in_bin == r.objects)
                .count(),
            suite,
        }
    }
}
