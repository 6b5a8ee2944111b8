//! A simple polygon cut into convex pieces: ear-clipping triangulation, then
//! Hertel–Mehlhorn merging (a diagonal is dropped while both sides stay convex), which
//! gives at most four times the fewest pieces possible. Exact, unlike V-HACD's
//! approximation: an arch's notch stays the notch it was drawn with.
//!
//! Hand-written rather than a triangulation crate: the merge step needs the diagonals,
//! which earcut-style crates do not return, and the whole is ~150 lines.

use crate::Vec2;
use crate::polygon::polygon_area;

/// Why a polygon has no convex pieces.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PolygonError {
    #[error("a polygon needs at least 3 vertices, got {0}")]
    TooFew(usize),
    #[error("polygon vertex {0} is not finite")]
    NotFinite(usize),
    #[error("the polygon encloses no area")]
    NoArea,
    #[error("the polygon's edges {0} and {1} cross: it must be simple")]
    SelfIntersecting(usize, usize),
}

/// Convex pieces (each counter-clockwise) covering the simple polygon `outline` (either
/// orientation). Repeated and collinear vertices are dropped first.
pub fn convex_pieces(outline: &[Vec2]) -> Result<Vec<Vec<Vec2>>, PolygonError> {
    if let Some(i) = outline.iter().position(|p| !p.is_finite()) {
        return Err(PolygonError::NotFinite(i));
    }
    let mut poly = cleaned(outline);
    if poly.len() < 3 {
        return Err(PolygonError::TooFew(poly.len()));
    }
    let area = polygon_area(&poly);
    let scale = poly
        .iter()
        .map(|p| p.length())
        .fold(0.0, f64::max)
        .max(1e-300);
    if area.abs() <= 1e-12 * scale * scale {
        return Err(PolygonError::NoArea);
    }
    if area < 0.0 {
        poly.reverse();
    }
    if let Some((a, b)) = crossing_edges(&poly) {
        return Err(PolygonError::SelfIntersecting(a, b));
    }
    let triangles = ear_clip(&poly);
    Ok(merged(&poly, triangles)
        .into_iter()
        .map(|piece| piece.iter().map(|&i| poly[i]).collect())
        .collect())
}

/// Without repeated vertices and vertices on a straight run.
fn cleaned(outline: &[Vec2]) -> Vec<Vec2> {
    let mut poly: Vec<Vec2> = Vec::with_capacity(outline.len());
    for &p in outline {
        if poly.last().is_none_or(|&q| (p - q).length() > 1e-12) {
            poly.push(p);
        }
    }
    while poly.len() > 1 && (poly[0] - poly[poly.len() - 1]).length() <= 1e-12 {
        poly.pop();
    }
    let mut k = 0;
    while poly.len() >= 3 && k < poly.len() {
        let n = poly.len();
        let (a, b, c) = (poly[(k + n - 1) % n], poly[k], poly[(k + 1) % n]);
        let bend = (b - a).perp_dot(c - b);
        if bend.abs() <= 1e-14 * (b - a).length().max(1e-300) * (c - b).length().max(1e-300)
            && (b - a).dot(c - b) > 0.0
        {
            poly.remove(k);
            k = k.saturating_sub(1);
        } else {
            k += 1;
        }
    }
    poly
}

/// Two non-adjacent edges that touch or cross, if any (O(n²); outlines are bounded).
fn crossing_edges(poly: &[Vec2]) -> Option<(usize, usize)> {
    let n = poly.len();
    for i in 0..n {
        for j in i + 1..n {
            if j == i + 1 || (i == 0 && j == n - 1) {
                continue;
            }
            if segments_touch(poly[i], poly[(i + 1) % n], poly[j], poly[(j + 1) % n]) {
                return Some((i, j));
            }
        }
    }
    None
}

