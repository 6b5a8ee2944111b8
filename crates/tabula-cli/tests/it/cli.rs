//! The `tabula` binary as a user runs it.

use std::process::Command;

/// Runs a command that must succeed and print one JSON value.
pub(crate) fn tabula_json(args: &[&str]) -> serde_json::Value {
    let out = tabula_ok(args);
    serde_json::from_slice(&out.stdout).expect("one JSON value")
}

/// Runs the `tabula` binary with `args`; it must succeed (its stderr says why not).
pub(crate) fn tabula_ok(args: &[&str]) -> std::process::Output {
    let out = tabula(args);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    out
}

/// The `x y z qx qy qz qw` that `sim capture` prints after `--world-from-camera`.
pub(crate) fn printed_camera_pose(stdout: &[u8]) -> Vec<String> {
    let text = String::from_utf8_lossy(stdout);
    text.split("--world-from-camera ")
        .nth(1)
        .and_then(|t| t.split(')').next())
        .expect("capture prints the camera pose")
        .split_whitespace()
        .map(str::to_string)
        .collect()
}

/// Runs the `tabula` binary with `args`.
pub(crate) fn tabula(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_tabula"))
        .args(args)
        .output()
        .expect("runs")
}

#[test]
fn bench_json_has_the_protocol_fields() {
    let v = tabula_json(&[
        "ik", "bench", "--robot", "golem3", "--solver", "analytic", "--poses", "200", "--seed",
        "3", "--json",
    ]);
    for key in ["success_rate", "max_pos_err_m", "max_rot_err_rad"] {
        assert!(v[key].is_number(), "{key}");
    }
    for key in ["solve_us", "fail_us"] {
        assert!(
            v[key]["median"].is_number() && v[key]["p95"].is_number(),
            "{key}"
        );
    }
    assert_eq!(v["success_rate"].as_f64(), Some(1.0));
}

#[test]
fn bench_works_on_a_urdf_file_with_base_and_tip() {
    let urdf = concat!(env!("CARGO_MANIFEST_DIR"), "/../../robots/pr2.urdf");
    let v = tabula_json(&[
        "ik",
        "bench",
        "--robot",
        urdf,
        "--base",
        "torso_lift_link",
        "--tip",
        "l_gripper_tool_frame",
        "--solver",
        "numeric",
        "--poses",
        "50",
        "--json",
    ]);
    assert_eq!(v["dof"].as_u64(), Some(7));
    assert!(v["success_rate"].as_f64().unwrap() > 0.9);
}

#[test]
fn solve_is_deterministic_and_prints_every_branch() {
    let args = [
        "ik", "solve", "--robot", "golem3", "--pose", "0.62", "-0.43", "1.04", "0", "0", "-0.2",
        "--json",
    ];
    let a = tabula(&args);
    let b = tabula(&args);
    assert!(a.status.success());
    assert_eq!(a.stdout, b.stdout);
    let v: serde_json::Value = serde_json::from_slice(&a.stdout).unwrap();
    assert_eq!(v["solutions"].as_array().unwrap().len(), 2);
    let numeric = [
        "ik", "solve", "--robot", "wam", "--pose", "0.4", "0.2", "0.5", "3.14", "0", "0",
        "--solver", "numeric", "--json",
    ];
    assert_eq!(tabula(&numeric).stdout, tabula(&numeric).stdout);
}

#[test]
fn bad_input_is_one_clear_line() {
    let cases: [(&[&str], &str); 4] = [
        (
            &[
                "ik", "solve", "--robot", "r2d2", "--pose", "0", "0", "0", "0", "0", "0",
            ],
            "unknown robot",
        ),
        (
            &[
                "ik", "solve", "--robot", "wam", "--tip", "hand", "--pose", "0", "0", "0", "0",
                "0", "0",
            ],
            "not in robot",
        ),
        (
            &[
                "ik", "bench", "--robot", "pr2", "--solver", "analytic", "--poses", "10",
            ],
            "no analytic solver",
        ),
        (
            &[
                "ik",
                "solve",
                "--robot",
                "/no/such.urdf",
                "--pose",
                "0",
                "0",
                "0",
                "0",
                "0",
                "0",
            ],
            "cannot read /no/such.urdf",
        ),
    ];
    for (args, expected) in cases {
        let out = tabula(args);
        assert!(!out.status.success());
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains(expected), "{args:?}: {err}");
        assert!(!err.contains("panicked"));
    }
    let nan = tabula(&[
        "ik", "solve", "--robot", "golem3", "--pose", "NaN", "0", "1", "0", "0", "0",
    ]);
    assert!(!nan.status.success());
    assert!(String::from_utf8_lossy(&nan.stderr).contains("finite number"));
}

