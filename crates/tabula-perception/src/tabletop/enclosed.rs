//! Concave parts in one piece. A mug handle's inner face, the hollow of a bottle's
//! grip, a notch: each is concave against the faces around it, so the crease test cuts
//! it off as a piece of its own. Such a piece lies inside the convex hull of the piece
//! around it; two separate objects do not (on the 110 labelled mOSD frames no object
//! has more than half its points inside another's hull).

use super::joins;
use tabula_geom::Vec3;
use tabula_geom::hull_input::{outermost_per_cell, sort_points};

/// A piece is enclosed when this share of its points …
const ENCLOSED_SHARE: f64 = 0.9;
/// … lies within the other piece's hull grown by this (m): the sensor's noise.
const SLACK: f64 = 0.005;
/// The hull is taken of the enclosing piece's outermost point in each cell of a grid
/// this many cells across its box's diagonal (the cell is added to the slack, so the
/// test is against the full hull; a 20 cm piece: 5 mm cells).
const HULL_CELLS: f64 = 40.0;

/// Rounds of joins: a piece may touch the one around it only through another piece
/// that a round joins to it (a handle in three pieces).
const MAX_ROUNDS: usize = 4;

/// `regions` with every piece of at least `min_points` that lies inside the hull of a
/// bigger piece touching it on the grid joined to that piece (organized frames only:
/// `width` is the grid's). Smaller pieces are not objects anyway.
pub(super) fn join_enclosed(
    pts: &[Vec3],
    width: usize,
    mut regions: Vec<Vec<usize>>,
    min_points: usize,
) -> Vec<Vec<usize>> {
    if width == 0 || regions.len() > 512 {
        return regions;
    }
    for _ in 0..MAX_ROUNDS {
        let before = regions.len();
        regions = join_round(pts, width, regions, min_points);
        if regions.len() == before {
            break;
        }
    }
    regions
}

/// One round of [`join_enclosed`]'s joins, each judged on the pieces as they were.
fn join_round(
    pts: &[Vec3],
    width: usize,
    regions: Vec<Vec<usize>>,
    min_points: usize,
) -> Vec<Vec<usize>> {
    if regions.len() < 2 {
        return regions;
    }
    let boxes: Vec<(Vec3, Vec3)> = regions.iter().map(|m| bounds(pts, m)).collect();
    let grown = Vec3::splat(SLACK);
    let boxed_in = |small: usize, big: usize| {
        let ((lo, hi), (glo, ghi)) = (boxes[small], boxes[big]);
        lo.cmpge(glo - grown).all() && hi.cmple(ghi + grown).all()
    };
    let mut label = None;
    let mut hulls: Vec<Option<Option<Hull>>> = vec![None; regions.len()];
    let mut pairs = Vec::new();
    for small in (0..regions.len()).filter(|&k| regions[k].len() >= min_points) {
        // The biggest enclosing piece, so a piece is joined once.
        let mut bigger: Vec<usize> = (0..regions.len())
            .filter(|&big| regions[big].len() > regions[small].len() && boxed_in(small, big))
            .collect();
        bigger.sort_by_key(|&big| std::cmp::Reverse(regions[big].len()));
        for big in bigger {
            let label = label.get_or_insert_with(|| joins::labels(pts.len(), &regions));
            if !joins::touches(label, width, &regions[small], big as u32) {
                continue;
            }
            let hull = hulls[big].get_or_insert_with(|| Hull::of(pts, &regions[big]));
            if hull.as_ref().is_some_and(|h| h.holds(pts, &regions[small])) {
                pairs.push((small, big));
                break;
            }
        }
    }
    joins::merge(regions, &pairs)
}

fn bounds(pts: &[Vec3], members: &[usize]) -> (Vec3, Vec3) {
    tabula_geom::bounds(members.iter().map(|&i| &pts[i]))
}

/// A convex hull as its faces' outward planes (unit normal, offset) and how far out
/// a point may lie and still count as inside.
#[derive(Clone)]
struct Hull {
    faces: Vec<(Vec3, f64)>,
    slack: f64,
}

impl Hull {
    fn of(pts: &[Vec3], members: &[usize]) -> Option<Hull> {
        let (input, cell) = outermost(pts, members);
        let (vertices, triangles) =
            tabula_geom::parry::transformation::try_convex_hull(&input).ok()?;
        if triangles.len() < 4 {
            return None;
        }
        let centre = vertices.iter().copied().sum::<Vec3>() / vertices.len() as f64;
        let faces = triangles
            .iter()
            .filter_map(|t| {
                let [a, b, c] = t.map(|k| vertices[k as usize]);
                let n = (b - a).cross(c - a).try_normalize()?;
                let n = if n.dot(centre - a) > 0.0 { -n } else { n };
                Some((n, n.dot(a)))
            })
            .collect();
        Some(Hull {
            faces,
            slack: SLACK + cell * 3f64.sqrt(),
        })
    }

    /// Whether [`ENCLOSED_SHARE`] of `members` lie inside.
    fn holds(&self, pts: &[Vec3], members: &[usize]) -> bool {
        let allowed = ((1.0 - ENCLOSED_SHARE) * members.len() as f64).floor() as usize;
        let mut outside = 0;
        for &i in members {
            if self
                .faces
                .iter()
                .any(|(n, d)| n.dot(pts[i]) - d > self.slack)
            {
                outside += 1;
                if outside > allowed {
                    return false;
                }
            }
        }
        true
    }
}

/// The outermost point of `members` in each cell of a grid [`HULL_CELLS`] across their
/// box (a hull loses less than a cell's diagonal), and the cell.
fn outermost(pts: &[Vec3], members: &[usize]) -> (Vec<Vec3>, f64) {
    let (lo, hi) = bounds(pts, members);
    let cell = ((hi - lo).length() / HULL_CELLS).max(1e-6);
    let mut kept = outermost_per_cell(members.iter().map(|&i| &pts[i]), (lo + hi) / 2.0, cell);
    sort_points(&mut kept);
    (kept, cell)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 6 × 6 grid of points on a bowl-shaped patch (the enclosing piece) and a patch
    /// of 2 × 2 lying in its hollow or floating above it.
    fn scene(inner_height: f64) -> (Vec<Vec3>, Vec<Vec<usize>>) {
        let width = 6;
        let mut pts = Vec::new();
        let mut outer = Vec::new();
        let mut inner = Vec::new();
        for y in 0..6 {
            for x in 0..width {
                let (fx, fy) = (x as f64 * 0.01, y as f64 * 0.01);
                let centre = (2..4).contains(&x) && (2..4).contains(&y);
                let bowl = (fx - 0.025).powi(2) + (fy - 0.025).powi(2);
                let z = if centre { inner_height } else { 10.0 * bowl };
                (if centre { &mut inner } else { &mut outer }).push(pts.len());
                pts.push(Vec3::new(fx, fy, z));
            }
        }
        (pts, vec![outer, inner])
    }

    #[test]
    fn a_piece_in_the_hollow_joins_and_one_above_does_not() {
        let (pts, regions) = scene(0.003);
        assert_eq!(join_enclosed(&pts, 6, regions, 1).len(), 1);
        let (pts, regions) = scene(0.05);
        assert_eq!(join_enclosed(&pts, 6, regions, 1).len(), 2);
    }
}
