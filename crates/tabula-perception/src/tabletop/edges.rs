//! Where an organized frame ends: the image's border, which cuts objects (only part of
//! each is in view), and the edge of the valid depth, below which what an object
//! stands on may be out of view.

use super::TableObject;
use tabula_geom::{PointCloud, Vec3, voxel_key};

/// Pixels within this many of an edge are on it.
const MARGIN: usize = 2;
/// A band of empty lines along a side of the image is the sensor's margin (a Kinect's
/// depth registered to its colour camera loses ~8 columns on one side and a few ragged
/// rows) when it is at most this share of the image; a wider one is the scene's (out
/// of range, or cropped away, as mOSD's test frames are), and does not cut what
/// borders it.
const MAX_BAND: f64 = 0.05;
/// A line with fewer finite pixels than this share is part of the margin (a Kinect's
/// last rows thin out over a few lines rather than ending).
const EMPTY_LINE: f64 = 0.25;

/// The image's border, moved in past the sensor's margin of missing depth: an object
/// is partly out of view only where it reaches this (issue 33: bordering pixels
/// without depth does not cut an object).
pub(super) struct ImageBorder {
    width: usize,
    height: usize,
    /// First and last column, first and last row of the image proper.
    cols: (usize, usize),
    rows: (usize, usize),
}

impl ImageBorder {
    pub(super) fn of(cloud: &PointCloud) -> Self {
        let (w, h) = (cloud.width, cloud.height);
        let finite = |x: usize, y: usize| cloud.points[y * w + x].is_finite();
        let empty_col =
            |x: usize| ((0..h).filter(|&y| finite(x, y)).count() as f64) < EMPTY_LINE * h as f64;
        let empty_row =
            |y: usize| ((0..w).filter(|&x| finite(x, y)).count() as f64) < EMPTY_LINE * w as f64;
        // The band along one side: its empty lines, counted inwards, when narrow.
        let band =
            |lines: &mut dyn Iterator<Item = usize>, empty: &dyn Fn(usize) -> bool, n: usize| {
                let run = lines.take_while(|&k| empty(k)).count();
                if (run as f64) <= MAX_BAND * n as f64 {
                    run
                } else {
                    0
                }
            };
        let left = band(&mut (0..w), &empty_col, w);
        let right = band(&mut (0..w).rev(), &empty_col, w);
        let top = band(&mut (0..h), &empty_row, h);
        let bottom = band(&mut (0..h).rev(), &empty_row, h);
        Self {
            width: w,
            height: h,
            cols: (left, w.saturating_sub(1 + right)),
            rows: (top, h.saturating_sub(1 + bottom)),
        }
    }

    /// Whether pixel `i` is on the border.
    pub(super) fn near(&self, i: usize) -> bool {
        let (x, y) = (i % self.width.max(1), i / self.width.max(1));
        y >= self.height
            || x <= self.cols.0 + MARGIN
            || x + MARGIN >= self.cols.1
            || y <= self.rows.0 + MARGIN
            || y + MARGIN >= self.rows.1
    }
}

/// Where an organized frame's valid data ends, row by row and column by column: a
/// region whose lowest points reach it may stand on something out of view.
pub(super) struct DataEdge {
    width: usize,
    /// First and last finite column of each row, first and last finite row of each
    /// column.
    rows: Vec<(usize, usize)>,
    cols: Vec<(usize, usize)>,
}

impl DataEdge {
    pub(super) fn of(cloud: &PointCloud) -> Self {
        let (w, h) = (cloud.width, cloud.height);
        let finite = |x: usize, y: usize| cloud.points[y * w + x].is_finite();
        let span = |n: usize, ok: &dyn Fn(usize) -> bool| {
            let first = (0..n).find(|&k| ok(k));
            let last = (0..n).rev().find(|&k| ok(k));
            first.zip(last).unwrap_or((usize::MAX, 0))
        };
        Self {
            width: w,
            rows: (0..h).map(|y| span(w, &|x| finite(x, y))).collect(),
            cols: (0..w).map(|x| span(h, &|y| finite(x, y))).collect(),
        }
    }

