//! Bad input is normal input: degenerate and hostile clouds get clear errors or empty
//! results, never a panic; and every stage is deterministic.

use proptest::prelude::*;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use tabula_geom::{PointCloud, Vec3};
use tabula_perception::filters::{
    NormalParams, OutlierParams, normals, radius_outliers, statistical_outliers, voxel_grid,
};
use tabula_perception::surfaces::{SurfaceParams, find_surfaces};
use tabula_perception::{TabletopError, TabletopParams, extract, to_world};
use tabula_sim::generate::{TabletopLayout, tabletop_frame};

fn every_stage(cloud: &PointCloud) -> Result<usize, TabletopError> {
    let eye = Vec3::new(0.0, 0.0, 2.0);
    let _ = statistical_outliers(cloud, Some(eye), &OutlierParams::default());
    let _ = radius_outliers(cloud, 0.02, 3);
    let _ = normals(cloud, eye, None, &NormalParams::default());
    let _ = voxel_grid(&cloud.points, 0.02);
    let _ = find_surfaces(cloud, None, &SurfaceParams::default(), false);
    extract(cloud, eye, &TabletopParams::default()).map(|t| t.objects.len())
}

#[test]
fn degenerate_clouds() {
    let organized_nan = PointCloud::organized(64, 48, vec![Vec3::NAN; 64 * 48]).unwrap();
    assert_eq!(every_stage(&organized_nan), Err(TabletopError::Empty));
    assert_eq!(
        every_stage(&PointCloud::unorganized(vec![])),
        Err(TabletopError::Empty)
    );
    assert!(every_stage(&PointCloud::unorganized(vec![Vec3::new(0.5, 0.0, 0.7)])).is_err());
    let collinear: Vec<Vec3> = (0..500)
        .map(|i| Vec3::new(i as f64 * 0.002, 0.0, 0.7))
        .collect();
    assert!(every_stage(&PointCloud::unorganized(collinear)).is_err());
    let same: Vec<Vec3> = vec![Vec3::new(0.3, 0.2, 0.7); 400];
    assert!(every_stage(&PointCloud::unorganized(same)).is_err());
    let infinite: Vec<Vec3> = vec![Vec3::INFINITY; 100];
    assert!(every_stage(&PointCloud::unorganized(infinite)).is_err());
}

#[test]
fn a_bare_table_is_a_table_with_nothing_on_it() {
    // All coplanar: a 1 m × 0.6 m table top, organized like a depth image.
    let (w, h) = (100, 60);
    let points: Vec<Vec3> = (0..w * h)
        .map(|k| Vec3::new((k % w) as f64 * 0.01, (k / w) as f64 * 0.01, 0.72))
        .collect();
    let cloud = PointCloud::organized(w, h, points).unwrap();
    let eye = Vec3::new(0.5, 0.3, 1.8);
    // Evenly spaced in metres, unlike a depth image (spacing grows with range), so
    // range-scaled outlier removal thins it; without it every point is table.
    let raw = TabletopParams {
        remove_outliers: false,
        ..TabletopParams::default()
    };
    let t = extract(&cloud, eye, &raw).unwrap();
    assert!(t.objects.is_empty());
    assert_eq!(t.table.inliers.len(), w * h);
    assert!((t.table.area - 0.6).abs() < 0.03, "area {}", t.table.area);
    let t = extract(&cloud, eye, &TabletopParams::default()).unwrap();
    assert!(t.objects.is_empty() && t.table.inliers.len() > w * h * 3 / 4);
    assert_eq!(
        every_stage(&PointCloud::unorganized(cloud.points.clone())),
        Ok(0)
    );
    // The same plane on the floor is no table.
    let floor: Vec<Vec3> = cloud
        .points
        .iter()
        .map(|p| Vec3::new(p.x, p.y, 0.0))
        .collect();
    assert_eq!(
        every_stage(&PointCloud::organized(w, h, floor).unwrap()),
        Err(TabletopError::NoTable)
    );
}

#[test]
fn half_the_frame_replaced_by_outliers() {
    let g = tabletop_frame(0, &TabletopLayout::nine()).unwrap();
    let mut cloud = to_world(&g.frame.world_from_camera, &g.frame.cloud);
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    for p in cloud.points.iter_mut() {
        if rng.random_bool(0.5) {
            *p = Vec3::new(
                rng.random_range(-1.0..4.0),
                rng.random_range(-2.0..2.0),
                rng.random_range(0.0..2.5),
            );
        }
    }
    let t = extract(
        &cloud,
        g.frame.world_from_camera.translation,
        &TabletopParams::default(),
    )
    .unwrap();
    // The table is still the table.
    assert!((t.plane.normal.z - 1.0).abs() < 1e-3 && (t.table.centroid.z - 0.72).abs() < 0.01);
    assert!(t.objects.len() <= 20, "{} segments", t.objects.len());
}

#[test]
fn same_frame_same_answer() {
    let a = tabletop_frame(4, &TabletopLayout::random(4)).unwrap();
    let b = tabletop_frame(4, &TabletopLayout::random(4)).unwrap();
    assert_eq!(a.scene_toml, b.scene_toml);
    assert_eq!(a.frame.labels, b.frame.labels);
    let cloud = to_world(&a.frame.world_from_camera, &a.frame.cloud);
    let eye = a.frame.world_from_camera.translation;
    let r1 = extract(&cloud, eye, &TabletopParams::default()).unwrap();
    let r2 = extract(&cloud, eye, &TabletopParams::default()).unwrap();
    assert_eq!(r1.table.inliers, r2.table.inliers);
    assert_eq!(r1.plane, r2.plane);
    let seg = |t: &tabula_perception::Tabletop| {
        t.objects
            .iter()
            .map(|o| o.indices.clone())
            .collect::<Vec<_>>()
    };
    assert_eq!(seg(&r1), seg(&r2));
    // And the same with one thread as with two.
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    let r3 = one.install(|| extract(&cloud, eye, &TabletopParams::default()).unwrap());
    assert_eq!(seg(&r1), seg(&r3));
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn voxel_centroids_stay_in_the_bounds(pts in prop::collection::vec((-2.0..2.0f64, -2.0..2.0f64, -2.0..2.0f64), 0..300), leaf in 0.01..1.0f64) {
        let pts: Vec<Vec3> = pts.into_iter().map(|(x, y, z)| Vec3::new(x, y, z)).collect();
        let v = voxel_grid(&pts, leaf).unwrap();
        prop_assert!(v.len() <= pts.len());
        for c in &v {
            prop_assert!(c.abs().max_element() <= 2.0);
        }
    }

    #[test]
    fn outlier_masks_match_the_cloud(pts in prop::collection::vec((-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64), 0..200), k in 1usize..30) {
        let cloud = PointCloud::unorganized(pts.into_iter().map(|(x, y, z)| Vec3::new(x, y, z)).collect());
        let keep = statistical_outliers(&cloud, None, &OutlierParams { mean_k: k, std_mul: 1.0 }).unwrap();
        prop_assert_eq!(keep.len(), cloud.points.len());
    }
}
