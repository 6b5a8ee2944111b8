//! Driving a mobile base and pointing a head.

use tabula_geom::Vec3;
use tabula_sim::world::SimError;
use tabula_sim::{PhysicsParams, Scene, SimWorld};

const SCENE: &str = r#"
[floor]
[[furniture]]
name = "table"
kind = "table"
pose = { xyz = [2.0, 0.0, 0.0] }
size = [0.8, 1.2, 0.74]
[[robot]]
name = "pr2"
urdf = "pr2"
"#;

fn world() -> SimWorld {
    SimWorld::from_scene(
        &Scene::parse(SCENE, "m.toml").unwrap(),
        PhysicsParams::default(),
    )
    .unwrap()
}

#[test]
fn the_base_drives_and_stops_at_furniture() {
    let mut w = world();
    w.drive_base("pr2", 0.5, 0.3, 0.4).unwrap();
    let (x, y, t) = (
        w.joint("pr2", "base_x_joint").unwrap(),
        w.joint("pr2", "base_y_joint").unwrap(),
        w.joint("pr2", "base_theta_joint").unwrap(),
    );
    assert!((x - 0.5).abs() < 1e-9 && (y - 0.3).abs() < 1e-9 && (t - 0.4).abs() < 1e-9);
    let base = w.pose("pr2/base_link").unwrap();
    assert!((base.translation.x - 0.5).abs() < 1e-6 && (base.translation.y - 0.3).abs() < 1e-6);
    // Straight through the table: stopped at its edge (1.6 m), not inside.
    match w.drive_base("pr2", 2.0, 0.0, 0.0) {
        Err(SimError::Blocked { by, .. }) => assert_eq!(by, "table"),
        other => panic!("{other:?}"),
    }
    let x = w.joint("pr2", "base_x_joint").unwrap();
    assert!(x > 0.9 && x < 1.6 - 0.25, "stopped at x = {x}");
}

/// Up against the table, then back out the way it came: a goal straight behind with
/// the same heading is reached backing up — turning round there would sweep the arms
/// through the table.
#[test]
fn the_base_backs_away_from_a_table_without_turning() {
    let mut w = world();
    assert!(matches!(
        w.drive_base("pr2", 1.5, 0.0, 0.0),
        Err(SimError::Blocked { .. })
    ));
    let x0 = w.joint("pr2", "base_x_joint").unwrap();
    w.drive_base("pr2", x0 - 0.3, 0.0, 0.0).unwrap();
    let (x, t) = (
        w.joint("pr2", "base_x_joint").unwrap(),
        w.joint("pr2", "base_theta_joint").unwrap(),
    );
    assert!(
        (x - (x0 - 0.3)).abs() < 1e-9 && t.abs() < 1e-9,
        "x {x}, θ {t}"
    );
    // A goal behind and facing elsewhere still turns to face it first.
    w.drive_base("pr2", x - 0.5, 0.0, 0.5).unwrap();
    let t = w.joint("pr2", "base_theta_joint").unwrap();
    assert!((t - 0.5).abs() < 1e-9, "θ {t}");
    // What backing up avoids: turning round at the table.
    let mut w = world();
    let _ = w.drive_base("pr2", 1.5, 0.0, 0.0);
    assert!(matches!(
        w.drive_base("pr2", x0 - 0.3, 0.0, std::f64::consts::PI),
        Err(SimError::Blocked { .. })
    ));
}

#[test]
fn the_head_looks_at_a_point() {
    let mut w = world();
    for target in [
        Vec3::new(1.8, 0.2, 0.74),
        Vec3::new(1.5, -0.4, 1.0),
        Vec3::new(3.0, 0.0, 1.2),
    ] {
        let err = w
            .look_at(
                "pr2",
                "head_pan_joint",
                "head_tilt_joint",
                "head_camera_optical_frame",
                target,
            )
            .unwrap();
        assert!(err < 1e-4, "{target:?}: {err}");
        let cam = w.link_pose("pr2", "head_camera_optical_frame").unwrap();
        let axis = cam.rotation * Vec3::Z;
        assert!(axis.angle_between(target - cam.translation) < 1e-4);
    }
}
