//! Ctrl+C in the middle of a run: the robot holds where it is, the run ends with status
//! 130, and the scene written with `--save-scene` loads and settles.

use std::io::{BufRead, BufReader};
use std::process::{Command, Stdio};
use tabula_sim::{PhysicsParams, Scene, SimWorld};

/// Runs `tabula ARGS -v --save-scene OUT`, sends SIGINT once a stderr line contains
/// `when` (so the stop lands mid-run, whatever the machine's speed), and returns the
/// exit status and the saved scene's path.
fn interrupt(name: &str, args: &[&str], when: &str) -> (Option<i32>, std::path::PathBuf, String) {
    let dir = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("stop");
    std::fs::create_dir_all(&dir).unwrap();
    let saved = dir.join(format!("{name}.toml"));
    let _ = std::fs::remove_file(&saved);
    let mut child = Command::new(env!("CARGO_BIN_EXE_tabula"))
        .args(args)
        .arg("-v")
        .arg("--save-scene")
        .arg(&saved)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run tabula");
    let stderr = child.stderr.take().unwrap();
    let mut seen = String::new();
    let mut sent = false;
    for line in BufReader::new(stderr).lines() {
        let line = line.unwrap();
        seen.push_str(&line);
        seen.push('\n');
        if !sent && line.contains(when) {
            // SAFETY: signalling our own child process by its id.
            unsafe {
                libc::kill(child.id() as libc::pid_t, libc::SIGINT);
            }
            sent = true;
        }
    }
    assert!(sent, "the run never printed `{when}`:\n{seen}");
    let status = child.wait().unwrap();
    (status.code(), saved, seen)
}

fn loads_and_settles(path: &std::path::Path) {
    let scene = Scene::load(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut world = SimWorld::from_scene(&scene, PhysicsParams::default()).unwrap();
    let report = world.settle();
    assert!(report.all_asleep, "the saved world does not come to rest");
}

#[test]
fn ctrl_c_stops_a_clearing_run_and_saves_the_scene() {
    let (status, saved, log) = interrupt(
        "clear",
        &["clear", "--scene", "../../scenes/clutter.toml"],
        "clear: action",
    );
    assert_eq!(status, Some(130), "{log}");
    assert!(log.contains("stopping"), "{log}");
    loads_and_settles(&saved);
}

#[test]
fn ctrl_c_stops_a_placing_run_and_saves_the_scene() {
    let (status, saved, log) = interrupt(
        "place",
        &["place", "--scene", "../../scenes/pr2_holding.toml"],
        "phase=\"model object\"",
    );
    assert_eq!(status, Some(130), "{log}");
    loads_and_settles(&saved);
    // It still holds the cup: the stop let go of nothing.
    let scene = Scene::load(&saved).unwrap();
    let text = std::fs::read_to_string(&saved).unwrap();
    assert!(
        text.contains("hold"),
        "the saved scene lost the grip:\n{text}"
    );
    assert!(!scene.objects.is_empty());
}
