//! Mesh objects: convex ones as their hull, concave ones as a convex decomposition.

use tabula_geom::Vec3;
use tabula_sim::camera::{Camera, capture, optical_frame_look_at};
use tabula_sim::{PhysicsParams, Scene, SimWorld};

/// An OBJ of axis-aligned boxes (min, max corners), each a closed outward shell.
fn boxes_obj(boxes: &[([f64; 3], [f64; 3])]) -> String {
    let faces = [
        [0, 2, 3],
        [0, 3, 1],
        [4, 5, 7],
        [4, 7, 6],
        [0, 1, 5],
        [0, 5, 4],
        [2, 6, 7],
        [2, 7, 3],
        [0, 4, 6],
        [0, 6, 2],
        [1, 3, 7],
        [1, 7, 5],
    ];
    let mut text = String::new();
    for (b, (lo, hi)) in boxes.iter().enumerate() {
        for c in 0..8 {
            let p = |k: usize| if c >> k & 1 == 0 { lo[k] } else { hi[k] };
            text += &format!("v {} {} {}\n", p(0), p(1), p(2));
        }
        for f in faces {
            text += &format!(
                "f {} {} {}\n",
                8 * b + f[0] + 1,
                8 * b + f[1] + 1,
                8 * b + f[2] + 1
            );
        }
    }
    text
}

#[test]
fn a_concave_mesh_keeps_its_hollow() {
    let dir = std::env::temp_dir().join(format!("tabula-mesh-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    // A U: two 20 cm posts and a 5 cm floor between them, 10 cm deep.
    let u = boxes_obj(&[
        ([-0.15, -0.05, 0.0], [-0.05, 0.05, 0.2]),
        ([-0.05, -0.05, 0.0], [0.05, 0.05, 0.05]),
        ([0.05, -0.05, 0.0], [0.15, 0.05, 0.2]),
    ]);
    std::fs::write(dir.join("u.obj"), u).unwrap();
    std::fs::write(dir.join("cube.obj"), boxes_obj(&[([-0.05; 3], [0.05; 3])])).unwrap();
    let scene_text = "[floor]\n[[object]]\nname = \"u\"\nshape = { mesh = { path = \"u.obj\" } }\npose = { xyz = [0.0, 0.0, 0.001] }\nmass = 0.5\n\
        [[object]]\nname = \"cube\"\nshape = { mesh = { path = \"cube.obj\" } }\npose = { xyz = [0.6, 0.0, 0.051] }\nmass = 0.2\n";
    std::fs::write(dir.join("scene.toml"), scene_text).unwrap();
    let scene = Scene::load(&dir.join("scene.toml")).unwrap();
    let mut world = SimWorld::from_scene(&scene, PhysicsParams::default()).unwrap();
    assert!(world.settle().all_asleep);
    let camera = Camera {
        noise_coefficient: 0.0,
        ..Camera::kinect(optical_frame_look_at(Vec3::new(0.0, 0.0, 2.0), Vec3::ZERO))
    };
    let frame = capture(&world, &camera, 1);
    let at = |x: f64| {
        // The pixel whose ray meets the plane z = 0.1 at (x, 0): looking straight down
        // with world x as "up", the image's y axis is world −x.
        let (_, fy, cx, cy) = camera.intrinsics();
        let v = (cy - fy * x / 1.9) as usize;
        frame.depth[v * frame.width + cx as usize]
    };
    assert!(at(0.0) > 1.9, "the hollow is filled: depth {}", at(0.0));
    assert!(
        (at(0.1) - 1.8).abs() < 0.02,
        "post top at depth {}",
        at(0.1)
    );
    assert!((world.pose("cube").unwrap().translation.z - 0.05).abs() < 2e-3);
    std::fs::write(dir.join("bad.obj"), "v 0 0 0\nf 1 2 3\n").unwrap();
    let bad = Scene::parse(
        "[[object]]\nname = \"b\"\nshape = { mesh = { path = \"/nonexistent/x.obj\" } }\n",
        "b.toml",
    )
    .unwrap();
    let err = SimWorld::from_scene(&bad, PhysicsParams::default())
        .err()
        .unwrap();
    assert!(err.to_string().contains("/nonexistent/x.obj"), "{err}");
    std::fs::remove_dir_all(&dir).ok();
}

/// Meshes whose resting face has many sides (a 32-sided cylinder, a cone, a mug, a
/// bottle: lathes) set down 8 mm above a table land and stay: parry's manifold on such a
/// face alone touched a sliver at one side and they rocked, tilted and slid centimetres.
#[test]
fn lathed_meshes_set_down_upright_stand_still() {
    for name in ["cylinder", "cone", "mug", "bottle", "cube", "drill"] {
        let mesh = tabula_sim::objects::object(name).unwrap();
        let dir = std::env::temp_dir().join(format!("tabula-lathe-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join(format!("{name}.obj"));
        std::fs::write(&path, mesh.to_obj()).unwrap();
        let scene = Scene::parse(
            &format!(
                "[floor]\nsize = [4.0, 4.0]\n\
                 [[furniture]]\nname = \"table\"\nkind = \"table\"\nsize = [0.8, 1.2, 0.72]\n\
                 [[object]]\nname = \"o\"\nshape = {{ mesh = {{ path = {:?} }} }}\n\
                 pose = {{ xyz = [0.1, 0.05, 0.728], rpy = [0.0, 0.0, 0.4] }}\nmass = 0.3\n",
                path.display().to_string()
            ),
            "lathe.toml",
        )
        .unwrap();
        let mut w = SimWorld::from_scene(&scene, PhysicsParams::default()).unwrap();
        let before = w.pose("o").unwrap();
        let report = w.settle();
        let after = w.pose("o").unwrap();
        let slide = (after.translation - before.translation).truncate().length();
        let tilt = (after.rotation * Vec3::Z)
            .angle_between(Vec3::Z)
            .to_degrees();
        assert!(report.all_asleep, "{name} never came to rest");
        assert!(slide < 0.002, "{name} slid {:.1} mm", slide * 1e3);
        assert!(tilt < 0.5, "{name} tilted {tilt:.2}°");
        assert!(
            (after.translation.z - 0.72).abs() < 0.001,
            "{name} rests at z = {:.4}",
            after.translation.z
        );
        // The helper pieces carry contacts only: the object looks and weighs the same.
        assert_eq!(w.object_shapes().len(), 1, "{name}");
        let _ = std::fs::remove_dir_all(&dir);
    }
}
