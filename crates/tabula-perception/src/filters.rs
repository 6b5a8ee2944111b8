//! Point-cloud filters: crop box / pass-through, voxel grid, statistical and radius
//! outlier removal, and surface normals.
//!
//! Organized clouds (a depth image: `width × height`, NaN holes) find neighbours in the
//! image grid, which costs a fixed window per pixel; unorganized clouds use a kd-tree
//! (kiddo). Filters that keep the grid return a mask (`true` = keep) so indices stay
//! pixel indices.

use crate::kd::KdTree;
use rayon::prelude::*;
use rustc_hash::FxHashMap;
use tabula_geom::input::{Validate, check_count, check_non_negative, check_positive};
use tabula_geom::{PointCloud, Vec3};

/// A filter that cannot run on its input.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FilterError {
    #[error("voxel leaf size must be positive and finite, got {0}")]
    BadLeaf(f64),
    #[error("voxel leaf {leaf} m is too small for a cloud {extent:.1} m across")]
    LeafTooSmall { leaf: f64, extent: f64 },
    #[error("{0}")]
    BadParameter(&'static str),
}

/// Indices of finite points inside the axis-aligned box `[min, max]`.
pub fn crop_box(points: &[Vec3], min: Vec3, max: Vec3) -> Vec<usize> {
    (0..points.len())
        .filter(|&i| {
            let p = points[i];
            p.is_finite() && p.cmpge(min).all() && p.cmple(max).all()
        })
        .collect()
}

/// Indices of finite points whose coordinate `axis` (0 = x, 1 = y, 2 = z) is in
/// `[lo, hi]` (PCL's pass-through).
pub fn pass_through(points: &[Vec3], axis: usize, lo: f64, hi: f64) -> Vec<usize> {
    (0..points.len())
        .filter(|&i| {
            let p = points[i];
            p.is_finite() && axis < 3 && (lo..=hi).contains(&p[axis])
        })
        .collect()
}

/// Centroids of the occupied cells of a grid with cubic cells of side `leaf`, in the
/// order of their cell coordinates (so the result does not depend on the input order
/// of the cells).
pub fn voxel_grid(points: &[Vec3], leaf: f64) -> Result<Vec<Vec3>, FilterError> {
    if !(leaf.is_finite() && leaf > 0.0) {
        return Err(FilterError::BadLeaf(leaf));
    }
    let mut lo = Vec3::splat(f64::INFINITY);
    let mut hi = Vec3::splat(f64::NEG_INFINITY);
    for p in points.iter().filter(|p| p.is_finite()) {
        lo = lo.min(*p);
        hi = hi.max(*p);
    }
    if lo.x > hi.x {
        return Ok(Vec::new());
    }
    let extent = (hi - lo).max_element();
    // Cell coordinates must fit 21 bits each to pack into one key.
    if extent / leaf > (1u64 << 21) as f64 - 2.0 {
        return Err(FilterError::LeafTooSmall { leaf, extent });
    }
    let inv = 1.0 / leaf;
    // p − lo ≥ 0, so truncation is floor (and needs no libm call).
    let key = |p: Vec3| {
        let c = (p - lo) * inv;
        ((c.x as u64) << 42) | ((c.y as u64) << 21) | c.z as u64
    };
    // Neighbouring points of a scan usually share a cell: remember the last one and
    // skip the hash lookup for runs.
    let mut slot_of: FxHashMap<u64, usize> = FxHashMap::default();
    let mut sums: Vec<(u64, Vec3, u32)> = Vec::new();
    let mut last = (u64::MAX, 0usize);
    for p in points.iter().filter(|p| p.is_finite()) {
        let k = key(*p);
        let slot = if k == last.0 {
            last.1
        } else {
            let next = sums.len();
            let slot = *slot_of.entry(k).or_insert(next);
            if slot == next {
                sums.push((k, Vec3::ZERO, 0));
            }
            last = (k, slot);
            slot
        };
        sums[slot].1 += *p;
        sums[slot].2 += 1;
    }
    let mut out: Vec<(u64, Vec3)> = sums
        .into_iter()
        .map(|(k, s, n)| (k, s / n as f64))
        .collect();
    out.sort_unstable_by_key(|(k, _)| *k);
    Ok(out.into_iter().map(|(_, p)| p).collect())
}