/// `tabula arm`: the dry run (a fake driver integrating commands) and the simulator
/// plan and execute the same trajectory and end at the same tool pose.
#[test]
fn arm_service_dry_run_matches_the_simulator() {
    for action in [
        vec!["move-pose", "0.6", "0.2", "1.0", "0", "3.1416", "0"],
        vec!["named", "tuck"],
        vec!["move-joints", "0.3", "-0.5", "0", "2.0", "0", "0.4", "0"],
    ] {
        let args = |dry: bool| {
            let mut v = vec!["arm", "--scene", "../../scenes/clutter.toml", "--json"];
            if dry {
                v.push("--dry-run");
            }
            v.extend(action.iter().copied());
            v
        };
        let sim = tabula_json(&args(false));
        let dry = tabula_json(&args(true));
        assert_eq!(sim["driver"], "simulator");
        assert_eq!(dry["driver"], "fake");
        assert_eq!(sim["trajectory"], dry["trajectory"], "{action:?}");
        assert!(sim["trajectory"]["positions"].as_array().unwrap().len() >= 2);
        let (a, b) = (&sim["tool_pose"], &dry["tool_pose"]);
        for k in 0..7 {
            let d = a[k].as_f64().unwrap() - b[k].as_f64().unwrap();
            assert!(d.abs() < 1e-6, "{action:?}: {a} vs {b}");
        }
    }
    let closed = tabula_json(&[
        "arm",
        "--scene",
        "../../scenes/clutter.toml",
        "--json",
        "--dry-run",
        "gripper",
        "close",
    ]);
    assert!(
        (closed["grip"][0].as_f64().unwrap() - 0.03).abs() < 1e-9,
        "{closed}"
    );
    // A gentle close on nothing holds nothing.
    let gentle = tabula_json(&[
        "arm",
        "--scene",
        "../../scenes/clutter.toml",
        "--json",
        "gripper",
        "close",
        "--effort",
        "5",
    ]);
    assert_eq!(gentle["grip"][1], false, "{gentle}");
    // Tele-operation without a terminal is an input error, not a crash.
    let teleop = Command::new(env!("CARGO_BIN_EXE_tabula"))
        .args(["teleop", "--scene", "../../scenes/clutter.toml"])
        .stdin(std::process::Stdio::null())
        .output()
        .unwrap();
    assert_eq!(teleop.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&teleop.stderr).contains("interactive terminal"));
    // Out of reach: no solution (status 2); a wrong arm or joint count: bad input (1).
    let far = tabula(&[
        "arm",
        "--scene",
        "../../scenes/clutter.toml",
        "move-pose",
        "5",
        "0",
        "1",
        "0",
        "0",
        "0",
    ]);
    assert_eq!(
        far.status.code(),
        Some(2),
        "{}",
        String::from_utf8_lossy(&far.stderr)
    );
    let wrong = tabula(&[
        "arm",
        "--scene",
        "../../scenes/clutter.toml",
        "named",
        "--arm",
        "left",
        "tuck",
    ]);
    assert_eq!(wrong.status.code(), Some(1));
    let count = tabula(&[
        "arm",
        "--scene",
        "../../scenes/clutter.toml",
        "move-joints",
        "0.1",
        "0.2",
    ]);
    assert_eq!(count.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&count.stderr).contains("7 joints"));
}

#[test]
fn ik_bench_compares_two_solvers_with_mann_whitney() {
    let v = tabula_json(&[
        "ik",
        "bench",
        "--robot",
        "golem3",
        "--compare",
        "analytic",
        "numeric",
        "--poses",
        "200",
        "--json",
    ]);
    let measures = v["measures"].as_array().unwrap();
    assert_eq!(measures.len(), 7, "{v}");
    assert_eq!(measures[0]["measure"], "solve time");
    for m in &measures[1..] {
        // The closed form is exact to rounding; Levenberg–Marquardt stops at its
        // tolerance: every axis error differs, the closed form's smaller.
        assert!(
            m["median_a"].as_f64().unwrap() < m["median_b"].as_f64().unwrap(),
            "{m}"
        );
        assert!(m["test"]["p"].as_f64().unwrap() < 0.05, "{m}");
        assert_eq!(m["test"]["n_a"], 200);
    }
}

