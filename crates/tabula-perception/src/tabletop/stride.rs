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
    let columns: Vec<(usize, usize)> = (0..full.width).map(|x| grid.around(x)).collect();
    for y in 0..full.height {
        let rows = grid.around(y);
        for (x, &cols) in columns.iter().enumerate() {
            let i = y * full.width + x;
            let q = full.points[i];
            if !q.is_finite() {
                continue;
            }
            let around = grid.around_pixel(rows, cols);
            // The points whose own sample (up and left) passed outlier removal.
            kept += usize::from(keep[around[0].0]);
            let reach = p.cluster_tolerance + p.cluster_range_gain * q.distance_squared(eye);
            let Some(k) = pick(q, &around, (&owners, &full.points), reach * reach) else {
                continue;
            };
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

/// The sample whose segment point `q` takes, among the samples `around` it (coarse and
/// full index), if any is within `reach2` (squared) of it: with one owner all round,
/// any sample within reach; otherwise the nearest that belongs to something — a sample
/// dropped as an outlier does not take its neighbours with it.
fn pick(
    q: Vec3,
    around: &[(usize, usize)],
    (owners, points): (&[Owner], &[Vec3]),
    reach2: f64,
) -> Option<usize> {
    let owner = owners[around[0].0];
    let same = around.iter().all(|&(k, _)| owners[k] == owner);
    if same && owner == Owner::Nobody {
        return None;
    }
    // NaN (a sample without depth) fails every comparison.
    let near = |at: usize| points[at].distance_squared(q) <= reach2;
    if same {
        return around.iter().find(|&&(_, at)| near(at)).map(|&(k, _)| k);
    }
    around
        .iter()
        .filter(|&&(k, _)| owners[k] != Owner::Nobody)
        .map(|&(k, at)| (points[at].distance_squared(q), k))
        .filter(|&(d2, _)| d2 <= reach2)
        .min_by(|a, b| a.0.total_cmp(&b.0))
        .map(|(_, k)| k)
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

    /// The samples at `rows` × `cols` (see [`Self::around`]; a row or column past the
    /// grid's last is its last): coarse index and full index of each, the one up and
    /// left first. A pixel on a sample's row or column has the same sample twice.
    fn around_pixel(
        &self,
        (r0, r1): (usize, usize),
        (c0, c1): (usize, usize),
    ) -> [(usize, usize); 4] {
        let r1 = if r1 < self.height { r1 } else { r0 };
        let c1 = if c1 < self.width { c1 } else { c0 };
        let at = |r: usize, c: usize| (r * self.width + c, (r * self.full.width + c) * self.stride);
        [at(r0, c0), at(r0, c1), at(r1, c0), at(r1, c1)]
    }
}
