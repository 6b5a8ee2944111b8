//! Stable poses of a rigid object on a horizontal plane (seed 000, SPEC §1.2, Algs 2–7),
//! from a mesh or from a scanned cloud.
//!
//! Only the convex hull can touch a plane, so everything is computed on the hull:
//! its triangles are oriented outwards (Alg. 2), merged into exact planar *facets*, and
//! facets are grouped into *patches* by the relaxation angle through facet adjacency
//! (Alg. 3, without the seed's O(n²) all-pairs loop). A patch is a candidate support;
//! its perimeter is the hull's contact polygon with the plane it defines (Alg. 5), and
//! it is a stable pose when the centre of mass (Alg. 4) projects inside (Alg. 7).
//!
//! Beyond the seed: each pose gets a stability margin (how far the projected centre of
//! mass is from the perimeter, and the tilt that topples it), poses are ranked by that
//! tilt rather than by area, and each gets a quasi-static landing probability — the
//! share of random drop orientations that end on it (Goldberg et al. 1999, as trimesh's
//! `compute_stable_poses`): every facet receives the solid angle it subtends from the
//! centre of mass and hands it on to the facet it topples onto until a stable one
//! keeps it.

mod hull;
mod poses;
#[cfg(test)]
mod tests;

use hull::{Hull, basis};
use rustc_hash::FxHashMap;
use tabula_geom::input::{Validate, check_in, check_non_negative};
use tabula_geom::polygon::{inside_convex, polygon_area};
use tabula_geom::{Quat, Vec2, Vec3};

/// Parameters of the stable-pose search (SPEC §1.2, §6).
#[derive(Debug, Clone, serde::Deserialize, serde::Serialize)]
#[serde(default, deny_unknown_fields)]
pub struct StableParams {
    /// Facets whose normals are within this angle of a patch's first facet join the
    /// patch (rad), SPEC §6: 0.2.
    pub relaxation_angle: f64,
    /// Adjacent hull triangles closer than this angle are one planar facet (rad):
    /// hulls of exact meshes come triangulated, and a face is one face.
    pub coplanar_angle: f64,
    /// Hull vertices within this distance of a support plane touch it (m), for meshes:
    /// a face split into slightly bent facets is still one face. A patch only grows by
    /// facets that lie this flat on its plane, so the relaxation angle cannot fold a
    /// bottle's shoulder into its side.
    pub contact_tolerance: f64,
    /// The same for scanned clouds (m): their faces are uneven by the scan's noise and
    /// voxel leaf.
    pub cloud_contact_tolerance: f64,
    /// Poses whose tilt-to-topple is below this are not reported (deg). Every resting
    /// pose is reported by default (their probabilities then sum to one); placing ranks
    /// by the margin instead of dropping poses.
    pub min_topple_deg: f64,
    /// A scanned cloud's centre of mass is the mean of its points thinned to one per
    /// cell this wide (m), SPEC §6's 5 mm scan leaf: an area-weighted surface
    /// centroid (Alg. 4) however unevenly the views sampled it.
    pub cloud_com_leaf: f64,
}

impl Default for StableParams {
    fn default() -> Self {
        Self {
            relaxation_angle: 0.2,
            coplanar_angle: 1e-3,
            contact_tolerance: 1e-4,
            cloud_contact_tolerance: 0.003,
            min_topple_deg: 0.0,
            cloud_com_leaf: 0.005,
        }
    }
}

/// Why no stable poses could be computed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum StableError {
    #[error("{0} points or vertices are not finite")]
    NonFinite(usize),
    #[error("{0} distinct points: a solid needs at least 4")]
    TooFewPoints(usize),
    #[error("the points are flat or collinear: no solid hull")]
    Degenerate,
    #[error("invalid parameters: {0}")]
    Params(String),
}

/// How the centre of mass was found.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ComMethod {
    /// Volume-weighted centroid of a closed mesh (uniform density).
    MeshVolume,
    /// Area-weighted centroid of an open mesh's surface (seed 000's Alg. 4).
    MeshSurface,
    /// Area-weighted centroid of a scanned cloud's surface (Alg. 4): its points thinned
    /// to one per cell.
    CloudSurface,
    /// Volume-weighted centroid of a scanned cloud's convex hull (when the surface's
    /// centroid falls outside it).
    HullVolume,
}

