//! The numeric solver on the built-in robots and on chains that climb the tree.

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use tabula_geom::{Pose, Quat, Vec3};
use tabula_robot::ik::{IkError, IkMode, IkSolver, NumericIk, NumericIkParams};
use tabula_robot::{Chain, RobotModel, robots};

fn deterministic() -> NumericIkParams {
    NumericIkParams {
        timeout_s: None,
        max_attempts: 400,
        ..NumericIkParams::default()
    }
}

fn check_rate(name: &str, base: &str, tip: &str, mode: IkMode, count: usize) {
    let robot = robots::load(name).unwrap();
    let chain = Chain::new(&robot.model, base, tip).unwrap();
    let ik = NumericIk::new(chain.clone(), deterministic());
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let seed = chain.mid_configuration();
    let mut solved = 0;
    for _ in 0..count {
        let q = chain.random_configuration(&mut rng);
        let target = chain.fk(&q).unwrap();
        if let Ok(sols) = ik.solve(&target, mode, &seed) {
            let reached = chain.fk(&sols[0].joints).unwrap();
            assert!(chain.within_limits(&sols[0].joints, 0.0));
            assert!((reached.translation - target.translation).length() < 1e-6);
            if mode == IkMode::Full {
                assert!(
                    tabula_geom::rotation_angle_between(reached.rotation, target.rotation) < 1e-6
                );
            }
            solved += 1;
        }
    }
    assert_eq!(
        solved, count,
        "{name} {base}→{tip} {mode:?}: {solved}/{count}"
    );
}

#[test]
fn numeric_full_pose_on_every_builtin_arm() {
    check_rate(
        "golem3",
        "torso_lift_link",
        "right_tool_link",
        IkMode::Full,
        300,
    );
    check_rate("wam", "base_link", "wam_tool", IkMode::Full, 300);
    check_rate(
        "pr2",
        "torso_lift_link",
        "r_gripper_tool_frame",
        IkMode::Full,
        300,
    );
    check_rate(
        "pr2",
        "torso_lift_link",
        "l_gripper_tool_frame",
        IkMode::Full,
        100,
    );
}

#[test]
fn numeric_position_only_and_free_roll() {
    check_rate("wam", "base_link", "wam_tool", IkMode::PositionOnly, 200);
    check_rate(
        "pr2",
        "base_link",
        "r_gripper_tool_frame",
        IkMode::PositionOnly,
        100,
    );
    let axis = IkMode::PositionAxis { tool_axis: Vec3::Z };
    check_rate("wam", "base_link", "wam_tool", axis, 200);
}

#[test]
fn free_roll_ignores_rotation_about_the_tool_axis() {
    let robot = robots::load("wam").unwrap();
    let chain = Chain::new(&robot.model, "base_link", "wam_tool").unwrap();
    let ik = NumericIk::new(chain.clone(), deterministic());
    let q = vec![0.3, 0.5, -0.2, 1.4, 0.3, 0.6, 0.4];
    let target = chain.fk(&q).unwrap();
    // Spin the target about its own z: the full pose changes, the tool axis does not.
    let spun = Pose::from_parts(
        target.translation,
        target.rotation * Quat::from_rotation_z(1.0),
    );
    let sols = ik
        .solve(&spun, IkMode::PositionAxis { tool_axis: Vec3::Z }, &q)
        .unwrap();
    let reached = chain.fk(&sols[0].joints).unwrap();
    let axis_err = (reached.rotation * Vec3::Z).angle_between(spun.rotation * Vec3::Z);
    assert!(axis_err < 1e-6 && (reached.translation - spun.translation).length() < 1e-6);
}

#[test]
fn same_seed_same_answer_and_nearest_to_seed() {
    let robot = robots::load("wam").unwrap();
    let chain = Chain::new(&robot.model, "base_link", "wam_tool").unwrap();
    let ik = NumericIk::new(
        chain.clone(),
        NumericIkParams {
            max_solutions: 4,
            ..deterministic()
        },
    );
    let q = vec![0.3, 0.5, -0.2, 1.4, 0.3, 0.6, 0.4];
    let target = chain.fk(&q).unwrap();
    let a = ik.solve(&target, IkMode::Full, &q).unwrap();
    let b = ik.solve(&target, IkMode::Full, &q).unwrap();
    assert_eq!(a, b);
    // Seeded at the generating configuration, the first answer is that configuration.
    let d: f64 = a[0].joints.iter().zip(&q).map(|(x, y)| (x - y).abs()).sum();
    assert!(d < 1e-6, "{:?}", a[0].joints);
}

