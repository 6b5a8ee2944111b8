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

use rustc_hash::FxHashMap;
use std::collections::VecDeque;
use tabula_geom::input::{Validate, check_in, check_non_negative};
use tabula_geom::polygon::{
    convex_hull_2d, distance_to_boundary, inside_convex, polygon_area, segment_distance,
};
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
}

impl Default for StableParams {
    fn default() -> Self {
        Self {
            relaxation_angle: 0.2,
            coplanar_angle: 1e-3,
            contact_tolerance: 1e-4,
            cloud_contact_tolerance: 0.003,
            min_topple_deg: 0.0,
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
    /// Volume-weighted centroid of a scanned cloud's convex hull.
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
        let n = self.normal();
        let d = self.origin_height();
        gripper.iter().all(|g| g.dot(n) <= d - clearance)
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

/// Stable poses of a scanned cloud (object frame): its hull with uniform density.
pub fn of_cloud(points: &[Vec3], params: &StableParams) -> Result<StablePoses, StableError> {
    check_points(points)?;
    let hull = Hull::new(points)?;
    let com = hull.volume_centroid();
    Ok(hull.stable_poses(
        com,
        ComMethod::HullVolume,
        params.cloud_contact_tolerance,
        params,
    ))
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

/// A convex hull with outward triangles, their adjacency and planar facets.
struct Hull {
    vertices: Vec<Vec3>,
    triangles: Vec<[u32; 3]>,
    normals: Vec<Vec3>,
    areas: Vec<f64>,
    /// For each triangle, the triangle across each of its edges (k, k+1).
    across: Vec<[usize; 3]>,
    /// Facet of each triangle, and each facet's triangles.
    facet_of: Vec<usize>,
    facets: Vec<Vec<usize>>,
    centre: Vec3,
}

/// Most points handed to the hull: parry's quickhull goes quadratic on many
/// coplanar or cocircular points (a 100,000-corner polygon took minutes).
const MAX_HULL_INPUT: usize = 5_000;

/// `None` when `points` are few enough; else the point farthest from the box's centre
/// in each cell of a grid coarse enough to leave at most [`MAX_HULL_INPUT`] — the
/// outermost points, so the hull shrinks by less than a cell (≤ 1/500 of the size).
fn thin_for_hull(points: &[Vec3]) -> Option<Vec<Vec3>> {
    if points.len() <= MAX_HULL_INPUT {
        return None;
    }
    let (lo, hi) = tabula_geom::bounds(points);
    let centre = (lo + hi) / 2.0;
    let mut leaf = (hi - lo).length() / 2000.0;
    loop {
        let mut cells: std::collections::HashMap<[i64; 3], Vec3> = Default::default();
        for p in points {
            let cell = cells.entry(tabula_geom::voxel_key(*p, leaf)).or_insert(*p);
            if p.distance_squared(centre) > cell.distance_squared(centre) {
                *cell = *p;
            }
        }
        if cells.len() <= MAX_HULL_INPUT {
            let mut kept: Vec<Vec3> = cells.into_values().collect();
            kept.sort_by(|a, b| {
                a.to_array()
                    .partial_cmp(&b.to_array())
                    .unwrap_or(std::cmp::Ordering::Equal)
            });
            return Some(kept);
        }
        leaf *= 2.0;
    }
}

impl Hull {
    fn new(points: &[Vec3]) -> Result<Self, StableError> {
        let mut distinct: Vec<[u64; 3]> = points
            .iter()
            .map(|p| p.to_array().map(f64::to_bits))
            .collect();
        distinct.sort_unstable();
        distinct.dedup();
        if distinct.len() < 4 {
            return Err(StableError::TooFewPoints(distinct.len()));
        }
        let thinned = thin_for_hull(points);
        let (vertices, mut triangles) = tabula_geom::parry::transformation::try_convex_hull(
            thinned.as_deref().unwrap_or(points),
        )
        .map_err(|_| StableError::Degenerate)?;
        if triangles.len() < 4 {
            return Err(StableError::Degenerate);
        }
        let centre = vertices.iter().copied().sum::<Vec3>() / vertices.len() as f64;
        // Alg. 2: a normal pointing back toward the centre is flipped.
        let mut normals = Vec::with_capacity(triangles.len());
        let mut areas = Vec::with_capacity(triangles.len());
        for t in &mut triangles {
            let [a, b, c] = t.map(|i| vertices[i as usize]);
            let cross = (b - a).cross(c - a);
            let mut n = cross.normalize_or_zero();
            if n.dot((a + b + c) / 3.0 - centre) < 0.0 {
                n = -n;
                t.swap(1, 2);
            }
            normals.push(n);
            areas.push(cross.length() / 2.0);
        }
        let scale = vertices
            .iter()
            .map(|v| (*v - centre).length())
            .fold(0.0, f64::max);
        let volume: f64 = triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| vertices[i as usize] - centre);
                a.dot(b.cross(c)) / 6.0
            })
            .sum();
        // NaN volumes fail too.
        if volume.partial_cmp(&(1e-9 * scale.powi(3))) != Some(std::cmp::Ordering::Greater) {
            return Err(StableError::Degenerate);
        }
        let mut edge_owner: FxHashMap<(u32, u32), usize> = FxHashMap::default();
        let mut across = vec![[usize::MAX; 3]; triangles.len()];
        for (ti, t) in triangles.iter().enumerate() {
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                let key = (a.min(b), a.max(b));
                if let Some(&other) = edge_owner.get(&key) {
                    across[ti][k] = other;
                    let o = &triangles[other];
                    for m in 0..3 {
                        let (c, d) = (o[m], o[(m + 1) % 3]);
                        if (c.min(d), c.max(d)) == key {
                            across[other][m] = ti;
                        }
                    }
                } else {
                    edge_owner.insert(key, ti);
                }
            }
        }
        let mut hull = Self {
            vertices,
            triangles,
            normals,
            areas,
            across,
            facet_of: Vec::new(),
            facets: Vec::new(),
            centre,
        };
        hull.merge_facets(1e-3);
        Ok(hull)
    }

