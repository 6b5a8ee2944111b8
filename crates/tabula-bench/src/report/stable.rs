//! The report page and printed lines of `bench stable-poses`.

use crate::stable::BenchRow;
use anyhow::Result;
use std::path::Path;

/// The report page: CPU per object.
pub fn bench_page(out: &Path, reps: usize, rows: &[BenchRow]) -> Result<()> {
    super::bench_report(
        out,
        super::BenchSummary {
            title: "Stable poses of the test objects",
            command: format!("tabula bench stable-poses --reps {reps}"),
            numbers: vec![("objects".into(), rows.len().to_string())],
            classes: ("", Vec::new()),
            distributions: Vec::new(),
            bars: vec![(
                "CPU per object (median)",
                "ms",
                rows.iter()
                    .map(|r| {
                        (
                            format!("{} ({} vertices)", r.object, r.vertices),
                            r.cpu_ms_median,
                        )
                    })
                    .collect(),
            )],
        },
        &rows,
    )?;
    Ok(())
}

/// What `bench stable-poses` prints: a line per object.
pub fn bench_lines(rows: &[BenchRow]) -> Vec<String> {
    let mut lines = Vec::new();
    lines.push(format!(
        "{:<14} {:>8} {:>6} {:>26} {:>7} {:>10}",
        "object", "vertices", "poses", "most likely normal", "prob", "CPU ms"
    ));
    for r in rows {
        let n = r.most_likely_normal.unwrap_or([f64::NAN; 3]);
        lines.push(format!(
            "{:<14} {:>8} {:>6} {:>26} {:>7.3} {:>10.3}",
            r.object,
            r.vertices,
            r.poses,
            format!("({:.3}, {:.3}, {:.3})", n[0], n[1], n[2]),
            r.most_likely_probability.unwrap_or(f64::NAN),
            r.cpu_ms_median
        ));
    }
    lines
}
