//! `tabula place` and `tabula bench place`: placing an unknown held object stably
//! (seed 000) in the simulator, judged by its physics.

use crate::report::{Recorded, Recording, Report, Section};
use crate::tasks::{TaskRunArgs, load_params, scene_robot};
use anyhow::Result;
use tabula_bench::place::{BenchRow, PlaceRun as PlaceJson, suite_of, task_of, trial};
use tabula_bench::stats::wilson;
use tabula_sim::SimWorld;
use tabula_tasks::place::{PlaceParams, PlaceRequest};

#[derive(clap::Args)]
pub struct PlaceArgs {
    #[command(flatten)]
    pub run: TaskRunArgs,
    /// The arm holding the object (`auto`: the one whose gripper is closed).
    #[arg(long, default_value = "auto")]
    pub arm: String,
}

/// One placement in `world`, judged by its physics (recorded for the report when
/// `record`); returns the world afterwards.
pub fn place_in(
    world: SimWorld,
    robot: Option<&str>,
    request: &PlaceRequest,
    params: &PlaceParams,
    seed: u64,
    record: bool,
) -> Result<(PlaceJson, SimWorld, Option<Recorded>)> {
    let mut recording = Recording::new(record);
    let (out, world) = tabula_bench::place::place_in(world, robot, (request, params), seed, |d| {
        recording.start(d)
    })?;
    let recorded = recording.finish(&world);
    Ok((out, world, recorded))
}

/// One placement by the robot served at `--connect`, judged there.
#[cfg(feature = "ros")]
fn place_remote(
    a: &PlaceArgs,
    world: &SimWorld,
    request: &PlaceRequest,
    params: &PlaceParams,
) -> Result<(PlaceJson, String)> {
    use crate::tasks::scene_robot_named;
    use tabula_bench::judged::planned_rest;
    use tabula_tasks::place::place;
    let (robot_name, robot) = scene_robot_named(world, a.run.robot.as_deref())?;
    let mut driver = crate::remote::connect(&a.run, &robot_name)?;
    let session = crate::remote::begin(
        &driver,
        tabula_ros::protocol::JudgedTask::new("place", a.run.seed, ()),
    )?;
    let outcome = place(&mut driver, &robot, request, params);
    let verdict = crate::remote::verdict(session, planned_rest(&outcome, params))?;
    let scene = crate::remote::scene(&driver)?;
    Ok((PlaceJson::of(outcome, verdict, false), scene))
}

pub fn run(a: PlaceArgs) -> Result<()> {
    let params: PlaceParams = load_params(a.run.params.as_deref())?;
    let world = a.run.world()?;
    let robot = scene_robot(&world, a.run.robot.as_deref())?;
    crate::tasks::check_arm(&world, &robot, &a.arm)?;
    let request = PlaceRequest {
        arm: if a.arm == "auto" {
            held_by(&world, &robot)
        } else {
            Some(a.arm.clone())
        },
        not_on: Vec::new(),
        near: None,
    };
    let sections = |report: &mut Report, out: &PlaceJson, recorded: Option<&Recorded>| {
        report.title = "tabula place".into();
        let section = report_section(report, out, &params, recorded)?;
        report.sections.push(section);
        Ok(())
    };
    if !a.run.connect.is_empty() {
        #[cfg(feature = "ros")]
        {
            let (out, scene) = place_remote(&a, &world, &request, &params)?;
            return a
                .run
                .finish(&scene, &out, out.success, print_summary, |r, o| {
                    sections(r, o, None)
                });
        }
        #[cfg(not(feature = "ros"))]
        anyhow::bail!("this tabula was built without ROS 2 support (feature `ros`)");
    }
    let (out, world, recorded) = place_in(
        world,
        Some(&robot),
        &request,
        &params,
        a.run.seed,
        a.run.recording(),
    )?;
    a.run
        .finish(&world, &out, out.success, print_summary, |report, out| {
            sections(report, out, recorded.as_ref())
        })
}

