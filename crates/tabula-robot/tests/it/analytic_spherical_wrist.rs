//! The closed-form solver for 6R arms with a spherical wrist (axes 4–6 meeting) on
//! KUKA's KR 16-2 as ros-industrial's `kuka_experimental` publishes it (joint origins,
//! axes — two of them negative — and limits copied from its `kr16_2.urdf`), and on
//! randomised arms of both sub-families: axes 2 and 3 parallel, axes 1 and 2 meeting.

use crate::common;

use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use tabula_robot::ik::{IkError, IkMode, IkSolver, SphericalWristIk, ThreeParallelIk};
use tabula_robot::{Chain, RobotModel};

/// One revolute joint and its child link.
struct Joint<'a> {
    xyz: &'a str,
    rpy: &'a str,
    axis: &'a str,
    limit: f64,
}

fn arm(joints: &[Joint], tool_xyz: &str, tool_rpy: &str) -> RobotModel {
    let mut s = String::from(r#"<robot name="arm"><link name="l0"/>"#);
    for (i, j) in joints.iter().enumerate() {
        s += &format!(
            r#"<link name="l{c}"/><joint name="j{c}" type="revolute"><parent link="l{i}"/><child link="l{c}"/><origin xyz="{}" rpy="{}"/><axis xyz="{}"/><limit lower="-{l}" upper="{l}" effort="1" velocity="1"/></joint>"#,
            j.xyz,
            j.rpy,
            j.axis,
            c = i + 1,
            l = j.limit
        );
    }
    s += &format!(
        r#"<link name="tool"/><joint name="t" type="fixed"><parent link="l{}"/><child link="tool"/><origin xyz="{tool_xyz}" rpy="{tool_rpy}"/></joint></robot>"#,
        joints.len()
    );
    RobotModel::from_urdf_str(&s, None).unwrap()
}

fn kr16() -> RobotModel {
    let j = |xyz, axis, limit| Joint {
        xyz,
        rpy: "0 0 0",
        axis,
        limit,
    };
    // Limits symmetric here (the published a2, a3 are not): the round trips draw
    // configurations inside them.
    arm(
        &[
            j("0 0 0.675", "0 0 -1", 3.22885911619),
            j("0.26 0 0", "0 1 0", 2.70526034059),
            j("0.68 0 0", "0 1 0", 2.26892802759),
            j("0.67 0 -0.035", "-1 0 0", 6.10865238198),
            j("0 0 0", "0 1 0", 2.26892802759),
            j("0 0 0", "-1 0 0", 6.10865238198),
        ],
        "0.158 0 0",
        "0 1.57079632679 0",
    )
}

/// Round trips of random configurations within the limits from the mid-range seed
/// ([`common::assert_round_trip`]).
fn check_round_trips(chain: &Chain, ik: &SphericalWristIk, rng: &mut ChaCha8Rng, n: usize) {
    let seed = chain.mid_configuration();
    for _ in 0..n {
        common::assert_round_trip(chain, ik, &chain.random_configuration(rng), &seed);
    }
}

#[test]
fn kukas_kr16_is_solved_in_closed_form_with_every_branch() {
    let m = kr16();
    let chain = Chain::new(&m, "l0", "tool").unwrap();
    let ik = SphericalWristIk::new(&chain).expect("a KR 16 has a spherical wrist");
    assert!(ThreeParallelIk::new(&chain).is_none());
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    check_round_trips(&chain, &ik, &mut rng, 2000);
    let far = tabula_geom::Pose::from_translation(tabula_geom::Vec3::new(4.0, 0.0, 0.0));
    assert_eq!(
        ik.solve(&far, IkMode::Full, &[0.0; 6]).unwrap_err(),
        IkError::NoSolution
    );
    assert!(ik.solve(&far, IkMode::PositionOnly, &[0.0; 6]).is_err());
}

#[test]
fn arms_of_both_shoulders_with_other_offsets_are_solved() {
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let pi = std::f64::consts::PI;
    for n in 0..40 {
        let mut r = |lo: f64, hi: f64| rng.random_range(lo..hi);
        let (d1, a1, a2, a3, d4, tool) = (
            r(0.2, 0.7),
            r(-0.3, 0.3),
            r(0.3, 0.9),
            r(0.05, 0.3),
            r(0.3, 0.9),
            r(0.0, 0.25),
        );
        let rz = r(-pi, pi);
        let (xyz2, xyz3) = if n % 2 == 0 {
            // Axes 2 ∥ 3, a shoulder offset a1 (KUKA, ABB, FANUC).
            (format!("{a1} 0 0"), format!("{a2} 0 0"))
        } else {
            // Axes 1 ∩ 2, joint 3 off the shoulder (Stäubli-like).
            (String::from("0 0 0"), format!("0 {a3} {a2}"))
        };
        // Axis 3 tilted about x away from axis 2 on the intersecting shoulder.
        let rpy3 = if n % 2 == 0 {
            String::from("0 0 0")
        } else {
            format!("{rz} 0 0")
        };
        let xyz4 = format!("{d4} 0 {a3}");
        let xyz1 = format!("0 0 {d1}");
        let limit = std::f64::consts::TAU;
        let m = arm(
            &[
                Joint {
                    xyz: &xyz1,
                    rpy: "0 0 0",
                    axis: "0 0 1",
                    limit,
                },
                Joint {
                    xyz: &xyz2,
                    rpy: "0 0 0",
                    axis: "0 1 0",
                    limit,
                },
                Joint {
                    xyz: &xyz3,
                    rpy: &rpy3,
                    axis: "0 1 0",
                    limit,
                },
                Joint {
                    xyz: &xyz4,
                    rpy: "0 0 0",
                    axis: "1 0 0",
                    limit,
                },
                Joint {
                    xyz: "0 0 0",
                    rpy: "0 0 0",
                    axis: "0 1 0",
                    limit,
                },
                Joint {
                    xyz: "0 0 0",
                    rpy: "0 0 0",
                    axis: "1 0 0",
                    limit,
                },
            ],
            &format!("{tool} 0 0"),
            "0 1.5707963267948966 0",
        );
        let chain = Chain::new(&m, "l0", "tool").unwrap();
        let ik = SphericalWristIk::new(&chain).unwrap_or_else(|| panic!("arm {n} of the family"));
        check_round_trips(&chain, &ik, &mut rng, 50);
    }
}

#[test]
fn arms_without_a_spherical_wrist_are_not_claimed() {
    // The WAM has seven joints; the UR5e's wrist axes 4 and 6 do not meet.
    let wam = tabula_robot::robots::load("wam").unwrap();
    let chain = Chain::new(&wam.model, "base_link", "wam_tool").unwrap();
    assert!(SphericalWristIk::new(&chain).is_none());
    let j = |xyz, rpy| Joint {
        xyz,
        rpy,
        axis: "0 0 1",
        limit: 6.0,
    };
    let ur5e_like = arm(
        &[
            j("0 0 0.1625", "0 0 0"),
            j("0 0 0", "1.570796327 0 0"),
            j("-0.425 0 0", "0 0 0"),
            j("-0.3922 0 0.1333", "0 0 0"),
            j("0 -0.0997 0", "1.570796327 0 0"),
            j(
                "0 0.0996 0",
                "1.570796327 3.141592653589793 3.141592653589793",
            ),
        ],
        "0 0 0",
        "0 0 0",
    );
    let chain = Chain::new(&ur5e_like, "l0", "tool").unwrap();
    assert!(ThreeParallelIk::new(&chain).is_some());
    assert!(SphericalWristIk::new(&chain).is_none());
}
