//! The demo's capabilities: kinematics, task planning, the simulator and motion
//! planning on their own, each said in a few lines.

use super::Tour;
use anyhow::Result;
use std::time::Instant;
use tabula_geom::{Pose, Vec3, pose_from_xyz_rpy};
use tabula_robot::Chain;
use tabula_robot::ik::{
    ArmSide, Golem3Ik, Golem3Params, IkMode, IkSolver, NumericIk, NumericIkParams,
};
use tabula_robot::robots;

pub fn kinematics(tour: &mut Tour) -> Result<()> {
    say!(
        tour,
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
            tour,
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
                for line in crate::ik::solution_lines(&chain, &sols) {
                    tour.tell(line);
                }
                say!(tour, "  nearest to the seed {:?}: #1 ({us:.1} µs)\n", seed);
            }
            Err(e) => say!(tour, "  {e} ({us:.1} µs)\n"),
        }
    }
    let reach = Vec3::new(0.35, -0.55, 1.0);
    let t0 = Instant::now();
    let sols = ik.solve(&Pose::from_translation(reach), IkMode::PositionOnly, &seed)?;
    say!(
        tour,
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
        tour,
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
            tour,
            "    {name:<4} {} → {}: solved in {:.1} µs, error {:.1e} m / {:.1e} rad",
            chain.base_link,
            chain.tip_link,
            t0.elapsed().as_secs_f64() * 1e6,
            sols[0].position_error,
            sols[0].rotation_error
        );
    }
    say!(
        tour,
        "\n  Benchmarks: `tabula ik bench --robot golem3 --solver analytic --poses 10000` (see BENCHMARKS.md)\n"
    );
    Ok(())
}

/// Seed 002's decision step: plan which objects to push or grasp, in process.
pub fn planning(tour: &mut Tour) -> Result<()> {
    use tabula_pddl::{
        GroundOptions, Planner, SearchMode, generator, parse_domain, parse_problem, validate,
    };
    say!(
        tour,
        "6. Task planning (seed 002): clearing a table, optimal PDDL plans in process\n"
    );
    let domain = parse_domain(include_str!("../../../../pddl/tablewclear-domain.pddl"))?;
    let problem = parse_problem(include_str!("../../../../pddl/thesis6-a.pddl"), &domain)?;
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
        tour,
        "  thesis6-a (6 objects): {} actions, optimal, {ms:.2} ms",
        steps.len()
    );
    say!(tour, "    {}", steps.join(" "));
    // The first action turns out to have no IK solution: mark it and replan (SPEC §3.5).
    let first = &plan.steps[0];
    let infeasible = crate::plan::infeasible(first);
    let t0 = Instant::now();
    planner.set_fact(&infeasible, true)?;
    // Objects that can no longer be removed leave the goal (the seed's rule, made exact).
    let dropped: Vec<String> = planner
        .drop_unreachable_goals(tabula_pddl::Budget::UNLIMITED)?
        .iter()
        .map(|a| a.args.join(" "))
        .collect();
    let replanned = planner.plan(SearchMode::Optimal, None)?;
    say!(
        tour,
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
    let dropped = planner.drop_unreachable_goals(tabula_pddl::Budget::UNLIMITED)?;
    let plan = planner.plan(SearchMode::Optimal, None)?;
    say!(
        tour,
        "  a generated 40-object table: {} objects can never be removed, optimal plan of {} actions, {:.1} ms with grounding",
        dropped.len(),
        plan.steps.len(),
        t0.elapsed().as_secs_f64() * 1e3
    );
    say!(
        tour,
        "\n  Benchmarks: `tabula plan bench` (see BENCHMARKS.md)\n"
    );
    Ok(())
}

/// The built-in simulator: settle seed 002's clutter, capture a frame, render a picture.
pub fn simulator(tour: &mut Tour) -> Result<tabula_sim::DepthFrame> {
    use tabula_sim::camera::{Camera, capture};
    use tabula_sim::{PhysicsParams, Scene, SimWorld};
    say!(
        tour,
        "7. Simulator (Gazebo's role): seed 002's cluttered table\n"
    );
    let mut scene = Scene::parse(tabula_sim::builtin::CLUTTER, "scenes/clutter.toml")?;
    scene.base_dir = None;
    let mut world = SimWorld::from_scene(&scene, PhysicsParams::default())?;
    let t0 = Instant::now();
    let report = world.settle();
    say!(
        tour,
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
        tour,
        "  overhead depth frame {}×{}: {} valid points, {:.1} ms",
        frame.width,
        frame.height,
        frame.cloud.finite_count(),
        t0.elapsed().as_secs_f64() * 1e3
    );
    let dir = std::env::temp_dir().join("tabula-demo");
    std::fs::create_dir_all(&dir)?;
    let png = dir.join("clutter.png");
    crate::report::default_snapshot(&world, &png)?;
    let pcd = dir.join("clutter.pcd");
    frame.cloud.write_pcd(
        &mut std::io::BufWriter::new(std::fs::File::create(&pcd)?),
        tabula_geom::PcdEncoding::Binary,
    )?;
    say!(
        tour,
        "  snapshot: {}\n  depth frame: {}\n",
        png.display(),
        pcd.display()
    );
    Ok(frame)
}

/// MoveIt's role: a collision-free reach for the WAM over a cluttered table.
pub fn motion(tour: &mut Tour) -> Result<()> {
    use tabula_motion::bench::{reach_configuration, robot_world, table_height, tabletop_world};
    use tabula_motion::{PlannerParams, WorldParams, rrt_connect, time_parameterize};
    say!(
        tour,
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
        let traj = time_parameterize(&path.waypoints, &world.chain.velocity, &[2.0; 7], 0.01)?;
        say!(
            tour,
            "  reach {}: {} waypoints, {:.2} rad, planned in {:.2} ms, {:.2} s to execute at the joints' limits",
            k + 1,
            path.waypoints.len(),
            path.length(),
            path.planning_time * 1e3,
            traj.duration()
        );
    }
    say!(
        tour,
        "\n  Benchmarks: `tabula motion bench --robot wam` (see BENCHMARKS.md)\n"
    );
    Ok(())
}
