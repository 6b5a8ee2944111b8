//! One object's description: centroid and principal axes, a box aligned with the table
//! (the footprint's minimal-area rectangle, robust to the sensor's noise), its hull
//! with its shadow on the table, and its flat top.

use super::{Obb, TableObject, TabletopParams, TopSurface};
use crate::filters::scatter;
use crate::plane::Plane;
use crate::segment::Locals;
use crate::surfaces::plane_basis;
use tabula_geom::polygon::{Rectangle, convex_hull_2d, min_area_rectangle_of_hull, polygon_area};
use tabula_geom::{Vec2, Vec3};

/// An object's points in the table's frame: the major and minor axes of their
/// projection onto the table, the points there, and their heights above it.
struct OnTable<'a> {
    plane: &'a Plane,
    points: Vec<Vec3>,
    major: Vec3,
    minor: Vec3,
    projected: Vec<Vec2>,
    heights: Vec<f64>,
}

impl<'a> OnTable<'a> {
    fn new(plane: &'a Plane, points: Vec<Vec3>, centroid: Vec3) -> Self {
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
        let projected = points
            .iter()
            .map(|q| Vec2::new(q.dot(major), q.dot(minor)))
            .collect();
        let heights = points.iter().map(|q| plane.distance(*q)).collect();
        Self {
            plane,
            points,
            major,
            minor,
            projected,
            heights,
        }
    }

    fn on_table(&self, q: Vec3) -> Vec3 {
        q - self.plane.normal * self.plane.distance(q)
    }

    /// The footprint's minimal-area rectangle (a PCA frame turns a square 45° and makes
    /// it √2 too big), its extents from the 0.5 % and 99.5 % quantiles along its sides:
    /// the extreme points are the sensor noise's tails (2–3 σ out on every side), not
    /// the object's edge.
    fn rectangle(&self, hull2: &[usize]) -> Rectangle {
        let projected = &self.projected;
        let hull_flat: Vec<Vec2> = hull2.iter().map(|&k| projected[k]).collect();
        let rect = min_area_rectangle_of_hull(&hull_flat).unwrap_or_else(|| {
            let (mut lo, mut hi) = (Vec2::splat(f64::INFINITY), Vec2::splat(f64::NEG_INFINITY));
            for q in projected {
                lo = lo.min(*q);
                hi = hi.max(*q);
            }
            Rectangle {
                center: (lo + hi) / 2.0,
                axis: Vec2::X,
                size: hi - lo,
            }
        });
        let perp = rect.axis.perp();
        let robust = |d: Vec2| {
            let mut v: Vec<f64> = projected.iter().map(|q| q.dot(d)).collect();
            let n = v.len();
            let k = n / 200;
            let lo = *v.select_nth_unstable_by(k, f64::total_cmp).1;
            let hi = *v.select_nth_unstable_by(n - 1 - k, f64::total_cmp).1;
            (lo, hi)
        };
        let ((a0, a1), (b0, b1)) = (robust(rect.axis), robust(perp));
        Rectangle {
            center: rect.axis * (a0 + a1) / 2.0 + perp * (b0 + b1) / 2.0,
            axis: rect.axis,
            size: Vec2::new(a1 - a0, b1 - b0),
        }
    }

    /// The box on the footprint's rectangle, as high as the 99.5 % quantile of the
    /// heights, its long side first.
    fn obb(&self, rect: &Rectangle, centroid: Vec3) -> Obb {
        let up = self.plane.normal;
        let (major, minor) = (self.major, self.minor);
        let box_height = {
            let mut h = self.heights.clone();
            let k = h.len() - 1 - h.len() / 200;
            *h.select_nth_unstable_by(k, f64::total_cmp).1
        };
        let along = |d: Vec2| major * d.x + minor * d.y;
        let base = self.on_table(centroid);
        let base = base
            + major * (rect.center.x - base.dot(major))
            + minor * (rect.center.y - base.dot(minor));
        let (first, second) = (along(rect.axis), along(rect.axis.perp()));
        let (size, box_axes) = if rect.size.x >= rect.size.y {
            (
                Vec3::new(rect.size.x / 2.0, rect.size.y / 2.0, box_height / 2.0),
                [first, second, up],
            )
        } else {
            (
                Vec3::new(rect.size.y / 2.0, rect.size.x / 2.0, box_height / 2.0),
                [second, -first, up],
            )
        };
        Obb {
            center: base + up * (box_height / 2.0),
            axes: box_axes,
            half_extents: size,
        }
    }