/// Statistical outlier removal; defaults are seed 002's (SPEC §6: mean-K 10, std
/// multiplier 1.0).
#[derive(Debug, Clone, serde::Deserialize, serde::Serialize)]
#[serde(default, deny_unknown_fields)]
pub struct OutlierParams {
    /// Neighbours whose mean distance is a point's statistic (SPEC §6: 10).
    pub mean_k: usize,
    /// Keep points whose statistic is within mean + std_mul · σ (SPEC §6: 1.0).
    pub std_mul: f64,
}

impl Default for OutlierParams {
    fn default() -> Self {
        Self {
            mean_k: 10,
            std_mul: 1.0,
        }
    }
}

/// The pixel offsets of the `k` nearest pixels, with every pixel at the k-th pixel
/// distance included so the set is symmetric.
fn nearest_pixel_offsets(k: usize) -> Vec<(isize, isize)> {
    let r = (1..64isize)
        .find(|r| ((2 * r + 1) * (2 * r + 1) - 1) as usize >= k)
        .unwrap_or(64);
    let mut order: Vec<(isize, isize)> = (-r..=r)
        .flat_map(|dy| (-r..=r).map(move |dx| (dx, dy)))
        .filter(|&o| o != (0, 0))
        .collect();
    order.sort_by_key(|&(dx, dy)| (dx * dx + dy * dy, dy, dx));
    let kth = order
        .get(k.max(1) - 1)
        .map_or(isize::MAX, |&(dx, dy)| dx * dx + dy * dy);
    order.retain(|&(dx, dy)| dx * dx + dy * dy <= kth);
    order
}

/// Per pixel, the mean distance to the valid pixels among its `k` nearest pixels,
/// divided by the point's range from `viewpoint` if given (NaN for missing points, ∞
/// when no neighbour is valid). On a depth image a point's nearest neighbours in space
/// are its nearest pixels, so this is PCL's k-NN statistic without a search; it runs
/// offset by offset over whole rows in f32, which the compiler vectorises.
fn organized_mean_distances(cloud: &PointCloud, k: usize, viewpoint: Option<Vec3>) -> Vec<f32> {
    let (w, h) = (cloud.width, cloud.height);
    let n_all = w * h;
    let (mut sx, mut sy, mut sz) = (
        Vec::with_capacity(n_all),
        Vec::with_capacity(n_all),
        Vec::with_capacity(n_all),
    );
    for p in &cloud.points {
        sx.push(p.x as f32);
        sy.push(p.y as f32);
        sz.push(p.z as f32);
    }
    let offsets = nearest_pixel_offsets(k);
    let view = viewpoint.map(|v| [v.x as f32, v.y as f32, v.z as f32]);
    let mut out = vec![0.0f32; n_all];
    out.par_chunks_mut(w).enumerate().for_each(|(y, row_out)| {
        let mut cnt = vec![0.0f32; w];
        let sum = row_out;
        let row = y * w;
        for &(dx, dy) in &offsets {
            let yy = y as isize + dy;
            if yy < 0 || yy as usize >= h {
                continue;
            }
            let other = yy as usize * w;
            // A frame narrower than the offset has no pair at this offset.
            let x0 = (-dx).max(0);
            let x1 = w as isize - dx.max(0);
            if x1 <= x0 {
                continue;
            }
            let (x0, x1) = (x0 as usize, x1 as usize);
            let n = x1 - x0;
            let (ax, ay, az) = (
                &sx[row + x0..][..n],
                &sy[row + x0..][..n],
                &sz[row + x0..][..n],
            );
            let o = (other as isize + x0 as isize + dx) as usize;
            let (bx, by, bz) = (&sx[o..][..n], &sy[o..][..n], &sz[o..][..n]);
            let (s, c) = (&mut sum[x0..][..n], &mut cnt[x0..][..n]);
            let a = ax.iter().zip(ay).zip(az);
            let b = bx.iter().zip(by).zip(bz);
            for ((s, c), (((ax, ay), az), ((bx, by), bz))) in
                s.iter_mut().zip(c.iter_mut()).zip(a.zip(b))
            {
                let (ex, ey, ez) = (ax - bx, ay - by, az - bz);
                let d2 = ex * ex + ey * ey + ez * ez;
                // NaN (a missing point) fails the comparison.
                let valid = d2 < f32::INFINITY;
                *s += if valid { d2.sqrt() } else { 0.0 };
                *c += if valid { 1.0 } else { 0.0 };
            }
        }
        for x in 0..w {
            let i = row + x;
            let range = match view {
                Some(v) => {
                    let (ex, ey, ez) = (sx[i] - v[0], sy[i] - v[1], sz[i] - v[2]);
                    (ex * ex + ey * ey + ez * ez).sqrt().max(1e-9)
                }
                None => 1.0,
            };
            sum[x] = if !(sx[i] + sy[i] + sz[i]).is_finite() {
                f32::NAN
            } else if cnt[x] == 0.0 {
                f32::INFINITY
            } else {
                sum[x] / cnt[x] / range
            };
        }
    });
    out
}

