//! The tabletop pipeline on the simulator's seed-002 frame, scored against its labels.

use tabula_perception::{TabletopParams, extract, read_pcd, to_world};
use tabula_sim::camera::{Camera, capture};
use tabula_sim::{PhysicsParams, Scene, SimWorld};

#[test]
fn table_and_objects_of_the_clutter_frame() {
    let path = std::path::Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../scenes/clutter.toml"
    ));
    let scene = Scene::load(path).unwrap();
    let mut world = SimWorld::from_scene(&scene, PhysicsParams::default()).unwrap();
    world.settle();
    let camera = Camera::from_spec(&scene.cameras[0], &world).unwrap();
    let frame = capture(&world, &camera, 7);
    // Through the file format, as a user would.
    let mut bytes = Vec::new();
    frame
        .cloud
        .write_pcd(&mut bytes, tabula_geom::PcdEncoding::Binary)
        .unwrap();
    let cloud = read_pcd(&bytes).unwrap();
    let points = to_world(&frame.world_from_camera, &cloud.points);
    let t = extract(
        &points,
        cloud.width,
        cloud.height,
        &TabletopParams::default(),
    )
    .unwrap();

    let table_label = world.entity("table").unwrap() as u32 + 1;
    let truth: Vec<usize> = (0..points.len())
        .filter(|&i| frame.labels[i] == table_label && points[i].is_finite() && points[i].z > 0.7)
        .collect();
    let found: std::collections::HashSet<usize> = t.table_indices.iter().copied().collect();
    let hits = truth.iter().filter(|i| found.contains(i)).count();
    let precision = t
        .table_indices
        .iter()
        .filter(|&&i| frame.labels[i] == table_label)
        .count() as f64
        / t.table_indices.len() as f64;
    let recall = hits as f64 / truth.len() as f64;
    assert!(
        precision > 0.99 && recall > 0.99,
        "table precision {precision} recall {recall}"
    );
    assert!(
        (t.plane.normal.z - 1.0).abs() < 1e-3 && (-t.plane.d - 0.72).abs() < 3e-3,
        "{:?}",
        t.plane
    );

    // Objects: IoU against each labelled object.
    let objects: Vec<(String, u32)> = world
        .object_poses()
        .iter()
        .map(|(n, _)| (n.clone(), world.entity(n).unwrap() as u32 + 1))
        .collect();
    let mut good = 0;
    for (name, label) in &objects {
        let mask: std::collections::HashSet<usize> = (0..points.len())
            .filter(|&i| frame.labels[i] == *label && points[i].is_finite())
            .collect();
        let best = t
            .objects
            .iter()
            .map(|o| {
                let inter = o.indices.iter().filter(|i| mask.contains(i)).count() as f64;
                inter / (o.indices.len() as f64 + mask.len() as f64 - inter)
            })
            .fold(0.0, f64::max);
        if best > 0.8 {
            good += 1;
        } else {
            eprintln!("{name}: best IoU {best:.2}");
        }
    }
    eprintln!(
        "{good} of {} objects with IoU > 0.8; {} segments",
        objects.len(),
        t.objects.len()
    );
    assert_eq!(good, objects.len(), "{good} of {} objects", objects.len());
}

#[test]
fn bad_clouds_get_clear_answers() {
    let p = TabletopParams::default();
    assert!(extract(&[tabula_geom::Vec3::NAN; 100], 10, 10, &p).is_err());
    assert!(extract(&[], 0, 0, &p).is_err());
    let line: Vec<tabula_geom::Vec3> = (0..100)
        .map(|i| tabula_geom::Vec3::new(i as f64 * 0.01, 0.0, 0.7))
        .collect();
    assert!(extract(&line, 100, 1, &p).is_err());
}
