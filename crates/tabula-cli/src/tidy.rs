//! `tabula tidy`: take every object from one table and stand each on another surface,
//! in the simulator, judged by its physics.

use crate::tasks::{TaskRunArgs, load_params};
use anyhow::{Result, bail};
use clap::Args;
use tabula_bench::report::{Recorded, Report};
use tabula_bench::tidy::{BenchRow, TidyRun as TidyJson};
use tabula_geom::Vec3;
use tabula_tasks::tidy::{TidyParams, TidyRequest};

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

/// The height the default look point and `--from`'s are taken at (m): a table's.
const TABLE_HEIGHT: f64 = 0.75;

fn point(xy: &Option<Vec<f64>>) -> Option<Vec3> {
    xy.as_ref().map(|v| Vec3::new(v[0], v[1], TABLE_HEIGHT))
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

/// One tidying run by the robot served at `--connect`, judged there against its
/// furniture `--source`.
#[cfg(feature = "ros")]
fn tidy_remote(
    a: &TidyArgs,
    request: &TidyRequest,
    params: &TidyParams,
) -> Result<(TidyJson, String)> {
    let world = a.run.world()?;
    let (robot_name, robot) = crate::tasks::scene_robot_named(&world, a.run.robot.as_deref())?;
    let mut driver = crate::remote::connect(&a.run, &robot_name)?;
    let ground = tabula_ros::protocol::ground::Tidy {
        source: a.source.clone(),
    };
    let task = tabula_ros::protocol::JudgedTask::new("tidy", a.run.seed, ground);
    let session = crate::remote::begin(&driver, task)?;
    let outcome = tabula_tasks::tidy::tidy(&mut driver, &robot, request, params);
    let verdict = crate::remote::verdict(session, None)?;
    let scene = crate::remote::scene(&driver)?;
    Ok((TidyJson::of(outcome, verdict), scene))
}

pub fn run(a: TidyArgs) -> Result<()> {
    if a.run.print_params {
        return crate::tasks::print_params::<TidyParams>();
    }
    if a.run.dry_run {
        bail!("tidying moves objects and a dry run moves none: run it in the simulator");
    }
    let params: TidyParams = load_params(a.run.params.as_deref())?;
    let request = TidyRequest {
        arm: a.arm.clone(),
        from: point(&a.from),
        to: point(&a.to),
    };
    if !a.run.connect.is_empty() {
        #[cfg(feature = "ros")]
        {
            let (out, scene) = tidy_remote(&a, &request, &params)?;
            return a
                .run
                .finish(&scene, &out, out.success, print_summary, |r, o| {
                    sections(r, o, None)
                });
        }
        #[cfg(not(feature = "ros"))]
        bail!("this tabula was built without ROS 2 support (feature `ros`)");
    }
    let (out, world, recorded) = tabula_bench::report::recorded(a.run.recording(), |start| {
        tabula_bench::tidy::tidy_in(
            a.run.world()?,
            (a.run.robot.as_deref(), &a.source),
            (&request, &params),
            a.run.seed,
            start,
        )
    })?;
    a.run
        .finish(&world, &out, out.success, print_summary, |report, out| {
            sections(report, out, recorded.as_ref())
        })
}

/// The report of a tidying run.
fn sections(report: &mut Report, out: &TidyJson, recorded: Option<&Recorded>) -> Result<()> {
    report.title = "tabula tidy".into();
    let section = tabula_bench::report::tidy::section(report, out, recorded)?;
    report.sections.push(section);
    Ok(())
}

/// `tabula bench tidy`: the family's tasks `seed..seed + tasks`, both cores.
pub fn bench(
    tasks: u64,
    seed: u64,
    save_scenes: Option<&std::path::Path>,
    json: bool,
) -> Result<()> {
    use rayon::prelude::*;
    let params = TidyParams::default();
    let rows: Vec<BenchRow> = (seed..seed.saturating_add(tasks))
        .into_par_iter()
        .map(|s| tabula_bench::tidy::trial(s, &params, save_scenes))
        .collect::<Result<_>>()?;
    if json {
        println!("{}", tabula_bench::report::tidy::bench_json(&rows));
        return Ok(());
    }
    for line in tabula_bench::report::tidy::bench_lines(&rows) {
        println!("{line}");
    }
    Ok(())
}