    /// Adjacent triangles within `angle` of each other form one facet (flood fill).
    fn merge_facets(&mut self, angle: f64) {
        let cos = angle.cos();
        let n = self.triangles.len();
        self.facet_of = vec![usize::MAX; n];
        self.facets.clear();
        for seed in 0..n {
            if self.facet_of[seed] != usize::MAX {
                continue;
            }
            let id = self.facets.len();
            let mut members = vec![seed];
            self.facet_of[seed] = id;
            let mut queue = VecDeque::from([seed]);
            while let Some(t) = queue.pop_front() {
                for &o in &self.across[t] {
                    if o != usize::MAX
                        && self.facet_of[o] == usize::MAX
                        && self.normals[o].dot(self.normals[seed]) >= cos
                    {
                        self.facet_of[o] = id;
                        members.push(o);
                        queue.push_back(o);
                    }
                }
            }
            self.facets.push(members);
        }
    }

    fn contains(&self, p: Vec3) -> bool {
        p.is_finite()
            && self
                .triangles
                .iter()
                .zip(&self.normals)
                .all(|(t, n)| n.dot(p - self.vertices[t[0] as usize]) < 0.0)
    }

    fn volume_centroid(&self) -> Vec3 {
        let (mut volume, mut moment) = (0.0, Vec3::ZERO);
        for t in &self.triangles {
            let [a, b, c] = t.map(|i| self.vertices[i as usize] - self.centre);
            let v = a.dot(b.cross(c)) / 6.0;
            volume += v;
            moment += (a + b + c) * (v / 4.0);
        }
        self.centre + moment / volume
    }

    /// Offset of the plane with normal `n` that touches the hull.
    fn support_offset(&self, n: Vec3) -> f64 {
        self.vertices
            .iter()
            .map(|v| v.dot(n))
            .fold(f64::NEG_INFINITY, f64::max)
    }

    fn facet_area(&self, f: usize) -> f64 {
        self.facets[f].iter().map(|&t| self.areas[t]).sum()
    }

    fn facet_normal(&self, f: usize) -> Vec3 {
        self.facets[f]
            .iter()
            .map(|&t| self.normals[t] * self.areas[t])
            .sum::<Vec3>()
            .normalize_or(self.normals[self.facets[f][0]])
    }

