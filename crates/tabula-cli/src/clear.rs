//! `tabula clear`: seed 002's table clearing run in the simulator, judged by its physics.

use crate::report::{Recorded, Recording, Report, Section};
use crate::tasks::{TaskRunArgs, load_params, scene_robot_named};
use anyhow::{Result, anyhow, bail};
use clap::Args;
use serde::Serialize;
use tabula_sim::SimWorld;
use tabula_sim::generate::{ClearSuite, clearing_scene};
use tabula_sim::verdict::{ClearSetup, ClearVerdict, run_clear_judged};
use tabula_tasks::clear::{ClearError, ClearParams, ClearReport, ClearRequest, clear};

#[derive(Args)]
pub struct ClearArgs {
    #[command(flatten)]
    pub run: TaskRunArgs,
    /// Stop after this many actions (default: 3 per object seen first, plus 5).
    #[arg(long, value_parser = crate::args::count)]
    pub max_actions: Option<usize>,
}

/// Everything `clear` prints with `--json`: the task's own metrics, the judged ones.
#[derive(Serialize)]
pub struct ClearJson {
    /// Every object that stood on the table (if any) ended in the bin.
    pub success: bool,
    pub error: Option<String>,
    pub error_message: Option<String>,
    #[serde(flatten)]
    pub report: ClearReport,
    /// Arm–object contacts with objects the arm was not acting on (judged).
    pub collisions: usize,
    pub verdict: ClearVerdict,
}

/// Clears the table of `world` with its robot, judged by physics; returns the world
/// afterwards.
pub fn clear_in(
    world: SimWorld,
    robot: Option<&str>,
    params: &ClearParams,
    max_actions: Option<usize>,
    seed: u64,
    record: bool,
) -> Result<(ClearJson, SimWorld, Option<Recorded>)> {
    let (robot_name, robot) = scene_robot_named(&world, robot)?;
    let mut recording = Recording::new(record);
    let (outcome, verdict, world) = run_clear_judged(
        world,
        &robot_name,
        (TABLE, BIN),
        seed,
        |driver, setup, hook| {
            recording.start(driver);
            let request = clear_request(setup, max_actions);
            clear(driver, &robot, &request, params, &mut |d, e| {
                hook(d, e.judged())
            })
        },
    )?;
    let recorded = recording.finish(&world);
    Ok((clear_json(outcome, verdict), world, recorded))
}

/// What `clear` prints, from the task's outcome and the judge's verdict.
fn clear_json(outcome: Result<ClearReport, ClearError>, verdict: ClearVerdict) -> ClearJson {
    let (report, error) = match outcome {
        Ok(r) => (r, None),
        Err(e) => (ClearReport::default(), Some(e)),
    };
    ClearJson {
        success: error.is_none() && verdict.in_bin == verdict.objects,
        error: error.as_ref().map(|e| e.kind().to_string()),
        error_message: error.as_ref().map(|e| e.to_string()),
        report,
        collisions: verdict.collisions.len(),
        verdict,
    }
}

/// The request a clearing run makes of its workcell.
fn clear_request(setup: &ClearSetup, max_actions: Option<usize>) -> ClearRequest {
    ClearRequest {
        arm: None,
        drop_point: setup.drop_point,
        drop_spread: setup.drop_spread,
        obstacles: setup.obstacles.clone(),
        max_actions,
    }
}

/// One clearing run by the robot served at `--connect`, judged there; the workcell
/// (bin, furniture) is read from the scene file here.
#[cfg(feature = "ros")]
fn clear_remote(a: &ClearArgs, params: &ClearParams) -> Result<(ClearJson, String)> {
    let world = a.run.world()?;
    let (robot_name, robot) = scene_robot_named(&world, a.run.robot.as_deref())?;
    let setup = ClearSetup::of(&world, BIN)?;
    let mut driver = crate::remote::connect(&a.run, &robot_name)?;
    crate::remote::begin(
        &driver,
        tabula_ros::protocol::JudgedTask::Clear {
            seed: a.run.seed,
            table: TABLE.into(),
            bin: BIN.into(),
        },
    )?;
    let request = clear_request(&setup, a.max_actions);
    let outcome = clear(&mut driver, &robot, &request, params, &mut |d, e| {
        if let Err(err) = d.clear_event(e.judged()) {
            tracing::warn!("the judge missed a moment: {err}");
        }
    });
    let verdict = crate::remote::verdict(&driver, None)?;
    let scene = crate::remote::scene(&driver)?;
    Ok((clear_json(outcome, verdict), scene))
}