/// The report's part for a placement: the verdict, the scanned model and its stable
/// poses, time per phase, the replay and pictures of the release.
pub fn report_section(
    report: &mut Report,
    out: &PlaceJson,
    params: &PlaceParams,
    recorded: Option<&Recorded>,
) -> Result<Section> {
    let r = &out.report;
    let v = &out.verdict;
    let mut s = Section::new("Placing an unknown object (seed 000)");
    s.text(format!(
        "{}: `{}` rests on {}, {:.1}° from the planned pose, moved {:.1} mm after release.",
        if out.success { "Placed" } else { "Failed" },
        v.object,
        v.surface.as_deref().unwrap_or("nothing"),
        v.orientation_error_deg,
        v.moved_after_release_m * 1e3
    ));
    if let Some(e) = &out.error {
        s.text(format!("Error ({}): {}", e.kind, e.message));
    }
    s.number("success", out.success)
        .number("arm", r.arm.as_deref().unwrap_or("-"))
        .number("decision CPU (ms)", format!("{:.1}", out.decision_ms))
        .number("scan processing CPU (ms)", format!("{:.1}", r.scan_cpu_ms))
        .number("stable poses found", r.poses_found)
        .number("surfaces found", r.surfaces_found)
        .number("spots tried", r.candidates_tried)
        .number(
            "orientation error (°)",
            format!("{:.2}", v.orientation_error_deg),
        )
        .number("furniture contacts", v.furniture_contacts.len());
    if let Some(m) = &r.model {
        s.number("scanned model", model_line(m));
    }
    s.log = r
        .rejected
        .iter()
        .map(|w| format!("rejected: {w}"))
        .collect();
    if !r.model_points.is_empty()
        && let Ok(poses) = tabula_tasks::stable::of_cloud(&r.model_points, &params.stable)
        && !poses.poses.is_empty()
    {
        let bars: Vec<(String, f64)> = poses
            .poses
            .iter()
            .take(12)
            .map(|p| {
                let chosen = out
                    .stable_pose
                    .as_ref()
                    .is_some_and(|c| c.normal().dot(p.normal()) > 0.999);
                (
                    format!(
                        "({:+.2} {:+.2} {:+.2}) margin {:.0} mm, {:.0}°{}",
                        p.support_normal[0],
                        p.support_normal[1],
                        p.support_normal[2],
                        p.margin_m * 1e3,
                        p.topple_deg,
                        if chosen { " — placed" } else { "" }
                    ),
                    100.0 * p.probability,
                )
            })
            .collect();
        let svg = crate::plots::bars(
            "Stable poses of the scanned object (support normal in the hand)",
            "landing probability (%)",
            &bars,
        )?;
        let fig = report.svg(
            "stable-poses",
            "Stable poses of the scanned model: probability, stability margin, topple tilt",
            &svg,
        )?;
        s.figures.push(fig);
    }
    if let Some(view) = &r.top_view {
        // Objects as the outlines of their points seen from above.
        let objects = view
            .objects
            .iter()
            .map(|pts| {
                let flat: Vec<tabula_geom::Vec2> =
                    pts.iter().map(|q| view.map.to_plane(*q)).collect();
                tabula_geom::polygon::convex_hull_2d(&flat)
                    .into_iter()
                    .map(|i| pts[i])
                    .collect()
            })
            .collect();
        let (svg, _) = crate::perceive::top_view(&crate::perceive::TopView {
            map: &view.map,
            outline: &view.outline,
            objects,
            boxes: Vec::new(),
            labels: Vec::new(),
            spot: view.spot.clone(),
        })?;
        let fig = report.svg(
            "top-view",
            "The surface as the placement saw it: free (green), objects (red), unseen (grey), the object's footprint where it was planned to rest (blue)",
            &svg,
        )?;
        s.figures.push(fig);
    }
    crate::pick_place::phase_plot(report, &mut s, &out.phases)?;
    if let Some(rec) = recorded {
        report.recorded(&mut s, "place", rec)?;
    }
    Ok(s)
}

/// The scanned model in one line: points, views, size in the tool frame, hull volume.
pub fn model_line(m: &tabula_tasks::place::ModelReport) -> String {
    format!(
        "{} points from {} of {} views, {:.0} × {:.0} × {:.0} mm, hull {:.1} cm³",
        m.points,
        m.views,
        m.views_tried,
        m.size[0] * 1e3,
        m.size[1] * 1e3,
        m.size[2] * 1e3,
        m.hull_volume_m3 * 1e6
    )
}

