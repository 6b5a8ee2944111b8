//! Segmentation of the points above a table into objects, by geometry alone.
//!
//! Region growing with a convexity cut in the spirit of LCCP, done on points rather
//! than supervoxels: a point lies on a *concave crease* when two points a few
//! neighbours away on either side have normals that differ by more than the concavity
//! tolerance and face each other ((n_a − n_b)·(p_a − p_b) < 0). Objects are convex, so
//! creases are where one object meets another (a box on a box, a box against a taller
//! one). Regions grow over neighbours closer than the cluster tolerance without crossing
//! crease points; crease points then join the region that reaches them first. Depth
//! jumps cut regions apart on their own; steps between table-parallel tops, ledge
//! merging and one-object-per-top splitting handle what creases cannot see.

use crate::kd::KdTree;
use crate::params::TabletopParams;
use crate::plane::Plane;
use crate::surfaces::plane_basis;
use std::collections::VecDeque;
use tabula_geom::polygon::{convex_hull_2d, distance_to_boundary, inside_convex};
use tabula_geom::{PointCloud, Vec2, Vec3};

/// Concave-crease test between two points with normals.
fn concave(pa: Vec3, na: Vec3, pb: Vec3, nb: Vec3, cos_tol: f64) -> bool {
    na.is_finite() && nb.is_finite() && na.dot(nb) < cos_tol && (na - nb).dot(pa - pb) < 0.0
}

/// Step test: two flat tops parallel to the table at different heights, side by side
/// (touching objects of different heights). Local-plane centroids average the sensor
/// noise; only table-parallel planes count, because near the edges of side faces the
/// windows mix two faces and their centroids shift. The offset is measured along the
/// planes' mean normal, not the table's up: two points of one top tilted by 20° (a box
/// leaning on another) differ in height by more than the tolerance a crease band apart.
fn step(ca: Vec3, na: Vec3, cb: Vec3, nb: Vec3, up: Vec3, cos_tol: f64, tolerance: f64) -> bool {
    na.is_finite()
        && nb.is_finite()
        && na.dot(up).abs() >= cos_tol
        && nb.dot(up).abs() >= cos_tol
        && (na + nb).normalize_or_zero().dot(ca - cb).abs() > tolerance
}

/// Pairs of regions that are one surface cut apart by crease bands (see
/// [`ledge_pairs`]); given the regions and each point's region.
type SameSurface<'a> = &'a dyn Fn(&[Vec<usize>], &[usize]) -> Vec<(usize, usize)>;

/// Grows regions over `neighbours` from non-crease seeds, then lets crease points join
/// the region that reaches them first (breadth-first, so they split half-way), then
/// merges regions smaller than `min_size` into their best-connected neighbour.
fn grow(
    n: usize,
    member: &[bool],
    seedable: &[bool],
    crease: &[bool],
    min_size: usize,
    same_surface: Option<SameSurface>,
    neighbours: impl Fn(usize, &mut Vec<usize>),
) -> Vec<Vec<usize>> {
    let mut label = vec![usize::MAX; n];
    let mut regions: Vec<Vec<usize>> = Vec::new();
    let mut nb = Vec::new();
    for start in 0..n {
        if !member[start] || !seedable[start] || crease[start] || label[start] != usize::MAX {
            continue;
        }
        let id = regions.len();
        label[start] = id;
        let mut stack = vec![start];
        let mut members = Vec::new();
        while let Some(i) = stack.pop() {
            members.push(i);
            nb.clear();
            neighbours(i, &mut nb);
            for &j in &nb {
                if member[j] && seedable[j] && !crease[j] && label[j] == usize::MAX {
                    label[j] = id;
                    stack.push(j);
                }
            }
        }
        regions.push(members);
    }
    let mut queue: VecDeque<usize> = regions.iter().flatten().copied().collect();
    while let Some(i) = queue.pop_front() {
        nb.clear();
        neighbours(i, &mut nb);
        for &j in &nb {
            if member[j] && label[j] == usize::MAX {
                label[j] = label[i];
                regions[label[i]].push(j);
                queue.push_back(j);
            }
        }
    }
    if let Some(pairs) = same_surface {
        let mut parent: Vec<usize> = (0..regions.len()).collect();
        let root = |parent: &[usize], mut r: usize| {
            while parent[r] != r {
                r = parent[r];
            }
            r
        };
        for (a, b) in pairs(&regions, &label) {
            let (a, b) = (root(&parent, a), root(&parent, b));
            if a != b {
                parent[b] = a;
                let moved = std::mem::take(&mut regions[b]);
                for &i in &moved {
                    label[i] = a;
                }
                regions[a].extend(moved);
            }
        }
    }
    // Fragments (a strip of a side face cut off by a crease band) join the neighbouring
    // region they share most links with, smallest first — LCCP's minimum segment size.
    let mut order: Vec<usize> = (0..regions.len())
        .filter(|&r| regions[r].len() < min_size)
        .collect();
    order.sort_by_key(|&r| (regions[r].len(), r));
    for r in order {
        if regions[r].len() >= min_size || regions[r].is_empty() {
            continue;
        }
        let mut links: Vec<(usize, usize)> = Vec::new();
        for &i in &regions[r] {
            nb.clear();
            neighbours(i, &mut nb);
            for &j in &nb {
                let l = label[j];
                if member[j] && l != usize::MAX && l != r {
                    match links.iter_mut().find(|x| x.0 == l) {
                        Some(x) => x.1 += 1,
                        None => links.push((l, 1)),
                    }
                }
            }
        }
        if let Some(&(into, _)) = links.iter().max_by_key(|x| (x.1, std::cmp::Reverse(x.0))) {
            let moved = std::mem::take(&mut regions[r]);
            for &i in &moved {
                label[i] = into;
            }
            regions[into].extend(moved);
        }
    }
    regions.retain(|r| !r.is_empty());
    for r in &mut regions {
        r.sort_unstable();
    }
    regions
}

