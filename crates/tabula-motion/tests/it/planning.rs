//! Motion planning correctness over many seeded problems, and bad input.

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use tabula_geom::parry::shape::SharedShape;
use tabula_geom::{Pose, Quat, Vec3};
use tabula_motion::bench::{reach_configuration, robot_world, table_height, tabletop_world};
use tabula_motion::{
    PlanError, PlannerParams, WorldParams, cartesian_path, fitted_world, pose_goals, rrt_connect,
    segment_valid, time_parameterize,
};
use tabula_robot::{Chain, robots};

fn wam() -> (robots::NamedRobot, Chain) {
    let r = robots::load("wam").unwrap();
    let chain = Chain::new(&r.model, "base_link", "wam_tool").unwrap();
    (r, chain)
}

/// The WAM alone in its world, and a configuration reaching forward and down.
fn wam_reaching() -> (tabula_motion::CollisionWorld, Vec<f64>) {
    let (robot, chain) = wam();
    let world = robot_world(&robot, chain, WorldParams::default()).unwrap();
    (world, vec![0.0, 0.6, 0.0, 1.6, 0.0, 0.4, 0.0])
}

#[test]
fn a_thousand_plans_are_valid_at_ten_times_finer_resolution() {
    let (robot, chain) = wam();
    let empty = robot_world(&robot, chain.clone(), WorldParams::default()).unwrap();
    // The re-check: the same 1 cm padding, configurations 10× closer.
    let strict = robot_world(
        &robot,
        chain,
        WorldParams {
            max_step_displacement: 0.001,
            ..Default::default()
        },
    )
    .unwrap();
    let top = table_height(&robot);
    let params = PlannerParams::default();
    let mut plans = 0;
    for scene in 0..50u64 {
        let world = tabletop_world(&empty, top, scene).unwrap();
        let recheck = tabletop_world(&strict, top, scene).unwrap();
        let mut rng = ChaCha8Rng::seed_from_u64(scene);
        for k in 0..20u64 {
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
                    ..params.clone()
                },
            )
            .expect("tabletop reach problems are solvable");
            assert_eq!(path.waypoints.first(), Some(&start));
            assert_eq!(path.waypoints.last(), Some(&goal));
            for w in path.waypoints.windows(2) {
                assert!(
                    segment_valid(&recheck, &w[0], &w[1], params.resolution / 10.0),
                    "scene {scene} plan {k}"
                );
                assert!(world.chain.within_limits(&w[1], 1e-12));
            }
            plans += 1;
        }
    }
    assert!(plans >= 1000, "only {plans} plans");
}

#[test]
fn a_goal_within_the_padding_is_reached_with_a_thinner_one_and_never_touched() {
    let (robot, chain) = wam();
    let q_goal = vec![0.0, 0.6, 0.0, 1.6, 0.0, 0.4, 0.0];
    let q_start = vec![0.8, 0.2, 0.0, 1.9, 0.0, 0.2, 0.0];
    let mut world = robot_world(&robot, chain, WorldParams::default()).unwrap();
    let tip = world.tip_pose(&q_goal).unwrap();
    // A wall 3 mm beyond the fingertips: inside the 1 cm padding, clear of contact.
    let down = tip.rotation * Vec3::Z;
    let wall_at = tip.translation + down * (0.0225 + 0.003 + 0.01);
    let wall = Pose::from_parts(wall_at, tip.rotation);
    world
        .add_box("wall", Vec3::new(0.5, 0.5, 0.02), wall)
        .unwrap();
    assert!(world.is_valid(&q_start) && !world.is_valid(&q_goal));
    let goals = vec![q_goal.clone()];
    let strict = PlannerParams::default();
    assert!(matches!(
        rrt_connect(&world, &q_start, &goals, &strict),
        Err(PlanError::GoalInvalid(why)) if why.contains("padding")
    ));
    assert!(matches!(
        fitted_world(&world, &q_start, &goals, &strict),
        std::borrow::Cow::Borrowed(_)
    ));
    let fit = PlannerParams {
        shrink_padding_to_endpoints: true,
        ..strict
    };
    let thinner = fitted_world(&world, &q_start, &goals, &fit);
    let pad = thinner.max_padding();
    assert!((0.01 / 64.0..0.003).contains(&pad), "padding {pad}");
    let path =
        rrt_connect(&thinner, &q_start, &goals, &fit).expect("the goal fits the thinner padding");
    assert_eq!(path.waypoints.last(), Some(&q_goal));
    // Every 0.5 mm of motion along the path: no contact on the exact geometry.
    assert_eq!(crate::first_touch(&world, &path.waypoints, 5e-4), None);
    // A goal that touches is still refused, whatever the padding.
    let touching = Pose::from_parts(tip.translation + down * 0.02, tip.rotation);
    world
        .add_box("block", Vec3::new(0.5, 0.5, 0.02), touching)
        .unwrap();
    assert!(matches!(
        fitted_world(&world, &q_start, &goals, &fit),
        std::borrow::Cow::Borrowed(_)
    ));
}

