//! Recording a run for reports: every body's triangles once, poses of what moves at
//! the recorder's rate, and pictures when a robot lets go of what it holds.

use std::sync::Arc;
use tabula_robot::driver::{Arms, Grippers, JointStates, JointTrajectory};
use tabula_sim::replay::{Recorder, RecorderParams, default_eyes};
use tabula_sim::{PhysicsParams, Scene, SimDriver, SimWorld};

fn holding() -> SimWorld {
    let scene = Scene::parse(
        include_str!("../../../../scenes/pr2_holding.toml"),
        "scenes/pr2_holding.toml",
    )
    .unwrap();
    SimWorld::from_scene(&scene, PhysicsParams::default()).unwrap()
}

#[test]
fn a_recorded_run_has_shapes_motion_and_the_release() {
    let mut driver = SimDriver::new(holding(), "pr2", 0).unwrap();
    let eyes = default_eyes(&driver.world);
    assert!(eyes.iter().any(|e| e.name == "overview"));
    let params = RecorderParams {
        rate_hz: 10.0,
        picture_size: (64, 48),
    };
    let (shared, feed) = Recorder::new(&driver.world, eyes.clone(), params).shared();
    driver.observe(feed);

    // Move the right arm a little over 1 s, then open its gripper.
    let state = driver.joint_state().unwrap();
    let names = ["r_shoulder_pan_joint", "r_elbow_flex_joint"];
    let start: Vec<f64> = names
        .iter()
        .map(|n| state.positions[state.names.iter().position(|m| m == n).unwrap()])
        .collect();
    let goal = vec![start[0] + 0.2, start[1] - 0.1];
    driver
        .execute(&JointTrajectory {
            joint_names: names.iter().map(|n| n.to_string()).collect(),
            times: vec![0.0, 1.2],
            positions: vec![start, goal],
        })
        .unwrap();
    driver.open("right_gripper").unwrap();
    drop(driver);

    let recorder = Arc::try_unwrap(shared).ok().unwrap().into_inner().unwrap();
    let (replay, moments) = recorder.finish();

    // Shapes: every body has triangles indexing its own vertices; furniture is fixed.
    assert!(
        replay
            .bodies
            .iter()
            .any(|b| b.kind == "furniture" && b.fixed)
    );
    assert!(replay.bodies.iter().any(|b| b.kind == "robot" && !b.fixed));
    for b in &replay.bodies {
        let n = (b.vertices.len() / 3) as u32;
        assert!(n > 0 && !b.triangles.is_empty(), "{} has no mesh", b.name);
        assert!(b.triangles.iter().all(|&i| i < n), "{}", b.name);
    }
    // Motion: about 10 frames a simulated second, each with a pose per moving body.
    assert!(replay.frames.len() >= 12, "{} frames", replay.frames.len());
    assert!(replay.times.windows(2).all(|w| w[1] > w[0]));
    for f in &replay.frames {
        assert_eq!(f.len(), 7 * replay.moving.len());
    }
    // The release is a moment, with a picture from every eye that is not one colour.
    assert_eq!(moments.len(), 1, "{:?}", replay.marks);
    assert!(
        moments[0].label.contains("lets go of cup"),
        "{}",
        moments[0].label
    );
    assert_eq!(moments[0].pictures.len(), eyes.len());
    for (eye, img) in &moments[0].pictures {
        let first = img.get_pixel(0, 0);
        assert!(
            img.pixels().any(|p| p != first),
            "a flat picture from {eye}"
        );
    }
}
