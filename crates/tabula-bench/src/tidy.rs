//! Tidying judged in the simulator: one run's outcome and verdict together (what
//! `tabula tidy --json` prints), and the tidying family's trials (`bench tidy`).

use crate::judged::run_in;
use anyhow::Result;
use serde::Serialize;
use tabula_sim::judge::TidyVerdict;
use tabula_sim::{SimDriver, SimWorld};
use tabula_tasks::task::Failure;
use tabula_tasks::tidy::{Tidy, TidyError, TidyParams, TidyReport, TidyRequest};

/// A tidying run: the task's report and the judged outcome (`tidy --json`).
#[derive(Serialize)]
pub struct TidyRun {
    /// Every object of the table rests on another surface and nothing was knocked.
    pub success: bool,
    /// Objects on the table to clear at the start (judged).
    pub objects: usize,
    /// Of those, resting on another surface at the end (judged by physics).
    pub moved: usize,
    pub actions: usize,
    pub failed: Vec<Failure>,
    pub decision_ms: tabula_tasks::clear::Stats,
    pub error: Option<String>,
    pub error_message: Option<String>,
    pub report: TidyReport,
    pub verdict: TidyVerdict,
}

impl TidyRun {
    /// The run from the task's outcome and the judge's verdict.
    pub fn of(outcome: Result<TidyReport, TidyError>, verdict: TidyVerdict) -> Self {
        let (report, error) = match outcome {
            Ok(r) => (r, None),
            Err(e) => (TidyReport::default(), Some(e)),
        };
        Self {
            success: error.is_none()
                && verdict.moved == verdict.objects
                && verdict.knocked.is_empty(),
            objects: verdict.objects,
            moved: verdict.moved,
            actions: report.actions,
            failed: report.failed.clone(),
            decision_ms: report.decision_ms,
            error: error.as_ref().map(|e| e.kind().to_string()),
            error_message: error.as_ref().map(|e| e.to_string()),
            report,
            verdict,
        }
    }
}

/// Tidies `world` (settled first) with its robot (`robot`, or the only one), judged
/// against furniture `source`; camera noise from `seed`. The run and the world after.
pub fn tidy_in(
    world: SimWorld,
    (robot, source): (Option<&str>, &str),
    (request, params): (&TidyRequest, &TidyParams),
    seed: u64,
    on_start: impl FnOnce(&mut SimDriver),
) -> Result<(TidyRun, SimWorld)> {
    let source = source.to_string();
    let (outcome, verdict, world) =
        run_in::<Tidy>(world, robot, (request, params, &source), seed, on_start)?;
    Ok((TidyRun::of(outcome, verdict), world))
}

/// One generated task's outcome, as `bench tidy` reports it.
#[derive(Serialize)]
pub struct BenchRow {
    pub seed: u64,
    pub objects: usize,
    pub moved: usize,
    pub knocked: usize,
    pub lost: usize,
    pub actions: usize,
    pub targets: usize,
    pub residents: usize,
    pub decision_ms: f64,
    pub wall_s: f64,
    pub error: Option<String>,
    /// Why the task's loop ended, and what failed on the way.
    pub stop: String,
    pub failed: Vec<String>,
}

/// Task `s` of the tidying family, tidied and judged (its scene saved into `save` first
/// when given).
pub fn trial(s: u64, params: &TidyParams, save: Option<&std::path::Path>) -> Result<BenchRow> {
    let task = tabula_sim::generate::tidy_task(s);
    if let Some(dir) = save {
        std::fs::create_dir_all(dir)?;
        std::fs::write(dir.join(format!("tidy-{s}.toml")), &task.scene)?;
    }
    let scene = tabula_sim::Scene::parse(&task.scene, &format!("tidy task {s}"))?;
    let world = SimWorld::from_scene(&scene, Default::default())?;
    let t0 = std::time::Instant::now();
    let request = TidyRequest::default();
    let (out, _) = tidy_in(world, (None, &task.source), (&request, params), s, |_| {})?;
    Ok(BenchRow {
        seed: s,
        objects: out.objects,
        moved: out.moved,
        knocked: out.verdict.knocked.len(),
        lost: out.verdict.lost.len(),
        actions: out.actions,
        targets: task.targets.len(),
        residents: task.residents,
        decision_ms: out.decision_ms.median,
        wall_s: t0.elapsed().as_secs_f64(),
        error: out.error_message,
        stop: out.report.stop.clone(),
        failed: out
            .failed
            .iter()
            .map(|f| format!("{}: {}", f.reason, f.message))
            .collect(),
    })
}