#[test]
fn chains_can_climb_the_tree() {
    // From the right gripper to the left one: climbs the right arm, descends the left.
    let robot = robots::load("pr2").unwrap();
    let chain = Chain::new(&robot.model, "r_gripper_tool_frame", "l_gripper_tool_frame").unwrap();
    assert_eq!(chain.dof(), 14);
    let model = &robot.model;
    let mut values = model.mid_configuration();
    let q = chain.mid_configuration();
    for (v, &j) in q.iter().zip(&chain.joint_indices) {
        values[j] = *v;
    }
    let world = model.forward_kinematics(&values).unwrap();
    let r = world[model.link("r_gripper_tool_frame").unwrap()];
    let l = world[model.link("l_gripper_tool_frame").unwrap()];
    let expected = r.inverse() * l;
    let got = chain.fk(&q).unwrap();
    assert!((expected.translation - got.translation).length() < 1e-12);
    // The Jacobian of a climbing chain matches finite differences.
    let jac = chain.jacobian(&q).unwrap();
    for i in 0..chain.dof() {
        let mut qp = q.clone();
        qp[i] += 1e-7;
        let dp = (chain.fk(&qp).unwrap().translation - got.translation) / 1e-7;
        for r in 0..3 {
            assert!((jac[(r, i)] - dp[r]).abs() < 1e-5, "column {i} row {r}");
        }
    }
}

#[test]
fn unreachable_and_invalid_targets() {
    let robot = robots::load("wam").unwrap();
    let chain = Chain::new(&robot.model, "base_link", "wam_tool").unwrap();
    let ik = NumericIk::new(chain.clone(), deterministic());
    let seed = chain.mid_configuration();
    let far = Pose::from_translation(Vec3::new(5.0, 0.0, 0.0));
    assert_eq!(
        ik.solve(&far, IkMode::Full, &seed),
        Err(IkError::NoSolution)
    );
    let inf = Pose::from_translation(Vec3::new(f64::INFINITY, 0.0, 0.0));
    assert_eq!(
        ik.solve(&inf, IkMode::Full, &seed),
        Err(IkError::NonFiniteTarget)
    );
    let nan_rot = Pose::from_parts(Vec3::ZERO, Quat::from_xyzw(f64::NAN, 0.0, 0.0, 1.0));
    assert_eq!(
        ik.solve(&nan_rot, IkMode::Full, &seed),
        Err(IkError::NonFiniteTarget)
    );
    assert!(matches!(
        ik.solve(&Pose::IDENTITY, IkMode::Full, &[0.0]),
        Err(IkError::WrongSeedLength { .. })
    ));
    // Inside the reach bound but behind a joint limit: a clean "no solution", in budget.
    let one_joint = r#"<robot name="r"><link name="a"/><link name="b"/><link name="tip"/>
      <joint name="j" type="revolute"><parent link="a"/><child link="b"/><axis xyz="0 0 1"/>
        <limit lower="-0.5" upper="0.5" effort="1" velocity="1"/></joint>
      <joint name="t" type="fixed"><origin xyz="1 0 0"/><parent link="b"/><child link="tip"/></joint></robot>"#;
    let model = RobotModel::from_urdf_str(one_joint, None).unwrap();
    let small = Chain::new(&model, "a", "tip").unwrap();
    let limited = NumericIk::new(small, deterministic());
    let beyond_limit = Pose::from_translation(Vec3::new(0.0, 1.0, 0.0));
    // A numeric solver cannot prove it: it says it found none, not "out of reach".
    let none = limited.solve(&beyond_limit, IkMode::PositionOnly, &[0.0]);
    assert!(matches!(none, Err(IkError::NotFound { .. })), "{none:?}");
    assert!(!none.unwrap_err().to_string().contains("out of reach"));
    let within = Pose::from_translation(Vec3::new(0.4f64.cos(), 0.4f64.sin(), 0.0));
    let sol = limited
        .solve(&within, IkMode::PositionOnly, &[0.0])
        .unwrap();
    assert!((sol[0].joints[0] - 0.4).abs() < 1e-6);
}

#[test]
fn parameters_load_from_toml() {
    let p: NumericIkParams = toml::from_str("timeout_s = 0.002\nmax_solutions = 3").unwrap();
    assert_eq!(p.max_solutions, 3);
    assert_eq!(
        p.position_tolerance,
        NumericIkParams::default().position_tolerance
    );
    assert!(toml::from_str::<NumericIkParams>("no_such_key = 1").is_err());
    let _ = RobotModel::from_urdf_str(robots::GOLEM3_URDF, None).unwrap();
}

/// Near a singularity (the WAM stretched straight up) `max_solutions = 8` returns
/// solutions that differ, not eight copies of one within a milliradian.
#[test]
fn several_solutions_are_distinct() {
    let robot = robots::load("wam").unwrap();
    let chain = Chain::new(&robot.model, "base_link", "wam_tool").unwrap();
    let params = NumericIkParams {
        max_solutions: 8,
        ..deterministic()
    };
    let ik = NumericIk::new(chain.clone(), params.clone());
    let mut q = vec![0.0; chain.dof()];
    q[3] = 0.05;
    let target = chain.fk(&q).unwrap();
    let sols = ik.solve(&target, IkMode::Full, &q).unwrap();
    assert!(sols.len() >= 2);
    for (i, a) in sols.iter().enumerate() {
        for b in &sols[i + 1..] {
            let d = tabula_robot::ik::joint_distance(&chain, &a.joints, &b.joints);
            assert!(d >= params.min_separation, "{d}");
        }
    }
}