/// Statistical outlier removal (PCL's `StatisticalOutlierRemoval`): a point's statistic
/// is the mean distance to its `mean_k` nearest neighbours (on organized clouds: to the
/// valid ones among its `mean_k` nearest pixels); points above mean +
/// `std_mul`·σ of all statistics go. With a `viewpoint` each statistic is divided by the
/// point's range, so the threshold means the same near and far (a depth sensor's point
/// spacing grows with range; PCL's global threshold strips far surfaces instead of
/// outliers). Returns the keep mask; non-finite points are never kept.
pub fn statistical_outliers(
    cloud: &PointCloud,
    viewpoint: Option<Vec3>,
    p: &OutlierParams,
) -> Result<Vec<bool>, FilterError> {
    if p.mean_k == 0 || !p.std_mul.is_finite() {
        return Err(FilterError::BadParameter(
            "mean_k must be ≥ 1 and std_mul finite",
        ));
    }
    let pts = &cloud.points;
    let k = p.mean_k;
    let stat: Vec<f32> = if cloud.is_organized() {
        organized_mean_distances(cloud, k, viewpoint)
    } else {
        let finite: Vec<usize> = (0..pts.len()).filter(|&i| pts[i].is_finite()).collect();
        let mut stat = vec![f32::NAN; pts.len()];
        if finite.len() > 1 {
            let tree = KdTree::over(pts, &finite)
                .ok_or(FilterError::BadParameter("too many points for the kd-tree"))?;
            let values: Vec<f64> = tree
                .mean_neighbour_distances(k)
                .into_iter()
                .zip(&finite)
                .map(|(mean, &i)| {
                    viewpoint.map_or(mean, |v| mean / (pts[i] - v).length().max(1e-9))
                })
                .collect();
            for (&i, v) in finite.iter().zip(values) {
                stat[i] = v as f32;
            }
        } else if let Some(&i) = finite.first() {
            stat[i] = f32::INFINITY;
        }
        stat
    };
    let (mut n, mut sum, mut sum2) = (0usize, 0.0f64, 0.0f64);
    for &s in stat.iter().filter(|s| s.is_finite()) {
        n += 1;
        sum += s as f64;
        sum2 += (s as f64) * (s as f64);
    }
    if n == 0 {
        return Ok(vec![false; pts.len()]);
    }
    let mean = sum / n as f64;
    let var = ((sum2 - n as f64 * mean * mean) / (n.max(2) - 1) as f64).max(0.0);
    // A hair above the threshold so that a noise-free cloud (σ = 0) is not thinned by
    // the rounding of equal statistics.
    let limit = (mean + p.std_mul * var.sqrt() + 1e-4 * mean) as f32;
    Ok(stat.iter().map(|s| *s <= limit).collect())
}

