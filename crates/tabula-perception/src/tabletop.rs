//! Seed 002's tabletop pipeline (SPEC §3.1): outlier removal, the table (first
//! accepted surface of the surface search), its hull, the prism of points above it, and
//! the objects in the prism, segmented by geometry alone so touching and stacked objects
//! come apart.
//!
//! Segmentation is region growing with a convexity cut in the spirit of LCCP, done on
//! points rather than supervoxels: a point lies on a *concave crease* when two points a
//! few neighbours away on either side have normals that differ by more than the
//! concavity tolerance and face each other ((n_a − n_b)·(p_a − p_b) < 0). Objects are
//! convex, so creases are where one object meets another (a box on a box, a box
//! against a taller one). Regions grow over neighbours closer than the cluster
//! tolerance without crossing crease points; crease points then join the region that
//! reaches them first. Depth jumps cut regions apart on their own.

use crate::filters::{NormalParams, OutlierParams, local_planes_at, scatter, statistical_outliers};
use crate::kd::KdTree;
use crate::plane::Plane;
use crate::surfaces::{Surface, SurfaceParams, find_surfaces, plane_basis};
use std::collections::VecDeque;
use std::time::Instant;
use tabula_geom::polygon::{convex_hull_2d, distance_to_boundary, inside_convex, polygon_area};
use tabula_geom::{PointCloud, Pose, Vec2, Vec3};

/// Parameters; defaults from SPEC §6 (seed 002's repository) where it has them.
#[derive(Debug, Clone, serde::Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct TabletopParams {
    /// Run statistical outlier removal first (SPEC §3.1).
    pub remove_outliers: bool,
    /// SPEC §6: mean-K 10, std multiplier 1.0.
    pub outliers: OutlierParams,
    /// Table search: SPEC §1.3/§6 (1 cm RANSAC, 0.09 rad tilt).
    pub surfaces: SurfaceParams,
    pub normals: NormalParams,
    /// Prism points start this far above the table (m).
    pub min_height: f64,
    /// Neighbours closer than this (m) can be one object.
    pub cluster_tolerance: f64,
    /// Normals differing by more than this (rad) across a concave crease cut objects
    /// apart (SPEC §6: 15°).
    pub concavity_tolerance: f64,
    /// How far (pixels, or cluster tolerances when unorganized) on either side of a
    /// point its crease test looks.
    pub concavity_step: usize,
    /// Parallel surfaces on either side of a point offset by more than this (m) along
    /// their normal are a step between two objects (organized clouds).
    pub step_tolerance: f64,
    /// Smallest object (points), SPEC §6: 200.
    pub min_object_points: usize,
    /// Objects must reach this high above the table (m), SPEC §6: 2.5 cm.
    pub min_object_height: f64,
    /// A top surface is the object's points within this distance (m) of its highest
    /// level whose normals are within `max_tilt` of the table's.
    pub top_band: f64,
}

impl Default for TabletopParams {
    fn default() -> Self {
        Self {
            remove_outliers: true,
            outliers: OutlierParams::default(),
            surfaces: SurfaceParams::default(),
            normals: NormalParams::default(),
            min_height: 0.01,
            cluster_tolerance: 0.01,
            concavity_tolerance: 15f64.to_radians(),
            concavity_step: 4,
            step_tolerance: 0.004,
            min_object_points: 200,
            min_object_height: 0.025,
            top_band: 0.01,
        }
    }
}

/// An oriented box.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Obb {
    pub center: Vec3,
    /// Unit axes (right-handed), largest extent first.
    pub axes: [Vec3; 3],
    pub half_extents: Vec3,
}

/// A flat top of an object, parallel to the table.
#[derive(Debug, Clone)]
pub struct TopSurface {
    /// Height above the table (m).
    pub height: f64,
    pub centroid: Vec3,
    /// Convex outline on the top's level (world points).
    pub hull: Vec<Vec3>,
    pub area: f64,
}

