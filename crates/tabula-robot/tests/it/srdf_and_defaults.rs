//! SRDF reading (srdfdom's schema, checked against the URDF as MoveIt does) and the
//! default arm of a URDF without any description.

use crate::common;

use tabula_robot::RobotModel;
use tabula_robot::description::RobotDescription;
use tabula_robot::srdf::Srdf;

/// A 4-DOF arm with a flange, a hand with two prismatic fingers (one mimics the other),
/// a tool frame, and a self-collision helper link, as franka_description builds them.
fn arm_urdf() -> String {
    let mut s = common::revolute_chain(4);
    s += r#"<link name="link4_sc"/><joint name="j4_sc" type="fixed"><parent link="link4"/><child link="link4_sc"/></joint>
    <link name="flange"/><joint name="jf" type="fixed"><parent link="link4"/><child link="flange"/><origin xyz="0 0 0.1"/></joint>
    <link name="hand"/><joint name="jh" type="fixed"><parent link="flange"/><child link="hand"/></joint>
    <link name="hand_tcp"/><joint name="jt" type="fixed"><parent link="hand"/><child link="hand_tcp"/><origin xyz="0 0 0.1"/></joint>
    <link name="left_pad"/><joint name="f1" type="prismatic"><parent link="hand"/><child link="left_pad"/><axis xyz="0 1 0"/><limit lower="0" upper="0.04" effort="1" velocity="1"/></joint>
    <link name="right_pad"/><joint name="f2" type="prismatic"><parent link="hand"/><child link="right_pad"/><axis xyz="0 -1 0"/><limit lower="0" upper="0.04" effort="1" velocity="1"/><mimic joint="f1"/></joint>
    </robot>"#;
    s
}

const SRDF: &str = r#"<?xml version="1.0"?>
<robot name="arm">
  <virtual_joint name="vj" type="fixed" parent_frame="world" child_link="base"/>
  <group name="manipulator"><chain base_link="base" tip_link="flange"/></group>
  <group name="by_joints"><joint name="j1"/><joint name="j2"/><joint name="j3"/></group>
  <group name="gripper"><link name="hand"/><link name="left_pad"/><link name="right_pad"/><joint name="f1"/></group>
  <group name="both"><group name="manipulator"/><group name="gripper"/></group>
  <group_state name="home" group="manipulator"><joint name="j1" value="0"/><joint name="j2" value="-0.5"/><joint name="j3" value="0"/><joint name="j4" value="1.2"/></group_state>
  <group_state name="tuck" group="manipulator"><joint name="j1" value="1"/></group_state>
  <end_effector name="hand" parent_link="hand_tcp" group="gripper" parent_group="manipulator"/>
  <passive_joint name="j4_sc"/>
  <disable_collisions link1="link1" link2="link3" reason="Never"/>
  <disable_collisions link1="link1" link2="gone_link" reason="Never"/>
  <disable_default_collisions link="left_pad"/>
  <enable_collisions link1="left_pad" link2="link1"/>
</robot>"#;

#[test]
fn srdf_groups_states_end_effectors_and_collisions_are_read() {
    let model = RobotModel::from_urdf_str(&arm_urdf(), None).unwrap();
    let srdf = Srdf::parse(SRDF, &model).unwrap();
    assert_eq!(srdf.groups.len(), 4);
    assert_eq!(srdf.virtual_joints[0].child_link, "base");
    assert_eq!(srdf.passive_joints, ["j4_sc"]);
    // The entry naming a link the URDF lacks is dropped with a warning, as MoveIt does.
    assert_eq!(srdf.disabled.len(), 1);
    assert!(
        srdf.warnings.iter().any(|w| w.contains("gone_link")),
        "{:?}",
        srdf.warnings
    );
    assert!(srdf.allows("link3", "link1") && !srdf.allows("link2", "link1"));
    assert!(srdf.allows("left_pad", "link3"), "disabled by default");
    assert!(!srdf.allows("left_pad", "link1"), "enabled explicitly");
    // Arms: chain groups and joint groups that line up, not the end effector's group
    // nor a composite; the end effector's parent link becomes the tip.
    let arms = srdf.arms(&model);
    let names: Vec<&str> = arms.iter().map(|a| a.name.as_str()).collect();
    assert_eq!(names, ["manipulator", "by_joints"]);
    assert_eq!(
        (arms[0].base.as_str(), arms[0].tip.as_str()),
        ("base", "hand_tcp")
    );
    assert_eq!(
        (arms[1].base.as_str(), arms[1].tip.as_str()),
        ("base", "link3")
    );
    assert_eq!(arms[0].named["home"]["j4"], 1.2);
    assert_eq!(arms[0].tucked["j1"], 1.0);
}