fn print_summary(out: &PlaceJson) {
    let r = &out.report;
    println!(
        "place{}: {} (arm {})",
        if out.dry_run { " (dry run)" } else { "" },
        if out.success { "success" } else { "FAILED" },
        r.arm.as_deref().unwrap_or("-")
    );
    if let Some(m) = &r.model {
        println!("  model: {}", model_line(m));
    }
    if let Some(s) = &out.stable_pose {
        println!(
            "  stable pose: normal ({:.2}, {:.2}, {:.2}) in the tool, margin {:.1} mm, topples at {:.1}° (of {} poses)",
            s.support_normal[0],
            s.support_normal[1],
            s.support_normal[2],
            s.margin_m * 1e3,
            s.topple_deg,
            r.poses_found
        );
    }
    if let Some(s) = &r.surface {
        println!(
            "  surface: {:.3} m high at ({:.2}, {:.2}), {:.0} cm² ({} found)",
            s.height,
            s.centroid[0],
            s.centroid[1],
            s.area_m2 * 1e4,
            r.surfaces_found
        );
    }
    if let Some(g) = r.base_goal {
        println!(
            "  base drove to ({:.2}, {:.2}, {:.0}°)",
            g[0],
            g[1],
            g[2].to_degrees()
        );
    }
    if let Some(e) = &out.error {
        println!("  error ({}): {}", e.kind, e.message);
        for why in r.rejected.iter().take(10) {
            println!("    rejected: {why}");
        }
    }
    for p in &out.phases {
        println!(
            "  {:<22} {:>9.1} ms  {:<6}  decision CPU {:>7.1} ms",
            p.name,
            p.ms,
            if p.ok { "ok" } else { "failed" },
            p.plan_ms.unwrap_or(0.0)
        );
    }
    println!("  decision (CPU)         {:>9.1} ms", out.decision_ms);
    let v = &out.verdict;
    println!(
        "  verdict: `{}` on {}, {} its edges, {:.1}° from the planned pose, moved {:.1} mm after release, {} disturbed, {} furniture contacts",
        v.object,
        v.surface.as_deref().unwrap_or("nothing"),
        if v.inside_edges { "inside" } else { "outside" },
        v.orientation_error_deg,
        v.moved_after_release_m * 1e3,
        v.disturbed.len(),
        v.furniture_contacts.len()
    );
}

/// The arm holding the scene's held object (the scene's `hold` says which gripper):
/// the task's precondition, as a user would state it.
fn held_by(world: &SimWorld, robot: &str) -> Option<String> {
    let r = world.robot(robot).ok()?;
    let object = world.held_objects(robot).into_iter().next()?;
    let at = world.pose(&object).ok()?.translation;
    r.description
        .arms
        .iter()
        .filter_map(|a| {
            let g = r
                .description
                .grippers
                .iter()
                .find(|g| Some(&g.name) == a.gripper.as_ref())?;
            let tool = world.link_pose(robot, &g.tool_link).ok()?;
            Some((tool.translation.distance(at), a.name.clone()))
        })
        .min_by(|a, b| a.0.total_cmp(&b.0))
        .map(|(_, n)| n)
}