/// A segmented object.
#[derive(Debug, Clone)]
pub struct TableObject {
    /// Point indices into the cloud.
    pub indices: Vec<usize>,
    pub centroid: Vec3,
    /// Principal directions (largest variance first, right-handed).
    pub axes: [Vec3; 3],
    /// The first two principal directions of the points projected onto the table
    /// (pushing directions, SPEC §3.1), unit vectors in the table plane.
    pub table_axes: [Vec3; 2],
    /// Oriented box of the points and their projection onto the table, aligned with
    /// the table: the camera sees tops, the object stands on the table.
    pub obb: Obb,
    /// Convex hull of the points plus their projection onto the table (SPEC §3.1):
    /// vertices and triangles.
    pub hull_vertices: Vec<Vec3>,
    pub hull_triangles: Vec<[u32; 3]>,
    /// Footprint on the table: convex outline of the projected points (world points).
    pub footprint: Vec<Vec3>,
    /// Highest point above the table (m).
    pub height: f64,
    pub top: Option<TopSurface>,
}

/// Wall-clock time of each stage (ms).
#[derive(Debug, Clone, Default, serde::Serialize)]
pub struct StageTimes {
    pub outliers: f64,
    pub planes: f64,
    pub prism: f64,
    pub normals: f64,
    pub segmentation: f64,
    pub objects: f64,
}

/// The result of the pipeline.
#[derive(Debug, Clone)]
pub struct Tabletop {
    /// The table as found by the surface search.
    pub table: Surface,
    /// Upward normal facing the camera.
    pub plane: Plane,
    pub objects: Vec<TableObject>,
    /// Points kept by outlier removal.
    pub kept: usize,
    pub times: StageTimes,
}

/// Why no table was found.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum TabletopError {
    #[error("the cloud has no finite points")]
    Empty,
    #[error("no horizontal surface with enough points in the height range")]
    NoTable,
    #[error(transparent)]
    Filter(#[from] crate::filters::FilterError),
}

fn ms(t: Instant) -> f64 {
    t.elapsed().as_secs_f64() * 1e3
}

/// Runs the pipeline on a cloud in the world frame (z up); `viewpoint` is the camera's
/// position in the world (it orients normals and scales outlier statistics).
pub fn extract(
    cloud: &PointCloud,
    viewpoint: Vec3,
    p: &TabletopParams,
) -> Result<Tabletop, TabletopError> {
    let pts = &cloud.points;
    if !pts.iter().any(|q| q.is_finite()) {
        return Err(TabletopError::Empty);
    }
    let mut times = StageTimes::default();
    let t = Instant::now();
    let keep = if p.remove_outliers {
        statistical_outliers(cloud, Some(viewpoint), &p.outliers)?
    } else {
        pts.iter().map(|q| q.is_finite()).collect()
    };
    let kept = keep.iter().filter(|k| **k).count();
    times.outliers = ms(t);

    let t = Instant::now();
    let search = find_surfaces(cloud, Some(&keep), &p.surfaces, true);
    let table = search
        .surfaces
        .into_iter()
        .next()
        .ok_or(TabletopError::NoTable)?;
    times.planes = ms(t);

    // The prism: the side of the plane the camera is on, inside the table's hull.
    let t = Instant::now();
    let plane = if table.plane.distance(viewpoint) < 0.0 {
        table.plane.flipped()
    } else {
        table.plane
    };
    let (u, v) = plane_basis(plane.normal);
    let to2 = |q: Vec3| Vec2::new(q.dot(u), q.dot(v));
    let mut poly: Vec<Vec2> = table.hull.iter().map(|&q| to2(q)).collect();
    if polygon_area(&poly) < 0.0 {
        poly.reverse();
    }
    let threshold = p.surfaces.ransac.threshold;
    let floor = p.min_height.max(threshold);
    // Outlier removal decides what may seed an object, not what may belong to one:
    // points it dropped join an object if they touch it (a real stray point touches
    // nothing), so objects keep their edges.
    let above: Vec<bool> = (0..pts.len())
        .map(|i| {
            pts[i].is_finite()
                && plane.distance(pts[i]) > floor
                && inside_convex(&poly, to2(pts[i]))
        })
        .collect();
    times.prism = ms(t);

    let t = Instant::now();
    let organized = cloud.is_organized();
    let prism: Vec<usize> = (0..pts.len()).filter(|&i| above[i]).collect();
    let mut slot = vec![u32::MAX; pts.len()];
    for (k, &i) in prism.iter().enumerate() {
        slot[i] = k as u32;
    }
    let locals = Locals {
        planes: local_planes_at(cloud, viewpoint, &above, &prism, &p.normals),
        slot,
    };
    times.normals = ms(t);

    let t = Instant::now();
    let labels = if organized {
        segment_organized(cloud, &above, &keep, &locals, plane.normal, p)
            .into_iter()
            .flat_map(|r| split_by_tops(cloud, &locals, &plane, r, p))
            .collect()
    } else {
        segment_unorganized(pts, &above, &prism, &keep, &locals, plane.normal, p)
    };
    times.segmentation = ms(t);

    let t = Instant::now();
    let mut regions: Vec<Vec<usize>> = labels
        .into_iter()
        .filter(|m| m.len() >= p.min_object_points)
        .filter(|m| {
            m.iter()
                .any(|&i| plane.distance(pts[i]) >= p.min_object_height)
        })
        .collect();
    let mut table = table;
    claim_object_bases(pts, &plane, &mut table.inliers, &mut regions, threshold);
    let objects = regions
        .into_iter()
        .map(|indices| describe(pts, &locals, &plane, indices, p))
        .collect();
    times.objects = ms(t);
    Ok(Tabletop {
        table,
        plane,
        objects,
        kept,
        times,
    })
}

