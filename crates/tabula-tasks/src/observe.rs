//! What the robot sees: camera frames in the world minus the robot's own body, the
//! object near a given position and the surface it stands on, and the occupancy that
//! becomes the collision world.

use crate::scene::SeenObject;
pub use crate::scene::robot_solids;
use rustc_hash::{FxHashMap, FxHashSet};
use tabula_geom::input::{Validate, check_count, check_non_negative, check_positive, nested};
use tabula_geom::polygon::min_area_rectangle;
use tabula_geom::{Vec2, Vec3};
use tabula_perception::selffilter::{PlacedSolid, SelfFilterParams, self_filter};
use tabula_perception::stray::{StrayParams, stray_returns};
use tabula_robot::driver::CameraFrame;

/// Parameters of looking at an object or a surface near a given position.
#[derive(Debug, Clone, serde::Deserialize, serde::Serialize)]
#[serde(default, deny_unknown_fields)]
pub struct ObserveParams {
    /// Self-filter padding (m), SPEC §1.1: 0.9 cm.
    pub self_filter: SelfFilterParams,
    /// Horizontal search radius around the given position (m): how approximate a
    /// position may be.
    pub search_radius: f64,
    /// Height band searched below and above the given position (m).
    pub below: f64,
    pub above: f64,
    /// Histogram bin of the support search (m); SPEC §6's 1 cm RANSAC threshold.
    pub support_bin: f64,
    /// Points at least this far above the support belong to objects (m).
    pub object_clearance: f64,
    /// Points closer than this are the same object (m).
    pub cluster_gap: f64,
    /// An object needs at least this many points.
    pub min_object_points: usize,
    /// Occupancy voxel for the collision world (m).
    pub voxel: f64,
    /// Frames are downsampled to this leaf before anything else (m), SPEC §6: 5 mm.
    pub leaf: f64,
    /// Points farther than this from the camera are dropped (m): beyond any arm's reach
    /// they only cost time.
    pub max_range: f64,
    /// Seen surfaces are taken to be solid this far behind themselves along the camera
    /// ray (m), in the collision world: the side of a panel seen only by its front edge
    /// is there too.
    pub thickness: f64,
    /// Which returns of a frame are strays, dropped before anything else sees them.
    pub stray: StrayParams,
}

impl Default for ObserveParams {
    fn default() -> Self {
        Self {
            self_filter: SelfFilterParams::default(),
            search_radius: 0.12,
            below: 0.25,
            above: 0.35,
            support_bin: 0.01,
            object_clearance: 0.008,
            cluster_gap: 0.015,
            min_object_points: 40,
            voxel: 0.02,
            leaf: 0.005,
            max_range: 2.5,
            thickness: 0.04,
            stray: StrayParams::default(),
        }
    }
}

impl ObserveParams {
    /// A seen point and points behind it along `ray` (unit) at half-voxel steps down to
    /// the thickness.
    pub fn thickness_steps(&self, point: Vec3, ray: Vec3) -> impl Iterator<Item = Vec3> {
        let step = (self.voxel / 2.0).max(1e-3);
        let n = (self.thickness.max(0.0) / step).ceil().min(64.0) as usize;
        (0..=n).map(move |k| point + ray * (k as f64 * step))
    }
}

/// Why looking found nothing.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ObserveError {
    #[error("no horizontal surface under ({0:.3}, {1:.3}, {2:.3})")]
    NoSurface(f64, f64, f64),
    #[error("no object near ({0:.3}, {1:.3}, {2:.3})")]
    NoObject(f64, f64, f64),
}

/// The finite points of a frame in the world, downsampled to `leaf`, minus those on the
/// robot's body.
pub fn world_points(
    frame: &CameraFrame,
    solids: &[PlacedSolid],
    p: &ObserveParams,
    leaf: f64,
) -> Vec<Vec3> {
    let near = in_range_world(frame, p);
    let pts = tabula_perception::filters::voxel_grid(&near, leaf).unwrap_or(near);
    off_the_robot(pts, solids, p)
}

/// [`world_points`] without the downsampling, for a caller that keeps one point per
/// voxel over many frames anyway (a sweep's merged scene): a frame at a few metres
/// has about one point per centimetre voxel, so thinning it first only costs time.
pub fn world_points_unthinned(
    frame: &CameraFrame,
    solids: &[PlacedSolid],
    p: &ObserveParams,
) -> Vec<Vec3> {
    off_the_robot(in_range_world(frame, p), solids, p)
}

