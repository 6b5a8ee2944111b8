//! `tabula demo`: the main job, one section per capability that has landed.

use anyhow::Result;
use std::time::Instant;
use tabula_geom::{Pose, Vec3, pose_from_xyz_rpy};
use tabula_robot::Chain;
use tabula_robot::ik::{
    ArmSide, Golem3Ik, Golem3Params, IkMode, IkSolver, NumericIk, NumericIkParams,
};
use tabula_robot::robots;

pub fn run() -> Result<()> {
    println!("tabula demo\n===========\n");
    kinematics()?;
    planning()?;
    let frame = simulator()?;
    perception(&frame)?;
    motion()?;
    pick_place()?;
    clearing()?;
    placing()?;
    Ok(())
}

/// Seed 000's system (SPEC §1): the PR2 scans the cup it holds, finds how it rests,
/// finds the table and a free spot on it, drives up, puts it down; physics judges it.
fn placing() -> Result<()> {
    use tabula_tasks::place::{PlaceParams, PlaceRequest};
    println!("8. Placing an unknown object (seed 000): the PR2 and the cup in its hand\n");
    let scene = tabula_sim::Scene::parse(
        include_str!("../../../scenes/pr2_holding.toml"),
        "scenes/pr2_holding.toml",
    )?;
    let world = tabula_sim::SimWorld::from_scene(&scene, Default::default())?;
    let t0 = Instant::now();
    let request = PlaceRequest {
        arm: Some("right".into()),
    };
    let (out, _) = crate::place::place_in(world, None, &request, &PlaceParams::default(), 1)?;
    let r = &out.report;
    if let Some(m) = &r.model {
        println!(
            "  scanned in {} views: {} points, {:.0} × {:.0} × {:.0} mm, hull {:.0} cm³ (the cup is 288 cm³)",
            m.views,
            m.points,
            m.size[0] * 1e3,
            m.size[1] * 1e3,
            m.size[2] * 1e3,
            m.hull_volume_m3 * 1e6
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
    println!(
        "  {}: on {}, {:.1}° from the planned pose, {:.1} s in all; decision {:.0} ms CPU (scan processing {:.0} ms apart)",
        if out.success { "placed" } else { "FAILED" },
        out.verdict.surface.as_deref().unwrap_or("nothing"),
        out.orientation_error_deg,
        t0.elapsed().as_secs_f64(),
        out.decision_ms,
        r.scan_cpu_ms
    );
    println!("\n  run it: cargo run --release -- place --scene scenes/pr2_holding.toml");
    println!(
        "  benchmarks: cargo run --release -- bench place --suite simple|complex; bench stable-poses\n"
    );
    Ok(())
}

/// Seed 002's system (SPEC §3): the WAM clears the seed's cluttered table into the bin,
/// replanning after every action, and physics counts what ended in the bin.
fn clearing() -> Result<()> {
    use tabula_sim::generate::{ClearSuite, clearing_scene};
    println!("7. Clearing a cluttered table (seed 002): the WAM, grasps and pushes into the bin\n");
    let scene =
        tabula_sim::Scene::parse(&clearing_scene(ClearSuite::Seed, 1), "scenes/clutter.toml")?;
    let world = tabula_sim::SimWorld::from_scene(&scene, Default::default())?;
    let t0 = Instant::now();
    let (out, _) = crate::clear::clear_in(
        world,
        None,
        &tabula_tasks::clear::ClearParams::default(),
        None,
        1,
    )?;
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
    println!(
        "  {} of {} objects in the bin in {} actions ({} grasps, {} pushes), {:.1} s in all; arm touched another object {} times",
        v.in_bin,
        v.objects,
        r.actions,
        r.grasps,
        r.pushes,
        t0.elapsed().as_secs_f64(),
        out.collisions
    );
    println!(
        "  decision per frame (CPU, frame in → action chosen): median {:.1} ms (perception {:.1}, predicates {:.1}, planning {:.1}, IK {:.1}); the seed needed ≈ 4.5 s\n",
        r.decision_ms.median, r.perception_ms, r.predicates_ms, r.planning_ms, r.ik_ms
    );
    println!("  run it: cargo run --release -- clear --scene scenes/clutter.toml");
    println!("  benchmarks: cargo run --release -- bench clear --suite random|packed|pile|seed\n");
    Ok(())
}

/// Seed 001's integral test (SPEC §2.5): Golem-III looks at a can on a shelf board,
/// plans every motion, carries it to the table, and physics judges the result.
fn pick_place() -> Result<()> {
    use tabula_tasks::pick_place::{PickPlaceParams, PickPlaceRequest};
    println!(
        "6. Pick and place by coordinates (seed 001's integral test): Golem-III, shelf → table\n"
    );
    let scene = tabula_sim::Scene::parse(GOLEM_SHELVES, "scenes/golem_shelves.toml")?;
    let world = tabula_sim::SimWorld::from_scene(&scene, Default::default())?;
    let request = PickPlaceRequest {
        arm: None,
        pick: Vec3::new(0.556, -0.663, 1.07),
        place: Vec3::new(0.82, -0.2, 1.01),
    };
    let t0 = Instant::now();
    let (out, _) =
        crate::tasks::pick_place_in(world, None, &request, &PickPlaceParams::default(), 1)?;
    let r = &out.report;
    println!(
        "  {} with the {} arm ({} grasp); decision {:.0} ms CPU (perceive → grasp → every plan), {:.1} s in all",
        if out.success { "placed" } else { "FAILED" },
        r.arm.as_deref().unwrap_or("-"),
        r.grasp
            .map_or("-".into(), |g| format!("{g:?}").to_lowercase()),
        r.decision_cpu_ms,
        t0.elapsed().as_secs_f64()
    );
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
    println!(
        "  physics: {:.1} cm from the target, tilted {:.1}°, {}, {} furniture contacts{}\n",
        v.target_error * 100.0,
        v.tilt.to_degrees(),
        if v.resting { "resting" } else { "moving" },
        v.furniture_contacts.len(),
        out.error_message
            .as_ref()
            .map_or(String::new(), |e| format!("; {e}"))
    );
    println!(
        "  run it: cargo run --release -- pick-place --scene scenes/golem_shelves.toml --pick 0.556 -0.663 1.07 --place 0.82 -0.2 1.01\n"
    );
    Ok(())
}

const GOLEM_SHELVES: &str = include_str!("../../../scenes/golem_shelves.toml");

/// Seed 002's perception on the simulator's frame: the table, the objects on it, and
/// where a new box would fit; then the nine-object frame scored against the
/// simulator's labels.
fn perception(frame: &tabula_sim::DepthFrame) -> Result<()> {
    use tabula_geom::Vec2;
    use tabula_perception::eval::{score, table_top_truth};
    use tabula_perception::freespace::{FreeSpaceMap, FreeSpaceParams};
    use tabula_perception::{TabletopParams, extract, to_world};
    use tabula_sim::generate::{TABLE_TOP, TabletopLayout, tabletop_frame};
    println!(
        "4. Perception (PCL's role): the table, its objects and its free space in that frame\n"
    );
    let t0 = Instant::now();
    let cloud = to_world(&frame.world_from_camera, &frame.cloud);
    let t = extract(
        &cloud,
        frame.world_from_camera.translation,
        &TabletopParams::default(),
    )?;
    let ms = t0.elapsed().as_secs_f64() * 1e3;
    println!(
        "  table at {:.3} m ({} points, {:.2} m² seen), {} objects, {ms:.1} ms",
        t.table.centroid.z,
        t.table.inliers.len(),
        t.table.area,
        t.objects.len(),
    );
    for o in &t.objects {
        let c = o.obb.center;
        let s = o.obb.half_extents * 2000.0;
        println!(
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
    match map.find_place(&footprint, 0.03, t.table.centroid) {
        Some(p) => println!(
            "  free: {:.2} m²; a 10 × 8 cm box with 3 cm to spare fits at ({:.3}, {:.3}), turned {:.0}°",
            map.free_area(),
            p.position.x,
            p.position.y,
            p.yaw.to_degrees()
        ),
        None => println!(
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
        &finite,
        &g.frame.labels,
        g.table_label,
        &table_top_truth(&cloud.points, TABLE_TOP),
        &labels,
        0.8,
        200,
    );
    println!(
        "  nine-object frame (two touching pairs, a stack, 0.5 % outliers): {} of {} objects with IoU > 0.8, \
         table precision {:.3} recall {:.3}, {ms:.1} ms (PCL: 1.2 s)\n",
        s.recovered, s.objects, s.table_precision, s.table_recall
    );
    Ok(())
}

/// MoveIt's role: a collision-free reach for the WAM over a cluttered table.
fn motion() -> Result<()> {
    use tabula_motion::bench::{reach_configuration, robot_world, table_height, tabletop_world};
    use tabula_motion::{PlannerParams, WorldParams, rrt_connect, time_parameterize};
    println!("5. Motion planning (MoveIt/OMPL's role): WAM reaches over a cluttered table\n");
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
        println!(
            "  reach {}: {} waypoints, {:.2} rad, planned in {:.2} ms, {:.2} s to execute at the joints' limits",
            k + 1,
            path.waypoints.len(),
            path.length(),
            path.planning_time * 1e3,
            traj.duration()
        );
    }
    println!("\n  Benchmarks: `tabula motion bench --robot wam` (see BENCHMARKS.md)\n");
    Ok(())
}

/// The built-in simulator: settle seed 002's clutter, capture a frame, render a picture.
fn simulator() -> Result<tabula_sim::DepthFrame> {
    use tabula_sim::camera::{Camera, capture};
    use tabula_sim::{PhysicsParams, Scene, SimWorld};
    println!("3. Simulator (Gazebo's role): seed 002's cluttered table\n");
    let mut scene = Scene::parse(
        include_str!("../../../scenes/clutter.toml"),
        "scenes/clutter.toml",
    )?;
    scene.base_dir = None;
    let mut world = SimWorld::from_scene(&scene, PhysicsParams::default())?;
    let t0 = Instant::now();
    let report = world.settle();
    println!(
        "  settled {} objects in {} steps ({:.1} ms): all at rest = {}",
        world.object_poses().len(),
        report.steps,
        t0.elapsed().as_secs_f64() * 1e3,
        report.all_asleep
    );
    let camera = Camera::from_spec(&scene.cameras[0], &world)?;
    let t0 = Instant::now();
    let frame = capture(&world, &camera, 1);
    println!(
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
    println!(
        "  snapshot: {}\n  depth frame: {}\n",
        png.display(),
        pcd.display()
    );
    Ok(frame)
}

/// Seed 002's decision step: plan which objects to push or grasp, in process.
fn planning() -> Result<()> {
    use tabula_pddl::{
        GroundAtom, Planner, SearchMode, generator, parse_domain, parse_problem, validate,
    };
    println!("2. Task planning (seed 002): clearing a table, optimal PDDL plans in process\n");
    let domain = parse_domain(include_str!("../../../pddl/tablewclear-domain.pddl"))?;
    let problem = parse_problem(include_str!("../../../pddl/thesis6-a.pddl"), &domain)?;
    let mut planner = Planner::for_table_clearing(domain.clone(), problem)?;
    let t0 = Instant::now();
    let plan = planner.plan(SearchMode::Optimal, None)?;
    let ms = t0.elapsed().as_secs_f64() * 1e3;
    let steps: Vec<String> = plan.steps.iter().map(ToString::to_string).collect();
    println!(
        "  thesis6-a (6 objects): {} actions, optimal, {ms:.2} ms",
        steps.len()
    );
    println!("    {}", steps.join(" "));
    // The first action turns out to have no IK solution: mark it and replan (SPEC §3.5).
    let first = &plan.steps[0];
    let infeasible = GroundAtom {
        predicate: if first.action == "grasp" {
            "ik_unfeasible_grasp".into()
        } else {
            format!("ik_unfeasible_{}", first.action.trim_start_matches("push_"))
        },
        args: first.args.clone(),
    };
    let t0 = Instant::now();
    planner.set_fact(&infeasible, true)?;
    // Objects that can no longer be removed leave the goal (the seed's rule, made exact).
    let dropped: Vec<String> = planner
        .drop_unreachable_goals(None)?
        .iter()
        .map(|a| a.args.join(" "))
        .collect();
    let replanned = planner.plan(SearchMode::Optimal, None)?;
    println!(
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
    let mut planner = Planner::for_table_clearing(domain.clone(), big)?;
    let dropped = planner.drop_unreachable_goals(None)?;
    let plan = planner.plan(SearchMode::Optimal, None)?;
    println!(
        "  a generated 40-object table: {} objects can never be removed, optimal plan of {} actions, {:.1} ms with grounding",
        dropped.len(),
        plan.steps.len(),
        t0.elapsed().as_secs_f64() * 1e3
    );
    println!("\n  Benchmarks: `tabula plan bench` (see BENCHMARKS.md)\n");
    Ok(())
}

fn kinematics() -> Result<()> {
    println!("1. Kinematics (seed 001): Golem-III closed-form IK, all branches\n");
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
        println!(
            "  target: {label} at ({:.3}, {:.3}, {:.3}) in torso_lift_link",
            t.x, t.y, t.z
        );
        let t0 = Instant::now();
        let result = ik.solve(target, IkMode::Full, &seed);
        let us = t0.elapsed().as_secs_f64() * 1e6;
        match result {
            Ok(sols) => {
                crate::ik::print_solutions(&chain, &sols);
                println!("  nearest to the seed {:?}: #1 ({us:.1} µs)\n", seed);
            }
            Err(e) => println!("  {e} ({us:.1} µs)\n"),
        }
    }
    let reach = Vec3::new(0.35, -0.55, 1.0);
    let t0 = Instant::now();
    let sols = ik.solve(&Pose::from_translation(reach), IkMode::PositionOnly, &seed)?;
    println!(
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

    println!("  Numeric IK on the 7-DOF WAM and the PR2 right arm (any URDF chain):");
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
        println!(
            "    {name:<4} {} → {}: solved in {:.1} µs, error {:.1e} m / {:.1e} rad",
            chain.base_link,
            chain.tip_link,
            t0.elapsed().as_secs_f64() * 1e6,
            sols[0].position_error,
            sols[0].rotation_error
        );
    }
    println!(
        "\n  Benchmarks: `tabula ik bench --robot golem3 --solver analytic --poses 10000` (see BENCHMARKS.md)\n"
    );
    Ok(())
}