/// The furniture a clearing scene clears, and the bin it clears into.
const TABLE: &str = "table";
const BIN: &str = "bin";

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

#[derive(Serialize, serde::Deserialize)]
pub struct BenchRow {
    seed: u64,
    objects: usize,
    in_bin: usize,
    actions: usize,
    grasps: usize,
    failed_grasps: usize,
    pushes: usize,
    no_plan_frames: usize,
    ik_backtracks: usize,
    push_loops: usize,
    collisions: usize,
    disturbed: usize,
    decision_median_ms: f64,
    stop: String,
    /// Cleared without error (every object on the table in the bin).
    success: bool,
}

/// Wilson score interval (95 %) of `k` successes in `n`.
pub fn wilson(k: usize, n: usize) -> (f64, f64) {
    if n == 0 {
        return (0.0, 1.0);
    }
    let (k, n, z) = (k as f64, n as f64, 1.96);
    let p = k / n;
    let d = 1.0 + z * z / n;
    let c = (p + z * z / (2.0 * n)) / d;
    let h = z * ((p * (1.0 - p) / n + z * z / (4.0 * n * n)).sqrt()) / d;
    ((c - h).max(0.0), (c + h).min(1.0))
}

/// One scene of a clearing suite, cleared in the simulator and judged by physics: its
/// row and each frame's decision time and its parts.
#[derive(Serialize, serde::Deserialize)]
pub struct Trial {
    row: BenchRow,
    frames: Vec<[f64; 5]>,
}

fn trial(which: ClearSuite, s: u64, params: &ClearParams) -> Result<Trial> {
    let text = clearing_scene(which, s);
    let scene = tabula_sim::Scene::parse(&text, "generated")?;
    let world = SimWorld::from_scene(&scene, Default::default())?;
    let (out, _, _) = clear_in(world, None, params, None, s, false)?;
    let r = &out.report;
    let v = &out.verdict;
    let frames = r
        .frames
        .iter()
        .map(|f| {
            [
                f.decision_ms,
                f.perception_ms,
                f.predicates_ms,
                f.planning_ms,
                f.ik_ms,
            ]
        })
        .collect();
    Ok(Trial {
        row: BenchRow {
            seed: s,
            objects: v.objects,
            in_bin: v.in_bin,
            actions: r.actions,
            grasps: r.grasps,
            failed_grasps: r.failed_grasps,
            pushes: r.pushes,
            no_plan_frames: r.no_plan_frames,
            ik_backtracks: r.ik_backtracks,
            push_loops: r.push_loops,
            collisions: out.collisions,
            disturbed: v.disturbed.len(),
            decision_median_ms: r.decision_ms.median,
            stop: match &out.error_message {
                Some(e) => e.clone(),
                None => r.stop.clone(),
            },
            success: out.success,
        },
        frames,
    })
}

/// A clearing trial as a worker runs it.
#[cfg(feature = "ros")]
pub fn trial_of(spec: &crate::trials::TrialSpec) -> Result<Trial> {
    let which: ClearSuite = spec.suite.parse().map_err(|e: String| anyhow!(e))?;
    let params: ClearParams = match &spec.params {
        Some(text) => crate::tasks::parse_params(text, "the bench's parameters")?,
        None => ClearParams::default(),
    };
    trial(which, spec.seed, &params)
}

