//! Robots from xacro: the WAM written with properties, macros, an include, an argument
//! and math (`robots/xacro/wam.urdf.xacro`) is the built-in WAM — same joints, limits,
//! link geometry and forward kinematics; hostile xacro gets a clear error.

use rand::{RngExt, SeedableRng};
use tabula_robot::model::RobotModel;
use tabula_robot::robots;

const XACRO: &str = "../../robots/xacro/wam.urdf.xacro";

#[test]
fn the_xacro_wam_is_the_built_in_wam() {
    let x = RobotModel::from_urdf_file(XACRO).unwrap();
    let w = robots::load("wam").unwrap().model;
    assert_eq!(x.joints.len(), w.joints.len());
    assert_eq!(x.links.len(), w.links.len());
    for (a, b) in x.joints.iter().zip(&w.joints) {
        assert_eq!(a.name, b.name);
        assert_eq!(a.kind, b.kind, "{}", a.name);
        assert_eq!(a.mimic.is_some(), b.mimic.is_some(), "{}", a.name);
        assert!((a.axis - b.axis).length() < 1e-12, "{}", a.name);
        for (p, q) in [
            (a.limits.lower, b.limits.lower),
            (a.limits.upper, b.limits.upper),
            (a.limits.velocity, b.limits.velocity),
        ] {
            assert!(p == q || (p - q).abs() < 1e-12, "{}", a.name);
        }
    }
    for (a, b) in x.links.iter().zip(&w.links) {
        assert_eq!(a.name, b.name);
        assert_eq!(a.collision.len(), b.collision.len(), "{}", a.name);
        assert!((a.mass - b.mass).abs() < 1e-12, "{}", a.name);
        for (s, t) in a.collision.iter().zip(&b.collision) {
            assert_eq!(format!("{:.9?}", s), format!("{:.9?}", t), "{}", a.name);
        }
    }
    // Forward kinematics of every link at random configurations within the limits.
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(3);
    for _ in 0..200 {
        let q: Vec<f64> = w
            .joints
            .iter()
            .map(|j| {
                if j.limits.lower.is_finite() && j.limits.upper > j.limits.lower {
                    rng.random_range(j.limits.lower..j.limits.upper)
                } else {
                    0.0
                }
            })
            .collect();
        let (fx, fw) = (
            x.forward_kinematics(&q).unwrap(),
            w.forward_kinematics(&q).unwrap(),
        );
        for (a, b) in fx.iter().zip(&fw) {
            assert!((a.translation - b.translation).length() < 1e-12);
            assert!(a.rotation.dot(b.rotation).abs() > 1.0 - 1e-12);
        }
    }
    // As a robot path, with the chain of the built-in description.
    let r = robots::load(XACRO).unwrap();
    assert_eq!(r.model.joints.len(), 11);
}

#[test]
fn xacro_arguments_reach_the_description() {
    let text = tabula_robot::xacro::expand(
        std::path::Path::new(XACRO),
        &[("prefix".into(), "left_".into())],
    )
    .unwrap();
    let m = RobotModel::from_urdf_str(&text, None).unwrap();
    assert!(m.joint("left_joint4").is_some() && m.joint("wam_joint4").is_none());
    assert!(
        m.joints
            .iter()
            .any(|j| j.name == "left_gripper_right_finger_joint" && j.mimic.is_some())
    );
}

#[test]
fn hostile_xacro_gets_an_error() {
    let dir = std::env::temp_dir().join(format!("tabula-xacro-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let cases = [
        // A macro that calls itself.
        (
            "loop.xacro",
            r#"<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro"><xacro:macro name="m" params=""><xacro:m/></xacro:macro><xacro:m/></robot>"#,
        ),
        // An undefined property, a missing include, unclosed XML, a bad expression.
        (
            "undefined.xacro",
            r#"<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro"><link name="${nope}"/></robot>"#,
        ),
        (
            "include.xacro",
            r#"<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro"><xacro:include filename="missing.xacro"/></robot>"#,
        ),
        (
            "unclosed.xacro",
            r#"<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro"><link name="a">"#,
        ),
        (
            "expr.xacro",
            r#"<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro"><link name="${1 +* 2}"/></robot>"#,
        ),
    ];
    for (name, text) in cases {
        let path = dir.join(name);
        std::fs::write(&path, text).unwrap();
        let e = RobotModel::from_urdf_file(&path).expect_err(name);
        assert!(e.to_string().contains(name), "{name}: {e}");
    }
    std::fs::remove_dir_all(&dir).ok();
}