fn segments_touch(a: Vec2, b: Vec2, c: Vec2, d: Vec2) -> bool {
    let side = |p: Vec2, q: Vec2, r: Vec2| (q - p).perp_dot(r - p);
    let on = |p: Vec2, q: Vec2, r: Vec2| {
        r.x >= p.x.min(q.x) && r.x <= p.x.max(q.x) && r.y >= p.y.min(q.y) && r.y <= p.y.max(q.y)
    };
    let (d1, d2, d3, d4) = (side(c, d, a), side(c, d, b), side(a, b, c), side(a, b, d));
    if ((d1 > 0.0 && d2 < 0.0) || (d1 < 0.0 && d2 > 0.0))
        && ((d3 > 0.0 && d4 < 0.0) || (d3 < 0.0 && d4 > 0.0))
    {
        return true;
    }
    (d1 == 0.0 && on(c, d, a))
        || (d2 == 0.0 && on(c, d, b))
        || (d3 == 0.0 && on(a, b, c))
        || (d4 == 0.0 && on(a, b, d))
}

/// Triangles (vertex indices, counter-clockwise) of a simple counter-clockwise polygon.
fn ear_clip(poly: &[Vec2]) -> Vec<[usize; 3]> {
    let mut left: Vec<usize> = (0..poly.len()).collect();
    let mut out = Vec::with_capacity(poly.len().saturating_sub(2));
    while left.len() > 3 {
        let n = left.len();
        let ear = (0..n).find(|&k| {
            let (a, b, c) = (left[(k + n - 1) % n], left[k], left[(k + 1) % n]);
            let (pa, pb, pc) = (poly[a], poly[b], poly[c]);
            (pb - pa).perp_dot(pc - pb) > 0.0
                && left
                    .iter()
                    .filter(|&&v| v != a && v != b && v != c)
                    .all(|&v| !in_triangle(poly[v], pa, pb, pc))
        });
        // A simple polygon always has an ear; rounding can hide it on near-degenerate
        // input, where the flattest corner is cut instead.
        let k = ear.unwrap_or_else(|| flattest(poly, &left));
        out.push([left[(k + n - 1) % n], left[k], left[(k + 1) % n]]);
        left.remove(k);
    }
    out.push([left[0], left[1], left[2]]);
    out
}

fn flattest(poly: &[Vec2], left: &[usize]) -> usize {
    let n = left.len();
    let bend = |k: usize| {
        let (a, b, c) = (
            poly[left[(k + n - 1) % n]],
            poly[left[k]],
            poly[left[(k + 1) % n]],
        );
        (b - a).perp_dot(c - b)
    };
    (0..n)
        .max_by(|&i, &j| bend(i).total_cmp(&bend(j)))
        .unwrap_or(0)
}

fn in_triangle(p: Vec2, a: Vec2, b: Vec2, c: Vec2) -> bool {
    (b - a).perp_dot(p - a) >= 0.0
        && (c - b).perp_dot(p - b) >= 0.0
        && (a - c).perp_dot(p - c) >= 0.0
}

/// Hertel–Mehlhorn: pieces sharing an edge are joined while the union stays convex.
fn merged(poly: &[Vec2], triangles: Vec<[usize; 3]>) -> Vec<Vec<usize>> {
    let mut pieces: Vec<Vec<usize>> = triangles.into_iter().map(|t| t.to_vec()).collect();
    let mut joined = true;
    while joined {
        joined = false;
        'search: for i in 0..pieces.len() {
            for j in i + 1..pieces.len() {
                if let Some(union) = join(poly, &pieces[i], &pieces[j]) {
                    pieces[i] = union;
                    pieces.swap_remove(j);
                    joined = true;
                    break 'search;
                }
            }
        }
    }
    pieces
}