#[test]
fn padding_is_honoured_and_attached_objects_are_checked() {
    let (robot, chain) = wam();
    let q = vec![0.0, 0.6, 0.0, 1.6, 0.0, 0.4, 0.0];
    let mut world = robot_world(&robot, chain.clone(), WorldParams::default()).unwrap();
    let tip = world.tip_pose(&q).unwrap();
    // A wall 5 mm beyond the fingertips: valid without padding, invalid with 1 cm.
    let mut bare = robot_world(
        &robot,
        chain,
        WorldParams {
            padding: 0.0,
            ..Default::default()
        },
    )
    .unwrap();
    let gap = 0.005;
    let down = tip.rotation * Vec3::Z;
    let wall_at = tip.translation + down * (0.0225 + gap + 0.01);
    let wall = Pose::from_parts(wall_at, tip.rotation);
    bare.add_box("wall", Vec3::new(0.5, 0.5, 0.02), wall)
        .unwrap();
    world
        .add_box("wall", Vec3::new(0.5, 0.5, 0.02), wall)
        .unwrap();
    assert!(bare.is_valid(&q), "{:?}", bare.first_collision(&q));
    assert!(!world.is_valid(&q));
    // Padding per link: only the fingers padded, 1 cm, reach the wall 5 mm away.
    let mut fingers_only = WorldParams {
        padding: 0.0,
        ..Default::default()
    };
    for f in ["wam_gripper_left_finger", "wam_gripper_right_finger"] {
        fingers_only.link_padding.insert(f.to_string(), 0.01);
    }
    let (_, chain2) = wam();
    let mut padded = robot_world(&robot, chain2, fingers_only).unwrap();
    padded
        .add_box("wall", Vec3::new(0.5, 0.5, 0.02), wall)
        .unwrap();
    let hit = padded
        .first_collision(&q)
        .unwrap()
        .expect("a padded finger touches the wall");
    assert!(hit.0.contains("finger") && hit.1 == "wall", "{hit:?}");
    assert!(bare.min_distance(&q).unwrap() > 0.0);
    // An object held by the palm, 10 cm long past the fingertips, reaches the wall.
    bare.attach(
        "bar",
        SharedShape::cuboid(0.01, 0.01, 0.06),
        "wam_tool",
        Pose::from_translation(Vec3::new(0.0, 0.0, 0.04)),
        &[
            "wam_gripper_left_finger",
            "wam_gripper_right_finger",
            "wam_gripper_palm",
        ],
    )
    .unwrap();
    let hit = bare.first_collision(&q).unwrap();
    assert_eq!(hit, Some(("bar".to_string(), "wall".to_string())));
}

