//! Parts that stand on their own body. A bottle's cap stands on its shoulder, a
//! carton's gable fin on its roof: each is cut off by the crease where it meets the
//! body, and rests on it as a box rests on a box. What tells them apart is the surface
//! under the piece: a stacked object stands on a level top, a part rises out of a
//! sloping one. So a small piece high on a bigger one whose surface along their seam
//! slopes is that piece's part.

use super::joins;
use crate::plane::Plane;
use crate::segment::Locals;
use tabula_geom::{Vec2, Vec3};

/// A part is at most this share of its body's points (a cap or fin is a tenth of its
/// bottle or carton; objects piled on each other are mostly of one size, and a small
/// box on a big one is told apart by its level seam).
const MAX_PART_SHARE: f64 = 0.25;
/// The part's footprint lies within the body's, grown by this (m): the sensor's noise.
const FOOTPRINT_SLACK: f64 = 0.01;
/// A seam point is level when its normal is within this of the table's up (rad) …
const LEVEL_TILT: f64 = 0.35;
/// … and sloping up to this; steeper points are the body's side, no evidence either way.
const SIDE_TILT: f64 = 1.22;
/// A part's seam has this many sloping points for each level one, at least: a box on
/// a box's top near its edge sees some of the edge's blurred normals as sloping (a box
/// on a box in mOSD's complex scenes: 1–2.3 sloping to each level one; the milk frame's
/// caps and fin: 16 or more).
const SLOPING_TO_LEVEL: usize = 4;

/// A region's extent: lowest and highest above the table, footprint box (in the
/// table's [`plane_basis`](crate::surfaces::plane_basis)).
pub(super) struct Extent {
    pub(super) lowest: f64,
    pub(super) highest: f64,
    pub(super) lo: Vec2,
    pub(super) hi: Vec2,
}

impl Extent {
    pub(super) fn of(pts: &[Vec3], plane: &Plane, members: &[usize]) -> Extent {
        let (u, v) = crate::surfaces::plane_basis(plane.normal);
        let mut e = Extent {
            lowest: f64::INFINITY,
            highest: f64::NEG_INFINITY,
            lo: Vec2::splat(f64::INFINITY),
            hi: Vec2::splat(f64::NEG_INFINITY),
        };
        for &i in members {
            let h = plane.distance(pts[i]);
            let q = Vec2::new(pts[i].dot(u), pts[i].dot(v));
            e.lowest = e.lowest.min(h);
            e.highest = e.highest.max(h);
            e.lo = e.lo.min(q);
            e.hi = e.hi.max(q);
        }
        e
    }

    /// Whether `self` could be a part of `body`: within its footprint, in its upper half.
    fn on_top_of(&self, body: &Extent) -> bool {
        let slack = Vec2::splat(FOOTPRINT_SLACK);
        self.lo.cmpge(body.lo - slack).all()
            && self.hi.cmple(body.hi + slack).all()
            && self.lowest >= 0.5 * (body.lowest + body.highest)
    }
}

/// The body's seam points along `part` (pixels where they touch, [`joins::pixels_near`])
/// on a grid `width` wide, counted as level and sloping by their local normals.
fn seam_slopes(
    label: &[u32],
    width: usize,
    (locals, plane): (&Locals, &Plane),
    part: &[usize],
    body: u32,
) -> (usize, usize) {
    let (cos_level, cos_side) = (LEVEL_TILT.cos(), SIDE_TILT.cos());
    let mut seen = rustc_hash::FxHashSet::default();
    let (mut level, mut sloping) = (0, 0);
    for j in joins::pixels_near(label, width, part, body) {
        if !seen.insert(j) {
            continue;
        }
        // A point without a normal (NaN) is neither.
        let upright = locals.get(j).0.dot(plane.normal).abs();
        if upright >= cos_level {
            level += 1;
        } else if upright >= cos_side {
            sloping += 1;
        }
    }
    (level, sloping)
}

