//! `tabula demo`: the main job, one section per capability that has landed.

use crate::report::{Report, Section};
use anyhow::Result;
use std::path::Path;
use std::time::Instant;
use tabula_geom::{Pose, Vec3, pose_from_xyz_rpy};
use tabula_robot::Chain;
use tabula_robot::ik::{
    ArmSide, Golem3Ik, Golem3Params, IkMode, IkSolver, NumericIk, NumericIkParams,
};
use tabula_robot::robots;

/// Prints a line and keeps it for the report's capabilities section.
macro_rules! say {
    ($log:expr, $($t:tt)*) => {{
        let line = format!($($t)*);
        println!("{line}");
        $log.push(line);
    }};
}

/// Runs the jobs end to end in the simulator (placing, clearing, pick and place, tidying),
/// then the capabilities they stand on, and writes the report into `report_dir`.
pub fn run(report_dir: &Path) -> Result<()> {
    println!("tabula demo\n===========\n");
    let t0 = Instant::now();
    let mut report = Report::create(report_dir, "tabula demo — the jobs in the simulator")?;
    let progress = crate::progress::steps(9, "demo");
    let mut jobs = Vec::new();
    let mut summary = Vec::new();
    progress.set_message("placing an unknown object");
    let (section, json, line) = placing(&mut report)?;
    jobs.push(section);
    summary.push(("placing", json, line));
    progress.inc(1);
    progress.set_message("clearing a cluttered table");
    let (section, json, line) = clearing(&mut report)?;
    jobs.push(section);
    summary.push(("clearing", json, line));
    progress.inc(1);
    progress.set_message("pick and place");
    let (section, json, line) = pick_place(&mut report)?;
    jobs.push(section);
    summary.push(("pick_place", json, line));
    progress.inc(1);
    progress.set_message("tidying a table");
    let (section, json, line) = tidying()?;
    jobs.push(section);
    summary.push(("tidying", json, line));
    progress.inc(1);
    let mut log = Vec::new();
    progress.set_message("kinematics");
    kinematics(&mut log)?;
    progress.inc(1);
    progress.set_message("task planning");
    planning(&mut log)?;
    progress.inc(1);
    progress.set_message("simulator");
    let frame = simulator(&mut log)?;
    progress.inc(1);
    progress.set_message("perception");
    let perceived = perception(&frame, &mut log, &mut report)?;
    progress.inc(1);
    progress.set_message("motion planning");
    motion(&mut log)?;
    progress.finish_and_clear();

    let mut overview = Section::new("Summary");
    overview.text(
        "Four jobs, end to end in tabula's simulator, each judged by its physics: the PR2 \
         places an object it holds and has no model of (seed 000), the WAM clears a cluttered \
         table into a bin by grasps and pushes (seed 002), Golem-III moves a can from a shelf \
         to a table (seed 001), and the PR2 tidies a table onto another (built from the \
         other three's skills). Each section has a 3D replay (drag to turn, wheel to zoom, \
         the slider scrubs), pictures of every grasp and release from the scene's camera and \
         from an overview, and plots.",
    );
    for (name, _, line) in &summary {
        overview.number(name.replace('_', " "), line);
    }
    overview.number(
        "wall time (s)",
        format!("{:.1}", t0.elapsed().as_secs_f64()),
    );
    // One picture per job at the top: the overview eye when the hand lets go.
    for job in &jobs {
        if let Some(f) = job
            .figures
            .iter()
            .find(|f| f.caption.contains("lets go") && f.caption.ends_with("from overview"))
        {
            overview.figures.push(crate::report::Figure {
                file: f.file.clone(),
                caption: format!("{} — {}", job.title, f.caption),
            });
        }
    }
    let mut capabilities = Section::new("What the jobs stand on");
    capabilities.text(
        "Kinematics, task planning, the simulator, perception and motion planning on their \
         own (benchmarks against KDL/IKFast, Fast Downward, Gazebo, PCL and MoveIt are in \
         BENCHMARKS.md).",
    );
    capabilities.log = log;
    report.sections.push(overview);
    report.sections.extend(jobs);
    report.sections.push(perceived);
    report.sections.push(capabilities);
    let json = serde_json::json!({
        "jobs": summary.iter().map(|(n, j, _)| (n.to_string(), j.clone())).collect::<serde_json::Map<_, _>>(),
        "wall_s": t0.elapsed().as_secs_f64(),
    });
    let page = report.finish(&json)?;
    println!("\nSummary");
    for (name, _, line) in &summary {
        println!("  {:<11} {line}", name.replace('_', " "));
    }
    println!("\nreport (pictures, plots, 3D replays): {}", page.display());
    Ok(())
}

