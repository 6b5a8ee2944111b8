//! One object seen in pieces: a box behind a nearer one shows on both sides of it, and
//! the pieces are one object when the geometry says so — they lie on one plane, and
//! everything between them on the sensor's grid is nearer the sensor (the occluder),
//! so nothing in view separates them.

use super::joins;
use crate::filters::{scatter, smallest_eigenvector};
use crate::plane::Plane;
use crate::surfaces::plane_basis;
use std::f64::consts::FRAC_PI_2;
use tabula_geom::polygon::{convex_hull_2d, min_area_rectangle_of_hull, polygon_area};
use tabula_geom::{Vec2, Vec3};

/// Pieces' faces within this angle (rad) of each other …
const MAX_NORMAL_ANGLE: f64 = 0.26;
/// … and within this distance (m) of each other's plane are one face.
const MAX_PLANE_OFFSET: f64 = 0.015;
/// The occluder is nearer the sensor than the line between the pieces by this (m).
const MIN_OCCLUDER_DEPTH: f64 = 0.01;
/// A box's piece fills this share of its footprint's minimal rectangle (a disc 79 %).
const MIN_BOX_FILL: f64 = 0.88;
/// Pieces of one box have footprint rectangles this parallel (rad).
const MAX_YAW_DIFFERENCE: f64 = 0.14;
/// Pieces of one object reach the same height above the table, within this (m).
const MAX_TOP_DIFFERENCE: f64 = 0.015;
/// Pieces farther apart than this (m) are not joined: the widest object on a table.
const MAX_GAP: f64 = 0.3;

/// A piece's plane and where it is on the grid.
struct Piece {
    centroid: Vec3,
    /// The piece's plane when it is flat (one face of a box); `None` when it shows
    /// more than one face or a curved side.
    normal: Option<Vec3>,
    /// Highest point above the table (m).
    top: f64,
    /// The footprint's minimal-area rectangle's side direction (rad, modulo 90°) when
    /// the footprint fills it (a box's pieces), else `None`.
    box_yaw: Option<f64>,
    /// Mean pixel (column, row).
    pixel: (f64, f64),
}

/// `regions` with the pieces of one occluded object joined (organized frames only:
/// `width` is the grid's, `eye` the sensor's position).
pub(super) fn join_occluded(
    pts: &[Vec3],
    width: usize,
    eye: Vec3,
    table: &Plane,
    regions: Vec<Vec<usize>>,
) -> Vec<Vec<usize>> {
    if width == 0 || regions.len() < 2 || regions.len() > 512 {
        return regions;
    }
    let label = joins::labels(pts.len(), &regions);
    let pieces: Vec<Option<Piece>> = regions
        .iter()
        .map(|m| piece(pts, width, table, m))
        .collect();
    let grid = Grid {
        pts,
        width,
        eye,
        label: &label,
    };
    let mut pairs = Vec::new();
    for a in 0..regions.len() {
        for b in a + 1..regions.len() {
            let (Some(pa), Some(pb)) = (&pieces[a], &pieces[b]) else {
                continue;
            };
            if alike(pa, pb) && grid.hidden_between((a, &regions[a]), (b, &regions[b]), pb) {
                pairs.push((a, b));
            }
        }
    }
    joins::merge(regions, &pairs)
}

fn piece(pts: &[Vec3], width: usize, table: &Plane, members: &[usize]) -> Option<Piece> {
    let (centroid, m) = scatter(members.iter().map(|&i| pts[i]))?;
    let (normal, [flat, _, _]) = smallest_eigenvector(m)?;
    let spread = m[0] + m[3] + m[5];
    let normal = (flat <= 0.02 * spread).then_some(normal);
    let top = members
        .iter()
        .map(|&i| table.distance(pts[i]))
        .fold(f64::NEG_INFINITY, f64::max);
    let (u, v) = plane_basis(table.normal);
    let flat: Vec<Vec2> = members
        .iter()
        .map(|&i| Vec2::new(pts[i].dot(u), pts[i].dot(v)))
        .collect();
    let hull: Vec<Vec2> = convex_hull_2d(&flat).into_iter().map(|k| flat[k]).collect();
    let box_yaw = min_area_rectangle_of_hull(&hull)
        .filter(|r| polygon_area(&hull).abs() >= MIN_BOX_FILL * r.size.x * r.size.y)
        .map(|r| r.axis.y.atan2(r.axis.x).rem_euclid(FRAC_PI_2));
    let n = members.len() as f64;
    let (sx, sy) = members.iter().fold((0.0, 0.0), |(x, y), &i| {
        (x + (i % width) as f64, y + (i / width) as f64)
    });
    Some(Piece {
        centroid,
        normal,
        top,
        box_yaw,
        pixel: (sx / n, sy / n),
    })
}

