//! A robot brought with its MoveIt package clears a table and picks and places by
//! coordinates: MoveIt's tutorial Panda (`data/robots/panda_moveit`: the published URDF
//! and SRDF, nothing written for it) and a UR5e from Universal Robots' xacro package with
//! a gripper on its flange (`data/robots/ur5e_gripper`), each gripper read off the
//! SRDF's end effector, each robot placed in the clearing cell by its reach, on a
//! pedestal its planners know.

use tabula_bench::clear::trial_with;
use tabula_bench::mount::clearing_mount;
use tabula_robot::robots::{LoadOptions, NamedRobot, load_with};
use tabula_sim::generate::{ClearSuite, RobotMount};
use tabula_tasks::clear::ClearParams;

fn data(path: &str) -> String {
    format!("{}/../../data/robots/{path}", env!("CARGO_MANIFEST_DIR"))
}

/// The Panda loaded from its URDF and SRDF, and where it stands in the clearing cell.
fn panda() -> (NamedRobot, RobotMount) {
    robot_and_mount(
        "panda_moveit/moveit_resources_panda_description/urdf/panda.urdf",
        "panda_moveit/panda.srdf",
    )
}

/// The UR5e with its gripper, expanded from the xacro (`$(find ur_description)` found
/// beside it), and where it stands.
fn ur5e() -> (NamedRobot, RobotMount) {
    robot_and_mount(
        "ur5e_gripper/ur5e_gripper.urdf.xacro",
        "ur5e_gripper/ur5e_gripper.srdf",
    )
}

fn robot_and_mount(urdf: &str, srdf: &str) -> (NamedRobot, RobotMount) {
    let (urdf, srdf) = (data(urdf), data(srdf));
    let options = LoadOptions {
        srdf: Some(srdf.clone().into()),
        ..Default::default()
    };
    let robot = load_with(&urdf, &options).unwrap();
    let mount = clearing_mount(&robot, &urdf, Some(&srdf), &[]).unwrap();
    (robot, mount)
}

#[test]
fn moveits_panda_clears_a_generated_table_with_the_hand_its_srdf_names() {
    let (robot, mount) = panda();
    let arm = robot.description.arm("panda_arm").unwrap();
    let hand = robot
        .description
        .gripper_of(arm)
        .expect("the hand is a gripper");
    assert_eq!(hand.finger_joint, "panda_finger_joint1");
    // Franka's hand: fingers touching when closed, 8 cm apart open (the meshes' pads
    // give 7.97 cm).
    assert!(hand.closed_width < 1e-3, "{hand:?}");
    assert!((hand.open_width - 0.08).abs() < 2e-3, "{hand:?}");
    assert_eq!(arm.tip, hand.tool_link);

    // Its shoulder must be above the table top to reach down onto the far side.
    assert!(mount.xyz[2] > 0.5 && mount.xyz[2] < 0.9, "{mount:?}");
    clears_scene_two(&mount);
}

/// The random suite's scene 2 (six objects, two touching) cleared by `mount`'s robot,
/// nothing off the table.
fn clears_scene_two(mount: &RobotMount) {
    let trial = trial_with(ClearSuite::Random, 2, &ClearParams::default(), Some(mount)).unwrap();
    let row = &trial.row;
    assert_eq!(row.objects, 6);
    assert!(
        row.success,
        "{} of {}: {}",
        row.in_bin, row.objects, row.stop
    );
    assert_eq!(row.off_table, 0);
}

/// Tasks of the table family picked and placed by `mount`'s robot, each within 2 cm of
/// its target, judged by physics.
fn picks_and_places(mount: &RobotMount, tasks: &[u64]) {
    for &task in tasks {
        let row = tabula_bench::pick_place::table_trial(task, mount).unwrap();
        assert!(row.success, "task {task}: {:?}", row.error);
        assert!(row.target_error_cm < 2.0, "{}", row.target_error_cm);
    }
}

#[test]
fn moveits_panda_picks_an_object_off_the_table_and_places_it_by_coordinates() {
    let (_, mount) = panda();
    // Task 2 of the table family: a side grasp, the pick camera the scene's overhead one.
    picks_and_places(&mount, &[2]);
}

#[test]
fn the_panda_places_where_its_forearm_clears_the_table_and_lifts_beside_the_place_spot() {
    let (_, mount) = panda();
    // Task 10: the placement first planned put link 7 on the table under a level side
    // placement; task 19: the place spot 14 cm from the object, whose support slab
    // reached under the object as it was lifted.
    picks_and_places(&mount, &[10, 19]);
}

#[test]
fn a_ur5e_from_its_xacro_package_clears_a_generated_table_with_the_gripper_its_srdf_names() {
    let (robot, mount) = ur5e();
    let arm = robot.description.arm("ur_manipulator").unwrap();
    let gripper = robot.description.gripper_of(arm).expect("a gripper");
    assert_eq!(gripper.finger_joint, "gripper_finger_joint");
    // Two fingers, each 0–42.5 mm from the middle.
    assert!(gripper.closed_width < 1e-3, "{gripper:?}");
    assert!((gripper.open_width - 0.085).abs() < 1e-3, "{gripper:?}");
    clears_scene_two(&mount);
}

#[test]
fn a_ur5e_on_its_pedestal_picks_and_places_without_touching_it() {
    let (_, mount) = ur5e();
    // Task 2: stood 15 cm above the table, the arm reached down past the side of a
    // stand it did not know (three contacts); task 31: a side grasp tilted down pressed
    // the palm 6 mm into the box and tipped it into the table.
    picks_and_places(&mount, &[2, 31]);
}