/// Seed 000's system (SPEC §1): the PR2 scans the cup it holds, finds how it rests,
/// finds the table and a free spot on it, drives up, puts it down; physics judges it.
fn placing(report: &mut Report) -> Result<(Section, serde_json::Value, String)> {
    use tabula_tasks::place::{PlaceParams, PlaceRequest};
    println!("1. Placing an unknown object (seed 000): the PR2 and the cup in its hand\n");
    let scene = tabula_sim::Scene::parse(
        include_str!("../../../scenes/pr2_holding.toml"),
        "scenes/pr2_holding.toml",
    )?;
    let world = tabula_sim::SimWorld::from_scene(&scene, Default::default())?;
    let t0 = Instant::now();
    let request = PlaceRequest {
        arm: Some("right".into()),
        not_on: Vec::new(),
        near: None,
    };
    let params = PlaceParams::default();
    let (out, _, recorded) = crate::place::place_in(world, None, &request, &params, 1, true)?;
    let wall = t0.elapsed().as_secs_f64();
    let r = &out.report;
    if let Some(m) = &r.model {
        println!(
            "  scanned: {} (the cup is 288 cm³)",
            crate::place::model_line(m)
        );
    }
    if let Some(p) = &out.stable_pose {
        println!(
            "  rests on the face with normal ({:.2}, {:.2}, {:.2}) in the hand: margin {:.0} mm, topples at {:.0}° ({} poses)",
            p.support_normal[0],
            p.support_normal[1],
            p.support_normal[2],
            p.margin_m * 1e3,
            p.topple_deg,
            r.poses_found
        );
    }
    if let (Some(s), Some(g)) = (&r.surface, r.base_goal) {
        println!(
            "  table found {:.2} m high; the base drove to ({:.2}, {:.2})",
            s.height, g[0], g[1]
        );
    }
    let line = format!(
        "{}: on {}, {:.1}° from the planned pose; decision {:.0} ms CPU, {wall:.1} s in all",
        if out.success { "placed" } else { "FAILED" },
        out.verdict.surface.as_deref().unwrap_or("nothing"),
        out.orientation_error_deg,
        out.decision_ms,
    );
    println!("  {line}");
    println!(
        "\n  run it: cargo run --release -- place --scene scenes/pr2_holding.toml --report DIR\n"
    );
    let mut section = crate::place::report_section(report, &out, &params, recorded.as_ref())?;
    section
        .text("Run it: cargo run --release -- place --scene scenes/pr2_holding.toml --report DIR");
    Ok((section, serde_json::to_value(&out)?, line))
}

/// Seed 002's system (SPEC §3): the WAM clears the seed's cluttered table into the bin,
/// replanning after every action, and physics counts what ended in the bin.
fn clearing(report: &mut Report) -> Result<(Section, serde_json::Value, String)> {
    use tabula_sim::generate::{ClearSuite, clearing_scene};
    println!("2. Clearing a cluttered table (seed 002): the WAM, grasps and pushes into the bin\n");
    let scene =
        tabula_sim::Scene::parse(&clearing_scene(ClearSuite::Seed, 1), "scenes/clutter.toml")?;
    let world = tabula_sim::SimWorld::from_scene(&scene, Default::default())?;
    let t0 = Instant::now();
    let (out, _, recorded) = crate::clear::clear_in(
        world,
        None,
        &tabula_tasks::clear::ClearParams::default(),
        None,
        1,
        true,
    )?;
    let wall = t0.elapsed().as_secs_f64();
    let r = &out.report;
    let v = &out.verdict;
    for a in &r.log {
        println!(
            "  frame {:>2}: {:<10} at ({:.3}, {:.3})  {}",
            a.frame,
            a.action,
            a.position[0],
            a.position[1],
            if a.ok { "ok" } else { "failed" }
        );
    }
    let line = format!(
        "{} of {} objects in the bin in {} actions ({} grasps, {} pushes), {} collisions; decision median {:.1} ms CPU, {wall:.1} s in all",
        v.in_bin, v.objects, r.actions, r.grasps, r.pushes, out.collisions, r.decision_ms.median
    );
    println!("  {line}");
    println!(
        "  decision per frame (CPU, frame in → action chosen): perception {:.1}, predicates {:.1}, planning {:.1}, IK {:.1} ms (medians); the seed needed ≈ 4.5 s",
        r.perception_ms, r.predicates_ms, r.planning_ms, r.ik_ms
    );
    println!("\n  run it: cargo run --release -- clear --scene scenes/clutter.toml --report DIR\n");
    let mut section = crate::clear::report_section(report, &out, recorded.as_ref())?;
    section.text("Run it: cargo run --release -- clear --scene scenes/clutter.toml --report DIR");
    Ok((section, serde_json::to_value(&out)?, line))
}

