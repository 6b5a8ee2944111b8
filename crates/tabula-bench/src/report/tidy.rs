//! The report's part for a tidying run: the counts, what failed and why, the replay.

use super::{Recorded, Report, Section};
use crate::tidy::{BenchRow, TidyRun};
use anyhow::Result;

/// The section of a tidying run (`recorded`: its replay and pictures, if recorded).
pub fn section(report: &mut Report, out: &TidyRun, recorded: Option<&Recorded>) -> Result<Section> {
    let mut s = Section::new("Tidying a table (from the shared skills)");
    s.number("objects on the table", out.objects)
        .number("moved to another surface", out.moved)
        .number("actions", out.actions)
        .number("knocked over", out.verdict.knocked.len())
        .number("lost", out.verdict.lost.len())
        .number(
            "decision CPU median / p95 (ms)",
            format!("{:.0} / {:.0}", out.decision_ms.median, out.decision_ms.p95),
        );
    s.log = out
        .failed
        .iter()
        .map(|f| {
            format!(
                "failed at ({:.2}, {:.2}): {} — {}",
                f.object[0], f.object[1], f.reason, f.message
            )
        })
        .collect();
    if let Some(rec) = recorded {
        report.recorded(&mut s, "tidy", rec)?;
    }
    Ok(s)
}

/// The family's totals: objects, moved, knocked over, the decisions' spread.
fn totals(rows: &[BenchRow]) -> (usize, usize, usize, tabula_tasks::clear::Stats) {
    let objects: usize = rows.iter().map(|r| r.objects).sum();
    let moved: usize = rows.iter().map(|r| r.moved).sum();
    let knocked: usize = rows.iter().map(|r| r.knocked).sum();
    let decisions: Vec<f64> = rows.iter().map(|r| r.decision_ms).collect();
    let spread = tabula_tasks::clear::Stats::of(&decisions);
    (objects, moved, knocked, spread)
}

/// What `bench tidy --json` prints.
pub fn bench_json(rows: &[BenchRow]) -> serde_json::Value {
    let (objects, moved, knocked, spread) = totals(rows);
    serde_json::json!({
        "tasks": rows.len(), "objects": objects, "moved": moved,
        "knocked": knocked, "decision_ms": spread, "rows": rows,
    })
}

/// What `bench tidy` prints: a line per task, then the totals.
pub fn bench_lines(rows: &[BenchRow]) -> Vec<String> {
    let (objects, moved, knocked, spread) = totals(rows);
    let mut lines = Vec::new();
    for r in rows {
        lines.push(format!(
            "seed {:>4}: {} of {} moved, {} knocked, {} lost, {} actions, {:.0} ms decision, {:.1} s{}",
            r.seed,
            r.moved,
            r.objects,
            r.knocked,
            r.lost,
            r.actions,
            r.decision_ms,
            r.wall_s,
            r.error
                .as_ref()
                .map(|e| format!(" ({e})"))
                .unwrap_or_default()
        ));
    }
    let (lo, hi) = crate::stats::wilson(moved, objects);
    lines.push(format!(
        "tidy: {moved} of {objects} objects moved ({:.1} %, 95 % {:.1}–{:.1} %), {knocked} knocked over; decision median {:.0} ms, p95 {:.0} ms",
        100.0 * moved as f64 / objects.max(1) as f64,
        100.0 * lo,
        100.0 * hi,
        spread.median,
        spread.p95
    ));
    lines
}
