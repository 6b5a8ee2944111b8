//! 2D polygons: convex hulls, areas and containment, for surfaces seen from above.

use crate::Vec2;

/// Indices of the convex hull of `points`, counter-clockwise, without collinear points
/// (Andrew's monotone chain). Fewer than three distinct points give what there is.
pub fn convex_hull_2d(points: &[Vec2]) -> Vec<usize> {
    let mut idx: Vec<usize> = (0..points.len())
        .filter(|&i| points[i].is_finite())
        .collect();
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

/// Distance from `p` to the boundary of a polygon.
pub fn distance_to_boundary(poly: &[Vec2], p: Vec2) -> f64 {
    let n = poly.len();
    (0..n)
        .map(|i| {
            let (a, b) = (poly[i], poly[(i + 1) % n]);
            let ab = b - a;
            let t = if ab.length_squared() > 0.0 {
                ((p - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0)
            } else {
                0.0
            };
            (a + ab * t).distance(p)
        })
        .fold(f64::INFINITY, f64::min)
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

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