#[test]
fn bad_starts_goals_and_input_get_clear_answers() {
    let (robot, chain) = wam();
    let empty = robot_world(&robot, chain, WorldParams::default()).unwrap();
    let top = table_height(&robot);
    let world = tabletop_world(&empty, top, 3).unwrap();
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let good = reach_configuration(&world, &mut rng, top).unwrap();
    // Folded into the table.
    let mut inside = good.clone();
    inside[1] = 1.9;
    inside[3] = 0.0;
    let p = PlannerParams::default();
    assert!(matches!(
        rrt_connect(&world, &inside, std::slice::from_ref(&good), &p),
        Err(PlanError::StartInvalid(_))
    ));
    assert!(matches!(
        rrt_connect(&world, &good, std::slice::from_ref(&inside), &p),
        Err(PlanError::GoalInvalid(_))
    ));
    let nan = vec![f64::NAN; 7];
    assert!(matches!(
        rrt_connect(&world, &nan, std::slice::from_ref(&good), &p),
        Err(PlanError::StartInvalid(_))
    ));
    assert!(matches!(
        rrt_connect(&world, &good[..3], std::slice::from_ref(&good), &p),
        Err(PlanError::StartInvalid(_))
    ));
    let far = Pose::from_translation(Vec3::new(3.0, 0.0, 1.0));
    assert!(pose_goals(&world, &far, &good, 4, 1).is_err());
    // A pose goal over the table: the planner reaches one of its IK solutions.
    let target = Pose::from_parts(
        Vec3::new(0.6, 0.3, top + 0.25),
        Quat::from_rotation_x(std::f64::consts::PI),
    );
    let goals = pose_goals(&world, &target, &good, 4, 1).unwrap();
    let path = rrt_connect(&world, &good, &goals, &p).unwrap();
    let end = world.tip_pose(path.waypoints.last().unwrap()).unwrap();
    assert!((end.translation - target.translation).length() < 1e-5);
}

#[test]
fn cartesian_approach_and_timing() {
    let (world, q) = wam_reaching();
    let from = world.tip_pose(&q).unwrap();
    // 10 cm straight down the tool axis, the seed's approach (SPEC §6).
    let goal = Pose::from_parts(
        from.translation + from.rotation * Vec3::new(0.0, 0.0, 0.1),
        from.rotation,
    );
    let (waypoints, fraction) =
        cartesian_path(&world, &q, &goal, 0.005, 0.3, &PlannerParams::default()).unwrap();
    assert!((fraction - 1.0).abs() < 1e-12, "{fraction}");
    for w in &waypoints {
        let t = world.tip_pose(w).unwrap().translation;
        let off_line = (t - from.translation)
            .cross(goal.translation - from.translation)
            .length()
            / 0.1;
        assert!(off_line < 1e-5, "{off_line}");
    }
    let vmax = vec![1.0; 7];
    let amax = vec![2.0; 7];
    let traj = time_parameterize(&waypoints, &vmax, &amax, 0.01).unwrap();
    assert!(traj.duration() > 0.0);
    for k in 1..traj.times.len() - 1 {
        let dt0 = traj.times[k] - traj.times[k - 1];
        let dt1 = traj.times[k + 1] - traj.times[k];
        for j in 0..7 {
            let v0 = (traj.positions[k][j] - traj.positions[k - 1][j]) / dt0;
            let v1 = (traj.positions[k + 1][j] - traj.positions[k][j]) / dt1;
            assert!(v0.abs() <= vmax[j] * 1.001, "velocity {v0}");
            assert!(
                ((v1 - v0) / (0.5 * (dt0 + dt1))).abs() <= amax[j] * 1.05,
                "acceleration"
            );
        }
    }
}