/// The fourth task, from the other three's skills: the PR2 takes every object off a
/// table and stands each on another table it finds; physics judges it.
fn tidying() -> Result<(Section, serde_json::Value, String)> {
    use tabula_tasks::tidy::{TidyParams, TidyRequest};
    println!("4. Tidying a table: the PR2 moves everything onto another table it finds\n");
    let scene = tabula_sim::Scene::parse(
        include_str!("../../../scenes/tidy.toml"),
        "scenes/tidy.toml",
    )?;
    let world = tabula_sim::SimWorld::from_scene(&scene, Default::default())?;
    let t0 = Instant::now();
    let (out, _) = tabula_bench::tidy::tidy_in(
        world,
        (None, "table"),
        (&TidyRequest::default(), &TidyParams::default()),
        1,
        |_| {},
    )?;
    let wall = t0.elapsed().as_secs_f64();
    for f in &out.failed {
        println!(
            "  failed at ({:.2}, {:.2}): {} — {}",
            f.object[0], f.object[1], f.reason, f.message
        );
    }
    let line = format!(
        "{} of {} objects moved to another table in {} actions, {} knocked over; decision median {:.0} ms CPU, {wall:.1} s in all",
        out.moved,
        out.objects,
        out.actions,
        out.verdict.knocked.len(),
        out.decision_ms.median
    );
    println!("  {line}");
    println!("\n  run it: cargo run --release -- tidy --scene scenes/tidy.toml --report DIR\n");
    let mut section = Section::new("Tidying a table (from the shared skills)");
    section
        .number("objects on the table", out.objects)
        .number("moved to another table", out.moved)
        .number("actions", out.actions)
        .number("knocked over", out.verdict.knocked.len());
    section.text("Run it: cargo run --release -- tidy --scene scenes/tidy.toml --report DIR");
    Ok((section, serde_json::to_value(&out)?, line))
}

/// Seed 001's integral test (SPEC §2.5): Golem-III looks at a can on a shelf board,
/// plans every motion, carries it to the table, and physics judges the result.
fn pick_place(report: &mut Report) -> Result<(Section, serde_json::Value, String)> {
    use tabula_tasks::pick_place::{PickPlaceParams, PickPlaceRequest};
    println!(
        "3. Pick and place by coordinates (seed 001's integral test): Golem-III, shelf → table\n"
    );
    let scene = tabula_sim::Scene::parse(GOLEM_SHELVES, "scenes/golem_shelves.toml")?;
    let world = tabula_sim::SimWorld::from_scene(&scene, Default::default())?;
    let request = PickPlaceRequest {
        arm: None,
        pick: Vec3::new(0.556, -0.663, 1.07),
        place: Vec3::new(0.82, -0.2, 1.01),
    };
    let t0 = Instant::now();
    let (out, _, recorded) = crate::pick_place::pick_place_in(
        world,
        None,
        &request,
        &PickPlaceParams::default(),
        1,
        true,
    )?;
    let wall = t0.elapsed().as_secs_f64();
    let r = &out.report;
    if let Some(o) = &r.object {
        println!(
            "  seen: {:.0} × {:.0} × {:.0} mm at ({:.3}, {:.3}, {:.3}), {} points",
            o.size[0] * 1e3,
            o.size[1] * 1e3,
            o.size[2] * 1e3,
            o.position[0],
            o.position[1],
            o.position[2],
            o.points
        );
    }
    let v = &out.verdict;
    let line = format!(
        "{} with the {} arm ({} grasp): {:.1} cm from the target, tilted {:.1}°; decision {:.0} ms CPU, {wall:.1} s in all{}",
        if out.success { "placed" } else { "FAILED" },
        r.arm.as_deref().unwrap_or("-"),
        r.grasp
            .map_or("-".into(), |g| format!("{g:?}").to_lowercase()),
        v.target_error * 100.0,
        v.tilt.to_degrees(),
        r.decision_cpu_ms,
        out.error_message
            .as_ref()
            .map_or(String::new(), |e| format!("; {e}"))
    );
    println!("  {line}");
    let command = "cargo run --release -- pick-place --scene scenes/golem_shelves.toml --pick 0.556 -0.663 1.07 --place 0.82 -0.2 1.01 --report DIR";
    println!("\n  run it: {command}\n");
    let mut section = crate::pick_place::pick_place_section(report, &out, recorded.as_ref())?;
    section.text(format!("Run it: {command}"));
    Ok((section, serde_json::to_value(&out)?, line))
}

