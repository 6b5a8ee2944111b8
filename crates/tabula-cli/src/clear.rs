//! `tabula clear`: seed 002's table clearing run in the simulator, judged by its physics.

use crate::tasks::{TaskRunArgs, load_params};
use anyhow::{Result, anyhow, bail};
use clap::Args;
use tabula_bench::clear::{ClearRun as ClearJson, Summary};
use tabula_bench::report::{Recorded, Report, recorded};
use tabula_sim::generate::{ClearSuite, RobotMount, clearing_scene_with};
use tabula_tasks::clear::ClearParams;

#[derive(Args)]
pub struct ClearArgs {
    #[command(flatten)]
    pub run: TaskRunArgs,
    /// Stop after this many actions (default: 3 per object seen first, plus 5).
    #[arg(long, value_parser = crate::args::count)]
    pub max_actions: Option<usize>,
}

/// One clearing run by the robot served at `--connect`, judged there; the workcell
/// (bin, furniture) is read from the scene file here.
#[cfg(feature = "ros")]
fn clear_remote(a: &ClearArgs, params: &ClearParams) -> Result<(ClearJson, String)> {
    use crate::tasks::scene_robot_named;
    use tabula_bench::clear::{BIN, TABLE};
    use tabula_sim::judge::ClearSetup;
    use tabula_tasks::clear::clear;
    let world = a.run.world()?;
    let (robot_name, robot) = scene_robot_named(&world, a.run.robot.as_deref())?;
    let setup = ClearSetup::of(&world, BIN)?;
    let mut driver = crate::remote::connect(&a.run, &robot_name)?;
    let session = crate::remote::begin(
        &driver,
        tabula_ros::protocol::JudgedTask::new(
            "clear",
            a.run.seed,
            tabula_ros::protocol::ground::Clear {
                table: TABLE.into(),
                bin: BIN.into(),
            },
        ),
    )?;
    let request = tabula_bench::clear::request(&setup, a.max_actions);
    let outcome = clear(&mut driver, &robot, &request, params, &mut |_, e| {
        if let Err(err) = session.moment(e.judged()) {
            tracing::warn!("the judge missed a moment: {err}");
        }
    });
    let verdict = crate::remote::verdict(session, None)?;
    let scene = crate::remote::scene(&driver)?;
    Ok((ClearJson::of(outcome, verdict), scene))
}

pub fn run(a: ClearArgs) -> Result<()> {
    if a.run.print_params {
        return crate::tasks::print_params::<ClearParams>();
    }
    if a.run.dry_run {
        bail!("clearing pushes objects and a dry run moves none: run it in the simulator");
    }
    let params: ClearParams = load_params(a.run.params.as_deref())?;
    params.validate()?;
    let sections = |report: &mut Report, out: &ClearJson, recorded: Option<&Recorded>| {
        report.title = "tabula clear".into();
        let section = tabula_bench::report::clear::section(report, out, recorded)?;
        report.sections.push(section);
        Ok(())
    };
    if !a.run.connect.is_empty() {
        #[cfg(feature = "ros")]
        {
            let (out, scene) = clear_remote(&a, &params)?;
            return a
                .run
                .finish(&scene, &out, out.success, print_summary, |r, o| {
                    sections(r, o, None)
                });
        }
        #[cfg(not(feature = "ros"))]
        bail!("this tabula was built without ROS 2 support (feature `ros`)");
    }
    let (out, world, recorded) = recorded(a.run.recording(), |start| {
        tabula_bench::clear::clear_in(
            a.run.world()?,
            a.run.robot.as_deref(),
            (&params, a.max_actions),
            a.run.seed,
            start,
        )
    })?;
    a.run
        .finish(&world, &out, out.success, print_summary, |report, out| {
            sections(report, out, recorded.as_ref())
        })
}

/// The user's robot placed in the clearing cell (`--robot` of `bench clear` and `bench
/// pick-place`); the scene names its files by absolute path, so a saved scene loads
/// from anywhere.
pub fn robot_mount(file: &str) -> Result<RobotMount> {
    let robot = tabula_robot::robots::load(file)?;
    let absolute = |p: &std::path::Path| -> Result<String> {
        Ok(std::path::absolute(p)?.display().to_string())
    };
    let options = tabula_robot::robots::default_options();
    let srdf = match &options.srdf {
        Some(s) => Some(absolute(s)?),
        None => None,
    };
    let mount = tabula_bench::mount::clearing_mount(
        &robot,
        &absolute(std::path::Path::new(file))?,
        srdf.as_deref(),
        &options.xacro_args,
    )?;
    eprintln!(
        "{file}: on a pedestal, its root at {:?}, starting at {:?}",
        mount.xyz, mount.joints
    );
    Ok(mount)
}

fn print_summary(out: &ClearJson) {
    for line in tabula_bench::report::clear::summary_lines(out) {
        println!("{line}");
    }
}

/// `tabula bench clear`: every scene of a suite cleared in the simulator (both cores,
/// one scene each, or spread over workers), judged by physics.
pub fn bench(robot: Option<&str>, b: &crate::trials::SuiteRun<'_>) -> Result<()> {
    let suite = b.suite;
    let which: ClearSuite = suite.parse().map_err(|e: String| anyhow!(e))?;
    let params: ClearParams = load_params(b.params)?;
    if robot.is_some() && b.spread.workers.is_some() {
        bail!("--robot with --workers: the workers clear with seed 002's WAM; run it here");
    }
    let mount = match robot {
        Some(file) => Some(robot_mount(file)?),
        None => None,
    };
    let runs = b.run("clear", |s| {
        tabula_bench::clear::trial_with(which, s, &params, mount.as_ref())
    })?;
    if let Some(dir) = b.save_failures {
        for t in &runs {
            if !t.row.success || t.row.collisions > 0 {
                std::fs::create_dir_all(dir)?;
                std::fs::write(
                    dir.join(format!("{suite}-{}.toml", t.row.seed)),
                    clearing_scene_with(which, t.row.seed, mount.as_ref()),
                )?;
            }
        }
    }
    let mut rows = Vec::new();
    let mut frames: Vec<[f64; 5]> = Vec::new();
    for t in runs {
        rows.push(t.row);
        frames.extend(t.frames);
    }
    let s = Summary::of(suite, &rows, &frames);
    let summary = serde_json::to_value(&s)?;
    if let Some(dir) = b.report {
        let command = format!(
            "tabula bench clear --suite {suite} --scenes {} --seed {}",
            b.count, b.seed
        );
        tabula_bench::report::clear::bench_page(dir, command, (&rows, &frames), &summary)?;
    }
    if b.json {
        println!("{}", serde_json::to_string_pretty(&summary)?);
        return Ok(());
    }
    for line in tabula_bench::report::clear::bench_lines(&rows, &s) {
        println!("{line}");
    }
    Ok(())
}
