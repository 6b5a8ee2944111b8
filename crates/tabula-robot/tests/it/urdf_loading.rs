//! Bad URDFs get one clear error each; mutated URDFs never panic.

use proptest::prelude::*;
use tabula_robot::{Chain, RobotError, RobotModel, robots};

const GOOD: &str = r#"<robot name="two">
  <link name="base"/><link name="upper"/><link name="tool"/>
  <joint name="shoulder" type="revolute"><parent link="base"/><child link="upper"/>
    <axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
  <joint name="elbow" type="revolute"><origin xyz="0.5 0 0"/><parent link="upper"/><child link="tool"/>
    <axis xyz="0 1 0"/><limit lower="-2" upper="2" effort="1" velocity="1"/></joint>
</robot>"#;

fn load(text: &str) -> Result<RobotModel, RobotError> {
    RobotModel::from_urdf_str(text, None)
}

#[test]
fn good_file_loads() {
    let m = load(GOOD).unwrap();
    assert_eq!(m.joints.len(), 2);
    let c = Chain::new(&m, "base", "tool").unwrap();
    assert_eq!(c.joint_names, ["shoulder", "elbow"]);
}

#[test]
fn every_bad_input_has_its_own_error() {
    type Expect = fn(&RobotError) -> bool;
    let cases: Vec<(String, Expect)> = vec![
        ("<robot name='x'><link name='a'".into(), |e| {
            matches!(e, RobotError::Parse { .. })
        }),
        ("not xml at all".into(), |e| {
            matches!(e, RobotError::Parse { .. })
        }),
        ("<robot name='x'></robot>".into(), |e| {
            matches!(e, RobotError::NoLinks | RobotError::Parse { .. })
        }),
        (
            GOOD.replace(
                r#"<link name="upper"/>"#,
                r#"<link name="upper"/><link name="upper"/>"#,
            ),
            |e| matches!(e, RobotError::DuplicateLink(_)),
        ),
        (
            GOOD.replace(r#"<child link="tool"/>"#, r#"<child link="nowhere"/>"#),
            |e| matches!(e, RobotError::JointMissingLink { .. }),
        ),
        (
            GOOD.replace(r#"lower="-2" upper="2""#, r#"lower="2" upper="-2""#),
            |e| matches!(e, RobotError::InvertedLimits { .. }),
        ),
        (
            GOOD.replace(r#"lower="-2" upper="2""#, r#"lower="nan" upper="2""#),
            |e| matches!(e, RobotError::NonFinite { .. } | RobotError::Parse { .. }),
        ),
        (
            GOOD.replace(r#"<axis xyz="0 1 0"/>"#, r#"<axis xyz="0 0 0"/>"#),
            |e| matches!(e, RobotError::ZeroAxis { .. }),
        ),
        (
            GOOD.replace(r#"<origin xyz="0.5 0 0"/>"#, r#"<origin xyz="inf 0 0"/>"#),
            |e| matches!(e, RobotError::NonFinite { .. } | RobotError::Parse { .. }),
        ),
        (
            GOOD.replace(r#"<child link="tool"/>"#, r#"<child link="upper"/>"#),
            |e| {
                matches!(
                    e,
                    RobotError::MultipleParents { .. } | RobotError::SelfLoop(_)
                )
            },
        ),
        (
            GOOD.replace(
                r#"<parent link="base"/><child link="upper"/>"#,
                r#"<parent link="tool"/><child link="upper"/>"#,
            ),
            |e| matches!(e, RobotError::Cycle(_)),
        ),
    ];
    for (text, is_expected) in cases {
        match load(&text) {
            Ok(_) => panic!("accepted a bad URDF:\n{text}"),
            Err(e) => {
                assert!(is_expected(&e), "unexpected error {e:?} for\n{text}");
                assert!(!e.to_string().is_empty());
            }
        }
    }
}

#[test]
fn revolute_without_limits_is_unbounded() {
    let text = GOOD.replace(
        r#"<limit lower="-1" upper="1" effort="1" velocity="1"/>"#,
        "",
    );
    let m = load(&text).unwrap();
    let c = Chain::new(&m, "base", "tool").unwrap();
    assert!(c.lower[0].is_infinite() && c.upper[0].is_infinite());
    assert!(c.velocity[0].is_infinite());
}

#[test]
fn missing_file_unknown_link_and_disconnected_chain() {
    let e = RobotModel::from_urdf_file("/definitely/not/here.urdf").unwrap_err();
    assert!(
        matches!(e, RobotError::Input(_)) && e.to_string().contains("/definitely/not/here.urdf")
    );
    let m = load(GOOD).unwrap();
    let e = Chain::new(&m, "base", "hand").unwrap_err();
    assert!(
        e.to_string().contains("`hand`") && e.to_string().contains("tool"),
        "{e}"
    );
    let two_trees = GOOD.replace("</robot>", r#"<link name="island"/></robot>"#);
    let m = load(&two_trees).unwrap();
    assert!(matches!(
        Chain::new(&m, "tool", "island"),
        Err(RobotError::Disconnected { .. })
    ));
    assert!(matches!(
        robots::load("r2d2"),
        Err(RobotError::UnknownRobot(_))
    ));
    let planar = GOOD.replace(
        r#"type="revolute"><parent link="base""#,
        r#"type="planar"><parent link="base""#,
    );
    let m = load(&planar).unwrap();
    assert!(matches!(
        Chain::new(&m, "base", "tool"),
        Err(RobotError::UnsupportedJoint { .. })
    ));
}

#[test]
fn package_paths_resolve_next_to_the_file() {
    let dir = std::env::temp_dir().join(format!("tabula-urdf-{}", std::process::id()));
    std::fs::create_dir_all(dir.join("my_robot/meshes")).unwrap();
    std::fs::write(
        dir.join("my_robot/meshes/arm.stl"),
        b"solid x\nendsolid x\n",
    )
    .unwrap();
    let urdf = GOOD.replace(
        r#"<link name="upper"/>"#,
        r#"<link name="upper"><collision><geometry><mesh filename="package://my_robot/meshes/arm.stl"/></geometry></collision></link>"#,
    );
    let file = dir.join("my_robot/robot.urdf");
    std::fs::write(&file, urdf).unwrap();
    let m = RobotModel::from_urdf_file(&file).unwrap();
    let upper = &m.links[m.link("upper").unwrap()];
    match &upper.collision[0].geometry {
        tabula_robot::model::Geometry::Mesh { path, .. } => assert!(path.exists(), "{path:?}"),
        other => panic!("{other:?}"),
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn builtin_robots_load_with_their_chains() {
    for (name, dof) in [("golem3", 6), ("wam", 7), ("pr2", 7)] {
        let r = robots::load(name).unwrap();
        let c = Chain::new(&r.model, &r.default_base, &r.default_tip).unwrap();
        assert_eq!(c.dof(), dof, "{name}");
        assert!(c.velocity.iter().all(|v| v.is_finite() && *v > 0.0));
        for link in ["head_camera_optical_frame"] {
            if name != "wam" {
                r.model.link(link).unwrap();
            }
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 512, ..ProptestConfig::default() })]

    /// Byte-level mutations of real URDFs: an error or a model, never a panic.
    #[test]
    fn mutated_urdf_never_panics(
        which in 0usize..4,
        edits in proptest::collection::vec((any::<prop::sample::Index>(), 0u8..4, any::<u8>()), 1..8),
    ) {
        let source = [GOOD, robots::GOLEM3_URDF, robots::WAM_URDF, robots::PR2_URDF][which];
        let mut bytes = source.as_bytes().to_vec();
        for (at, op, byte) in edits {
            let i = at.index(bytes.len().max(1));
            match op {
                0 => { bytes.remove(i.min(bytes.len().saturating_sub(1))); }
                1 => bytes.insert(i, byte),
                2 => {
                    let last = bytes.len() - 1;
                    bytes[i.min(last)] = byte;
                }
                _ => bytes.truncate(i),
            }
            if bytes.is_empty() { break; }
        }
        let text = String::from_utf8_lossy(&bytes);
        if let Ok(m) = RobotModel::from_urdf_str(&text, None) {
            // Whatever loaded must be usable: chains and FK give answers or errors.
            let names: Vec<String> = m.links.iter().map(|l| l.name.clone()).collect();
            if let (Some(a), Some(b)) = (names.first(), names.last())
                && let Ok(c) = Chain::new(&m, a, b) {
                    let _ = c.fk(&c.mid_configuration());
                }
            let _ = m.forward_kinematics(&m.mid_configuration());
        }
    }

    /// Numbers in the attributes replaced by anything a float parser might meet.
    #[test]
    fn odd_numbers_never_panic(value in prop::sample::select(vec!["nan", "inf", "-inf", "1e400", "", "-", "0x10", "1 2", "1e-400"]), slot in 0usize..6) {
        let fields = [r#"lower="-2""#, r#"upper="2""#, r#"xyz="0.5 0 0""#, r#"axis xyz="0 1 0""#, r#"velocity="1""#, r#"effort="1""#];
        let key = fields[slot];
        let replacement = match key.split_once('=') { Some((k, _)) => format!("{k}=\"{value}\""), None => key.to_string() };
        let text = GOOD.replacen(key, &replacement, 1);
        let _ = RobotModel::from_urdf_str(&text, None);
    }
}

/// A chain that meets a mimic joint before its master (from one fingertip to the other)
/// moves both: the gap between parallel fingers is twice the master's travel.
#[test]
fn a_mimic_joint_before_its_master_on_a_chain_follows_it() {
    let urdf = r#"<robot name="g"><link name="hand"/>
      <link name="left"/><joint name="f1" type="prismatic"><parent link="hand"/><child link="left"/><axis xyz="0 1 0"/><limit lower="0" upper="0.04" effort="1" velocity="1"/></joint>
      <link name="right"/><joint name="f2" type="prismatic"><parent link="hand"/><child link="right"/><axis xyz="0 -1 0"/><limit lower="0" upper="0.04" effort="1" velocity="1"/><mimic joint="f1" multiplier="1" offset="0.001"/></joint>
      </robot>"#;
    let m = RobotModel::from_urdf_str(urdf, None).unwrap();
    for (base, tip) in [("right", "left"), ("left", "right")] {
        let c = Chain::new(&m, base, tip).unwrap();
        assert_eq!(c.joint_names, ["f1"], "{base} → {tip}");
        for v in [0.0, 0.01, 0.04] {
            let gap = c.fk(&[v]).unwrap().translation.length();
            assert!(
                (gap - (2.0 * v + 0.001)).abs() < 1e-12,
                "{base} → {tip} at {v}: {gap}"
            );
        }
    }
}

/// MotionBenchMaker's Panda fixes its fingers and keeps their `<mimic>`: ignored with a
/// note, not refused.
#[test]
fn a_mimic_on_a_fixed_joint_is_ignored_with_a_note() {
    let urdf = r#"<robot name="g"><link name="hand"/>
      <link name="left"/><joint name="f1" type="fixed"><parent link="hand"/><child link="left"/></joint>
      <link name="right"/><joint name="f2" type="fixed"><parent link="hand"/><child link="right"/><mimic joint="f1"/></joint>
      </robot>"#;
    let m = RobotModel::from_urdf_str(urdf, None).unwrap();
    assert!(m.joints.iter().all(|j| j.mimic.is_none()));
    assert_eq!(m.ignored.len(), 1);
    assert!(
        m.ignored[0].contains("f2") && m.ignored[0].contains("fixed"),
        "{:?}",
        m.ignored
    );
}