    /// The facet a body resting on facet `f` topples onto, or `None` when it rests.
    /// It pivots about the boundary edge that the line from the facet's centroid to
    /// the centre of mass's projection leaves through.
    fn topples_to(&self, f: usize, com: Vec3) -> Option<usize> {
        let n = self.facet_normal(f);
        let (u, v) = basis(n);
        let origin = self.vertices[self.triangles[self.facets[f][0]][0] as usize];
        let to2 = |p: Vec3| Vec2::new((p - origin).dot(u), (p - origin).dot(v));
        let com2 = to2(com);
        // The projection inside any of the facet's triangles: it rests.
        let inside_triangle = |t: usize| {
            let [a, b, c] = self.triangles[t].map(|i| to2(self.vertices[i as usize]));
            let s = [
                (b - a).perp_dot(com2 - a),
                (c - b).perp_dot(com2 - b),
                (a - c).perp_dot(com2 - c),
            ];
            s.iter().all(|&x| x >= 0.0) || s.iter().all(|&x| x <= 0.0)
        };
        if self.facets[f].iter().any(|&t| inside_triangle(t)) {
            return None;
        }
        let area = self.facet_area(f).max(1e-300);
        let centroid2 = self.facets[f]
            .iter()
            .map(|&t| {
                let [a, b, c] = self.triangles[t].map(|i| to2(self.vertices[i as usize]));
                (a + b + c) / 3.0 * self.areas[t]
            })
            .sum::<Vec2>()
            / area;
        let dir = com2 - centroid2;
        let mut best: Option<(f64, usize)> = None;
        for &t in &self.facets[f] {
            for k in 0..3 {
                let o = self.across[t][k];
                if o == usize::MAX || self.facet_of[o] == f {
                    continue;
                }
                let a = to2(self.vertices[self.triangles[t][k] as usize]);
                let b = to2(self.vertices[self.triangles[t][(k + 1) % 3] as usize]);
                // Crossing of the ray centroid → com with edge a–b; else nearness.
                let denom = dir.perp_dot(b - a);
                let score = if denom.abs() > 1e-300 {
                    let s = (a - centroid2).perp_dot(b - a) / denom;
                    let r = (a - centroid2).perp_dot(dir) / denom;
                    if s >= 0.0 && (-1e-9..=1.0 + 1e-9).contains(&r) {
                        -1.0
                    } else {
                        segment_distance(com2, a, b)
                    }
                } else {
                    segment_distance(com2, a, b)
                };
                if best.is_none_or(|(s, _)| score < s) {
                    best = Some((score, self.facet_of[o]));
                }
            }
        }
        best.map(|(_, g)| g)
    }

