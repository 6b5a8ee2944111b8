//! The tabletop pipeline's parameters, shared by its stages (outliers, the table's
//! plane, segmentation, objects).

use crate::filters::{NormalParams, OutlierParams};
use crate::surfaces::SurfaceParams;
use tabula_geom::input::{
    Validate, check_count, check_in, check_non_negative, check_off_or_in, check_positive, nested,
};

/// Parameters; defaults from SPEC §6 (seed 002's repository) where it has them.
#[derive(Debug, Clone, serde::Deserialize, serde::Serialize)]
#[serde(default, deny_unknown_fields)]
pub struct TabletopParams {
    /// Run statistical outlier removal first (SPEC §3.1).
    pub remove_outliers: bool,
    /// SPEC §6: mean-K 10, std multiplier 1.0.
    pub outliers: OutlierParams,
    /// Table search: SPEC §1.3/§6 (1 cm RANSAC, 0.09 rad tilt).
    pub surfaces: SurfaceParams,
    pub normals: NormalParams,
    /// Prism points start this far above the table (m).
    pub min_height: f64,
    /// Neighbours closer than this (m) can be one object …
    pub cluster_tolerance: f64,
    /// … plus this times the squared range (m⁻¹), on organized frames: a
    /// structured-light sensor's depth steps grow as range² (2.85e-3 · z² for a
    /// Kinect), so neighbouring pixels of one surface 4 m away are centimetres apart
    /// in depth (PCL's depth-dependent cluster threshold).
    pub cluster_range_gain: f64,
    /// Normals differing by more than this (rad) across a concave crease cut objects
    /// apart. SPEC §6 has 15° (seed 002's frames); the default is 25° because real
    /// structured-light normals over a 7-pixel window have a median error near 7°
    /// (measured on the carpet of a real Kinect frame), and two of them differ by
    /// more than 15° often enough to cut a laptop lid into pieces, while every
    /// touching pair of the generated suite still comes apart at 25°.
    pub concavity_tolerance: f64,
    /// How far (pixels, or cluster tolerances when unorganized) on either side of a
    /// point its crease test looks.
    pub concavity_step: usize,
    /// Parallel surfaces on either side of a point offset by more than this (m) along
    /// their normal are a step between two objects (organized clouds).
    pub step_tolerance: f64,
    /// Smallest object (points), SPEC §6: 200.
    pub min_object_points: usize,
    /// Objects on the table must reach this high above it (m). SPEC §6 has 2.5 cm
    /// for every object; on the table the default is 1.2 cm (just above `min_height`,
    /// where the prism starts), because flat things — a phone, a coaster, a book, a
    /// 1.5 cm disc at the gripper's 7 cm limit — are objects to see and clear, and
    /// nothing on the support rises that far above it by noise alone.
    pub min_object_height: f64,
    /// What rests on another object must be this tall above what it rests on (m),
    /// SPEC §6's 2.5 cm: shorter, it is a strip cut off the face below it (a laptop
    /// lid's rim on a real Kinect frame), not an object.
    pub min_stacked_height: f64,
    /// A top surface is the object's points within this distance (m) of its highest
    /// level whose normals are within `max_tilt` of the table's.
    pub top_band: f64,
    /// Support found without a world pose: points this far (m) outside its outline
    /// may still belong to objects on it (they hide the support around them) …
    pub support_reach: f64,
    /// … which must reach down to within this distance (m) of the prism's floor …
    pub rest_tolerance: f64,
    /// … and be no wider or taller than this (m).
    pub max_object_extent: f64,
    /// Pieces this near (m) an object cut by the frame's edge are cut too.
    pub partial_gap: f64,
    /// Points of an unorganized cloud closer than this (m) to one already seen are
    /// the same sample (merged scans, drivers that write invalid pixels as one point):
    /// they carry no geometry and make every radius search quadratic. Not in the seed.
    pub duplicate_leaf: f64,
    /// Unorganized clouds are segmented on one point per voxel of this leaf (m) and
    /// every prism point takes its voxel's label and normal: their k-d tree crease test
    /// and normals cost a radius search per point, and a Kinect's points lie 1–2 mm
    /// apart at a metre, far denser than the centimetre a crease or a gap is judged on.
    /// 0 segments every point. Not in the seed.
    pub unorganized_leaf: f64,
    /// Organized frames are segmented on every `frame_stride`-th pixel of every
    /// `frame_stride`-th row, and every pixel then takes the segment of the nearest
    /// sample within the clustering's reach (see `tabletop::stride`). 1 (the default)
    /// segments every pixel. 2 is ¼ of the work on a 640×480 frame and on PCL's real
    /// labelled mOSD frames found as many objects as every pixel did, but on the
    /// generated suite it merges touching boxes a few millimetres apart in height
    /// (126 of 133 objects against 129; BENCHMARKS.md, issue 33).
    /// Point counts and pixel steps above are for the full frame. Not in the seed.
    pub frame_stride: usize,
    /// Sensor pixels between neighbouring pixels of the frames given: 1 for a full
    /// frame, the step of a decimated one (set by `at_stride`). The crease test's reach
    /// in metres counts pixels of the sensor, so it grows with the spacing. Not in the
    /// seed.
    pub pixel_spacing: usize,
}

