//! `perceive --labels` (a segmentation as PCL's labelled cloud) and `perceive --score`
//! (against a ground truth as PCD or PNG), on a simulated frame whose labels the
//! simulator knows.

use super::cli::{printed_camera_pose, tabula, tabula_ok};
use std::path::{Path, PathBuf};
use std::process::Command;

/// A settled frame of `scenes/clutter.toml`, its objects' labels as PCD, and the
/// camera pose `perceive` needs.
fn frame(dir: &Path) -> (PathBuf, PathBuf, Vec<String>) {
    let scene = concat!(env!("CARGO_MANIFEST_DIR"), "/../../scenes/clutter.toml");
    let (cloud, truth) = (dir.join("frame.pcd"), dir.join("truth.pcd"));
    let out = tabula_ok(&[
        "sim",
        "capture",
        "--scene",
        scene,
        "--settle",
        "--binary",
        "--out",
        cloud.to_str().unwrap(),
        "--labels",
        truth.to_str().unwrap(),
    ]);
    (cloud, truth, printed_camera_pose(&out.stdout))
}

#[test]
fn a_segmentation_written_as_labels_and_scored_against_the_truth() {
    let dir = std::env::temp_dir().join(format!("tabula-labels-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let (cloud, truth, pose) = frame(&dir);
    let labels = dir.join("segments.pcd");
    let mut args = vec!["perceive", "--cloud", cloud.to_str().unwrap()];
    args.push("--world-from-camera");
    args.extend(pose.iter().map(String::as_str));
    let base = args.clone();
    args.extend(["--labels", labels.to_str().unwrap(), "--score"]);
    args.extend([truth.to_str().unwrap(), "--truth-format", "plain", "--json"]);
    let out = tabula_ok(&args);
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("json");
    let objects = v["objects"].as_array().expect("objects");
    assert_eq!(objects.len(), 7, "the seven objects of the scene");
    let score = &v["score"];
    assert_eq!(score["objects"], 7);
    assert_eq!(score["found_iou50"], 7, "{score}");
    assert_eq!(score["extra_segments"], 0, "{score}");
    assert!(score["f_measure"].as_f64().unwrap() > 0.85, "{score}");

    // The labelled cloud: the input's grid, segment k has `objects[k - 1]`'s points.
    let file = tabula_geom::read_pcd_file(&std::fs::read(&labels).unwrap()).unwrap();
    assert_eq!((file.cloud.width, file.cloud.height), (640, 480));
    let written = file.labels.expect("a label field");
    for o in objects {
        let k = o["label"].as_u64().unwrap() as u32;
        let n = written.iter().filter(|&&l| l == k).count();
        assert_eq!(n as u64, o["points"].as_u64().unwrap(), "segment {k}");
    }
    read_back_by_pcl(&labels, &written);
    // Scored against itself, the segmentation is perfect.
    let mut again = base.clone();
    again.extend([
        "--score",
        labels.to_str().unwrap(),
        "--truth-format",
        "plain",
    ]);
    let out = tabula(&again);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("precision 1.000, recall 1.000, F 1.000"),
        "{text}"
    );

    // The same truth as a 16-bit PNG of labels (OCID's kind of file).
    let gt = tabula_geom::read_pcd_file(&std::fs::read(&truth).unwrap()).unwrap();
    let raw: Vec<u16> = gt.labels.unwrap().iter().map(|&l| l as u16).collect();
    let png = dir.join("truth.png");
    image::ImageBuffer::<image::Luma<u16>, _>::from_raw(640, 480, raw)
        .unwrap()
        .save(&png)
        .unwrap();
    let mut from_png = base.clone();
    from_png.extend(["--score", png.to_str().unwrap(), "--json"]);
    let out = tabula(&from_png);
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).expect("json");
    assert_eq!(v["score"]["found_iou50"], 7, "{}", v["score"]);

    // A truth on another grid, or without labels, is refused by name.
    let small = dir.join("small.png");
    image::GrayImage::new(10, 10).save(&small).unwrap();
    let mut wrong = base.clone();
    wrong.extend(["--score", small.to_str().unwrap()]);
    let err = String::from_utf8_lossy(&tabula(&wrong).stderr).to_string();
    assert!(
        err.contains("10 × 10") && err.contains("640 × 480"),
        "{err}"
    );
    let mut unlabelled = base;
    unlabelled.extend(["--score", cloud.to_str().unwrap()]);
    let err = String::from_utf8_lossy(&tabula(&unlabelled).stderr).to_string();
    assert!(err.contains("no `label` field"), "{err}");
    std::fs::remove_dir_all(&dir).ok();
}

/// With PCL's tools installed (`apt-get install pcl-tools`), PCL reads the labelled
/// cloud: it converts it to ASCII with the `label` channel and every label kept.
fn read_back_by_pcl(labels: &Path, written: &[u32]) {
    let ascii = labels.with_extension("ascii.pcd");
    let Ok(out) = Command::new("pcl_convert_pcd_ascii_binary")
        .args([labels.to_str().unwrap(), ascii.to_str().unwrap(), "0"])
        .output()
    else {
        eprintln!("pcl_convert_pcd_ascii_binary not installed: PCL's read-back skipped");
        return;
    };
    let said =
        String::from_utf8_lossy(&out.stdout).to_string() + &String::from_utf8_lossy(&out.stderr);
    assert!(said.contains("channels: x y z label"), "{said}");
    let text = std::fs::read_to_string(&ascii).unwrap();
    let body = text.split("DATA ascii\n").nth(1).expect("PCL's ascii body");
    let read: Vec<u32> = body
        .lines()
        .map(|l| l.split_whitespace().nth(3).unwrap().parse().unwrap())
        .collect();
    assert_eq!(read, written, "PCL's labels");
}