/// Radius outlier removal: keep points with at least `min_neighbors` others within
/// `radius`. Organized clouds search an image window sized from the local pixel
/// spacing (capped at 8 pixels); others use a kd-tree.
pub fn radius_outliers(
    cloud: &PointCloud,
    radius: f64,
    min_neighbors: usize,
) -> Result<Vec<bool>, FilterError> {
    if !(radius.is_finite() && radius > 0.0) {
        return Err(FilterError::BadParameter("radius must be positive"));
    }
    let pts = &cloud.points;
    let r2 = radius * radius;
    if cloud.is_organized() {
        let (w, h) = (cloud.width, cloud.height);
        let mut keep = vec![false; pts.len()];
        keep.par_chunks_mut(w).enumerate().for_each(|(y, row)| {
            for (x, out) in row.iter_mut().enumerate() {
                let c = pts[y * w + x];
                if !c.is_finite() {
                    continue;
                }
                let spacing = [(x + 1, y), (x.wrapping_sub(1), y)]
                    .iter()
                    .filter(|(xx, _)| *xx < w)
                    .map(|&(xx, yy)| pts[yy * w + xx])
                    .filter(|q| q.is_finite())
                    .map(|q| q.distance(c))
                    .fold(f64::INFINITY, f64::min);
                let half = if spacing.is_finite() && spacing > 0.0 {
                    ((radius / spacing).ceil() as usize).clamp(1, 8)
                } else {
                    1
                };
                let mut count = 0;
                'window: for yy in y.saturating_sub(half)..(y + half + 1).min(h) {
                    for xx in x.saturating_sub(half)..(x + half + 1).min(w) {
                        let q = pts[yy * w + xx];
                        if (yy != y || xx != x) && q.is_finite() && c.distance_squared(q) <= r2 {
                            count += 1;
                            if count >= min_neighbors {
                                break 'window;
                            }
                        }
                    }
                }
                *out = count >= min_neighbors;
            }
        });
        return Ok(keep);
    }
    let finite: Vec<usize> = (0..pts.len()).filter(|&i| pts[i].is_finite()).collect();
    let mut keep = vec![false; pts.len()];
    if finite.is_empty() {
        return Ok(keep);
    }
    let tree = KdTree::over(pts, &finite)
        .ok_or(FilterError::BadParameter("too many points for the kd-tree"))?;
    let counts: Vec<usize> = finite
        .par_iter()
        .map(|&i| tree.within(&pts[i].to_array(), r2).len().saturating_sub(1))
        .collect();
    for (&i, n) in finite.iter().zip(counts) {
        keep[i] = n >= min_neighbors;
    }
    Ok(keep)
}

/// Largest half window (pixels) a normal is fitted over.
pub(crate) const MAX_WINDOW: usize = 15;

/// Normal estimation parameters.
#[derive(Debug, Clone, serde::Deserialize, serde::Serialize)]
#[serde(default, deny_unknown_fields)]
pub struct NormalParams {
    /// Half size of the pixel window (organized clouds), at most 15.
    pub window: usize,
    /// Neighbours (unorganized clouds): about as many as the pixel window holds.
    pub k: usize,
    /// Neighbours farther than this many times the distance to the nearest pixel
    /// neighbour are across a depth edge and ignored.
    pub depth_edge_factor: f64,
}

impl Default for NormalParams {
    fn default() -> Self {
        Self {
            window: 3,
            k: 48,
            depth_edge_factor: 4.0,
        }
    }
}