    fn stable_poses(
        &self,
        com: Vec3,
        method: ComMethod,
        tolerance: f64,
        params: &StableParams,
    ) -> StablePoses {
        let nf = self.facets.len();
        // Quasi-static landing: each triangle's solid angle from the centre of mass,
        // summed per facet, flows along the topple graph to a resting facet.
        let mut prob = vec![0.0; nf];
        for (t, tri) in self.triangles.iter().enumerate() {
            let [a, b, c] = tri.map(|i| self.vertices[i as usize] - com);
            prob[self.facet_of[t]] += solid_angle(a, b, c) / (4.0 * std::f64::consts::PI);
        }
        let next: Vec<Option<usize>> = (0..nf).map(|f| self.topples_to(f, com)).collect();
        let mut sink_prob = vec![0.0; nf];
        for (f, &p) in prob.iter().enumerate() {
            let mut at = f;
            // Toppling lowers the centre of mass, so chains end; the bound guards
            // against numerical ties.
            for _ in 0..nf {
                match next[at] {
                    Some(g) if g != at => at = g,
                    _ => break,
                }
            }
            sink_prob[at] += p;
        }
        // Alg. 3 with adjacency: patches grown from the largest resting facets (a body
        // rests on a facet exactly when the centre of mass projects into it; patches add
        // the neighbours that lie as flat, so a scanned face's many small facets count
        // as the one face they are).
        let cos = params.relaxation_angle.cos();
        let mut order: Vec<usize> = (0..nf).filter(|&f| next[f].is_none()).collect();
        let areas: Vec<f64> = (0..nf).map(|f| self.facet_area(f)).collect();
        let normals: Vec<Vec3> = (0..nf).map(|f| self.facet_normal(f)).collect();
        order.sort_by(|&a, &b| areas[b].total_cmp(&areas[a]).then(a.cmp(&b)));
        let mut facet_adjacent: Vec<Vec<usize>> = vec![Vec::new(); nf];
        for (t, ac) in self.across.iter().enumerate() {
            for &o in ac {
                if o != usize::MAX && self.facet_of[o] != self.facet_of[t] {
                    let (a, b) = (self.facet_of[t], self.facet_of[o]);
                    if !facet_adjacent[a].contains(&b) {
                        facet_adjacent[a].push(b);
                    }
                }
            }
        }
        let mut claimed = vec![false; nf];
        let mut poses = Vec::new();
        for &seed in &order {
            if claimed[seed] {
                continue;
            }
            let mut patch = vec![seed];
            claimed[seed] = true;
            let mut queue = VecDeque::from([seed]);
            let top = self.support_offset(normals[seed]);
            let flat = |g: usize| {
                self.facets[g].iter().all(|&t| {
                    self.triangles[t]
                        .iter()
                        .all(|&i| self.vertices[i as usize].dot(normals[seed]) >= top - tolerance)
                })
            };
            while let Some(f) = queue.pop_front() {
                for &g in &facet_adjacent[f] {
                    if !claimed[g] && normals[g].dot(normals[seed]) >= cos && flat(g) {
                        claimed[g] = true;
                        patch.push(g);
                        queue.push_back(g);
                    }
                }
            }
            if let Some(p) = self
                .patch_pose(&patch, &normals, &areas, &sink_prob, com, tolerance, params)
                .or_else(|| {
                    // The patch's mean plane may tip the centre of mass out; the
                    // resting facet's own plane holds it.
                    self.patch_pose(
                        &[seed],
                        &normals,
                        &areas,
                        &sink_prob,
                        com,
                        tolerance,
                        params,
                    )
                    .map(|mut p| {
                        p.probability = patch.iter().map(|&f| sink_prob[f]).sum();
                        p
                    })
                })
            {
                poses.push(p);
            }
        }
        poses.sort_by(|a: &StablePose, b| {
            b.topple_deg
                .total_cmp(&a.topple_deg)
                .then(b.probability.total_cmp(&a.probability))
        });
        let most_likely = (0..poses.len()).max_by(|&a, &b| {
            poses[a]
                .probability
                .total_cmp(&poses[b].probability)
                .then(b.cmp(&a))
        });
        let hull_volume = self
            .triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| self.vertices[i as usize] - self.centre);
                a.dot(b.cross(c)) / 6.0
            })
            .sum();
        StablePoses {
            poses,
            most_likely,
            center_of_mass: com.to_array(),
            com_method: method,
            hull_vertices: self.vertices.len(),
            hull_facets: nf,
            hull_volume_m3: hull_volume,
        }
    }

    /// Algs 5 and 7 for one patch: the plane (the patch's area-weighted normal, pushed
    /// out to touch the hull), its contact polygon, and the centre of mass against it.
    #[allow(clippy::too_many_arguments)]
    fn patch_pose(
        &self,
        patch: &[usize],
        normals: &[Vec3],
        areas: &[f64],
        sink_prob: &[f64],
        com: Vec3,
        tolerance: f64,
        params: &StableParams,
    ) -> Option<StablePose> {
        let n = patch
            .iter()
            .map(|&f| normals[f] * areas[f])
            .sum::<Vec3>()
            .try_normalize()?;
        let d = self.support_offset(n);
        let (u, v) = basis(n);
        let contact: Vec<Vec3> = self
            .vertices
            .iter()
            .copied()
            .filter(|p| p.dot(n) >= d - tolerance)
            .collect();
        let flat: Vec<Vec2> = contact
            .iter()
            .map(|p| Vec2::new(p.dot(u), p.dot(v)))
            .collect();
        let ring = convex_hull_2d(&flat);
        if ring.len() < 3 {
            return None;
        }
        let poly: Vec<Vec2> = ring.iter().map(|&i| flat[i]).collect();
        let com2 = Vec2::new(com.dot(u), com.dot(v));
        if !inside_convex(&poly, com2) {
            return None;
        }
        let margin = distance_to_boundary(&poly, com2);
        let height = d - com.dot(n);
        let topple_deg = margin.atan2(height).to_degrees();
        if topple_deg < params.min_topple_deg {
            return None;
        }
        let area = polygon_area(&poly);
        let centroid2 = polygon_centroid(&poly);
        let lift = |q: Vec2| (u * q.x + v * q.y + n * d).to_array();
        Some(StablePose {
            support_normal: n.to_array(),
            probability: patch.iter().map(|&f| sink_prob[f]).sum(),
            margin_m: margin,
            topple_deg,
            area_m2: area,
            com_height_m: height,
            contact_centroid: lift(centroid2),
            perimeter: poly.iter().map(|&q| lift(q)).collect(),
        })
    }
}

/// Two unit vectors completing `n` to a right-handed frame (u × v = n), so a polygon
/// counter-clockwise in (u, v) is counter-clockwise seen from the tip of `n`.
fn basis(n: Vec3) -> (Vec3, Vec3) {
    let u = n.any_orthonormal_vector();
    (u, n.cross(u))
}

fn polygon_centroid(poly: &[Vec2]) -> Vec2 {
    let n = poly.len();
    let (mut a, mut c) = (0.0, Vec2::ZERO);
    for i in 0..n {
        let (p, q) = (poly[i], poly[(i + 1) % n]);
        let w = p.perp_dot(q);
        a += w;
        c += (p + q) * w;
    }
    if a.abs() < 1e-300 {
        poly.iter().copied().sum::<Vec2>() / n.max(1) as f64
    } else {
        c / (3.0 * a)
    }
}

/// Solid angle of triangle (a, b, c) seen from the origin (Van Oosterom & Strackee).
fn solid_angle(a: Vec3, b: Vec3, c: Vec3) -> f64 {
    let (la, lb, lc) = (a.length(), b.length(), c.length());
    let num = a.dot(b.cross(c)).abs();
    let den = la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la;
    2.0 * num.atan2(den)
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
        check_in(at, "min_topple_deg", self.min_topple_deg, 0.0, 90.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
}