    /// 3D hull of the points and their shadow on the table: the hull of the points'
    /// own hull vertices and the footprint is the same body, from far fewer points.
    /// Only the highest point of each 5 mm column can be a vertex of that body (the
    /// rest lie between it and its shadow), up to the column's width: tens of
    /// thousands of points become a few thousand.
    fn body_hull(&self, footprint: &[Vec3]) -> (Vec<Vec3>, Vec<[u32; 3]>) {
        let mut columns: rustc_hash::FxHashMap<[i64; 2], usize> = Default::default();
        for (k, q) in self.projected.iter().enumerate() {
            let key = [(q.x / 0.005).floor() as i64, (q.y / 0.005).floor() as i64];
            let top = columns.entry(key).or_insert(k);
            if self.heights[k] > self.heights[*top] {
                *top = k;
            }
        }
        let mut body: Vec<Vec3> = footprint.to_vec();
        body.extend(columns.values().map(|&k| self.points[k]));
        tabula_geom::parry::transformation::try_convex_hull(&body).unwrap_or_default()
    }

    /// The top: points near the highest level with table-parallel normals.
    fn top(&self, indices: &[usize], locals: &Locals, p: &TabletopParams) -> Option<TopSurface> {
        let up = self.plane.normal;
        let height = self.heights.iter().copied().fold(0.0, f64::max);
        let cos_tilt = p.surfaces.max_tilt.max(0.2).cos();
        let top_idx: Vec<usize> = (0..self.points.len())
            .filter(|&k| {
                self.heights[k] >= height - p.top_band
                    && locals.get(indices[k]).0.dot(up).abs() >= cos_tilt
            })
            .collect();
        (top_idx.len() >= 10).then(|| {
            let level =
                top_idx.iter().map(|&k| self.heights[k]).sum::<f64>() / top_idx.len() as f64;
            let flat: Vec<Vec2> = top_idx.iter().map(|&k| self.projected[k]).collect();
            let h: Vec<usize> = convex_hull_2d(&flat);
            let outline: Vec<Vec2> = h.iter().map(|&k| flat[k]).collect();
            let at_level = |k: usize| self.on_table(self.points[top_idx[k]]) + up * level;
            TopSurface {
                height: level,
                centroid: top_idx.iter().map(|&k| self.points[k]).sum::<Vec3>()
                    / top_idx.len() as f64,
                hull: h.iter().map(|&k| at_level(k)).collect(),
                area: polygon_area(&outline).abs(),
            }
        })
    }
}

/// Centroid, principal axes, table-aligned box, hull with the table projection, and
/// top surface of one object.
pub(super) fn describe(
    pts: &[Vec3],
    locals: &Locals,
    plane: &Plane,
    indices: Vec<usize>,
    p: &TabletopParams,
) -> TableObject {
    let points: Vec<Vec3> = indices.iter().map(|&i| pts[i]).collect();
    let (centroid, m) = scatter(points.iter().copied()).unwrap_or((points[0], [0.0; 6]));
    let axes = principal_axes(m);
    let t = OnTable::new(plane, points, centroid);
    let hull2: Vec<usize> = convex_hull_2d(&t.projected);
    let height = t.heights.iter().copied().fold(0.0, f64::max);
    let rect = t.rectangle(&hull2);
    let obb = t.obb(&rect, centroid);
    let footprint: Vec<Vec3> = hull2.iter().map(|&k| t.on_table(t.points[k])).collect();
    let (hull_vertices, hull_triangles) = t.body_hull(&footprint);
    let top = t.top(&indices, locals, p);
    TableObject {
        indices,
        centroid,
        axes,
        table_axes: [t.major, t.minor],
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
