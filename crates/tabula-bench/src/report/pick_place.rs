//! The report's part for a pick and place, and the time-per-phase plot every task with
//! phases shows.

use super::{Recorded, Report, Section};
use crate::pick_place::{BenchRow, PickPlaceRun};
use crate::stats::median;
use anyhow::Result;

/// The report's part for a pick and place: the verdict, the phases, the replay.
pub fn section(
    report: &mut Report,
    out: &PickPlaceRun,
    recorded: Option<&Recorded>,
) -> Result<Section> {
    let r = &out.report;
    let v = &out.verdict;
    let mut s = Section::new("Pick and place by coordinates (seed 001)");
    s.text(format!(
        "{}: arm {}, {} grasp; `{}` ended {:.1} cm from the target, tilted {:.1}°.",
        if out.success { "Success" } else { "Failed" },
        r.arm.as_deref().unwrap_or("-"),
        r.grasp
            .map_or("-".into(), |g| format!("{g:?}").to_lowercase()),
        v.object,
        v.target_error * 100.0,
        v.tilt.to_degrees()
    ));
    if let Some(e) = &out.error_message {
        s.text(format!("Error: {e}"));
    }
    s.number("success", out.success)
        .number("arm", r.arm.as_deref().unwrap_or("-"))
        .number("decision CPU (ms)", format!("{:.1}", r.decision_cpu_ms))
        .number("grasp candidates tried", r.candidates_tried)
        .number(
            "target error (cm)",
            format!("{:.2}", v.target_error * 100.0),
        )
        .number("tilt (°)", format!("{:.2}", v.tilt.to_degrees()))
        .number("furniture contacts", v.furniture_contacts.len());
    s.log = r
        .rejected
        .iter()
        .map(|w| format!("rejected: {w}"))
        .collect();
    phase_plot(report, &mut s, &r.phases)?;
    if let Some(rec) = recorded {
        report.recorded(&mut s, "pick-place", rec)?;
    }
    Ok(s)
}

/// Time per phase as bars (wall ms: the simulated motion is in it).
pub fn phase_plot(
    report: &mut Report,
    section: &mut Section,
    phases: &[tabula_tasks::pick_place::Phase],
) -> Result<()> {
    if phases.is_empty() {
        return Ok(());
    }
    let bars: Vec<(String, f64)> = phases
        .iter()
        .map(|p| {
            (
                format!("{}{}", p.name, if p.ok { "" } else { " (failed)" }),
                p.ms,
            )
        })
        .collect();
    let svg = super::plots::bars(
        "Time per phase",
        "ms (wall, simulated motion included)",
        &bars,
    )?;
    let fig = report.svg("phases", "Time per phase", &svg)?;
    section.figures.push(fig);
    Ok(())
}

/// The tasks placed and the decision times of the successful ones.
fn placed(rows: &[BenchRow]) -> (usize, Vec<f64>) {
    let ok = rows.iter().filter(|r| r.success).count();
    let decisions: Vec<f64> = rows
        .iter()
        .filter(|r| r.success)
        .map(|r| r.decision_cpu_ms)
        .collect();
    (ok, decisions)
}

/// The report page of `bench pick-place`: success per target, decision times.
pub fn bench_page(dir: &std::path::Path, variants: u64, rows: &[BenchRow]) -> Result<()> {
    let (ok, decisions) = placed(rows);
    super::bench_report(
        dir,
        super::BenchSummary {
            title: "Pick and place by coordinates (seed 001's integral test)",
            command: format!("tabula bench pick-place --variants {variants}"),
            numbers: vec![
                ("tasks".into(), rows.len().to_string()),
                ("placed (physics)".into(), ok.to_string()),
            ],
            classes: (
                "target",
                super::per_class(rows.iter().map(|r| (r.target.as_str(), r.success))),
            ),
            distributions: vec![(
                "Decision CPU per task (successful tasks)",
                "ms",
                decisions.clone(),
            )],
            bars: Vec::new(),
        },
        &rows,
    )?;
    Ok(())
}

/// What `bench pick-place --json` prints.
pub fn bench_json(rows: &[BenchRow]) -> serde_json::Value {
    let (ok, decisions) = placed(rows);
    serde_json::json!({
        "variants": rows.len(),
        "succeeded": ok,
        "median_decision_cpu_ms": median(&decisions).unwrap_or(f64::NAN),
        "rows": rows,
    })
}

/// What `bench pick-place` prints: a table row per task, then the totals.
pub fn bench_lines(rows: &[BenchRow]) -> Vec<String> {
    let (ok, decisions) = placed(rows);
    let mut lines = Vec::new();
    lines.push("| seed | to | arm | success | decision CPU ms | error cm | why |".to_string());
    lines.push("|---|---|---|---|---|---|---|".to_string());
    for r in rows {
        lines.push(format!(
            "| {} | {} | {} | {} | {:.1} | {:.2} | {} |",
            r.seed,
            r.target,
            r.arm.as_deref().unwrap_or("-"),
            if r.success { "yes" } else { "NO" },
            r.decision_cpu_ms,
            r.target_error_cm,
            r.error.as_deref().unwrap_or("")
        ));
    }
    lines.push(format!(
        "\n{ok} of {} placed (physics verdict); median decision {:.1} ms CPU",
        rows.len(),
        median(&decisions).unwrap_or(f64::NAN)
    ));
    lines
}
