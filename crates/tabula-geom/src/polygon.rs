//! 2D polygons: convex hulls, areas and containment, for surfaces seen from above.

use crate::{Vec2, Vec3};

/// A basis of the plane: `u`, `v` and the normal form a right-handed frame.
pub fn plane_basis(normal: Vec3) -> (Vec3, Vec3) {
    let u = normal.any_orthonormal_vector();
    (u, normal.cross(u))
}

/// Indices of the convex hull of `points`, counter-clockwise, without collinear points
/// (Andrew's monotone chain). Fewer than three distinct points give what there is.
/// Big inputs are first thinned by Akl–Toussaint's heuristic: points strictly inside
/// the octagon of the eight extreme points in x, y, x + y and x − y cannot be on the
/// hull, and for an object's tens of thousands of points that is nearly all of them,
/// so the sort sees a few hundred.
pub fn convex_hull_2d(points: &[Vec2]) -> Vec<usize> {
    let mut idx: Vec<usize> = (0..points.len())
        .filter(|&i| points[i].is_finite())
        .collect();
    if idx.len() > 64 {
        // Extremes along ±x, ±y, ±(x+y), ±(x−y), found in one pass.
        let keys = |p: Vec2| {
            [
                p.x,
                p.x + p.y,
                p.y,
                p.y - p.x,
                -p.x,
                -p.x - p.y,
                -p.y,
                p.x - p.y,
            ]
        };
        let mut best = [idx[0]; 8];
        let mut best_key = keys(points[idx[0]]);
        for &i in &idx[1..] {
            let k = keys(points[i]);
            for d in 0..8 {
                if k[d] > best_key[d] {
                    best_key[d] = k[d];
                    best[d] = i;
                }
            }
        }
        // In the order they go round: +x, +x+y, +y, −x+y, −x, −x−y, −y, +x−y.
        let mut octagon: Vec<Vec2> = Vec::with_capacity(8);
        for q in best.map(|i| points[i]) {
            if octagon.last() != Some(&q) && octagon.first() != Some(&q) {
                octagon.push(q);
            }
        }
        if octagon.len() >= 3 && polygon_area(&octagon) > 0.0 {
            let n = octagon.len();
            let edges: Vec<(Vec2, Vec2)> = (0..n)
                .map(|k| (octagon[k], octagon[(k + 1) % n] - octagon[k]))
                .collect();
            idx.retain(|&i| {
                let p = points[i];
                edges.iter().any(|&(o, e)| e.perp_dot(p - o) <= 0.0)
            });
        }
    }
    monotone_chain(points, idx)
}

/// Andrew's monotone chain over the finite points `idx` of `points`.
fn monotone_chain(points: &[Vec2], mut idx: Vec<usize>) -> Vec<usize> {
    idx.sort_by(|&a, &b| {
        points[a]
            .x
            .total_cmp(&points[b].x)
            .then(points[a].y.total_cmp(&points[b].y))
    });
    idx.dedup_by(|a, b| points[*a] == points[*b]);
    if idx.len() < 3 {
        return idx;
    }
    let cross =
        |o: usize, a: usize, b: usize| (points[a] - points[o]).perp_dot(points[b] - points[o]);
    let mut hull: Vec<usize> = Vec::with_capacity(2 * idx.len());
    for pass in 0..2 {
        let start = hull.len();
        let order: Box<dyn Iterator<Item = &usize>> = if pass == 0 {
            Box::new(idx.iter())
        } else {
            Box::new(idx.iter().rev())
        };
        for &i in order {
            while hull.len() >= start + 2
                && cross(hull[hull.len() - 2], hull[hull.len() - 1], i) <= 0.0
            {
                hull.pop();
            }
            hull.push(i);
        }
        hull.pop();
    }
    hull
}

/// Signed area (positive when counter-clockwise).
pub fn polygon_area(poly: &[Vec2]) -> f64 {
    let n = poly.len();
    (0..n)
        .map(|i| poly[i].perp_dot(poly[(i + 1) % n]))
        .sum::<f64>()
        / 2.0
}

/// Whether `p` is inside (or on) a counter-clockwise convex polygon.
pub fn inside_convex(poly: &[Vec2], p: Vec2) -> bool {
    let n = poly.len();
    n >= 3 && (0..n).all(|i| (poly[(i + 1) % n] - poly[i]).perp_dot(p - poly[i]) >= 0.0)
}

/// Whether `p` is inside a simple polygon of either orientation (even–odd rule).
pub fn inside_polygon(poly: &[Vec2], p: Vec2) -> bool {
    let n = poly.len();
    let mut inside = false;
    for i in 0..n {
        let (a, b) = (poly[i], poly[(i + n - 1) % n]);
        if (a.y > p.y) != (b.y > p.y) && p.x < (b.x - a.x) * (p.y - a.y) / (b.y - a.y) + a.x {
            inside = !inside;
        }
    }
    inside
}

