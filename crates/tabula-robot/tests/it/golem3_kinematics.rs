//! Golem-III: the URDF against the DH table of SPEC §2.1, and the analytic solver.

use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use tabula_geom::{Mat4, Pose, Vec3};
use tabula_robot::ik::{ArmSide, Golem3Ik, Golem3Params, IkError, IkMode, IkSolver};
use tabula_robot::{Chain, RobotModel, robots};

/// The DH product of SPEC §2.1, written independently of the URDF generator.
fn dh_product(q: &[f64; 6]) -> Mat4 {
    let rho = 13.43f64.to_radians();
    let h90 = std::f64::consts::FRAC_PI_2;
    // (theta, d, a, alpha) per row.
    let rows = [
        (q[0] - h90, 1.283, 0.1225, 0.0),
        (q[1], 0.0, 0.212, 0.0),
        (q[2] + h90, 0.0, 0.0, h90),
        (q[3] - h90 + rho, 0.0, 0.256, 0.0),
        (q[4] - rho, 0.0, 0.034, -h90),
        (q[5] - h90, 0.4, 0.0, h90),
        (h90, 0.0, 0.0, 0.0),
    ];
    rows.iter()
        .fold(Mat4::IDENTITY, |t, &(theta, d, a, alpha)| {
            t * Mat4::from_rotation_z(theta)
                * Mat4::from_translation(Vec3::new(0.0, 0.0, d))
                * Mat4::from_translation(Vec3::new(a, 0.0, 0.0))
                * Mat4::from_rotation_x(alpha)
        })
}

fn golem() -> RobotModel {
    RobotModel::from_urdf_str(robots::GOLEM3_URDF, None).unwrap()
}

fn random_q(chain: &Chain, rng: &mut ChaCha8Rng) -> Vec<f64> {
    chain.random_configuration(rng)
}

#[test]
fn urdf_fk_equals_dh_product_on_10000_configurations() {
    let model = golem();
    let right = Chain::new(&model, "base_link", "right_tool_link").unwrap();
    let left = Chain::new(&model, "base_link", "left_tool_link").unwrap();
    assert_eq!(right.dof(), 7, "lift + torso + 5 arm joints");
    let mirror = Mat4::from_scale(Vec3::new(1.0, -1.0, 1.0));
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let mut worst: f64 = 0.0;
    for _ in 0..10_000 {
        let mut q = [0.0; 6];
        for (i, v) in q.iter_mut().enumerate() {
            let (lo, hi) = right.sample_range(i + 1);
            *v = rng.random_range(lo..=hi);
        }
        let mut full = vec![0.0];
        full.extend_from_slice(&q);
        let urdf = right.fk(&full).unwrap().to_mat4();
        worst = worst.max(
            (urdf - dh_product(&q))
                .abs()
                .to_cols_array()
                .iter()
                .cloned()
                .fold(0.0, f64::max),
        );
        // Left arm: the mirror image of the right arm with the torso angle negated.
        let urdf_left = left.fk(&full).unwrap().to_mat4();
        let mut qm = q;
        qm[0] = -qm[0];
        let dh_left = mirror * dh_product(&qm) * mirror;
        worst = worst.max(
            (urdf_left - dh_left)
                .abs()
                .to_cols_array()
                .iter()
                .cloned()
                .fold(0.0, f64::max),
        );
    }
    assert!(worst < 1e-12, "largest element difference {worst}");
}

#[test]
fn torso_lift_raises_the_shoulder() {
    let model = golem();
    let chain = Chain::new(&model, "base_link", "right_tool_link").unwrap();
    let low = chain.fk(&[0.0; 7]).unwrap();
    let mut q = [0.0; 7];
    q[0] = 0.05;
    let high = chain.fk(&q).unwrap();
    assert!((high.translation - low.translation - Vec3::new(0.0, 0.0, 0.05)).length() < 1e-12);
}

fn solver(side: ArmSide) -> Golem3Ik {
    Golem3Ik::new(&golem(), side, Golem3Params::default()).unwrap()
}

