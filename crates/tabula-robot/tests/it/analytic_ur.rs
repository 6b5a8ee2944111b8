//! The closed-form solver for UR-type arms (axes 2–4 parallel, 5 and 6 meeting) on the
//! UR5e as Universal_Robots_ROS2_Description publishes it (joint origins copied from its
//! expansion with `ur_type:=ur5e`, including the rounded π/2 of its YAML), and on
//! randomised arms of the same family.

use crate::common;

use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use tabula_robot::ik::{IkError, IkMode, IkSolver, ThreeParallelIk};
use tabula_robot::{Chain, RobotModel};

fn joint(name: &str, parent: &str, child: &str, xyz: &str, rpy: &str) -> String {
    format!(
        r#"<link name="{child}"/><joint name="{name}" type="revolute"><parent link="{parent}"/><child link="{child}"/><origin xyz="{xyz}" rpy="{rpy}"/><axis xyz="0 0 1"/><limit lower="-6.283185307179586" upper="6.283185307179586" effort="1" velocity="1"/></joint>"#
    )
}

fn ur5e() -> RobotModel {
    let mut s = String::from(
        r#"<robot name="ur5e"><link name="base_link"/><link name="base_link_inertia"/><joint name="bi" type="fixed"><parent link="base_link"/><child link="base_link_inertia"/><origin rpy="0 0 3.141592653589793"/></joint>"#,
    );
    s += &joint(
        "shoulder_pan_joint",
        "base_link_inertia",
        "shoulder_link",
        "0 0 0.1625",
        "0 0 0",
    );
    s += &joint(
        "shoulder_lift_joint",
        "shoulder_link",
        "upper_arm_link",
        "0 0 0",
        "1.570796327 0 0",
    );
    s += &joint(
        "elbow_joint",
        "upper_arm_link",
        "forearm_link",
        "-0.425 0 0",
        "0 0 0",
    );
    s += &joint(
        "wrist_1_joint",
        "forearm_link",
        "wrist_1_link",
        "-0.3922 0 0.1333",
        "0 0 0",
    );
    s += &joint(
        "wrist_2_joint",
        "wrist_1_link",
        "wrist_2_link",
        "0 -0.0997 -2.044881182297852e-11",
        "1.570796327 0 0",
    );
    s += &joint(
        "wrist_3_joint",
        "wrist_2_link",
        "wrist_3_link",
        "0 0.0996 -2.042830148012698e-11",
        "1.570796326589793 3.141592653589793 3.141592653589793",
    );
    s += r#"<link name="flange"/><joint name="f" type="fixed"><parent link="wrist_3_link"/><child link="flange"/><origin rpy="0 -1.5707963267948966 -1.5707963267948966"/></joint>
<link name="tool0"/><joint name="t" type="fixed"><parent link="flange"/><child link="tool0"/><origin rpy="1.5707963267948966 0 1.5707963267948966"/></joint></robot>"#;
    RobotModel::from_urdf_str(&s, None).unwrap()
}

/// Round trips of random configurations from a zero seed ([`common::assert_round_trip`]).
fn check_round_trips(chain: &Chain, ik: &ThreeParallelIk, rng: &mut ChaCha8Rng, n: usize) {
    for _ in 0..n {
        let q: Vec<f64> = (0..6).map(|_| rng.random_range(-3.1..3.1)).collect();
        common::assert_round_trip(chain, ik, &q, &[0.0; 6]);
    }
}

#[test]
fn the_published_ur5e_is_solved_in_closed_form_with_every_branch() {
    let m = ur5e();
    let chain = Chain::new(&m, "base_link", "tool0").unwrap();
    let ik = ThreeParallelIk::new(&chain).expect("a UR5e is of the family");
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    check_round_trips(&chain, &ik, &mut rng, 2000);
    // Beyond reach: no solution, said so.
    let far = tabula_geom::Pose::from_translation(tabula_geom::Vec3::new(3.0, 0.0, 0.0));
    assert_eq!(
        ik.solve(&far, IkMode::Full, &[0.0; 6]).unwrap_err(),
        IkError::NoSolution
    );
    // Other modes are the numeric solver's.
    assert!(ik.solve(&far, IkMode::PositionOnly, &[0.0; 6]).is_err());
}

#[test]
fn arms_of_the_family_with_other_offsets_are_solved_and_others_are_not_claimed() {
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    for _ in 0..20 {
        let mut r = |lo: f64, hi: f64| rng.random_range(lo..hi);
        let (d1, a2, a3, d4, d5, d6) = (
            r(0.05, 0.3),
            r(0.1, 0.7),
            r(0.1, 0.6),
            r(0.0, 0.2),
            r(0.05, 0.15),
            r(0.0, 0.15),
        );
        let mut s = String::from(r#"<robot name="arm"><link name="base"/>"#);
        s += &joint("j1", "base", "l1", &format!("0 0 {d1}"), "0 0 0");
        s += &joint("j2", "l1", "l2", "0 0 0", "1.5707963267948966 0 0");
        s += &joint("j3", "l2", "l3", &format!("{a2} 0 0"), "0 0 0");
        s += &joint("j4", "l3", "l4", &format!("{a3} 0 {d4}"), "0 0 0");
        s += &joint(
            "j5",
            "l4",
            "l5",
            &format!("0 {d5} 0"),
            "-1.5707963267948966 0 0",
        );
        s += &joint(
            "j6",
            "l5",
            "l6",
            &format!("0 {d6} 0"),
            "1.5707963267948966 0 0",
        );
        s += "</robot>";
        let m = RobotModel::from_urdf_str(&s, None).unwrap();
        let chain = Chain::new(&m, "base", "l6").unwrap();
        let ik = ThreeParallelIk::new(&chain).expect("of the family");
        check_round_trips(&chain, &ik, &mut rng, 50);
    }
    // The WAM (7 joints) and a 6R arm whose wrist axes 5 and 6 do not meet are not.
    let wam = tabula_robot::robots::load("wam").unwrap();
    let chain = Chain::new(&wam.model, "base_link", "wam_tool").unwrap();
    assert!(ThreeParallelIk::new(&chain).is_none());
    let mut s = String::from(r#"<robot name="arm"><link name="base"/>"#);
    for (k, (xyz, rpy)) in [
        ("0 0 0.1", "0 0 0"),
        ("0 0 0", "1.5707963267948966 0 0"),
        ("0.4 0 0", "0 0 0"),
        ("0.4 0 0.1", "0 0 0"),
        ("0 0.1 0", "-1.5707963267948966 0 0"),
        ("0.05 0.1 0", "1.5707963267948966 0 0"),
    ]
    .iter()
    .enumerate()
    {
        s += &joint(
            &format!("j{k}"),
            if k == 0 { "base" } else { "x" },
            "x",
            xyz,
            rpy,
        )
        .replace(r#"<link name="x"/>"#, &format!(r#"<link name="l{k}"/>"#))
        .replace(r#"child link="x""#, &format!(r#"child link="l{k}""#))
        .replace(
            r#"parent link="x""#,
            &format!(r#"parent link="l{}""#, k.saturating_sub(1)),
        );
    }
    s += "</robot>";
    let m = RobotModel::from_urdf_str(&s, None).unwrap();
    let chain = Chain::new(&m, "base", "l5").unwrap();
    assert!(
        ThreeParallelIk::new(&chain).is_none(),
        "skew wrist axes are not of the family"
    );
}
