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

/// How high over a surface what stands on it is looked for (m): above, it is not on
/// the surface but over it (a shelf, the robot's own arm).
pub(super) const CLUTTER_TOP: f64 = 0.5;

/// The fewest scene points (one per search leaf) that make an object on a surface: a
/// lone point or two over an empty table is a stray return or the range noise of a far
/// view (a Kinect's σ = 1.5 mm·z² is 1.3 cm at 3 m) that no near view confirmed.
pub(super) const MIN_OBJECT_POINTS: usize = 3;

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

    /// What stands on the surface: the points of `pts` over the outline between
    /// `above` and [`CLUTTER_TOP`] over its plane, as clusters `gap` apart of at least
    /// [`MIN_OBJECT_POINTS`]. Free space and the placement's collision world both take
    /// the surface's clutter from here, so a spot the map calls free is not blocked by
    /// what the map ignored.
    pub(super) fn objects_on(&self, pts: &[Vec3], above: f64, gap: f64) -> Vec<Vec<Vec3>> {
        let over: Vec<Vec3> = pts
            .iter()
            .copied()
            .filter(|&q| self.holds(q, above))
            .collect();
        crate::observe::clusters(&over, gap)
            .into_iter()
            .filter(|c| c.len() >= MIN_OBJECT_POINTS)
            .map(|c| c.into_iter().map(|i| over[i]).collect())
            .collect()
    }

    /// Whether `q` is over the outline between `above` and [`CLUTTER_TOP`] over it:
    /// where [`Self::objects_on`] looks.
    pub(super) fn holds(&self, q: Vec3, above: f64) -> bool {
        let h = self.height(q);
        h > above && h < CLUTTER_TOP && self.over(q)
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_lone_point_over_a_table_is_no_object_and_three_together_are() {
        let table = Outline {
            normal: Vec3::Z,
            offset: 0.7,
            poly: vec![
                Vec2::new(0.0, 0.0),
                Vec2::new(1.0, 0.0),
                Vec2::new(1.0, 1.0),
                Vec2::new(0.0, 1.0),
            ],
        };
        // A range-noise point 1.7 cm up, a small box's three points, something over
        // the table but higher than clutter stands, and a point beside the table.
        let noise = Vec3::new(0.3, 0.3, 0.717);
        let small = [0.0, 0.01, 0.02].map(|d| Vec3::new(0.6 + d, 0.6, 0.73));
        let high = Vec3::new(0.5, 0.5, 0.7 + CLUTTER_TOP + 0.1);
        let beside = Vec3::new(1.2, 0.5, 0.75);
        let mut pts = vec![noise, high, beside];
        pts.extend(small);
        let objects = table.objects_on(&pts, 0.015, 0.015);
        assert_eq!(objects.len(), 1);
        assert_eq!(objects[0].len(), 3);
        assert!(objects[0].iter().all(|q| q.x >= 0.6));
        assert!(table.holds(noise, 0.015) && !table.holds(noise, 0.02));
        assert!(!table.holds(high, 0.015) && !table.holds(beside, 0.015));
    }
}