/// One way the object rests on a horizontal plane. Vectors are in the object's frame.
#[derive(Debug, Clone, serde::Serialize)]
pub struct StablePose {
    /// Unit vector from the object toward the surface it rests on: gravity's direction
    /// in the object's frame.
    pub support_normal: [f64; 3],
    /// Share of random drop orientations that come to rest here (quasi-static).
    pub probability: f64,
    /// Distance from the centre of mass's projection to the nearest perimeter edge (m).
    pub margin_m: f64,
    /// Tilt about that edge that topples the object (deg).
    pub topple_deg: f64,
    /// Area of the contact polygon (m²).
    pub area_m2: f64,
    /// Height of the centre of mass above the surface (m).
    pub com_height_m: f64,
    /// Where the contact polygon's centroid is (object frame, on the support plane).
    pub contact_centroid: [f64; 3],
    /// The contact polygon (object frame, on the support plane), counter-clockwise seen
    /// from above the surface.
    pub perimeter: Vec<[f64; 3]>,
}

impl StablePose {
    pub fn normal(&self) -> Vec3 {
        Vec3::from_array(self.support_normal)
    }

    /// A rotation `world_from_object` that makes this pose rest on a horizontal
    /// surface (the support normal turned onto −z), with `yaw` about the vertical.
    pub fn resting_rotation(&self, yaw: f64) -> Quat {
        Quat::from_rotation_z(yaw) * Quat::from_rotation_arc(self.normal(), -Vec3::Z)
    }

    /// Distance from the object's origin to the support plane along the normal: a
    /// resting object's origin is this high above the surface.
    pub fn origin_height(&self) -> f64 {
        Vec3::from_array(self.contact_centroid).dot(self.normal())
    }

    /// Share of the contact polygon under which the object's own surface (`points`,
    /// object frame) actually touches the plane, on a `cell` grid: a hull face bridging
    /// a concavity (an L resting on two edges) has a large polygon and little contact,
    /// and rests less surely than its tilt-to-topple says.
    pub fn contact_fill(&self, points: &[Vec3], tolerance: f64, cell: f64) -> f64 {
        let n = self.normal();
        let d = self.origin_height();
        let (u, v) = basis(n);
        let poly: Vec<Vec2> = self
            .perimeter
            .iter()
            .map(|q| {
                let q = Vec3::from_array(*q);
                Vec2::new(q.dot(u), q.dot(v))
            })
            .collect();
        let area = polygon_area(&poly).abs();
        if area <= 0.0 || cell <= 0.0 {
            return 0.0;
        }
        let touched: rustc_hash::FxHashSet<(i64, i64)> = points
            .iter()
            .filter(|q| q.dot(n) >= d - tolerance)
            .map(|q| {
                (
                    (q.dot(u) / cell).floor() as i64,
                    (q.dot(v) / cell).floor() as i64,
                )
            })
            .collect();
        // The touched cells, each grown to its neighbours (sparse scans), inside the
        // polygon.
        let mut covered: rustc_hash::FxHashSet<(i64, i64)> = Default::default();
        for &(i, j) in &touched {
            for di in -1..=1 {
                for dj in -1..=1 {
                    let c = Vec2::new((i + di) as f64 + 0.5, (j + dj) as f64 + 0.5) * cell;
                    if inside_convex(&poly, c) {
                        covered.insert((i + di, j + dj));
                    }
                }
            }
        }
        (covered.len() as f64 * cell * cell / area).min(1.0)
    }

