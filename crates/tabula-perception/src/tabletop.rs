//! Seed 002's tabletop pipeline (SPEC §3.1) on an organized frame: the table plane (a
//! horizontal plane found by peeling off others), its 2D convex hull, the prism of points
//! above it, and connected objects, each with centroid, principal directions and an
//! oriented box.

use crate::plane::{Plane, RansacParams, ransac_plane};
use tabula_geom::{Pose, Vec3};

/// Parameters; defaults from SPEC §6.
#[derive(Debug, Clone, serde::Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct TabletopParams {
    pub ransac: RansacParams,
    /// Largest tilt of a table's normal from vertical (rad), SPEC §6.
    pub max_tilt: f64,
    /// A surface needs this fraction of the cloud's points, SPEC §6 (5 %).
    pub min_surface_fraction: f64,
    /// Objects start this far above the table (m).
    pub min_height: f64,
    /// Neighbouring pixels join one object if closer than this (m).
    pub cluster_tolerance: f64,
    /// Smallest object (points), SPEC §6 (200).
    pub min_object_points: usize,
    /// Lowest and highest table height accepted (world z, m).
    pub height_range: [f64; 2],
}

impl Default for TabletopParams {
    fn default() -> Self {
        Self {
            ransac: RansacParams::default(),
            max_tilt: 0.09,
            min_surface_fraction: 0.05,
            min_height: 0.005,
            cluster_tolerance: 0.01,
            min_object_points: 200,
            height_range: [0.2, 1.6],
        }
    }
}

/// A found object.
#[derive(Debug, Clone)]
pub struct TableObject {
    /// Pixel indices into the cloud.
    pub indices: Vec<usize>,
    pub centroid: Vec3,
    /// Principal directions (largest variance first), world frame.
    pub axes: [Vec3; 3],
    /// Oriented box: centre, axes as above, half sizes.
    pub obb_center: Vec3,
    pub obb_half: Vec3,
    /// Highest point above the table (m).
    pub height: f64,
}

/// The result of the pipeline.
#[derive(Debug, Clone)]
pub struct Tabletop {
    pub plane: Plane,
    pub table_indices: Vec<usize>,
    /// Convex hull of the table in the plane (world points on the plane).
    pub hull: Vec<Vec3>,
    pub objects: Vec<TableObject>,
}

/// Why no table was found.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum TabletopError {
    #[error("the cloud has no finite points")]
    Empty,
    #[error("no horizontal surface with enough points in the height range")]
    NoTable,
}

/// 2D convex hull (monotone chain) of points given in a plane basis; returns indices.
fn hull_2d(pts: &[(f64, f64)]) -> Vec<usize> {
    let mut idx: Vec<usize> = (0..pts.len()).collect();
    idx.sort_by(|&a, &b| {
        pts[a]
            .0
            .total_cmp(&pts[b].0)
            .then(pts[a].1.total_cmp(&pts[b].1))
    });
    if idx.len() < 3 {
        return idx;
    }
    let cross = |o: usize, a: usize, b: usize| {
        (pts[a].0 - pts[o].0) * (pts[b].1 - pts[o].1)
            - (pts[a].1 - pts[o].1) * (pts[b].0 - pts[o].0)
    };
    let mut lower: Vec<usize> = Vec::new();
    for &i in &idx {
        while lower.len() >= 2 && cross(lower[lower.len() - 2], lower[lower.len() - 1], i) <= 0.0 {
            lower.pop();
        }
        lower.push(i);
    }
    let mut upper: Vec<usize> = Vec::new();
    for &i in idx.iter().rev() {
        while upper.len() >= 2 && cross(upper[upper.len() - 2], upper[upper.len() - 1], i) <= 0.0 {
            upper.pop();
        }
        upper.push(i);
    }
    lower.pop();
    upper.pop();
    lower.extend(upper);
    lower
}

fn inside(poly: &[(f64, f64)], p: (f64, f64)) -> bool {
    let n = poly.len();
    if n < 3 {
        return false;
    }
    (0..n).all(|i| {
        let (a, b) = (poly[i], poly[(i + 1) % n]);
        (b.0 - a.0) * (p.1 - a.1) - (b.1 - a.1) * (p.0 - a.0) >= 0.0
    })
}