#[test]
fn analytic_solves_every_fk_target_and_finds_the_generating_branch() {
    for side in [ArmSide::Right, ArmSide::Left] {
        let ik = solver(side);
        let chain = ik.chain().clone();
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        let seed = chain.mid_configuration();
        for _ in 0..3000 {
            let q = random_q(&chain, &mut rng);
            let target = chain.fk(&q).unwrap();
            let sols = ik
                .solve(&target, IkMode::Full, &seed)
                .unwrap_or_else(|e| panic!("{side:?} {q:?}: {e}"));
            assert!(sols.len() <= 8);
            for s in &sols {
                let reached = chain.fk(&s.joints).unwrap();
                assert!((reached.translation - target.translation).length() < 1e-6);
                assert!(
                    tabula_geom::rotation_angle_between(reached.rotation, target.rotation) < 1e-6
                );
                assert!(chain.within_limits(&s.joints, 1e-9));
            }
            let nearest_to_truth = sols
                .iter()
                .map(|s| {
                    s.joints
                        .iter()
                        .zip(&q)
                        .map(|(a, b)| (a - b).abs())
                        .fold(0.0, f64::max)
                })
                .fold(f64::INFINITY, f64::min);
            assert!(
                nearest_to_truth < 1e-6,
                "{side:?}: the generating configuration {q:?} is not among {sols:?}"
            );
        }
    }
}

#[test]
fn analytic_solutions_are_sorted_by_distance_to_the_seed() {
    let ik = solver(ArmSide::Right);
    let chain = ik.chain().clone();
    let q = [0.2, 0.4, -0.3, 0.5, 0.4, 0.1];
    let target = chain.fk(&q).unwrap();
    let sols = ik.solve(&target, IkMode::Full, &q).unwrap();
    assert!(sols.len() >= 2, "this pose has several branches");
    let d = |s: &[f64]| s.iter().zip(&q).map(|(a, b)| (a - b).powi(2)).sum::<f64>();
    assert!(d(&sols[0].joints) < 1e-12);
    for w in sols.windows(2) {
        assert!(d(&w[0].joints) <= d(&w[1].joints));
    }
}

#[test]
fn singular_targets_keep_their_solutions() {
    let ik = solver(ArmSide::Right);
    let chain = ik.chain().clone();
    // Stretched elbow (θ2 = 0), tool pointing straight down (θ4+θ5 = π/2), θ4+ρ = 0.
    let rho = 13.43f64.to_radians();
    for q in [
        [0.3, 0.0, 0.2, 0.1, 0.4, 0.2],
        [0.1, 0.5, 0.3, 0.2, std::f64::consts::FRAC_PI_2 - 0.2, -0.4],
        [0.0, 0.0, 0.0, -rho, 0.3, 0.0],
        [-0.5, 0.0, 1.0, 0.4, std::f64::consts::FRAC_PI_2 - 0.4, 1.2],
        [0.2, 0.0, -0.3, -rho, 1.0, -1.0],
    ] {
        let target = chain.fk(&q).unwrap();
        let sols = ik
            .solve(&target, IkMode::Full, &q)
            .unwrap_or_else(|e| panic!("{q:?}: {e}"));
        let best = &sols[0];
        assert!(
            best.position_error < 1e-6 && best.rotation_error < 1e-6,
            "{q:?}"
        );
    }
}

#[test]
fn analytic_no_solution_and_bad_input() {
    let ik = solver(ArmSide::Right);
    let seed = vec![0.0; 6];
    let far = Pose::from_translation(Vec3::new(3.0, 0.0, 1.0));
    assert_eq!(
        ik.solve(&far, IkMode::Full, &seed),
        Err(IkError::NoSolution)
    );
    let nan = Pose::from_translation(Vec3::new(f64::NAN, 0.0, 1.0));
    assert_eq!(
        ik.solve(&nan, IkMode::Full, &seed),
        Err(IkError::NonFiniteTarget)
    );
    let ok = ik.chain().fk(&seed).unwrap();
    assert!(matches!(
        ik.solve(&ok, IkMode::Full, &[0.0; 3]),
        Err(IkError::WrongSeedLength { .. })
    ));
    assert_eq!(
        ik.solve(&ok, IkMode::Full, &[f64::INFINITY; 6]),
        Err(IkError::NonFiniteSeed)
    );
}

#[test]
fn position_only_reaches_random_positions() {
    for side in [ArmSide::Right, ArmSide::Left] {
        let ik = solver(side);
        let chain = ik.chain().clone();
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        let seed = chain.mid_configuration();
        for _ in 0..1000 {
            let q = random_q(&chain, &mut rng);
            let target = chain.fk(&q).unwrap();
            let sols = ik
                .solve(&target, IkMode::PositionOnly, &seed)
                .unwrap_or_else(|e| panic!("{side:?} {q:?}: {e}"));
            let reached = chain.fk(&sols[0].joints).unwrap();
            assert!((reached.translation - target.translation).length() < 1e-6);
            assert!(chain.within_limits(&sols[0].joints, 1e-9));
        }
    }
}

#[test]
fn golem_solver_refuses_other_robots() {
    let wam = RobotModel::from_urdf_str(robots::WAM_URDF, None).unwrap();
    assert!(Golem3Ik::new(&wam, ArmSide::Right, Golem3Params::default()).is_err());
}