/// Normals and local-plane centroids of the prism's points.
pub(crate) struct Locals {
    pub(crate) planes: Vec<(Vec3, Vec3)>,
    /// Point index → position in `planes` (`u32::MAX`: not in the prism).
    pub(crate) slot: Vec<u32>,
}

impl Locals {
    pub(crate) fn get(&self, i: usize) -> (Vec3, Vec3) {
        match self.slot.get(i) {
            Some(&k) if k != u32::MAX => self.planes[k as usize],
            _ => (Vec3::NAN, Vec3::NAN),
        }
    }
}

/// Which points of the region being split belong to a top patch already: a mark per
/// point of the frame, allocated once for every region (a hash set per region cost a
/// tenth of segmentation).
pub(crate) struct PatchOf {
    /// 0: not in the region; 1: in it, no patch yet; 2: in a patch.
    mark: Vec<u8>,
    /// The points marked by the last region, to clear before the next.
    marked: Vec<usize>,
}

impl PatchOf {
    pub(crate) fn new(n: usize) -> Self {
        Self {
            mark: vec![0; n],
            marked: Vec::new(),
        }
    }

    fn open(&mut self, region: &[usize]) {
        for &i in &self.marked {
            self.mark[i] = 0;
        }
        self.marked.clear();
        for &i in region {
            self.mark[i] = 1;
        }
        self.marked.extend_from_slice(region);
    }

    fn has_patch(&self, i: usize) -> bool {
        self.mark[i] == 2
    }

    /// In the region and in no patch yet.
    fn open_member(&self, i: usize) -> bool {
        self.mark.get(i) == Some(&1)
    }

    fn set(&mut self, i: usize) {
        self.mark[i] = 2;
    }
}