/// Points within the plane threshold of the table but under an object's footprint
/// are the object's bottom centimetre, not table: they move to the object.
fn claim_object_bases(
    pts: &[Vec3],
    plane: &Plane,
    table: &mut Vec<usize>,
    regions: &mut [Vec<usize>],
    margin: f64,
) {
    let (u, v) = plane_basis(plane.normal);
    let to2 = |q: Vec3| Vec2::new(q.dot(u), q.dot(v));
    // Footprints grown by a few millimetres of sensor noise.
    let slack = 0.25 * margin;
    let footprints: Vec<(Vec<Vec2>, Vec2, Vec2)> = regions
        .iter()
        .map(|r| {
            let flat: Vec<Vec2> = r.iter().map(|&i| to2(pts[i])).collect();
            let hull: Vec<Vec2> = convex_hull_2d(&flat).into_iter().map(|k| flat[k]).collect();
            let (mut lo, mut hi) = (Vec2::splat(f64::INFINITY), Vec2::splat(f64::NEG_INFINITY));
            for q in &hull {
                lo = lo.min(*q);
                hi = hi.max(*q);
            }
            (hull, lo - Vec2::splat(slack), hi + Vec2::splat(slack))
        })
        .collect();
    let mut moved = false;
    table.retain(|&i| {
        let q = to2(pts[i]);
        let owner = footprints.iter().position(|(hull, lo, hi)| {
            q.cmpge(*lo).all()
                && q.cmple(*hi).all()
                && hull.len() >= 3
                && (inside_convex(hull, q) || distance_to_boundary(hull, q) <= slack)
        });
        if let Some(k) = owner {
            regions[k].push(i);
            moved = true;
        }
        owner.is_none()
    });
    if moved {
        for r in regions.iter_mut() {
            r.sort_unstable();
        }
    }
}

/// Concave-crease test between two points with normals.
fn concave(pa: Vec3, na: Vec3, pb: Vec3, nb: Vec3, cos_tol: f64) -> bool {
    na.is_finite() && nb.is_finite() && na.dot(nb) < cos_tol && (na - nb).dot(pa - pb) < 0.0
}

/// Step test: two flat tops parallel to the table at different heights, side by side
/// (touching objects of different heights). Local-plane centroids average the sensor
/// noise; only table-parallel planes count, because near the edges of side faces the
/// windows mix two faces and their centroids shift.
fn step(ca: Vec3, na: Vec3, cb: Vec3, nb: Vec3, up: Vec3, cos_tol: f64, tolerance: f64) -> bool {
    na.is_finite()
        && nb.is_finite()
        && na.dot(up).abs() >= cos_tol
        && nb.dot(up).abs() >= cos_tol
        && up.dot(ca - cb).abs() > tolerance
}

