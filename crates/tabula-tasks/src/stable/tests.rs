//! Unit tests of stable poses.

use super::{ComMethod, StableError, StableParams, StablePose, of_cloud, of_mesh};
use tabula_geom::Vec3;

fn box_mesh(s: Vec3) -> (Vec<Vec3>, Vec<[u32; 3]>) {
    tabula_sim::objects::cuboid(-s / 2.0, s)
}

#[test]
fn a_flat_box_rests_best_on_its_largest_face() {
    let (v, t) = box_mesh(Vec3::new(0.3, 0.1, 0.05));
    let s = of_mesh(&v, &t, &StableParams::default()).unwrap();
    assert_eq!(s.com_method, ComMethod::MeshVolume);
    assert_eq!(s.poses.len(), 6);
    let best = &s.poses[0];
    assert!(best.normal().z.abs() > 0.999, "{:?}", best.support_normal);
    assert!((best.area_m2 - 0.03).abs() < 1e-9);
    assert!((best.margin_m - 0.05).abs() < 1e-9);
    assert!((best.topple_deg - (0.05f64).atan2(0.025).to_degrees()).abs() < 1e-6);
    let ml = &s.poses[s.most_likely.unwrap()];
    assert!(ml.normal().z.abs() > 0.999);
    let total: f64 = s.poses.iter().map(|p| p.probability).sum();
    assert!((total - 1.0).abs() < 1e-9, "probabilities sum to {total}");
    // Resting rotation puts the support normal down.
    let r = best.resting_rotation(0.7);
    assert!((r * best.normal() + Vec3::Z).length() < 1e-12);
    assert!((best.origin_height() - 0.025).abs() < 1e-12);
}

#[test]
fn a_centre_of_mass_beyond_a_face_leaves_no_pose_on_it() {
    // An obtuse prism: its centre of mass (x = 0.133) overhangs the short bottom
    // face (x ∈ [0, 0.1]), so it cannot rest on it; the other two faces and the end caps hold.
    let v = vec![
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(0.1, 0.0, 0.0),
        Vec3::new(0.3, 0.0, 0.05),
        Vec3::new(0.0, 0.1, 0.0),
        Vec3::new(0.1, 0.1, 0.0),
        Vec3::new(0.3, 0.1, 0.05),
    ];
    let s = of_cloud(&v, &StableParams::default()).unwrap();
    assert!(
        s.poses.iter().all(|p| p.normal().z > -0.99),
        "{:?}",
        s.poses
    );
    assert_eq!(s.poses.len(), 4);
    let total: f64 = s.poses.iter().map(|p| p.probability).sum();
    assert!(
        (total - 1.0).abs() < 1e-9,
        "every drop ends somewhere: {total}"
    );
}

#[test]
fn bad_inputs_are_errors() {
    let p = StableParams::default();
    assert!(matches!(
        of_cloud(&[], &p),
        Err(StableError::TooFewPoints(0))
    ));
    let flat: Vec<Vec3> = (0..20)
        .map(|i| Vec3::new(i as f64, (i * i) as f64, 0.0))
        .collect();
    assert_eq!(of_cloud(&flat, &p).unwrap_err(), StableError::Degenerate);
    let nan = vec![Vec3::NAN; 5];
    assert_eq!(of_cloud(&nan, &p).unwrap_err(), StableError::NonFinite(5));
    let (v, _) = box_mesh(Vec3::ONE);
    assert!(of_mesh(&v, &[[0, 1, 99]], &p).is_err());
}

#[test]
fn an_open_mesh_uses_its_surface_centroid() {
    let (v, t) = box_mesh(Vec3::new(0.1, 0.1, 0.1));
    let s = of_mesh(&v, &t[..10], &StableParams::default()).unwrap();
    assert_eq!(s.com_method, ComMethod::MeshSurface);
}

/// Points on a bottle-like cylinder (r 3.4 cm, 12 cm long, axis z) with ±1 mm of
/// deterministic scan-like noise along the surface normal.
fn noisy_cylinder() -> Vec<Vec3> {
    let (r, len) = (0.034, 0.12);
    let mut noise = 0x2545_f491_4f6c_dd1d_u64;
    let mut jitter = || {
        noise ^= noise << 13;
        noise ^= noise >> 7;
        noise ^= noise << 17;
        (noise % 2001) as f64 / 1000.0 - 1.0
    };
    let mut pts = Vec::new();
    for i in 0..48 {
        let a = std::f64::consts::TAU * i as f64 / 48.0;
        let radial = Vec3::new(a.cos(), a.sin(), 0.0);
        for k in 0..=24 {
            let z = len * k as f64 / 24.0;
            pts.push(radial * (r + 0.001 * jitter()) + Vec3::Z * z);
        }
        for k in 0..6 {
            let z = if k % 2 == 0 { 0.0 } else { len };
            let rr = r * (k / 2 + 1) as f64 / 4.0;
            pts.push(radial * rr + Vec3::Z * (z + 0.001 * jitter()));
        }
    }
    pts
}