/// `tabula bench clear`: every scene of a suite cleared in the simulator (both cores,
/// one scene each, or spread over workers), judged by physics.
#[allow(clippy::too_many_arguments)]
pub fn bench(
    suite: &str,
    scenes: u64,
    seed: u64,
    params_path: Option<&std::path::Path>,
    save_failures: Option<&std::path::Path>,
    json: bool,
    report: Option<&std::path::Path>,
    spread: &crate::trials::TrialArgs,
) -> Result<()> {
    let which: ClearSuite = suite.parse().map_err(|e: String| anyhow!(e))?;
    let params: ClearParams = load_params(params_path)?;
    params.validate()?;
    let params_text = crate::trials::params_text(params_path)?;
    let progress = crate::progress::steps(scenes, suite);
    let runs = crate::trials::run(
        spread,
        seed..seed.saturating_add(scenes),
        |s| crate::trials::TrialSpec {
            bench: "clear".into(),
            suite: suite.into(),
            params: params_text.clone(),
            seed: s,
        },
        |s| trial(which, s, &params),
        &progress,
    )?;
    if let Some(dir) = save_failures {
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
    progress.finish_and_clear();
    let mut rows = Vec::new();
    let mut frames: Vec<[f64; 5]> = Vec::new();
    for t in runs {
        rows.push(t.row);
        frames.extend(t.frames);
    }
    let sum = |f: fn(&BenchRow) -> usize| rows.iter().map(f).sum::<usize>();
    let (objects, in_bin, actions) = (sum(|r| r.objects), sum(|r| r.in_bin), sum(|r| r.actions));
    let (grasps, failed) = (sum(|r| r.grasps), sum(|r| r.failed_grasps));
    let cleared = rows
        .iter()
        .filter(|r| r.objects > 0 && r.in_bin == r.objects)
        .count();
    let (lo, hi) = wilson(in_bin, objects);
    let col =
        |k: usize| tabula_tasks::clear::Stats::of(&frames.iter().map(|f| f[k]).collect::<Vec<_>>());
    let decision = col(0);
    let summary = serde_json::json!({
        "suite": suite,
        "scenes": rows.len(),
        "objects": objects,
        "removed": in_bin,
        "completion": in_bin as f64 / objects.max(1) as f64,
        "completion_95": [lo, hi],
        "scenes_cleared": cleared,
        "actions": actions,
        "objects_per_action": in_bin as f64 / actions.max(1) as f64,
        "grasps": grasps,
        "failed_grasps": failed,
        "grasp_success": (grasps - failed) as f64 / grasps.max(1) as f64,
        "pushes": sum(|r| r.pushes),
        "push_loops": sum(|r| r.push_loops),
        "collisions": sum(|r| r.collisions),
        "disturbed": sum(|r| r.disturbed),
        "no_plan_frames": sum(|r| r.no_plan_frames),
        "ik_backtracks": sum(|r| r.ik_backtracks),
        "frames": frames.len(),
        "decision_ms": decision,
        "perception_ms": col(1).median,
        "predicates_ms": col(2).median,
        "planning_ms": col(3).median,
        "ik_ms": col(4).median,
        "rows": rows,
    });
    if let Some(dir) = report {
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
        for r in &rows {
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
                command: format!(
                    "tabula bench clear --suite {suite} --scenes {scenes} --seed {seed}"
                ),
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
    }
    if json {
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
        rows.len(),
        in_bin,
        objects,
        100.0 * in_bin as f64 / objects.max(1) as f64,
        100.0 * lo,
        100.0 * hi,
        cleared,
        in_bin as f64 / actions.max(1) as f64,
        100.0 * (grasps - failed) as f64 / grasps.max(1) as f64,
        grasps - failed,
        grasps,
        sum(|r| r.push_loops),
        sum(|r| r.collisions),
        sum(|r| r.disturbed)
    );
    println!(
        "decision CPU per frame ({} frames): median {:.1} ms, p95 {:.1}, max {:.1}; medians: perception {:.1}, predicates {:.1}, planning {:.1}, IK {:.1}",
        frames.len(),
        decision.median,
        decision.p95,
        decision.max,
        col(1).median,
        col(2).median,
        col(3).median,
        col(4).median
    );
    Ok(())
}
