//! `tabula perceive` as a user runs it: files, frames, the robot's own points, real
//! frames without a pose, bad options.

use super::cli::{printed_camera_pose, tabula, tabula_json, tabula_ok};

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
        let out = tabula_ok(&[
            "sim",
            "capture",
            "--scene",
            scene,
            "--settle",
            "--binary",
            "--out",
            out_path.to_str().unwrap(),
        ]);
        pose = printed_camera_pose(&out.stdout);
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
        let out = tabula_ok(&args);
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
    tabula_ok(&[
        "sim",
        "capture",
        "--scene",
        scene.to_str().unwrap(),
        "--binary",
        "--out",
        frame.to_str().unwrap(),
    ]);
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
        let out = tabula_ok(&args);
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