const GOLEM_SHELVES: &str = include_str!("../../../scenes/golem_shelves.toml");

/// Seed 002's perception on the simulator's frame: the table, the objects on it, and
/// where a new box would fit; then the nine-object frame scored against the
/// simulator's labels.
fn perception(
    frame: &tabula_sim::DepthFrame,
    log: &mut Vec<String>,
    report: &mut Report,
) -> Result<Section> {
    use tabula_geom::Vec2;
    use tabula_perception::eval::{Truth, score, table_top_truth};
    use tabula_perception::freespace::{FreeSpaceMap, FreeSpaceParams};
    use tabula_perception::{TabletopParams, extract, to_world};
    use tabula_sim::generate::{TABLE_TOP, TabletopLayout, tabletop_frame};
    say!(
        log,
        "8. Perception (PCL's role): the table, its objects and its free space in that frame\n"
    );
    let t0 = Instant::now();
    let cloud = to_world(&frame.world_from_camera, &frame.cloud);
    let t = extract(
        &cloud,
        frame.world_from_camera.translation,
        &TabletopParams::default(),
    )?;
    let ms = t0.elapsed().as_secs_f64() * 1e3;
    say!(
        log,
        "  table at {:.3} m ({} points, {:.2} m² seen), {} objects, {ms:.1} ms",
        t.table.centroid.z,
        t.table.inliers.len(),
        t.table.area,
        t.objects.len(),
    );
    for o in &t.objects {
        let c = o.obb.center;
        let s = o.obb.half_extents * 2000.0;
        say!(
            log,
            "    centre ({:.3}, {:.3}), {:.0} × {:.0} × {:.0} mm box, {} points{}",
            c.x,
            c.y,
            s.x,
            s.y,
            s.z,
            o.indices.len(),
            o.top.as_ref().map_or(String::new(), |top| format!(
                ", flat top {:.0} cm²",
                top.area * 1e4
            ))
        );
    }
    let map = FreeSpaceMap::from_tabletop(&t, &cloud.points, &FreeSpaceParams::default())?;
    let footprint = [
        Vec2::new(-0.05, -0.04),
        Vec2::new(0.05, -0.04),
        Vec2::new(0.05, 0.04),
        Vec2::new(-0.05, 0.04),
    ];
    let spot = map.find_place(&footprint, 0.03, t.table.centroid);
    let mut section = Section::new("Perception on the simulator's frame");
    section.text(format!(
        "Seed 002's tabletop pipeline on the overhead Kinect-like frame of the cluttered table: \
         the table ({:.2} m² seen), {} objects with their footprints and minimal-area boxes, the \
         free space, and where a 10 × 8 cm box fits with 3 cm to spare (blue).",
        t.table.area,
        t.objects.len()
    ));
    let (svg, _) = crate::perceive::top_view(&crate::perceive::TopView::of_tabletop(
        &t,
        &map,
        spot.map(|p| (p, &[0.1, 0.08][..])),
    ))?;
    let fig = report.svg("top-view", "Top view of the table: free (green), objects (red), unseen (grey), boxes, the free spot (blue)", &svg)?;
    section.figures.push(fig);
    match spot {
        Some(p) => say!(
            log,
            "  free: {:.2} m²; a 10 × 8 cm box with 3 cm to spare fits at ({:.3}, {:.3}), turned {:.0}°",
            map.free_area(),
            p.position.x,
            p.position.y,
            p.yaw.to_degrees()
        ),
        None => say!(
            log,
            "  free: {:.2} m²; a 10 × 8 cm box fits nowhere",
            map.free_area()
        ),
    }
    let g = tabletop_frame(0, &TabletopLayout::nine())?;
    let cloud = to_world(&g.frame.world_from_camera, &g.frame.cloud);
    let t0 = Instant::now();
    let t = extract(
        &cloud,
        g.frame.world_from_camera.translation,
        &TabletopParams::default(),
    )?;
    let ms = t0.elapsed().as_secs_f64() * 1e3;
    let finite: Vec<bool> = cloud.points.iter().map(|p| p.is_finite()).collect();
    let labels: Vec<u32> = g.object_labels.iter().map(|o| o.1).collect();
    let s = score(
        &t,
        &Truth {
            finite: &finite,
            labels: &g.frame.labels,
            table_label: g.table_label,
            table_top: &table_top_truth(&cloud.points, TABLE_TOP),
            object_labels: &labels,
        },
        0.8,
        200,
    );
    say!(
        log,
        "  nine-object frame (two touching pairs, a stack, 0.5 % outliers): {} of {} objects with IoU > 0.8, \
         table precision {:.3} recall {:.3}, {ms:.1} ms (PCL: 1.2 s)\n",
        s.recovered,
        s.objects,
        s.table_precision,
        s.table_recall
    );
    section
        .number(
            "objects recovered (IoU > 0.8) in the nine-object frame",
            format!("{} of {}", s.recovered, s.objects),
        )
        .number(
            "table precision / recall",
            format!("{:.3} / {:.3}", s.table_precision, s.table_recall),
        )
        .number("pipeline time on that frame (ms, wall)", format!("{ms:.1}"));
    Ok(section)
}

