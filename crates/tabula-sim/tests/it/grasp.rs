//! The gripper holds what it closes on (issue 3's grasp scenario).

use crate::common;

use tabula_geom::Vec3;
use tabula_robot::Chain;
use tabula_robot::driver::JointTrajectory;
use tabula_sim::{PhysicsParams, Scene, SimWorld};

const SCENE: &str = r#"
[floor]
[[furniture]]
name = "table"
kind = "table"
pose = { xyz = [0.55, 0.0, 0.0] }
size = [0.5, 0.8, 0.4]

[[object]]
name = "box"
shape = { box = [0.05, 0.05, 0.05] }
pose = { xyz = [0.55, 0.0, 0.425] }
mass = 0.1

[[robot]]
name = "wam"
urdf = "wam"
"#;

/// Joint values putting the WAM's tool at `xyz` pointing down.
fn ik(chain: &Chain, xyz: Vec3, seed: &[f64]) -> Vec<f64> {
    common::tool_down(chain, xyz, seed)
}

/// `scene_text` loaded and settled with the WAM's fingers around the box at
/// (0.55, 0, 0.425), open.
fn settled_around_the_box(scene_text: &str) -> SimWorld {
    let scene = Scene::parse(scene_text, "grasp.toml").unwrap();
    let mut world = SimWorld::from_scene(&scene, PhysicsParams::default()).unwrap();
    let robot = tabula_robot::robots::load("wam").unwrap();
    let chain = Chain::new(&robot.model, "base_link", "wam_tool").unwrap();
    let grasp = ik(
        &chain,
        Vec3::new(0.55, 0.0, 0.425),
        &chain.mid_configuration(),
    );
    let q: Vec<(&str, f64)> = chain
        .joint_names
        .iter()
        .map(String::as_str)
        .zip(grasp.iter().copied())
        .collect();
    world.set_joints("wam", &q).unwrap();
    world.settle();
    world
}

#[test]
fn the_gripper_carries_a_box_and_lets_it_fall_on_the_table() {
    let scene = Scene::parse(SCENE, "grasp.toml").unwrap();
    let mut world = SimWorld::from_scene(&scene, PhysicsParams::default()).unwrap();
    let robot = tabula_robot::robots::load("wam").unwrap();
    let chain = Chain::new(&robot.model, "base_link", "wam_tool").unwrap();
    let names: Vec<&str> = chain.joint_names.iter().map(String::as_str).collect();
    let grasp = ik(
        &chain,
        Vec3::new(0.55, 0.0, 0.425),
        &chain.mid_configuration(),
    );
    let at = |q: &[f64]| {
        names
            .iter()
            .copied()
            .zip(q.iter().copied())
            .collect::<Vec<_>>()
    };
    world.set_joints("wam", &at(&grasp)).unwrap();
    world.settle();
    let before = world.pose("box").unwrap();

    let held = world
        .close_gripper(
            "wam",
            "wam_gripper_left_finger_joint",
            ["wam_gripper_left_finger", "wam_gripper_right_finger"],
            "wam_gripper_palm",
        )
        .unwrap();
    assert_eq!(held.as_deref(), Some("box"));
    let gap = world.joint("wam", "wam_gripper_left_finger_joint").unwrap();
    assert!(
        (gap - 0.025).abs() < 2e-3,
        "fingers stopped at the box faces, half gap {gap}"
    );

    // Up in two timed waypoints (15 cm after 1 s, 30 cm after 2 s).
    let half = ik(&chain, Vec3::new(0.55, 0.0, 0.575), &grasp);
    let lifted = ik(&chain, Vec3::new(0.55, 0.0, 0.725), &half);
    let lift = JointTrajectory {
        joint_names: chain.joint_names.clone(),
        times: vec![0.0, 1.0, 2.0],
        positions: vec![grasp.clone(), half, lifted.clone()],
    };
    let steps = world.follow_trajectory("wam", &lift).unwrap();
    // The trajectory's own timing is kept: 2 s at 120 Hz.
    assert_eq!(steps, 240);
    let malformed = JointTrajectory {
        joint_names: chain.joint_names.clone(),
        times: vec![0.0],
        positions: vec![vec![0.0]],
    };
    assert!(world.follow_trajectory("wam", &malformed).is_err());
    let up = world.pose("box").unwrap();
    assert!(
        (up.translation - before.translation - Vec3::new(0.0, 0.0, 0.3)).length() < 5e-3,
        "box at {:?}",
        up.translation
    );

    world
        .open_gripper("wam", "wam_gripper_left_finger_joint")
        .unwrap();
    assert!(world.settle().all_asleep);
    let rest = world.pose("box").unwrap();
    assert!(
        (rest.translation.z - 0.425).abs() < 5e-3,
        "box rests at z = {}",
        rest.translation.z
    );
    assert!((rest.translation.x - 0.55).abs() < 0.1 && rest.translation.y.abs() < 0.1);
}

