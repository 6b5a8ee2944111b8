//! Unit tests of placing's geometry.

use super::body::{palm_front, protective_shape};
use tabula_geom::{Pose, Vec3};

#[test]
fn the_protective_shape_holds_the_object_but_not_the_wrist_behind_the_palm() {
    // A 25 cm bottle held by its neck from the side (the tool frame's x is the
    // approach, the fingers close along y), hanging down along −z; the camera saw
    // its front half, the palm against its back 3 cm behind the tool point.
    let first: Vec<Vec3> = (0..=50)
        .flat_map(|i| {
            (0..8).map(move |k| {
                let a = std::f64::consts::PI * k as f64 / 7.0;
                Vec3::new(
                    0.005 + 0.035 * a.sin(),
                    0.035 * a.cos(),
                    0.02 - 0.005 * i as f64,
                )
            })
        })
        .collect();
    let centre = first.iter().copied().sum::<Vec3>() / first.len() as f64;
    let radius = first.iter().map(|q| q.distance(centre)).fold(0.0, f64::max) + 0.03;
    // A PR2's palm: its front face 4.6 cm behind the tool point.
    let g = tabula_robot::robots::load("pr2")
        .unwrap()
        .description
        .grippers[0]
        .clone();
    let front = palm_front(&g).unwrap();
    assert!((front + 0.046).abs() < 1e-9, "{front}");
    let shape = protective_shape(&first, Vec3::X, Some(front), centre, radius);
    let at = Pose::from_translation(centre);
    let inside = |q: Vec3| shape.contains_point(&at, q);
    // All of the ball in front of the cut, the unseen back of the bottle included.
    for q in &first {
        let back = Vec3::new(0.01 - q.x, q.y, q.z);
        assert!(inside(*q) && inside(back), "{q:?}");
    }
    for k in 0..200 {
        let d = Vec3::new(
            (k as f64 * 0.37).sin(),
            (k as f64 * 1.13).cos(),
            (k as f64 * 2.71).sin(),
        )
        .normalize();
        let q = centre + d * radius * 0.999;
        if q.x >= front {
            assert!(inside(q), "{q:?} of the ball in front of the cut");
        }
    }
    // Behind the deepest point seen by more than the margin (where the wrist is),
    // nothing, though the whole ball would reach there.
    assert!(centre.x - radius < -0.12, "{centre:?} {radius}");
    for y in [-0.05, 0.0, 0.05] {
        for x in [-0.05, -0.07, -0.12] {
            assert!(!inside(Vec3::new(x, y, centre.z)), "{x} {y}");
        }
    }
    // No palm known: 3 cm behind the deepest point seen.
    let seen = protective_shape(&first, Vec3::X, None, centre, radius);
    assert!(seen.contains_point(&at, Vec3::new(-0.02, 0.0, centre.z)));
    assert!(!seen.contains_point(&at, Vec3::new(-0.03, 0.0, centre.z)));
    // Nor enough points to know where the object is: the whole ball.
    let ball = protective_shape(&first[..5], Vec3::X, None, centre, radius);
    let back = centre - Vec3::X * radius * 0.99;
    assert!(ball.contains_point(&at, back));
}

#[test]
fn scan_shifts_past_a_metre_are_refused_by_name() {
    use super::PlaceParams;
    let parse = |text: &str| tabula_geom::input::parse_params::<PlaceParams>(text, "test");
    let ok = parse("scan_shifts = [[-0.15, 0.3, 0.0], [0.0, -1.0, 1.0]]\n").unwrap();
    assert_eq!(ok.scan_shifts.len(), 2);
    assert!(parse("scan_shifts = []\n").unwrap().scan_shifts.is_empty());
    for bad in [
        "[[0.0, 1.5, 0.0]]",
        "[[-2.0, 0.0, 0.0]]",
        "[[0.0, 0.0, 1e300]]",
    ] {
        let e = parse(&format!("scan_shifts = {bad}\n"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("scan_shifts"), "{bad}: {e}");
    }
}

#[test]
fn an_object_is_let_go_as_low_as_the_hand_stays_clear_of_the_surface() {
    use super::PlaceParams;
    use super::model::Resting;
    use crate::stable::{StableParams, of_mesh};
    let (v, t) = tabula_sim::objects::cuboid(Vec3::splat(-0.025), Vec3::splat(0.05));
    let poses = of_mesh(&v, &t, &StableParams::default()).unwrap();
    let bottom = poses
        .poses
        .iter()
        .find(|s| s.normal().z < -0.999)
        .expect("a cube rests on its bottom")
        .clone();
    let p = PlaceParams::default();
    // The hand's lowest point `h` above the cube's bottom (support plane z = −0.025).
    let release =
        |h: f64| Resting::new(bottom.clone(), &[Vec3::new(0.0, 0.0, h - 0.025)], &p).release_height;
    // Held high: down to the lowest release, 3 mm.
    assert!((release(0.03) - p.release_height_min).abs() < 1e-12);
    // Fingers level with the bottom: the hand needs its 3 mm of clearance.
    assert!((release(0.0) - p.gripper_clearance).abs() < 1e-12);
    // Fingers 4 mm below it: 7 mm; 2 cm below: never above SPEC's 8 mm.
    assert!((release(-0.004) - 0.007).abs() < 1e-12);
    assert!((release(-0.02) - p.release_height).abs() < 1e-12);
}