/// MoveIt's role: a collision-free reach for the WAM over a cluttered table.
fn motion(log: &mut Vec<String>) -> Result<()> {
    use tabula_motion::bench::{reach_configuration, robot_world, table_height, tabletop_world};
    use tabula_motion::{PlannerParams, WorldParams, rrt_connect, time_parameterize};
    say!(
        log,
        "9. Motion planning (MoveIt/OMPL's role): WAM reaches over a cluttered table\n"
    );
    let robot = robots::load("wam")?;
    let chain = Chain::new(&robot.model, &robot.default_base, &robot.default_tip)?;
    let empty = robot_world(&robot, chain, WorldParams::default())?;
    let top = table_height(&robot);
    let world = tabletop_world(&empty, top, 4)?;
    let mut rng = <rand_chacha::ChaCha8Rng as rand::SeedableRng>::seed_from_u64(4);
    for k in 0..3 {
        let (Some(start), Some(goal)) = (
            reach_configuration(&world, &mut rng, top),
            reach_configuration(&world, &mut rng, top),
        ) else {
            continue;
        };
        let path = rrt_connect(
            &world,
            &start,
            std::slice::from_ref(&goal),
            &PlannerParams {
                seed: k,
                ..PlannerParams::default()
            },
        )?;
        let traj = time_parameterize(&path.waypoints, &world.chain.velocity, &[2.0; 7], 0.01);
        say!(
            log,
            "  reach {}: {} waypoints, {:.2} rad, planned in {:.2} ms, {:.2} s to execute at the joints' limits",
            k + 1,
            path.waypoints.len(),
            path.length(),
            path.planning_time * 1e3,
            traj.duration()
        );
    }
    say!(
        log,
        "\n  Benchmarks: `tabula motion bench --robot wam` (see BENCHMARKS.md)\n"
    );
    Ok(())
}

