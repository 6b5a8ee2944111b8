//! A surface's outline and footprints on it: heights, edges, blocked paths.

use crate::stable::StablePose;
use tabula_geom::polygon::{convex_hull_2d, inside_convex};
use tabula_geom::{Vec2, Vec3};
use tabula_perception::surfaces::Surface;

/// The object's footprint resting in `pose` (yaw 0), relative to the contact centroid.
pub(super) fn footprint_of(pose: &StablePose, model: &[Vec3]) -> Vec<Vec2> {
    let r = pose.resting_rotation(0.0);
    let c = r * Vec3::from_array(pose.contact_centroid);
    let flat: Vec<Vec2> = model.iter().map(|q| (r * *q - c).truncate()).collect();
    convex_hull_2d(&flat).into_iter().map(|i| flat[i]).collect()
}

/// A surface's plane and outline seen from above (counter-clockwise), built once: the
/// scene's points are tested against it one by one.
pub(super) struct Outline {
    pub(super) normal: Vec3,
    pub(super) offset: f64,
    pub(super) poly: Vec<Vec2>,
}

impl Outline {
    pub(super) fn of(surface: &Surface) -> Self {
        let mut poly: Vec<Vec2> = surface.hull.iter().map(|p| p.truncate()).collect();
        if tabula_geom::polygon::polygon_area(&poly) < 0.0 {
            poly.reverse();
        }
        let normal = surface.plane.normal;
        Self {
            normal,
            offset: surface.centroid.dot(normal),
            poly,
        }
    }

    /// Height of `q` above the surface's plane (m).
    pub(super) fn height(&self, q: Vec3) -> f64 {
        q.dot(self.normal) - self.offset
    }

    /// Whether `q` is over the outline.
    pub(super) fn over(&self, q: Vec3) -> bool {
        inside_convex(&self.poly, q.truncate())
    }

    /// Horizontal distance from `q` to the outline (0 over it).
    pub(super) fn distance(&self, q: Vec2) -> f64 {
        if inside_convex(&self.poly, q) {
            0.0
        } else {
            tabula_geom::polygon::distance_to_boundary(&self.poly, q)
        }
    }
}

/// The outline's point nearest `q` and the edge's outward normal there.
pub(super) fn nearest_edge(poly: &[Vec2], q: Vec2) -> (Vec2, Vec2) {
    let mut p: Vec<Vec2> = poly.to_vec();
    if tabula_geom::polygon::polygon_area(&p) < 0.0 {
        p.reverse();
    }
    let n = p.len();
    let mut best = (f64::INFINITY, q, Vec2::X);
    for i in 0..n {
        let (a, b) = (p[i], p[(i + 1) % n]);
        let ab = b - a;
        let t = if ab.length_squared() > 0.0 {
            ((q - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let c = a + ab * t;
        let d = c.distance(q);
        if d < best.0 {
            // Counter-clockwise: outward is to the right of the edge.
            let out = Vec2::new(ab.y, -ab.x).normalize_or(Vec2::X);
            best = (d, c, out);
        }
    }
    (best.1, best.2)
}

/// Whether the base (its half-width plus 2 cm, as it drives front first) would sweep
/// through seen obstacles (points between 5 cm and 1.5 m high) going straight from
/// `from` to `to`.
pub(super) fn path_blocked(from: Vec2, to: Vec2, half: f64, scene: &[Vec3]) -> bool {
    let radius = half + 0.02;
    let seg = to - from;
    let len2 = seg.length_squared();
    scene.iter().any(|q| {
        if q.z < 0.05 || q.z > 1.5 {
            return false;
        }
        let p = q.truncate();
        let t = if len2 > 0.0 {
            ((p - from).dot(seg) / len2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        (from + seg * t).distance(p) < radius
    })
}
