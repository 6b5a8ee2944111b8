//! `tabula teleop` driven in a real terminal (tmux: send-keys, capture-pane): a key
//! moves the tool by the step in the base frame, another in the tool's own frame, a
//! step that cannot be made is refused with its reason, and quitting restores the
//! terminal. Needs tmux (`.ci/run` installs it and sets `TABULA_REQUIRE_TMUX=1`).

use std::process::Command;
use std::time::{Duration, Instant};

fn tmux(args: &[&str]) -> String {
    let out = Command::new("tmux").args(args).output().expect("run tmux");
    String::from_utf8_lossy(&out.stdout).to_string()
}

/// The screen once `pred` holds (or after 60 s, failing with the screen).
fn screen_when(session: &str, what: &str, pred: impl Fn(&str) -> bool) -> String {
    let t0 = Instant::now();
    loop {
        let s = tmux(&["capture-pane", "-p", "-t", session]);
        if pred(&s) {
            return s;
        }
        assert!(
            t0.elapsed() < Duration::from_secs(60),
            "waited for {what}; the screen:\n{s}"
        );
        std::thread::sleep(Duration::from_millis(100));
    }
}

/// Numbers after `label` on the screen's line that has it.
fn numbers(screen: &str, label: &str) -> Vec<f64> {
    let line = screen
        .lines()
        .find(|l| l.contains(label))
        .unwrap_or_else(|| panic!("no `{label}` on the screen:\n{screen}"));
    line[line.find(label).unwrap() + label.len()..]
        .split(|c: char| !(c.is_ascii_digit() || c == '.' || c == '-' || c == '+'))
        .filter_map(|w| w.parse::<f64>().ok())
        .collect()
}

fn last_line(screen: &str) -> String {
    screen
        .lines()
        .find(|l| l.contains("last:"))
        .map(|l| {
            l.trim_matches(|c: char| c == '│' || c.is_whitespace())
                .to_string()
        })
        .unwrap_or_default()
}

#[test]
fn keys_step_the_tool_in_the_right_frame_and_quitting_restores_the_terminal() {
    if Command::new("tmux").arg("-V").output().is_err() {
        assert!(
            std::env::var_os("TABULA_REQUIRE_TMUX").is_none(),
            "TABULA_REQUIRE_TMUX is set but tmux is missing"
        );
        eprintln!("skipped: no tmux (apt-get install tmux)");
        return;
    }
    let session = format!("tabula-teleop-{}", std::process::id());
    let command = format!(
        "sh -c '{} teleop --scene ../../scenes/clutter.toml; echo EXIT=$?; stty -a | grep -o -- \"-\\?icanon\"; sleep 120'",
        env!("CARGO_BIN_EXE_tabula")
    );
    let started = Command::new("tmux")
        .args([
            "new-session",
            "-d",
            "-s",
            &session,
            "-x",
            "120",
            "-y",
            "40",
            &command,
        ])
        .status()
        .unwrap();
    assert!(started.success());
    let kill = || {
        let _ = Command::new("tmux")
            .args(["kill-session", "-t", &session])
            .status();
    };
    let run = std::panic::catch_unwind(|| {
        let s0 = screen_when(&session, "the UI", |s| s.contains("tool (base)"));
        let p0 = numbers(&s0, "tool (base):");
        let axis = numbers(&s0, "tool x axis (base):");

        // w: +x by the 1 cm step in the base frame.
        tmux(&["send-keys", "-t", &session, "w"]);
        let s1 = screen_when(&session, "the +x step", |s| {
            s.contains("moved: +x 1.0 cm (base")
        });
        let p1 = numbers(&s1, "tool (base):");
        for (k, want) in [0.01, 0.0, 0.0].iter().enumerate() {
            assert!(
                (p1[k] - p0[k] - want).abs() < 5e-4,
                "base step: {p0:?} → {p1:?}"
            );
        }
        // t, w: +x of the tool's own frame, along its x axis.
        tmux(&["send-keys", "-t", &session, "t", "w"]);
        let s2 = screen_when(&session, "the tool-frame step", |s| {
            s.contains("moved: +x 1.0 cm (tool")
        });
        let p2 = numbers(&s2, "tool (base):");
        for k in 0..3 {
            assert!(
                (p2[k] - p1[k] - 0.01 * axis[k]).abs() < 5e-4,
                "tool step: {p1:?} → {p2:?}, axis {axis:?}"
            );
        }
        // h: the WAM has no torso to lower — refused, with the reason, nothing moved.
        tmux(&["send-keys", "-t", &session, "h"]);
        let s3 = screen_when(&session, "the refusal", |s| s.contains("refused"));
        assert!(
            last_line(&s3).contains("no torso lift"),
            "{}",
            last_line(&s3)
        );
        assert_eq!(numbers(&s3, "tool (base):"), p2);
        // Six doublings to a 50 cm step, then down through the stand and the table.
        tmux(&[
            "send-keys",
            "-t",
            &session,
            "t",
            "+",
            "+",
            "+",
            "+",
            "+",
            "+",
            "f",
            "f",
        ]);
        let s4 = screen_when(&session, "a refused long step", |s| {
            s.contains("refused: -z 50.0 cm")
        });
        assert!(
            last_line(&s4).len() > "last: refused: -z 50.0 cm: ".len(),
            "{}",
            last_line(&s4)
        );
        // q: the UI ends and the shell's terminal is back in cooked mode.
        tmux(&["send-keys", "-t", &session, "q"]);
        let s5 = screen_when(&session, "the exit", |s| s.contains("icanon"));
        assert!(s5.contains("EXIT=0"), "{s5}");
        assert!(
            s5.lines().any(|l| l.trim() == "icanon"),
            "the terminal was not restored:\n{s5}"
        );
        assert!(
            !s5.contains("tabula teleop —"),
            "the UI is still on screen:\n{s5}"
        );
    });
    kill();
    if let Err(e) = run {
        std::panic::resume_unwind(e);
    }
}

