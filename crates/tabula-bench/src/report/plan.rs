//! The report page and printed lines of `tabula plan bench`.

use crate::plan::SizeRow;
use anyhow::Result;
use serde_json::Value;
use std::path::Path;

/// The report page: problems solved optimally per size, grounding and planning,
/// replanning and the seed's loop per size.
pub fn bench_page(dir: &Path, (objects, problems): (&[usize], u64), rows: &[Value]) -> Result<()> {
    let per_size = |key: &str| -> Vec<(String, f64)> {
        rows.iter()
            .map(|r| {
                (
                    format!("{} objects", r["objects"]),
                    r[key].as_f64().unwrap_or(f64::NAN),
                )
            })
            .collect()
    };
    super::bench_report(
        dir,
        super::BenchSummary {
            title: "Task planning: table clearing in PDDL (seed 002's domain)",
            command: format!(
                "tabula plan bench --objects {} --problems {}",
                objects
                    .iter()
                    .map(ToString::to_string)
                    .collect::<Vec<_>>()
                    .join(","),
                problems
            ),
            numbers: Vec::new(),
            classes: (
                "table size (solved optimally)",
                rows.iter()
                    .map(|r| {
                        (
                            format!("{} objects", r["objects"]),
                            r["solved"].as_u64().unwrap_or(0) as usize,
                            problems as usize,
                        )
                    })
                    .collect(),
            ),
            distributions: Vec::new(),
            bars: vec![
                (
                    "Grounding and optimal plan (median)",
                    "ms",
                    per_size("ground_plus_optimal_ms"),
                ),
                (
                    "Replanning after one IK-infeasible fact (median)",
                    "ms",
                    per_size("replan_ms"),
                ),
                (
                    "The seed's loop, ten decisions (median)",
                    "ms",
                    per_size("loop10_ms"),
                ),
            ],
        },
        &rows,
    )?;
    Ok(())
}

/// What `plan bench` prints before its rows.
pub fn header_lines(problems: u64) -> Vec<String> {
    let mut lines = Vec::new();
    lines.push(format!(
        "table clearing (seed 002 domain), in process, {} problems per size, median wall ms",
        problems
    ));
    lines.push("  N  ground  optimal (len, exp.)  ground+optimal  replan-1-change  fast (len)  10-call loop  goal check".to_string());
    lines
}

/// A table size's row as `plan bench` prints it.
pub fn row_line(r: &SizeRow, problems: u64) -> String {
    let n = r.objects;
    format!(
        "{:>3}  {:>6.2}  {:>7.2} ({:>5.1}, {:>5.0})  {:>14.2}  {:>15.2}  {:>4.2} ({:>5.1})  {:>12.2}  {:>10.2}{}",
        n,
        r.ground_ms,
        r.optimal_ms,
        r.mean_optimal_length,
        r.mean_expanded,
        r.ground_plus_optimal_ms,
        r.replan_ms,
        r.fast_ms,
        r.mean_fast_length,
        r.loop10_ms,
        r.goal_check_ms,
        if r.solved < problems {
            format!("   ({}/{} solved)", r.solved, problems)
        } else {
            String::new()
        }
    )
}
