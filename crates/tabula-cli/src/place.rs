//! `tabula place` and `tabula bench place`: placing an unknown held object stably
//! (seed 000) in the simulator, judged by its physics.

use crate::report::{Recorded, Recording, Report, Section};
use crate::tasks::{TaskRunArgs, load_params, scene_robot, scene_robot_named};
use anyhow::Result;
use serde::Serialize;
use tabula_geom::{Pose, Quat, Vec3};
use tabula_sim::SimWorld;
use tabula_sim::verdict::{StablePlaceVerdict, run_place_judged};
use tabula_tasks::pick_place::Phase;
use tabula_tasks::place::{PlaceOutcome, PlaceParams, PlaceReport, PlaceRequest, place};
use tabula_tasks::stable::StablePose;

#[derive(clap::Args)]
pub struct PlaceArgs {
    #[command(flatten)]
    pub run: TaskRunArgs,
    /// The arm holding the object (`auto`: the one whose gripper is closed).
    #[arg(long, default_value = "auto")]
    pub arm: String,
}

/// A typed failure: its kind and its message.
#[derive(Debug, Clone, Serialize)]
pub struct TypedError {
    pub kind: String,
    pub message: String,
}

/// Everything `place` prints with `--json`.
#[derive(Debug, Clone, Serialize)]
pub struct PlaceJson {
    pub success: bool,
    /// The furniture the object rests on (physics), and the surface perceived.
    pub surface: Option<String>,
    pub stable_pose: Option<StablePose>,
    /// Poses as x y z qx qy qz qw (world).
    pub predicted_pose: Option<[f64; 7]>,
    pub final_pose: [f64; 7],
    pub orientation_error_deg: f64,
    pub phases: Vec<Phase>,
    pub decision_ms: f64,
    pub error: Option<TypedError>,
    pub report: PlaceReport,
    pub verdict: StablePlaceVerdict,
    /// Run with `--dry-run`: no physics judged the verdict.
    pub dry_run: bool,
}

/// Where the task expects the object to rest: the tool's planned pose lowered by the
/// release height (none when the task failed).
fn planned_rest(out: &PlaceOutcome, params: &PlaceParams) -> Option<Pose> {
    out.report.planned_world_from_tool.and_then(|p| {
        let q = Quat::from_xyzw(p[3], p[4], p[5], p[6]);
        let pose = Pose::from_parts(Vec3::new(p[0], p[1], p[2]), q);
        out.error.is_none().then(|| {
            Pose::from_parts(
                pose.translation - Vec3::Z * params.release_height,
                pose.rotation,
            )
        })
    })
}

/// What `place` prints, from the task's outcome and the judge's verdict.
fn place_json(outcome: PlaceOutcome, verdict: StablePlaceVerdict, dry_run: bool) -> PlaceJson {
    let error = outcome.error.as_ref().map(|e| TypedError {
        kind: e.kind().into(),
        message: e.to_string(),
    });
    PlaceJson {
        success: verdict.success && error.is_none(),
        surface: verdict.surface.clone(),
        stable_pose: outcome.report.stable_pose.clone(),
        predicted_pose: verdict.predicted_pose,
        final_pose: verdict.final_pose,
        orientation_error_deg: verdict.orientation_error_deg,
        phases: outcome.report.phases.clone(),
        decision_ms: outcome.report.decision_ms,
        error,
        report: outcome.report,
        verdict,
        dry_run,
    }
}

/// One placement in `world`, judged by its physics; returns the world afterwards.
pub fn place_in(
    world: SimWorld,
    robot: Option<&str>,
    request: &PlaceRequest,
    params: &PlaceParams,
    seed: u64,
    record: bool,
) -> Result<(PlaceJson, SimWorld, Option<Recorded>)> {
    let (robot_name, robot) = scene_robot_named(&world, robot)?;
    let dry_run = world.kinematic_only;
    let mut recording = Recording::new(record);
    let (outcome, verdict, world) = run_place_judged(world, &robot_name, seed, |driver| {
        recording.start(driver);
        let out = place(driver, &robot, request, params);
        let planned = planned_rest(&out, params);
        (out, planned)
    })?;
    let recorded = recording.finish(&world);
    Ok((place_json(outcome, verdict, dry_run), world, recorded))
}

