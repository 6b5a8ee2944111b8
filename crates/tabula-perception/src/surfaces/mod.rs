//! Surface search (SPEC §1.3, Alg. 9): fit planes one after another, accept the
//! horizontal ones at a reachable height, peel everything else (floor, walls, ramps)
//! off and look again. Unlike the seed, coplanar but disjoint surfaces (two tables at
//! one height, shelves of a bookshelf) come out as separate surfaces, and each surface
//! reports the area it really covers, not its hull's.

mod split;

pub(crate) use split::split;

use crate::filters::{Neighbours, NormalParams, local_planes_at};
use crate::plane::{Plane, RansacParams, ransac_plane, ransac_round};
use tabula_geom::input::{
    Validate, check_count, check_in, check_non_negative, check_positive, nested,
};
use tabula_geom::{PointCloud, Vec3};

/// Parameters; defaults from SPEC §6 (seed 000's repository).
#[derive(Debug, Clone, serde::Deserialize, serde::Serialize)]
#[serde(default, deny_unknown_fields)]
pub struct SurfaceParams {
    /// Plane fitting (1 cm inlier threshold, SPEC §6).
    pub ransac: RansacParams,
    /// Largest tilt of a surface's normal from vertical (rad), SPEC §6.
    pub max_tilt: f64,
    /// A plane needs this fraction of the cloud's points to count. SPEC §6 has 5 %;
    /// the default is 0 because a share of the cloud says nothing about one table (a
    /// table that is 5 % of a frame was missed in half the noise draws): absolute
    /// units decide — `min_plane_points`, `min_area`, `min_inscribed_radius`.
    pub min_plane_fraction: f64,
    /// Stop when less than this fraction of the cloud is left. SPEC §6 has 10 %; the
    /// default is 0 for the same reason.
    pub stop_fraction: f64,
    /// A plane needs this many (searched) points to be looked at, and the search stops
    /// when fewer are left.
    pub min_plane_points: usize,
    /// Heights (world z, m) where a surface is reachable.
    pub height_range: [f64; 2],
    /// Smallest surface area (m²); the seed's tests used 100 cm².
    pub min_area: f64,
    /// A surface must hold a disc of this radius (m) somewhere — 10 cm across, as the
    /// seed's 100 cm² — so slices of vertical things (a drum's side cut by a table's
    /// plane) are not surfaces.
    pub min_inscribed_radius: f64,
    /// A slice of something vertical (a wall or a drum's side cut by a plane, widened
    /// by depth noise at range) has as many points just above and below the slice as
    /// in it; a surface has what stands on it above and nothing below. A piece is
    /// refused when the points 3–8 RANSAC thresholds off its plane in cells that have
    /// them on both sides outnumber its own points by more than this ratio.
    pub max_slice_ratio: f64,
    /// A surface's own points must be flat: at least `min_flat_fraction` of a sample of
    /// them have local normals (from the whole cloud around them) within this angle
    /// (rad) of the plane's — a plane cutting a shallow cone or a dome has a band of
    /// inliers whose surface is tilted.
    pub flat_normal_angle: f64,
    pub min_flat_fraction: f64,
    /// Refinement: points this close (m) to the plane are refitted (SPEC §6: 0.02 m) …
    pub refine_threshold: f64,
    /// … this many times (SPEC §6: 3).
    pub refine_iterations: usize,
    /// Grid cell (m) that decides which inliers are one connected surface.
    pub cell: f64,
    /// Most planes tried.
    pub max_planes: usize,
    /// Organized clouds are searched on every `stride`-th pixel of every `stride`-th
    /// row (SPEC §1.3 downsamples first); accepted surfaces then collect their points
    /// at full resolution.
    pub stride: usize,
}

impl Default for SurfaceParams {
    fn default() -> Self {
        Self {
            ransac: RansacParams::default(),
            max_tilt: 0.09,
            min_plane_fraction: 0.0,
            stop_fraction: 0.0,
            min_plane_points: 30,
            height_range: [0.2, 1.6],
            min_area: 0.01,
            min_inscribed_radius: 0.05,
            max_slice_ratio: 1.0,
            flat_normal_angle: 15f64.to_radians(),
            min_flat_fraction: 0.6,
            refine_threshold: 0.02,
            refine_iterations: 3,
            cell: 0.02,
            max_planes: 12,
            stride: 2,
        }
    }
}

/// A horizontal surface.
#[derive(Debug, Clone)]
pub struct Surface {
    /// Upward-facing plane.
    pub plane: Plane,
    /// Indices of its points in the cloud.
    pub inliers: Vec<usize>,
    /// Convex hull on the plane (world points, counter-clockwise seen from above).
    pub hull: Vec<Vec3>,
    /// Area covered by its points (occupied grid cells, m²).
    pub area: f64,
    /// Area of the hull (m²).
    pub hull_area: f64,
    pub centroid: Vec3,
    /// Distance (m) from the plane within which its points were taken: the RANSAC
    /// threshold, or more where the sensor's noise on this surface is larger.
    pub threshold: f64,
}