#[test]
fn bench_results_repeat_with_the_same_seed() {
    let args = [
        "ik", "bench", "--robot", "wam", "--solver", "numeric", "--poses", "100", "--seed", "9",
        "--json",
    ];
    let parse =
        |o: std::process::Output| serde_json::from_slice::<serde_json::Value>(&o.stdout).unwrap();
    let (a, b) = (parse(tabula(&args)), parse(tabula(&args)));
    for key in [
        "success_rate",
        "max_pos_err_m",
        "max_rot_err_rad",
        "mean_solutions_per_pose",
        "one_attempt_success_rate",
    ] {
        assert_eq!(a[key], b[key], "{key}");
    }
    assert_eq!(a["errors"], b["errors"]);
}

const PDDL: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../pddl/");

#[test]
fn plan_prints_sas_plan_format_and_validates() {
    let domain = format!("{PDDL}tablewclear-domain.pddl");
    let problem = format!("{PDDL}thesis6-c.pddl");
    let out = tabula(&["plan", &domain, &problem]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8_lossy(&out.stdout).to_string();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.last(), Some(&"; cost = 11 (unit cost)"), "{text}");
    assert_eq!(lines.len(), 12);
    assert!(
        lines[..11]
            .iter()
            .all(|l| l.starts_with("(grasp ") || l.starts_with("(push_dir"))
    );
    let plan_file = std::env::temp_dir().join(format!("tabula-plan-{}.txt", std::process::id()));
    std::fs::write(&plan_file, &text).unwrap();
    let ok = tabula(&[
        "plan",
        "--validate",
        &domain,
        &problem,
        plan_file.to_str().unwrap(),
    ]);
    assert!(
        ok.status.success() && String::from_utf8_lossy(&ok.stdout).contains("plan valid: 11 steps")
    );
    std::fs::write(&plan_file, lines[1..].join("\n")).unwrap();
    let broken = tabula(&[
        "plan",
        "--validate",
        &domain,
        &problem,
        plan_file.to_str().unwrap(),
    ]);
    assert!(!broken.status.success());
    std::fs::remove_file(&plan_file).ok();
}

#[test]
fn plan_reports_unsolvable_and_bad_files() {
    let domain = format!("{PDDL}tablewclear-domain.pddl");
    let out = tabula(&[
        "plan",
        &domain,
        &format!("{PDDL}thesis6-unsolvable.pddl"),
        "--json",
    ]);
    // No plan is not success: exit status 2, the JSON still printed.
    assert_eq!(out.status.code(), Some(2));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["status"], "unsolvable");
    let plain = tabula(&["plan", &domain, &format!("{PDDL}thesis6-unsolvable.pddl")]);
    assert_eq!(plain.status.code(), Some(2));
    let bad = std::env::temp_dir().join(format!("tabula-bad-{}.pddl", std::process::id()));
    std::fs::write(
        &bad,
        "(define (problem p) (:domain tablewclear)\n  (:objects a - obj)\n  (:init (on a b)))",
    )
    .unwrap();
    let out = tabula(&["plan", &domain, bad.to_str().unwrap()]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success() && err.contains(":3:16:") && err.contains("`b`"),
        "{err}"
    );
    std::fs::remove_file(&bad).ok();
    let fast = tabula(&[
        "plan",
        &domain,
        &format!("{PDDL}thesis6-a.pddl"),
        "--fast",
        "--json",
    ]);
    let v: serde_json::Value = serde_json::from_slice(&fast.stdout).unwrap();
    assert_eq!(v["status"], "solved");
    assert_eq!(v["optimal"], false);
}