/// Unit eigenvector of the smallest eigenvalue of a symmetric 3×3 matrix
/// `[xx, xy, xz, yy, yz, zz]`, and the eigenvalues (ascending). Closed form: the
/// trigonometric solution of the characteristic cubic, then the largest cross product
/// of two rows of `A − λI` — about 100× cheaper than a general eigen solver, which
/// matters when every pixel needs one.
pub fn smallest_eigenvector(m: [f64; 6]) -> Option<(Vec3, [f64; 3])> {
    let [a, b, c, d, e, f] = m;
    if m.iter().any(|v| !v.is_finite()) {
        return None;
    }
    let p1 = b * b + c * c + e * e;
    let q = (a + d + f) / 3.0;
    let p2 = (a - q).powi(2) + (d - q).powi(2) + (f - q).powi(2) + 2.0 * p1;
    let p = (p2 / 6.0).sqrt();
    if p < 1e-300 {
        return None;
    }
    // B = (A − qI)/p; r = det(B)/2.
    let (ba, bd, bf) = ((a - q) / p, (d - q) / p, (f - q) / p);
    let (bb, bc, be) = (b / p, c / p, e / p);
    let det = ba * (bd * bf - be * be) - bb * (bb * bf - be * bc) + bc * (bb * be - bd * bc);
    let r = (det / 2.0).clamp(-1.0, 1.0);
    let phi = r.acos() / 3.0;
    let l_max = q + 2.0 * p * phi.cos();
    let l_min = q + 2.0 * p * (phi + 2.0 * std::f64::consts::FRAC_PI_3).cos();
    let l_mid = 3.0 * q - l_max - l_min;
    let r0 = Vec3::new(a - l_min, b, c);
    let r1 = Vec3::new(b, d - l_min, e);
    let r2 = Vec3::new(c, e, f - l_min);
    let candidates = [r0.cross(r1), r0.cross(r2), r1.cross(r2)];
    let best = candidates
        .iter()
        .copied()
        .max_by(|x, y| x.length_squared().total_cmp(&y.length_squared()))?;
    let n = best.try_normalize()?;
    Some((n, [l_min, l_mid, l_max]))
}

/// First and second moments of points, accumulated in one pass about a reference
/// point (near the data, so the subtraction at the end loses no precision).
#[derive(Clone, Copy)]
pub(crate) struct Moments {
    origin: Vec3,
    n: usize,
    sum: Vec3,
    products: [f64; 6],
}

impl Moments {
    pub(crate) fn new(origin: Vec3) -> Self {
        Self {
            origin,
            n: 0,
            sum: Vec3::ZERO,
            products: [0.0; 6],
        }
    }

    #[inline]
    pub(crate) fn add(&mut self, p: Vec3) {
        let d = p - self.origin;
        self.n += 1;
        self.sum += d;
        self.products[0] += d.x * d.x;
        self.products[1] += d.x * d.y;
        self.products[2] += d.x * d.z;
        self.products[3] += d.y * d.y;
        self.products[4] += d.y * d.z;
        self.products[5] += d.z * d.z;
    }

    /// Centroid and scatter matrix `[xx, xy, xz, yy, yz, zz]` about it (≥ 3 points).
    pub(crate) fn scatter(&self) -> Option<(Vec3, [f64; 6])> {
        if self.n < 3 {
            return None;
        }
        let nf = self.n as f64;
        let m = self.sum / nf;
        let s = self.products;
        Some((
            self.origin + m,
            [
                s[0] - nf * m.x * m.x,
                s[1] - nf * m.x * m.y,
                s[2] - nf * m.x * m.z,
                s[3] - nf * m.y * m.y,
                s[4] - nf * m.y * m.z,
                s[5] - nf * m.z * m.z,
            ],
        ))
    }
}

/// Centroid and scatter of points about it, as `[xx, xy, xz, yy, yz, zz]`.
pub(crate) fn scatter(mut points: impl Iterator<Item = Vec3>) -> Option<(Vec3, [f64; 6])> {
    let first = points.next()?;
    let mut m = Moments::new(first);
    m.add(first);
    for p in points {
        m.add(p);
    }
    m.scatter()
}

