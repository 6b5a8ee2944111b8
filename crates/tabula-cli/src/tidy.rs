//! `tabula tidy`: take every object from one table and stand each on another surface,
//! in the simulator, judged by its physics.

use crate::tasks::{TaskRunArgs, load_params};
use anyhow::{Result, bail};
use clap::Args;
use tabula_bench::tidy::{BenchRow, TidyRun as TidyJson};
use tabula_geom::Vec3;
use tabula_tasks::tidy::{TidyParams, TidyRequest};

#[derive(Args)]
pub struct TidyArgs {
    #[command(flatten)]
    pub run: TaskRunArgs,
    /// A point on the table to clear (world, m; default 0.8 m ahead of the robot).
    #[arg(long, num_args = 2, value_names = ["X", "Y"], allow_negative_numbers = true, value_parser = crate::args::finite)]
    pub from: Option<Vec<f64>>,
    /// A point on the surface to put things on (world, m; default the first found).
    #[arg(long, num_args = 2, value_names = ["X", "Y"], allow_negative_numbers = true, value_parser = crate::args::finite)]
    pub to: Option<Vec<f64>>,
    /// The scene's furniture to clear (the judge's reference).
    #[arg(long, default_value = "table")]
    pub source: String,
    /// Which arm (default: the robot's first arm with a gripper).
    #[arg(long)]
    pub arm: Option<String>,
}

/// The height the default look point and `--from`'s are taken at (m): a table's.
const TABLE_HEIGHT: f64 = 0.75;

fn point(xy: &Option<Vec<f64>>) -> Option<Vec3> {
    xy.as_ref().map(|v| Vec3::new(v[0], v[1], TABLE_HEIGHT))
}

fn print_summary(out: &TidyJson) {
    println!(
        "tidy: {} of {} objects moved to another surface in {} actions; {} knocked over, {} lost; decision median {:.0} ms",
        out.moved,
        out.objects,
        out.actions,
        out.verdict.knocked.len(),
        out.verdict.lost.len(),
        out.decision_ms.median
    );
    for f in &out.failed {
        println!(
            "  failed at ({:.2}, {:.2}): {} — {}",
            f.object[0], f.object[1], f.reason, f.message
        );
    }
    if let Some(e) = &out.error_message {
        println!("  stopped: {e}");
    }
}

pub fn run(a: TidyArgs) -> Result<()> {
    if a.run.dry_run || !a.run.connect.is_empty() {
        bail!("tidy runs in the simulator here (no --dry-run, no --connect yet)");
    }
    let params: TidyParams = load_params(a.run.params.as_deref())?;
    let request = TidyRequest {
        arm: a.arm.clone(),
        from: point(&a.from),
        to: point(&a.to),
    };
    let (out, world) = tabula_bench::tidy::tidy_in(
        a.run.world()?,
        (a.run.robot.as_deref(), &a.source),
        (&request, &params),
        a.run.seed,
        |_| {},
    )?;
    a.run
        .finish(&world, &out, out.success, print_summary, |report, out| {
            report.title = "tabula tidy".into();
            let mut s = tabula_bench::report::Section::new("Tidying a table");
            s.number("objects on the table", out.objects)
                .number("moved to another surface", out.moved)
                .number("actions", out.actions)
                .number("knocked over", out.verdict.knocked.len());
            report.sections.push(s);
            Ok(())
        })
}

/// `tabula bench tidy`: the family's tasks `seed..seed + tasks`, both cores.
pub fn bench(
    tasks: u64,
    seed: u64,
    save_scenes: Option<&std::path::Path>,
    json: bool,
) -> Result<()> {
    use rayon::prelude::*;
    let params = TidyParams::default();
    let rows: Vec<BenchRow> = (seed..seed.saturating_add(tasks))
        .into_par_iter()
        .map(|s| tabula_bench::tidy::trial(s, &params, save_scenes))
        .collect::<Result<_>>()?;
    let objects: usize = rows.iter().map(|r| r.objects).sum();
    let moved: usize = rows.iter().map(|r| r.moved).sum();
    let knocked: usize = rows.iter().map(|r| r.knocked).sum();
    let decisions: Vec<f64> = rows.iter().map(|r| r.decision_ms).collect();
    let spread = tabula_tasks::clear::Stats::of(&decisions);
    if json {
        println!(
            "{}",
            serde_json::json!({
                "tasks": rows.len(), "objects": objects, "moved": moved,
                "knocked": knocked, "decision_ms": spread, "rows": rows,
            })
        );
        return Ok(());
    }
    for r in &rows {
        println!(
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
        );
    }
    let (lo, hi) = tabula_bench::stats::wilson(moved, objects);
    println!(
        "tidy: {moved} of {objects} objects moved ({:.1} %, 95 % {:.1}–{:.1} %), {knocked} knocked over; decision median {:.0} ms, p95 {:.0} ms",
        100.0 * moved as f64 / objects.max(1) as f64,
        100.0 * lo,
        100.0 * hi,
        spread.median,
        spread.p95
    );
    Ok(())
}
