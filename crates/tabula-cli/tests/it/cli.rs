//! The `tabula` binary as a user runs it.

use std::process::Command;

/// Runs a command that must succeed and print one JSON value.
fn tabula_json(args: &[&str]) -> serde_json::Value {
    let out = tabula(args);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("one JSON value")
}

/// The WAM as scenes/clutter.toml places it, for `perceive --robot`.
const WAM_IN_CLUTTER: [&str; 10] = [
    "--robot",
    "wam",
    "--robot-base",
    "0",
    "0",
    "0.6",
    "0",
    "0",
    "0",
    "1",
];

/// The WAM's arm reaching over the table beside the objects, in the camera's view.
const ARM_IN_VIEW: &str = "joints = { wam_joint1 = 0.35, wam_joint2 = 0.7, wam_joint4 = 1.4 }";
const ARM_IN_VIEW_ARGS: [&str; 6] = [
    "--joint",
    "wam_joint1=0.35",
    "--joint",
    "wam_joint2=0.7",
    "--joint",
    "wam_joint4=1.4",
];

/// scenes/clutter.toml with the arm at `joints` (a `joints = { … }` line).
fn clutter_with_arm(joints: &str) -> String {
    let clutter = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../scenes/clutter.toml"
    ))
    .unwrap();
    let moved = clutter.replace("joints = { wam_joint2 = -1.9, wam_joint4 = 2.6 }", joints);
    assert_ne!(moved, clutter);
    moved
}