/// Surface normals by local PCA, oriented towards `viewpoint`; NaN where a point has
/// too few neighbours. Only points with `mask[i]` (all if `None`) get normals and serve
/// as neighbours, so an object's normals do not bend towards the table it stands on.
/// Organized clouds use the pixel window (skipping neighbours across depth edges);
/// others use the `k` nearest neighbours.
pub fn normals(
    cloud: &PointCloud,
    viewpoint: Vec3,
    mask: Option<&[bool]>,
    p: &NormalParams,
) -> Vec<Vec3> {
    local_planes(cloud, viewpoint, mask, p)
        .into_iter()
        .map(|(n, _)| n)
        .collect()
}

/// As [`normals`], with the centroid of each point's neighbourhood: a point on the
/// local plane with the sensor noise averaged out.
pub fn local_planes(
    cloud: &PointCloud,
    viewpoint: Vec3,
    mask: Option<&[bool]>,
    p: &NormalParams,
) -> Vec<(Vec3, Vec3)> {
    let pts = &cloud.points;
    let all: Vec<bool>;
    let mask = match mask {
        Some(m) => m,
        None => {
            all = pts.iter().map(|q| q.is_finite()).collect();
            &all
        }
    };
    let wanted: Vec<usize> = (0..pts.len())
        .filter(|&i| mask.get(i) == Some(&true))
        .collect();
    let mut out = vec![(Vec3::NAN, Vec3::NAN); pts.len()];
    for (&i, l) in wanted
        .iter()
        .zip(local_planes_at(cloud, viewpoint, mask, &wanted, p))
    {
        out[i] = l;
    }
    out
}

/// [`local_planes`] for the points `at` only (same order), with `mask` choosing the
/// neighbours: cheap when few points need normals in a big frame.
pub fn local_planes_at(
    cloud: &PointCloud,
    viewpoint: Vec3,
    mask: &[bool],
    at: &[usize],
    p: &NormalParams,
) -> Vec<(Vec3, Vec3)> {
    let pts = &cloud.points;
    let none = (Vec3::NAN, Vec3::NAN);
    let usable = |i: usize| mask.get(i) == Some(&true) && pts.get(i).is_some_and(|q| q.is_finite());
    let orient = |i: usize, n: Vec3| toward(viewpoint, pts[i], n);
    if cloud.is_organized() {
        let (w, h) = (cloud.width, cloud.height);
        let r = p.window.clamp(1, MAX_WINDOW);
        return at
            .par_iter()
            .map(|&i| {
                if !usable(i) {
                    return none;
                }
                let (x, y) = (i % w, i / w);
                let c = pts[i];
                let step = [
                    (x + 1, y),
                    (x.wrapping_sub(1), y),
                    (x, y + 1),
                    (x, y.wrapping_sub(1)),
                ]
                .iter()
                .filter(|(xx, yy)| *xx < w && *yy < h)
                .map(|&(xx, yy)| pts[yy * w + xx])
                .filter(|q| q.is_finite())
                .map(|q| q.distance(c))
                .fold(f64::INFINITY, f64::min);
                if !step.is_finite() {
                    return none;
                }
                let limit = (step * p.depth_edge_factor * r as f64).powi(2);
                let mut moments = Moments::new(c);
                for yy in y.saturating_sub(r)..(y + r + 1).min(h) {
                    for xx in x.saturating_sub(r)..(x + r + 1).min(w) {
                        let j = yy * w + xx;
                        if pts[j].distance_squared(c) <= limit && mask[j] {
                            moments.add(pts[j]);
                        }
                    }
                }
                let Some((centroid, cov)) = moments.scatter() else {
                    return none;
                };
                smallest_eigenvector(cov).map_or(none, |(n, _)| (orient(i, n), centroid))
            })
            .collect();
    }
    let Some(index) = Neighbours::over(cloud, mask) else {
        return vec![none; at.len()];
    };
    index.local_planes_at(cloud, viewpoint, at, p)
}

/// The normal `n` at `at`, flipped if need be to face `viewpoint`.
fn toward(viewpoint: Vec3, at: Vec3, n: Vec3) -> Vec3 {
    if n.dot(viewpoint - at) < 0.0 { -n } else { n }
}