/// One placement by the robot served at `--connect`, judged there.
#[cfg(feature = "ros")]
fn place_remote(
    a: &PlaceArgs,
    world: &SimWorld,
    request: &PlaceRequest,
    params: &PlaceParams,
) -> Result<(PlaceJson, String)> {
    let (robot_name, robot) = scene_robot_named(world, a.run.robot.as_deref())?;
    let mut driver = crate::remote::connect(&a.run, &robot_name)?;
    crate::remote::begin(
        &driver,
        tabula_ros::protocol::JudgedTask::Place { seed: a.run.seed },
    )?;
    let outcome = place(&mut driver, &robot, request, params);
    let verdict = crate::remote::verdict(&driver, planned_rest(&outcome, params))?;
    let scene = crate::remote::scene(&driver)?;
    Ok((place_json(outcome, verdict, false), scene))
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
    crate::tasks::phase_plot(report, &mut s, &out.phases)?;
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

#[derive(Serialize, serde::Deserialize)]
pub struct BenchRow {
    seed: u64,
    object: String,
    layout: tabula_sim::generate::PlaceLayout,
    clutter: usize,
    arm: String,
    success: bool,
    cause: Option<String>,
    orientation_error_deg: f64,
    moved_after_release_mm: f64,
    decision_ms: f64,
    wall_s: f64,
    /// The surface the task chose is the generated table's top (centroid over it,
    /// height within 2 cm): the sweep found it.
    #[serde(default)]
    table_found: bool,
    /// Ground truth for meshes: whether the true object, held as the task holds it,
    /// has a resting pose the hand leaves free (see [`resting_faces`]).
    #[serde(default)]
    grip_allows_rest: Option<bool>,
    /// Ground truth for meshes: the angle (°) from the chosen pose's support normal to
    /// the nearest stable pose of the true object, both in the tool frame — how well the
    /// scan found the face it set the object down on.
    #[serde(default)]
    normal_error_deg: Option<f64>,
}

/// The true object's (the scene's held mesh's) stable poses as support normals in the
/// tool frame, each with whether it is a resting face the hand leaves free: it tilts at
/// least `min_topple_deg` before toppling, it is a flat face (not a curved side), and
/// the hand stays clear of its plane — the tests the placer applies to its scanned
/// model, here on the exact mesh. When no
/// face leaves the hand clear, no placement can rest as planned without a regrasp (a
/// ball with a pocket held across the pocket). `None` for primitives and scenes
/// without a held mesh.
fn resting_faces(scene: &tabula_sim::Scene, params: &PlaceParams) -> Option<Vec<(Vec3, bool)>> {
    let (robot_spec, hold) = scene
        .robots
        .iter()
        .find_map(|r| r.hold.as_ref().map(|h| (r, h)))?;
    let object = scene
        .objects
        .iter()
        .find(|o| *o.name.get_ref() == hold.object)?;
    let tabula_sim::scene::ShapeSpec::Mesh { path, scale } = &object.shape else {
        return None;
    };
    let path = scene
        .base_dir
        .as_ref()
        .map_or_else(|| path.into(), |d| d.join(path));
    let (vertices, triangles) = tabula_geom::mesh::load_mesh(&path, *scale).ok()?;
    // At the placer's own contact tolerance: a rim of slightly uneven vertices (a
    // pocket's) is one support, as a scanned one is to the placer.
    let tolerant = tabula_tasks::stable::StableParams {
        contact_tolerance: params.stable.cloud_contact_tolerance,
        ..params.stable.clone()
    };
    let poses = tabula_tasks::stable::of_mesh(&vertices, &triangles, &tolerant).ok()?;
    let com = Vec3::from_array(poses.center_of_mass);
    let robot = tabula_robot::robots::load(&robot_spec.urdf).ok()?;
    let arm = robot
        .description
        .arms
        .iter()
        .find(|a| {
            a.gripper
                .as_deref()
                .and_then(|g| robot.description.grippers.iter().find(|x| x.name == g))
                .is_some_and(|g| g.tool_link == hold.tool_link)
        })?
        .name
        .clone();
    let tool_from_object = hold.tool_from_object.as_ref().map_or(Pose::IDENTITY, |p| {
        tabula_geom::pose_from_xyz_rpy(p.xyz, p.rpy)
    });
    let object_from_tool = tool_from_object.inverse();
    let gripper: Vec<Vec3> = tabula_tasks::place::gripper_points(&robot, &arm)
        .into_iter()
        .map(|g| object_from_tool.transform_point(g))
        .collect();
    // A flat support (not a curved side that only looks flat within the tolerance:
    // most of its energy barrier really there), tilting far enough, the hand clear.
    Some(
        poses
            .poses
            .iter()
            .map(|s| {
                let flat =
                    s.topple_deg >= params.min_topple_deg && s.rocking(&vertices, com) >= 0.5;
                (
                    tool_from_object.rotation * s.normal(),
                    flat && s.clear_of(&gripper, params.gripper_clearance - params.release_height),
                )
            })
            .collect(),
    )
}

/// The suite's generated task `seed`.
fn task_of(
    seed: u64,
    suite: Suite,
    mesh_dir: &std::path::Path,
) -> std::io::Result<tabula_sim::generate::PlaceTask> {
    match suite {
        Suite::Rooms => tabula_sim::generate::room_task(seed, mesh_dir),
        Suite::Simple => tabula_sim::generate::place_task(seed, true, mesh_dir),
        Suite::Complex => tabula_sim::generate::place_task(seed, false, mesh_dir),
    }
}

/// Whether a found surface is the task's table top.
fn is_table(
    task: &tabula_sim::generate::PlaceTask,
    surface: &tabula_tasks::place::SurfaceReport,
) -> bool {
    let [cx, cy] = task.table_center;
    let (dx, dy) = (surface.centroid[0] - cx, surface.centroid[1] - cy);
    let (s, c) = task.table_yaw.sin_cos();
    let (u, v) = (c * dx + s * dy, -s * dx + c * dy);
    u.abs() <= task.table_size[0] / 2.0
        && v.abs() <= task.table_size[1] / 2.0
        && (surface.height - task.table_size[2]).abs() <= 0.02
}

/// One task of the placing suite (`simple` or complex objects), placed in the
/// simulator and judged by physics; complex objects' meshes go to `mesh_dir`.
fn trial(
    s: u64,
    suite: Suite,
    params: &PlaceParams,
    mesh_dir: &std::path::Path,
) -> Result<BenchRow> {
    let task = task_of(s, suite, mesh_dir)?;
    let scene = tabula_sim::Scene::parse(&task.scene, "generated")
        .map_err(|e| anyhow::anyhow!("task {s}: {e}"))?;
    let world = SimWorld::from_scene(&scene, Default::default())
        .map_err(|e| anyhow::anyhow!("task {s}: {e}"))?;
    let faces = resting_faces(&scene, params);
    let grip_allows_rest = faces.as_ref().map(|f| f.iter().any(|(_, clear)| *clear));
    let t0 = std::time::Instant::now();
    let request = PlaceRequest {
        arm: Some(task.arm.clone()),
        not_on: Vec::new(),
        near: None,
    };
    let (out, _, _) = place_in(world, None, &request, params, s, false)?;
    let cause = if out.success {
        None
    } else if let Some(e) = &out.error {
        Some(e.kind.clone())
    } else {
        let v = &out.verdict;
        Some(
            if v.surface.is_none() {
                "fell off"
            } else if !v.inside_edges {
                "over the edge"
            } else if v.orientation_error_deg > 5.0 {
                "toppled or turned"
            } else if v.moved_after_release_m >= 0.01 {
                "slid after release"
            } else if !v.disturbed.is_empty() {
                "disturbed others"
            } else if !v.furniture_contacts.is_empty() {
                "hit furniture"
            } else {
                "not released"
            }
            .to_string(),
        )
    };
    let table_found = out
        .report
        .surface
        .as_ref()
        .is_some_and(|f| is_table(&task, f));
    Ok(BenchRow {
        seed: s,
        table_found,
        grip_allows_rest,
        normal_error_deg: faces
            .zip(out.report.stable_pose.as_ref())
            .and_then(|(f, chosen)| {
                f.iter()
                    .map(|(n, _)| n.angle_between(chosen.normal()).to_degrees())
                    .min_by(f64::total_cmp)
            }),
        object: task.object,
        layout: task.layout,
        clutter: task.clutter,
        arm: task.arm,
        success: out.success,
        cause,
        orientation_error_deg: out.orientation_error_deg,
        moved_after_release_mm: out.verdict.moved_after_release_m * 1e3,
        decision_ms: out.decision_ms,
        wall_s: t0.elapsed().as_secs_f64(),
    })
}

/// The placing suites.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Suite {
    Simple,
    Complex,
    /// Simple objects in rooms with walls and things that are not surfaces.
    Rooms,
}

