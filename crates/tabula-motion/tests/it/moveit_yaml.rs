//! MoveIt planning scenes and motion plan requests in YAML: both spellings tools write
//! (maps as MoveIt and `ros2 topic echo` give them, lists as MotionBenchMaker does),
//! shapes placed as ROS places them, and bad files refused with the field named.

use std::time::Instant;
use tabula_geom::{Pose, Quat, Vec3};
use tabula_motion::CollisionWorld;
use tabula_motion::WorldParams;
use tabula_motion::moveit::{Goal, Limits, MotionRequest, MoveItError, PlanningScene};
use tabula_robot::robots;

fn scene(text: &str) -> Result<PlanningScene, MoveItError> {
    PlanningScene::from_yaml(text, &Limits::default())
}

fn request(text: &str) -> Result<MotionRequest, MoveItError> {
    MotionRequest::from_yaml(text, &Limits::default())
}

fn wam_world() -> CollisionWorld {
    let r = robots::load("wam").expect("wam");
    let chain = tabula_robot::Chain::new(&r.model, &r.default_base, &r.default_tip).expect("chain");
    CollisionWorld::new(
        r.model.clone(),
        chain,
        Pose::IDENTITY,
        None,
        WorldParams::default(),
    )
    .expect("world")
}

const MAP_FORM: &str = r#"
name: lab
robot_state:
  joint_state:
    name: [j1]
    position: [0.5]
world:
  collision_objects:
    - id: table
      header: {frame_id: world}
      pose:
        position: {x: 1.0, y: 0.0, z: 0.0}
        orientation: {x: 0, y: 0, z: 0, w: 1}
      primitives:
        - {type: 1, dimensions: [0.8, 1.2, 0.04]}
        - {type: cylinder, dimensions: [0.7, 0.03]}
      primitive_poses:
        - position: {x: 0, y: 0, z: 0.7}
          orientation: {x: 0, y: 0, z: 0, w: 1}
        - position: {x: 0.35, y: 0.55, z: 0.35}
          orientation: {x: 0, y: 0, z: 0, w: 1}
      operation: 0
    - id: table
      operation: append
      primitives: [{type: sphere, dimensions: [0.05]}]
      primitive_poses: [{position: [0, 0, 1.0], orientation: [0, 0, 0, 1]}]
"#;

#[test]
fn map_and_list_spellings_read_alike_and_parts_are_placed_as_ros_places_them() {
    let s = scene(MAP_FORM).expect("scene reads");
    assert_eq!(s.name, "lab");
    assert_eq!(s.joints, [("j1".to_string(), 0.5)]);
    assert_eq!(
        s.objects.len(),
        1,
        "APPEND adds to the object of the same id"
    );
    let o = &s.objects[0];
    assert_eq!(o.frame_id, "world");
    assert_eq!(o.parts.len(), 3);
    // Object pose × primitive pose.
    assert!((o.parts[0].1.translation - Vec3::new(1.0, 0.0, 0.7)).length() < 1e-12);
    // A ROS cylinder stands along z: its top at +0.35 m above its centre.
    let (cyl, at) = &o.parts[1];
    let aabb = cyl.compute_aabb(at);
    assert!(
        (aabb.maxs.z - 0.7).abs() < 1e-9 && (aabb.mins.z - 0.0).abs() < 1e-9,
        "{aabb:?}"
    );
    let list = MAP_FORM
        .replace("{x: 1.0, y: 0.0, z: 0.0}", "[1.0, 0.0, 0.0]")
        .replace("{x: 0, y: 0, z: 0, w: 1}", "[0, 0, 0, 1]");
    let l = scene(&list).expect("list spelling reads");
    for (a, b) in o.parts.iter().zip(&l.objects[0].parts) {
        assert!((a.1.translation - b.1.translation).length() < 1e-12);
    }
}

#[test]
fn a_scene_goes_into_a_world_with_frames_of_links() {
    let mut world = wam_world();
    let link = world.chain.tip_link.clone();
    let text = format!(
        r#"
world:
  collision_objects:
    - id: near_tip
      header: {{frame_id: {link}}}
      primitives: [{{type: box, dimensions: [0.3, 0.3, 0.3]}}]
      primitive_poses: [{{position: [0, 0, 0], orientation: [0, 0, 0, 1]}}]
"#
    );
    let s = scene(&text).expect("scene");
    s.apply(&mut world).expect("applies");
    let q = world.chain_values();
    let tip = world.tip_pose(&q).expect("tip");
    let (a, b) = world
        .first_collision(&q)
        .expect("finite")
        .expect("the box sits on the tip");
    assert_eq!(b, "near_tip", "{a} {b} at tip {tip:?}");
    // The same box in the planning frame sits at the robot's fixed base: nothing moving
    // touches it there.
    let mut at_origin = wam_world();
    scene(&text.replace(&format!("frame_id: {link}"), "frame_id: world"))
        .expect("scene")
        .apply(&mut at_origin)
        .expect("applies");
    assert_eq!(at_origin.first_collision(&q).expect("finite"), None);
    let bad = text.replace(&link, "no_such_link");
    let err = scene(&bad)
        .expect("parses")
        .apply(&mut wam_world())
        .expect_err("unknown frame");
    assert!(err.to_string().contains("no_such_link"), "{err}");
}