/// The points of an unorganized cloud a mask chooses, in a k-d tree: built once, it
/// serves every normal estimate among the same neighbours.
pub struct Neighbours {
    members: Vec<usize>,
    tree: KdTree,
    usable: Vec<bool>,
}

impl Neighbours {
    /// `None` when fewer than three finite points are chosen.
    pub fn over(cloud: &PointCloud, mask: &[bool]) -> Option<Self> {
        let pts = &cloud.points;
        let usable: Vec<bool> = (0..pts.len())
            .map(|i| mask.get(i) == Some(&true) && pts[i].is_finite())
            .collect();
        let members: Vec<usize> = (0..pts.len()).filter(|&i| usable[i]).collect();
        if members.len() < 3 {
            return None;
        }
        let tree = KdTree::over(pts, &members)?;
        Some(Self {
            members,
            tree,
            usable,
        })
    }

    /// [`local_planes_at`] of an unorganized cloud among these neighbours: points not
    /// among them get NaN.
    pub fn local_planes_at(
        &self,
        cloud: &PointCloud,
        viewpoint: Vec3,
        at: &[usize],
        p: &NormalParams,
    ) -> Vec<(Vec3, Vec3)> {
        let pts = &cloud.points;
        let none = (Vec3::NAN, Vec3::NAN);
        let k = p.k.clamp(3, self.members.len());
        at.par_iter()
            .map(|&i| {
                if self.usable.get(i) != Some(&true) {
                    return none;
                }
                let nn = self.tree.nearest(&pts[i].to_array(), k);
                scatter(nn.iter().map(|m| pts[self.members[m.1]]))
                    .and_then(|(c, m)| Some((smallest_eigenvector(m)?.0, c)))
                    .map_or(none, |(n, c)| (toward(viewpoint, pts[i], n), c))
            })
            .collect()
    }
}

impl Validate for OutlierParams {
    fn check(&self, at: &str) -> Result<(), String> {
        check_count(at, "mean_k", self.mean_k, 1)?;
        check_non_negative(at, "std_mul", self.std_mul)
    }
}

