//! One frame, start to end: read a cloud file (PCD or PLY), frame it (a given pose,
//! `up`, its VIEWPOINT or the optical frame), remove the robot, and run the tabletop
//! pipeline, the surface search and the free-space map — what `tabula perceive` and the
//! `/tabula/perceive` service answer, and the JSON they answer with.

use crate::freespace::{FreeSpaceError, FreeSpaceMap, FreeSpaceParams, Placement};
use crate::selffilter::{PlacedSolid, SelfFilterParams, self_filter};
use crate::support::{Framing, SupportError, SupportParams, frame_cloud};
use crate::surfaces::{SurfaceParams, SurfaceSearch, find_surfaces};
use crate::tabletop::{TableObject, Tabletop, TabletopError, TabletopParams, extract_framed};
use crate::{Surface, to_world};
use serde_json::{Value, json};
use std::path::Path;
use std::time::Instant;
use tabula_geom::input::{Format, InputError, read_bytes};
use tabula_geom::{CloudFile, PcdError, PlyError, PointCloud, Pose, Vec3, read_pcd_file, read_ply};

/// Why a frame gave no answer.
#[derive(Debug, thiserror::Error)]
pub enum FrameError {
    #[error(transparent)]
    Input(#[from] InputError),
    #[error("{path}: {source}")]
    Pcd { path: String, source: PcdError },
    #[error("{path}: {source}")]
    Ply { path: String, source: PlyError },
    #[error(transparent)]
    Support(#[from] SupportError),
    #[error(transparent)]
    Tabletop(#[from] TabletopError),
    #[error(transparent)]
    FreeSpace(#[from] FreeSpaceError),
}

/// Reads a PCD or PLY file (by its first bytes, whatever the extension) with its
/// colours and sensor pose.
pub fn read_cloud_file(path: &Path) -> Result<CloudFile, FrameError> {
    let bytes = read_bytes(path, Format::Cloud)?;
    let shown = path.display().to_string();
    if bytes.starts_with(b"ply") {
        read_ply(&bytes)
            .map(CloudFile::plain)
            .map_err(|source| FrameError::Ply {
                path: shown,
                source,
            })
    } else {
        read_pcd_file(&bytes).map_err(|source| FrameError::Pcd {
            path: shown,
            source,
        })
    }
}

/// What perception makes of one frame: how it was framed, the cloud in that frame
/// (robot removed), the tabletop, every surface, the support's free space.
pub struct Perceived {
    pub framing: Framing,
    pub cloud: PointCloud,
    pub result: Tabletop,
    pub surfaces: SurfaceSearch,
    pub map: FreeSpaceMap,
    /// Points the robot's self-filter removed.
    pub removed: usize,
    /// Wall time of framing and the tabletop pipeline.
    pub ms: f64,
}

/// Frames `file` (a given pose, `up`, its VIEWPOINT or the optical frame), removes the
/// robot's `solids`, and runs the tabletop pipeline, the surface search and the free
/// space map.
pub fn perceive(
    file: &CloudFile,
    world_from_camera: Option<Pose>,
    up: Option<Vec3>,
    solids: &[PlacedSolid],
    params: &TabletopParams,
) -> Result<Perceived, FrameError> {
    let t0 = Instant::now();
    let framing = frame_cloud(
        &file.cloud,
        &file.viewpoint,
        world_from_camera,
        up,
        &SupportParams::default(),
    )?;
    let mut cloud = to_world(&framing.world_from_cloud, &file.cloud);
    let mut removed = 0;
    if !solids.is_empty() {
        let keep = self_filter(&cloud.points, solids, &SelfFilterParams::default());
        for (p, k) in cloud.points.iter_mut().zip(&keep) {
            if !k && p.is_finite() {
                *p = Vec3::NAN;
                removed += 1;
            }
        }
    }
    let result = extract_framed(&cloud, &framing, params)?;
    let ms = t0.elapsed().as_secs_f64() * 1e3;
    let surfaces = find_surfaces(&cloud, None, &listed_surfaces(&framing, params), false);
    let map = FreeSpaceMap::from_tabletop(&result, &cloud.points, &FreeSpaceParams::default())?;
    Ok(Perceived {
        framing,
        cloud,
        result,
        surfaces,
        map,
        removed,
        ms,
    })
}

/// The surface search behind `Perceived::surfaces`. `height_range` is world z over a
/// floor; in a frame built on the support (at z = 0, whatever it is: a table, a floor)
/// the same span is counted from the support, which is itself listed.
fn listed_surfaces(framing: &Framing, params: &TabletopParams) -> SurfaceParams {
    let p = &params.surfaces;
    let [lo, hi] = p.height_range;
    match framing.support {
        Some(_) => SurfaceParams {
            height_range: [-p.ransac.threshold, hi - lo],
            ..p.clone()
        },
        None => p.clone(),
    }
}

impl Perceived {
    /// What `perceive --json` prints (`placement`: the answer to `--place`, if asked;
    /// `colors`: the file's, for each object's mean colour).
    /// One label per point of the input, PCL's convention for segmentations: 0 not an
    /// object (the table, the background, no depth), k ≥ 1 segment k — the whole objects
    /// first (`objects[k − 1]`), then the objects cut by the frame's edge (`--json`'s
    /// `label` keys).
    pub fn segment_labels(&self) -> Vec<u32> {
        let t = &self.result;
        let mut labels = vec![0u32; self.cloud.points.len()];
        for (k, o) in t.objects.iter().chain(&t.partial).enumerate() {
            for &i in &o.indices {
                if let Some(l) = labels.get_mut(i) {
                    *l = k as u32 + 1;
                }
            }
        }
        labels
    }

    pub fn to_json(
        &self,
        placement: Option<Option<Placement>>,
        colors: Option<&[[u8; 3]]>,
    ) -> Value {
        let t = &self.result;
        // Labels as `segment_labels` gives them: whole objects first, then the cut ones.
        let whole = t.objects.len();
        let objects: Vec<_> = (t.objects.iter().enumerate())
            .map(|(k, o)| object_json(o, k + 1, colors))
            .collect();
        let partial: Vec<_> = (t.partial.iter().enumerate())
            .map(|(k, o)| object_json(o, whole + k + 1, colors))
            .collect();
        let surfaces: Vec<_> = self.surfaces.surfaces.iter().map(surface_json).collect();
        json!({
            "partial_objects": partial,
            "table": {"height": t.table.centroid.z, "normal": arr(t.plane.normal), "d": t.plane.d, "points": t.table.inliers.len(), "area": t.table.area, "hull_area": t.table.hull_area, "centroid": arr(t.table.centroid), "hull": points(&t.table.hull)},
            "surfaces": surfaces,
            "objects": objects,
            "free_area": self.map.free_area(),
            "placement": placement.map(|p| p.map(|p| json!({"position": arr(p.position), "yaw": p.yaw, "clearance": p.clearance}))),
            "self_filtered_points": self.removed,
            "kept_after_outlier_removal": t.kept,
            "times_ms": t.times,
            "ms": self.ms,
            "frame": {
                "source": self.framing.source,
                "world_from_cloud": pose_json(&self.framing.world_from_cloud),
                "sensor": arr(self.framing.eye),
            },
        })
    }
}

fn object_json(o: &TableObject, label: usize, colors: Option<&[[u8; 3]]>) -> Value {
    json!({
        "label": label,
        "points": o.indices.len(),
        "size": arr(o.obb.half_extents * 2.0),
        "yaw": box_yaw(o),
        "color": colors.map(|c| mean_colour(c, &o.indices)),
        "centroid": arr(o.centroid),
        "axes": o.axes.map(arr),
        "table_axes": o.table_axes.map(arr),
        "obb": {"center": arr(o.obb.center), "axes": o.obb.axes.map(arr), "half_extents": arr(o.obb.half_extents)},
        "height": o.height,
        "footprint": points(&o.footprint),
        "hull": {"vertices": points(&o.hull_vertices), "triangles": o.hull_triangles},
        "top": o.top.as_ref().map(|s| json!({"height": s.height, "area": s.area, "centroid": arr(s.centroid), "hull": points(&s.hull)})),
    })
}

fn surface_json(s: &Surface) -> Value {
    json!({"normal": arr(s.plane.normal), "d": s.plane.d, "points": s.inliers.len(), "area": s.area, "hull_area": s.hull_area, "centroid": arr(s.centroid), "hull": points(&s.hull)})
}

/// Yaw (rad) of a box's long side from the world x axis, in [-90°, 90°): a box turned
/// by 180° is the same box.
pub fn box_yaw(o: &TableObject) -> f64 {
    let a = o.obb.axes[0];
    let yaw = a.y.atan2(a.x);
    let half = std::f64::consts::FRAC_PI_2;
    (yaw + half).rem_euclid(std::f64::consts::PI) - half
}

/// Mean colour of some points.
pub fn mean_colour(colors: &[[u8; 3]], indices: &[usize]) -> [u8; 3] {
    let mut sum = [0u64; 3];
    for &i in indices {
        for (s, c) in sum.iter_mut().zip(colors[i]) {
            *s += c as u64;
        }
    }
    let n = indices.len().max(1) as u64;
    sum.map(|s| (s / n) as u8)
}

fn pose_json(p: &Pose) -> [f64; 7] {
    let (t, q) = (p.translation, p.rotation);
    [t.x, t.y, t.z, q.x, q.y, q.z, q.w]
}

fn arr(v: Vec3) -> [f64; 3] {
    v.to_array()
}

fn points(v: &[Vec3]) -> Vec<[f64; 3]> {
    v.iter().map(|p| arr(*p)).collect()
}
