//! The simulator behind the driver traits, and the joins that used to be wrong: a base
//! driven in world coordinates when the robot is not at the origin, cameras that follow
//! their link, a head that moves under its limits, timed trajectories kept as timed,
//! deleted objects, grips held at an angle.

use tabula_geom::{Pose, Quat, Vec3};
use tabula_robot::driver::{
    Arms, BaseControl, Cameras, Grippers, HeadControl, JointStates, JointTrajectory,
};
use tabula_sim::{PhysicsParams, Scene, SimDriver, SimWorld};

const PR2_AWAY: &str = r#"
[floor]
[[object]]
name = "cup"
shape = { box = [0.05, 0.05, 0.08] }
pose = { xyz = [3.0, 3.0, 0.04] }
mass = 0.1
[[robot]]
name = "pr2"
urdf = "pr2"
pose = { xyz = [1.0, 2.0, 0.0], rpy = [0.0, 0.0, 1.5707963267948966] }
[[camera]]
name = "head"
robot = "pr2"
link = "head_camera_optical_frame"
"#;

fn world(text: &str) -> SimWorld {
    SimWorld::from_scene(
        &Scene::parse(text, "t.toml").unwrap(),
        PhysicsParams::default(),
    )
    .unwrap()
}

#[test]
fn the_base_drives_to_world_coordinates_from_anywhere() {
    let mut d = SimDriver::new(world(PR2_AWAY), "pr2", 0).unwrap();
    d.drive_to(1.5, 2.5, 0.3).unwrap();
    let base = d.world.link_pose("pr2", "base_footprint").unwrap();
    assert!(
        (base.translation - Vec3::new(1.5, 2.5, 0.0)).length() < 1e-6,
        "base at {}",
        base.translation
    );
    let forward = base.rotation * Vec3::X;
    assert!((forward.y.atan2(forward.x) - 0.3).abs() < 1e-6);
}

#[test]
fn a_mounted_camera_follows_its_link_and_the_head_moves_under_its_limits() {
    let mut d = SimDriver::new(world(PR2_AWAY), "pr2", 0).unwrap();
    let before = d.capture("head").unwrap();
    let start = d.joint_state().unwrap();
    let target = Vec3::new(1.5, 3.5, 0.5);
    let left = d.look_at(target).unwrap();
    assert!(left < 1e-3, "axis {left} rad off");
    let after = d.capture("head").unwrap();
    let link = d
        .world
        .link_pose("pr2", "head_camera_optical_frame")
        .unwrap();
    assert!((after.world_from_camera.translation - link.translation).length() < 1e-9);
    assert!(
        tabula_geom::rotation_angle_between(after.world_from_camera.rotation, link.rotation) < 1e-9
    );
    assert!(
        tabula_geom::rotation_angle_between(
            after.world_from_camera.rotation,
            before.world_from_camera.rotation
        ) > 0.1
    );
    // Turning took time at the joints' velocity limits instead of a jump.
    let state = d.joint_state().unwrap();
    let change = |j: &str| (state.get(j).unwrap() - start.get(j).unwrap()).abs();
    // pr2.urdf: pan 6 rad/s, tilt 5 rad/s.
    let needed = (change("head_pan_joint") / 6.0).max(change("head_tilt_joint") / 5.0);
    assert!(needed > 0.05);
    let took = state.stamp - start.stamp;
    assert!(took >= needed - 1e-2, "{took} s for {needed} s");
}

#[test]
fn a_timed_trajectory_keeps_its_timing() {
    let mut d = SimDriver::new(world(PR2_AWAY), "pr2", 0).unwrap();
    let t0 = d.joint_state().unwrap().stamp;
    let q0 = d.joint_state().unwrap().get("r_elbow_flex_joint").unwrap();
    let traj = JointTrajectory {
        joint_names: vec!["r_elbow_flex_joint".into()],
        times: vec![0.0, 0.5, 2.0],
        positions: vec![vec![q0], vec![q0 - 0.1], vec![q0 - 0.2]],
    };
    d.execute(&traj).unwrap();
    let s = d.joint_state().unwrap();
    assert!((s.stamp - t0 - 2.0).abs() < 0.01, "{}", s.stamp - t0);
    assert!((s.get("r_elbow_flex_joint").unwrap() - (q0 - 0.2)).abs() < 1e-9);
    let backwards = JointTrajectory {
        times: vec![0.0, 1.0, 0.5],
        ..traj
    };
    assert!(d.execute(&backwards).is_err());
}

