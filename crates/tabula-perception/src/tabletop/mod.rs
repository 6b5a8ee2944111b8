//! Seed 002's tabletop pipeline (SPEC §3.1): outlier removal, the table (first
//! accepted surface of the surface search), its hull, the prism of points above it, and
//! the objects in the prism, segmented by geometry alone so touching and stacked objects
//! come apart.
//!
//! The segmentation itself lives in [`crate::segment`].

mod containers;
mod describe;
mod edges;
mod enclosed;
mod joins;
mod occluded;
mod parts;
mod prism;
mod stride;

use describe::describe;
use edges::{DataEdge, ImageBorder, set_apart_pieces_of_partial};

use crate::filters::{local_planes_at, statistical_outliers};
pub use crate::params::TabletopParams;
use crate::plane::Plane;
use crate::segment::{Locals, segment_organized, segment_unorganized};
use crate::surfaces::{Surface, find_surfaces, plane_basis, surfaces_on};
use std::time::Instant;
use tabula_geom::polygon::{convex_hull_2d, min_area_rectangle};
use tabula_geom::{PointCloud, Pose, Vec2, Vec3};

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
    /// the table (the camera sees tops, the object stands on the table): the
    /// footprint's minimal-area rectangle (rotating calipers) from the table up to the
    /// object's highest point.
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
    /// Carrying a coarse grid's segments to every pixel (`frame_stride` > 1).
    pub expand: f64,
}