/// A frame's finite points within range, in the world frame, without its stray
/// returns (a lone point in the air would stay in a sweep's scene for good).
fn in_range_world(frame: &CameraFrame, p: &ObserveParams) -> Vec<Vec3> {
    let stray = stray_returns(&frame.cloud, &p.stray);
    frame
        .cloud
        .points
        .iter()
        .zip(stray)
        .filter(|(q, stray)| !stray && q.is_finite() && q.length() <= p.max_range)
        .map(|(q, _)| frame.world_from_camera.transform_point(*q))
        .collect()
}

/// `points` minus those on the robot's body.
fn off_the_robot(points: Vec<Vec3>, solids: &[PlacedSolid], p: &ObserveParams) -> Vec<Vec3> {
    let keep = self_filter(&points, solids, &p.self_filter);
    points
        .into_iter()
        .zip(keep)
        .filter_map(|(q, k)| k.then_some(q))
        .collect()
}

/// A horizontal support found under a position.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Support {
    /// Height of the support's top (m).
    pub z: f64,
    /// Points on it within the search radius.
    pub points: usize,
}

/// The highest well-populated horizontal level at or below `below_z` within the search
/// radius of `at` — the board or table top something stands (or will stand) on.
pub fn support_under(
    points: &[Vec3],
    at: Vec3,
    below_z: f64,
    p: &ObserveParams,
) -> Option<Support> {
    let bin = p.support_bin.max(1e-3);
    let r2 = p.search_radius * p.search_radius;
    let near: Vec<f64> = points
        .iter()
        .filter(|q| {
            (q.truncate() - at.truncate()).length_squared() <= r2
                && q.z <= below_z
                && q.z >= at.z - p.below
        })
        .map(|q| q.z)
        .collect();
    let mut bins: FxHashMap<i64, usize> = FxHashMap::default();
    for z in &near {
        *bins.entry((z / bin).floor() as i64).or_default() += 1;
    }
    // A level counts with its neighbour bins (noise straddles a bin edge).
    let count = |k: i64| -> usize {
        (k - 1..=k + 1)
            .map(|b| bins.get(&b).copied().unwrap_or(0))
            .sum()
    };
    let peak = bins.keys().map(|&k| count(k)).max()?;
    let floor = (peak as f64 * 0.3).max(p.min_object_points as f64) as usize;
    // Highest level with at least 30 % of the best level's support: a board seen at a
    // grazing angle has fewer points than one seen from above, but far more than the
    // rim of an object standing on it.
    let mut candidates: Vec<i64> = bins
        .keys()
        .copied()
        .filter(|&k| count(k) >= floor)
        .collect();
    candidates.sort_unstable();
    let top = *candidates.last()?;
    // Local maximum near the top candidate, then the mean height of its points.
    let k = (top - 2..=top).max_by_key(|&b| count(b))?;
    let level: Vec<f64> = near
        .iter()
        .copied()
        .filter(|z| (z / bin).floor() as i64 >= k - 1 && (z / bin).floor() as i64 <= k + 1)
        .collect();
    let z = level.iter().sum::<f64>() / level.len().max(1) as f64;
    Some(Support {
        z,
        points: level.len(),
    })
}

