//! The report pages and printed lines of the perception benchmarks.

use crate::perception::PerceptionBench;
use anyhow::Result;
use serde_json::Value;
use std::path::Path;

/// The report page of `bench perception`: the reference frame's quality, the suite's
/// objects found, the pipeline's CPU per suite frame, every stage's CPU.
pub fn bench_page(dir: &Path, b: &PerceptionBench) -> Result<()> {
    let (scenes, reps, reference, rows) = (b.scenes, b.reps, &b.reference, &b.stages);
    let (recovered, objects) = b.recovered();
    super::bench_report(
        dir,
        super::BenchSummary {
            title: "Perception stages and the tabletop pipeline",
            command: format!("tabula bench perception --scenes {scenes} --reps {reps}"),
            numbers: vec![
                (
                    "reference frame: objects with IoU > 0.8".into(),
                    format!("{} of {}", reference.recovered, reference.objects),
                ),
                (
                    "reference frame: table precision / recall".into(),
                    format!(
                        "{:.4} / {:.4}",
                        reference.table_precision, reference.table_recall
                    ),
                ),
                (
                    "suite: objects recovered".into(),
                    format!("{recovered} of {objects}"),
                ),
            ],
            classes: ("", Vec::new()),
            distributions: vec![("Pipeline CPU per suite frame", "ms", b.cpu())],
            bars: vec![(
                "CPU per stage on the reference frame (1 thread, median)",
                "ms",
                rows.iter()
                    .map(|r| (r.stage.clone(), r.cpu_ms_1_thread))
                    .collect(),
            )],
        },
        &serde_json::json!({"stages": rows, "suite": b.suite}),
    )?;
    Ok(())
}

/// The report page of `bench frames`: the pipeline's CPU and wall time per file.
pub fn frames_page(
    dir: &Path,
    (layout, reps, clouds): (&str, usize, usize),
    rows: &[Value],
) -> Result<()> {
    let bars = |key: &str| -> Vec<(String, f64)> {
        rows.iter()
            .map(|r| {
                (
                    format!(
                        "{} ({})",
                        std::path::Path::new(r["file"].as_str().unwrap_or(""))
                            .file_name()
                            .map_or(String::new(), |f| f.to_string_lossy().to_string()),
                        r["layout"].as_str().unwrap_or("")
                    ),
                    r[key].as_f64().unwrap_or(f64::NAN),
                )
            })
            .collect()
    };
    super::bench_report(
        dir,
        super::BenchSummary {
            title: "Perception on sensor frames",
            command: format!("tabula bench frames --layout {layout} --reps {reps} --cloud …"),
            numbers: vec![("frames".into(), clouds.to_string())],
            classes: ("", Vec::new()),
            distributions: Vec::new(),
            bars: vec![
                (
                    "Pipeline CPU per frame (1 thread, median)",
                    "ms",
                    bars("cpu_ms"),
                ),
                (
                    "Pipeline wall time per frame (2 threads, median)",
                    "ms",
                    bars("wall_ms"),
                ),
            ],
        },
        &rows.to_vec(),
    )?;
    Ok(())
}

/// What `bench frames` prints: a table row per file and layout.
pub fn frames_lines(rows: &[Value]) -> Vec<String> {
    let mut lines = Vec::new();
    lines.push("| file | layout | points | objects (+ cut by the edge) | CPU ms, 1 thread | wall ms, 2 threads |".to_string());
    lines.push("|---|---|---:|---:|---:|---:|".to_string());
    for r in rows {
        lines.push(format!(
            "| {} | {} | {} | {} (+{}) | {:.1} | {:.1} |",
            r["file"].as_str().unwrap_or(""),
            r["layout"].as_str().unwrap_or(""),
            r["points"],
            r["objects"],
            r["partial_objects"],
            r["cpu_ms"].as_f64().unwrap_or(f64::NAN),
            r["wall_ms"].as_f64().unwrap_or(f64::NAN)
        ));
    }
    lines
}