#[test]
fn a_robot_without_a_base_says_so() {
    let text = "[floor]\n[[robot]]\nname = \"wam\"\nurdf = \"wam\"\n";
    let mut d = SimDriver::new(world(text), "wam", 0).unwrap();
    assert!(d.drive_to(1.0, 0.0, 0.0).is_err());
    assert!(d.look_at(Vec3::X).is_err());
    assert!(d.open("no_such_gripper").is_err());
    d.open("gripper").unwrap();
    let g = d.close("gripper").unwrap();
    assert!(!g.holding && (g.width - 0.03).abs() < 1e-9, "{g:?}");
}

#[test]
fn deleted_objects_leave_no_holes() {
    let mut w = world(PR2_AWAY);
    w.delete("cup").unwrap();
    assert!(w.settle().all_asleep);
    assert!(w.object_poses().is_empty());
    assert!(w.delete("pr2/base_link").is_err());
    let cam = w.camera("head").unwrap();
    let frame = tabula_sim::camera::capture(&w, &cam, 1);
    assert_eq!(frame.cloud.points.len(), 640 * 480);
}

#[test]
fn an_object_held_at_an_angle_stays_so() {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../scenes/pr2_holding.toml"
    ))
    .unwrap()
    .replace(
        "palm = \"r_gripper_palm_link\" }",
        "palm = \"r_gripper_palm_link\", tool_from_object = { xyz = [0.01, 0.0, 0.0], rpy = [0.4, 0.0, 0.0] } }",
    );
    let w = world(&text);
    let tool = w.link_pose("pr2", "r_gripper_tool_frame").unwrap();
    let cup = w.pose("cup").unwrap();
    let tool_from_cup: Pose = tool.inverse() * cup;
    let expected = Quat::from_rotation_x(0.4);
    assert!(tabula_geom::rotation_angle_between(tool_from_cup.rotation, expected) < 1e-6);
    assert!((tool_from_cup.translation - Vec3::new(0.01, 0.0, 0.0)).length() < 1e-6);
    assert_eq!(w.held_objects("pr2"), vec!["cup".to_string()]);
}

/// A dry run moves the robot along its trajectories and keeps the clock, but nothing
/// falls or is pushed: a cup left in the air stays there, one in the arm's way stays
/// put while the arm passes through it, and settling takes no steps.
#[test]
fn a_dry_run_moves_the_robot_and_nothing_else() {
    let text = r#"
[floor]
[[object]]
name = "floating"
shape = { box = [0.05, 0.05, 0.08] }
pose = { xyz = [2.0, 2.0, 0.5] }
mass = 0.1
[[robot]]
name = "wam"
urdf = "wam"
"#;
    let mut w = world(text);
    w.kinematic_only = true;
    let lifted = w.pose("floating").unwrap();
    let mut d = SimDriver::new(w, "wam", 0).unwrap();
    let t0 = d.joint_state().unwrap().stamp;
    let traj = JointTrajectory {
        joint_names: vec!["wam_joint2".into(), "wam_joint4".into()],
        times: vec![0.0, 1.0],
        positions: vec![vec![0.0, 0.0], vec![0.8, 1.2]],
    };
    d.execute(&traj).unwrap();
    let s = d.joint_state().unwrap();
    assert!((s.get("wam_joint2").unwrap() - 0.8).abs() < 1e-9);
    assert!((s.stamp - t0 - 1.0).abs() < 0.01, "{}", s.stamp - t0);
    let tip = d.world.link_pose("wam", "wam_link7").unwrap();
    let fk = d.world.robot("wam").unwrap().model.clone();
    let values = s.model_values(&fk);
    let root_from_tip = fk.forward_kinematics(&values).unwrap()[fk.link("wam_link7").unwrap()];
    assert!((tip.translation - root_from_tip.translation).length() < 1e-9);
    let settled = d.world.settle();
    assert_eq!(settled.steps, 0);
    assert!((d.world.pose("floating").unwrap().translation - lifted.translation).length() < 1e-12);
    // The same cup where the arm sweeps: it stays; with physics it is knocked and falls.
    let in_the_way = |dry: bool| {
        let tip = d.world.link_pose("wam", "wam_link7").unwrap().translation;
        let text = text.replace(
            "[2.0, 2.0, 0.5]",
            &format!("[{}, {}, {}]", tip.x, tip.y, tip.z),
        );
        let mut w = world(&text);
        w.kinematic_only = dry;
        w.set_joints("wam", &[("wam_joint2", 0.0), ("wam_joint4", 0.0)])
            .unwrap();
        let start = w.pose("floating").unwrap().translation;
        let mut d = SimDriver::new(w, "wam", 0).unwrap();
        d.execute(&traj).unwrap();
        (d.world.pose("floating").unwrap().translation - start).length()
    };
    assert!(in_the_way(true) < 1e-12);
    assert!(in_the_way(false) > 0.02);
}