#[test]
fn sim_capture_snapshot_and_errors() {
    let scene = concat!(env!("CARGO_MANIFEST_DIR"), "/../../scenes/clutter.toml");
    let dir = std::env::temp_dir().join(format!("tabula-sim-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let pcd = dir.join("f.pcd");
    let labels = dir.join("l.json");
    let out = tabula(&[
        "sim",
        "capture",
        "--scene",
        scene,
        "--out",
        pcd.to_str().unwrap(),
        "--labels",
        labels.to_str().unwrap(),
        "--binary",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let bytes = std::fs::read(&pcd).unwrap();
    let header = String::from_utf8_lossy(&bytes[..200]);
    assert!(
        header.contains("WIDTH 640\nHEIGHT 480\n") && header.contains("DATA binary"),
        "{header}"
    );
    let v: serde_json::Value = serde_json::from_slice(&std::fs::read(&labels).unwrap()).unwrap();
    assert_eq!(v["labels"].as_array().unwrap().len(), 640 * 480);
    let png = dir.join("s.png");
    let out = tabula(&[
        "sim",
        "snapshot",
        "--scene",
        scene,
        "--png",
        png.to_str().unwrap(),
        "--width",
        "64",
        "--height",
        "48",
    ]);
    assert!(out.status.success() && std::fs::read(&png).unwrap().starts_with(b"\x89PNG"));
    let bad_camera = tabula(&[
        "sim",
        "capture",
        "--scene",
        scene,
        "--camera",
        "nope",
        "--out",
        pcd.to_str().unwrap(),
    ]);
    assert!(String::from_utf8_lossy(&bad_camera.stderr).contains("cameras: overhead"));
    let bad_model = tabula(&[
        "sim", "spawn", "--scene", scene, "--model", "unicorn", "--name", "u", "--at", "0", "0",
        "1",
    ]);
    assert!(String::from_utf8_lossy(&bad_model.stderr).contains("valid models: cube_5cm"));
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn sim_scene_commands_run_in_order() {
    let scene = concat!(env!("CARGO_MANIFEST_DIR"), "/../../scenes/clutter.toml");
    let out = tabula(&[
        "sim",
        "do",
        "--scene",
        scene,
        "--cmd",
        "spawn can extra 0.6 -0.4 1.2",
        "--cmd",
        "put extra",
        "--cmd",
        "move extra 0.5 -0.45 1.0",
        "--cmd",
        "put extra",
        "--cmd",
        "delete box_red",
        "--cmd",
        "list",
    ]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(
        text.contains("at z = 0.78") && text.contains("  extra") && !text.contains("  box_red"),
        "{text}"
    );
    let bad = tabula(&["sim", "do", "--scene", scene, "--cmd", "teleport x"]);
    assert!(String::from_utf8_lossy(&bad.stderr).contains("unknown command"));
}

#[test]
fn motion_bench_reports_json() {
    let v = tabula_json(&[
        "motion",
        "bench",
        "--robot",
        "wam",
        "--problems",
        "5",
        "--json",
    ]);
    assert!(v["problems"].as_u64().unwrap() > 0);
    assert_eq!(v["success_rate"].as_f64(), Some(1.0));
    let bad = tabula(&["motion", "bench", "--robot", "golem3"]);
    assert!(!bad.status.success());
}

/// The README's own examples run: `plan generate` makes a solvable table (its
/// `--objects 40 --seed 3` example was unsolvable), and `sim do … delete … settle` ends
/// cleanly (it panicked on the deleted body).
#[test]
fn readme_examples_run() {
    let dir = std::env::temp_dir().join(format!("tabula-readme-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let problem = dir.join("table40.pddl");
    let out = tabula(&["plan", "generate", "--objects", "40", "--seed", "3"]);
    assert!(out.status.success());
    std::fs::write(&problem, &out.stdout).unwrap();
    let v = tabula_json(&[
        "plan",
        &format!("{PDDL}tablewclear-domain.pddl"),
        problem.to_str().unwrap(),
        "--fast",
        "--json",
    ]);
    assert_eq!(v["status"], "solved");
    let scene = concat!(env!("CARGO_MANIFEST_DIR"), "/../../scenes/clutter.toml");
    let png = dir.join("after.png");
    let out = tabula(&[
        "sim",
        "do",
        "--scene",
        scene,
        "--cmd",
        "spawn can can2 0.6 -0.4 1.0",
        "--cmd",
        "put can2",
        "--cmd",
        "delete box_red",
        "--cmd",
        "settle",
        "--png",
        png.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("deleted box_red")
            && text.lines().any(|l| l.trim_start().starts_with("can2"))
            && !text.lines().any(|l| l.trim_start().starts_with("box_red ")),
        "{text}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn stable_poses_of_a_mesh_and_a_cloud_and_bad_files() {
    let dir = std::env::temp_dir().join(format!("tabula-stable-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let rows = tabula_json(&[
        "bench",
        "stable-poses",
        "--dir",
        dir.to_str().unwrap(),
        "--reps",
        "1",
        "--json",
    ]);
    assert!(rows.as_array().unwrap().len() >= 10);
    let mug = dir.join("mug.obj");
    let v = tabula_json(&["stable-poses", "--mesh", mug.to_str().unwrap(), "--json"]);
    let poses = v["poses"].as_array().unwrap();
    assert!(!poses.is_empty());
    for key in [
        "support_normal",
        "probability",
        "margin_m",
        "topple_deg",
        "area_m2",
    ] {
        assert!(poses[0].get(key).is_some(), "missing `{key}`");
    }
    assert!(v["cpu_ms"].as_f64().unwrap() >= 0.0);
    // Best first: the mug stands on its bottom, its support normal down in its frame.
    assert!(poses[0]["support_normal"][2].as_f64().unwrap() < -0.99);
    let total: f64 = poses
        .iter()
        .map(|p| p["probability"].as_f64().unwrap())
        .sum();
    assert!((total - 1.0).abs() < 1e-6);
    // A cloud of a box's corners.
    let pcd = dir.join("box.pcd");
    let mut text = String::from(
        "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 8\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 8\nDATA ascii\n",
    );
    for i in 0..8 {
        text += &format!(
            "{} {} {}\n",
            if i & 1 == 0 { -0.1 } else { 0.1 },
            if i & 2 == 0 { -0.05 } else { 0.05 },
            if i & 4 == 0 { 0.0 } else { 0.04 }
        );
    }
    std::fs::write(&pcd, text).unwrap();
    let v = tabula_json(&["stable-poses", "--cloud", pcd.to_str().unwrap(), "--json"]);
    assert_eq!(v["poses"].as_array().unwrap().len(), 6);
    // Degenerate and malformed input: one clear line, no panic.
    let flat = dir.join("flat.obj");
    std::fs::write(
        &flat,
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nf 1 2 3\nf 2 4 3\n",
    )
    .unwrap();
    for bad in [flat.to_str().unwrap(), "/nonexistent.obj"] {
        let out = tabula(&["stable-poses", "--mesh", bad]);
        assert_eq!(out.status.code(), Some(1));
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            err.starts_with("error:") && err.lines().count() == 1,
            "{err}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// A robot as a ROS description package brings it: a workspace folder with a package
/// manifest, a xacro top file that takes an argument and finds its own package, a
/// COLLADA collision mesh, and a MoveIt SRDF beside the URDF — loaded by `ik fk`,
/// described by `robot describe`, and moved to an SRDF group state by `arm --dry-run`.
#[test]
fn a_robot_package_with_xacro_dae_and_srdf_runs_through_the_cli() {
    let ws = std::env::temp_dir().join(format!("tabula-cli-pkg-{}", std::process::id()));
    let pkg = ws.join("src/cell_description");
    std::fs::create_dir_all(pkg.join("urdf")).unwrap();
    std::fs::create_dir_all(pkg.join("meshes")).unwrap();
    std::fs::write(
        pkg.join("package.xml"),
        "<package><name>cell_description</name></package>",
    )
    .unwrap();
    let cube = "-0.03 -0.03 -0.03 0.03 -0.03 -0.03 0.03 0.03 -0.03 -0.03 0.03 -0.03 -0.03 -0.03 0.03 0.03 -0.03 0.03 0.03 0.03 0.03 -0.03 0.03 0.03";
    let faces = "0 2 1 0 3 2 4 5 6 4 6 7 0 1 5 0 5 4 1 2 6 1 6 5 2 3 7 2 7 6 3 0 4 3 4 7";
    std::fs::write(
        pkg.join("meshes/link.dae"),
        format!(r##"<?xml version="1.0"?><COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1"><library_geometries><geometry id="g"><mesh><source id="p"><float_array id="pa" count="24">{cube}</float_array><technique_common><accessor source="#pa" count="8" stride="3"/></technique_common></source><vertices id="v"><input semantic="POSITION" source="#p"/></vertices><triangles count="12"><input semantic="VERTEX" source="#v" offset="0"/><p>{faces}</p></triangles></mesh></geometry></library_geometries><library_visual_scenes><visual_scene id="s"><node><instance_geometry url="#g"/></node></visual_scene></library_visual_scenes><scene><instance_visual_scene url="#s"/></scene></COLLADA>"##),
    )
    .unwrap();
    let mut links = String::new();
    let mut parent = "${prefix}base".to_string();
    for k in 1..=3 {
        links += &format!(
            r#"<link name="${{prefix}}link{k}"><collision><geometry><mesh filename="package://cell_description/meshes/link.dae"/></geometry></collision></link>
<joint name="${{prefix}}j{k}" type="revolute"><parent link="{parent}"/><child link="${{prefix}}link{k}"/><origin xyz="0 0 0.25"/><axis xyz="0 {a} {b}"/><limit lower="-2.5" upper="2.5" effort="1" velocity="1"/></joint>"#,
            a = k % 2,
            b = (k + 1) % 2
        );
        parent = format!("${{prefix}}link{k}");
    }
    let xacro = format!(
        r#"<robot name="cell" xmlns:xacro="http://www.ros.org/wiki/xacro"><xacro:arg name="prefix" default=""/><xacro:property name="prefix" value="$(arg prefix)"/><xacro:include filename="$(find cell_description)/urdf/parts.xacro"/><link name="${{prefix}}base"/>{links}<xacro:tool_frame/></robot>"#
    );
    std::fs::write(pkg.join("urdf/arm.urdf.xacro"), xacro).unwrap();
    std::fs::write(
        pkg.join("urdf/parts.xacro"),
        r#"<robot xmlns:xacro="http://www.ros.org/wiki/xacro"><xacro:macro name="tool_frame"><link name="${prefix}tool0"/><joint name="${prefix}jt" type="fixed"><parent link="${prefix}link3"/><child link="${prefix}tool0"/><origin xyz="0 0 0.1"/></joint></xacro:macro></robot>"#,
    )
    .unwrap();
    std::fs::write(
        pkg.join("urdf/arm.urdf.srdf"),
        r#"<robot name="cell"><group name="manipulator"><chain base_link="a_base" tip_link="a_tool0"/></group>
<group_state name="home" group="manipulator"><joint name="a_j1" value="0.3"/><joint name="a_j2" value="0.5"/><joint name="a_j3" value="-0.4"/></group_state>
<disable_collisions link1="a_link1" link2="a_link3" reason="Never"/></robot>"#,
    )
    .unwrap();
    let top = pkg.join("urdf/arm.urdf.xacro");
    let top = top.to_str().unwrap();
    let fk = tabula_json(&[
        "ik",
        "fk",
        "--robot",
        top,
        "--xacro-arg",
        "prefix:=a_",
        "--json",
        "--joints",
        "0",
        "0",
        "0",
    ]);
    assert_eq!(fk["tip"], "a_tool0", "{fk}");
    assert!(
        (fk["xyz"][2].as_f64().unwrap() - 0.85).abs() < 1e-12,
        "{fk}"
    );
    let described = tabula(&["robot", "describe", top, "--xacro-arg", "prefix:=a_"]);
    let text = String::from_utf8_lossy(&described.stdout);
    assert!(
        described.status.success()
            && text.contains("name = \"manipulator\"")
            && text.contains("[arm.named.home]"),
        "{text}"
    );
    let scene = ws.join("cell.toml");
    std::fs::write(
        &scene,
        format!("[floor]\nsize = [3.0, 3.0]\n\n[[robot]]\nname = \"cell\"\nurdf = \"{top}\"\nxacro_args = {{ prefix = \"a_\" }}\npose = {{ xyz = [0.0, 0.0, 0.0] }}\n"),
    )
    .unwrap();
    let moved = tabula_json(&[
        "arm",
        "--scene",
        scene.to_str().unwrap(),
        "--dry-run",
        "--json",
        "named",
        "--arm",
        "manipulator",
        "home",
    ]);
    assert_eq!(moved["arm"], "manipulator", "{moved}");
    let joints = &moved["joints"];
    assert!(joints.to_string().contains("a_j2"), "{moved}");
    std::fs::remove_dir_all(&ws).ok();
}
