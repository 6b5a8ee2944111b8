//! A parallel gripper read off an SRDF end effector and the URDF's finger geometry: the
//! widths, axes and grasp frame the tasks need, without a hand-written description.

use crate::common;

use tabula_geom::Vec3;
use tabula_robot::RobotModel;
use tabula_robot::description::{RobotDescription, attach_grippers};
use tabula_robot::srdf::Srdf;

/// A 3-DOF arm, a hand (a palm box 6 cm deep) and two 5 cm box fingers sliding apart
/// along y from 6 cm below the palm's origin, 0–4 cm each, the second mimicking the
/// first; `extra` is added inside `<robot>`; `finger_kind` is the first finger's joint.
fn urdf(extra: &str, finger_kind: &str) -> String {
    let mut s = common::revolute_chain(3);
    let finger = |name: &str, side: f64| {
        format!(
            r#"<link name="{name}"><collision><origin xyz="0 {y} 0.025"/><geometry><box size="0.02 0.01 0.05"/></geometry></collision></link>"#,
            y = 0.005 * side
        )
    };
    s += r#"<link name="hand"><collision><origin xyz="0 0 0.03"/><geometry><box size="0.06 0.2 0.06"/></geometry></collision></link>
    <joint name="jh" type="fixed"><parent link="link3"/><child link="hand"/><origin xyz="0 0 0.1"/></joint>"#;
    s += &finger("left", 1.0);
    s += &finger("right", -1.0);
    s += &format!(
        r#"<joint name="f1" type="{finger_kind}"><parent link="hand"/><child link="left"/><origin xyz="0 0 0.06"/><axis xyz="0 1 0"/><limit lower="0" upper="0.04" effort="1" velocity="1"/></joint>
    <joint name="f2" type="prismatic"><parent link="hand"/><child link="right"/><origin xyz="0 0 0.06"/><axis xyz="0 -1 0"/><limit lower="0" upper="0.04" effort="1" velocity="1"/><mimic joint="f1"/></joint>"#
    );
    s + extra + "</robot>"
}

const SRDF: &str = r#"<robot name="arm">
  <group name="arm"><chain base_link="base" tip_link="link3"/></group>
  <group name="hand"><link name="hand"/><link name="left"/><link name="right"/></group>
  <end_effector name="hand" parent_link="link3" group="hand" parent_group="arm"/>
</robot>"#;

fn described(urdf: &str) -> (RobotModel, RobotDescription) {
    let mut model = RobotModel::from_urdf_str(urdf, None).unwrap();
    let srdf = Srdf::parse(SRDF, &model).unwrap();
    let mut description = RobotDescription {
        arms: srdf.arms(&model),
        ..RobotDescription::minimal(&model, "arm")
    };
    attach_grippers(&mut model, &srdf, &mut description);
    (model, description)
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() < 1e-9
}

#[test]
fn a_parallel_end_effector_becomes_the_arms_gripper_with_a_frame_between_the_pads() {
    let (model, d) = described(&urdf("", "prismatic"));
    let arm = &d.arms[0];
    let g = d.gripper_of(arm).expect("the hand is a parallel gripper");
    assert_eq!((g.palm.as_str(), g.finger_joint.as_str()), ("hand", "f1"));
    assert_eq!(g.fingers, ["left".to_string(), "right".to_string()]);
    // The pads' inner faces: touching at the lower limit, 2 × 4 cm apart at the upper.
    assert!(
        close(g.closed_width, 0.0) && close(g.open_width, 0.08),
        "{g:?}"
    );
    assert_eq!(g.approach(), Vec3::Z);
    assert_eq!(g.closing().abs(), Vec3::Y);
    // No frame between the pads in the URDF: one is added 2 cm in from the fingertips
    // (fingers 5 cm long: 40 % of them), and the arm's tip moves to it.
    assert_eq!(g.tool_link, "hand_tcp");
    assert_eq!(arm.tip, "hand_tcp");
    let tcp = model.link("hand_tcp").unwrap();
    let joint = &model.joints[model.links[tcp].parent_joint.unwrap()];
    assert_eq!(model.links[joint.parent].name, "hand");
    assert!((joint.parent_from_joint.translation - Vec3::new(0.0, 0.0, 0.09)).length() < 1e-9);
    assert_eq!(model.added_frames, [tcp]);
    // The chain to it is the arm's three joints.
    assert_eq!(arm.chain(&model).unwrap().dof(), 3);
}

#[test]
fn a_tool_frame_the_urdf_has_between_the_pads_is_used() {
    let tcp = r#"<link name="tcp"/><joint name="jt" type="fixed"><parent link="hand"/><child link="tcp"/><origin xyz="0 0 0.1"/></joint>
    <link name="camera"/><joint name="jc" type="fixed"><parent link="hand"/><child link="camera"/><origin xyz="0.05 0 0.09"/></joint>"#;
    let (model, d) = described(&urdf(tcp, "prismatic"));
    let g = d.gripper_of(&d.arms[0]).unwrap();
    assert_eq!(g.tool_link, "tcp");
    assert!(model.added_frames.is_empty());
}

#[test]
fn an_end_effector_that_is_not_a_parallel_gripper_leaves_the_arm_without_one() {
    // A revolute finger (a linkage gripper) is not measured: no guess.
    let (model, d) = described(&urdf("", "revolute"));
    assert!(d.arms[0].gripper.is_none() && d.grippers.is_empty());
    assert_eq!(d.arms[0].tip, "link3");
    assert!(model.added_frames.is_empty());
}