/// One object per top: a segment holding two flat, table-parallel tops at different
/// heights (two boxes side by side whose front faces are flush, so nothing concave
/// separates them in view) is split, every point going to the lowest top above it
/// whose footprint covers it (or to the nearest footprint). Boxes and cylinders have
/// one top; stacked pieces that the creases already split are untouched.
fn split_by_tops(
    pts: &[Vec3],
    locals: &Locals,
    plane: &Plane,
    region: Vec<usize>,
    p: &TabletopParams,
    neighbours: &dyn Fn(usize, &mut Vec<usize>),
    patch_of: &mut PatchOf,
) -> Vec<Vec<usize>> {
    let up = plane.normal;
    let cos_tol = p.concavity_tolerance.cos();
    let height_of = |i: usize| -> Option<f64> {
        let (n, c) = locals.get(i);
        (n.dot(up).abs() >= cos_tol).then(|| plane.distance(c))
    };
    patch_of.open(&region);
    // Patches: connected up-facing points at one height.
    let mut patches: Vec<(Vec<usize>, f64)> = Vec::new();
    for &start in &region {
        if patch_of.has_patch(start) {
            continue;
        }
        let Some(h0) = height_of(start) else {
            continue;
        };
        patch_of.set(start);
        let (mut stack, mut members, mut heights) = (vec![start], Vec::new(), Vec::new());
        let mut near = Vec::new();
        while let Some(i) = stack.pop() {
            members.push(i);
            heights.push(height_of(i).unwrap_or(h0));
            near.clear();
            neighbours(i, &mut near);
            for &j in &near {
                if patch_of.open_member(j)
                    && height_of(j).is_some_and(|h| {
                        (h - height_of(i).unwrap_or(h0)).abs() <= p.step_tolerance / 2.0
                    })
                {
                    patch_of.set(j);
                    stack.push(j);
                }
            }
        }
        heights.sort_unstable_by(f64::total_cmp);
        let decile = |k: usize| heights[(heights.len() - 1) * k / 10];
        // A top is level: a face tilted 20° (a box leaning on another) passes the
        // up-facing test in fragments, each at its own height, and is not two tops.
        if decile(9) - decile(1) <= 2.0 * p.step_tolerance {
            patches.push((members, decile(5)));
        }
    }
    // Levels: big patches, those within the step tolerance of each other joined.
    let min_patch = 30.max(region.len() / 20);
    let mut levels: Vec<(f64, Vec<usize>)> = Vec::new();
    let mut big: Vec<&(Vec<usize>, f64)> = patches
        .iter()
        .filter(|(m, _)| m.len() >= min_patch)
        .collect();
    big.sort_by(|a, b| a.1.total_cmp(&b.1));
    for (members, h) in big {
        match levels.last_mut() {
            Some((lh, lm)) if (*h - *lh).abs() <= p.step_tolerance => lm.extend(members),
            _ => levels.push((*h, members.clone())),
        }
    }
    if levels.len() < 2 {
        return vec![region];
    }
    let (u, v) = plane_basis(up);
    let to2 = |q: Vec3| Vec2::new(q.dot(u), q.dot(v));
    let footprints: Vec<Vec<Vec2>> = levels
        .iter()
        .map(|(_, m)| {
            let flat: Vec<Vec2> = m.iter().map(|&i| to2(pts[i])).collect();
            convex_hull_2d(&flat).into_iter().map(|k| flat[k]).collect()
        })
        .collect();
    let slack = 0.005;
    let mut parts: Vec<Vec<usize>> = vec![Vec::new(); levels.len()];
    for &i in &region {
        let (q, h) = (to2(pts[i]), plane.distance(pts[i]));
        let covers = |k: usize| {
            footprints[k].len() >= 3
                && (inside_convex(&footprints[k], q)
                    || distance_to_boundary(&footprints[k], q) <= slack)
        };
        // Levels are sorted by height: the lowest top above the point that covers it.
        let k = (0..levels.len())
            .find(|&k| levels[k].0 >= h - p.step_tolerance && covers(k))
            .unwrap_or_else(|| {
                (0..levels.len())
                    .min_by(|&a, &b| {
                        distance_to_boundary(&footprints[a], q)
                            .total_cmp(&distance_to_boundary(&footprints[b], q))
                    })
                    .unwrap_or(0)
            });
        parts[k].push(i);
    }
    parts.retain(|r| !r.is_empty());
    parts
}

/// How far a pixel's normal may be off because the sensor's depth comes in steps: where
/// the normal window spans under two steps of depth (a surface facing the sensor), its
/// tilt is known only to within one step across the window. Worked out on demand (only
/// candidate creases need it) and kept.
struct TiltBlur<'a> {
    pts: &'a [Vec3],
    above: &'a [bool],
    width: usize,
    eye: Vec3,
    /// Half size of the normals' window (pixels).
    r: isize,
    /// Depth step at range z: `gain · z²` (the clustering's sensor model).
    gain: f64,
    memo: Vec<std::cell::Cell<f32>>,
}