/// Grows regions over `neighbours` from non-crease seeds, then lets crease points join
/// the region that reaches them first (breadth-first, so they split half-way), then
/// merges regions smaller than `min_size` into their best-connected neighbour.
/// Pairs of regions that are one surface cut apart by crease bands (see
/// [`ledge_pairs`]); given the regions and each point's region.
type SameSurface<'a> = &'a dyn Fn(&[Vec<usize>], &[usize]) -> Vec<(usize, usize)>;

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
struct Locals {
    planes: Vec<(Vec3, Vec3)>,
    /// Point index → position in `planes` (`u32::MAX`: not in the prism).
    slot: Vec<u32>,
}

impl Locals {
    fn get(&self, i: usize) -> (Vec3, Vec3) {
        match self.slot.get(i) {
            Some(&k) if k != u32::MAX => self.planes[k as usize],
            _ => (Vec3::NAN, Vec3::NAN),
        }
    }
}

/// One object per top: a segment holding two flat, table-parallel tops at different
/// heights (two boxes side by side whose front faces are flush, so nothing concave
/// separates them in view) is split, every point going to the lowest top above it
/// whose footprint covers it (or to the nearest footprint). Boxes and cylinders have
/// one top; stacked pieces that the creases already split are untouched.
fn split_by_tops(
    cloud: &PointCloud,
    locals: &Locals,
    plane: &Plane,
    region: Vec<usize>,
    p: &TabletopParams,
) -> Vec<Vec<usize>> {
    let w = cloud.width;
    let pts = &cloud.points;
    let up = plane.normal;
    let cos_tol = p.concavity_tolerance.cos();
    let height_of = |i: usize| -> Option<f64> {
        let (n, c) = locals.get(i);
        (n.dot(up).abs() >= cos_tol).then(|| plane.distance(c))
    };
    let member: rustc_hash::FxHashSet<usize> = region.iter().copied().collect();
    // Patches: 4-connected up-facing points at one height.
    let mut patch_of: rustc_hash::FxHashMap<usize, usize> = rustc_hash::FxHashMap::default();
    let mut patches: Vec<(Vec<usize>, f64)> = Vec::new();
    for &start in &region {
        if patch_of.contains_key(&start) {
            continue;
        }
        let Some(h0) = height_of(start) else {
            continue;
        };
        let id = patches.len();
        patch_of.insert(start, id);
        let (mut stack, mut members, mut heights) = (vec![start], Vec::new(), Vec::new());
        while let Some(i) = stack.pop() {
            members.push(i);
            heights.push(height_of(i).unwrap_or(h0));
            let (x, y) = (i % w, i / w);
            for (ok, j) in [
                (x > 0, i.wrapping_sub(1)),
                (x + 1 < w, i + 1),
                (y > 0, i.wrapping_sub(w)),
                (true, i + w),
            ] {
                if ok
                    && member.contains(&j)
                    && !patch_of.contains_key(&j)
                    && height_of(j).is_some_and(|h| {
                        (h - height_of(i).unwrap_or(h0)).abs() <= p.step_tolerance / 2.0
                    })
                {
                    patch_of.insert(j, id);
                    stack.push(j);
                }
            }
        }
        let mid = heights.len() / 2;
        let median = *heights.select_nth_unstable_by(mid, f64::total_cmp).1;
        patches.push((members, median));
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

fn segment_organized(
    cloud: &PointCloud,
    above: &[bool],
    keep: &[bool],
    locals: &Locals,
    up: Vec3,
    p: &TabletopParams,
) -> Vec<Vec<usize>> {
    let (w, h) = (cloud.width, cloud.height);
    let pts = &cloud.points;
    let s = p.concavity_step.max(1) as isize;
    let cos_tol = p.concavity_tolerance.cos();
    let reach = p.cluster_tolerance * 2.0 * s as f64;
    let at = |x: isize, y: isize| -> Option<usize> {
        (x >= 0 && y >= 0 && (x as usize) < w && (y as usize) < h)
            .then(|| y as usize * w + x as usize)
    };
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
                above[a]
                    && above[b]
                    && pts[a].distance(pts[b]) <= reach
                    && (concave(pts[a], na, pts[b], nb, cos_tol)
                        || step(ca, na, cb, nb, up, cos_tol, p.step_tolerance))
            })
        })
        .collect();
    let tol2 = p.cluster_tolerance * p.cluster_tolerance;
    grow(
        pts.len(),
        above,
        keep,
        &crease,
        p.min_object_points,
        Some(&|regions: &[Vec<usize>], label: &[usize]| {
            ledge_pairs(cloud, above, locals, up, regions, label, p)
        }),
        |i, out| {
            let (x, y) = ((i % w) as isize, (i / w) as isize);
            for (dx, dy) in [(1, 0), (-1, 0), (0, 1), (0, -1)] {
                if let Some(j) = at(x + dx, y + dy)
                    && pts[i].distance_squared(pts[j]) <= tol2
                {
                    out.push(j);
                }
            }
        },
    )
}