/// `regions` (on a grid `width` wide) with every part joined to its body.
pub(super) fn join_parts(
    pts: &[Vec3],
    width: usize,
    (locals, plane): (&Locals, &Plane),
    regions: Vec<Vec<usize>>,
) -> Vec<Vec<usize>> {
    if width == 0 || regions.len() < 2 || regions.len() > 512 {
        return regions;
    }
    let extents: Vec<Extent> = regions.iter().map(|r| Extent::of(pts, plane, r)).collect();
    let label = joins::labels(pts.len(), &regions);
    let mut pairs = Vec::new();
    for part in 0..regions.len() {
        let mut bodies: Vec<usize> = (0..regions.len())
            .filter(|&body| {
                part != body
                    && regions[part].len() as f64 <= MAX_PART_SHARE * regions[body].len() as f64
                    && extents[part].on_top_of(&extents[body])
            })
            .collect();
        bodies.sort_by_key(|&body| std::cmp::Reverse(regions[body].len()));
        for body in bodies {
            let (level, sloping) =
                seam_slopes(&label, width, (locals, plane), &regions[part], body as u32);
            if sloping > SLOPING_TO_LEVEL * level {
                pairs.push((part, body));
                break;
            }
        }
    }
    joins::merge(regions, &pairs)
}

#[cfg(test)]
mod tests {
    use super::*;

    const WIDTH: usize = 20;

    /// A body on grid rows 5–19 falling from 20 cm high to 2 cm, its surface's normals
    /// tilted `tilt` from up, and a piece on rows 0–4, columns 5–14, standing on its
    /// top (1–3 cm above it, within its footprint).
    fn scene(tilt: f64) -> (Vec<Vec3>, Locals, Vec<Vec<usize>>) {
        let (mut pts, mut planes) = (Vec::new(), Vec::new());
        let (mut body, mut part) = (Vec::new(), Vec::new());
        for row in 0..20 {
            for col in 0..WIDTH {
                let i = row * WIDTH + col;
                let (x, y) = (col as f64 * 0.01, row as f64 * 0.01);
                if row >= 5 {
                    pts.push(Vec3::new(x, y, 0.2 - (row - 5) as f64 * 0.013));
                    planes.push((Vec3::new(0.0, tilt.sin(), tilt.cos()), Vec3::ZERO));
                    body.push(i);
                } else if (5..15).contains(&col) {
                    pts.push(Vec3::new(x, 0.1 + y * 0.5, 0.21 + y * 0.5));
                    planes.push((Vec3::X, Vec3::ZERO));
                    part.push(i);
                } else {
                    pts.push(Vec3::NAN);
                    planes.push((Vec3::NAN, Vec3::NAN));
                }
            }
        }
        let slot = (0..pts.len() as u32).collect();
        (pts, Locals { planes, slot }, vec![body, part])
    }

    fn joined(tilt: f64) -> usize {
        let (pts, locals, regions) = scene(tilt);
        let table = Plane {
            normal: Vec3::Z,
            d: 0.0,
        };
        join_parts(&pts, WIDTH, (&locals, &table), regions).len()
    }

    #[test]
    fn a_piece_on_a_sloping_shoulder_joins_and_one_on_a_level_top_does_not() {
        assert_eq!(joined(40f64.to_radians()), 1, "a cap on a shoulder");
        assert_eq!(joined(5f64.to_radians()), 2, "a box on a box");
        assert_eq!(
            joined(85f64.to_radians()),
            2,
            "beside the body's wall: no evidence"
        );
    }

    /// A box near the edge of a box's top: the edge's blurred normals slope, the top's
    /// are level; three sloping points to each level one are not a shoulder.
    #[test]
    fn a_seam_of_level_and_blurred_edge_points_is_a_stack() {
        let (pts, mut locals, regions) = scene(5f64.to_radians());
        let blurred = Vec3::new(0.0, 40f64.to_radians().sin(), 40f64.to_radians().cos());
        for &i in regions[0].iter().filter(|&&i| i % 4 != 0) {
            locals.planes[i].0 = blurred;
        }
        let table = Plane {
            normal: Vec3::Z,
            d: 0.0,
        };
        assert_eq!(join_parts(&pts, WIDTH, (&locals, &table), regions).len(), 2);
    }

    #[test]
    fn a_piece_as_big_as_the_one_under_it_is_an_object_of_its_own() {
        let (pts, locals, mut regions) = scene(40f64.to_radians());
        // The body cut to the piece's size: a stacked object of a pile, not a part.
        let piece = regions[1].len();
        regions[0].truncate(3 * piece);
        let table = Plane {
            normal: Vec3::Z,
            d: 0.0,
        };
        assert_eq!(join_parts(&pts, WIDTH, (&locals, &table), regions).len(), 2);
    }
}