impl<'a> TiltBlur<'a> {
    fn new(cloud: &'a PointCloud, above: &'a [bool], eye: Vec3, p: &TabletopParams) -> Self {
        Self {
            pts: &cloud.points,
            above,
            width: cloud.width,
            eye,
            r: p.normals.window.clamp(1, crate::filters::MAX_WINDOW) as isize,
            gain: p.cluster_range_gain,
            memo: vec![std::cell::Cell::new(f32::NAN); cloud.points.len()],
        }
    }

    fn pixel(&self, x: isize, y: isize) -> Option<usize> {
        let height = (self.pts.len() / self.width.max(1)) as isize;
        (x >= 0 && y >= 0 && x < self.width as isize && y < height)
            .then(|| y as usize * self.width + x as usize)
            .filter(|&j| self.above[j])
    }

    /// The blur (rad) of pixel `i`'s normal.
    fn at(&self, i: usize) -> f64 {
        let known = self.memo[i].get();
        if !known.is_nan() {
            return known as f64;
        }
        let blur = self.work_out(i);
        self.memo[i].set(blur as f32);
        blur
    }

    fn work_out(&self, i: usize) -> f64 {
        let (x, y) = ((i % self.width) as isize, (i / self.width) as isize);
        let pitch = [(1, 0), (-1, 0), (0, 1), (0, -1)]
            .iter()
            .filter_map(|&(dx, dy)| self.pixel(x + dx, y + dy))
            .map(|j| self.pts[j].distance(self.pts[i]))
            .fold(f64::INFINITY, f64::min);
        let range = self.pts[i].distance(self.eye);
        let quantum = self.gain * range * range;
        let (mut near, mut far) = (range, range);
        for yy in y - self.r..=y + self.r {
            for xx in x - self.r..=x + self.r {
                if let Some(j) = self.pixel(xx, yy) {
                    let d = self.pts[j].distance(self.eye);
                    (near, far) = (near.min(d), far.max(d));
                }
            }
        }
        if far - near >= 2.0 * quantum || !pitch.is_finite() {
            0.0
        } else {
            (quantum / (2.0 * self.r as f64 * pitch)).atan()
        }
    }
}

/// `eye` is the sensor's position: neighbouring pixels are one object while closer
/// than the cluster tolerance grown with the depth noise at their range.
pub(crate) fn segment_organized(
    cloud: &PointCloud,
    eye: Vec3,
    above: &[bool],
    keep: &[bool],
    locals: &Locals,
    plane: &Plane,
    p: &TabletopParams,
) -> Vec<Vec<usize>> {
    let up = plane.normal;
    let (w, h) = (cloud.width, cloud.height);
    let pts = &cloud.points;
    let s = p.concavity_step.max(1) as isize;
    let cos_tol = p.concavity_tolerance.cos();
    // Points 2s pixels apart may be 2s cluster tolerances apart to be compared: pixels
    // of the sensor, so a decimated frame's pair (as far apart in metres) reaches as far.
    let reach = p.cluster_tolerance * 2.0 * (s as usize * p.pixel_spacing.max(1)) as f64;
    let at = |x: isize, y: isize| -> Option<usize> {
        (x >= 0 && y >= 0 && (x as usize) < w && (y as usize) < h)
            .then(|| y as usize * w + x as usize)
    };
    let blur = TiltBlur::new(cloud, above, eye, p);
    let crease: Vec<bool> = (0..pts.len())
        .map(|i| {
            if !above[i] {
                return false;
            }
            let (x, y) = ((i % w) as isize, (i / w) as isize);
            [(1, 0), (0, 1), (1, 1), (1, -1)].iter().any(|&(dx, dy)| {
                let (Some(a), Some(b)) = (at(x - s * dx, y - s * dy), at(x + s * dx, y + s * dy))
                else {
                    return false;
                };
                let ((na, ca), (nb, cb)) = (locals.get(a), locals.get(b));
                if !(above[a] && above[b] && pts[a].distance(pts[b]) <= reach) {
                    return false;
                }
                let blurred = || {
                    let tol = p.concavity_tolerance + blur.at(a) + blur.at(b);
                    na.angle_between(nb) < tol
                };
                (concave(pts[a], na, pts[b], nb, cos_tol) && !blurred())
                    || step(ca, na, cb, nb, up, cos_tol, p.step_tolerance)
            })
        })
        .collect();
    let tolerance2 = |i: usize| {
        let t = p.cluster_tolerance + p.cluster_range_gain * pts[i].distance_squared(eye);
        t * t
    };
    let neighbours = |i: usize, out: &mut Vec<usize>| {
        let (x, y) = ((i % w) as isize, (i / w) as isize);
        let tol2 = tolerance2(i);
        for (dx, dy) in [(1, 0), (-1, 0), (0, 1), (0, -1)] {
            if let Some(j) = at(x + dx, y + dy)
                && pts[i].distance_squared(pts[j]) <= tol2
            {
                out.push(j);
            }
        }
    };
    let mut patch_of = PatchOf::new(pts.len());
    grow(
        pts.len(),
        above,
        keep,
        &crease,
        p.min_object_points,
        Some(&|regions: &[Vec<usize>], label: &[usize]| {
            ledge_pairs(cloud, above, locals, up, regions, label, p)
        }),
        neighbours,
    )
    .into_iter()
    .flat_map(|r| split_by_tops(pts, locals, plane, r, p, &neighbours, &mut patch_of))
    .collect()
}