/// The result of the pipeline.
#[derive(Debug, Clone)]
pub struct Tabletop {
    /// The table as found by the surface search.
    pub table: Surface,
    /// Upward normal facing the camera.
    pub plane: Plane,
    pub objects: Vec<TableObject>,
    /// Objects cut by the border of an organized frame (inside the sensor's margin of
    /// missing depth; not where the scene has no depth): only part of each is in view,
    /// so its size and centre are not the object's (obstacles still).
    pub partial: Vec<TableObject>,
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
/// position in the world (it orients normals and scales outlier statistics). The
/// table is the first surface the surface search accepts.
pub fn extract(
    cloud: &PointCloud,
    viewpoint: Vec3,
    p: &TabletopParams,
) -> Result<Tabletop, TabletopError> {
    extract_from(cloud, viewpoint, None, p)
}

/// As [`extract`] on a table whose plane is already known (the support found by
/// [`crate::support::find_support`], in the cloud's frame): its biggest flat piece.
pub fn extract_on(
    cloud: &PointCloud,
    viewpoint: Vec3,
    table: Plane,
    p: &TabletopParams,
) -> Result<Tabletop, TabletopError> {
    extract_from(cloud, viewpoint, Some(table), p)
}

/// The pipeline on a cloud already moved into its [`Framing`]'s world frame: the table
/// is the support when the frame was built on one (at z = 0, facing up), else the
/// first surface the search accepts.
pub fn extract_framed(
    cloud: &PointCloud,
    framing: &crate::support::Framing,
    p: &TabletopParams,
) -> Result<Tabletop, TabletopError> {
    let support = framing.support.as_ref().map(|_| Plane {
        normal: Vec3::Z,
        d: 0.0,
    });
    extract_from(cloud, framing.eye, support, p)
}

/// `cloud` with every point after the first in each `leaf`-sized voxel made NaN (so
/// indices into it still hold), or `None` when it is organized or has no duplicate.
fn without_duplicates(cloud: &PointCloud, leaf: f64) -> Option<PointCloud> {
    if cloud.is_organized() || leaf.is_nan() || leaf <= 0.0 {
        return None;
    }
    let mut seen = rustc_hash::FxHashSet::default();
    let mut out: Option<PointCloud> = None;
    for (i, q) in cloud.points.iter().enumerate() {
        if q.is_finite() && !seen.insert(tabula_geom::voxel_key(*q, leaf)) {
            out.get_or_insert_with(|| cloud.clone()).points[i] = Vec3::NAN;
        }
    }
    out
}

/// The pipeline, on every `frame_stride`-th pixel of an organized frame's grid when
/// the stride is above 1 (see [`stride`]).
fn extract_from(
    cloud: &PointCloud,
    viewpoint: Vec3,
    known: Option<Plane>,
    p: &TabletopParams,
) -> Result<Tabletop, TabletopError> {
    let step = p.frame_stride.max(1);
    if step == 1 || !cloud.is_organized() {
        return run(cloud, viewpoint, known, p).map(|(t, _)| t);
    }
    let coarse = cloud.decimated(step);
    let (t, keep) = run(&coarse, viewpoint, known, &p.at_stride(step))?;
    let started = Instant::now();
    let mut t = stride::expand(cloud, step, t, &keep, viewpoint, p);
    t.times.expand = ms(started);
    Ok(t)
}

/// The pipeline on every point; the outlier mask with its answer.
fn run(
    cloud: &PointCloud,
    viewpoint: Vec3,
    known: Option<Plane>,
    p: &TabletopParams,
) -> Result<(Tabletop, Vec<bool>), TabletopError> {
    let unique = without_duplicates(cloud, p.duplicate_leaf);
    let cloud = unique.as_ref().unwrap_or(cloud);
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
    // The table is its biggest piece; objects stand on any piece of it (a support
    // found in the scene is seen in pieces between the objects that hide it, and a
    // crowded front row may stand on a strip far from the biggest one).
    let (table, outline) = match known {
        Some(plane) => {
            let pieces = surfaces_on(cloud, Some(&keep), plane, &p.surfaces);
            let outline = outline_of(&pieces);
            (pieces.into_iter().next(), outline)
        }
        None => {
            let found = find_surfaces(cloud, Some(&keep), &p.surfaces, true);
            let table = found.surfaces.into_iter().next();
            let outline = table.as_ref().map_or_else(Vec::new, |t| t.hull.clone());
            (table, outline)
        }
    };
    let mut table = table.ok_or(TabletopError::NoTable)?;
    times.planes = ms(t);

    // The prism: the side of the plane the camera is on, inside the table's hull.
    let t = Instant::now();
    let plane = if table.plane.distance(viewpoint) < 0.0 {
        table.plane.flipped()
    } else {
        table.plane
    };
    let threshold = table.threshold.max(p.surfaces.ransac.threshold);
    let floor = p.min_height.max(threshold);
    let reach = if known.is_some() {
        p.support_reach
    } else {
        0.0
    };
    let above = prism::above(pts, (&plane, &outline), (floor, reach));
    times.prism = ms(t);

    let t = Instant::now();
    let organized = cloud.is_organized();
    let prism: Vec<usize> = (0..pts.len()).filter(|&i| above[i]).collect();
    let voxels = prism::voxel_carriers(pts, &prism, organized, p);
    let (carriers, carrier_of): (&[usize], Option<&Vec<usize>>) = match &voxels {
        Some((c, of)) => (c, Some(of)),
        None => (&prism, None),
    };
    let locals = Locals {
        planes: local_planes_at(cloud, viewpoint, &above, carriers, &p.normals),
        slot: prism::slots(pts.len(), &prism, (carriers, carrier_of)),
    };
    times.normals = ms(t);

    let t = Instant::now();
    let seen = Seen {
        pts,
        keep: &keep,
        locals: &locals,
        plane: &plane,
        grid: organized.then_some(cloud.width),
        viewpoint,
    };
    let labels = match carrier_of {
        None if organized => segment_organized(cloud, viewpoint, &above, &keep, &locals, &plane, p),
        None => segment_unorganized(pts, &above, &prism, &keep, &locals, &plane, p),
        Some(carrier_of) => seen.segment_by_carriers(&prism, (carriers, carrier_of), p),
    };
    let labels = if organized {
        let joined = occluded::join_occluded(pts, cloud.width, viewpoint, &plane, labels);
        let joined = containers::join_insides(pts, cloud.width, &plane, joined);
        enclosed::join_enclosed(pts, cloud.width, joined, p.min_object_points)
    } else {
        labels
    };
    times.segmentation = ms(t);

    let t = Instant::now();
    let edges = organized.then(|| (DataEdge::of(cloud), ImageBorder::of(cloud)));
    let (objects, partial) = seen.objects(labels, (&mut table, threshold), (known, edges), p);
    times.objects = ms(t);
    let tabletop = Tabletop {
        table,
        plane,
        objects,
        partial,
        kept,
        times,
    };
    Ok((tabletop, keep))
}

/// The convex outline (world points) around every piece of a surface.
fn outline_of(pieces: &[Surface]) -> Vec<Vec3> {
    let corners: Vec<Vec3> = pieces.iter().flat_map(|s| s.hull.iter().copied()).collect();
    let Some(first) = pieces.first() else {
        return Vec::new();
    };
    let (u, v) = plane_basis(first.plane.normal);
    let flat: Vec<Vec2> = corners
        .iter()
        .map(|q| Vec2::new(q.dot(u), q.dot(v)))
        .collect();
    convex_hull_2d(&flat)
        .into_iter()
        .map(|k| corners[k])
        .collect()
}

/// A frame's points as segmentation sees them: which passed outlier removal, their
/// local planes, the table's plane.
struct Seen<'a> {
    pts: &'a [Vec3],
    keep: &'a [bool],
    locals: &'a Locals,
    plane: &'a Plane,
    /// The sensor's grid width when the cloud is organized, and where the sensor is.
    grid: Option<usize>,
    viewpoint: Vec3,
}

