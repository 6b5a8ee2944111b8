//! `tabula tidy`: take every object from one table and stand each on another surface,
//! in the simulator, judged by its physics.

use crate::tasks::{TaskRunArgs, load_params, scene_robot_named};
use anyhow::{Result, bail};
use clap::Args;
use serde::Serialize;
use tabula_geom::Vec3;
use tabula_sim::judge::tidy::{TidyStart, TidyVerdict};
use tabula_tasks::tidy::{Failure, TidyParams, TidyReport, TidyRequest, tidy};

#[derive(Args)]
pub struct TidyArgs {
    #[command(flatten)]
    pub run: TaskRunArgs,
    /// A point on the table to clear (world, m; default 0.8 m ahead of the robot).
    #[arg(long, num_args = 2, value_names = ["X", "Y"], allow_negative_numbers = true, value_parser = crate::args::finite)]
    pub from: Option<Vec<f64>>,
    /// A point on the surface to put things on (world, m; default the first found).
    #[arg(long, num_args = 2, value_names = ["X", "Y"], allow_negative_numbers = true, value_parser = crate::args::finite)]
    pub to: Option<Vec<f64>>,
    /// The scene's furniture to clear (the judge's reference).
    #[arg(long, default_value = "table")]
    pub source: String,
    /// Which arm (default: the robot's first arm with a gripper).
    #[arg(long)]
    pub arm: Option<String>,
}

/// Everything `tidy` prints with `--json`.
#[derive(Serialize)]
pub struct TidyJson {
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

/// The height the default look point and `--from`'s are taken at (m): a table's.
const TABLE_HEIGHT: f64 = 0.75;

fn point(xy: &Option<Vec<f64>>) -> Option<Vec3> {
    xy.as_ref().map(|v| Vec3::new(v[0], v[1], TABLE_HEIGHT))
}

/// Runs tidying on `world` (settled first), judged; returns what it prints and the
/// world afterwards.
pub fn tidy_in(
    mut world: tabula_sim::SimWorld,
    a: &TidyArgs,
    params: &TidyParams,
) -> Result<(TidyJson, tabula_sim::SimWorld)> {
    let (robot_name, robot) = scene_robot_named(&world, a.run.robot.as_deref())?;
    world.settle();
    let start = TidyStart::of(&world, &a.source)?;
    let mut driver = tabula_sim::SimDriver::new(world, &robot_name, a.run.seed)?;
    let request = TidyRequest {
        arm: a.arm.clone(),
        from: point(&a.from),
        to: point(&a.to),
    };
    let outcome = tidy(&mut driver, &robot, &request, params);
    let mut world = driver.world;
    world.settle();
    let verdict = start.verdict(&world);
    let (report, error) = match outcome {
        Ok(r) => (r, None),
        Err(e) => (TidyReport::default(), Some(e)),
    };
    let out = TidyJson {
        success: error.is_none() && verdict.moved == verdict.objects && verdict.knocked.is_empty(),
        objects: verdict.objects,
        moved: verdict.moved,
        actions: report.actions,
        failed: report.failed.clone(),
        decision_ms: report.decision_ms.clone(),
        error: error.as_ref().map(|e| e.kind().to_string()),
        error_message: error.as_ref().map(|e| e.to_string()),
        report,
        verdict,
    };
    Ok((out, world))
}

fn print_summary(out: &TidyJson) {
    println!(
        "tidy: {} of {} objects moved to another surface in {} actions; {} knocked over, {} lost; decision median {:.0} ms",
        out.moved,
        out.objects,
        out.actions,
        out.verdict.knocked.len(),
        out.verdict.lost.len(),
        out.decision_ms.median
    );
    for f in &out.failed {
        println!(
            "  failed at ({:.2}, {:.2}): {} — {}",
            f.object[0], f.object[1], f.reason, f.message
        );
    }
    if let Some(e) = &out.error_message {
        println!("  stopped: {e}");
    }
}

pub fn run(a: TidyArgs) -> Result<()> {
    if a.run.dry_run || !a.run.connect.is_empty() {
        bail!("tidy runs in the simulator here (no --dry-run, no --connect yet)");
    }
    let params: TidyParams = load_params(a.run.params.as_deref())?;
    let (out, world) = tidy_in(a.run.world()?, &a, &params)?;
    a.run
        .finish(&world, &out, out.success, print_summary, |report, out| {
            report.title = "tabula tidy".into();
            let mut s = crate::report::Section::new("Tidying a table");
            s.number("objects on the table", out.objects)
                .number("moved to another surface", out.moved)
                .number("actions", out.actions)
                .number("knocked over", out.verdict.knocked.len());
            report.sections.push(s);
            Ok(())
        })
}