pub(crate) fn segment_unorganized(
    pts: &[Vec3],
    above: &[bool],
    members: &[usize],
    keep: &[bool],
    locals: &Locals,
    plane: &Plane,
    p: &TabletopParams,
) -> Vec<Vec<usize>> {
    let up = plane.normal;
    let Some(tree) = KdTree::over(pts, members) else {
        return Vec::new();
    };
    let cos_tol = p.concavity_tolerance.cos();
    // As on the image grid: compare a point with neighbours a crease band's width away
    // (`concavity_step` times the typical spacing, taken as a third of the cluster
    // tolerance), not with the nearest ones whose normals blend with its own.
    let r = p.cluster_tolerance * p.concavity_step.max(1) as f64 / 3.0;
    let mut crease = vec![false; pts.len()];
    for &i in members {
        let near = tree.within(&pts[i].to_array(), r * r);
        let (ni, ci) = locals.get(i);
        crease[i] = near.iter().any(|&a| {
            let a = members[a];
            let (na, ca) = locals.get(a);
            pts[a].distance_squared(pts[i]) >= 0.25 * r * r
                && (concave(pts[a], na, pts[i], ni, cos_tol)
                    || step(ca, na, ci, ni, up, cos_tol, p.step_tolerance))
        });
    }
    let tol2 = p.cluster_tolerance * p.cluster_tolerance;
    let neighbours = |i: usize, out: &mut Vec<usize>| {
        out.extend(
            tree.within(&pts[i].to_array(), tol2)
                .into_iter()
                .map(|j| members[j]),
        );
    };
    let mut patch_of = PatchOf::new(pts.len());
    grow(
        pts.len(),
        above,
        keep,
        &crease,
        p.min_object_points,
        None,
        neighbours,
    )
    .into_iter()
    .flat_map(|r| split_by_tops(pts, locals, plane, r, p, &neighbours, &mut patch_of))
    .collect()
}