impl Seen<'_> {
    /// Segments the voxels' carriers, then gives every prism point its carrier's
    /// region. Sizes count carriers: the prism's points per carrier scale the minimum.
    fn segment_by_carriers(
        &self,
        prism: &[usize],
        (carriers, carrier_of): (&[usize], &[usize]),
        p: &TabletopParams,
    ) -> Vec<Vec<usize>> {
        let n = self.pts.len();
        let mut carries = vec![false; n];
        for &i in carriers {
            carries[i] = true;
        }
        let per_carrier = prism.len() as f64 / carriers.len().max(1) as f64;
        let scaled = TabletopParams {
            min_object_points: ((p.min_object_points as f64 / per_carrier).ceil() as usize).max(1),
            ..p.clone()
        };
        let (pts, keep, locals, plane) = (self.pts, self.keep, self.locals, self.plane);
        let regions = segment_unorganized(pts, &carries, carriers, keep, locals, plane, &scaled);
        let mut region_of = vec![usize::MAX; n];
        for (r, members) in regions.iter().enumerate() {
            for &i in members {
                region_of[i] = r;
            }
        }
        let mut expanded = vec![Vec::new(); regions.len()];
        for &i in prism {
            let r = region_of[carrier_of[i]];
            if r != usize::MAX {
                expanded[r].push(i);
            }
        }
        expanded
    }

    /// The regions that are objects (big and tall enough; standing, around a support
    /// found without a pose), their bases claimed from the table, described; those
    /// reaching the image's border set apart as partly seen.
    fn objects(
        &self,
        labels: Vec<Vec<usize>>,
        (table, threshold): (&mut Surface, f64),
        (known, edges): (Option<Plane>, Option<(DataEdge, ImageBorder)>),
        p: &TabletopParams,
    ) -> (Vec<TableObject>, Vec<TableObject>) {
        let (pts, plane) = (self.pts, self.plane);
        let mut regions: Vec<Vec<usize>> = labels
            .into_iter()
            .filter(|m| m.len() >= p.min_object_points)
            .filter(|m| {
                m.iter()
                    .any(|&i| plane.distance(pts[i]) >= p.min_object_height)
            })
            .collect();
        if known.is_some() {
            let occluded = self.grid.map(|width| (width, self.viewpoint));
            let edge = edges.as_ref().map(|(data, _)| data);
            regions = standing(pts, plane, regions, (threshold, occluded, edge), p);
        }
        if let Some(width) = self.grid {
            regions = parts::join_parts(pts, width, (self.locals, plane), regions);
        }
        claim_object_bases(pts, plane, &mut table.inliers, &mut regions, threshold);
        let (mut partial, mut objects): (Vec<TableObject>, Vec<TableObject>) = regions
            .into_iter()
            .map(|indices| describe(pts, self.locals, plane, indices, p))
            .partition(|o| {
                edges
                    .as_ref()
                    .is_some_and(|(_, border)| o.indices.iter().any(|&i| border.near(i)))
            });
        set_apart_pieces_of_partial(pts, &mut objects, &mut partial, p.partial_gap);
        (objects, partial)
    }
}

