//! The report's parts for clearing: a run's section and lines, the bench's page.

use super::{Recorded, Report, Section};
use crate::clear::{BenchRow, ClearRun, Summary};
use anyhow::Result;
use std::path::Path;

/// The report's part for a clearing run: the metrics, the decision time per frame and
/// its parts, the action log, the replay and pictures of every grasp and release.
pub fn section(
    report: &mut Report,
    out: &ClearRun,
    recorded: Option<&Recorded>,
) -> Result<Section> {
    let r = &out.report;
    let v = &out.verdict;
    let mut s = Section::new("Clearing a cluttered table (seed 002)");
    let lines = summary_lines(out);
    s.text(lines[0].clone());
    s.number("objects on the table", v.objects)
        .number("in the bin", v.in_bin)
        .number("left on the table", v.left_on_table)
        .number("actions", r.actions)
        .number(
            "grasps (failed)",
            format!("{} ({})", r.grasps, r.failed_grasps),
        )
        .number("pushes", r.pushes)
        .number(
            "objects per action",
            format!("{:.2}", v.in_bin as f64 / r.actions.max(1) as f64),
        )
        .number("frames without a plan", r.no_plan_frames)
        .number("IK backtracks", r.ik_backtracks)
        .number("push loops", r.push_loops)
        .number("collisions with other objects", out.collisions)
        .number(
            "decision CPU median / p95 / max (ms)",
            format!(
                "{:.1} / {:.1} / {:.1}",
                r.decision_ms.median, r.decision_ms.p95, r.decision_ms.max
            ),
        );
    s.log = lines[1..].to_vec();
    if !r.frames.is_empty() {
        let steps: Vec<Vec<f64>> = r
            .frames
            .iter()
            .map(|f| vec![f.perception_ms, f.predicates_ms, f.planning_ms, f.ik_ms])
            .collect();
        let svg = super::plots::stacked(
            "Decision latency per frame (CPU)",
            "frame",
            "ms",
            &["perception", "predicates", "planning", "IK"],
            &steps,
        )?;
        let fig = report.svg(
            "decision",
            "Decision latency per frame: frame in → first action chosen",
            &svg,
        )?;
        s.figures.push(fig);
    }
    if let Some(rec) = recorded {
        report.recorded(&mut s, "clear", rec)?;
    }
    Ok(s)
}

/// What `clear` prints: the outcome, the action log, the counts and the timing.
pub fn summary_lines(out: &ClearRun) -> Vec<String> {
    let r = &out.report;
    let v = &out.verdict;
    let mut lines = Vec::new();
    lines.push(format!(
        "clear: {} — {} of {} objects in the bin, {} left on the table, {} off it ({})",
        if out.success { "success" } else { "INCOMPLETE" },
        v.in_bin,
        v.objects,
        v.left_on_table,
        v.off_table,
        if r.stop.is_empty() { "-" } else { &r.stop }
    ));
    if let Some(e) = &out.error_message {
        lines.push(format!("  error: {e}"));
    }
    for a in &r.log {
        lines.push(format!(
            "  frame {:>2}: {:<10} o{:<3} at ({:.3}, {:.3}){}  {}",
            a.frame,
            a.action,
            a.object,
            a.position[0],
            a.position[1],
            a.push
                .map_or(String::new(), |(_, l)| format!(" by {:.2} m", l)),
            if a.ok {
                "ok".to_string()
            } else {
                format!("failed: {}", a.error.as_deref().unwrap_or("-"))
            }
        ));
    }
    for o in &r.left {
        lines.push(format!(
            "  left: o{:<3} at ({:.3}, {:.3}), {:.0} × {:.0} × {:.0} mm: {}",
            o.id,
            o.position[0],
            o.position[1],
            o.size[0] * 1e3,
            o.size[1] * 1e3,
            o.size[2] * 1e3,
            o.why
        ));
    }
    lines.push(format!(
        "  actions {} (grasps {}, failed {}, pushes {}), {:.2} objects per action; no-plan frames {}, IK backtracks {}, push loops {}",
        r.actions,
        r.grasps,
        r.failed_grasps,
        r.pushes,
        v.in_bin as f64 / r.actions.max(1) as f64,
        r.no_plan_frames,
        r.ik_backtracks,
        r.push_loops
    ));
    lines.push(format!(
        "  decision (CPU, frame in → first action): median {:.1} ms, p95 {:.1}, max {:.1} — perception {:.1}, predicates {:.1}, planning {:.1}, IK {:.1} (medians)",
        r.decision_ms.median,
        r.decision_ms.p95,
        r.decision_ms.max,
        r.perception_ms,
        r.predicates_ms,
        r.planning_ms,
        r.ik_ms
    ));
    lines.push(format!(
        "  collisions with other objects: {}; moved by accident: {}",
        out.collisions,
        v.disturbed.len()
    ));
    lines
}