fn suite_of(suite: &str) -> Result<Suite> {
    match suite {
        "simple" => Ok(Suite::Simple),
        "complex" => Ok(Suite::Complex),
        "rooms" => Ok(Suite::Rooms),
        other => anyhow::bail!("--suite is `simple`, `complex` or `rooms`, not `{other}`"),
    }
}

/// A placing trial as a worker runs it (meshes in the worker's own temporary folder).
#[cfg(feature = "ros")]
pub fn trial_of(spec: &crate::trials::TrialSpec) -> Result<BenchRow> {
    let params: PlaceParams = match &spec.params {
        Some(text) => crate::tasks::parse_params(text, "the bench's parameters")?,
        None => PlaceParams::default(),
    };
    trial(
        spec.seed,
        suite_of(&spec.suite)?,
        &params,
        &worker_mesh_dir(),
    )
}

/// Where a worker process writes the complex objects' meshes.
#[cfg(feature = "ros")]
pub fn worker_mesh_dir() -> std::path::PathBuf {
    std::env::temp_dir().join(format!("tabula-worker-meshes-{}", std::process::id()))
}

/// `tabula bench place`: the generated suite, each task placed in the simulator (both
/// cores, one task each, or spread over workers) and judged by physics.
#[allow(clippy::too_many_arguments)]
pub fn bench(
    suite: &str,
    trials: u64,
    seed: u64,
    params_path: Option<&std::path::Path>,
    save_failures: Option<&std::path::Path>,
    json: bool,
    report: Option<&std::path::Path>,
    spread: &crate::trials::TrialArgs,
) -> Result<()> {
    let kind = suite_of(suite)?;
    let params: PlaceParams = load_params(params_path)?;
    let params_text = crate::trials::params_text(params_path)?;
    // Saved failures keep their meshes beside them.
    let mesh_dir = match save_failures {
        Some(d) => d.join("meshes"),
        None => std::env::temp_dir().join(format!("tabula-place-meshes-{}", std::process::id())),
    };
    if let Some(d) = save_failures {
        std::fs::create_dir_all(d)?;
    }
    let progress = crate::progress::steps(trials, suite);
    let rows = crate::trials::run(
        spread,
        seed..seed.saturating_add(trials),
        |s| crate::trials::TrialSpec {
            bench: "place".into(),
            suite: suite.into(),
            params: params_text.clone(),
            seed: s,
        },
        |s| trial(s, kind, &params, &mesh_dir),
        &progress,
    );
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
    progress.finish_and_clear();
    let rows: Vec<BenchRow> = rows?;
    // Failures by cause, for the report and the summary line.
    let mut causes: std::collections::BTreeMap<&str, usize> = Default::default();
    for r in &rows {
        if let Some(c) = &r.cause {
            *causes.entry(c.as_str()).or_default() += 1;
        }
    }
    if let Some(dir) = report {
        let n = rows.len();
        let k = rows.iter().filter(|r| r.success).count();
        let (lo, hi) = crate::clear::wilson(k, n);
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
                command: format!(
                    "tabula bench place --suite {suite} --trials {trials} --seed {seed}"
                ),
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
    }
    if json {
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
    let (lo, hi) = crate::clear::wilson(k, n);
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
    let (flo, fhi) = crate::clear::wilson(found, n);
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
        let (plo, phi) = crate::clear::wilson(placed, free.len());
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