/// Around a support found without a world pose, the regions that are objects standing
/// on it: no wider or taller than `max_object_extent` (walls and rows of furniture seen
/// at a floor's edge are background), and resting — their lowest points reach down to
/// the support, or to the top of a resting region under them (a stack), or (on a
/// sensor's grid, `occluded` = its width and the sensor) they are hidden below by a
/// nearer region (an object standing behind another), or the frame's `edge` cuts them
/// at their lowest; a cluster hanging in the air is part of something else.
fn standing(
    pts: &[Vec3],
    plane: &Plane,
    regions: Vec<Vec<usize>>,
    (threshold, occluded, edge): (f64, Option<(usize, Vec3)>, Option<&DataEdge>),
    p: &TabletopParams,
) -> Vec<Vec<usize>> {
    let (u, v) = plane_basis(plane.normal);
    let extents: Vec<parts::Extent> = regions
        .iter()
        .map(|r| parts::Extent::of(pts, plane, r))
        .collect();
    let small = |k: usize| {
        let flat: Vec<Vec2> = regions[k]
            .iter()
            .map(|&i| Vec2::new(pts[i].dot(u), pts[i].dot(v)))
            .collect();
        let wide = min_area_rectangle(&flat).map_or(0.0, |r| r.size.max_element());
        wide <= p.max_object_extent && extents[k].highest <= p.max_object_extent
    };
    let mut order: Vec<usize> = (0..regions.len()).filter(|&k| small(k)).collect();
    order.sort_by(|&a, &b| extents[a].lowest.total_cmp(&extents[b].lowest));
    let ground = p.min_height.max(threshold) + p.rest_tolerance;
    // Each region's highest point per 2 cm column: what something could rest on.
    const COLUMN: f64 = 0.02;
    let column = |i: usize| {
        let q = pts[i];
        [
            (q.dot(u) / COLUMN).floor() as i64,
            (q.dot(v) / COLUMN).floor() as i64,
        ]
    };
    let tops: Vec<rustc_hash::FxHashMap<[i64; 2], f64>> = regions
        .iter()
        .map(|r| {
            let mut m = rustc_hash::FxHashMap::default();
            for &i in r {
                let h = plane.distance(pts[i]);
                let top = m.entry(column(i)).or_insert(h);
                *top = f64::max(*top, h);
            }
            m
        })
        .collect();
    let mut resting: Vec<usize> = Vec::new();
    // Each point's region, for the occlusion test (made when first needed).
    let region_of = std::cell::OnceCell::new();
    for k in order {
        let e = &extents[k];
        // Resting on a region: some of this one's bottom points have that region's top
        // right beside or under them at their own height (a box on a box), not its side
        // rising past them (a strip cut off an object's face).
        // Or its lowest points at the height of that region's top over the same ground
        // (a box lying across another, overhanging it towards the camera: the top it
        // rests on is hidden under it, the bottom edge seen is in the air).
        let on = |r: &usize| {
            let under = &extents[*r];
            let overlap = e.lo.cmple(under.hi).all() && under.lo.cmple(e.hi).all();
            let across = (e.lowest - under.highest).abs() <= p.rest_tolerance;
            overlap
                && (across
                    || regions[k].iter().any(|&i| {
                        let h = plane.distance(pts[i]);
                        let c = column(i);
                        h <= e.lowest + p.rest_tolerance
                            && (-1..=1).any(|dx| {
                                (-1..=1).any(|dy| {
                                    tops[*r]
                                        .get(&[c[0] + dx, c[1] + dy])
                                        .is_some_and(|t| (h - t).abs() <= p.rest_tolerance)
                                })
                            })
                    }))
        };
        // On the support; or on a resting region and, as an object must be above the
        // table, at least `min_stacked_height` tall above what it rests on.
        let stacked = e.highest - e.lowest >= p.min_stacked_height && resting.iter().any(on);
        let hidden = || {
            occluded.is_some_and(|(width, sensor)| {
                let bottom = e.lowest + p.rest_tolerance;
                let region_of = region_of.get_or_init(|| joins::labels(pts.len(), &regions));
                let grid = (region_of.as_slice(), width, sensor);
                bottom_occluded(pts, &regions[k], k, grid, |i| {
                    plane.distance(pts[i]) <= bottom
                })
            })
        };
        // Cut by the frame's edge at its lowest: what it stands on is out of view (a
        // book at the bottom of the image shows its top only).
        let cut = || {
            edge.is_some_and(|edge| {
                regions[k]
                    .iter()
                    .any(|&i| edge.near(i) && plane.distance(pts[i]) <= e.lowest + p.rest_tolerance)
            })
        };
        if e.lowest <= ground || stacked || hidden() || cut() {
            resting.push(k);
        }
    }
    resting.sort_unstable();
    let mut regions: Vec<Option<Vec<usize>>> = regions.into_iter().map(Some).collect();
    resting
        .into_iter()
        .filter_map(|k| regions[k].take())
        .collect()
}

