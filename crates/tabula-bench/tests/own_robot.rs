//! A robot brought with its MoveIt package clears a table: MoveIt's tutorial Panda
//! (`data/robots/panda_moveit`: the published URDF and SRDF, nothing written for it),
//! its gripper read off the SRDF's end effector, placed in the clearing cell by its reach.

use tabula_bench::clear::trial_with;
use tabula_bench::mount::clearing_mount;
use tabula_robot::robots::{LoadOptions, load_with};
use tabula_sim::generate::ClearSuite;
use tabula_tasks::clear::ClearParams;

fn data(path: &str) -> String {
    format!(
        "{}/../../data/robots/panda_moveit/{path}",
        env!("CARGO_MANIFEST_DIR")
    )
}

#[test]
fn moveits_panda_clears_a_generated_table_with_the_hand_its_srdf_names() {
    let urdf = data("moveit_resources_panda_description/urdf/panda.urdf");
    let srdf = data("panda.srdf");
    let options = LoadOptions {
        srdf: Some(srdf.clone().into()),
        ..Default::default()
    };
    let robot = load_with(&urdf, &options).unwrap();
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

    let mount = clearing_mount(&robot, &urdf, Some(&srdf), &[]).unwrap();
    // Its shoulder must be above the table top to reach down onto the far side.
    assert!(mount.xyz[2] > 0.5 && mount.xyz[2] < 0.9, "{mount:?}");
    // Six objects, two touching (the suite's scene 2).
    let trial = trial_with(ClearSuite::Random, 2, &ClearParams::default(), Some(&mount)).unwrap();
    let row = &trial.row;
    assert_eq!(row.objects, 6);
    assert!(
        row.success,
        "{} of {}: {}",
        row.in_bin, row.objects, row.stop
    );
    assert_eq!(row.off_table, 0);
}
