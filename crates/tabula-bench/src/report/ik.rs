//! The report pages and printed lines of `tabula ik bench` and `ik bench --compare`.

use crate::ik::Compared;
use anyhow::Result;
use std::path::{Path, PathBuf};
use tabula_robot::ik::bench::IkBenchReport;

/// The report page of `ik bench --compare`: every measure's test and the errors' and
/// times' distributions.
pub fn compare_page(
    dir: &Path,
    (ra, rb): (&IkBenchReport, &IkBenchReport),
    compared: &[Compared],
    out: &serde_json::Value,
) -> Result<PathBuf> {
    let mut report = super::Report::create(dir, "IK solvers compared")?;
    let mut section = super::Section::new(format!(
        "{} (A) against {} (B), {} targets, seed {}",
        ra.solver, rb.solver, ra.poses, ra.seed
    ));
    section.text(
        "Mann–Whitney U on every measure (two-sided, normal approximation with tie and \
         continuity corrections, α = 0.05), as seed 001 §5.1 compares its solvers.",
    );
    for c in compared {
        section.number(
            format!("{} ({})", c.measure, c.unit),
            format!(
                "median A {:.3e}, B {:.3e}; p = {}{}",
                c.median_a,
                c.median_b,
                c.test.map_or("-".into(), |t| format!("{:.3e}", t.p)),
                if c.different { " — different" } else { "" }
            ),
        );
    }
    let per_axis =
        |r: &IkBenchReport, range: std::ops::Range<usize>| r.axis_error_samples[range].to_vec();
    for (title, unit, range, names) in [
        ("Position error per axis", "m", 0..3, vec!["x", "y", "z"]),
        (
            "Orientation error per axis",
            "rad",
            3..6,
            vec!["roll", "pitch", "yaw"],
        ),
    ] {
        let svg = super::plots::boxes(
            title,
            unit,
            &names,
            &[
                (ra.solver.as_str(), per_axis(ra, range.clone())),
                (rb.solver.as_str(), per_axis(rb, range)),
            ],
            true,
        )?;
        let fig = report.svg(title, title, &svg)?;
        section.figures.push(fig);
    }
    let svg = super::plots::boxes(
        "Solve time",
        "µs",
        &["solve time"],
        &[
            (ra.solver.as_str(), vec![ra.solve_us_samples.clone()]),
            (rb.solver.as_str(), vec![rb.solve_us_samples.clone()]),
        ],
        true,
    )?;
    let fig = report.svg("solve time", "Solve time per target", &svg)?;
    section.figures.push(fig);
    report.sections.push(section);
    report.finish(out)
}

/// The report page of `ik bench`: the solver, its success rate, solve times and the
/// per-axis errors.
pub fn bench_page(dir: &Path, robot: &str, report: &IkBenchReport) -> Result<()> {
    let e = &report.axis_error_samples;
    let p95 = |v: &[f64]| tabula_robot::ik::bench::Spread::of(v).p95;
    super::bench_report(
        dir,
        super::BenchSummary {
            title: "Inverse kinematics (seed 001's protocol)",
            command: format!(
                "tabula ik bench --robot {} --solver {} --poses {} --seed {}",
                robot, report.solver, report.poses, report.seed
            ),
            numbers: vec![
                (
                    "chain".into(),
                    format!("{} → {} ({} DOF)", report.base, report.tip, report.dof),
                ),
                ("mode".into(), report.mode.clone()),
                ("success rate".into(), format!("{:.4}", report.success_rate)),
                (
                    "solve µs median / p95 / max".into(),
                    format!(
                        "{:.2} / {:.2} / {:.2}",
                        report.solve_us.median, report.solve_us.p95, report.solve_us.max
                    ),
                ),
                (
                    "CPU µs per solve".into(),
                    format!("{:.2}", report.cpu_us_per_solve),
                ),
                (
                    "unreachable targets rejected".into(),
                    format!("{:.4}", report.unreachable_rejected_rate),
                ),
            ],
            classes: ("", Vec::new()),
            distributions: vec![(
                "Wall time per solve (reachable targets)",
                "µs",
                report.solve_us_samples.clone(),
            )],
            bars: vec![(
                "Error per axis, 95th percentile (µm for x y z, µrad for roll pitch yaw)",
                "µm / µrad",
                ["x", "y", "z", "roll", "pitch", "yaw"]
                    .iter()
                    .zip(e.iter())
                    .map(|(n, v)| (n.to_string(), p95(v) * 1e6))
                    .collect(),
            )],
        },
        &report,
    )?;
    Ok(())
}

