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
        &Default::default(),
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

/// A ROS-style workspace: two packages, the robot's top file finds the other with
/// `$(find)`, reads its joint limits with `xacro.load_yaml`, takes `$(arg)` in its root
/// tag, and names a mesh by `package://` — as UR's, Franka's and Kortex's do.
#[test]
fn ros_packages_args_and_yaml_resolve_like_ros() {
    let ws = std::env::temp_dir().join(format!("tabula-ws-{}", std::process::id()));
    let (arm, parts) = (ws.join("src/arm_description"), ws.join("src/parts-master"));
    for d in [arm.join("urdf"), parts.join("config"), parts.join("meshes")] {
        std::fs::create_dir_all(d).unwrap();
    }
    std::fs::write(
        arm.join("package.xml"),
        "<package><name>arm_description</name></package>",
    )
    .unwrap();
    std::fs::write(
        parts.join("package.xml"),
        "<package format=\"3\"><name>parts</name></package>",
    )
    .unwrap();
    std::fs::write(
        parts.join("config/limits.yaml"),
        "joint1:\n  lower: -1.5\n  upper: 2.5\n",
    )
    .unwrap();
    std::fs::write(parts.join("meshes/link.stl"), b"solid x\nendsolid x\n").unwrap();
    std::fs::write(
        parts.join("macro.xacro"),
        r#"<robot xmlns:xacro="http://www.ros.org/wiki/xacro"><xacro:macro name="arm" params="prefix">
  <xacro:property name="lim" value="${xacro.load_yaml('$(find parts)/config/limits.yaml')}"/>
  <link name="${prefix}base"/><link name="${prefix}link1"><collision><geometry><mesh filename="package://parts/meshes/link.stl"/></geometry></collision></link>
  <joint name="${prefix}joint1" type="revolute"><parent link="${prefix}base"/><child link="${prefix}link1"/><axis xyz="0 0 1"/>
    <limit lower="${lim['joint1']['lower']}" upper="${lim['joint1']['upper']}" effort="1" velocity="1"/></joint>
</xacro:macro></robot>"#,
    )
    .unwrap();
    let top = arm.join("urdf/arm.urdf.xacro");
    std::fs::write(
        &top,
        r#"<robot name="$(arg name)" xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:arg name="name" default="arm"/><xacro:arg name="prefix" default=""/>
  <xacro:include filename="$(find parts)/macro.xacro"/><xacro:arm prefix="$(arg prefix)"/></robot>"#,
    )
    .unwrap();
    let options = tabula_robot::robots::LoadOptions {
        xacro_args: vec![("name".into(), "ur".into()), ("prefix".into(), "r_".into())],
        ..Default::default()
    };
    let r = tabula_robot::robots::load_with(top.to_str().unwrap(), &options).unwrap();
    assert_eq!(r.model.name, "ur");
    let j = &r.model.joints[r.model.joint("r_joint1").unwrap()];
    assert_eq!((j.limits.lower, j.limits.upper), (-1.5, 2.5));
    assert!(
        r.model.unreadable_meshes.is_empty(),
        "{:?}",
        r.model.unreadable_meshes
    );
    r.model.require_meshes().unwrap();
    std::fs::remove_dir_all(&ws).ok();
}

#[test]
fn includes_of_devices_loops_and_bombs_are_refused_in_bounded_time() {
    let dir = std::env::temp_dir().join(format!("tabula-xacro-bad-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let head = r#"<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">"#;
    // Ten nested macros each calling the next ten times: 10^10 links.
    let mut bomb = String::from(head);
    for k in 0..10 {
        bomb += &format!(
            r#"<xacro:macro name="m{k}" params="p">{}</xacro:macro>"#,
            format!(r#"<xacro:m{} p="${{p}}x"/>"#, k + 1).repeat(10)
        );
    }
    bomb += r#"<xacro:macro name="m10" params="p"><link name="${p}"/></xacro:macro><xacro:m0 p="a"/></robot>"#;
    let cases = [
        (
            "zero.xacro",
            format!(r#"{head}<xacro:include filename="/dev/zero"/></robot>"#),
            "not a regular file",
        ),
        (
            "yaml.xacro",
            format!(
                r#"{head}<xacro:property name="y" value="${{xacro.load_yaml('/dev/urandom')}}"/></robot>"#
            ),
            "not a regular file",
        ),
        (
            "self.xacro",
            format!(r#"{head}<xacro:include filename="self.xacro"/><link name="a"/></robot>"#),
            "self.xacro",
        ),
        ("bomb.xacro", bomb, "xacro"),
    ];
    for (name, text, expect) in cases {
        let path = dir.join(name);
        std::fs::write(&path, text).unwrap();
        let start = std::time::Instant::now();
        let e = RobotModel::from_urdf_file(&path)
            .expect_err(name)
            .to_string();
        assert!(e.contains(expect), "{name}: {e}");
        assert!(start.elapsed().as_secs() < 25, "{name}");
    }
    std::fs::remove_dir_all(&dir).ok();
}
