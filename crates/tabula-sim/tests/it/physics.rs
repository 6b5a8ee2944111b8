//! Physics scenarios of issue 3, with the scene format.

use tabula_geom::{Pose, Vec3};
use tabula_sim::{PhysicsParams, Scene, SimWorld};

fn world(toml: &str) -> SimWorld {
    let scene = Scene::parse(toml, "test.toml").unwrap_or_else(|e| panic!("{e}"));
    SimWorld::from_scene(&scene, PhysicsParams::default()).unwrap_or_else(|e| panic!("{e}"))
}

const TABLE: &str = r#"
[floor]
[[furniture]]
name = "table"
kind = "table"
pose = { xyz = [0.0, 0.0, 0.0] }
size = [1.0, 1.0, 0.7]
"#;

#[test]
fn a_tilted_box_dropped_on_the_table_rests_flat() {
    let mut w = world(&format!(
        "{TABLE}\n[[object]]\nname = \"box\"\nshape = {{ box = [0.1, 0.08, 0.06] }}\npose = {{ xyz = [0.0, 0.0, 0.85], rpy = [0.3, 0.2, 0.5] }}\nmass = 0.3\n"
    ));
    let report = w.settle();
    assert!(report.all_asleep, "{report:?}");
    let p = w.pose("box").unwrap();
    // Resting on its largest face: centre 3 cm above the top, z axis vertical.
    let tilt = (p.rotation * Vec3::Z)
        .angle_between(Vec3::Z)
        .min((p.rotation * Vec3::Z).angle_between(-Vec3::Z));
    assert!(
        (p.translation.z - 0.73).abs() < 1e-3,
        "height {}",
        p.translation.z
    );
    assert!(tilt < 0.5f64.to_radians(), "tilt {tilt}");
}

#[test]
fn a_cylinder_does_not_stay_on_the_120_degree_ramp() {
    // The ramp rises along +x at 60° from horizontal (120° from the floor across the
    // ramp); the can lies across it, 1 cm above the surface at x = 0.
    let mut w = world(
        "[floor]\n[[furniture]]\nname = \"ramp\"\nkind = \"ramp\"\nsize = [0.4, 0.8, 1.0]\nangle_deg = 120.0\n\
         [[object]]\nname = \"can\"\nshape = { cylinder = { radius = 0.033, height = 0.12 } }\n\
         pose = { xyz = [-0.037, 0.0, 0.368], rpy = [1.5708, 0.0, 0.0] }\nmass = 0.35\n",
    );
    w.settle();
    let p = w.pose("can").unwrap();
    assert!(
        p.translation.z < 0.1,
        "the can stayed on the ramp at z = {}",
        p.translation.z
    );
}

#[test]
fn a_tall_box_with_its_centre_of_mass_outside_the_support_topples() {
    // Stood on its 4×4 cm face, tilted 20°: the centre of mass is outside the face.
    let start = "pose = { xyz = [0.0, 0.0, 0.862], rpy = [0.35, 0.0, 0.0] }";
    let mut w = world(&format!(
        "{TABLE}\n[[object]]\nname = \"tall\"\nshape = {{ box = [0.04, 0.04, 0.3] }}\n{start}\nmass = 0.3\n"
    ));
    let upright = Pose::IDENTITY;
    w.settle();
    assert!(w.has_toppled("tall", &upright, 0.5).unwrap());
    // The same box stood straight stays up.
    let mut w = world(&format!(
        "{TABLE}\n[[object]]\nname = \"tall\"\nshape = {{ box = [0.04, 0.04, 0.3] }}\npose = {{ xyz = [0.0, 0.0, 0.8505] }}\nmass = 0.3\n"
    ));
    w.settle();
    assert!(!w.has_toppled("tall", &upright, 0.05).unwrap());
}

#[test]
fn a_stack_of_two_boxes_stays() {
    let mut w = world(&format!(
        "{TABLE}\n[[object]]\nname = \"base\"\nshape = {{ box = [0.1, 0.1, 0.1] }}\npose = {{ xyz = [0.0, 0.0, 0.7505] }}\nmass = 0.5\n\
         [[object]]\nname = \"top\"\nshape = {{ box = [0.06, 0.06, 0.06] }}\npose = {{ xyz = [0.01, 0.0, 0.8312] }}\nmass = 0.2\n"
    ));
    let before = w.pose("top").unwrap();
    assert!(w.settle().all_asleep);
    let (dp, dr) = w.pose_error("top", &before).unwrap();
    assert!(
        dp < 3e-3 && dr < 1f64.to_radians(),
        "moved {dp} m, {dr} rad"
    );
    assert!(!w.has_toppled("base", &Pose::IDENTITY, 0.01).unwrap());
}

#[test]
fn the_clutter_scene_settles_in_place() {
    let scene = Scene::load(std::path::Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../scenes/clutter.toml"
    )))
    .unwrap();
    let mut w = SimWorld::from_scene(&scene, PhysicsParams::default()).unwrap();
    let before = w.object_poses();
    let report = w.settle();
    assert!(report.all_asleep, "{report:?}");
    for (name, pose) in before {
        let (dp, _) = w.pose_error(&name, &pose).unwrap();
        assert!(dp < 5e-3, "{name} moved {dp} m while settling");
    }
}

#[test]
fn same_seed_same_settled_poses() {
    let path = std::path::Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../scenes/clutter.toml"
    ));
    let run = || {
        let mut w =
            SimWorld::from_scene(&Scene::load(path).unwrap(), PhysicsParams::default()).unwrap();
        w.settle();
        w.object_poses()
    };
    assert_eq!(run(), run());
}
