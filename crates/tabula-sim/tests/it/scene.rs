//! Scene files and scene commands: clear errors, no panics.

use proptest::prelude::*;
use tabula_geom::Pose;
use tabula_sim::world::SimError;
use tabula_sim::{PhysicsParams, Scene, SimWorld};

#[test]
fn errors_name_file_line_and_key() {
    let e = Scene::parse("[floor]\nsize = [1.0, 2.0]\n\n[[object]]\nname = \"box\"\nshape = { box = [0.1, -0.1, 0.1] }\n", "s.toml").unwrap_err();
    assert_eq!(
        (e.file.as_str(), e.line, e.key.as_str()),
        ("s.toml", 5, "object.box.shape"),
        "{e}"
    );
    assert!(e.to_string().starts_with("s.toml:5: "));
    let e = Scene::parse(
        "[[object]]\nname = \"a\"\nshape = { pyramid = 1 }\n",
        "s.toml",
    )
    .unwrap_err();
    assert_eq!(e.line, 3, "{e}");
    let e = Scene::parse("[floor]\nsize = \"big\"\n", "s.toml").unwrap_err();
    assert_eq!(e.line, 2, "{e}");
    let e = Scene::parse(
        "[[object]]\nname = \"a\"\nshape = { sphere = { radius = 0.1 } }\ncolour = [1, 0, 0]\n",
        "s.toml",
    )
    .unwrap_err();
    assert!(e.to_string().contains("colour"), "{e}");
    let e = Scene::parse(
        "[[object]]\nname = \"a\"\nshape = { sphere = { radius = 0.1 } }\n[[furniture]]\nname = \"a\"\nkind = \"table\"\n",
        "s.toml",
    )
    .unwrap_err();
    assert!(e.to_string().contains("used twice") && e.line == 5, "{e}");
    let e = Scene::parse("[[camera]]\nname = \"c\"\n", "s.toml").unwrap_err();
    assert_eq!(e.key, "camera.c.look_at", "{e}");
    let e = Scene::load(std::path::Path::new("/no/such/scene.toml")).unwrap_err();
    assert!(e.to_string().contains("/no/such/scene.toml"));
}

#[test]
fn shipped_scenes_load() {
    for name in ["clutter", "pr2_holding", "golem_shelves"] {
        let path = std::path::PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../../scenes"))
            .join(format!("{name}.toml"));
        let scene = Scene::load(&path).unwrap_or_else(|e| panic!("{e}"));
        let mut world = SimWorld::from_scene(&scene, PhysicsParams::default())
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        assert!(world.settle().all_asleep, "{name}");
        assert!(!scene.cameras.is_empty(), "{name}");
    }
}

fn table_world() -> SimWorld {
    let text =
        "[floor]\n[[furniture]]\nname = \"table\"\nkind = \"table\"\nsize = [1.0, 1.0, 0.7]\n";
    SimWorld::from_scene(
        &Scene::parse(text, "t.toml").unwrap(),
        PhysicsParams::default(),
    )
    .unwrap()
}

