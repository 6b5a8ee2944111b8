//! The report page and printed lines of `tabula motion bench`, generated reaches and
//! MotionBenchMaker's sets, and the paths file outside checkers read.

use anyhow::{Context, Result};
use std::path::Path;
use tabula_motion::bench::MotionBenchReport as BenchReport;
use tabula_motion::mbm::{MbmReport, Outcome, ProblemResult};

/// The report page of the generated reaches: solved, times, checks per second.
pub fn reach_page(
    dir: &Path,
    (robot, seed, timeout): (&str, u64, f64),
    report: &BenchReport,
) -> Result<()> {
    let problems = report.problems;
    super::bench_report(
        dir,
        super::BenchSummary {
            title: "Motion planning: RRT-Connect on tabletop reaches",
            command: format!(
                "tabula motion bench --robot {robot} --problems {problems} --seed {seed} --timeout {timeout}"
            ),
            numbers: vec![
                ("problems".into(), report.problems.to_string()),
                ("solved".into(), report.solved.to_string()),
                (
                    "planning ms median / p95".into(),
                    format!("{:.2} / {:.2}", report.time_ms_median, report.time_ms_p95),
                ),
                (
                    "collision checks per second".into(),
                    format!("{:.0}", report.checks_per_second),
                ),
            ],
            classes: ("", Vec::new()),
            distributions: vec![(
                "Planning time per solved problem",
                "ms",
                report.time_ms_samples.clone(),
            )],
            bars: Vec::new(),
        },
        report,
    )?;
    Ok(())
}

/// What `motion bench` prints for the generated reaches.
pub fn reach_lines((_, seed, timeout): (&str, u64, f64), report: &BenchReport) -> Vec<String> {
    let mut lines = Vec::new();
    lines.push(format!(
        "RRT-Connect on {} tabletop reach problems ({}), seed {seed}, {timeout} s limit",
        report.problems, report.robot
    ));
    lines.push(format!(
        "  solved              {}/{} ({:.1} %)",
        report.solved,
        report.problems,
        100.0 * report.success_rate
    ));
    lines.push(format!(
        "  planning time       median {:.3} ms   p95 {:.3} ms",
        report.time_ms_median, report.time_ms_p95
    ));
    lines.push(format!(
        "  path length         median {:.3} rad",
        report.path_length_median
    ));
    lines.push(format!(
        "  validity checks     {:.0} per second; one check median {:.2} µs",
        report.checks_per_second, report.validity_check_us_median
    ));
    lines.push(format!(
        "  convex–convex query median {:.3} µs",
        report.convex_query_us_median
    ));

    lines
}

/// What `motion bench --mbm` prints: the totals, each set, the problems not solved.
pub fn mbm_lines(report: &MbmReport, timeout: f64) -> Vec<String> {
    let mut lines = Vec::new();
    let a = &report.all;
    lines.push(format!(
        "MotionBenchMaker: {} problems, {} valid, {} solved ({:.1} % of valid) within {timeout} s",
        a.total,
        a.valid,
        a.solved,
        100.0 * a.solved as f64 / a.valid.max(1) as f64
    ));
    lines.push(format!(
        "  plan + shortcut (CPU µs)  median {:.0}   p95 {:.0}   max {:.0}",
        a.time_us.median, a.time_us.p95, a.time_us.max
    ));
    lines.push(format!(
        "  plan alone (CPU µs)       median {:.0}",
        a.plan_us.median
    ));
    lines.push(format!(
        "  configurations checked    median {:.0}   ({:.1} µs each)",
        a.checks.median,
        a.time_us.median / a.checks.median.max(1.0)
    ));
    for (set, t) in &report.sets {
        lines.push(format!(
            "  {set:<28} {:>4}/{:<4} solved   median {:>8.0} µs   p95 {:>8.0} µs",
            t.solved, t.valid, t.time_us.median, t.time_us.p95
        ));
    }
    for (set, index, why) in report.not_solved.iter().take(20) {
        lines.push(format!("  not solved: {set} {index:04}: {why}"));
    }
    if report.not_solved.len() > 20 {
        lines.push(format!(
            "  … and {} more (--json lists all)",
            report.not_solved.len() - 20
        ));
    }
    lines
}

/// Every problem's path (solved ones) as JSON lines of the outside checker's input.
/// Every problem's path (solved ones) as JSON lines of the outside checker's input.
pub fn write_paths(out: &Path, results: &[ProblemResult]) -> Result<()> {
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
