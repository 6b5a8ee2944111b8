//! URDF pieces the robot tests share.

/// `<robot name="arm">` opened, a `base` link and `n` revolute joints `j1…jn` each 0.2 m
/// up from the last (axes alternating between z and a tilted y+z), ending at `link{n}`.
#[allow(dead_code)] // not every test file that shares this module builds chains
pub fn revolute_chain(n: usize) -> String {
    let mut s = String::from(r#"<robot name="arm"><link name="base"/>"#);
    let mut parent = "base".to_string();
    for k in 1..=n {
        s += &format!(
            r#"<link name="link{k}"/><joint name="j{k}" type="revolute"><parent link="{parent}"/><child link="link{k}"/><origin xyz="0 0 0.2"/><axis xyz="0 {y} 1"/><limit lower="-2" upper="2" effort="1" velocity="1"/></joint>"#,
            y = k % 2
        );
        parent = format!("link{k}");
    }
    s
}

/// A closed form's round trip: the FK pose of `q` is solved from `seed`, at most eight
/// answers, each reaching it (by the solver's check and by the chain's own FK) within the
/// limits, and `q` among them up to whole turns.
#[allow(dead_code)] // not every test file that shares this module solves IK
pub fn assert_round_trip(
    chain: &tabula_robot::Chain,
    ik: &dyn tabula_robot::ik::IkSolver,
    q: &[f64],
    seed: &[f64],
) {
    use tabula_robot::ik::{IkMode, pose_error};
    let target = chain.fk(q).unwrap();
    let sols = ik
        .solve(&target, IkMode::Full, seed)
        .unwrap_or_else(|e| panic!("{q:?}: {e}"));
    assert!(sols.len() <= 8);
    for s in &sols {
        assert!(s.position_error < 1e-9 && s.rotation_error < 1e-9, "{s:?}");
        let (p, r) = pose_error(&chain.fk(&s.joints).unwrap(), &target, IkMode::Full);
        assert!(p < 1e-9 && r < 1e-9, "by the chain's FK: {p} m, {r} rad");
        assert!(chain.within_limits(&s.joints, 1e-9));
    }
    let wrapped = |a: f64, b: f64| {
        (a - b + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU) - std::f64::consts::PI
    };
    assert!(
        sols.iter().any(|s| s
            .joints
            .iter()
            .zip(q)
            .all(|(a, b)| wrapped(*a, *b).abs() < 1e-6)),
        "{q:?} not among {sols:?}"
    );
}
