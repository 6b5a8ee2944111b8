//! `tabula motion bench --mbm PATH`: MotionBenchMaker's problem sets planned on tabula,
//! timed as VAMP and OMPL time theirs (CPU of the planning thread, plan + shortcut,
//! world built once per problem), with every path written out for outside checking.

use anyhow::{Context, Result};
use std::path::{Path, PathBuf};
use tabula_geom::Pose;
use tabula_motion::group::MoveGroupParams;
use tabula_motion::mbm::{self, MbmReport, Outcome, ProblemResult};
use tabula_motion::moveit::Limits;
use tabula_motion::world::CollisionWorld;
use tabula_robot::robots;

/// What `--mbm` was asked.
pub struct MbmRun<'a> {
    pub problems: &'a Path,
    pub robot: &'a str,
    pub params: Option<&'a Path>,
    pub seed: u64,
    pub timeout: f64,
    pub json: bool,
    pub paths: Option<&'a PathBuf>,
}

pub fn run(r: MbmRun) -> Result<()> {
    let mut params: MoveGroupParams = super::planning_params(r.params)?;
    params.planner.timeout_s = r.timeout;
    params.planner.seed = r.seed;
    let robot = robots::load(r.robot)?;
    let problems = mbm::load(r.problems, &Limits::default())
        .with_context(|| r.problems.display().to_string())?;
    let world_params = {
        let mut w = params.world.clone();
        if w.srdf.is_none() {
            w.srdf = robot.srdf.clone();
        }
        w
    };
    let progress =
        crate::progress::spinner(&format!("{} MotionBenchMaker problems", problems.len()));
    let results = mbm::run(
        &problems,
        &params.planner,
        |group| {
            let arm = robot.description.arm(group).map_err(|e| e.to_string())?;
            let chain = arm.chain(&robot.model).map_err(|e| e.to_string())?;
            CollisionWorld::new(
                robot.model.clone(),
                chain,
                Pose::IDENTITY,
                None,
                world_params.clone(),
            )
            .map_err(|e| e.to_string())
        },
        |_| {},
    );
    progress.finish_and_clear();
    if let Some(out) = r.paths {
        write_paths(out, &results)?;
    }
    let report = MbmReport::of(&results);
    if r.json {
        println!("{}", serde_json::to_string(&report)?);
    } else {
        print_report(&report, r.timeout);
    }
    Ok(())
}

/// Every problem's path (solved ones) as JSON lines of the outside checker's input.
fn write_paths(out: &Path, results: &[ProblemResult]) -> Result<()> {
    #[derive(serde::Serialize)]
    struct PathJson<'a> {
        set: &'a str,
        index: u32,
        joint_names: &'a [String],
        path: &'a [Vec<f64>],
    }
    let rows: Vec<PathJson> = results
        .iter()
        .filter_map(|r| match &r.outcome {
            Outcome::Solved { path, .. } => Some(PathJson {
                set: &r.set,
                index: r.index,
                joint_names: &r.joint_names,
                path,
            }),
            _ => None,
        })
        .collect();
    std::fs::write(out, serde_json::to_string(&rows)?).with_context(|| out.display().to_string())
}

fn print_report(report: &MbmReport, timeout: f64) {
    let a = &report.all;
    println!(
        "MotionBenchMaker: {} problems, {} valid, {} solved ({:.1} % of valid) within {timeout} s",
        a.total,
        a.valid,
        a.solved,
        100.0 * a.solved as f64 / a.valid.max(1) as f64
    );
    println!(
        "  plan + shortcut (CPU µs)  median {:.0}   p95 {:.0}   max {:.0}",
        a.time_us.median, a.time_us.p95, a.time_us.max
    );
    println!("  plan alone (CPU µs)       median {:.0}", a.plan_us.median);
    println!(
        "  configurations checked    median {:.0}   ({:.1} µs each)",
        a.checks.median,
        a.time_us.median / a.checks.median.max(1.0)
    );
    for (set, t) in &report.sets {
        println!(
            "  {set:<28} {:>4}/{:<4} solved   median {:>8.0} µs   p95 {:>8.0} µs",
            t.solved, t.valid, t.time_us.median, t.time_us.p95
        );
    }
    for (set, index, why) in report.not_solved.iter().take(20) {
        println!("  not solved: {set} {index:04}: {why}");
    }
    if report.not_solved.len() > 20 {
        println!(
            "  … and {} more (--json lists all)",
            report.not_solved.len() - 20
        );
    }
}
