//! `tabula pick-place` as a user runs it: the can moved and the world saved, a dry run,
//! the other hand full.

use super::cli::{tabula, tabula_json};

/// Seed 001's integral test in scenes/golem_shelves.toml: the can on the right shelf
/// goes to the table.
const CAN_TO_TABLE: [&str; 8] = [
    "--pick", "0.556", "-0.663", "1.07", "--place", "0.82", "-0.2", "1.01",
];

/// Seed 001's integral test from the command line: the can goes from the right shelf
/// to the table, judged by physics; the final world is saved and loads again.
#[test]
fn pick_place_moves_the_can_and_saves_the_world() {
    let dir = std::env::temp_dir().join(format!("tabula-pp-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let saved = dir.join("after.toml");
    let scene = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../scenes/golem_shelves.toml"
    );
    let out = tabula(
        &[
            &["pick-place", "--scene", scene, "--arm", "auto"][..],
            &CAN_TO_TABLE,
            &["--json", "--save-scene", saved.to_str().unwrap()],
        ]
        .concat(),
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON");
    assert_eq!(v["success"], true, "{v}");
    assert!(out.status.success());
    assert!(v["phases"].as_array().is_some_and(|p| p.len() >= 10));
    let fp = v["final_pose"].as_array().unwrap();
    assert!((fp[0].as_f64().unwrap() - 0.82).abs() < 0.02);
    // The saved scene loads (from anywhere) and the can rests where it was put.
    let settled = tabula_json(&[
        "sim",
        "settle",
        "--scene",
        saved.to_str().unwrap(),
        "--json",
    ]);
    let text = settled.to_string();
    assert!(text.contains("can_a"), "{text}");
    // An object nobody can reach is a typed failure, not a crash.
    let out = tabula(&[
        "pick-place",
        "--scene",
        scene,
        "--pick",
        "3.0",
        "3.0",
        "1.0",
        "--place",
        "0.82",
        "-0.2",
        "1.01",
        "--json",
    ]);
    assert_eq!(out.status.code(), Some(2));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON");
    assert_eq!(v["success"], false);
    assert!(v["error"].is_string(), "{v}");
    std::fs::remove_dir_all(&dir).ok();
}

/// Seed 001's pick and place tried dry (joints set along the trajectories, no physics):
/// the same phases run, the can rides in the gripper to the target, the other object
/// and the shelves are untouched, and the output says it was dry.
#[test]
fn pick_place_runs_dry() {
    let scene = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../scenes/golem_shelves.toml"
    );
    let v = tabula_json(
        &[
            &["pick-place", "--scene", scene][..],
            &CAN_TO_TABLE,
            &["--dry-run", "--json"],
        ]
        .concat(),
    );
    assert_eq!(v["dry_run"], true, "{v}");
    assert_eq!(v["success"], true, "{v}");
    let phases: Vec<&str> = v["phases"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p["name"].as_str().unwrap())
        .collect();
    for phase in [
        "move to pre-grasp",
        "grasp",
        "transfer",
        "release",
        "return",
    ] {
        assert!(phases.contains(&phase), "{phases:?}");
    }
    let fp = v["final_pose"].as_array().unwrap();
    assert!((fp[0].as_f64().unwrap() - 0.82).abs() < 0.02, "{fp:?}");
    assert!((fp[1].as_f64().unwrap() + 0.2).abs() < 0.02, "{fp:?}");
    assert_eq!(v["verdict"]["disturbed"], serde_json::json!([]), "{v}");
    // Clearing needs pushes to move things: refused, not faked.
    let out = tabula(&[
        "clear",
        "--scene",
        concat!(env!("CARGO_MANIFEST_DIR"), "/../../scenes/clutter.toml"),
        "--dry-run",
    ]);
    assert_eq!(out.status.code(), Some(1));
}

/// Golem-III holding a bar in its left hand picks the can with its right: the left
/// hand keeps its bar (it is neither opened nor used), planning carries the bar with
/// the shared torso joint, and asking the full hand to pick is a typed refusal.
#[test]
fn pick_place_with_the_other_hand_full() {
    let dir = std::env::temp_dir().join(format!("tabula-full-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let shelves = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../scenes/golem_shelves.toml"
    ))
    .unwrap();
    let holding = shelves
        .replacen(
            "[[robot]]",
            "[[object]]\nname = \"bar\"\nshape = { box = [0.12, 0.04, 0.04] }\npose = { xyz = [0.0, 0.0, 3.0] }\nmass = 0.1\n\n[[robot]]",
            1,
        )
        .replacen(
            "left_arm_joint4 = 0.3 }",
            "left_arm_joint4 = 0.3 }\nhold = { object = \"bar\", tool_link = \"left_tool_link\", finger_joint = \"left_gripper_l_finger_joint\", fingers = [\"left_gripper_l_finger_link\", \"left_gripper_r_finger_link\"], palm = \"left_gripper_palm_link\", tool_from_object = { xyz = [0.03, 0.0, 0.0] } }",
            1,
        );
    assert_ne!(holding, shelves);
    let scene = dir.join("holding.toml");
    std::fs::write(&scene, holding).unwrap();
    let saved = dir.join("after.toml");
    let mut args = [
        &["pick-place", "--scene", scene.to_str().unwrap()][..],
        &CAN_TO_TABLE,
        &["--json"],
    ]
    .concat();
    let mut run = args.clone();
    run.extend(["--save-scene", saved.to_str().unwrap()]);
    let v = tabula_json(&run);
    assert_eq!(v["success"], true, "{v}");
    assert_eq!(v["arm"], "right");
    assert_eq!(v["held_elsewhere"], serde_json::json!(["left_gripper"]));
    let after = std::fs::read_to_string(&saved).unwrap();
    assert!(
        after.contains("[robot.hold]") && after.contains("object = \"bar\""),
        "{after}"
    );
    args.extend(["--arm", "left"]);
    let out = tabula(&args);
    assert_eq!(out.status.code(), Some(2));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON");
    assert_eq!(v["error"], "hand full", "{v}");
    std::fs::remove_dir_all(&dir).ok();
}