/// The built-in simulator: settle seed 002's clutter, capture a frame, render a picture.
fn simulator(log: &mut Vec<String>) -> Result<tabula_sim::DepthFrame> {
    use tabula_sim::camera::{Camera, capture};
    use tabula_sim::{PhysicsParams, Scene, SimWorld};
    say!(
        log,
        "7. Simulator (Gazebo's role): seed 002's cluttered table\n"
    );
    let mut scene = Scene::parse(
        include_str!("../../../scenes/clutter.toml"),
        "scenes/clutter.toml",
    )?;
    scene.base_dir = None;
    let mut world = SimWorld::from_scene(&scene, PhysicsParams::default())?;
    let t0 = Instant::now();
    let report = world.settle();
    say!(
        log,
        "  settled {} objects in {} steps ({:.1} ms): all at rest = {}",
        world.object_poses().len(),
        report.steps,
        t0.elapsed().as_secs_f64() * 1e3,
        report.all_asleep
    );
    let camera = Camera::from_spec(&scene.cameras[0], &world)?;
    let t0 = Instant::now();
    let frame = capture(&world, &camera, 1);
    say!(
        log,
        "  overhead depth frame {}×{}: {} valid points, {:.1} ms",
        frame.width,
        frame.height,
        frame.cloud.finite_count(),
        t0.elapsed().as_secs_f64() * 1e3
    );
    let dir = std::env::temp_dir().join("tabula-demo");
    std::fs::create_dir_all(&dir)?;
    let png = dir.join("clutter.png");
    crate::sim::default_snapshot(&world, &png)?;
    let pcd = dir.join("clutter.pcd");
    frame.cloud.write_pcd(
        &mut std::io::BufWriter::new(std::fs::File::create(&pcd)?),
        tabula_geom::PcdEncoding::Binary,
    )?;
    say!(
        log,
        "  snapshot: {}\n  depth frame: {}\n",
        png.display(),
        pcd.display()
    );
    Ok(frame)
}

/// Seed 002's decision step: plan which objects to push or grasp, in process.
fn planning(log: &mut Vec<String>) -> Result<()> {
    use tabula_pddl::{
        GroundOptions, Planner, SearchMode, generator, parse_domain, parse_problem, validate,
    };
    say!(
        log,
        "6. Task planning (seed 002): clearing a table, optimal PDDL plans in process\n"
    );
    let domain = parse_domain(include_str!("../../../pddl/tablewclear-domain.pddl"))?;
    let problem = parse_problem(include_str!("../../../pddl/thesis6-a.pddl"), &domain)?;
    let mut planner = Planner::new(
        domain.clone(),
        problem,
        GroundOptions::switchable(&domain, "ik_unfeasible"),
    )?;
    let t0 = Instant::now();
    let plan = planner.plan(SearchMode::Optimal, None)?;
    let ms = t0.elapsed().as_secs_f64() * 1e3;
    let steps: Vec<String> = plan.steps.iter().map(ToString::to_string).collect();
    say!(
        log,
        "  thesis6-a (6 objects): {} actions, optimal, {ms:.2} ms",
        steps.len()
    );
    say!(log, "    {}", steps.join(" "));
    // The first action turns out to have no IK solution: mark it and replan (SPEC §3.5).
    let first = &plan.steps[0];
    let infeasible = tabula_bench::plan::infeasible(first);
    let t0 = Instant::now();
    planner.set_fact(&infeasible, true)?;
    // Objects that can no longer be removed leave the goal (the seed's rule, made exact).
    let dropped: Vec<String> = planner
        .drop_unreachable_goals(None)?
        .iter()
        .map(|a| a.args.join(" "))
        .collect();
    let replanned = planner.plan(SearchMode::Optimal, None)?;
    say!(
        log,
        "  {first} has no IK solution → replanned in {:.2} ms ({} dropped from the goal): {} actions, starting {}",
        t0.elapsed().as_secs_f64() * 1e3,
        if dropped.is_empty() {
            "nothing".to_string()
        } else {
            dropped.join(", ")
        },
        replanned.steps.len(),
        replanned
            .steps
            .first()
            .map_or("-".to_string(), ToString::to_string)
    );
    validate(&domain, planner.problem(), &replanned.steps)?;
    let big = parse_problem(&generator::table_clearing_problem(40, 7), &domain)?;
    let t0 = Instant::now();
    let mut planner = Planner::new(
        domain.clone(),
        big,
        GroundOptions::switchable(&domain, "ik_unfeasible"),
    )?;
    let dropped = planner.drop_unreachable_goals(None)?;
    let plan = planner.plan(SearchMode::Optimal, None)?;
    say!(
        log,
        "  a generated 40-object table: {} objects can never be removed, optimal plan of {} actions, {:.1} ms with grounding",
        dropped.len(),
        plan.steps.len(),
        t0.elapsed().as_secs_f64() * 1e3
    );
    say!(
        log,
        "\n  Benchmarks: `tabula plan bench` (see BENCHMARKS.md)\n"
    );
    Ok(())
}