impl Default for TabletopParams {
    fn default() -> Self {
        Self {
            remove_outliers: true,
            outliers: OutlierParams::default(),
            surfaces: SurfaceParams::default(),
            normals: NormalParams::default(),
            min_height: 0.01,
            cluster_tolerance: 0.01,
            cluster_range_gain: 0.003,
            concavity_tolerance: 25f64.to_radians(),
            concavity_step: 4,
            step_tolerance: 0.004,
            min_object_points: 200,
            min_object_height: 0.012,
            min_stacked_height: 0.025,
            top_band: 0.01,
            support_reach: 0.3,
            rest_tolerance: 0.015,
            max_object_extent: 1.5,
            partial_gap: 0.03,
            duplicate_leaf: 0.0005,
            unorganized_leaf: 0.004,
            frame_stride: 1,
            pixel_spacing: 1,
        }
    }
}

impl Validate for TabletopParams {
    fn check(&self, at: &str) -> Result<(), String> {
        self.outliers.check(&nested(at, "outliers"))?;
        self.surfaces.check(&nested(at, "surfaces"))?;
        self.normals.check(&nested(at, "normals"))?;
        check_non_negative(at, "min_height", self.min_height)?;
        check_positive(at, "cluster_tolerance", self.cluster_tolerance)?;
        check_non_negative(at, "cluster_range_gain", self.cluster_range_gain)?;
        check_in(
            at,
            "concavity_tolerance",
            self.concavity_tolerance,
            0.0,
            std::f64::consts::PI,
        )?;
        check_count(at, "concavity_step", self.concavity_step, 1)?;
        check_non_negative(at, "step_tolerance", self.step_tolerance)?;
        check_count(at, "min_object_points", self.min_object_points, 1)?;
        check_non_negative(at, "min_object_height", self.min_object_height)?;
        check_non_negative(at, "min_stacked_height", self.min_stacked_height)?;
        check_non_negative(at, "top_band", self.top_band)?;
        check_non_negative(at, "support_reach", self.support_reach)?;
        check_non_negative(at, "rest_tolerance", self.rest_tolerance)?;
        check_positive(at, "max_object_extent", self.max_object_extent)?;
        check_non_negative(at, "partial_gap", self.partial_gap)?;
        check_off_or_in(at, "duplicate_leaf", self.duplicate_leaf, 1e-6, 0.05)?;
        check_off_or_in(at, "unorganized_leaf", self.unorganized_leaf, 1e-4, 0.5)?;
        check_in(at, "frame_stride", self.frame_stride as f64, 1.0, 8.0)?;
        check_in(at, "pixel_spacing", self.pixel_spacing as f64, 1.0, 64.0)
    }
}

impl TabletopParams {
    /// These parameters for a frame decimated to every `stride`-th pixel of every
    /// `stride`-th row: point counts and pixel steps are for full frames, and a
    /// decimated frame has `stride`² fewer points and its pixels `stride` times as far
    /// apart — the crease step and the normals' window cover as much of a surface as
    /// on the full frame (rounded up), and the crease test reaches as far in metres.
    /// The result segments every pixel it is given (`frame_stride` 1).
    pub fn at_stride(&self, stride: usize) -> Self {
        let d = stride.max(1);
        Self {
            min_object_points: (self.min_object_points / (d * d)).max(1),
            concavity_step: (self.concavity_step / d).max(1),
            normals: NormalParams {
                window: self.normals.window.div_ceil(d),
                ..self.normals.clone()
            },
            frame_stride: 1,
            pixel_spacing: self.pixel_spacing * d,
            ..self.clone()
        }
    }
}