/// How far `p` can travel along the unit direction `d` before it leaves a
/// counter-clockwise convex polygon (0 when it is outside; infinite for a polygon of
/// fewer than three corners, which bounds nothing).
pub fn exit_distance(poly: &[Vec2], p: Vec2, d: Vec2) -> f64 {
    let n = poly.len();
    if n < 3 {
        return f64::INFINITY;
    }
    if !inside_convex(poly, p) {
        return 0.0;
    }
    (0..n)
        .filter_map(|i| {
            let (a, b) = (poly[i], poly[(i + 1) % n]);
            // Outward normal of a counter-clockwise edge: its right side.
            let e = b - a;
            let out = Vec2::new(e.y, -e.x);
            let towards = d.dot(out);
            (towards > 0.0).then(|| (a - p).dot(out) / towards)
        })
        .fold(f64::INFINITY, f64::min)
        .max(0.0)
}

/// Distance from `p` to the boundary of a polygon.
pub fn distance_to_boundary(poly: &[Vec2], p: Vec2) -> f64 {
    let n = poly.len();
    (0..n)
        .map(|i| segment_distance(p, poly[i], poly[(i + 1) % n]))
        .fold(f64::INFINITY, f64::min)
}

/// Distance from `p` to the segment `a`–`b`.
pub fn segment_distance(p: Vec2, a: Vec2, b: Vec2) -> f64 {
    let ab = b - a;
    let t = if ab.length_squared() > 0.0 {
        ((p - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (a + ab * t).distance(p)
}

/// The smallest-area rectangle holding `points` (rotating calipers over the convex
/// hull's edges: one side of the optimum lies on a hull edge). A square object gets its
/// own square, not the √2-larger box a PCA frame gives it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rectangle {
    pub center: Vec2,
    /// Unit direction of the first side.
    pub axis: Vec2,
    /// Side lengths along `axis` and its perpendicular.
    pub size: Vec2,
}

impl Rectangle {
    /// The four corners, counter-clockwise.
    pub fn corners(&self) -> [Vec2; 4] {
        let (u, v) = (
            self.axis * self.size.x / 2.0,
            self.axis.perp() * self.size.y / 2.0,
        );
        let c = self.center;
        [c - u - v, c + u - v, c + u + v, c - u + v]
    }

    /// Extent of the rectangle along unit direction `d`.
    pub fn extent_along(&self, d: Vec2) -> f64 {
        let perp = self.axis.perp();
        self.size.x * self.axis.dot(d).abs() + self.size.y * perp.dot(d).abs()
    }

    /// The longer side's direction and the shorter side's (unit; the first side's
    /// when square).
    pub fn principal_axes(&self) -> (Vec2, Vec2) {
        let a = self.axis.normalize_or(Vec2::X);
        if self.size.x >= self.size.y {
            (a, a.perp())
        } else {
            (a.perp(), a)
        }
    }
}

/// See [`Rectangle`]; `None` without three non-collinear finite points.
pub fn min_area_rectangle(points: &[Vec2]) -> Option<Rectangle> {
    let hull: Vec<Vec2> = convex_hull_2d(points).iter().map(|&i| points[i]).collect();
    min_area_rectangle_of_hull(&hull)
}

/// [`min_area_rectangle`] of a convex polygon already at hand (counter-clockwise, as
/// [`convex_hull_2d`] gives it), so callers holding the hull do not build it twice.
pub fn min_area_rectangle_of_hull(hull: &[Vec2]) -> Option<Rectangle> {
    if hull.len() < 3 {
        return None;
    }
    let mut best: Option<(f64, Rectangle)> = None;
    for i in 0..hull.len() {
        let Some(axis) = (hull[(i + 1) % hull.len()] - hull[i]).try_normalize() else {
            continue;
        };
        let perp = axis.perp();
        let (mut lo, mut hi) = (Vec2::splat(f64::INFINITY), Vec2::splat(f64::NEG_INFINITY));
        for p in hull {
            let q = Vec2::new(p.dot(axis), p.dot(perp));
            lo = lo.min(q);
            hi = hi.max(q);
        }
        let size = hi - lo;
        let area = size.x * size.y;
        if best.as_ref().is_none_or(|(a, _)| area < *a) {
            let mid = (lo + hi) / 2.0;
            best = Some((
                area,
                Rectangle {
                    center: axis * mid.x + perp * mid.y,
                    axis,
                    size,
                },
            ));
        }
    }
    best.map(|(_, r)| r)
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    #[test]
    fn exit_distance_along_a_ray_out_of_a_rectangle() {
        let r = [
            Vec2::new(0.0, 0.0),
            Vec2::new(2.0, 0.0),
            Vec2::new(2.0, 1.0),
            Vec2::new(0.0, 1.0),
        ];
        let p = Vec2::new(0.5, 0.5);
        assert!((exit_distance(&r, p, Vec2::X) - 1.5).abs() < 1e-12);
        assert!((exit_distance(&r, p, -Vec2::X) - 0.5).abs() < 1e-12);
        assert!((exit_distance(&r, p, Vec2::Y) - 0.5).abs() < 1e-12);
        let diag = Vec2::new(1.0, 1.0).normalize();
        assert!((exit_distance(&r, p, diag) - 0.5 * 2f64.sqrt()).abs() < 1e-12);
        assert_eq!(exit_distance(&r, Vec2::new(3.0, 0.5), Vec2::X), 0.0);
        assert_eq!(exit_distance(&r[..2], p, Vec2::X), f64::INFINITY);
    }

    #[test]
    fn hull_of_a_square_with_inner_and_collinear_points() {
        let pts: Vec<Vec2> = [
            (0.0, 0.0),
            (1.0, 0.0),
            (1.0, 1.0),
            (0.0, 1.0),
            (0.5, 0.5),
            (0.5, 0.0),
            (1.0, 1.0),
        ]
        .iter()
        .map(|&(x, y)| Vec2::new(x, y))
        .collect();
        let h = convex_hull_2d(&pts);
        assert_eq!(h.len(), 4);
        let poly: Vec<Vec2> = h.iter().map(|&i| pts[i]).collect();
        assert!((polygon_area(&poly) - 1.0).abs() < 1e-12);
        assert!(inside_convex(&poly, Vec2::new(0.5, 0.5)));
        assert!(!inside_convex(&poly, Vec2::new(1.5, 0.5)));
        assert!(inside_polygon(&poly, Vec2::new(0.2, 0.9)));
        assert!((distance_to_boundary(&poly, Vec2::new(0.5, 0.4)) - 0.4).abs() < 1e-12);
        assert!(convex_hull_2d(&[]).is_empty());
        assert_eq!(convex_hull_2d(&[Vec2::ONE, Vec2::ONE, Vec2::NAN]).len(), 1);
        // Collinear input: the two ends.
        let line: Vec<Vec2> = (0..5).map(|i| Vec2::new(i as f64, i as f64)).collect();
        assert_eq!(convex_hull_2d(&line).len(), 2);
    }

    proptest! {
        /// The octagon thinning keeps every hull vertex: the same hull as the monotone
        /// chain over all points, on clouds big enough to be thinned.
        #[test]
        fn thinning_keeps_the_hull(pts in prop::collection::vec((-10.0..10.0f64, -10.0..10.0f64), 65..400)) {
            let pts: Vec<Vec2> = pts.into_iter().map(|(x, y)| Vec2::new(x, y)).collect();
            let mut fast = convex_hull_2d(&pts);
            let mut full = monotone_chain(&pts, (0..pts.len()).collect());
            fast.sort_unstable();
            full.sort_unstable();
            prop_assert_eq!(fast, full);
        }

        #[test]
        fn every_point_is_inside_its_hull(pts in prop::collection::vec((-10.0..10.0f64, -10.0..10.0f64), 3..60)) {
            let pts: Vec<Vec2> = pts.into_iter().map(|(x, y)| Vec2::new(x, y)).collect();
            let h = convex_hull_2d(&pts);
            let poly: Vec<Vec2> = h.iter().map(|&i| pts[i]).collect();
            if poly.len() >= 3 {
                prop_assert!(polygon_area(&poly) > 0.0);
                for p in &pts {
                    // Inside up to rounding: nudge towards the centroid.
                    let c = poly.iter().copied().sum::<Vec2>() / poly.len() as f64;
                    prop_assert!(inside_convex(&poly, *p + (c - *p) * 1e-9));
                }
            }
        }
    }
}
#[cfg(test)]
mod rectangle_tests {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        /// A rotated, shifted rectangle's corners and inner points give back that
        /// rectangle, whatever its angle.
        #[test]
        fn recovers_a_rotated_rectangle(
            angle in -3.2f64..3.2, w in 0.01f64..1.0, h in 0.01f64..1.0,
            cx in -2.0f64..2.0, cy in -2.0f64..2.0,
        ) {
            let axis = Vec2::new(angle.cos(), angle.sin());
            let perp = axis.perp();
            let c = Vec2::new(cx, cy);
            let mut pts = Vec::new();
            for i in 0..=4 {
                for j in 0..=4 {
                    let (s, t) = (i as f64 / 4.0 - 0.5, j as f64 / 4.0 - 0.5);
                    pts.push(c + axis * (s * w) + perp * (t * h));
                }
            }
            let r = min_area_rectangle(&pts).unwrap();
            prop_assert!((r.size.x * r.size.y - w * h).abs() < 1e-9 * (1.0 + w * h));
            prop_assert!((r.center - c).length() < 1e-9);
            prop_assert!((r.extent_along(axis) - w).abs() < 1e-9);
            prop_assert!((r.extent_along(perp) - h).abs() < 1e-9);
        }
    }

    #[test]
    fn degenerate_input_has_no_rectangle() {
        assert!(min_area_rectangle(&[]).is_none());
        let line: Vec<Vec2> = (0..5).map(|i| Vec2::new(i as f64, 0.0)).collect();
        assert!(min_area_rectangle(&line).is_none());
        assert!(min_area_rectangle(&[Vec2::NAN, Vec2::ONE, Vec2::ZERO]).is_none());
    }
}
