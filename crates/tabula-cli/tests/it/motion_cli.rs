//! `tabula motion plan` and `tabula motion bench --mbm` as a MoveIt or OMPL user runs
//! them, on MotionBenchMaker's Panda (data/mbm/panda: one problem of each set).

use std::path::PathBuf;
use std::process::{Command, Output};

fn fixture(rel: &str) -> String {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../data/mbm/panda")
        .join(rel)
        .to_string_lossy()
        .into_owned()
}

fn tabula(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_tabula"))
        .args(args)
        .output()
        .expect("runs")
}

const SETS: [&str; 7] = [
    "bookshelf_small_panda",
    "bookshelf_tall_panda",
    "bookshelf_thin_panda",
    "box_panda",
    "cage_panda",
    "table_pick_panda",
    "table_under_pick_panda",
];

fn plan(set: &str, extra: &[&str]) -> Output {
    let (urdf, scene, request) = (
        fixture("panda.urdf"),
        fixture(&format!("problems/{set}/scene0001.yaml")),
        fixture(&format!("problems/{set}/request0001.yaml")),
    );
    let mut args = vec![
        "motion",
        "plan",
        "--robot",
        &urdf,
        "--scene",
        &scene,
        "--request",
        &request,
        "--json",
    ];
    args.extend_from_slice(extra);
    tabula(&args)
}

#[test]
fn plan_and_bench_agree_on_every_set_and_plans_are_timed_trajectories() {
    let problems = fixture("problems");
    let urdf = fixture("panda.urdf");
    let out = tabula(&[
        "motion",
        "bench",
        "--mbm",
        &problems,
        "--robot",
        &urdf,
        "--timeout",
        "30",
        "--json",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let bench: serde_json::Value = serde_json::from_slice(&out.stdout).expect("json");
    assert_eq!(
        (bench["total"].as_u64(), bench["solved"].as_u64()),
        (Some(7), Some(7)),
        "{bench}"
    );
    for key in ["median", "p95", "max"] {
        assert!(
            bench["time_us"][key].as_f64().is_some_and(|t| t > 0.0),
            "{key}"
        );
    }
    assert_eq!(bench["sets"].as_array().map(Vec::len), Some(7));
    for set in SETS {
        let out = plan(set, &["--timeout", "30"]);
        assert!(
            out.status.success(),
            "{set}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("json");
        assert_eq!(v["solved"], true);
        assert_eq!(v["group"], "panda_arm");
        assert_eq!(v["joint_names"].as_array().map(Vec::len), Some(7));
        assert!(v["planning_us"].as_f64().is_some_and(|t| t > 0.0));
        assert!(v["path_length"].as_f64().is_some_and(|l| l > 0.0));
        let points = v["points"].as_array().expect("points");
        assert!(points.len() >= 2);
        let first = &points[0];
        let last = &points[points.len() - 1];
        assert_eq!(first["time"], 0.0);
        for p in [first, last] {
            // A rest-to-rest trajectory.
            assert!(
                p["velocities"]
                    .as_array()
                    .expect("velocities")
                    .iter()
                    .all(|x| x.as_f64() == Some(0.0))
            );
        }
        assert!(
            points
                .windows(2)
                .all(|w| w[0]["time"].as_f64() < w[1]["time"].as_f64())
        );
        assert!(points.iter().any(|p| {
            p["velocities"]
                .as_array()
                .expect("v")
                .iter()
                .any(|x| x.as_f64() != Some(0.0))
        }));
    }
}

#[test]
fn goals_from_flags_and_named_states() {
    let urdf = fixture("panda.urdf");
    let scene = fixture("problems/table_pick_panda/scene0001.yaml");
    let out = tabula(&[
        "motion",
        "plan",
        "--robot",
        &urdf,
        "--scene",
        &scene,
        "--start-named",
        "ready",
        "--goal-named",
        "extended",
        "--json",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("json");
    let path = v["path"].as_array().expect("path");
    assert_eq!(path[0][3].as_f64(), Some(-2.356), "starts at `ready`");
    assert_eq!(
        path[path.len() - 1][3].as_f64(),
        Some(0.0),
        "ends at `extended`"
    );
    // No robot for a MoveIt scene: a clear error.
    let out = tabula(&[
        "motion",
        "plan",
        "--scene",
        &scene,
        "--goal-named",
        "extended",
    ]);
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--robot is required"));
}

#[test]
fn bad_requests_are_named_and_impossible_ones_exit_2() {
    let urdf = fixture("panda.urdf");
    let scene = fixture("problems/box_panda/scene0001.yaml");
    let dir = std::env::temp_dir().join(format!("tabula-motion-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("dir");
    // An unknown group lists the known ones.
    let out = tabula(&[
        "motion",
        "plan",
        "--robot",
        &urdf,
        "--group",
        "left_arm",
        "--goal-named",
        "ready",
    ]);
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("left_arm") && err.contains("panda_arm"),
        "{err}"
    );
    // A goal outside the joint limits: no plan, exit 2, the joint named.
    let out = tabula(&[
        "motion",
        "plan",
        "--robot",
        &urdf,
        "--scene",
        &scene,
        "--start-named",
        "ready",
        "--goal-joints",
        "0",
        "0",
        "0",
        "1.0",
        "0",
        "1.5",
        "0",
        "--json",
    ]);
    assert_eq!(
        out.status.code(),
        Some(2),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("json");
    assert_eq!(
        (v["solved"].as_bool(), v["reason"].as_str()),
        (Some(false), Some("goal_invalid"))
    );
    assert!(
        v["message"]
            .as_str()
            .expect("message")
            .contains("panda_joint4")
    );
    // The wrong number of goal values is a usage error naming the joints.
    let out = tabula(&[
        "motion",
        "plan",
        "--robot",
        &urdf,
        "--goal-joints",
        "0",
        "0",
    ]);
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("panda_joint7"));
    // NaN anywhere on the command line is refused before any work.
    let out = tabula(&[
        "motion",
        "plan",
        "--robot",
        &urdf,
        "--goal-pose",
        "0.5",
        "0",
        "NaN",
        "0",
        "0",
        "0",
    ]);
    assert_eq!(out.status.code(), Some(64));
    // Malformed YAML names the file and where.
    let broken = dir.join("broken.yaml");
    std::fs::write(
        &broken,
        "world:\n  collision_objects:\n    - id: [unclosed\n",
    )
    .expect("write");
    let out = tabula(&[
        "motion",
        "plan",
        "--robot",
        &urdf,
        "--scene",
        broken.to_str().expect("utf-8"),
        "--goal-named",
        "ready",
    ]);
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("broken.yaml") && err.contains("YAML"), "{err}");
    // A request for a group the robot lacks.
    let request = dir.join("request.yaml");
    std::fs::write(&request, "group_name: right_arm\ngoal_constraints: [{joint_constraints: [{joint_name: a, position: 0}]}]\n").expect("write");
    let out = tabula(&[
        "motion",
        "plan",
        "--robot",
        &urdf,
        "--request",
        request.to_str().expect("utf-8"),
    ]);
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("right_arm"));
    // A problems folder with nothing in it.
    let out = tabula(&[
        "motion",
        "bench",
        "--mbm",
        dir.to_str().expect("utf-8"),
        "--robot",
        &urdf,
    ]);
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("no MotionBenchMaker problems"));
    let _ = std::fs::remove_dir_all(&dir);
}