    /// How much of this pose's energy barrier the object's own surface really has
    /// (0–1 and above): tilted toward each edge of the contact polygon up to the angle
    /// that topples it over that edge, the highest rise of the centre of mass on
    /// `points` (object frame: the support function of their hull) over the rise a
    /// flat face gives there, √(h² + m²) − h (h: the centre of mass's height, m: its
    /// distance from the edge); the least over the edges. The barrier is the energy
    /// stability margin of legged robotics (Messuri & Klein 1985). A flat face has all
    /// of it; a curved contact whose tolerance-band strip only looks like a face — a
    /// bottle or a ball on its side — has next to none and rolls to wherever its facets
    /// end.
    pub fn rocking(&self, points: &[Vec3], com: Vec3) -> f64 {
        const STEPS: usize = 8;
        let n = self.normal();
        let height = self.com_height_m;
        if height.is_nan() || height <= 0.0 || points.is_empty() || self.perimeter.len() < 3 {
            return 0.0;
        }
        let (u, v) = basis(n);
        let to2 = |q: Vec3| Vec2::new(q.dot(u), q.dot(v));
        let poly: Vec<Vec2> = self
            .perimeter
            .iter()
            .map(|q| to2(Vec3::from_array(*q)))
            .collect();
        let com2 = to2(com);
        let lift = |down: Vec3| {
            let support = points
                .iter()
                .filter(|q| q.is_finite())
                .map(|q| q.dot(down))
                .fold(f64::NEG_INFINITY, f64::max);
            support - com.dot(down)
        };
        let rest = lift(n);
        let k = poly.len();
        (0..k)
            .filter_map(|i| {
                let (a, b) = (poly[i], poly[(i + 1) % k]);
                // Counter-clockwise polygon: the outward normal is the edge turned right.
                let outward = -(b - a).perp().try_normalize()?;
                let margin = outward.dot(a - com2);
                if margin.is_nan() || margin <= 0.0 {
                    return Some(0.0);
                }
                let expected = (height * height + margin * margin).sqrt() - height;
                let topple = margin.atan2(height);
                let side = u * outward.x + v * outward.y;
                let rise = (1..=STEPS)
                    .map(|s| {
                        let alpha = topple * s as f64 / STEPS as f64;
                        lift(n * alpha.cos() + side * alpha.sin()) - rest
                    })
                    .fold(f64::NEG_INFINITY, f64::max);
                Some(rise / expected)
            })
            .fold(f64::INFINITY, f64::min)
    }

    /// Whether a gripper (points in the object's frame) stays on the object's side of
    /// the support plane with `clearance` to spare (seed 000's Alg. 6: a plane that
    /// cuts the gripper is unusable — the hand would have to be inside the table).
    pub fn clear_of(&self, gripper: &[Vec3], clearance: f64) -> bool {
        self.hand_margin(gripper) >= clearance
    }

    /// How far the gripper's lowest point (points in the object's frame) stays above
    /// the support plane when the object rests so (m; negative: below it, inside the
    /// surface). Infinite for no points.
    pub fn hand_margin(&self, gripper: &[Vec3]) -> f64 {
        let n = self.normal();
        let d = self.origin_height();
        gripper
            .iter()
            .map(|g| d - g.dot(n))
            .fold(f64::INFINITY, f64::min)
    }
}

/// Every stable pose of an object, best (hardest to topple) first.
#[derive(Debug, Clone, serde::Serialize)]
pub struct StablePoses {
    pub poses: Vec<StablePose>,
    /// Index in `poses` of the most likely pose when dropped at random.
    pub most_likely: Option<usize>,
    pub center_of_mass: [f64; 3],
    pub com_method: ComMethod,
    pub hull_vertices: usize,
    pub hull_facets: usize,
    pub hull_volume_m3: f64,
}

impl StablePoses {
    /// The best pose that leaves a gripper (object frame) clear of the surface.
    pub fn best_clear_of(&self, gripper: &[Vec3], clearance: f64) -> Option<&StablePose> {
        self.poses.iter().find(|p| p.clear_of(gripper, clearance))
    }
}

/// Stable poses of a triangle mesh (vertices and triangles in the object's frame).
/// The centre of mass is the mesh's volume centroid when the mesh is closed, its
/// surface's area-weighted centroid when it is not.
pub fn of_mesh(
    vertices: &[Vec3],
    triangles: &[[u32; 3]],
    params: &StableParams,
) -> Result<StablePoses, StableError> {
    check_points(vertices)?;
    if triangles
        .iter()
        .any(|t| t.iter().any(|&i| i as usize >= vertices.len()))
    {
        return Err(StableError::Degenerate);
    }
    let hull = Hull::new(vertices)?;
    let (com, method) = match mesh_centroid(vertices, triangles) {
        Some(c) if hull.contains(c) => (c, MeshCentroid::Volume(c)),
        _ => match surface_centroid(vertices, triangles) {
            Some(c) if hull.contains(c) => (c, MeshCentroid::Surface),
            _ => (hull.volume_centroid(), MeshCentroid::Hull),
        },
    };
    let method = match method {
        MeshCentroid::Volume(_) => ComMethod::MeshVolume,
        MeshCentroid::Surface => ComMethod::MeshSurface,
        MeshCentroid::Hull => ComMethod::HullVolume,
    };
    Ok(hull.stable_poses(com, method, params.contact_tolerance, params))
}