#[test]
fn spawn_move_put_on_surface_delete_list() {
    let mut w = table_world();
    w.spawn("can", "can1", [0.1, 0.0, 1.2]).unwrap();
    w.put_on_surface("can1").unwrap();
    let z = w.pose("can1").unwrap().translation.z;
    assert!((z - 0.76).abs() < 1e-3, "can centre {z}");
    w.settle();
    assert!((w.pose("can1").unwrap().translation.z - 0.76).abs() < 2e-3);
    // Unknown models list the valid ones; an overlapping spawn is refused.
    match w.spawn("unicorn", "u", [0.0, 0.0, 1.0]) {
        Err(SimError::UnknownModel { valid, .. }) => {
            assert!(valid.contains("cube_5cm") && valid.contains("can"))
        }
        other => panic!("{other:?}"),
    }
    assert!(matches!(
        w.spawn("can", "can2", [0.1, 0.0, 0.76]),
        Err(SimError::Overlap { .. })
    ));
    assert!(matches!(
        w.spawn("can", "can1", [0.3, 0.3, 1.0]),
        Err(SimError::NameTaken(_))
    ));
    assert!(matches!(
        w.spawn("can", "x", [f64::NAN, 0.0, 1.0]),
        Err(SimError::NonFinite)
    ));
    w.move_to(
        "can1",
        Pose::from_translation(tabula_geom::Vec3::new(-0.2, 0.2, 0.9)),
    )
    .unwrap();
    assert_eq!(
        w.list(Some(tabula_sim::world::EntityKind::Object)),
        ["can1"]
    );
    w.delete("can1").unwrap();
    assert!(
        w.list(Some(tabula_sim::world::EntityKind::Object))
            .is_empty()
    );
    assert!(matches!(w.delete("can1"), Err(SimError::UnknownEntity(_))));
    // Nothing under a point beside the table but the floor.
    w.spawn("ball", "b", [2.0, 2.0, 1.0]).unwrap();
    w.put_on_surface("b").unwrap();
    assert!((w.pose("b").unwrap().translation.z - 0.035).abs() < 1e-3);
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 300, ..ProptestConfig::default() })]

    /// Mutated scene files: an error with a place, or a scene that builds; never a panic.
    #[test]
    fn mutated_scenes_never_panic(edits in proptest::collection::vec((any::<prop::sample::Index>(), 0u8..3, prop::sample::select(vec!['[', ']', '=', '"', '-', '0', '9', '.', '\n', 'x', '{', '}', ','])), 1..6)) {
        let source = include_str!("../../../../scenes/clutter.toml");
        let mut chars: Vec<char> = source.chars().collect();
        for (at, op, c) in edits {
            if chars.is_empty() { break; }
            let i = at.index(chars.len());
            match op {
                0 => { chars.remove(i); }
                1 => chars.insert(i, c),
                _ => chars[i] = c,
            }
        }
        let text: String = chars.into_iter().collect();
        if let Ok(scene) = Scene::parse(&text, "m.toml") {
            let _ = SimWorld::from_scene(&scene, PhysicsParams::default());
        }
    }
}

/// An arch 6 cm wide with a half-round notch of 1.5 cm radius, laid down over z = 0
/// with the notch open below (outline upright, length along y).
const ARCH: &str = r#"
[floor]

[[object]]
name = "arch"
shape = { prism = { outline = [[0.03, 0.0], [0.03, 0.04], [-0.03, 0.04], [-0.03, 0.0], [-0.015, 0.0], [-0.0106, 0.0106], [0.0, 0.015], [0.0106, 0.0106], [0.015, 0.0]], length = 0.08 } }
pose = { xyz = [0.0, 0.0, 0.0005], rpy = [1.5708, 0.0, 0.0] }
"#;

#[test]
fn a_prism_keeps_its_notch_open_and_rests_where_it_is_put() {
    let scene = Scene::parse(ARCH, "arch.toml").unwrap();
    let mut world = SimWorld::from_scene(&scene, PhysicsParams::default()).unwrap();
    assert!(world.settle().all_asleep);
    let p = world.pose("arch").unwrap();
    assert!(p.translation.length() < 2e-3, "{p:?}");
    // A 1.6 cm cube fits under the arch: a convex hull would have filled the notch.
    let under = "[[object]]\nname = \"cube\"\nshape = { box = [0.016, 0.016, 0.016] }\npose = { xyz = [0.0, 0.0, 0.0085] }\n";
    let both = Scene::parse(&format!("{ARCH}{under}"), "arch.toml").unwrap();
    SimWorld::from_scene(&both, PhysicsParams::default()).expect("the notch is free");
    // Bounds: 6 cm across, 4 cm high, 8 cm long.
    let b = world.entity_bounds("arch").unwrap();
    let size = b.maxs - b.mins;
    assert!(
        (size.x - 0.06).abs() < 1e-3
            && (size.z - 0.04).abs() < 2e-3
            && (size.y - 0.08).abs() < 1e-3,
        "{size:?}"
    );
}