/// The object standing nearest `at` (world; approximate): the support under it, the
/// points above the support clustered, the cluster nearest `at`. Its footprint comes
/// from its top face when the camera sees one (the whole top of a can or a box is
/// visible from above, its sides only half), otherwise from all its points.
pub fn object_near(
    points: &[Vec3],
    at: Vec3,
    p: &ObserveParams,
) -> Result<SeenObject, ObserveError> {
    let no_object = || ObserveError::NoObject(at.x, at.y, at.z);
    let support =
        support_under(points, at, at.z, p).ok_or(ObserveError::NoSurface(at.x, at.y, at.z))?;
    let reach = p.search_radius + 0.1;
    let above: Vec<Vec3> = points
        .iter()
        .copied()
        .filter(|q| {
            (q.truncate() - at.truncate()).length() <= reach
                && q.z > support.z + p.object_clearance
                && q.z < at.z + p.above
        })
        .collect();
    let clusters = clusters(&above, p.cluster_gap);
    let best = clusters
        .into_iter()
        .filter(|c| c.len() >= p.min_object_points)
        .map(|c| {
            let centroid = c.iter().map(|&i| above[i]).sum::<Vec3>() / c.len() as f64;
            let d = (centroid.truncate() - at.truncate()).length();
            (d, c)
        })
        .filter(|(d, _)| *d <= p.search_radius)
        .min_by(|a, b| a.0.total_cmp(&b.0))
        .ok_or_else(no_object)?;
    let pts: Vec<Vec3> = best.1.iter().map(|&i| above[i]).collect();
    let mut zs: Vec<f64> = pts.iter().map(|q| q.z).collect();
    zs.sort_by(f64::total_cmp);
    let top = zs[(zs.len() * 98 / 100).min(zs.len() - 1)];
    let all_xy: Vec<Vec2> = pts.iter().map(|q| q.truncate()).collect();
    let whole = min_area_rectangle(&all_xy).ok_or_else(no_object)?;
    let top_xy: Vec<Vec2> = pts
        .iter()
        .filter(|q| q.z >= top - 0.012)
        .map(|q| q.truncate())
        .collect();
    let (footprint, outline_of) = match min_area_rectangle(&top_xy) {
        // A top face seen whole spans (nearly) the object's own width and depth.
        Some(r) if r.size.x * r.size.y >= 0.6 * whole.size.x * whole.size.y => (r, &top_xy),
        _ => (whole, &all_xy),
    };
    let outline: Vec<Vec2> = tabula_geom::polygon::convex_hull_2d(outline_of)
        .iter()
        .map(|&i| outline_of[i])
        .collect();
    SeenObject::standing(pts, (outline, footprint), (support.z, top)).ok_or_else(no_object)
}

/// Connected components of points closer than `gap` (a voxel hash of cell `gap`).
pub fn clusters(points: &[Vec3], gap: f64) -> Vec<Vec<usize>> {
    let gap = gap.max(1e-4);
    let key = |q: Vec3| tabula_geom::voxel_key(q, gap);
    let mut cells: FxHashMap<[i64; 3], Vec<usize>> = FxHashMap::default();
    for (i, q) in points.iter().enumerate() {
        cells.entry(key(*q)).or_default().push(i);
    }
    let mut label = vec![usize::MAX; points.len()];
    let mut out = Vec::new();
    for seed in 0..points.len() {
        if label[seed] != usize::MAX {
            continue;
        }
        let id = out.len();
        let mut members = vec![seed];
        label[seed] = id;
        let mut k = 0;
        while k < members.len() {
            let q = points[members[k]];
            let c = key(q);
            for dx in -1..=1 {
                for dy in -1..=1 {
                    for dz in -1..=1 {
                        let Some(list) = cells.get(&[c[0] + dx, c[1] + dy, c[2] + dz]) else {
                            continue;
                        };
                        for &j in list {
                            if label[j] == usize::MAX && (points[j] - q).length() <= gap {
                                label[j] = id;
                                members.push(j);
                            }
                        }
                    }
                }
            }
            k += 1;
        }
        out.push(members);
    }
    out
}

/// Occupied voxels of a point set: integer cell keys of edge `voxel`.
pub fn voxel_keys(points: &[Vec3], voxel: f64) -> FxHashSet<[i64; 3]> {
    points
        .iter()
        .filter(|q| q.is_finite())
        .map(|q| tabula_geom::voxel_key(*q, voxel))
        .collect()
}

impl Validate for ObserveParams {
    fn check(&self, at: &str) -> Result<(), String> {
        self.self_filter.check(&nested(at, "self_filter"))?;
        self.stray.check(&nested(at, "stray"))?;
        for (name, v) in [
            ("search_radius", self.search_radius),
            ("support_bin", self.support_bin),
            ("cluster_gap", self.cluster_gap),
            ("voxel", self.voxel),
            ("leaf", self.leaf),
            ("max_range", self.max_range),
            ("thickness", self.thickness),
        ] {
            check_positive(at, name, v)?;
        }
        for (name, v) in [
            ("below", self.below),
            ("above", self.above),
            ("object_clearance", self.object_clearance),
        ] {
            check_non_negative(at, name, v)?;
        }
        check_count(at, "min_object_points", self.min_object_points, 1)
    }
}