fn kinematics(log: &mut Vec<String>) -> Result<()> {
    say!(
        log,
        "5. Kinematics (seed 001): Golem-III closed-form IK, all branches\n"
    );
    let golem = robots::load("golem3")?;
    let ik = Golem3Ik::new(&golem.model, ArmSide::Right, Golem3Params::default())?;
    let chain = ik.chain().clone();
    let seed = vec![0.1, 0.3, 0.2, 0.3, 0.4, 0.0];
    let targets: [(&str, Pose); 3] = [
        (
            "in front of the right shoulder, tool level",
            pose_from_xyz_rpy([0.62, -0.43, 1.04], [0.0, 0.0, -0.2]),
        ),
        (
            "low, tool pitched down",
            chain.fk(&[0.3, 0.5, -0.4, 0.6, 0.5, 0.2])?,
        ),
        (
            "out of reach",
            pose_from_xyz_rpy([1.4, -0.2, 1.3], [0.0, 0.0, 0.0]),
        ),
    ];
    for (label, target) in &targets {
        let t = target.translation;
        say!(
            log,
            "  target: {label} at ({:.3}, {:.3}, {:.3}) in torso_lift_link",
            t.x,
            t.y,
            t.z
        );
        let t0 = Instant::now();
        let result = ik.solve(target, IkMode::Full, &seed);
        let us = t0.elapsed().as_secs_f64() * 1e6;
        match result {
            Ok(sols) => {
                crate::ik::print_solutions(&chain, &sols);
                say!(log, "  nearest to the seed {:?}: #1 ({us:.1} µs)\n", seed);
            }
            Err(e) => say!(log, "  {e} ({us:.1} µs)\n"),
        }
    }
    let reach = Vec3::new(0.35, -0.55, 1.0);
    let t0 = Instant::now();
    let sols = ik.solve(&Pose::from_translation(reach), IkMode::PositionOnly, &seed)?;
    say!(
        log,
        "  position only ({:.2}, {:.2}, {:.2}): {:?} in {:.1} µs\n",
        reach.x,
        reach.y,
        reach.z,
        sols[0]
            .joints
            .iter()
            .map(|v| (v * 1e4).round() / 1e4)
            .collect::<Vec<_>>(),
        t0.elapsed().as_secs_f64() * 1e6
    );

    say!(
        log,
        "  Numeric IK on the 7-DOF WAM and the PR2 right arm (any URDF chain):"
    );
    for name in ["wam", "pr2"] {
        let robot = robots::load(name)?;
        let chain = Chain::new(&robot.model, &robot.default_base, &robot.default_tip)?;
        let solver = NumericIk::new(chain.clone(), NumericIkParams::default());
        let q_true: Vec<f64> = chain
            .mid_configuration()
            .iter()
            .enumerate()
            .map(|(i, v)| v + 0.3 * ((i % 3) as f64 - 1.0))
            .collect();
        let target = chain.fk(&q_true)?;
        let t0 = Instant::now();
        let sols = solver.solve(&target, IkMode::Full, &chain.mid_configuration())?;
        say!(
            log,
            "    {name:<4} {} → {}: solved in {:.1} µs, error {:.1e} m / {:.1e} rad",
            chain.base_link,
            chain.tip_link,
            t0.elapsed().as_secs_f64() * 1e6,
            sols[0].position_error,
            sols[0].rotation_error
        );
    }
    say!(
        log,
        "\n  Benchmarks: `tabula ik bench --robot golem3 --solver analytic --poses 10000` (see BENCHMARKS.md)\n"
    );
    Ok(())
}