#[test]
fn bad_prism_outlines_are_refused_by_name() {
    for (outline, why) in [
        ("[[0.0, 0.0], [0.1, 0.0]]", "at least 3 vertices"),
        ("[[0.0, 0.0], [0.1, 0.1], [0.1, 0.0], [0.0, 0.05]]", "cross"),
        (
            "[[0.0, 0.0], [0.1, 0.0], [0.2, 0.0]]",
            "at least 3 vertices",
        ),
        ("[[0.0, 0.0], [1e300, 0.0], [0.0, 0.1]]", "= 1e300"),
        ("[[0.0, 0.0], [200.0, 0.0], [0.0, 0.1]]", "within"),
        ("[[0.0, 0.0], [0.1, 0.0], [0.0, 1e-9]]", "at least"),
    ] {
        let text = format!(
            "[[object]]\nname = \"p\"\nshape = {{ prism = {{ outline = {outline}, length = 0.05 }} }}\n"
        );
        let e = Scene::parse(&text, "p.toml").unwrap_err();
        assert!(e.to_string().contains(why), "{outline}: {e}");
    }
    let many: Vec<String> = (0..300)
        .map(|k| {
            let t = std::f64::consts::TAU * k as f64 / 300.0;
            format!("[{}, {}]", 0.05 * t.cos(), 0.05 * t.sin())
        })
        .collect();
    let text = format!(
        "[[object]]\nname = \"p\"\nshape = {{ prism = {{ outline = [{}], length = 0.05 }} }}\n",
        many.join(", ")
    );
    let e = Scene::parse(&text, "p.toml").unwrap_err();
    assert!(e.to_string().contains("at most 256"), "{e}");
}

/// A robot's pedestal is furniture to the world — an arm link pressed into it is a
/// contact the judges see — and a link of the robot's own model, so its planners keep
/// off it; a bad size is refused by key.
#[test]
fn a_pedestal_is_furniture_to_the_world_and_a_link_to_the_robot() {
    let scene = |pedestal: &str| {
        format!(
            "[floor]\nsize = [3.0, 3.0]\n\n[[robot]]\nname = \"arm\"\nurdf = \"wam\"\n\
             pose = {{ xyz = [0.0, 0.0, 0.6] }}\npedestal = {pedestal}\n"
        )
    };
    let world = SimWorld::from_scene(
        &Scene::parse(&scene("[0.3, 0.3, 0.6]"), "p.toml").unwrap(),
        PhysicsParams::default(),
    )
    .unwrap();
    let furniture: Vec<String> = world.furniture_shapes().into_iter().map(|f| f.0).collect();
    assert_eq!(furniture, ["arm/pedestal"]);
    let robot = world.robot("arm").unwrap();
    assert!(robot.model.link("pedestal").is_ok());
    // Not an obstacle to its own robot's planners or to the task's workcell.
    assert!(world.planning_scene("arm").is_empty());
    assert!(world.workcell_shapes().is_empty());
    // Top at the root, down to the floor.
    let (_, shape, pose) = &world.furniture_shapes()[0];
    let bounds = shape.compute_aabb(pose);
    assert!((bounds.maxs.z - 0.6).abs() < 1e-9 && bounds.mins.z.abs() < 1e-9);
    assert!(
        world
            .robot_contacts("arm", &[tabula_sim::world::EntityKind::Furniture], 1e-3)
            .unwrap()
            .is_empty()
    );
    for bad in ["[0.3, 0.0, 0.6]", "[0.3, 0.3, 500.0]"] {
        let e = Scene::parse(&scene(bad), "p.toml").unwrap_err();
        assert_eq!(e.key, "robot.arm.pedestal", "{e}");
    }
}