/// A grip limited in force holds what friction can carry and no more: 2·μ·F ≥ m·g.
#[test]
fn a_gentle_grip_holds_light_objects_and_lets_heavy_ones_stay() {
    let robot = tabula_robot::robots::load("wam").unwrap();
    let chain = Chain::new(&robot.model, "base_link", "wam_tool").unwrap();
    let names: Vec<String> = chain.joint_names.clone();
    let grasp = ik(
        &chain,
        Vec3::new(0.55, 0.0, 0.425),
        &chain.mid_configuration(),
    );
    let held_with = |mass: f64, effort: Option<f64>| {
        let text = SCENE.replace("mass = 0.1", &format!("mass = {mass}"));
        let scene = Scene::parse(&text, "grasp.toml").unwrap();
        let mut world = SimWorld::from_scene(&scene, PhysicsParams::default()).unwrap();
        let at: Vec<(&str, f64)> = names
            .iter()
            .map(String::as_str)
            .zip(grasp.iter().copied())
            .collect();
        world.set_joints("wam", &at).unwrap();
        world.settle();
        world
            .close_gripper_with_effort(
                "wam",
                "wam_gripper_left_finger_joint",
                ["wam_gripper_left_finger", "wam_gripper_right_finger"],
                "wam_gripper_palm",
                effort,
            )
            .unwrap()
    };
    // 0.1 kg needs ~1 N of friction: 5 N per finger is plenty.
    assert_eq!(held_with(0.1, Some(5.0)).as_deref(), Some("box"));
    // 5 kg needs ~49 N: 5 N slips, and asking 500 N is capped at the joint's 20 N.
    assert_eq!(held_with(5.0, Some(5.0)), None);
    assert_eq!(held_with(5.0, Some(500.0)), None);
    // Without a limit the grip holds whatever both fingers touch.
    assert_eq!(held_with(5.0, None).as_deref(), Some("box"));
}

/// A gentle release: the fingers let go of the squeeze at once and then part at the
/// asked pace, taking that long; the box, held 8 mm above the table, drops straight
/// onto it instead of being flicked.
#[test]
fn a_slow_release_takes_its_time_and_sets_the_box_down_straight() {
    use tabula_robot::driver::{Grippers, JointStates};
    let robot = tabula_robot::robots::load("wam").unwrap();
    let chain = Chain::new(&robot.model, "base_link", "wam_tool").unwrap();
    let names: Vec<String> = chain.joint_names.clone();
    let at = |q: &[f64]| -> Vec<(String, f64)> {
        names.iter().cloned().zip(q.iter().copied()).collect()
    };
    let grasp = ik(
        &chain,
        Vec3::new(0.55, 0.0, 0.425),
        &chain.mid_configuration(),
    );
    let above = ik(&chain, Vec3::new(0.55, 0.0, 0.433), &grasp);
    let scene = Scene::parse(SCENE, "grasp.toml").unwrap();
    let mut world = SimWorld::from_scene(&scene, PhysicsParams::default()).unwrap();
    let q: Vec<(String, f64)> = at(&grasp);
    let q: Vec<(&str, f64)> = q.iter().map(|(n, v)| (n.as_str(), *v)).collect();
    world.set_joints("wam", &q).unwrap();
    world.settle();
    let mut d = tabula_sim::SimDriver::new(world, "wam", 0).unwrap();
    let grip = d.close("gripper").unwrap();
    assert!(grip.holding);
    assert!(d.grip_state("gripper").unwrap().holding);
    let up: Vec<(String, f64)> = at(&above);
    let up: Vec<(&str, f64)> = up.iter().map(|(n, v)| (n.as_str(), *v)).collect();
    d.world.move_joints("wam", &up).unwrap();
    let before = d.world.pose("box").unwrap();
    assert!(
        before.translation.z > 0.43,
        "lifted: {}",
        before.translation.z
    );
    let t0 = d.joint_state().unwrap().stamp;
    let speed = 0.02;
    d.open_slowly("gripper", speed).unwrap();
    let took = d.joint_state().unwrap().stamp - t0;
    let state = d.grip_state("gripper").unwrap();
    assert!(!state.holding);
    let widened = state.width - grip.width;
    assert!(
        took >= 0.8 * widened / speed && took <= widened / speed + 0.05,
        "{took} s to widen {widened} m"
    );
    d.world.settle();
    let after = d.world.pose("box").unwrap();
    let slid = (after.translation - before.translation).truncate().length();
    assert!(slid < 0.005, "slid {slid} m");
    assert!(
        (after.translation.z - 0.425).abs() < 0.003,
        "{}",
        after.translation.z
    );
    assert!(d.open_slowly("gripper", f64::NAN).is_err());
}

