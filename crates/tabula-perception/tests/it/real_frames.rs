//! The pipeline on real Kinect frames (`data/real/`, from PCL's test data): optical-frame
//! points, PCL's flipped `VIEWPOINT`, NaN margins, depth quantisation at range, objects
//! cut by the frame's edge — and no world pose.

use tabula_geom::{CloudFile, Vec3, read_pcd_file};
use tabula_perception::support::{FrameSource, SupportParams, frame_cloud};
use tabula_perception::tabletop::{Tabletop, extract_framed};
use tabula_perception::{TabletopParams, to_world};

fn load(name: &str) -> CloudFile {
    let path = format!("{}/../../data/real/{name}", env!("CARGO_MANIFEST_DIR"));
    read_pcd_file(&std::fs::read(path).unwrap()).unwrap()
}

/// Frames the file as `tabula perceive --cloud` does, and runs the pipeline.
fn perceive(file: &CloudFile) -> (tabula_perception::support::Framing, Tabletop) {
    perceive_with(file, &TabletopParams::default())
}

fn perceive_with(
    file: &CloudFile,
    p: &TabletopParams,
) -> (tabula_perception::support::Framing, Tabletop) {
    let framing = frame_cloud(
        &file.cloud,
        &file.viewpoint,
        None,
        None,
        &SupportParams::default(),
    )
    .unwrap();
    let cloud = to_world(&framing.world_from_cloud, &file.cloud);
    let t = extract_framed(&cloud, &framing, p).unwrap();
    (framing, t)
}

/// The default parameters on every `stride`-th pixel of every `stride`-th row.
fn at_stride(stride: usize) -> TabletopParams {
    TabletopParams {
        frame_stride: stride,
        ..TabletopParams::default()
    }
}

#[test]
fn laptop_and_box_on_a_carpet() {
    let file = load("kinect_laptop_box.pcd");
    assert_eq!((file.cloud.width, file.cloud.height), (640, 480));
    assert!(file.colors.is_some(), "rgba is read");
    let (framing, t) = perceive(&file);
    // PCL's `0 0 0 0 1 0 0` over optical-frame points: the support is found under the
    // optical frame's up, and it is the carpet the camera looks down on.
    assert_eq!(framing.source, FrameSource::Support);
    let support = framing.support.as_ref().unwrap();
    assert!(support.angle_from_hint < 60f64.to_radians());
    assert!(
        (0.4..1.5).contains(&framing.eye.z),
        "sensor {}",
        framing.eye
    );
    assert!(t.table.area > 1.0, "carpet seen {} m²", t.table.area);
    // The laptop (37 cm wide, 23 cm tall, leaning) and the box (25 × 17 × 9 cm), each
    // whole and alone, and a small dark item on the carpet to the right.
    let sizes: Vec<Vec3> = t.objects.iter().map(|o| o.obb.half_extents * 2.0).collect();
    assert_eq!(t.objects.len(), 3, "{sizes:?}");
    let near = |s: Vec3, w: [f64; 3]| (s - Vec3::from(w)).abs().max_element() < 0.03;
    assert!(
        sizes.iter().any(|&s| near(s, [0.374, 0.126, 0.235])),
        "{sizes:?}"
    );
    assert!(
        sizes.iter().any(|&s| near(s, [0.253, 0.167, 0.09])),
        "{sizes:?}"
    );
    assert!(sizes.iter().all(|s| s.max_element() < 0.45), "{sizes:?}");
    // Nothing of the carpet passes for an object: each rises from it, and no flat
    // piece of floor is among them.
    for o in &t.objects {
        assert!(o.height > 0.04, "{}", o.height);
    }
    // The chair base and the boxes behind are cut by the frame's edge: set apart.
    assert!(!t.partial.is_empty());
    assert!(
        t.partial.iter().all(|o| o.centroid.x > 0.9),
        "background only"
    );
}

#[test]
fn office_floor_under_a_bigger_back_wall() {
    let file = load("kinect_office.pcd");
    let (framing, t) = perceive(&file);
    // The back wall is the biggest plane in view; the support is the floor, 1.3 m
    // under a level camera.
    let support = framing.support.as_ref().unwrap();
    assert!(support.angle_from_hint < 15f64.to_radians());
    assert!(
        (1.0..1.8).contains(&framing.eye.z),
        "sensor {}",
        framing.eye
    );
    // The bag, the box and the chair all run out of the frame; the desk, the walls and
    // the wardrobes are background: no whole object, and nothing wall-sized at all.
    assert!(t.objects.is_empty(), "{}", t.objects.len());
    for o in &t.partial {
        assert!(o.obb.half_extents.max_element() * 2.0 <= 1.5);
    }
}

/// A mug on a table from a stereo rig: its handle's loop is concave against the faces
/// around it and came out as pieces of its own; it lies inside the mug's hull, so it is
/// the mug's. One object, handle included (11.5 cm long, the body 8.4 cm across), on the
/// full grid and on every second pixel.
#[test]
fn a_mug_with_its_handle_is_one_object() {
    let file = load("stereo_mug.pcd");
    for stride in [1, 2] {
        let (_, t) = perceive_with(&file, &at_stride(stride));
        let sizes: Vec<Vec3> = t.objects.iter().map(|o| o.obb.half_extents * 2.0).collect();
        assert_eq!(t.objects.len(), 1, "stride {stride}: {sizes:?}");
        assert!(t.partial.is_empty(), "stride {stride}");
        let s = sizes[0];
        assert!(
            (s - Vec3::new(0.115, 0.084, 0.098)).abs().max_element() < 0.015,
            "stride {stride}: {s}"
        );
    }
}

/// A milk carton, a Clorox bottle and a detergent bottle (PCL's correspondence-grouping
/// frame): the caps and the carton's gable fin are cut off by the crease where they meet
/// the shoulder or roof, and stand on it as a box stands on a box. They rise from a
/// sloping surface, so they are their bottle's: three objects of their full heights,
/// caps included, and at most two more (the Clorox handle, a chair's caster).
#[test]
fn caps_and_a_gable_top_stay_on_their_bottles() {
    let file = load("milk_detergent.pcd");
    for stride in [1, 2] {
        let (_, t) = perceive_with(&file, &at_stride(stride));
        let mut heights: Vec<f64> = t
            .objects
            .iter()
            .filter(|o| o.indices.len() >= 5000)
            .map(|o| o.height)
            .collect();
        heights.sort_by(f64::total_cmp);
        assert_eq!(heights.len(), 3, "stride {stride}: {heights:?}");
        for (seen, whole) in heights.iter().zip([0.209, 0.245, 0.261]) {
            assert!((seen - whole).abs() < 0.01, "stride {stride}: {heights:?}");
        }
        if stride == 1 {
            assert!((3..=5).contains(&t.objects.len()), "{}", t.objects.len());
        }
    }
}