/// The report page of `bench clear`: the suite's numbers, completion per table size,
/// decision, perception and planning times per frame.
pub fn bench_page(
    dir: &Path,
    command: String,
    (rows, frames): (&[BenchRow], &[[f64; 5]]),
    summary: &serde_json::Value,
) -> Result<()> {
    let numbers = [
        "scenes",
        "objects",
        "removed",
        "completion",
        "scenes_cleared",
        "actions",
        "objects_per_action",
        "grasp_success",
        "pushes",
        "push_loops",
        "collisions",
        "disturbed",
        "no_plan_frames",
        "ik_backtracks",
    ]
    .iter()
    .map(|k| (k.replace('_', " "), summary[*k].to_string()))
    .collect();
    // Completion per scene size: how many objects the table had.
    let mut sizes: Vec<(String, usize, usize)> = Vec::new();
    let mut by_size: std::collections::BTreeMap<usize, (usize, usize)> = Default::default();
    for r in rows {
        let e = by_size.entry(r.objects).or_default();
        e.0 += r.in_bin;
        e.1 += r.objects;
    }
    for (objects, (k, n)) in by_size {
        sizes.push((format!("{objects} objects"), k, n));
    }
    super::bench_report(
        dir,
        super::BenchSummary {
            title: "Clearing a cluttered table (seed 002)",
            command,
            numbers,
            classes: ("table size (objects in the bin)", sizes),
            distributions: vec![
                (
                    "Decision CPU per frame",
                    "ms",
                    frames.iter().map(|f| f[0]).collect(),
                ),
                (
                    "Perception CPU per frame",
                    "ms",
                    frames.iter().map(|f| f[1]).collect(),
                ),
                (
                    "Planning CPU per frame",
                    "ms",
                    frames.iter().map(|f| f[3]).collect(),
                ),
            ],
            bars: Vec::new(),
        },
        &summary,
    )?;
    Ok(())
}

/// What `bench clear` prints: a table row per scene, then the suite's numbers.
pub fn bench_lines(rows: &[BenchRow], s: &Summary) -> Vec<String> {
    let suite = &s.suite;
    let mut lines = Vec::new();
    lines.push("| seed | objects | in bin | actions | grasps (failed) | pushes | no-plan | IK backtracks | loops | collisions | moved | decision ms | stop |".to_string());
    lines.push("|---|---|---|---|---|---|---|---|---|---|---|---|---|".to_string());
    for r in rows {
        lines.push(format!(
            "| {} | {} | {} | {} | {} ({}) | {} | {} | {} | {} | {} | {} | {:.1} | {} |",
            r.seed,
            r.objects,
            r.in_bin,
            r.actions,
            r.grasps,
            r.failed_grasps,
            r.pushes,
            r.no_plan_frames,
            r.ik_backtracks,
            r.push_loops,
            r.collisions,
            r.disturbed,
            r.decision_median_ms,
            r.stop
        ));
    }
    lines.push(format!(
        "\n{suite}: {} scenes, completion {}/{} = {:.1} % (95 %: {:.1}–{:.1} %), {} scenes cleared; {:.2} objects per action; grasp success {:.1} % ({} of {}); push loops {}; collisions {}; moved by accident {}; off the table {}",
        s.scenes,
        s.removed,
        s.objects,
        100.0 * s.completion,
        100.0 * s.completion_95[0],
        100.0 * s.completion_95[1],
        s.scenes_cleared,
        s.objects_per_action,
        100.0 * s.grasp_success,
        s.grasps - s.failed_grasps,
        s.grasps,
        s.push_loops,
        s.collisions,
        s.disturbed,
        s.off_table
    ));
    lines.push(format!(
        "decision CPU per frame ({} frames): median {:.1} ms, p95 {:.1}, max {:.1}; medians: perception {:.1}, predicates {:.1}, planning {:.1}, IK {:.1}",
        s.frames,
        s.decision_ms.median,
        s.decision_ms.p95,
        s.decision_ms.max,
        s.perception_ms,
        s.predicates_ms,
        s.planning_ms,
        s.ik_ms
    ));
    lines
}
