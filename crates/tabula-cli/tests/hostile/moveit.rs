//! MoveIt planning scenes, motion plan requests and MotionBenchMaker problem sets for
//! `tabula motion plan` and `tabula motion bench --mbm`.

use super::Expect::{Error, NoSolution};
use super::{Corpus, repo};

const OBJECT: &str = "{id: o, primitives: [{type: 1, dimensions: [0.1, 0.1, 0.1]}], primitive_poses: [{position: [2, 0, 0]}]}";

fn scene_with(object: &str) -> String {
    format!("world:\n  collision_objects:\n    - {object}\n")
}

pub(super) fn moveit(c: &mut Corpus) {
    let urdf = repo("data/mbm/panda/panda.urdf");
    let plan =
        |c: &mut Corpus, name: &str, class, expect, scene: &str, extra: &[&str], needle: &str| {
            let mut args = vec!["motion", "plan", "--robot", urdf.as_str(), "--scene", scene];
            if !extra
                .iter()
                .any(|a| a.starts_with("--goal") || *a == "--request")
            {
                args.extend(["--start-named", "ready", "--goal-named", "extended"]);
            }
            args.extend_from_slice(extra);
            c.case(&format!("moveit-{name}"), class, expect, &args);
            c.needs(needle);
        };
    let mut alias_bomb = String::from("a: &a [x, x, x, x, x, x, x, x, x, x]\n");
    for k in 1..14u8 {
        let (this, prev) = ((b'a' + k) as char, (b'a' + k - 1) as char);
        alias_bomb += &format!(
            "{this}: &{this} [{}]\n",
            vec![format!("*{prev}"); 10].join(", ")
        );
    }
    alias_bomb += "world: {collision_objects: [*n]}\n";
    let many: String = std::iter::once("world:\n  collision_objects:\n".to_string())
        .chain((0..10_001).map(|i| format!("    - {{id: o{i}, primitives: [{{type: 2, dimensions: [0.01]}}], primitive_poses: [{{position: [9, 9, {i}]}}]}}\n")))
        .collect();
    let scenes: Vec<(&str, &'static str, String, &str)> = vec![
        ("truncated", "malformed", scene_with(OBJECT)[..40].to_string(), "yaml"),
        ("not-a-map", "malformed", "- 1\n- 2\n".into(), "a planning scene is a map"),
        ("unknown-type", "malformed", scene_with(&OBJECT.replace("type: 1", "type: torus")), "torus"),
        ("nan-size", "garbage", scene_with(&OBJECT.replace("0.1, 0.1, 0.1", "0.1, .nan, 0.1")), "finite"),
        ("huge-size", "overflow", scene_with(&OBJECT.replace("0.1, 0.1, 0.1", "0.1, 1e300, 0.1")), "beyond"),
        ("zero-size", "garbage", scene_with(&OBJECT.replace("0.1, 0.1, 0.1", "0.1, 0, 0.1")), "positive"),
        ("zero-quaternion", "garbage", scene_with(&OBJECT.replace("position: [2, 0, 0]", "orientation: [0, 0, 0, 0]")), "zero length"),
        ("poses-missing", "malformed", scene_with(&OBJECT.replace("primitive_poses: [{position: [2, 0, 0]}]", "primitive_poses: []")), "1 primitives but 0"),
        ("bad-mesh-index", "garbage", scene_with("{id: m, meshes: [{vertices: [[0,0,0],[1,0,0],[0,1,0],[0,0,1]], triangles: [{vertex_indices: [0, 1, 99]}]}], mesh_poses: [{}]}"), "vertex indices"),
        ("flat-mesh", "garbage", scene_with("{id: m, meshes: [{vertices: [[0,0,0],[1,0,0],[0,1,0]], triangles: [{vertex_indices: [0, 1, 2]}]}], mesh_poses: [{}]}"), "m"),
        ("unknown-frame", "garbage", scene_with(&OBJECT.replace("{id: o,", "{id: o, header: {frame_id: elsewhere},")), "elsewhere"),
        ("duplicate-id", "garbage", format!("world:\n  collision_objects:\n    - {OBJECT}\n    - {OBJECT}\n"), "second object"),
        ("acm-ragged", "malformed", "allowed_collision_matrix: {entry_names: [a, b], entry_values: [[true], [false, true]]}\n".into(), "1 values for 2"),
        ("joint-nan", "garbage", "robot_state: {joint_state: {name: [panda_joint1], position: [.nan]}}\n".into(), "finite"),
        ("alias-bomb", "unbounded", alias_bomb, "yaml"),
        ("deep-nesting", "recursion", format!("world: {}{}\n", "[".repeat(100_000), "]".repeat(100_000)), "yaml"),
        ("ten-thousand-and-one", "unbounded", many, "10001 collision objects"),
    ];
    for (name, class, text, needle) in scenes {
        let f = c.file(&format!("moveit/{name}.yaml"), text);
        plan(c, name, class, Error, &f, &[], needle);
    }
    let fine = c.file("moveit/fine-scene.yaml", scene_with(OBJECT));
    let requests: Vec<(&str, &'static str, super::Expect, &str, &str)> = vec![
        (
            "request-no-group",
            "malformed",
            Error,
            "goal_constraints: [{joint_constraints: [{joint_name: panda_joint1, position: 0}]}]\n",
            "group_name",
        ),
        (
            "request-unknown-group",
            "garbage",
            Error,
            "group_name: wing\ngoal_constraints: [{joint_constraints: [{joint_name: a, position: 0}]}]\n",
            "wing",
        ),
        (
            "request-nan-goal",
            "garbage",
            Error,
            "group_name: panda_arm\ngoal_constraints: [{joint_constraints: [{joint_name: panda_joint1, position: .nan}]}]\n",
            "finite",
        ),
        (
            "request-foreign-joint",
            "garbage",
            Error,
            "group_name: panda_arm\ngoal_constraints: [{joint_constraints: [{joint_name: elbow, position: 0}]}]\n",
            "elbow",
        ),
        (
            "request-partial-goal",
            "garbage",
            Error,
            "group_name: panda_arm\ngoal_constraints: [{joint_constraints: [{joint_name: panda_joint1, position: 0}]}]\n",
            "panda_joint2",
        ),
        (
            "request-goal-out-of-limits",
            "odd-legal",
            NoSolution,
            "group_name: panda_arm\nstart_state: {joint_state: {name: [panda_joint4], position: [-2.356]}}\ngoal_constraints: [{joint_constraints: [{joint_name: panda_joint1, position: 0}, {joint_name: panda_joint2, position: 0}, {joint_name: panda_joint3, position: 0}, {joint_name: panda_joint4, position: 1.5}, {joint_name: panda_joint5, position: 0}, {joint_name: panda_joint6, position: 1.5}, {joint_name: panda_joint7, position: 0}]}]\n",
            "panda_joint4",
        ),
        (
            "request-position-only",
            "odd-legal",
            Error,
            "group_name: panda_arm\ngoal_constraints: [{position_constraints: [{link_name: panda_link8, constraint_region: {primitives: [{type: 2, dimensions: [0.01]}], primitive_poses: [{position: [0.4, 0, 0.4]}]}}]}]\n",
            "orientation",
        ),
    ];
    for (name, class, expect, text, needle) in requests {
        let f = c.file(&format!("moveit/{name}.yaml"), text);
        plan(c, name, class, expect, &fine, &["--request", &f], needle);
    }
    // Problem sets.
    let empty = c.file("mbm/empty/.keep", "");
    let empty = empty.trim_end_matches("/.keep").to_string();
    let lone = c.file("mbm/lone/set_a/scene0001.yaml", scene_with(OBJECT));
    let lone = lone.trim_end_matches("/set_a/scene0001.yaml").to_string();
    let garbage = c.file(
        "mbm/garbage.tar.bz2",
        b"BZh91AY&SY not really bzip2".repeat(10),
    );
    for (name, class, path, needle) in [
        (
            "mbm-empty-folder",
            "special-file",
            empty.as_str(),
            "no MotionBenchMaker problems",
        ),
        (
            "mbm-scene-without-request",
            "malformed",
            lone.as_str(),
            "lacks its scene or its request",
        ),
        (
            "mbm-garbage-archive",
            "malformed",
            garbage.as_str(),
            "garbage.tar.bz2",
        ),
        (
            "mbm-dev-zero",
            "special-file",
            "/dev/zero",
            "neither a folder nor",
        ),
    ] {
        c.case(
            name,
            class,
            Error,
            &["motion", "bench", "--mbm", path, "--robot", &urdf],
        );
        c.needs(needle);
    }
}
