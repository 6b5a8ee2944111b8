//! Two processes on loopback: the simulator served by `tabula serve`, the task run by
//! `tabula place|clear|pick-place --connect` through the zenoh driver — the same outcome
//! as the same task in one process.

#![cfg(feature = "ros")]

use serde_json::Value;
use std::io::{BufRead, BufReader};
use std::net::TcpListener;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};

fn scene(name: &str) -> String {
    format!("{}/../../scenes/{name}", env!("CARGO_MANIFEST_DIR"))
}

fn tmp(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("ros");
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

/// `tabula serve` on a free loopback port, once it says it serves; killed on drop.
struct Served {
    child: Child,
    endpoint: String,
}

impl Served {
    fn start(scene_file: &str, save: &Path) -> Self {
        let port = TcpListener::bind("127.0.0.1:0")
            .and_then(|l| l.local_addr())
            .unwrap()
            .port();
        let endpoint = format!("tcp/127.0.0.1:{port}");
        let mut child = Command::new(env!("CARGO_BIN_EXE_tabula"))
            .args(["serve", "--scene", scene_file, "--listen", &endpoint])
            .args(["--camera-hz", "0.5", "--save-scene"])
            .arg(save)
            .stderr(Stdio::piped())
            .spawn()
            .expect("run tabula serve");
        let stderr = child.stderr.take().unwrap();
        let mut lines = BufReader::new(stderr).lines();
        let first = lines.next().and_then(Result::ok).unwrap_or_default();
        assert!(first.contains("serving `"), "serve said: {first}");
        // Keep draining stderr so the server never blocks on a full pipe.
        std::thread::spawn(move || for _ in lines {});
        Self { child, endpoint }
    }

    /// Ctrl+C: the server stops, writes its world, and ends with status 130.
    fn stop(mut self) -> Option<i32> {
        // SAFETY: signalling our own child process by its id.
        unsafe {
            libc::kill(self.child.id() as libc::pid_t, libc::SIGINT);
        }
        self.child.wait().ok().and_then(|s| s.code())
    }
}

impl Drop for Served {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

fn run_json(args: &[&str]) -> (Option<i32>, Value) {
    let out = Command::new(env!("CARGO_BIN_EXE_tabula"))
        .args(args)
        .arg("--json")
        .output()
        .expect("run tabula");
    let json = serde_json::from_slice(&out.stdout).unwrap_or_else(|e| {
        panic!(
            "{args:?}: no JSON ({e}); stderr: {}",
            String::from_utf8_lossy(&out.stderr)
        )
    });
    (out.status.code(), json)
}

fn pose(v: &Value) -> Vec<f64> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect()
}

#[test]
fn placing_through_zenoh_ends_as_in_one_process() {
    let file = scene("pr2_holding.toml");
    let served_end = tmp("place_served_end.toml");
    let served = Served::start(&file, &served_end);
    let remote_scene = tmp("place_remote.toml");
    let (status, remote) = run_json(&[
        "place",
        "--scene",
        &file,
        "--connect",
        &served.endpoint,
        "--save-scene",
        remote_scene.to_str().unwrap(),
    ]);
    assert_eq!(status, Some(0), "{remote}");
    let (_, local) = run_json(&["place", "--scene", &file]);
    assert_eq!(remote["success"], true);
    assert_eq!(remote["success"], local["success"]);
    assert_eq!(remote["surface"], local["surface"]);
    // Frames cross the wire as float32 (as every ROS 2 point cloud): the plan can
    // differ by the rounding, nothing more.
    let (r, l) = (pose(&remote["final_pose"]), pose(&local["final_pose"]));
    let dist = ((r[0] - l[0]).powi(2) + (r[1] - l[1]).powi(2) + (r[2] - l[2]).powi(2)).sqrt();
    assert!(dist < 1e-3, "{r:?} vs {l:?}");
    let dq = (r[3] * l[3] + r[4] * l[4] + r[5] * l[5] + r[6] * l[6]).abs();
    assert!(dq > (0.25f64.to_radians() / 2.0).cos(), "{r:?} vs {l:?}");
    let (rn, ln) = (
        pose(&remote["stable_pose"]["support_normal"]),
        pose(&local["stable_pose"]["support_normal"]),
    );
    assert!(rn[0] * ln[0] + rn[1] * ln[1] + rn[2] * ln[2] > 0.9999);
    // The served world saved by the task client is where the cup now rests.
    let saved = std::fs::read_to_string(&remote_scene).unwrap();
    assert!(saved.contains("cup"), "{saved}");

    // The same robot holds nothing now: a second placing run is refused by its judge.
    let out = Command::new(env!("CARGO_BIN_EXE_tabula"))
        .args(["place", "--scene", &file, "--connect", &served.endpoint])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("holds nothing"), "{err}");
    assert_eq!(err.trim().lines().count(), 1, "{err}");

    assert_eq!(served.stop(), Some(130));
    let end = tabula_sim::Scene::load(&served_end).unwrap();
    tabula_sim::SimWorld::from_scene(&end, Default::default()).unwrap();
}

#[test]
fn clearing_through_zenoh_ends_as_in_one_process() {
    let file = scene("clutter.toml");
    let served = Served::start(&file, &tmp("clear_served_end.toml"));
    let (status, remote) = run_json(&["clear", "--scene", &file, "--connect", &served.endpoint]);
    assert_eq!(status, Some(0), "{remote}");
    let (_, local) = run_json(&["clear", "--scene", &file]);
    for key in [
        "success",
        "objects",
        "removed",
        "grasps",
        "pushes",
        "collisions",
    ] {
        assert_eq!(remote[key], local[key], "{key}");
    }
    assert_eq!(remote["verdict"]["in_bin"], local["verdict"]["in_bin"]);
    assert_eq!(remote["verdict"]["objects"], remote["verdict"]["in_bin"]);
}

#[test]
fn connecting_to_nothing_is_a_clear_error() {
    let port = TcpListener::bind("127.0.0.1:0")
        .and_then(|l| l.local_addr())
        .unwrap()
        .port();
    let out = Command::new(env!("CARGO_BIN_EXE_tabula"))
        .args(["place", "--scene", &scene("pr2_holding.toml"), "--connect"])
        .arg(format!("tcp/127.0.0.1:{port}"))
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("cannot reach the robot"), "{err}");
    let out = Command::new(env!("CARGO_BIN_EXE_tabula"))
        .args(["place", "--scene", &scene("pr2_holding.toml")])
        .args(["--connect", "not an endpoint"])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
}