fn tabula(args: &[&str]) -> std::process::Output {
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

#[test]
fn perceive_reads_pcd_and_ply_filters_the_robot_places_and_reports() {
    let dir = std::env::temp_dir().join(format!("tabula-perceive-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    // The arm in view, beside the objects.
    let reaching = dir.join("reach.toml");
    std::fs::write(&reaching, clutter_with_arm(ARM_IN_VIEW)).unwrap();
    let scene = reaching.to_str().unwrap();
    let mut pose: Vec<String> = Vec::new();
    for file in ["frame.pcd", "frame.ply"] {
        let out_path = dir.join(file);
        let out = tabula(&[
            "sim",
            "capture",
            "--scene",
            scene,
            "--settle",
            "--binary",
            "--out",
            out_path.to_str().unwrap(),
        ]);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let text = String::from_utf8_lossy(&out.stdout).to_string();
        let args = text
            .split("--world-from-camera ")
            .nth(1)
            .unwrap()
            .split(')')
            .next()
            .unwrap();
        pose = args.split_whitespace().map(str::to_string).collect();
        assert_eq!(pose.len(), 7);
    }
    let report = dir.join("report");
    let mut results = Vec::new();
    for file in ["frame.pcd", "frame.ply"] {
        let path = dir.join(file);
        let mut args = vec![
            "perceive",
            "--cloud",
            path.to_str().unwrap(),
            "--world-from-camera",
        ];
        args.extend(pose.iter().map(String::as_str));
        args.extend(WAM_IN_CLUTTER);
        args.extend(ARM_IN_VIEW_ARGS);
        args.extend([
            "--place",
            "0.08",
            "0.06",
            "--json",
            "--report",
            report.to_str().unwrap(),
        ]);
        let out = tabula(&args);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON");
        assert_eq!(v["objects"].as_array().unwrap().len(), 7, "{file}");
        assert!((v["table"]["centroid"][2].as_f64().unwrap() - 0.72).abs() < 0.01);
        assert!(
            v["self_filtered_points"].as_u64().unwrap() > 100,
            "the arm is in view"
        );
        let place = &v["placement"];
        assert!(
            (place["position"][2].as_f64().unwrap() - 0.72).abs() < 0.01,
            "{place}"
        );
        results.push(v["objects"].clone());
    }
    // The same frame through either format gives the same objects.
    assert_eq!(results[0], results[1]);
    assert!(report.join("top.png").exists() && report.join("top.svg").exists());
    // Junk in, one clear line out.
    let junk = dir.join("junk.ply");
    std::fs::write(
        &junk,
        b"ply\nformat ascii 1.0\nelement vertex 5\nend_header\n1 2",
    )
    .unwrap();
    let out = tabula(&["perceive", "--cloud", junk.to_str().unwrap()]);
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("PLY") && err.lines().count() == 1, "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn perceive_self_filter_removes_the_arm_reaching_over_the_table() {
    let dir = std::env::temp_dir().join(format!("tabula-selffilter-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let reaching = clutter_with_arm(ARM_IN_VIEW);
    let scene = dir.join("reach.toml");
    std::fs::write(&scene, reaching).unwrap();
    let frame = dir.join("reach.pcd");
    let out = tabula(&[
        "sim",
        "capture",
        "--scene",
        scene.to_str().unwrap(),
        "--binary",
        "--out",
        frame.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let base = [
        "perceive",
        "--cloud",
        frame.to_str().unwrap(),
        "--world-from-camera",
        "0.62",
        "0",
        "1.75",
        "0.7071067811865475",
        "-0.7071067811865475",
        "0",
        "0",
        "--json",
    ];
    let objects = |extra: &[&str]| {
        let mut args = base.to_vec();
        args.extend_from_slice(extra);
        let out = tabula(&args);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        let partial = v["partial_objects"].as_array().unwrap().len();
        (v["objects"].as_array().unwrap().len(), partial)
    };
    // The arm over the table is taken for objects (cut by the frame's edge, as it
    // reaches in from outside the view) …
    let (whole, cut) = objects(&[]);
    assert!(whole + cut > 7, "{whole} + {cut}");
    // … until the robot's own shapes, padded by 0.9 cm, are filtered out.
    let mut args = WAM_IN_CLUTTER.to_vec();
    args.extend(ARM_IN_VIEW_ARGS);
    assert_eq!(objects(&args), (7, 0));
    let _ = std::fs::remove_dir_all(&dir);
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

/// A scene's `joints` table copied into `perceive --joint` describes the same robot:
/// joints not given are at mid-range, where the simulator starts them (they were set to
/// 0, and none of the PR2's ~17k points in its own holding scene were removed).
#[test]
fn perceive_joints_default_to_the_simulators_start() {
    let dir = std::env::temp_dir().join(format!("tabula-pr2joints-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let scene = concat!(env!("CARGO_MANIFEST_DIR"), "/../../scenes/pr2_holding.toml");
    let frame = dir.join("held.pcd");
    let out = tabula(&[
        "sim",
        "capture",
        "--scene",
        scene,
        "--binary",
        "--out",
        frame.to_str().unwrap(),
    ]);
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout).to_string();
    let pose: Vec<String> = text
        .split("--world-from-camera ")
        .nth(1)
        .and_then(|t| t.split(')').next())
        .expect("capture prints the camera pose")
        .split_whitespace()
        .map(str::to_string)
        .collect();
    assert_eq!(pose.len(), 7);
    let mut args: Vec<String> = vec![
        "perceive".into(),
        "--cloud".into(),
        frame.display().to_string(),
    ];
    args.push("--world-from-camera".into());
    args.extend(pose);
    args.extend(["--robot", "pr2", "--json"].map(String::from));
    // Exactly the scene's `joints` table.
    for j in [
        "torso_lift_joint=0.2",
        "head_tilt_joint=0.5",
        "r_shoulder_pan_joint=-0.3",
        "r_shoulder_lift_joint=0.2",
        "r_elbow_flex_joint=-1.0",
        "r_wrist_flex_joint=-0.6",
        "l_shoulder_pan_joint=1.5",
        "l_elbow_flex_joint=-2.0",
        "l_wrist_flex_joint=-0.5",
    ] {
        args.push("--joint".into());
        args.push(j.into());
    }
    let refs: Vec<&str> = args.iter().map(String::as_str).collect();
    let out = tabula(&refs);
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap_or_else(|_| {
        panic!("{}", String::from_utf8_lossy(&out.stderr));
    });
    let removed = v["self_filtered_points"].as_u64().unwrap_or(0);
    assert!(removed > 5000, "only {removed} robot points removed");
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

/// A frame written in the world with the camera's pose as `VIEWPOINT` needs no pose on
/// the command line and gives what the optical frame with the pose gives; a real Kinect
/// frame (optical points, PCL's flipped `VIEWPOINT`) needs nothing at all.
#[test]
fn perceive_reads_viewpoint_and_real_frames_need_no_pose() {
    let dir = std::env::temp_dir().join(format!("tabula-viewpoint-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let scene = concat!(env!("CARGO_MANIFEST_DIR"), "/../../scenes/clutter.toml");
    let (world, optical) = (dir.join("world.pcd"), dir.join("optical.pcd"));
    let capture = |out: &std::path::Path, world: bool| {
        let mut args = vec![
            "sim",
            "capture",
            "--scene",
            scene,
            "--binary",
            "--out",
            out.to_str().unwrap(),
        ];
        if world {
            args.push("--world");
        }
        let o = tabula(&args);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        String::from_utf8_lossy(&o.stdout).to_string()
    };
    capture(&world, true);
    let printed = capture(&optical, false);
    // The capture prints the pose as `--world-from-camera x y z qx qy qz qw`.
    let pose: Vec<String> = printed
        .split("--world-from-camera ")
        .nth(1)
        .unwrap()
        .split(')')
        .next()
        .unwrap()
        .split_whitespace()
        .map(str::to_string)
        .collect();
    let v = tabula_json(&["perceive", "--cloud", world.to_str().unwrap(), "--json"]);
    assert_eq!(v["frame"]["source"], "viewpoint");
    let mut args = vec!["perceive", "--cloud", optical.to_str().unwrap(), "--json"];
    args.push("--world-from-camera");
    args.extend(pose.iter().map(String::as_str));
    let w = tabula_json(&args);
    assert_eq!(w["frame"]["source"], "given_pose");
    // The same objects, up to the f32 rounding of points stored in another frame.
    let centres = |v: &serde_json::Value| -> Vec<[f64; 3]> {
        v["objects"]
            .as_array()
            .unwrap()
            .iter()
            .map(|o| {
                let c = &o["centroid"];
                [0, 1, 2].map(|k| c[k].as_f64().unwrap())
            })
            .collect()
    };
    let (a, b) = (centres(&v), centres(&w));
    assert_eq!(a.len(), 7);
    assert_eq!(a.len(), b.len());
    for (p, q) in a.iter().zip(&b) {
        assert!((0..3).all(|k| (p[k] - q[k]).abs() < 1e-3), "{p:?} {q:?}");
    }
    let real = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../data/real/kinect_laptop_box.pcd"
    );
    let r = tabula_json(&["perceive", "--cloud", real, "--json"]);
    assert_eq!(r["frame"]["source"], "support");
    assert_eq!(r["objects"].as_array().unwrap().len(), 3);
    assert!(r["objects"][0]["color"].is_array());
    // Every horizontal surface in reach is listed, counted from the support when the
    // frame is built on it: the carpet itself (z = 0) and the box's lid 9 cm above it.
    let heights: Vec<(f64, f64)> = r["surfaces"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| {
            (
                s["centroid"][2].as_f64().unwrap(),
                s["area"].as_f64().unwrap(),
            )
        })
        .collect();
    assert!(
        heights.iter().any(|&(z, a)| z.abs() < 0.01 && a > 1.0),
        "{heights:?}"
    );
    assert!(
        heights.iter().any(|&(z, _)| (z - 0.087).abs() < 0.01),
        "{heights:?}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// NaN and infinite options of `perceive` are refused with one line, not turned into a
/// wrong placement.
#[test]
fn perceive_refuses_non_finite_options() {
    let real = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../data/real/kinect_laptop_box.pcd"
    );
    for bad in [
        &["--place", "0.1", "0.1", "--margin", "nan"][..],
        &["--place", "0.1", "0.1", "--near", "nan", "0", "0"],
        &["--robot", "wam", "--joint", "wam_joint2=inf"],
        &["--up", "0", "nan", "0"],
        &["--up", "0", "0", "0"],
    ] {
        let mut args = vec!["perceive", "--cloud", real];
        args.extend_from_slice(bad);
        let out = tabula(&args);
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{bad:?} was accepted");
        assert!(
            err.lines().count() == 1 && !err.contains("panicked"),
            "{bad:?}: {err}"
        );
    }
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