#[test]
fn a_curved_side_has_no_energy_barrier_and_a_flat_end_has_it_all() {
    let pts = noisy_cylinder();
    let s = of_cloud(&pts, &StableParams::default()).unwrap();
    let com = Vec3::from_array(s.center_of_mass);
    let end = s
        .poses
        .iter()
        .find(|p| p.normal().z.abs() > 0.99)
        .expect("rests on an end");
    assert!(end.rocking(&pts, com) > 0.8, "{}", end.rocking(&pts, com));
    // Lying down, its noisy side gives tolerance-band "faces" with a margin, but
    // tilting it barely lifts the centre of mass.
    let sides: Vec<&StablePose> = s
        .poses
        .iter()
        .filter(|p| p.normal().z.abs() < 0.2)
        .collect();
    assert!(!sides.is_empty());
    for side in sides {
        let rock = side.rocking(&pts, com);
        assert!(
            rock < 0.5,
            "side {:?} topple {}: {rock}",
            side.support_normal,
            side.topple_deg
        );
    }
    // A box's faces keep their whole barrier.
    let (v, _) = box_mesh(Vec3::new(0.05, 0.08, 0.1));
    let b = of_cloud(&v, &StableParams::default()).unwrap();
    let com = Vec3::from_array(b.center_of_mass);
    for p in &b.poses {
        assert!(p.rocking(&v, com) > 0.99, "{:?}", p.support_normal);
    }
}

#[test]
fn the_hand_margin_is_the_grippers_lowest_point_above_the_support_plane() {
    let (v, t) = box_mesh(Vec3::new(0.3, 0.1, 0.05));
    let s = of_mesh(&v, &t, &StableParams::default()).unwrap();
    // Resting on its bottom (−z face): the support plane is z = −0.025.
    let bottom = s
        .poses
        .iter()
        .find(|p| p.normal().z < -0.999)
        .expect("the bottom face holds");
    let fingers = [Vec3::new(0.0, 0.06, 0.01), Vec3::new(0.0, -0.06, -0.02)];
    assert!((bottom.hand_margin(&fingers) - 0.005).abs() < 1e-12);
    assert!(bottom.clear_of(&fingers, 0.005));
    assert!(!bottom.clear_of(&fingers, 0.006));
    // A finger below the plane: a negative margin.
    assert!((bottom.hand_margin(&[Vec3::new(0.0, 0.0, -0.03)]) + 0.005).abs() < 1e-12);
    assert_eq!(bottom.hand_margin(&[]), f64::INFINITY);
}

/// A 10 × 10 cm plate, 5 mm thick, with a 1 cm square rod 10 cm tall on one corner
/// (a door handle's rose and lever in miniature), its surface sampled every 2.5 mm.
fn plate_with_a_rod() -> (Vec<Vec3>, Vec<Vec3>) {
    let step = 0.0025;
    let grid = |n: usize| (0..=n).map(move |i| i as f64 * step);
    let mut plate = Vec::new();
    for x in grid(40) {
        for y in grid(40) {
            plate.push(Vec3::new(x, y, 0.0));
            plate.push(Vec3::new(x, y, 0.005));
        }
    }
    let mut rod = Vec::new();
    for s in grid(4) {
        for z in grid(40) {
            let z = 0.005 + z * 0.095 / 0.1;
            rod.extend([
                Vec3::new(s, 0.0, z),
                Vec3::new(s, 0.01, z),
                Vec3::new(0.0, s, z),
                Vec3::new(0.01, s, z),
            ]);
        }
    }
    (plate, rod)
}

#[test]
fn a_scanned_clouds_centre_of_mass_is_its_surfaces_not_its_hulls() {
    let (plate, rod) = plate_with_a_rod();
    let cloud: Vec<Vec3> = plate.iter().chain(&rod).copied().collect();
    let s = of_cloud(&cloud, &StableParams::default()).unwrap();
    assert_eq!(s.com_method, ComMethod::CloudSurface);
    let com = Vec3::from_array(s.center_of_mass);
    // Areas: the plate's two faces 0.02 m² at z = 2.5 mm, the rod's sides 0.0038 m²
    // at z = 5.25 cm: z ≈ 1.05 cm. The hull (a pyramid over the plate) has its
    // centroid near 2.8 cm.
    let expected_z = (0.02 * 0.0025 + 0.0038 * 0.0525) / 0.0238;
    assert!(
        (com.z - expected_z).abs() < 0.002,
        "{com:?} vs z {expected_z}"
    );
    let hull_z = super::hull::Hull::new(&cloud).unwrap().volume_centroid().z;
    assert!(
        hull_z > 0.02,
        "the hull's centroid {hull_z} is another point"
    );
    // Seen ten times over, the rod weighs what its area weighs.
    let mut oversampled = cloud.clone();
    for _ in 0..10 {
        oversampled.extend(&rod);
    }
    let again = of_cloud(&oversampled, &StableParams::default()).unwrap();
    assert!(Vec3::from_array(again.center_of_mass).distance(com) < 5e-4);
    // A leaf that is not a length is refused, not used.
    let p = StableParams {
        cloud_com_leaf: 0.0,
        ..StableParams::default()
    };
    assert!(tabula_geom::input::Validate::check(&p, "stable").is_err());
    assert!(super::cloud_surface_centroid(&cloud, f64::NAN).is_none());
}