/// A plane that was looked at, accepted or not, and why (for reports and tests).
#[derive(Debug, Clone)]
pub struct PlaneTrial {
    pub plane: Plane,
    pub points: usize,
    pub tilt: f64,
    pub height: f64,
    pub verdict: Verdict,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Verdict {
    Accepted,
    TooTilted,
    OutOfReach,
    TooSmall,
}

/// Everything the search found.
#[derive(Debug, Clone, Default)]
pub struct SurfaceSearch {
    pub surfaces: Vec<Surface>,
    pub trials: Vec<PlaneTrial>,
}

pub use tabula_geom::polygon::plane_basis;

/// Searches a cloud in the world frame (z up; NaN = none), restricted to `keep` if
/// given while fitting. Each accepted surface's `inliers` are then every finite point
/// within the RANSAC threshold of its plane in its connected region — outlier removal
/// protects the fit, it does not decide what is table. With `first_only` the search
/// stops at the first accepted plane (the tabletop pipeline).
pub fn find_surfaces(
    cloud: &PointCloud,
    keep: Option<&[bool]>,
    p: &SurfaceParams,
    first_only: bool,
) -> SurfaceSearch {
    let points = &cloud.points;
    let mut remaining = searched_points(cloud, keep, p);
    let total = remaining.len();
    let mut out = SurfaceSearch::default();
    let mut taken = vec![false; points.len()];
    for round in 0..p.max_planes {
        if remaining.len() < p.min_plane_points.max(3)
            || (remaining.len() as f64) < p.stop_fraction * total as f64
        {
            break;
        }
        let Some((plane, inliers)) = ransac_round(points, &remaining, &p.ransac, round) else {
            break;
        };
        if (inliers.len() as f64) < p.min_plane_fraction * total as f64
            || inliers.len() < p.min_plane_points.max(3)
        {
            break;
        }
        let up = if plane.normal.z < 0.0 {
            plane.flipped()
        } else {
            plane
        };
        let tilt = up.normal.angle_between(Vec3::Z);
        let height = inliers.iter().map(|&i| points[i].z).sum::<f64>() / inliers.len() as f64;
        let mut verdict = if tilt > p.max_tilt {
            Verdict::TooTilted
        } else if height < p.height_range[0] || height > p.height_range[1] {
            Verdict::OutOfReach
        } else {
            Verdict::Accepted
        };
        let mut peeled = inliers;
        if verdict == Verdict::Accepted {
            let (found, inliers) = pieces(cloud, &remaining, up, p);
            if found.is_empty() {
                verdict = Verdict::TooSmall;
            }
            peeled = inliers;
            out.surfaces.extend(found);
        }
        out.trials.push(PlaneTrial {
            plane: up,
            points: peeled.len(),
            tilt,
            height,
            verdict,
        });
        if first_only && !out.surfaces.is_empty() {
            break;
        }
        for &i in &peeled {
            taken[i] = true;
        }
        remaining.retain(|&i| !taken[i]);
    }
    out
}

/// The points a search looks at: finite, kept, and on an organized cloud every
/// `stride`-th pixel of every `stride`-th row.
fn searched_points(cloud: &PointCloud, keep: Option<&[bool]>, p: &SurfaceParams) -> Vec<usize> {
    let points = &cloud.points;
    grid_sample(cloud, p.stride, |i| {
        points[i].is_finite() && keep.is_none_or(|k| k.get(i) == Some(&true))
    })
}

/// The indices `usable` accepts of every `stride`-th pixel of every `stride`-th row of
/// an organized cloud; of every point of an unorganized one.
pub(crate) fn grid_sample(
    cloud: &PointCloud,
    stride: usize,
    usable: impl Fn(usize) -> bool,
) -> Vec<usize> {
    let stride = stride.max(1);
    if cloud.is_organized() && stride > 1 {
        (0..cloud.height)
            .step_by(stride)
            .flat_map(|y| {
                (0..cloud.width)
                    .step_by(stride)
                    .map(move |x| y * cloud.width + x)
            })
            .filter(|&i| usable(i))
            .collect()
    } else {
        (0..cloud.points.len()).filter(|&i| usable(i)).collect()
    }
}

/// The surfaces on a plane hypothesis: refined, split into connected pieces, only the
/// flat ones; and the searched points it claims.
fn pieces(
    cloud: &PointCloud,
    candidates: &[usize],
    plane: Plane,
    p: &SurfaceParams,
) -> (Vec<Surface>, Vec<usize>) {
    let (plane, inliers, threshold, band) = refine(cloud, candidates, plane, p);
    let at_noise = SurfaceParams {
        ransac: RansacParams {
            threshold,
            ..p.ransac.clone()
        },
        ..p.clone()
    };
    // The flatness check looks among the points within 8 thresholds of the plane: at
    // the RANSAC threshold those are the refinement's own band (the refined plane is
    // within a threshold of it), whose neighbour index is reused.
    let band = band.filter(|_| threshold <= p.ransac.threshold);
    let mut found = split(&cloud.points, &plane, &inliers, &at_noise);
    found.retain(|s| is_flat(cloud, s, &at_noise, band.as_ref()));
    (found, inliers)
}

/// Every surface on a plane already known — a surface seen again to refine it (Alg. 9's
/// second look): the same refinement, pieces and checks, without searching for the
/// plane among everything else at that height.
pub fn surfaces_on(
    cloud: &PointCloud,
    keep: Option<&[bool]>,
    plane: Plane,
    p: &SurfaceParams,
) -> Vec<Surface> {
    let candidates = searched_points(cloud, keep, p);
    pieces(cloud, &candidates, plane, p).0
}

/// Whether a surface's points lie on something flat (see `flat_normal_angle`).
/// Neighbours come from the pixel window (organized) or, unorganized, from the points
/// near the plane, which hold whatever the surface is part of.
fn is_flat(cloud: &PointCloud, s: &Surface, p: &SurfaceParams, band: Option<&Neighbours>) -> bool {
    const SAMPLES: usize = 200;
    let step = s.inliers.len().div_ceil(SAMPLES).max(1);
    let sample: Vec<usize> = s.inliers.iter().copied().step_by(step).collect();
    let eye = s.centroid + s.plane.normal;
    // Wide neighbourhoods: depth noise at a few metres swamps a 7-pixel window.
    let wide = NormalParams {
        window: 7,
        k: 200,
        ..NormalParams::default()
    };
    let normals = match band {
        Some(index) if !cloud.is_organized() => index.local_planes_at(cloud, eye, &sample, &wide),
        _ => {
            let band = 8.0 * p.ransac.threshold;
            let mask: Vec<bool> = cloud
                .points
                .iter()
                .map(|q| {
                    let off = s.plane.distance(*q).abs();
                    cloud.is_organized() && q.is_finite() || off <= band
                })
                .collect();
            local_planes_at(cloud, eye, &mask, &sample, &wide)
        }
    };
    let cos = p.flat_normal_angle.cos();
    let flat = normals
        .iter()
        .filter(|(n, _)| n.dot(s.plane.normal).abs() >= cos)
        .count();
    flat as f64 >= p.min_flat_fraction * sample.len() as f64
}

/// The candidates within twice the refinement band of a plane (an even sample of at
/// most 4,000) whose local normals (from the whole cloud around them) are within the
/// RANSAC normal angle of the plane's, sorted.
fn facing_points(
    cloud: &PointCloud,
    candidates: &[usize],
    plane: &Plane,
    p: &SurfaceParams,
) -> (Vec<usize>, Option<Neighbours>) {
    let reach = 2.0 * p.refine_threshold.max(p.ransac.threshold);
    let near: Vec<usize> = candidates
        .iter()
        .copied()
        .filter(|&i| plane.distance(cloud.points[i]).abs() <= reach)
        .collect();
    // Fits need thousands of points, not a floor's hundred thousand: an even sample.
    const MOST: usize = 1_000;
    let near: Vec<usize> = near
        .iter()
        .copied()
        .step_by(near.len().div_ceil(MOST).max(1))
        .collect();
    let band = 8.0 * p.ransac.threshold;
    let mask: Vec<bool> = cloud
        .points
        .iter()
        .map(|q| cloud.is_organized() && q.is_finite() || plane.distance(*q).abs() <= band)
        .collect();
    let eye = plane.normal * (1.0 - plane.d);
    let band = (!cloud.is_organized())
        .then(|| Neighbours::over(cloud, &mask))
        .flatten();
    let normals = match &band {
        Some(index) => index.local_planes_at(cloud, eye, &near, &NormalParams::default()),
        None => local_planes_at(cloud, eye, &mask, &near, &NormalParams::default()),
    };
    let cos = p.ransac.max_normal_angle.cos();
    let mut out: Vec<usize> = near
        .iter()
        .zip(normals)
        .filter(|(_, (n, _))| n.is_finite() && n.dot(plane.normal).abs() >= cos)
        .map(|(&i, _)| i)
        .collect();
    out.sort_unstable();
    (out, band)
}

/// Seed 000's refinement: refit to everything within the refinement threshold, then
/// take the inliers at the RANSAC threshold — widened to the surface's own depth noise
/// when that is larger (2.5 σ, σ from the median distance of the points in the
/// refinement band, at most the band): a table 2.5 m from a Kinect has σ ≈ 1 cm, and
/// a 1 cm threshold would leave a third of it behind to be found again as a second
/// table. Returns the plane, its inliers, the threshold used and the neighbour index of
/// the band the fits' normals came from (unorganized clouds).
fn refine(
    cloud: &PointCloud,
    candidates: &[usize],
    mut plane: Plane,
    p: &SurfaceParams,
) -> (Plane, Vec<usize>, f64, Option<Neighbours>) {
    let points = &cloud.points;
    // Fits only use points whose own surface faces the plane's way: a band around a
    // table's plane also cuts a strip out of the wall behind it, and that strip, far
    // from the table, tilts a least-squares fit more with every iteration.
    let (facing, index) = facing_points(cloud, candidates, &plane, p);
    for _ in 0..p.refine_iterations {
        let near = facing
            .iter()
            .map(|&i| points[i])
            .filter(|q| plane.distance(*q).abs() <= p.refine_threshold);
        match Plane::fit_iter(near) {
            Some(f) if f.normal.dot(plane.normal) > 0.0 => plane = f,
            Some(f) => plane = f.flipped(),
            None => break,
        }
    }
    let mut band: Vec<f64> = facing
        .iter()
        .map(|&i| plane.distance(points[i]).abs())
        .filter(|d| *d <= p.refine_threshold)
        .collect();
    let threshold = if band.is_empty() {
        p.ransac.threshold
    } else {
        let mid = band.len() / 2;
        let median = *band.select_nth_unstable_by(mid, f64::total_cmp).1;
        (2.5 * 1.4826 * median).clamp(
            p.ransac.threshold,
            p.refine_threshold.max(p.ransac.threshold),
        )
    };
    let inliers_of = |plane: &Plane| -> Vec<usize> {
        candidates
            .iter()
            .copied()
            .filter(|&i| plane.distance(points[i]).abs() <= threshold)
            .collect()
    };
    let mut inliers = inliers_of(&plane);
    // Then refit while that gains inliers: a hypothesis that crossed the table at a
    // slant (RANSAC out of iterations on a small share of the frame) and a 2 cm band
    // that mixed in a little of something else (a table's apron under its edge tilts
    // a least-squares fit) both settle on the surface. Each refit is a RANSAC among
    // the inliers at half the threshold, which the surface dominates, then least
    // squares on its inliers.
    for round in 0..5 {
        let core = RansacParams {
            threshold: threshold / 2.0,
            seed: p.ransac.seed.wrapping_add(1000 + round),
            ..p.ransac.clone()
        };
        let facing_inliers: Vec<usize> = inliers
            .iter()
            .copied()
            .filter(|i| facing.binary_search(i).is_ok())
            .collect();
        let Some((_, core)) = ransac_plane(points, &facing_inliers, &core) else {
            break;
        };
        let Some(fit) = Plane::fit_iter(core.iter().map(|&i| points[i])) else {
            break;
        };
        let fit = if fit.normal.dot(plane.normal) < 0.0 {
            fit.flipped()
        } else {
            fit
        };
        let more = inliers_of(&fit);
        if more.len() <= inliers.len() {
            break;
        }
        (plane, inliers) = (fit, more);
    }
    (plane, inliers, threshold, index)
}

impl Validate for SurfaceParams {
    fn check(&self, at: &str) -> Result<(), String> {
        self.ransac.check(&nested(at, "ransac"))?;
        check_in(
            at,
            "max_tilt",
            self.max_tilt,
            0.0,
            std::f64::consts::PI / 2.0,
        )?;
        check_in(at, "min_plane_fraction", self.min_plane_fraction, 0.0, 1.0)?;
        check_in(at, "stop_fraction", self.stop_fraction, 0.0, 1.0)?;
        check_count(at, "min_plane_points", self.min_plane_points, 3)?;
        let [lo, hi] = self.height_range;
        check_in(at, "height_range[0]", lo, -1e6, 1e6)?;
        check_in(at, "height_range[1]", hi, lo, 1e6)?;
        check_non_negative(at, "min_area", self.min_area)?;
        check_non_negative(at, "min_inscribed_radius", self.min_inscribed_radius)?;
        check_positive(at, "max_slice_ratio", self.max_slice_ratio)?;
        check_in(
            at,
            "flat_normal_angle",
            self.flat_normal_angle,
            0.0,
            std::f64::consts::PI,
        )?;
        check_in(at, "min_flat_fraction", self.min_flat_fraction, 0.0, 1.0)?;
        check_positive(at, "refine_threshold", self.refine_threshold)?;
        // Under 0.1 mm no two points share a cell and the grid's keys overflow.
        check_in(at, "cell", self.cell, 1e-4, 10.0)?;
        check_count(at, "max_planes", self.max_planes, 1)?;
        check_count(at, "stride", self.stride, 1)
    }
}