/// The union of two counter-clockwise pieces sharing an edge, if it is convex.
fn join(poly: &[Vec2], a: &[usize], b: &[usize]) -> Option<Vec<usize>> {
    let (na, nb) = (a.len(), b.len());
    for i in 0..na {
        let (u, v) = (a[i], a[(i + 1) % na]);
        let Some(j) = (0..nb).find(|&j| b[j] == v && b[(j + 1) % nb] == u) else {
            continue;
        };
        // a from v round to u, then b from u round to v, without repeating the edge.
        let mut union: Vec<usize> = (0..na).map(|k| a[(i + 1 + k) % na]).collect();
        union.extend((2..nb).map(|k| b[(j + k) % nb]));
        let m = union.len();
        let convex = (0..m).all(|k| {
            let (p, q, r) = (
                poly[union[k]],
                poly[union[(k + 1) % m]],
                poly[union[(k + 2) % m]],
            );
            (q - p).perp_dot(r - q) >= 0.0
        });
        return convex.then_some(union);
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn arch(notch_segments: usize) -> Vec<Vec2> {
        // 6 cm wide, 4 cm tall, a half-round notch of radius 1.5 cm from below.
        let mut p = vec![
            Vec2::new(0.03, 0.0),
            Vec2::new(0.03, 0.04),
            Vec2::new(-0.03, 0.04),
        ];
        p.push(Vec2::new(-0.03, 0.0));
        for k in 0..=notch_segments {
            let t = std::f64::consts::PI * (1.0 - k as f64 / notch_segments as f64);
            p.push(Vec2::new(0.015 * t.cos(), 0.015 * t.sin()));
        }
        p
    }

    fn total_area(pieces: &[Vec<Vec2>]) -> f64 {
        pieces.iter().map(|p| polygon_area(p)).sum()
    }

    fn is_convex_ccw(p: &[Vec2]) -> bool {
        let n = p.len();
        (0..n).all(|k| (p[(k + 1) % n] - p[k]).perp_dot(p[(k + 2) % n] - p[(k + 1) % n]) >= -1e-15)
    }

    #[test]
    fn an_arch_is_cut_into_few_convex_pieces_of_its_area() {
        let outline = arch(12);
        let pieces = convex_pieces(&outline).unwrap();
        assert!(pieces.iter().all(|p| is_convex_ccw(p)));
        assert!((total_area(&pieces) - polygon_area(&outline).abs()).abs() < 1e-12);
        // Each notch segment needs its own side; far fewer than the 16 triangles.
        assert!(pieces.len() <= 14, "{} pieces", pieces.len());
    }

    #[test]
    fn a_convex_outline_is_one_piece_either_way_round() {
        let square = [Vec2::ZERO, Vec2::X, Vec2::ONE, Vec2::Y];
        assert_eq!(convex_pieces(&square).unwrap().len(), 1);
        let mut cw = square.to_vec();
        cw.reverse();
        assert_eq!(convex_pieces(&cw).unwrap().len(), 1);
    }

    #[test]
    fn bad_outlines_are_refused() {
        assert_eq!(
            convex_pieces(&[Vec2::ZERO, Vec2::X]),
            Err(PolygonError::TooFew(2))
        );
        let line = [Vec2::ZERO, Vec2::X, Vec2::new(2.0, 0.0)];
        assert!(convex_pieces(&line).is_err());
        let bow = [
            Vec2::ZERO,
            Vec2::new(2.0, 2.0),
            Vec2::new(2.0, 0.0),
            Vec2::Y,
        ];
        assert!(matches!(
            convex_pieces(&bow),
            Err(PolygonError::SelfIntersecting(..))
        ));
        assert_eq!(
            convex_pieces(&[Vec2::ZERO, Vec2::X, Vec2::new(f64::NAN, 1.0)]),
            Err(PolygonError::NotFinite(2))
        );
    }

    proptest! {
        /// Star-shaped outlines (random radii round the origin) of any size: convex
        /// pieces whose areas add up to the outline's.
        #[test]
        fn star_outlines_keep_their_area(
            radii in proptest::collection::vec(0.2f64..1.0, 3..40),
            scale in prop_oneof![Just(1e-3), Just(1.0), Just(1e3)],
        ) {
            let n = radii.len();
            let outline: Vec<Vec2> = radii.iter().enumerate().map(|(k, r)| {
                let t = std::f64::consts::TAU * k as f64 / n as f64;
                Vec2::new(t.cos(), t.sin()) * r * scale
            }).collect();
            let pieces = convex_pieces(&outline).unwrap();
            prop_assert!(pieces.iter().all(|p| is_convex_ccw(p)));
            let want = polygon_area(&outline);
            prop_assert!((total_area(&pieces) - want).abs() <= 1e-9 * want);
        }
    }
}