#[test]
fn srdf_groups_that_name_missing_parts_are_errors() {
    let model = RobotModel::from_urdf_str(&arm_urdf(), None).unwrap();
    for (bad, expect) in [
        (
            SRDF.replace(r#"tip_link="flange""#, r#"tip_link="nowhere""#),
            "nowhere",
        ),
        (
            SRDF.replace(r#"<joint name="j3"/>"#, r#"<joint name="j9"/>"#),
            "j9",
        ),
        (
            SRDF.replace(r#"<group name="gripper"/>"#, r#"<group name="nope"/>"#),
            "nope",
        ),
        (
            SRDF.replace(
                r#"group="manipulator"><joint name="j1" value="1"/>"#,
                r#"group="x"><joint name="j1" value="1"/>"#,
            ),
            "`x`",
        ),
        (SRDF.replace(r#"value="-0.5""#, r#"value="nan""#), "j2"),
        (
            SRDF.replace(
                "<robot name=\"arm\">",
                "<!DOCTYPE r [<!ENTITY a \"b\">]><robot name=\"arm\">",
            ),
            "SRDF",
        ),
        ("<robot><group></robot>".to_string(), "SRDF"),
        ("<srdf/>".to_string(), "<srdf>"),
    ] {
        let e = Srdf::parse(&bad, &model).expect_err(expect).to_string();
        assert!(e.contains(expect), "{expect}: {e}");
    }
}

#[test]
fn without_a_description_the_arm_ends_at_the_tool_not_a_finger_or_helper() {
    let model = RobotModel::from_urdf_str(&arm_urdf(), None).unwrap();
    let d = RobotDescription::minimal(&model, "arm");
    assert_eq!(
        (d.arms[0].base.as_str(), d.arms[0].tip.as_str()),
        ("base", "hand_tcp")
    );
    // Without the tool frame: the hand, never a pad.
    let no_tcp = arm_urdf().replace(
        r#"<link name="hand_tcp"/><joint name="jt" type="fixed"><parent link="hand"/><child link="hand_tcp"/><origin xyz="0 0 0.1"/></joint>"#,
        "",
    );
    let model = RobotModel::from_urdf_str(&no_tcp, None).unwrap();
    assert_eq!(model.links[model.default_tool()].name, "hand");
    // The built-in robots' URDFs alone end where their descriptions do.
    for (urdf, tool) in [
        (tabula_robot::robots::WAM_URDF, "wam_tool"),
        (tabula_robot::robots::PR2_URDF, "l_gripper_tool_frame"), // arms by name
    ] {
        let m = RobotModel::from_urdf_str(urdf, None).unwrap();
        assert_eq!(m.links[m.default_tool()].name, tool);
    }
}

#[test]
fn a_robot_file_with_an_srdf_beside_it_has_its_groups_as_arms() {
    let dir = std::env::temp_dir().join(format!("tabula-srdf-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("arm.urdf"), arm_urdf()).unwrap();
    std::fs::write(dir.join("arm.srdf"), SRDF).unwrap();
    let r = tabula_robot::robots::load(dir.join("arm.urdf").to_str().unwrap()).unwrap();
    assert_eq!(r.description.arms[0].name, "manipulator");
    assert_eq!(r.default_tip, "hand_tcp");
    assert!(r.srdf.as_ref().unwrap().has_collision_matrix());
    std::fs::remove_dir_all(&dir).ok();
}