#[test]
fn requests_give_joint_goals_and_pose_goals() {
    let r = request(
        r#"
group_name: arm
allowed_planning_time: 5
max_velocity_scaling_factor: 0
start_state:
  joint_state: {name: [a, b], position: [0.1, 0.2]}
goal_constraints:
  - joint_constraints:
      - {joint_name: a, position: 1.0}
      - {joint_name: b, position: -1.0}
  - position_constraints:
      - link_name: tool
        header: {frame_id: base}
        target_point_offset: {x: 0, y: 0, z: 0.1}
        constraint_region:
          primitives: [{type: sphere, dimensions: [0.01]}]
          primitive_poses: [{position: {x: 0.5, y: 0, z: 0.3}}]
    orientation_constraints:
      - {link_name: tool, orientation: {x: 0, y: 0, z: 0, w: 1}}
"#,
    )
    .expect("request reads");
    assert_eq!(r.group, "arm");
    assert_eq!(r.allowed_planning_time, Some(5.0));
    assert_eq!(r.velocity_scaling, None, "0 means the default");
    assert_eq!(r.goals.len(), 2);
    assert_eq!(
        r.goals[0],
        Goal::Joints(vec![("a".into(), 1.0), ("b".into(), -1.0)])
    );
    let Goal::Pose {
        link,
        frame_id,
        position,
        link_offset,
        orientation,
    } = &r.goals[1]
    else {
        panic!("pose goal");
    };
    assert_eq!((link.as_str(), frame_id.as_str()), ("tool", "base"));
    assert_eq!(
        (*position, *link_offset),
        (Vec3::new(0.5, 0.0, 0.3), Vec3::new(0.0, 0.0, 0.1))
    );
    assert_eq!(*orientation, Some(Quat::IDENTITY));
}

#[test]
fn request_goals_must_fit_the_group() {
    let mut world = wam_world();
    let names = world.chain.joint_names.clone();
    let goal = |names: &[String]| -> String {
        let rows: Vec<String> = names
            .iter()
            .map(|n| format!("      - {{joint_name: {n}, position: 0.1}}"))
            .collect();
        format!(
            "group_name: arm\ngoal_constraints:\n  - joint_constraints:\n{}\n",
            rows.join("\n")
        )
    };
    let ok = request(&goal(&names))
        .expect("reads")
        .problem(&mut world)
        .expect("fits");
    assert_eq!(ok.joint_goals, vec![vec![0.1; names.len()]]);
    let missing = request(&goal(&names[1..]))
        .expect("reads")
        .problem(&mut world)
        .expect_err("missing joint");
    assert!(missing.to_string().contains(&names[0]), "{missing}");
    let mut extra = names.clone();
    extra.push("elbow_of_someone_else".into());
    let e = request(&goal(&extra))
        .expect("reads")
        .problem(&mut world)
        .expect_err("foreign joint");
    assert!(e.to_string().contains("elbow_of_someone_else"), "{e}");
}

