//! `tabula clear`: seed 002's table clearing run in the simulator, judged by its physics.

use crate::report::{Recorded, Recording, Report, Section};
use crate::tasks::{TaskRunArgs, load_params};
use anyhow::{Result, anyhow, bail};
use clap::Args;
use tabula_bench::clear::{ClearRun as ClearJson, Summary};
use tabula_sim::SimWorld;
use tabula_sim::generate::{ClearSuite, clearing_scene};
use tabula_tasks::clear::ClearParams;

#[derive(Args)]
pub struct ClearArgs {
    #[command(flatten)]
    pub run: TaskRunArgs,
    /// Stop after this many actions (default: 3 per object seen first, plus 5).
    #[arg(long, value_parser = crate::args::count)]
    pub max_actions: Option<usize>,
}

/// Clears the table of `world` with its robot, judged by physics (recorded for the
/// report when `record`); returns the world afterwards.
pub fn clear_in(
    world: SimWorld,
    robot: Option<&str>,
    params: &ClearParams,
    max_actions: Option<usize>,
    seed: u64,
    record: bool,
) -> Result<(ClearJson, SimWorld, Option<Recorded>)> {
    let mut recording = Recording::new(record);
    let (out, world) =
        tabula_bench::clear::clear_in(world, robot, (params, max_actions), seed, |d| {
            recording.start(d)
        })?;
    let recorded = recording.finish(&world);
    Ok((out, world, recorded))
}

/// One clearing run by the robot served at `--connect`, judged there; the workcell
/// (bin, furniture) is read from the scene file here.
#[cfg(feature = "ros")]
fn clear_remote(a: &ClearArgs, params: &ClearParams) -> Result<(ClearJson, String)> {
    use crate::tasks::scene_robot_named;
    use tabula_bench::clear::{BIN, TABLE};
    use tabula_sim::judge::ClearSetup;
    use tabula_tasks::clear::clear;
    let world = a.run.world()?;
    let (robot_name, robot) = scene_robot_named(&world, a.run.robot.as_deref())?;
    let setup = ClearSetup::of(&world, BIN)?;
    let mut driver = crate::remote::connect(&a.run, &robot_name)?;
    let session = crate::remote::begin(
        &driver,
        tabula_ros::protocol::JudgedTask::new(
            "clear",
            a.run.seed,
            tabula_ros::protocol::ground::Clear {
                table: TABLE.into(),
                bin: BIN.into(),
            },
        ),
    )?;
    let request = tabula_bench::clear::request(&setup, a.max_actions);
    let outcome = clear(&mut driver, &robot, &request, params, &mut |_, e| {
        if let Err(err) = session.moment(e.judged()) {
            tracing::warn!("the judge missed a moment: {err}");
        }
    });
    let verdict = crate::remote::verdict(session, None)?;
    let scene = crate::remote::scene(&driver)?;
    Ok((ClearJson::of(outcome, verdict), scene))
}

pub fn run(a: ClearArgs) -> Result<()> {
    if a.run.dry_run {
        bail!("clearing pushes objects and a dry run moves none: run it in the simulator");
    }
    let params: ClearParams = load_params(a.run.params.as_deref())?;
    params.validate()?;
    let sections = |report: &mut Report, out: &ClearJson, recorded: Option<&Recorded>| {
        report.title = "tabula clear".into();
        let section = report_section(report, out, recorded)?;
        report.sections.push(section);
        Ok(())
    };
    if !a.run.connect.is_empty() {
        #[cfg(feature = "ros")]
        {
            let (out, scene) = clear_remote(&a, &params)?;
            return a
                .run
                .finish(&scene, &out, out.success, print_summary, |r, o| {
                    sections(r, o, None)
                });
        }
        #[cfg(not(feature = "ros"))]
        bail!("this tabula was built without ROS 2 support (feature `ros`)");
    }
    let (out, world, recorded) = clear_in(
        a.run.world()?,
        a.run.robot.as_deref(),
        &params,
        a.max_actions,
        a.run.seed,
        a.run.recording(),
    )?;
    a.run
        .finish(&world, &out, out.success, print_summary, |report, out| {
            sections(report, out, recorded.as_ref())
        })
}