/// Runs the pipeline on an organized cloud given in the world frame (`world_points`,
/// NaN = no return).
pub fn extract(
    world_points: &[Vec3],
    width: usize,
    height: usize,
    p: &TabletopParams,
) -> Result<Tabletop, TabletopError> {
    let finite: Vec<usize> = (0..world_points.len())
        .filter(|&i| world_points[i].is_finite())
        .collect();
    if finite.is_empty() {
        return Err(TabletopError::Empty);
    }
    let min_points = (p.min_surface_fraction * finite.len() as f64) as usize;
    let mut remaining = finite.clone();
    let mut found = None;
    for round in 0..8 {
        let params = RansacParams {
            seed: p.ransac.seed.wrapping_add(round),
            ..p.ransac.clone()
        };
        let Some((plane, inliers)) = ransac_plane(world_points, &remaining, &params) else {
            break;
        };
        if inliers.len() < min_points.max(3) {
            break;
        }
        let up = if plane.normal.z < 0.0 {
            Plane {
                normal: -plane.normal,
                d: -plane.d,
            }
        } else {
            plane
        };
        let tilt = up.normal.angle_between(Vec3::Z);
        let centre_z =
            inliers.iter().map(|&i| world_points[i].z).sum::<f64>() / inliers.len() as f64;
        if tilt <= p.max_tilt && centre_z >= p.height_range[0] && centre_z <= p.height_range[1] {
            found = Some((up, inliers));
            break;
        }
        // Floor, walls, anything else: peel it off and look again (SPEC §1.3, Alg. 9).
        let drop: std::collections::HashSet<usize> = inliers.into_iter().collect();
        remaining.retain(|i| !drop.contains(i));
    }
    let (plane, table) = found.ok_or(TabletopError::NoTable)?;
    // The plane's own 2D basis.
    let u = plane.normal.any_orthonormal_vector();
    let v = plane.normal.cross(u);
    let to2 = |q: Vec3| (q.dot(u), q.dot(v));
    // Hull candidates: the first and last table pixel of every image row. A row of rays
    // is a plane through the camera, which meets the table in a line, so the row's table
    // points lie between those two: the hull of all of them is the hull of these.
    let rows = height.max(1);
    let mut first = vec![usize::MAX; rows];
    let mut last = vec![0usize; rows];
    for &i in &table {
        let row = (i / width.max(1)).min(rows - 1);
        first[row] = first[row].min(i);
        last[row] = last[row].max(i);
    }
    let mut row_ends: Vec<usize> = Vec::with_capacity(2 * rows);
    if rows == 1 {
        // Not organized: every table point is a candidate.
        row_ends.extend(table.iter().copied());
    }
    for row in (0..rows).filter(|_| rows > 1) {
        if first[row] != usize::MAX {
            row_ends.push(first[row]);
            if last[row] != first[row] {
                row_ends.push(last[row]);
            }
        }
    }
    let table_2d: Vec<(f64, f64)> = row_ends.iter().map(|&i| to2(world_points[i])).collect();
    let hull_idx = hull_2d(&table_2d);
    let poly: Vec<(f64, f64)> = hull_idx.iter().map(|&k| table_2d[k]).collect();
    let hull: Vec<Vec3> = hull_idx
        .iter()
        .map(|&k| {
            let q = world_points[row_ends[k]];
            q - plane.normal * plane.distance(q)
        })
        .collect();
    // The prism: above the plane, inside the hull.
    let mut above = vec![false; world_points.len()];
    for &i in &finite {
        let q = world_points[i];
        let h = plane.distance(q);
        if h > p.min_height.max(p.ransac.threshold) && inside(&poly, to2(q)) {
            above[i] = true;
        }
    }
    // Connected components over the pixel grid (4-neighbours closer than the tolerance).
    let mut label = vec![usize::MAX; world_points.len()];
    let mut objects = Vec::new();
    for start in 0..world_points.len() {
        if !above[start] || label[start] != usize::MAX {
            continue;
        }
        let id = objects.len();
        let mut stack = vec![start];
        label[start] = id;
        let mut members = Vec::new();
        while let Some(i) = stack.pop() {
            members.push(i);
            let (x, y) = (i % width, i / width);
            let mut visit = |j: usize| {
                if above[j]
                    && label[j] == usize::MAX
                    && (world_points[j] - world_points[i]).length() <= p.cluster_tolerance
                {
                    label[j] = id;
                    stack.push(j);
                }
            };
            if x > 0 {
                visit(i - 1);
            }
            if x + 1 < width {
                visit(i + 1);
            }
            if y > 0 {
                visit(i - width);
            }
            if y + 1 < height {
                visit(i + width);
            }
        }
        objects.push(members);
    }
    let objects = objects
        .into_iter()
        .filter(|m| m.len() >= p.min_object_points)
        .map(|indices| describe(world_points, &plane, indices))
        .collect();
    Ok(Tabletop {
        plane,
        table_indices: table,
        hull,
        objects,
    })
}

fn describe(points: &[Vec3], plane: &Plane, indices: Vec<usize>) -> TableObject {
    let pts: Vec<Vec3> = indices.iter().map(|&i| points[i]).collect();
    let centroid = pts.iter().copied().sum::<Vec3>() / pts.len() as f64;
    let mut m = nalgebra::Matrix3::zeros();
    for q in &pts {
        let d = nalgebra::Vector3::new(q.x - centroid.x, q.y - centroid.y, q.z - centroid.z);
        m += d * d.transpose();
    }
    let eig = nalgebra::SymmetricEigen::new(m);
    let mut order = [0usize, 1, 2];
    order.sort_by(|&a, &b| eig.eigenvalues[b].total_cmp(&eig.eigenvalues[a]));
    let axis = |k: usize| {
        let c = eig.eigenvectors.column(order[k]);
        Vec3::new(c[0], c[1], c[2]).normalize_or(Vec3::X)
    };
    let (a0, a1) = (axis(0), axis(1));
    let a2 = a0.cross(a1).normalize_or(Vec3::Z);
    let axes = [a0, a1, a2];
    let mut lo = Vec3::splat(f64::INFINITY);
    let mut hi = Vec3::splat(f64::NEG_INFINITY);
    for q in &pts {
        let l = Vec3::new(
            (*q - centroid).dot(a0),
            (*q - centroid).dot(a1),
            (*q - centroid).dot(a2),
        );
        lo = lo.min(l);
        hi = hi.max(l);
    }
    let mid = (lo + hi) / 2.0;
    let obb_center = centroid + a0 * mid.x + a1 * mid.y + a2 * mid.z;
    let height = pts.iter().map(|q| plane.distance(*q)).fold(0.0, f64::max);
    TableObject {
        indices,
        centroid,
        axes,
        obb_center,
        obb_half: (hi - lo) / 2.0,
        height,
    }
}

/// Transforms an organized camera-frame cloud into the world frame.
pub fn to_world(world_from_camera: &Pose, camera_points: &[Vec3]) -> Vec<Vec3> {
    camera_points
        .iter()
        .map(|p| {
            if p.is_finite() {
                *world_from_camera * *p
            } else {
                Vec3::NAN
            }
        })
        .collect()
}