#[test]
fn point_cloud_occupancy_and_contact_lists() {
    let (mut world, q) = wam_reaching();
    let tip = world.tip_pose(&q).unwrap().translation;
    // A dense blob of points around the tool, with NaN points that must be skipped.
    let mut points = vec![Vec3::NAN; 10];
    for i in 0..20 {
        for j in 0..20 {
            points.push(tip + Vec3::new(i as f64 * 0.005 - 0.05, j as f64 * 0.005 - 0.05, 0.0));
        }
    }
    let cells = world.add_occupancy("scan", &points, 0.02).unwrap();
    assert!(cells > 10 && cells < 100, "{cells}");
    assert!(!world.is_valid(&q));
    let contacts = world.contacts(&q).unwrap();
    assert!(contacts.iter().any(|(_, b)| b == "scan"), "{contacts:?}");
    assert_eq!(world.add_occupancy("empty", &[Vec3::NAN], 0.02).unwrap(), 0);
    // A mesh obstacle at the tool, as a hull; a missing file is an error.
    let dir = std::env::temp_dir().join(format!("tabula-motion-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let obj = dir.join("block.obj");
    std::fs::write(&obj, "v -1 -1 -1\nv 1 -1 -1\nv -1 1 -1\nv 1 1 -1\nv -1 -1 1\nv 1 -1 1\nv -1 1 1\nv 1 1 1\nf 1 2 3\n").unwrap();
    let mut meshy = world.clone();
    meshy.remove_object("scan").unwrap();
    meshy
        .add_mesh(
            "block",
            &obj,
            Vec3::splat(0.03),
            Pose::from_translation(tip),
            false,
        )
        .unwrap();
    assert!(!meshy.is_valid(&q));
    assert!(
        meshy
            .add_mesh(
                "ghost",
                &dir.join("missing.obj"),
                Vec3::ONE,
                Pose::IDENTITY,
                false
            )
            .is_err()
    );
    std::fs::remove_dir_all(&dir).ok();
    world.remove_object("scan").unwrap();
    assert!(world.is_valid(&q));
    assert!(world.contacts(&q).unwrap().is_empty());
}

/// Golem-III's torso rotation θ1 is the first joint of both arms: planning the right
/// arm turns the left one too, and what the left hand holds with it. An object held in
/// the left hand, attached to it, is kept clear of the world by the right arm's plans;
/// without it the same motion looks free.
#[test]
fn what_the_other_hand_holds_turns_with_the_shared_torso() {
    use tabula_motion::{MoveGroup, MoveGroupParams};
    let robot = robots::load("golem3").unwrap();
    // Fingers open (closed, they touch each other), the rest at zero.
    let state = every_joint(&robot, |j| {
        if j.name.contains("finger") {
            j.limits.upper
        } else {
            0.0
        }
    });
    let params = MoveGroupParams::default();
    let bare = MoveGroup::new(&robot, "right", &state, Pose::IDENTITY, params).unwrap();
    let yaw = bare
        .joint_names()
        .iter()
        .position(|n| n == "torso_yaw_joint")
        .expect("θ1 is in the right arm's chain");
    let left = robot
        .description
        .grippers
        .iter()
        .find(|g| g.name == "left_gripper")
        .unwrap()
        .clone();
    let values = state.model_values(&robot.model);
    let fk = robot.model.forward_kinematics(&values).unwrap();
    let world_from_left_tool = fk[robot.model.link(&left.tool_link).unwrap()];
    // A bar held across the fingers, sticking 10–18 cm out along the approach.
    let tool_from_bar = Pose::from_translation(left.approach() * 0.14);
    let bar = SharedShape::cuboid(0.04, 0.02, 0.02);
    let bar_tip = world_from_left_tool * tool_from_bar.translation + left.approach() * 0.04;
    // A post where the bar's tip passes when θ1 turns by 0.5 rad.
    let turned = Quat::from_rotation_z(0.5) * bar_tip;
    let mut with_bar = bare.for_arm(&robot, "right").unwrap();
    let mut without_bar = bare.for_arm(&robot, "right").unwrap();
    for g in [&mut with_bar, &mut without_bar] {
        g.add_object(
            "post",
            SharedShape::cuboid(0.015, 0.015, 0.3),
            Pose::from_translation(turned),
        )
        .unwrap();
    }
    with_bar
        .attach_to_gripper(&left, "bar", bar, tool_from_bar)
        .unwrap();
    let start = with_bar.arm_values(&state);
    let mut goal = start.clone();
    goal[yaw] = 0.9;
    let mut middle = start.clone();
    middle[yaw] = 0.5;
    assert!(
        with_bar.world.is_valid(&start),
        "{:?}",
        with_bar.world.contacts(&start)
    );
    assert!(without_bar.world.is_valid(&start));
    assert!(
        without_bar.world.is_valid(&middle),
        "the bare hand misses the post"
    );
    assert!(
        !with_bar.world.is_valid(&middle),
        "the bar turns into the post"
    );
    // Every path from θ1 = 0 to 0.9 sweeps the bar through the post; the bare arm goes.
    assert!(without_bar.plan_to_joints(&start, &[goal.clone()]).is_ok());
    assert!(with_bar.plan_to_joints(&start, &[goal]).is_err());
}

#[test]
fn the_moving_bound_holds_the_arm_and_what_it_holds_in_every_configuration() {
    use rand::RngExt;
    use tabula_motion::{MoveGroup, MoveGroupParams};
    let robot = robots::load("pr2").unwrap();
    let state = every_joint(&robot, |_| 0.0);
    let root = Pose::from_parts(Vec3::new(1.0, -2.0, 0.0), Quat::from_rotation_z(0.7));
    let mut group =
        MoveGroup::new(&robot, "left", &state, root, MoveGroupParams::default()).unwrap();
    let (centre, bare) = group.world.moving_bound().unwrap();
    // A 25 cm bar held 10 cm ahead of the tool.
    let tool_from_bar = Pose::from_translation(Vec3::new(0.1, 0.0, 0.0));
    group
        .attach("bar", SharedShape::cuboid(0.125, 0.01, 0.01), tool_from_bar)
        .unwrap();
    let (same_centre, holding) = group.world.moving_bound().unwrap();
    assert!(centre.distance(same_centre) < 1e-12);
    assert!(holding > bare, "{holding} vs {bare}");
    // A PR2 arm reaches about 0.8 m from its shoulder, plus hand and bar.
    assert!((0.7..1.6).contains(&holding), "{holding}");
    let chain = &group.world.chain;
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    for _ in 0..500 {
        let q: Vec<f64> = (0..chain.dof())
            .map(|i| {
                let (lo, hi) = chain.sample_range(i);
                rng.random_range(lo..=hi)
            })
            .collect();
        let world_from_tool = group.world.tip_pose(&q).unwrap();
        assert!(world_from_tool.translation.distance(centre) <= bare);
        for corner in [Vec3::new(0.125, 0.01, 0.01), Vec3::new(-0.125, -0.01, 0.01)] {
            let p = world_from_tool.transform_point(tool_from_bar.transform_point(corner));
            assert!(p.distance(centre) <= holding, "{p:?}");
        }
    }
}

/// A joint state naming every single-axis joint of `robot`, each at `value` of it.
fn every_joint(
    robot: &robots::NamedRobot,
    value: impl Fn(&tabula_robot::model::Joint) -> f64,
) -> tabula_robot::driver::JointState {
    let mut state = tabula_robot::driver::JointState::default();
    for j in robot
        .model
        .joints
        .iter()
        .filter(|j| j.kind.is_single_axis())
    {
        state.names.push(j.name.clone());
        state.positions.push(value(j));
    }
    state
}

/// A velocity limit of 1e-300 (a URDF can say so) would time a one-radian move over
/// 10^300 s: refused with the joint and the limits named, no samples allocated.
#[test]
fn a_trajectory_too_long_to_sample_is_refused_naming_the_limit() {
    let waypoints = vec![vec![0.0, 0.0], vec![1.0, 0.5]];
    let e = time_parameterize(&waypoints, &[1.0, 1e-300], &[2.0, 2.0], 0.01).unwrap_err();
    assert_eq!(e.joint, 1);
    assert!(e.samples > tabula_motion::rrt::MAX_TRAJECTORY_SAMPLES as f64);
    assert!(e.to_string().contains("1e-300"), "{e}");
    // At the sampled bound's edge it is still timed.
    let ok = time_parameterize(&waypoints, &[1.0, 1e-3], &[2.0, 2.0], 0.01).unwrap();
    assert!(ok.times.len() <= tabula_motion::rrt::MAX_TRAJECTORY_SAMPLES + 1);
}

/// A robot that knows its pedestal keeps its arm off it: the pedestal is welded to the
/// base (never checked against it), and configurations that reach down past its side —
/// free without it — collide with it, and only with it.
#[test]
fn the_pedestal_is_part_of_the_robot_and_the_arm_keeps_off_it() {
    let (mut robot, chain) = wam();
    let (plain, _) = wam();
    robot.model.add_pedestal([0.3, 0.3, 0.6]).unwrap();
    assert!(
        robot.model.add_pedestal([0.3, 0.3, 0.6]).is_err(),
        "one pedestal"
    );
    let mut bad = wam().0;
    assert!(bad.model.add_pedestal([0.3, f64::NAN, 0.6]).is_err());
    assert!(bad.model.add_pedestal([0.3, 0.0, 0.6]).is_err());
    let world = robot_world(&robot, chain.clone(), WorldParams::default()).unwrap();
    let without = robot_world(&plain, chain.clone(), WorldParams::default()).unwrap();
    let pair = |a: &str, b: &str| {
        let allowed = world.allowed_pairs();
        allowed.contains(&(a.to_string(), b.to_string()))
            || allowed.contains(&(b.to_string(), a.to_string()))
    };
    assert!(pair("base_link", "pedestal"));
    // Without an SRDF the matrix is sampled: what can reach down there is checked.
    for link in ["wam_link7", "wam_gripper_palm"] {
        assert!(!pair(link, "pedestal"), "{link}");
    }
    assert!(world.is_valid(&chain.mid_configuration()));
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let mut hits = 0;
    for _ in 0..20_000 {
        let q = chain.random_configuration(&mut rng);
        if !without.is_valid(&q) || world.is_valid(&q) {
            continue;
        }
        hits += 1;
        let contacts = world.contacts(&q).unwrap();
        assert!(
            contacts
                .iter()
                .any(|(a, b)| a == "pedestal" || b == "pedestal"),
            "{contacts:?}"
        );
    }
    assert!(hits >= 5, "{hits} configurations reach into the pedestal");
}

/// Every object the arm touches is named, in a scene large enough for the objects' BVH
/// (more than 32 objects): `contacts` removes each object it reports and asks again,
/// and the index over the objects must follow.
#[test]
fn contacts_name_every_object_touched_among_many() {
    let (mut world, q) = wam_reaching();
    let tip = world.tip_pose(&q).unwrap().translation;
    for i in 0..40 {
        let far = Vec3::new(3.0 + 0.2 * i as f64, 3.0, 0.0);
        world
            .add_box(
                &format!("far{i}"),
                Vec3::splat(0.05),
                Pose::from_translation(far),
            )
            .unwrap();
    }
    for (name, dz) in [("first", 0.0), ("second", 0.01)] {
        let at = Pose::from_translation(tip + Vec3::new(0.0, 0.0, dz));
        world.add_box(name, Vec3::splat(0.03), at).unwrap();
    }
    let touched: Vec<String> = world
        .contacts(&q)
        .unwrap()
        .into_iter()
        .map(|(_, object)| object)
        .collect();
    for name in ["first", "second"] {
        assert!(
            touched.iter().any(|o| o == name),
            "{name} not in {touched:?}"
        );
    }
    assert!(!touched.iter().any(|o| o.starts_with("far")), "{touched:?}");
}