/// The report's part for a clearing run: the metrics, the decision time per frame and
/// its parts, the action log, the replay and pictures of every grasp and release.
pub fn report_section(
    report: &mut Report,
    out: &ClearJson,
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
        let svg = crate::plots::stacked(
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

fn print_summary(out: &ClearJson) {
    for line in summary_lines(out) {
        println!("{line}");
    }
}

/// What `clear` prints: the outcome, the action log, the counts and the timing.
fn summary_lines(out: &ClearJson) -> Vec<String> {
    let r = &out.report;
    let v = &out.verdict;
    let mut lines = Vec::new();
    lines.push(format!(
        "clear: {} — {} of {} objects in the bin, {} left on the table ({})",
        if out.success { "success" } else { "INCOMPLETE" },
        v.in_bin,
        v.objects,
        v.left_on_table,
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

/// `tabula bench clear`: every scene of a suite cleared in the simulator (both cores,
/// one scene each, or spread over workers), judged by physics.
pub fn bench(b: &crate::trials::SuiteRun<'_>) -> Result<()> {
    let suite = b.suite;
    let which: ClearSuite = suite.parse().map_err(|e: String| anyhow!(e))?;
    let params: ClearParams = load_params(b.params)?;
    let runs = b.run("clear", |s| tabula_bench::clear::trial(which, s, &params))?;
    if let Some(dir) = b.save_failures {
        for t in &runs {
            if !t.row.success || t.row.collisions > 0 {
                std::fs::create_dir_all(dir)?;
                std::fs::write(
                    dir.join(format!("{suite}-{}.toml", t.row.seed)),
                    clearing_scene(which, t.row.seed),
                )?;
            }
        }
    }
    let mut rows = Vec::new();
    let mut frames: Vec<[f64; 5]> = Vec::new();
    for t in runs {
        rows.push(t.row);
        frames.extend(t.frames);
    }
    let s = Summary::of(suite, &rows, &frames);
    let summary = serde_json::to_value(&s)?;
    if let Some(dir) = b.report {
        bench_report(dir, b, (&rows, &frames), &summary)?;
    }
    if b.json {
        println!("{}", serde_json::to_string_pretty(&summary)?);
        return Ok(());
    }
    println!(
        "| seed | objects | in bin | actions | grasps (failed) | pushes | no-plan | IK backtracks | loops | collisions | moved | decision ms | stop |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    for r in &rows {
        println!(
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
        );
    }
    println!(
        "\n{suite}: {} scenes, completion {}/{} = {:.1} % (95 %: {:.1}–{:.1} %), {} scenes cleared; {:.2} objects per action; grasp success {:.1} % ({} of {}); push loops {}; collisions {}; moved by accident {}",
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
        s.disturbed
    );
    println!(
        "decision CPU per frame ({} frames): median {:.1} ms, p95 {:.1}, max {:.1}; medians: perception {:.1}, predicates {:.1}, planning {:.1}, IK {:.1}",
        s.frames,
        s.decision_ms.median,
        s.decision_ms.p95,
        s.decision_ms.max,
        s.perception_ms,
        s.predicates_ms,
        s.planning_ms,
        s.ik_ms
    );
    Ok(())
}

/// The report page of `bench clear`: the suite's numbers, completion per table size,
/// decision, perception and planning times per frame.
fn bench_report(
    dir: &std::path::Path,
    b: &crate::trials::SuiteRun<'_>,
    (rows, frames): (&[tabula_bench::clear::BenchRow], &[[f64; 5]]),
    summary: &serde_json::Value,
) -> Result<()> {
    let (suite, scenes, seed) = (b.suite, b.count, b.seed);
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
    crate::report::bench_report(
        dir,
        crate::report::BenchSummary {
            title: "Clearing a cluttered table (seed 002)",
            command: format!("tabula bench clear --suite {suite} --scenes {scenes} --seed {seed}"),
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
