//! The convex hull stable poses are computed on: outward triangles, their adjacency,
//! exact planar facets, and what a facet topples onto.

use super::StableError;
use rustc_hash::FxHashMap;
use std::collections::VecDeque;
use tabula_geom::polygon::segment_distance;
use tabula_geom::{Vec2, Vec3};

/// A convex hull with outward triangles, their adjacency and planar facets.
pub(super) struct Hull {
    pub(super) vertices: Vec<Vec3>,
    pub(super) triangles: Vec<[u32; 3]>,
    pub(super) normals: Vec<Vec3>,
    pub(super) areas: Vec<f64>,
    /// For each triangle, the triangle across each of its edges (k, k+1).
    pub(super) across: Vec<[usize; 3]>,
    /// Facet of each triangle, and each facet's triangles.
    pub(super) facet_of: Vec<usize>,
    pub(super) facets: Vec<Vec<usize>>,
    pub(super) centre: Vec3,
}

impl Hull {
    pub(super) fn new(points: &[Vec3]) -> Result<Self, StableError> {
        let mut distinct: Vec<[u64; 3]> = points
            .iter()
            .map(|p| p.to_array().map(f64::to_bits))
            .collect();
        distinct.sort_unstable();
        distinct.dedup();
        if distinct.len() < 4 {
            return Err(StableError::TooFewPoints(distinct.len()));
        }
        let thinned =
            tabula_geom::hull_input::thin_for_hull(points, tabula_geom::hull_input::MAX_HULL_INPUT);
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
    pub(super) fn merge_facets(&mut self, angle: f64) {
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

    pub(super) fn contains(&self, p: Vec3) -> bool {
        p.is_finite()
            && self
                .triangles
                .iter()
                .zip(&self.normals)
                .all(|(t, n)| n.dot(p - self.vertices[t[0] as usize]) < 0.0)
    }

    pub(super) fn volume_centroid(&self) -> Vec3 {
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
    pub(super) fn support_offset(&self, n: Vec3) -> f64 {
        self.vertices
            .iter()
            .map(|v| v.dot(n))
            .fold(f64::NEG_INFINITY, f64::max)
    }

    pub(super) fn facet_area(&self, f: usize) -> f64 {
        self.facets[f].iter().map(|&t| self.areas[t]).sum()
    }

    pub(super) fn facet_normal(&self, f: usize) -> Vec3 {
        self.facets[f]
            .iter()
            .map(|&t| self.normals[t] * self.areas[t])
            .sum::<Vec3>()
            .normalize_or(self.normals[self.facets[f][0]])
    }

    /// The facet a body resting on facet `f` topples onto, or `None` when it rests.
    /// It pivots about the boundary edge that the line from the facet's centroid to
    /// the centre of mass's projection leaves through.
    pub(super) fn topples_to(&self, f: usize, com: Vec3) -> Option<usize> {
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
}

/// Two unit vectors completing `n` to a right-handed frame (u × v = n), so a polygon
/// counter-clockwise in (u, v) is counter-clockwise seen from the tip of `n`.
pub(super) fn basis(n: Vec3) -> (Vec3, Vec3) {
    let u = n.any_orthonormal_vector();
    (u, n.cross(u))
}

pub(super) fn polygon_centroid(poly: &[Vec2]) -> Vec2 {
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
pub(super) fn solid_angle(a: Vec3, b: Vec3, c: Vec3) -> f64 {
    let (la, lb, lc) = (a.length(), b.length(), c.length());
    let num = a.dot(b.cross(c)).abs();
    let den = la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la;
    2.0 * num.atan2(den)
}