/// `tabula bench place`: the generated suite, each task placed in the simulator (both
/// cores, one task each, or spread over workers) and judged by physics.
pub fn bench(b: &crate::trials::SuiteRun<'_>) -> Result<()> {
    let (suite, save_failures) = (b.suite, b.save_failures);
    let kind = suite_of(suite)?;
    let params: PlaceParams = load_params(b.params)?;
    // Saved failures keep their meshes beside them.
    let mesh_dir = match save_failures {
        Some(d) => d.join("meshes"),
        None => std::env::temp_dir().join(format!("tabula-place-meshes-{}", std::process::id())),
    };
    if let Some(d) = save_failures {
        std::fs::create_dir_all(d)?;
    }
    let rows = b.run("place", |s| trial(s, kind, &params, &mesh_dir));
    // Failures are kept; so are slow decisions (over a second), to look into.
    if let (Some(d), Ok(rows)) = (save_failures, &rows) {
        for r in rows {
            if r.cause.is_some() || r.decision_ms > 1000.0 {
                let task = task_of(r.seed, kind, &mesh_dir)?;
                std::fs::write(
                    d.join(format!("place-{suite}-{}.toml", r.seed)),
                    &task.scene,
                )?;
            }
        }
    }
    if save_failures.is_none() {
        let _ = std::fs::remove_dir_all(&mesh_dir);
    }
    let rows: Vec<BenchRow> = rows?;
    // Failures by cause, for the report and the summary line.
    let mut causes: std::collections::BTreeMap<&str, usize> = Default::default();
    for r in &rows {
        if let Some(c) = &r.cause {
            *causes.entry(c.as_str()).or_default() += 1;
        }
    }
    if let Some(dir) = b.report {
        bench_report(dir, b, &rows, &causes)?;
    }
    if b.json {
        println!("{}", serde_json::to_string_pretty(&rows)?);
        return Ok(());
    }
    for r in &rows {
        println!(
            "{:>5} {:<14} {:<7} clutter {} {:<5} {:<8} {:>6.1}° {:>7.1} mm {:>8.1} ms {:>6}  {}",
            r.seed,
            r.object,
            format!("{:?}", r.layout).to_lowercase(),
            r.clutter,
            r.arm,
            if r.success { "placed" } else { "FAILED" },
            r.orientation_error_deg.min(999.0),
            r.moved_after_release_mm.min(9999.0),
            r.decision_ms,
            r.normal_error_deg
                .map_or(String::new(), |e| format!("n{e:.1}°")),
            r.cause.as_deref().unwrap_or("")
        );
    }
    let n = rows.len();
    let k = rows.iter().filter(|r| r.success).count();
    let (lo, hi) = wilson(k, n);
    let decisions: Vec<f64> = rows.iter().map(|r| r.decision_ms).collect();
    let d = tabula_robot::ik::bench::Spread::of(&decisions);
    println!(
        "{suite}: {k}/{n} placed = {:.1} % (95 % interval {:.1}–{:.1} %); decision CPU median {:.0} ms, p95 {:.0} ms",
        100.0 * k as f64 / n.max(1) as f64,
        lo * 100.0,
        hi * 100.0,
        d.median,
        d.p95
    );
    let found = rows.iter().filter(|r| r.table_found).count();
    let (flo, fhi) = wilson(found, n);
    println!(
        "the table found by the sweep: {found}/{n} = {:.1} % (95 % interval {:.1}–{:.1} %)",
        100.0 * found as f64 / n.max(1) as f64,
        flo * 100.0,
        fhi * 100.0
    );
    let free: Vec<&BenchRow> = rows
        .iter()
        .filter(|r| r.grip_allows_rest == Some(true))
        .collect();
    let judged = rows.iter().filter(|r| r.grip_allows_rest.is_some()).count();
    if judged > 0 {
        let placed = free.iter().filter(|r| r.success).count();
        let (plo, phi) = wilson(placed, free.len());
        println!(
            "grips that leave the true object a resting face: {}/{judged}; of those, {placed} placed = {:.1} % (95 % interval {:.1}–{:.1} %)",
            free.len(),
            100.0 * placed as f64 / free.len().max(1) as f64,
            plo * 100.0,
            phi * 100.0
        );
    }
    if !causes.is_empty() {
        println!(
            "failures by cause: {}",
            causes
                .iter()
                .map(|(c, n)| format!("{c} {n}"))
                .collect::<Vec<_>>()
                .join(", ")
        );
    }
    Ok(())
}

/// The report page of `bench place`: the success rate with its interval, failures by
/// cause, success per object class, decision times.
fn bench_report(
    dir: &std::path::Path,
    b: &crate::trials::SuiteRun<'_>,
    rows: &[BenchRow],
    causes: &std::collections::BTreeMap<&str, usize>,
) -> Result<()> {
    let (suite, trials, seed) = (b.suite, b.count, b.seed);
    let n = rows.len();
    let k = rows.iter().filter(|r| r.success).count();
    let (lo, hi) = wilson(k, n);
    let mut numbers = vec![
        ("trials".to_string(), n.to_string()),
        (
            "placed (95 % interval)".to_string(),
            format!(
                "{k} = {:.1} % ({:.1}–{:.1} %)",
                100.0 * k as f64 / n.max(1) as f64,
                100.0 * lo,
                100.0 * hi
            ),
        ),
    ];
    numbers.extend(
        causes
            .iter()
            .map(|(c, count)| (format!("failed: {c}"), count.to_string())),
    );
    crate::report::bench_report(
        dir,
        crate::report::BenchSummary {
            title: "Placing an unknown object (seed 000)",
            command: format!("tabula bench place --suite {suite} --trials {trials} --seed {seed}"),
            numbers,
            classes: (
                "object class",
                crate::report::per_class(rows.iter().map(|r| (r.object.as_str(), r.success))),
            ),
            distributions: vec![(
                "Decision CPU per task",
                "ms",
                rows.iter().map(|r| r.decision_ms).collect(),
            )],
            bars: Vec::new(),
        },
        &rows,
    )?;
    Ok(())
}