/// A pre-grasp posture: the fingers open to the asked gap (clamped to the gripper's
/// range), letting go of what they held; NaN is refused.
#[test]
fn the_gripper_opens_to_a_gap_and_lets_go() {
    use tabula_robot::driver::Grippers;
    let world = settled_around_the_box(SCENE);
    let mut d = tabula_sim::SimDriver::new(world, "wam", 0).unwrap();
    assert!(d.close("gripper").unwrap().holding);
    d.open_to("gripper", 0.055).unwrap();
    let state = d.grip_state("gripper").unwrap();
    assert!(!state.holding);
    assert!((state.width - 0.055).abs() < 1e-6, "{}", state.width);
    // Wider than the gripper opens: fully open.
    d.open_to("gripper", 1.0).unwrap();
    assert!((d.grip_state("gripper").unwrap().width - 0.07).abs() < 1e-6);
    assert!(d.open_to("gripper", f64::NAN).is_err());
}

/// The clearing judge: an object the hand takes may go on touching what it leaned on
/// when taken (within 2 mm), but anything else it meets while held is a collision.
#[test]
fn a_taken_object_is_excused_what_it_touched_when_taken_only() {
    use tabula_robot::driver::Grippers;
    use tabula_sim::judge::ClearJudge;
    let scene = format!(
        "{SCENE}\n[[furniture]]\nname = \"bin\"\nkind = \"bin\"\npose = {{ xyz = [0.0, 0.6, 0.0] }}\nsize = [0.3, 0.3, 0.3]\n\n\
         [[object]]\nname = \"beside\"\nshape = {{ box = [0.05, 0.05, 0.05] }}\npose = {{ xyz = [0.55, 0.0515, 0.425] }}\nmass = 0.1\n\n\
         [[object]]\nname = \"far\"\nshape = {{ box = [0.05, 0.05, 0.05] }}\npose = {{ xyz = [0.55, -0.2, 0.425] }}\nmass = 0.1\n"
    );
    let world = settled_around_the_box(&scene);
    let mut judge = ClearJudge::new(&world, "wam", ("table", "bin")).unwrap();
    let held_at = world.pose("box").unwrap().translation;
    judge.before(&world, held_at, &[]);
    let mut observe = judge.observer("wam");
    let mut d = tabula_sim::SimDriver::new(world, "wam", 0).unwrap();
    assert!(d.close("gripper").unwrap().holding);
    observe(&d.world);
    // Pressed 3 mm into each side of the held box: the neighbour it leaned on is
    // excused, the one it had not touched is not.
    let box_y = d.world.pose("box").unwrap().translation.y;
    for (name, y) in [("beside", box_y + 0.047), ("far", box_y - 0.047)] {
        let mut p = d.world.pose(name).unwrap();
        p.translation.y = y;
        d.world.move_to(name, p).unwrap();
        observe(&d.world);
    }
    judge.after(&d.world);
    let verdict = judge.verdict_on(&d.world);
    assert_eq!(
        verdict.collisions,
        vec![("box".to_string(), "far".to_string())]
    );
}