/// Stable poses of a scanned cloud (object frame). The centre of mass is its
/// surface's centroid (Alg. 4), not its hull's: the hull of a door handle fills the
/// space between lever and rose, and its centroid sits centimetres off the handle's,
/// so the faces it rests on were not found.
pub fn of_cloud(points: &[Vec3], params: &StableParams) -> Result<StablePoses, StableError> {
    check_points(points)?;
    let hull = Hull::new(points)?;
    let (com, method) = match cloud_surface_centroid(points, params.cloud_com_leaf) {
        Some(c) if hull.contains(c) => (c, ComMethod::CloudSurface),
        _ => (hull.volume_centroid(), ComMethod::HullVolume),
    };
    Ok(hull.stable_poses(com, method, params.cloud_contact_tolerance, params))
}

/// The mean of the centroids of the cells `leaf` wide (perception's voxel grid): a
/// cloud's surface centroid with every patch of surface weighed by its area, not by
/// how many views saw it. `None` for no finite point or a leaf the grid refuses.
pub fn cloud_surface_centroid(points: &[Vec3], leaf: f64) -> Option<Vec3> {
    let cells = tabula_perception::filters::voxel_grid(points, leaf).ok()?;
    (!cells.is_empty()).then(|| cells.iter().copied().sum::<Vec3>() / cells.len() as f64)
}

enum MeshCentroid {
    Volume(#[allow(dead_code)] Vec3),
    Surface,
    Hull,
}

fn check_points(points: &[Vec3]) -> Result<(), StableError> {
    let bad = points.iter().filter(|p| !p.is_finite()).count();
    if bad > 0 {
        return Err(StableError::NonFinite(bad));
    }
    Ok(())
}

/// Volume centroid of a closed mesh (every edge shared by exactly two triangles), by
/// signed tetrahedra from the origin; `None` when the mesh is open or has no volume.
pub fn mesh_centroid(vertices: &[Vec3], triangles: &[[u32; 3]]) -> Option<Vec3> {
    let mut edges: FxHashMap<(u32, u32), u32> = FxHashMap::default();
    for t in triangles {
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            *edges.entry((a.min(b), a.max(b))).or_default() += 1;
        }
    }
    if triangles.is_empty() || edges.values().any(|&n| n != 2) {
        return None;
    }
    let (mut volume, mut moment) = (0.0, Vec3::ZERO);
    for t in triangles {
        let [a, b, c] = t.map(|i| vertices[i as usize]);
        let v = a.dot(b.cross(c)) / 6.0;
        volume += v;
        moment += (a + b + c) * (v / 4.0);
    }
    let scale = vertices
        .iter()
        .fold(0.0f64, |m, p| m.max(p.abs().max_element()))
        .max(1e-12);
    (volume.abs() > 1e-9 * scale.powi(3)).then(|| moment / volume)
}

/// Area-weighted mean of triangle centroids (seed 000's Alg. 4): unlike a mean of
/// points, not biased by uneven sampling.
pub fn surface_centroid(vertices: &[Vec3], triangles: &[[u32; 3]]) -> Option<Vec3> {
    let (mut area, mut sum) = (0.0, Vec3::ZERO);
    for t in triangles {
        let [a, b, c] = t.map(|i| vertices[i as usize]);
        let w = (b - a).cross(c - a).length() / 2.0;
        area += w;
        sum += (a + b + c) / 3.0 * w;
    }
    (area > 0.0).then(|| sum / area)
}

impl Validate for StableParams {
    fn check(&self, at: &str) -> Result<(), String> {
        check_in(
            at,
            "relaxation_angle",
            self.relaxation_angle,
            0.0,
            std::f64::consts::PI / 2.0,
        )?;
        check_in(
            at,
            "coplanar_angle",
            self.coplanar_angle,
            0.0,
            std::f64::consts::PI / 2.0,
        )?;
        check_non_negative(at, "contact_tolerance", self.contact_tolerance)?;
        check_non_negative(at, "cloud_contact_tolerance", self.cloud_contact_tolerance)?;
        check_in(at, "cloud_com_leaf", self.cloud_com_leaf, 1e-5, 1.0)?;
        check_in(at, "min_topple_deg", self.min_topple_deg, 0.0, 90.0)
    }
}
