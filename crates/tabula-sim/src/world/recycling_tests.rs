//! A kinematic finger sliding down beside a resting box must not press it into the
//! table (rapier's contact recycling kept a stale, slanted contact point and did).

use super::{PhysicsParams, SimWorld};
use crate::Scene;
use rapier3d_f64::prelude::*;
use tabula_geom::{Pose, Vec3};

const BOX_ON_TABLE: &str = r#"
[[furniture]]
name = "table"
kind = "table"
pose = { xyz = [0.0, 0.0, 0.0] }
size = [1.0, 1.0, 0.7]

[[object]]
name = "box"
shape = { box = [0.057, 0.07, 0.095] }
pose = { xyz = [0.0, 0.0, 0.7475] }
density = 400.0
"#;

/// How far the box sinks while a finger 1 cm beyond its edge, starting just above
/// its top, slides 4 cm down beside it at 6 cm/s.
fn sink_beside_sliding_finger(params: PhysicsParams) -> f64 {
    let scene = Scene::parse(BOX_ON_TABLE, "test.toml").unwrap();
    let mut w = SimWorld::from_scene(&scene, params).unwrap();
    w.settle();
    let rest = w.pose("box").unwrap().translation.z;
    let top = rest + 0.0475;
    let start = Vec3::new(0.0285 + 0.01 + 0.005, 0.0, top + 0.01 + 0.025);
    let finger = w.physics.insert_body(
        RigidBodyBuilder::kinematic_position_based().pose(Pose::from_translation(start)),
    );
    // A convex mesh, as a link's collision mesh is.
    let corners: Vec<Vector> = (0..8)
        .map(|i| {
            let s = |b: usize, h: f64| if i & b == 0 { -h } else { h };
            Vector::new(s(1, 0.005), s(2, 0.01), s(4, 0.025))
        })
        .collect();
    let hull = ColliderBuilder::convex_hull(&corners).unwrap();
    w.physics.insert_collider(hull, Some(finger));
    let the_box = w.entities[w.entity("box").unwrap()].body;
    w.physics.bodies[the_box].wake_up(true);
    let dt = w.physics.integration_parameters.dt;
    let steps = (0.04 / 0.06 / dt).ceil() as usize;
    let mut lowest = rest;
    for k in 1..=steps {
        let z = start.z - 0.06 * dt * k as f64;
        let to = Pose::from_translation(Vec3::new(start.x, start.y, z));
        w.physics.bodies[finger].set_next_kinematic_position(to);
        w.step();
        lowest = lowest.min(w.pose("box").unwrap().translation.z);
    }
    rest - lowest
}

#[test]
fn a_finger_sliding_past_a_box_leaves_it_where_it_rests() {
    let sink = sink_beside_sliding_finger(PhysicsParams::default());
    assert!(sink < 2e-4, "the box sank {sink} m");
}

#[test]
fn rapiers_default_recycling_pressed_it_down() {
    // The defect the default guards against, pinned so a rapier upgrade that fixes
    // or changes it is noticed.
    let params = PhysicsParams {
        contact_recycle_distance: 0.05,
        ..Default::default()
    };
    let sink = sink_beside_sliding_finger(params);
    assert!(sink > 1e-3, "the box sank only {sink} m");
}