#[test]
fn bad_files_name_the_field() {
    let cases: &[(&str, &str)] = &[
        (
            "world: {collision_objects: [{primitives: []}]}",
            "missing `id`",
        ),
        (
            "world: {collision_objects: [{id: a, primitives: [{type: box, dimensions: [1, 1]}], primitive_poses: [{}]}]}",
            "3 dimensions",
        ),
        (
            "world: {collision_objects: [{id: a, primitives: [{type: box, dimensions: [1, 1, .nan]}], primitive_poses: [{}]}]}",
            "finite",
        ),
        (
            "world: {collision_objects: [{id: a, primitives: [{type: box, dimensions: [1, 1, -1]}], primitive_poses: [{}]}]}",
            "positive",
        ),
        (
            "world: {collision_objects: [{id: a, primitives: [{type: box, dimensions: [1, 1, 1e300]}], primitive_poses: [{}]}]}",
            "beyond",
        ),
        (
            "world: {collision_objects: [{id: a, primitives: [{type: torus, dimensions: [1]}], primitive_poses: [{}]}]}",
            "torus",
        ),
        (
            "world: {collision_objects: [{id: a, primitives: [{type: 1, dimensions: [1, 1, 1]}], primitive_poses: []}]}",
            "1 primitives but 0",
        ),
        (
            "world: {collision_objects: [{id: a, primitives: [{type: 1, dimensions: [1, 1, 1]}], primitive_poses: [{orientation: [0, 0, 0, 0]}]}]}",
            "zero length",
        ),
        ("world: {collision_objects: [{id: a}]}", "no shapes"),
        (
            "world: {collision_objects: [{id: a, operation: 1, primitives: [{type: 1, dimensions: [1, 1, 1]}], primitive_poses: [{}]}]}",
            "REMOVE",
        ),
        (
            "world: {collision_objects: [{id: a, meshes: [{vertices: [[0,0,0],[1,0,0],[0,1,0]], triangles: [{vertex_indices: [0, 1, 7]}]}], mesh_poses: [{}]}]}",
            "vertex indices",
        ),
        ("is_diff: true", "diffs"),
        (
            "robot_state: {joint_state: {name: [a, b], position: [1]}}",
            "2 names but 1 positions",
        ),
        (
            "allowed_collision_matrix: {entry_names: [a, b], entry_values: [[false, true]]}",
            "1 rows for 2",
        ),
        ("- just a list", "a planning scene is a map"),
        ("world: [unclosed", "YAML"),
    ];
    for (text, expected) in cases {
        let e = match scene(text) {
            Ok(_) => panic!("accepted: {text}"),
            Err(e) => e.to_string(),
        };
        assert!(
            e.contains(expected),
            "{text}\n  → {e}\n  expected `{expected}`"
        );
    }
    let r = request("group_name: arm\ngoal_constraints: []").expect_err("no goal");
    assert!(r.to_string().contains("goal_constraints"), "{r}");
    let r = request("goal_constraints: [{joint_constraints: [{joint_name: a, position: 1}]}]")
        .expect_err("no group");
    assert!(r.to_string().contains("group_name"), "{r}");
}

#[test]
fn hostile_sizes_are_refused_quickly() {
    // 100,000 obstacles: refused by count, in bounded time.
    let mut text = String::from("world:\n  collision_objects:\n");
    for i in 0..100_000 {
        text.push_str(&format!(
            "    - {{id: o{i}, primitives: [{{type: 2, dimensions: [0.01]}}], primitive_poses: [{{position: [{i}, 0, 0]}}]}}\n"
        ));
    }
    let limits = Limits {
        bytes: usize::MAX,
        ..Limits::default()
    };
    let t = Instant::now();
    let e = PlanningScene::from_yaml(&text, &limits)
        .err()
        .expect("refused");
    assert!(matches!(e, MoveItError::TooLarge(_)), "{e}");
    assert!(t.elapsed().as_secs_f64() < 20.0);
    // The default size limit refuses that file before parsing it.
    let e = scene(&text).err().expect("refused by size");
    assert!(e.to_string().contains("bytes"), "{e}");
    // A billion laughs: alias expansion is bounded by the YAML reader.
    let mut bomb = String::from("a: &a [x, x, x, x, x, x, x, x, x, x]\n");
    for k in 1..12 {
        bomb.push_str(&format!(
            "{}: &{} [",
            (b'a' + k) as char,
            (b'a' + k) as char
        ));
        bomb.push_str(&vec![format!("*{}", (b'a' + k - 1) as char); 10].join(", "));
        bomb.push_str("]\n");
    }
    let t = Instant::now();
    assert!(scene(&bomb).is_err());
    assert!(t.elapsed().as_secs_f64() < 5.0);
    // Ten thousand objects are fine, and go into a world at once.
    let many: String = std::iter::once("world:\n  collision_objects:\n".to_string())
        .chain((0..10_000).map(|i| {
            format!("    - {{id: o{i}, primitives: [{{type: 1, dimensions: [0.01, 0.01, 0.01]}}], primitive_poses: [{{position: [{}, 5, 0]}}]}}\n", i as f64 * 0.001)
        }))
        .collect();
    let t = Instant::now();
    let s = scene(&many).expect("10k objects read");
    let mut world = wam_world();
    s.apply(&mut world).expect("overlapping obstacles are fine");
    assert_eq!(world.object_names().len(), 10_000);
    assert!(t.elapsed().as_secs_f64() < 20.0);
}