fn segment_unorganized(
    pts: &[Vec3],
    above: &[bool],
    members: &[usize],
    keep: &[bool],
    locals: &Locals,
    up: Vec3,
    p: &TabletopParams,
) -> Vec<Vec<usize>> {
    let coords: Vec<[f64; 3]> = members.iter().map(|&i| pts[i].to_array()).collect();
    let Some(tree) = KdTree::build(&coords) else {
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
    grow(
        pts.len(),
        above,
        keep,
        &crease,
        p.min_object_points,
        None,
        |i, out| {
            out.extend(
                tree.within(&pts[i].to_array(), tol2)
                    .into_iter()
                    .map(|j| members[j]),
            );
        },
    )
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

/// Centroid, principal axes, table-aligned box, hull with the table projection, and
/// top surface of one object.
fn describe(
    pts: &[Vec3],
    locals: &Locals,
    plane: &Plane,
    indices: Vec<usize>,
    p: &TabletopParams,
) -> TableObject {
    let points: Vec<Vec3> = indices.iter().map(|&i| pts[i]).collect();
    let (centroid, m) = scatter(points.iter().copied()).unwrap_or((points[0], [0.0; 6]));
    let axes = principal_axes(m);
    let up = plane.normal;
    let (u, v) = plane_basis(up);
    // PCA of the projection onto the table: a 2×2 eigenproblem in the plane basis.
    let (mut suu, mut suv, mut svv) = (0.0, 0.0, 0.0);
    for q in &points {
        let d = *q - centroid;
        let (a, b) = (d.dot(u), d.dot(v));
        suu += a * a;
        suv += a * b;
        svv += b * b;
    }
    let angle = 0.5 * (2.0 * suv).atan2(suu - svv);
    let major = u * angle.cos() + v * angle.sin();
    let minor = up.cross(major);
    // Footprint and box in the (major, minor, up) frame.
    let projected: Vec<Vec2> = points
        .iter()
        .map(|q| Vec2::new(q.dot(major), q.dot(minor)))
        .collect();
    let hull2: Vec<usize> = convex_hull_2d(&projected);
    let heights: Vec<f64> = points.iter().map(|q| plane.distance(*q)).collect();
    let height = heights.iter().copied().fold(0.0, f64::max);
    let (mut lo, mut hi) = (Vec2::splat(f64::INFINITY), Vec2::splat(f64::NEG_INFINITY));
    for &k in &hull2 {
        lo = lo.min(projected[k]);
        hi = hi.max(projected[k]);
    }
    let on_table = |q: Vec3| q - up * plane.distance(q);
    let mid = (lo + hi) / 2.0;
    let base = on_table(centroid);
    let base = base + major * (mid.x - base.dot(major)) + minor * (mid.y - base.dot(minor));
    let (size, box_axes) = if hi.x - lo.x >= hi.y - lo.y {
        (
            Vec3::new((hi.x - lo.x) / 2.0, (hi.y - lo.y) / 2.0, height / 2.0),
            [major, minor, up],
        )
    } else {
        (
            Vec3::new((hi.y - lo.y) / 2.0, (hi.x - lo.x) / 2.0, height / 2.0),
            [minor, -major, up],
        )
    };
    let obb = Obb {
        center: base + up * (height / 2.0),
        axes: box_axes,
        half_extents: size,
    };
    let footprint: Vec<Vec3> = hull2.iter().map(|&k| on_table(points[k])).collect();
    // 3D hull of the points and their shadow on the table: the hull of the points'
    // own hull vertices and the footprint is the same body, from far fewer points.
    let mut body: Vec<Vec3> = footprint.clone();
    body.extend(points.iter().copied());
    let (hull_vertices, hull_triangles) =
        tabula_geom::parry::transformation::try_convex_hull(&body).unwrap_or_default();
    // Top: points near the highest level with table-parallel normals.
    let cos_tilt = p.surfaces.max_tilt.max(0.2).cos();
    let top_idx: Vec<usize> = (0..points.len())
        .filter(|&k| {
            heights[k] >= height - p.top_band && locals.get(indices[k]).0.dot(up).abs() >= cos_tilt
        })
        .collect();
    let top = (top_idx.len() >= 10).then(|| {
        let level = top_idx.iter().map(|&k| heights[k]).sum::<f64>() / top_idx.len() as f64;
        let flat: Vec<Vec2> = top_idx.iter().map(|&k| projected[k]).collect();
        let h: Vec<usize> = convex_hull_2d(&flat);
        let outline: Vec<Vec2> = h.iter().map(|&k| flat[k]).collect();
        let at_level = |k: usize| on_table(points[top_idx[k]]) + up * level;
        TopSurface {
            height: level,
            centroid: top_idx.iter().map(|&k| points[k]).sum::<Vec3>() / top_idx.len() as f64,
            hull: h.iter().map(|&k| at_level(k)).collect(),
            area: polygon_area(&outline).abs(),
        }
    });
    TableObject {
        indices,
        centroid,
        axes,
        table_axes: [major, minor],
        obb,
        hull_vertices,
        hull_triangles,
        footprint,
        height,
        top,
    }
}

/// Unit principal directions of a scatter matrix, largest variance first,
/// right-handed.
fn principal_axes(m: [f64; 6]) -> [Vec3; 3] {
    let a = nalgebra::Matrix3::new(m[0], m[1], m[2], m[1], m[3], m[4], m[2], m[4], m[5]);
    let eig = nalgebra::SymmetricEigen::new(a);
    let mut order = [0usize, 1, 2];
    order.sort_by(|&x, &y| eig.eigenvalues[y].total_cmp(&eig.eigenvalues[x]));
    let axis = |k: usize| {
        let c = eig.eigenvectors.column(order[k]);
        Vec3::new(c[0], c[1], c[2]).normalize_or(Vec3::X)
    };
    let (a0, a1) = (axis(0), axis(1));
    [a0, a1, a0.cross(a1).normalize_or(Vec3::Z)]
}

/// Transforms a camera-frame cloud into the world frame, keeping its grid.
pub fn to_world(world_from_camera: &Pose, camera: &PointCloud) -> PointCloud {
    camera.transformed(world_from_camera)
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
        let coords: Vec<[f64; 3]> = members.iter().map(|&i| pts[i].to_array()).collect();
        let Some(tree) = KdTree::build(&coords) else {
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn params_load_from_toml_with_the_seed_defaults_elsewhere() {
        let p: TabletopParams = toml::from_str(
            "min_object_points = 150\n[outliers]\nmean_k = 20\nstd_mul = 2.0\n[surfaces.ransac]\nthreshold = 0.015\n",
        )
        .unwrap();
        assert_eq!(p.min_object_points, 150);
        assert_eq!(p.outliers.mean_k, 20);
        assert_eq!(p.surfaces.ransac.threshold, 0.015);
        // Untouched keys keep SPEC §6's values.
        assert_eq!(p.surfaces.max_tilt, 0.09);
        assert_eq!(p.surfaces.min_plane_fraction, 0.05);
        assert!((p.concavity_tolerance - 15f64.to_radians()).abs() < 1e-12);
        assert!(toml::from_str::<TabletopParams>("no_such_key = 1").is_err());
    }
}