/// Whether most of region `k`'s bottom points (`is_bottom`) have, within 3 pixels on the
/// sensor's grid, a point of another region (`region_of` each point, `u32::MAX` none)
/// at least 1 cm nearer the sensor: what held the region up is hidden behind that one.
fn bottom_occluded(
    pts: &[Vec3],
    region: &[usize],
    k: usize,
    (region_of, width, sensor): (&[u32], usize, Vec3),
    is_bottom: impl Fn(usize) -> bool,
) -> bool {
    const RADIUS: i64 = 3;
    let other = |j: usize| region_of[j] != u32::MAX && region_of[j] as usize != k;
    let (w, n) = (width as i64, pts.len() as i64);
    let (mut bottom, mut hidden) = (0usize, 0usize);
    for &i in region.iter().filter(|&&i| is_bottom(i)) {
        bottom += 1;
        let depth = pts[i].distance(sensor);
        let (x, y) = (i as i64 % w, i as i64 / w);
        let nearer = (-RADIUS..=RADIUS).any(|dy| {
            (-RADIUS..=RADIUS).any(|dx| {
                let (nx, ny) = (x + dx, y + dy);
                let j = ny * w + nx;
                (0..w).contains(&nx)
                    && (0..n).contains(&j)
                    && other(j as usize)
                    && pts[j as usize].distance(sensor) < depth - 0.01
            })
        });
        hidden += usize::from(nearer);
    }
    bottom > 0 && 2 * hidden >= bottom
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
    // Each footprint as its edges' outward unit normals and offsets: a point is within
    // `slack` of the convex footprint (up to its corners' rounding) when no edge has it
    // farther out than that — a few multiply-adds with an early exit, no square roots.
    type Footprint = (Vec<(Vec2, f64)>, Vec2, Vec2);
    let footprints: Vec<Footprint> = regions
        .iter()
        .map(|r| {
            let flat: Vec<Vec2> = r.iter().map(|&i| to2(pts[i])).collect();
            let hull: Vec<Vec2> = convex_hull_2d(&flat).into_iter().map(|k| flat[k]).collect();
            let (mut lo, mut hi) = (Vec2::splat(f64::INFINITY), Vec2::splat(f64::NEG_INFINITY));
            for q in &hull {
                lo = lo.min(*q);
                hi = hi.max(*q);
            }
            let n = hull.len();
            let edges = if n >= 3 {
                (0..n)
                    .filter_map(|k| {
                        let outward = -(hull[(k + 1) % n] - hull[k]).perp().try_normalize()?;
                        Some((outward, outward.dot(hull[k]) + slack))
                    })
                    .collect()
            } else {
                Vec::new()
            };
            (edges, lo - Vec2::splat(slack), hi + Vec2::splat(slack))
        })
        .collect();
    let mut moved = false;
    table.retain(|&i| {
        let q = to2(pts[i]);
        let owner = footprints.iter().position(|(edges, lo, hi)| {
            q.cmpge(*lo).all()
                && q.cmple(*hi).all()
                && !edges.is_empty()
                && edges.iter().all(|(n, off)| n.dot(q) <= *off)
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

/// Transforms a camera-frame cloud into the world frame, keeping its grid.
pub fn to_world(world_from_camera: &Pose, camera: &PointCloud) -> PointCloud {
    camera.transformed(world_from_camera)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A decimated frame's parameters cover as much of a surface as the full frame's:
    /// counts by the stride², pixel steps and windows by the stride (rounded up), the
    /// crease reach in sensor pixels; decimating twice compounds.
    #[test]
    fn parameters_at_a_stride_keep_their_meaning_in_metres() {
        let full = TabletopParams::default();
        let half = full.at_stride(2);
        assert_eq!(half.min_object_points, full.min_object_points / 4);
        assert_eq!(half.concavity_step, full.concavity_step / 2);
        assert_eq!(half.normals.window, full.normals.window.div_ceil(2));
        assert_eq!((half.pixel_spacing, half.frame_stride), (2, 1));
        let quarter = half.at_stride(2);
        assert_eq!((quarter.pixel_spacing, quarter.concavity_step), (4, 1));
        assert_eq!(full.at_stride(1).normals.window, full.normals.window);
    }

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
        assert_eq!(p.surfaces.min_plane_points, 30);
        assert!((p.concavity_tolerance - 25f64.to_radians()).abs() < 1e-12);
        assert!(toml::from_str::<TabletopParams>("no_such_key = 1").is_err());
    }
}