/// Whether two pieces can be one object: as tall as each other, and one flat face on
/// one plane or pieces of one box's outline.
fn alike(a: &Piece, b: &Piece) -> bool {
    let apart = b.centroid - a.centroid;
    let coplanar = match (a.normal, b.normal) {
        (Some(na), Some(nb)) => {
            na.dot(nb).abs() >= MAX_NORMAL_ANGLE.cos()
                && na.dot(apart).abs() <= MAX_PLANE_OFFSET
                && nb.dot(apart).abs() <= MAX_PLANE_OFFSET
        }
        // Pieces showing more than one face: pieces of one box, the same box's
        // outline — each fills its footprint's rectangle, and the rectangles are
        // parallel (two boxes of one height behind one book rarely are).
        _ => match (a.box_yaw, b.box_yaw) {
            (Some(ya), Some(yb)) => {
                let d = (ya - yb).abs();
                d.min(FRAC_PI_2 - d) <= MAX_YAW_DIFFERENCE
            }
            _ => false,
        },
    };
    coplanar && (a.top - b.top).abs() <= MAX_TOP_DIFFERENCE && apart.length() <= 1.5 * MAX_GAP
}

struct Grid<'a> {
    pts: &'a [Vec3],
    width: usize,
    eye: Vec3,
    label: &'a [u32],
}

impl Grid<'_> {
    /// Whether the pixels between the nearest points of two pieces are all nearer the
    /// sensor than the line joining them: a gap of table, background or missing depth
    /// between them means two objects.
    fn hidden_between(
        &self,
        (a, ma): (usize, &[usize]),
        (b, mb): (usize, &[usize]),
        pb: &Piece,
    ) -> bool {
        let px = |i: usize| ((i % self.width) as f64, (i / self.width) as f64);
        let d2 = |i: usize, (x, y): (f64, f64)| {
            let (u, v) = px(i);
            (u - x).powi(2) + (v - y).powi(2)
        };
        let Some(&ia) = ma
            .iter()
            .min_by(|&&i, &&j| d2(i, pb.pixel).total_cmp(&d2(j, pb.pixel)))
        else {
            return false;
        };
        let Some(&ib) = mb
            .iter()
            .min_by(|&&i, &&j| d2(i, px(ia)).total_cmp(&d2(j, px(ia))))
        else {
            return false;
        };
        let (qa, qb) = (self.pts[ia], self.pts[ib]);
        if qa.distance(qb) > MAX_GAP {
            return false;
        }
        let ((xa, ya), (xb, yb)) = (px(ia), px(ib));
        let steps = (xb - xa).abs().max((yb - ya).abs()).round() as usize;
        let (ra, rb) = (qa.distance(self.eye), qb.distance(self.eye));
        let (mut nearer, mut shadow) = (0, 0);
        for k in 1..steps {
            let t = k as f64 / steps as f64;
            let (x, y) = ((xa + t * (xb - xa)).round(), (ya + t * (yb - ya)).round());
            let i = y as usize * self.width + x as usize;
            let l = self.label[i];
            if l == a as u32 || l == b as u32 {
                continue;
            }
            let q = self.pts[i];
            if !q.is_finite() {
                // The occluder's shadow: a structured-light sensor sees no depth beside
                // a nearer edge.
                shadow += 1;
                continue;
            }
            // Anything not nearer than the pieces (the table between two objects).
            if q.distance(self.eye) > ra + t * (rb - ra) - MIN_OCCLUDER_DEPTH {
                return false;
            }
            nearer += 1;
        }
        nearer > 0 && nearer >= shadow
    }
}
