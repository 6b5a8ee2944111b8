//! One object seen in pieces is one object: a low box on either side of a tall one in
//! front of it (mOSD's "occluded objects" frames), an open container whose inside the
//! rim cuts from its outside (its "cylindric objects" frames: bowls, mugs); two boxes of
//! one height behind the same occluder, turned differently, stay two.

use tabula_perception::{TabletopParams, extract, to_world};
use tabula_sim::{Camera, PhysicsParams, Scene, SimWorld};

/// A frame of `objects` (scene TOML) on a `table_width` m wide table whose top is at
/// z = 0.72 (its near edge at x = 0.3), seen from `eye` looking at its middle: the
/// world-frame cloud and what `extract` finds in it.
pub(crate) fn tabletop_seen(
    objects: &str,
    table_width: f64,
    eye: [f64; 3],
) -> (tabula_geom::PointCloud, tabula_perception::Tabletop) {
    let text = format!(
        "[[furniture]]\nname = \"table\"\nkind = \"table\"\npose = {{ xyz = [0.7, 0.0, 0.0] }}\n\
         size = [0.8, {table_width:?}, 0.72]\n\n{objects}\n\
         [[camera]]\nname = \"eye\"\nlook_at = {{ eye = {eye:?}, target = [0.75, 0.0, 0.72] }}\n"
    );
    let scene = Scene::parse(&text, "tabletop.toml").unwrap();
    let world = SimWorld::from_scene(&scene, PhysicsParams::default()).unwrap();
    let camera = Camera::from_spec(&scene.cameras[0], &world).unwrap();
    let frame = tabula_sim::camera::capture(&world, &camera, 1);
    let cloud = to_world(&frame.world_from_camera, &frame.cloud);
    let eye = frame.world_from_camera.translation;
    let t = extract(&cloud, eye, &TabletopParams::default()).unwrap();
    (cloud, t)
}

/// The objects `extract` finds in a frame of `objects` (scene TOML) on a table whose
/// top is at z = 0.72, seen from above the table's near edge.
fn objects_seen(objects: &str) -> Vec<Vec<tabula_geom::Vec3>> {
    let (cloud, t) = tabletop_seen(objects, 1.0, [0.05, 0.0, 1.35]);
    t.objects
        .iter()
        .chain(&t.partial)
        .map(|o| o.indices.iter().map(|&i| cloud.points[i]).collect())
        .collect()
}

const OCCLUDER: &str = "[[object]]\nname = \"tall\"\nshape = { box = [0.05, 0.05, 0.25] }\n\
                        pose = { xyz = [0.55, 0.0, 0.845] }\n";

#[test]
fn a_box_behind_a_tall_one_is_one_object_in_two_pieces() {
    let behind = "[[object]]\nname = \"low\"\nshape = { box = [0.06, 0.30, 0.07] }\n\
                  pose = { xyz = [0.72, 0.0, 0.755] }\n";
    let seen = objects_seen(&format!("{OCCLUDER}\n{behind}"));
    assert_eq!(seen.len(), 2, "{} objects", seen.len());
    let low = seen
        .iter()
        .find(|p| p.iter().all(|q| q.z < 0.80))
        .expect("the low box");
    // Both ends are in it, and not the middle the tall box hides.
    assert!(low.iter().any(|q| q.y < -0.1) && low.iter().any(|q| q.y > 0.1));
    assert!(!low.iter().any(|q| q.y.abs() < 0.01 && q.x > 0.68));
}

#[test]
fn two_boxes_turned_differently_behind_one_are_two() {
    let behind = "[[object]]\nname = \"left\"\nshape = { box = [0.06, 0.12, 0.07] }\n\
                  pose = { xyz = [0.72, -0.09, 0.755] }\n\n\
                  [[object]]\nname = \"right\"\nshape = { box = [0.06, 0.12, 0.07] }\n\
                  pose = { xyz = [0.74, 0.10, 0.755], rpy = [0.0, 0.0, 0.7] }\n";
    let seen = objects_seen(&format!("{OCCLUDER}\n{behind}"));
    assert_eq!(seen.len(), 3, "{} objects", seen.len());
}

/// An open tube (a mug without handle or bottom: the table is its bottom) of `radius`
/// and `height`, its wall 5 mm thick, as a prism: a ring with a 2 mm slit at the back.
fn tube(name: &str, at: [f64; 2], radius: f64, height: f64) -> String {
    let slit = 0.001 / radius;
    let arc = |r: f64, reverse: bool| -> Vec<String> {
        let mut a: Vec<String> = (0..=48)
            .map(|k| {
                let t = slit + (std::f64::consts::TAU - 2.0 * slit) * k as f64 / 48.0;
                format!("[{:.5}, {:.5}]", r * t.cos(), r * t.sin())
            })
            .collect();
        if reverse {
            a.reverse();
        }
        a
    };
    let mut outline = arc(radius, false);
    outline.extend(arc(radius - 0.005, true));
    format!(
        "[[object]]\nname = \"{name}\"\nshape = {{ prism = {{ outline = [{}], length = {height} }} }}\n\
         pose = {{ xyz = [{}, {}, {}] }}\n",
        outline.join(", "),
        at[0],
        at[1],
        0.72 + height / 2.0
    )
}

#[test]
fn an_open_container_is_one_object_inside_and_out() {
    let mugs = format!(
        "{}\n{}",
        tube("mug", [0.75, -0.12], 0.045, 0.09),
        tube("pot", [0.8, 0.12], 0.08, 0.07)
    );
    let seen = objects_seen(&mugs);
    assert_eq!(seen.len(), 2, "{} objects", seen.len());
}