    pub(super) fn near(&self, i: usize) -> bool {
        let (x, y) = (i % self.width, i / self.width);
        let (l, r) = self.rows[y];
        let (t, b) = self.cols[x];
        x <= l + MARGIN || x + MARGIN >= r || y <= t + MARGIN || y + MARGIN >= b
    }
}

/// Pieces within `gap` (m) of an object cut by the frame's edge and far smaller than it
/// (`FRAGMENT` times fewer points) are more of what the frame cut (the wheels of a
/// chair whose base runs out of view), and are set apart too. Whole objects touching
/// a cut one are not (on a crowded table everything touches something), nor are
/// pieces near a piece that was set apart (it would cascade across the table).
pub(super) fn set_apart_pieces_of_partial(
    pts: &[Vec3],
    objects: &mut Vec<TableObject>,
    partial: &mut Vec<TableObject>,
    gap: f64,
) {
    if gap <= 0.0 || !gap.is_finite() {
        return;
    }
    const FRAGMENT: usize = 4;
    // Each cut object's voxels, with its size.
    let cut: Vec<(rustc_hash::FxHashSet<[i64; 3]>, usize)> = partial
        .iter()
        .map(|o| {
            let voxels = o.indices.iter().map(|&i| voxel_key(pts[i], gap));
            (voxels.collect(), o.indices.len())
        })
        .collect();
    let fragment_of_cut = |o: &TableObject| {
        let own: rustc_hash::FxHashSet<[i64; 3]> =
            o.indices.iter().map(|&i| voxel_key(pts[i], gap)).collect();
        cut.iter().any(|(voxels, size)| {
            o.indices.len() * FRAGMENT <= *size
                && own.iter().any(|k| {
                    (-1..=1).any(|dx| {
                        (-1..=1).any(|dy| {
                            (-1..=1).any(|dz| voxels.contains(&[k[0] + dx, k[1] + dy, k[2] + dz]))
                        })
                    })
                })
        })
    };
    let (fragments, whole): (Vec<TableObject>, Vec<TableObject>) = std::mem::take(objects)
        .into_iter()
        .partition(fragment_of_cut);
    *objects = whole;
    partial.extend(fragments);
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 64 × 48 frame with depth everywhere but `missing` pixels.
    fn frame(missing: impl Fn(usize, usize) -> bool) -> PointCloud {
        let points = (0..48)
            .flat_map(|y| (0..64).map(move |x| (x, y)))
            .map(|(x, y)| {
                if missing(x, y) {
                    Vec3::NAN
                } else {
                    Vec3::new(x as f64, y as f64, 1.0)
                }
            })
            .collect();
        PointCloud::organized(64, 48, points).unwrap()
    }

    #[test]
    fn a_narrow_band_without_depth_is_the_sensor_s_margin_a_wide_one_the_scene_s() {
        let at = |x: usize, y: usize| y * 64 + x;
        // A Kinect-like band: 3 empty columns on the left, the last row ragged.
        let kinect = ImageBorder::of(&frame(|x, y| x < 3 || (y == 47 && x % 8 != 0)));
        assert!(kinect.near(at(5, 20)), "inside the band's edge");
        assert!(!kinect.near(at(6, 20)));
        assert!(kinect.near(at(30, 44)), "above the ragged row");
        assert!(!kinect.near(at(30, 43)));
        // The top 20 rows cropped away (a table's far edge, nothing beyond): an object
        // bordering them is not cut, one at the image's real border is.
        let cropped = ImageBorder::of(&frame(|_, y| y < 20));
        assert!(!cropped.near(at(30, 20)));
        assert!(cropped.near(at(30, 46)));
        assert!(cropped.near(at(62, 30)));
    }
}
