//! The depth camera against geometry whose depth is known in closed form.

use tabula_geom::Vec3;
use tabula_sim::camera::{Camera, capture, optical_frame_look_at};
use tabula_sim::{PhysicsParams, Scene, SimWorld};

/// The floor (top at z = 0) and a 40×30×50 cm box centred under a camera 2 m up.
fn scene() -> SimWorld {
    let text =
        "[floor]\n[[furniture]]\nname = \"block\"\nkind = \"cabinet\"\nsize = [0.4, 0.3, 0.5]\n";
    SimWorld::from_scene(
        &Scene::parse(text, "t.toml").unwrap(),
        PhysicsParams::default(),
    )
    .unwrap()
}

fn down_camera(noise: f64) -> Camera {
    Camera {
        noise_coefficient: noise,
        ..Camera::kinect(optical_frame_look_at(Vec3::new(0.0, 0.0, 2.0), Vec3::ZERO))
    }
}

#[test]
fn noiseless_depth_and_labels_match_the_analytic_answer() {
    let world = scene();
    let camera = down_camera(0.0);
    let frame = capture(&world, &camera, 1);
    let floor = world.entity("floor").unwrap() as u32 + 1;
    let block = world.entity("block").unwrap() as u32 + 1;
    let rot = camera.world_from_camera.rotation;
    let (mut checked, mut on_block) = (0, 0);
    for v in 0..frame.height {
        for u in 0..frame.width {
            let i = v * frame.width + u;
            // Where the pixel's ray crosses the block's top plane (1.5 m down).
            let d = rot * camera.pixel_ray(u, v);
            let at_top = Vec3::new(0.0, 0.0, 2.0) + d * (1.5 / -d.z);
            let (mx, my) = (0.2 - at_top.x.abs(), 0.15 - at_top.y.abs());
            if mx.abs() < 1e-9 || my.abs() < 1e-9 {
                continue;
            }
            let (depth, label) = if mx > 0.0 && my > 0.0 {
                (1.5, block)
            } else {
                (2.0, floor)
            };
            assert!(
                (frame.depth[i] - depth).abs() < 1e-6,
                "pixel ({u}, {v}): {} vs {depth}",
                frame.depth[i]
            );
            assert_eq!(frame.labels[i], label, "pixel ({u}, {v})");
            let p = frame.cloud.points[i];
            assert!((p.z - depth).abs() < 1e-6);
            checked += 1;
            on_block += usize::from(label == block);
        }
    }
    assert!(
        checked > 300_000 && on_block > 10_000,
        "{checked} {on_block}"
    );
    assert_eq!(frame.label_names[block as usize - 1], "block");
}

#[test]
fn depth_noise_has_the_kinect_standard_deviation() {
    let world = scene();
    let camera = down_camera(0.0015);
    let frame = capture(&world, &camera, 42);
    let residuals: Vec<f64> = frame
        .depth
        .iter()
        .zip(&frame.labels)
        .filter(|&(d, &l)| d.is_finite() && l == 1)
        .map(|(d, _)| d - 2.0)
        .collect();
    let n = residuals.len() as f64;
    let mean = residuals.iter().sum::<f64>() / n;
    let std = (residuals.iter().map(|r| (r - mean).powi(2)).sum::<f64>() / n).sqrt();
    let expected = 0.0015 * 2.0 * 2.0;
    assert!(
        (std / expected - 1.0).abs() < 0.1,
        "std {std} vs {expected}"
    );
    assert!(
        mean.abs() < 3.0 * expected / n.sqrt() + 1e-6,
        "biased: {mean}"
    );
    // Same seed, same frame; another seed, another one.
    assert_eq!(capture(&world, &camera, 42).depth, frame.depth);
    assert_ne!(capture(&world, &camera, 43).depth, frame.depth);
}

#[test]
fn out_of_range_and_grazing_returns_are_missing() {
    let world = scene();
    let far = Camera {
        noise_coefficient: 0.0,
        ..Camera::kinect(optical_frame_look_at(Vec3::new(0.0, 0.0, 4.4), Vec3::ZERO))
    };
    let frame = capture(&world, &far, 1);
    // The floor at 4.4 m is beyond range; the block's top at 3.9 m is inside.
    let finite: Vec<f64> = frame
        .depth
        .iter()
        .copied()
        .filter(|d| d.is_finite())
        .collect();
    assert!(!finite.is_empty() && finite.iter().all(|d| (d - 3.9).abs() < 1e-6));
    // Looking along the floor from 1 cm above it: nearly every floor return is grazing.
    let grazing = Camera {
        noise_coefficient: 0.0,
        ..Camera::kinect(optical_frame_look_at(
            Vec3::new(-3.0, 0.0, 0.01),
            Vec3::new(3.0, 0.0, 0.01),
        ))
    };
    let frame = capture(&world, &grazing, 1);
    let floor_hits = frame
        .depth
        .iter()
        .zip(&frame.labels)
        .filter(|&(d, &l)| l == 1 && d.is_finite())
        .count();
    assert_eq!(floor_hits, 0);
}

#[test]
fn a_head_camera_sees_out_of_the_head_it_is_mounted_in() {
    // The PR2's head camera frame sits inside the head's collision box; the box is the
    // sensor's housing, not something in front of it.
    let path = std::path::Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../scenes/pr2_holding.toml"
    ));
    let scene = tabula_sim::Scene::load(path).unwrap();
    let world = SimWorld::from_scene(&scene, tabula_sim::PhysicsParams::default()).unwrap();
    let camera = Camera::from_spec(&scene.cameras[0], &world).unwrap();
    let frame = capture(&world, &camera, 1);
    let table = world.entity("table").unwrap() as u32 + 1;
    let valid = frame.depth.iter().filter(|d| d.is_finite()).count();
    let on_table = (0..frame.labels.len())
        .filter(|&i| frame.depth[i].is_finite() && frame.labels[i] == table)
        .count();
    assert!(valid > frame.depth.len() / 2, "{valid} valid returns");
    assert!(on_table > 50_000, "{on_table} table returns");
}