impl Validate for NormalParams {
    fn check(&self, at: &str) -> Result<(), String> {
        check_count(at, "window", self.window, 1)?;
        check_count(at, "k", self.k, 3)?;
        check_positive(at, "depth_edge_factor", self.depth_edge_factor)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid(w: usize, h: usize, f: impl Fn(usize, usize) -> Vec3) -> PointCloud {
        let points = (0..h)
            .flat_map(|y| (0..w).map(move |x| (x, y)))
            .map(|(x, y)| f(x, y))
            .collect();
        PointCloud::organized(w, h, points).unwrap()
    }

    #[test]
    fn crop_and_pass_through_keep_what_is_inside() {
        let pts = vec![
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::NAN,
            Vec3::new(0.5, 0.5, 2.0),
        ];
        assert_eq!(crop_box(&pts, Vec3::splat(-0.1), Vec3::splat(1.0)), [0, 1]);
        assert_eq!(pass_through(&pts, 2, 1.0, 3.0), [3]);
        assert!(pass_through(&pts, 7, 0.0, 1.0).is_empty());
    }

    #[test]
    fn voxel_grid_averages_cells_and_rejects_bad_leaves() {
        let pts = vec![
            Vec3::new(0.01, 0.01, 0.0),
            Vec3::new(0.03, 0.01, 0.0),
            Vec3::new(0.51, 0.0, 0.0),
            Vec3::NAN,
        ];
        let v = voxel_grid(&pts, 0.1).unwrap();
        assert_eq!(v.len(), 2);
        assert!((v[0] - Vec3::new(0.02, 0.01, 0.0)).length() < 1e-12);
        assert!(voxel_grid(&pts, 0.0).is_err());
        assert!(voxel_grid(&pts, f64::NAN).is_err());
        assert!(voxel_grid(&pts, 1e-9).is_err());
        assert!(voxel_grid(&[Vec3::NAN], 0.1).unwrap().is_empty());
    }

    #[test]
    fn outliers_go_and_surfaces_stay_in_both_neighbour_modes() {
        // A plane 1 m away with a few points pulled 20 cm off it.
        let cloud = grid(60, 40, |x, y| {
            let z = if (x * 7 + y * 13) % 97 == 0 { 0.8 } else { 1.0 };
            Vec3::new(x as f64 * 0.002, y as f64 * 0.002, z)
        });
        let bad: Vec<usize> = (0..cloud.points.len())
            .filter(|&i| cloud.points[i].z < 0.9)
            .collect();
        assert!(!bad.is_empty());
        for organized in [true, false] {
            let c = if organized {
                cloud.clone()
            } else {
                PointCloud::unorganized(cloud.points.clone())
            };
            let p = OutlierParams {
                mean_k: 8,
                std_mul: 2.0,
            };
            let keep = statistical_outliers(&c, Some(Vec3::ZERO), &p).unwrap();
            assert!(bad.iter().all(|&i| !keep[i]), "organized {organized}");
            let kept = keep.iter().filter(|k| **k).count();
            assert!(kept as f64 > 0.95 * (c.points.len() - bad.len()) as f64);
            let keep = radius_outliers(&c, 0.01, 4).unwrap();
            assert!(bad.iter().all(|&i| !keep[i]), "organized {organized}");
            assert!(keep.iter().filter(|k| **k).count() > c.points.len() - bad.len() - 10);
        }
    }

    #[test]
    fn degenerate_clouds_do_not_panic() {
        let p = OutlierParams::default();
        for c in [
            PointCloud::unorganized(vec![]),
            PointCloud::unorganized(vec![Vec3::ONE]),
            PointCloud::unorganized(vec![Vec3::NAN; 5]),
            grid(3, 2, |_, _| Vec3::NAN),
            grid(4, 4, |_, _| Vec3::ONE),
        ] {
            let keep = statistical_outliers(&c, None, &p).unwrap();
            assert_eq!(keep.len(), c.points.len());
            assert_eq!(radius_outliers(&c, 0.1, 1).unwrap().len(), c.points.len());
            let n = normals(&c, Vec3::ZERO, None, &NormalParams::default());
            assert!(
                n.iter()
                    .all(|n| n.is_nan() || (n.length() - 1.0).abs() < 1e-9)
            );
        }
        assert!(
            statistical_outliers(
                &PointCloud::unorganized(vec![]),
                None,
                &OutlierParams {
                    mean_k: 0,
                    std_mul: 1.0
                }
            )
            .is_err()
        );
        assert!(radius_outliers(&PointCloud::unorganized(vec![]), -1.0, 1).is_err());
    }

    #[test]
    fn normals_of_a_tilted_plane_face_the_viewpoint() {
        let n_true = Vec3::new(0.0, -0.6, 0.8);
        let cloud = grid(40, 30, |x, y| {
            let (u, v) = (x as f64 * 0.003, y as f64 * 0.003);
            // Points on the plane n_true · p = 0.8 … seen from the origin along +z.
            Vec3::new(u, v, (0.8 + 0.6 * v) / 0.8)
        });
        for c in [cloud.clone(), PointCloud::unorganized(cloud.points.clone())] {
            let n = normals(&c, Vec3::ZERO, None, &NormalParams::default());
            for (i, n) in n.iter().enumerate() {
                assert!(n.dot(-n_true) > 0.999, "{i}: {n:?}");
            }
        }
    }

    #[test]
    fn closed_form_eigenvector_matches_nalgebra() {
        let m = [2.0, 0.3, -0.1, 1.5, 0.2, 0.4];
        let (n, l) = smallest_eigenvector(m).unwrap();
        let a = nalgebra::Matrix3::new(m[0], m[1], m[2], m[1], m[3], m[4], m[2], m[4], m[5]);
        let e = nalgebra::SymmetricEigen::new(a);
        let lmin = e.eigenvalues.min();
        assert!((l[0] - lmin).abs() < 1e-9);
        let v = nalgebra::Vector3::new(n.x, n.y, n.z);
        assert!((a * v - v * lmin).norm() < 1e-9);
    }
}
