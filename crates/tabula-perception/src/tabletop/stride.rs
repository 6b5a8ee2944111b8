//! Organized frames segmented on a coarser grid, every pixel labelled after.
//!
//! A Kinect-class sensor's 640×480 depth image is denser than its depth is sharp: the
//! disparity comes from correlation windows several pixels wide, and every stage of
//! the pipeline judges gaps, creases and tops over centimetres, which are 5–20 pixels
//! at a table's range. So the pipeline runs on every `frame_stride`-th pixel of every
//! `frame_stride`-th row (¼ of the work at 2) and each pixel then takes the segment of
//! the nearest of the four samples around it — when that sample is within the
//! clustering's reach of it, as two neighbouring samples would have to be; otherwise
//! (a flying pixel at a silhouette) it is nobody's. Objects, partial objects and the
//! table come out with indices into the full frame; their shapes (boxes, hulls, tops)
//! are the samples', which are points of the frame.

use super::{Tabletop, TabletopParams};
use tabula_geom::{PointCloud, Vec3};

/// What a sample was: nothing, the table, or object `k` (whole ones first, then the
/// partial ones).
#[derive(Clone, Copy, PartialEq)]
enum Owner {
    Nobody,
    Table,
    Object(u32),
}

/// The frame's pixels at `stride` (as [`PointCloud::decimated`]), with
/// `coarse_result` — the pipeline's answer on them — carried to every pixel of `full`.
/// `keep` is the samples' outlier mask.
pub(super) fn expand(
    full: &PointCloud,
    stride: usize,
    mut coarse_result: Tabletop,
    keep: &[bool],
    eye: Vec3,
    p: &TabletopParams,
) -> Tabletop {
    let grid = Samples::of(full, stride);
    let owners = sample_owners(&coarse_result, grid.width * grid.height);
    let n_objects = coarse_result.objects.len() + coarse_result.partial.len();
    let mut members: Vec<Vec<usize>> = vec![Vec::new(); n_objects];
    let mut table = Vec::new();
    let mut kept = 0;
    for y in 0..full.height {
        let rows = grid.around(y);
        for x in 0..full.width {
            let i = y * full.width + x;
            let q = full.points[i];
            if !q.is_finite() {
                continue;
            }
            let reach = p.cluster_tolerance + p.cluster_range_gain * q.distance_squared(eye);
            let owned = |k: usize| owners[k] != Owner::Nobody;
            let Some(k) = grid.nearest(q, (rows, grid.around(x)), reach * reach, owned) else {
                continue;
            };
            kept += usize::from(keep[k]);
            match owners[k] {
                Owner::Nobody => {}
                Owner::Table => table.push(i),
                Owner::Object(j) => members[j as usize].push(i),
            }
        }
    }
    coarse_result.table.inliers = table;
    for (o, m) in coarse_result
        .objects
        .iter_mut()
        .chain(coarse_result.partial.iter_mut())
        .zip(members)
    {
        o.indices = m;
    }
    coarse_result.kept = kept;
    coarse_result
}

/// Each sample's owner in the coarse result.
fn sample_owners(t: &Tabletop, n: usize) -> Vec<Owner> {
    let mut owners = vec![Owner::Nobody; n];
    for &i in &t.table.inliers {
        if let Some(o) = owners.get_mut(i) {
            *o = Owner::Table;
        }
    }
    for (k, o) in t.objects.iter().chain(&t.partial).enumerate() {
        for &i in &o.indices {
            if let Some(slot) = owners.get_mut(i) {
                *slot = Owner::Object(k as u32);
            }
        }
    }
    owners
}

/// The samples' grid: every `stride`-th pixel of every `stride`-th row of `full`.
struct Samples<'a> {
    full: &'a PointCloud,
    stride: usize,
    width: usize,
    height: usize,
}

impl<'a> Samples<'a> {
    fn of(full: &'a PointCloud, stride: usize) -> Self {
        Self {
            full,
            stride,
            width: full.width.div_ceil(stride),
            height: full.height.div_ceil(stride),
        }
    }

    /// The sample rows (or columns) either side of full row (column) `at`: its own
    /// alone when it is a sample's.
    fn around(&self, at: usize) -> (usize, usize) {
        let before = at / self.stride;
        (
            before,
            if at.is_multiple_of(self.stride) {
                before
            } else {
                before + 1
            },
        )
    }

    /// The sample (coarse index) nearest to `q` among `rows` × `cols` that `counts`,
    /// if within `reach2` (squared) of it.
    fn nearest(
        &self,
        q: Vec3,
        ((r0, r1), (c0, c1)): ((usize, usize), (usize, usize)),
        reach2: f64,
        counts: impl Fn(usize) -> bool,
    ) -> Option<usize> {
        let r1 = if r1 < self.height { r1 } else { r0 };
        let c1 = if c1 < self.width { c1 } else { c0 };
        let mut best = (reach2, usize::MAX);
        let mut consider = |r: usize, c: usize| {
            let d2 = self.full.points[r * self.stride * self.full.width + c * self.stride]
                .distance_squared(q);
            let k = r * self.width + c;
            // NaN (a sample without depth) fails the comparison.
            if d2 <= best.0 && counts(k) {
                best = (d2, k);
            }
        };
        consider(r0, c0);
        if c1 != c0 {
            consider(r0, c1);
        }
        if r1 != r0 {
            consider(r1, c0);
            if c1 != c0 {
                consider(r1, c1);
            }
        }
        (best.1 != usize::MAX).then_some(best.1)
    }
}