/// A tmux session running `tabula teleop` on the PR2 holding its cup, saving the scene
/// on the way out; killed when dropped.
struct HoldingSession {
    name: String,
    saved: std::path::PathBuf,
}

impl HoldingSession {
    fn start(tag: &str) -> Option<Self> {
        if Command::new("tmux").arg("-V").output().is_err() {
            assert!(
                std::env::var_os("TABULA_REQUIRE_TMUX").is_none(),
                "TABULA_REQUIRE_TMUX is set but tmux is missing"
            );
            eprintln!("skipped: no tmux (apt-get install tmux)");
            return None;
        }
        let name = format!("tabula-teleop-{tag}-{}", std::process::id());
        let saved = std::env::temp_dir().join(format!("{name}.toml"));
        let _ = std::fs::remove_file(&saved);
        let command = format!(
            "sh -c '{} teleop --scene ../../scenes/pr2_holding.toml --save-scene {}; echo EXIT=$?; sleep 120'",
            env!("CARGO_BIN_EXE_tabula"),
            saved.display()
        );
        let started = Command::new("tmux")
            .args(["new-session", "-d", "-s", &name, "-x", "120", "-y", "40"])
            .arg(&command)
            .status()
            .unwrap();
        assert!(started.success());
        Some(Self { name, saved })
    }

    fn saved_scene(&self) -> toml::Table {
        std::fs::read_to_string(&self.saved)
            .expect("the scene was saved")
            .parse()
            .expect("the saved scene is TOML")
    }
}

impl Drop for HoldingSession {
    fn drop(&mut self) {
        let _ = Command::new("tmux")
            .args(["kill-session", "-t", &self.name])
            .status();
        let _ = std::fs::remove_file(&self.saved);
    }
}

fn cup_z(scene: &toml::Table) -> f64 {
    let objects = scene["object"].as_array().unwrap();
    let cup = objects
        .iter()
        .find(|o| o["name"].as_str() == Some("cup"))
        .unwrap();
    cup["pose"]["xyz"][2].as_float().unwrap()
}

fn holds(scene: &toml::Table) -> usize {
    scene
        .get("hold")
        .and_then(|h| h.as_array())
        .map_or(0, Vec::len)
        + scene["robot"]
            .as_array()
            .unwrap()
            .iter()
            .filter_map(|r| r.get("hold"))
            .count()
}

/// Ctrl+C in the UI stops and quits (exit 0) with the cup still held; `v` lets it go,
/// and the saved scene has it out of the hand, lower than where it was held.
#[test]
fn ctrl_c_quits_with_the_gripper_untouched_and_v_releases() {
    let held_z = {
        let Some(s) = HoldingSession::start("ctrlc") else {
            return;
        };
        let s0 = screen_when(&s.name, "the UI", |x| x.contains("tool (base)"));
        assert!(s0.contains("holding `cup`"), "{s0}");
        tmux(&["send-keys", "-t", &s.name, "C-c"]);
        let s1 = screen_when(&s.name, "the exit", |x| x.contains("EXIT="));
        assert!(s1.contains("EXIT=0"), "{s1}");
        let scene = s.saved_scene();
        assert_eq!(holds(&scene), 1, "the cup is no longer held:\n{scene}");
        cup_z(&scene)
    };
    let s = HoldingSession::start("release").unwrap();
    screen_when(&s.name, "the UI", |x| x.contains("holding `cup`"));
    tmux(&["send-keys", "-t", &s.name, "v"]);
    let s1 = screen_when(&s.name, "the release", |x| x.contains("released `cup`"));
    assert!(s1.contains("holding nothing"), "{s1}");
    tmux(&["send-keys", "-t", &s.name, "q"]);
    let s2 = screen_when(&s.name, "the exit", |x| x.contains("EXIT="));
    assert!(s2.contains("EXIT=0"), "{s2}");
    let scene = s.saved_scene();
    assert_eq!(holds(&scene), 0, "the cup is still held:\n{scene}");
    assert!(
        cup_z(&scene) < held_z - 0.005,
        "the cup did not drop: {held_z} → {}",
        cup_z(&scene)
    );
}