/// What `ik bench --compare` prints: both solvers' success, then each measure's test.
pub fn compare_lines(
    (ra, rb): (&IkBenchReport, &IkBenchReport),
    compared: &[Compared],
) -> Vec<String> {
    let mut lines = Vec::new();
    lines.push(format!(
        "IK solvers compared (seed 001 §5.1): A = {}, B = {}; {} targets, seed {}, mode {}",
        ra.solver, rb.solver, ra.poses, ra.seed, ra.mode
    ));
    lines.push(format!(
        "success: A {:.4}, B {:.4}",
        ra.success_rate, rb.success_rate
    ));
    lines.push(format!(
        "{:<12} {:>5} {:>12} {:>12} {:>14} {:>10}  α = 0.05",
        "measure", "unit", "median A", "median B", "U", "p"
    ));
    for c in compared {
        lines.push(format!(
            "{:<12} {:>5} {:>12.3e} {:>12.3e} {:>14} {:>10}  {}",
            c.measure,
            c.unit,
            c.median_a,
            c.median_b,
            c.test.map_or("-".into(), |t| format!("{:.1}", t.u)),
            c.test.map_or("-".into(), |t| format!("{:.2e}", t.p)),
            if c.different {
                "different"
            } else {
                "no difference shown"
            }
        ));
    }
    lines
}

/// What `ik bench` prints: success, times to a solution and to "no solution", the
/// errors per axis.
pub fn bench_lines(robot: &str, report: &IkBenchReport) -> Vec<String> {
    let mut lines = Vec::new();
    let r = &report;
    lines.push(format!(
        "IK benchmark (seed 001 protocol, SPEC §2.4) — {} {} → {} ({} DOF)",
        robot, r.base, r.tip, r.dof
    ));
    lines.push(format!(
        "solver {}, mode {}, {} reachable + {} unreachable targets, seed {}",
        r.solver, r.mode, r.poses, r.poses, r.seed
    ));
    lines.push(format!(
        "  success rate            {:.3} %",
        100.0 * r.success_rate
    ));
    if let Some(one) = r.one_attempt_success_rate {
        lines.push(format!("  one-attempt success     {:.3} %", 100.0 * one));
    }
    lines.push(format!(
        "  time to a solution      median {:.2} µs   p95 {:.2} µs   max {:.1} µs",
        r.solve_us.median, r.solve_us.p95, r.solve_us.max
    ));
    lines.push(format!(
        "  CPU per solve (mean)    {:.2} µs",
        r.cpu_us_per_solve
    ));
    lines.push(format!(
        "  time to 'no solution'   median {:.2} µs   p95 {:.2} µs   (targets pushed out ×1.5: {:.1} % rejected, the rest solved)",
        r.fail_us.median,
        r.fail_us.p95,
        100.0 * r.unreachable_rejected_rate
    ));
    lines.push(format!(
        "  beyond reach bound      median {:.2} µs   p95 {:.2} µs   ({:.1} % rejected)",
        r.beyond_reach_fail_us.median,
        r.beyond_reach_fail_us.p95,
        100.0 * r.beyond_reach_rejected_rate
    ));
    lines.push(format!(
        "  solutions per pose      mean {:.2}   median {}   max {}",
        r.mean_solutions_per_pose, r.solutions_per_pose.median, r.solutions_per_pose.max
    ));
    lines.push("  error           median        p95          max".to_string());
    let e = &r.errors;
    for (name, sp) in [
        ("x (m)", e.x),
        ("y (m)", e.y),
        ("z (m)", e.z),
        ("roll (rad)", e.roll),
        ("pitch (rad)", e.pitch),
        ("yaw (rad)", e.yaw),
    ] {
        lines.push(format!(
            "  {name:<12} {:>10.2e}  {:>10.2e}  {:>10.2e}",
            sp.median, sp.p95, sp.max
        ));
    }
    lines
}
