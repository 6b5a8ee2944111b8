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

/// A loopback endpoint nothing listens on (yet).
fn free_endpoint() -> String {
    let port = TcpListener::bind("127.0.0.1:0")
        .and_then(|l| l.local_addr())
        .unwrap()
        .port();
    format!("tcp/127.0.0.1:{port}")
}

/// `tabula serve` on a free loopback port, once it says it serves; killed on drop.
struct Served {
    child: Child,
    endpoint: String,
}

impl Served {
    fn start(scene_file: &str, save: &Path) -> Self {
        let endpoint = free_endpoint();
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
fn tidying_through_zenoh_ends_as_in_one_process() {
    let file = one_item_tidy();
    let served = Served::start(&file, &tmp("tidy_served_end.toml"));
    let (status, remote) = run_json(&["tidy", "--scene", &file, "--connect", &served.endpoint]);
    assert_eq!(status, Some(0), "{remote}");
    let (_, local) = run_json(&["tidy", "--scene", &file]);
    for key in ["success", "objects", "moved", "actions"] {
        assert_eq!(remote[key], local[key], "{key}");
    }
    assert_eq!(remote["objects"], remote["moved"]);
    assert_eq!(remote["verdict"]["knocked"], serde_json::json!([]));
}

/// The shipped tidy task with one of its four items (and the other table's resident,
/// which must stay standing): the transport is what is compared; tidying all four runs
/// a minute and a half twice, and the tasks' own tests tidy whole tables.
fn one_item_tidy() -> String {
    let text = std::fs::read_to_string(scene("tidy.toml")).unwrap();
    let mut world: toml::Table = toml::from_str(&text).unwrap();
    let Some(toml::Value::Array(objects)) = world.get_mut("object") else {
        panic!("tidy.toml has no objects");
    };
    objects.retain(|o| matches!(o["name"].as_str(), Some("item0" | "resident0")));
    assert_eq!(objects.len(), 2);
    let file = tmp("tidy_one_item.toml");
    std::fs::write(&file, toml::to_string(&world).unwrap()).unwrap();
    file.display().to_string()
}

#[test]
fn connecting_to_nothing_is_a_clear_error() {
    let out = Command::new(env!("CARGO_BIN_EXE_tabula"))
        .args(["place", "--scene", &scene("pr2_holding.toml"), "--connect"])
        .arg(free_endpoint())
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

/// A JSON service of the served robot, called as any ROS 2 node would.
fn call(node: &tabula_ros::node::Node, name: &str, request: Value) -> (bool, Value) {
    use tabula_ros::msgs::{CallRequest, CallResponse};
    let client = node
        .client::<CallRequest, CallResponse>(name, "tabula_msgs/srv/Call")
        .unwrap();
    client
        .wait_for_server(0, std::time::Duration::from_secs(10))
        .unwrap();
    let r = client
        .call(
            &CallRequest {
                request: request.to_string(),
            },
            std::time::Duration::from_secs(30),
        )
        .unwrap();
    let v = serde_json::from_str(&r.response).unwrap_or(Value::String(r.response));
    (r.ok, v)
}

#[test]
fn the_served_robot_answers_ik_stable_poses_plans_and_perception() {
    use tabula_ros::node::{Mode, Node, NodeConfig};
    let served = Served::start(&scene("pr2_holding.toml"), &tmp("services_end.toml"));
    let mut config = NodeConfig::new("tabula_test", Mode::Client);
    config.connect = vec![served.endpoint.clone()];
    let node = Node::open(config).unwrap();

    // IK of a pose the right arm reaches (its FK at mid-range), in its base frame.
    let pr2 = tabula_robot::robots::load("pr2").unwrap();
    let chain = pr2
        .description
        .arm("right")
        .unwrap()
        .chain(&pr2.model)
        .unwrap();
    let target = chain.fk(&chain.mid_configuration()).unwrap();
    let (t, q) = (target.translation, target.rotation);
    let (ok, ik) = call(
        &node,
        "/tabula/ik",
        serde_json::json!({"arm": "right", "pose": [t.x, t.y, t.z, q.x, q.y, q.z, q.w]}),
    );
    assert!(ok, "{ik}");
    let best = &ik["solutions"][0];
    assert!(best["position_error_m"].as_f64().unwrap() < 1e-3, "{ik}");
    let joints = pose(&best["joints"]);
    let reached = chain.fk(&joints).unwrap();
    assert!(reached.translation.distance(t) < 1e-3);
    let (ok, bad) = call(
        &node,
        "/tabula/ik",
        serde_json::json!({"arm": "tail", "pose": [0, 0, 0, 0, 0, 0, 1]}),
    );
    assert!(!ok && bad.to_string().contains("no arm `tail`"), "{bad}");

    // Stable poses of a 4 × 2 × 1 cm box's corners: six faces, most likely the largest.
    let mut corners = Vec::new();
    for x in [-0.02, 0.02] {
        for y in [-0.01, 0.01] {
            for z in [-0.005, 0.005] {
                corners.push([x, y, z]);
            }
        }
    }
    let (ok, poses) = call(
        &node,
        "/tabula/stable_poses",
        serde_json::json!({"points": corners}),
    );
    assert!(ok, "{poses}");
    let list = poses["poses"].as_array().unwrap();
    assert_eq!(list.len(), 6);
    let sum: f64 = list
        .iter()
        .map(|p| p["probability"].as_f64().unwrap())
        .sum();
    assert!((sum - 1.0).abs() < 1e-6);
    let (ok, _) = call(
        &node,
        "/tabula/stable_poses",
        serde_json::json!({"points": [[0, 0, 0]]}),
    );
    assert!(!ok);

    // A plan for the seed's first problem, with its domain.
    let pddl = |f: &str| {
        std::fs::read_to_string(format!("{}/../../pddl/{f}", env!("CARGO_MANIFEST_DIR"))).unwrap()
    };
    let (ok, plan) = call(
        &node,
        "/tabula/plan",
        serde_json::json!({"domain": pddl("tablewclear-domain-fixed.pddl"), "problem": pddl("thesis6-a.pddl")}),
    );
    assert!(ok, "{plan}");
    assert_eq!(plan["status"], "solved");
    assert!(!plan["plan"].as_array().unwrap().is_empty());
    let (ok, _) = call(
        &node,
        "/tabula/plan",
        serde_json::json!({"domain": "(define", "problem": ""}),
    );
    assert!(!ok);

    // Perception of a frame the served camera took, sent back as a PointCloud2.
    use tabula_ros::msgs::CallResponse;
    use tabula_ros::protocol::{CaptureRequest, CaptureResponse, PerceiveRequest};
    let capture = node
        .client::<CaptureRequest, CaptureResponse>("/tabula/capture", "tabula_msgs/srv/Capture")
        .unwrap();
    let frame = capture
        .call(
            &CaptureRequest {
                camera: "head".into(),
            },
            std::time::Duration::from_secs(30),
        )
        .unwrap();
    assert!(frame.ok, "{}", frame.error);
    let perceive = node
        .client::<PerceiveRequest, CallResponse>("/tabula/perceive", "tabula_msgs/srv/Perceive")
        .unwrap();
    let r = perceive
        .call(
            &PerceiveRequest {
                cloud: frame.cloud,
                has_pose: true,
                world_from_cloud: frame.world_from_camera,
            },
            std::time::Duration::from_secs(30),
        )
        .unwrap();
    assert!(r.ok, "{}", r.response);
    let seen: Value = serde_json::from_str(&r.response).unwrap();
    let height = seen["table"]["height"].as_f64().unwrap();
    assert!((height - 0.74).abs() < 0.03, "table at {height}");

    // A ROS 2 controller's way in: a JointTrajectory on /right/joint_trajectory moves
    // the arm (as joint_trajectory_controller's topic does).
    let joint = |node: &tabula_ros::node::Node| -> f64 {
        let (ok, state) = call(
            node,
            "/tabula/driver",
            serde_json::json!({"op": "joint_state"}),
        );
        assert!(ok, "{state}");
        let names = state["names"].as_array().unwrap();
        let k = names
            .iter()
            .position(|n| n == "r_shoulder_pan_joint")
            .unwrap();
        state["positions"][k].as_f64().unwrap()
    };
    let before = joint(&node);
    let publisher = node
        .publisher::<tabula_ros::msgs::JointTrajectory>(
            "/right/joint_trajectory",
            "trajectory_msgs/msg/JointTrajectory",
            tabula_ros::wire::Qos::default(),
        )
        .unwrap();
    let trajectory = tabula_robot::driver::JointTrajectory {
        joint_names: vec!["r_shoulder_pan_joint".into()],
        times: vec![0.0, 0.5],
        positions: vec![vec![before], vec![before + 0.2]],
    };
    let msg = tabula_ros::msgs::JointTrajectory::from_trajectory(&trajectory, Default::default());
    let deadline = std::time::Instant::now() + std::time::Duration::from_secs(10);
    while (joint(&node) - (before + 0.2)).abs() > 1e-3 {
        assert!(std::time::Instant::now() < deadline, "the arm never moved");
        publisher.publish(&msg).unwrap();
        std::thread::sleep(std::time::Duration::from_millis(300));
    }

    // `tabula graph` lists what is served, as `ros2 node list` / `topic list -t` would.
    let out = Command::new(env!("CARGO_BIN_EXE_tabula"))
        .args(["graph", "--json", "--connect", &served.endpoint])
        .output()
        .unwrap();
    let graph: Value = serde_json::from_slice(&out.stdout).unwrap();
    assert!(
        graph["nodes"]
            .as_array()
            .unwrap()
            .iter()
            .any(|n| n == "/tabula_sim"),
        "{graph}"
    );
    assert_eq!(
        graph["topics"]["/head/points"]["types"][0],
        "sensor_msgs/msg/PointCloud2"
    );
    assert_eq!(graph["services"]["/tabula/ik"]["servers"], 1);
}

/// `tabula worker` processes joined to a bench that listens: the rows are the ones the
/// same seeds give in one process.
#[test]
fn trials_spread_over_workers_give_the_single_process_rows() {
    let endpoint = free_endpoint();
    let workers: Vec<Child> = (0..2)
        .map(|_| {
            Command::new(env!("CARGO_BIN_EXE_tabula"))
                .args(["worker", "--connect", &endpoint, "--duration", "120"])
                .stderr(Stdio::null())
                .spawn()
                .unwrap()
        })
        .collect();
    let bench = [
        "bench", "clear", "--suite", "random", "--scenes", "3", "--seed", "40",
    ];
    let spread: Vec<&str> = bench
        .iter()
        .copied()
        .chain(["--workers", "2", "--listen", &endpoint])
        .collect();
    let (status, remote) = run_json(&spread);
    let (_, local) = run_json(&bench);
    for mut w in workers {
        let _ = w.kill();
        let _ = w.wait();
    }
    assert_eq!(status, Some(0), "{remote}");
    for key in [
        "objects",
        "removed",
        "actions",
        "grasps",
        "pushes",
        "collisions",
    ] {
        assert_eq!(remote[key], local[key], "{key}");
    }
    let seeds = |v: &Value| -> Vec<u64> {
        v["rows"]
            .as_array()
            .unwrap()
            .iter()
            .map(|r| r["seed"].as_u64().unwrap())
            .collect()
    };
    assert_eq!(seeds(&remote), [40, 41, 42]);
    assert_eq!(seeds(&remote), seeds(&local));
}