/// Regions that are one flat, table-parallel surface cut apart only by crease bands:
/// the ledge of a box around a smaller box stacked on it is narrower than the bands on
/// both sides of the crease, so it comes out in pieces. Two regions are one surface
/// when most of each faces up at the same height (within the step tolerance) and some
/// of their points are a few pixels apart with only prism points, and no depth jump,
/// between them — a gap of table between two objects never qualifies.
fn ledge_pairs(
    cloud: &PointCloud,
    above: &[bool],
    locals: &Locals,
    up: Vec3,
    regions: &[Vec<usize>],
    label: &[usize],
    p: &TabletopParams,
) -> Vec<(usize, usize)> {
    let (w, h) = (cloud.width as isize, cloud.height as isize);
    let pts = &cloud.points;
    let cos_tol = p.concavity_tolerance.cos();
    let facing_up = |i: usize| {
        let (n, c) = locals.get(i);
        (n.dot(up).abs() >= cos_tol).then(|| up.dot(c))
    };
    // Each region's top: the median height of its up-facing points, if most face up.
    let tops: Vec<Option<f64>> = regions
        .iter()
        .map(|r| {
            let mut heights: Vec<f64> = r.iter().filter_map(|&i| facing_up(i)).collect();
            if heights.len() * 3 < r.len() || heights.len() < 5 {
                return None;
            }
            let mid = heights.len() / 2;
            Some(*heights.select_nth_unstable_by(mid, f64::total_cmp).1)
        })
        .collect();
    // Crease bands reach `concavity_step` pixels on each side of a crease.
    let reach = 2 * p.concavity_step.max(1) as isize + 1;
    let mut pairs: Vec<(usize, usize)> = Vec::new();
    for (a, r) in regions.iter().enumerate() {
        let Some(top_a) = tops[a] else {
            continue;
        };
        // Only a region's rim can be near another region.
        let rim = |i: usize| {
            let (x, y) = ((i % cloud.width) as isize, (i / cloud.width) as isize);
            [(1, 0), (-1, 0), (0, 1), (0, -1)].iter().any(|&(dx, dy)| {
                let (xx, yy) = (x + dx, y + dy);
                xx < 0 || yy < 0 || xx >= w || yy >= h || label[(yy * w + xx) as usize] != a
            })
        };
        for &i in r.iter().filter(|&&i| rim(i) && facing_up(i).is_some()) {
            let (x, y) = ((i % cloud.width) as isize, (i / cloud.width) as isize);
            for dy in -reach..=reach {
                for dx in -reach..=reach {
                    let (xx, yy) = (x + dx, y + dy);
                    if xx < 0 || yy < 0 || xx >= w || yy >= h {
                        continue;
                    }
                    let j = (yy * w + xx) as usize;
                    let b = label[j];
                    if b == usize::MAX || b <= a || pairs.contains(&(a, b)) {
                        continue;
                    }
                    let Some(top_b) = tops[b] else {
                        continue;
                    };
                    if (top_a - top_b).abs() > p.step_tolerance || facing_up(j).is_none() {
                        continue;
                    }
                    // Walk the pixels from i to j: all prism, no jumps.
                    let steps = dx.abs().max(dy.abs());
                    let mut prev = i;
                    let connected = (1..=steps).all(|k| {
                        let q = ((y + dy * k / steps) * w + x + dx * k / steps) as usize;
                        let ok = above[q] && pts[q].distance(pts[prev]) <= p.cluster_tolerance;
                        prev = q;
                        ok
                    });
                    if connected {
                        pairs.push((a, b));
                    }
                }
            }
        }
    }
    pairs
}

/// Euclidean clustering (PCL's `EuclideanClusterExtraction`): connected components of
/// the points in `mask` linked when closer than `tolerance`, keeping those with at
/// least `min_size` points. Organized clouds link 4-neighbouring pixels; others use a
/// kd-tree radius search. This is the baseline the convexity segmentation improves on.
pub fn euclidean_clusters(
    cloud: &PointCloud,
    mask: Option<&[bool]>,
    tolerance: f64,
    min_size: usize,
) -> Vec<Vec<usize>> {
    let pts = &cloud.points;
    let member: Vec<bool> = (0..pts.len())
        .map(|i| pts[i].is_finite() && mask.is_none_or(|m| m.get(i) == Some(&true)))
        .collect();
    let none = vec![false; pts.len()];
    let tol2 = tolerance * tolerance;
    let regions = if cloud.is_organized() {
        let (w, h) = (cloud.width, cloud.height);
        grow(pts.len(), &member, &member, &none, 0, None, |i, out| {
            let (x, y) = (i % w, i / w);
            for (ok, j) in [
                (x > 0, i.wrapping_sub(1)),
                (x + 1 < w, i + 1),
                (y > 0, i.wrapping_sub(w)),
                (y + 1 < h, i + w),
            ] {
                if ok && pts[i].distance_squared(pts[j]) <= tol2 {
                    out.push(j);
                }
            }
        })
    } else {
        let members: Vec<usize> = (0..pts.len()).filter(|&i| member[i]).collect();
        let Some(tree) = KdTree::over(pts, &members) else {
            return Vec::new();
        };
        grow(pts.len(), &member, &member, &none, 0, None, |i, out| {
            out.extend(
                tree.within(&pts[i].to_array(), tol2)
                    .into_iter()
                    .map(|j| members[j]),
            );
        })
    };
    regions
        .into_iter()
        .filter(|r| r.len() >= min_size)
        .collect()
}
