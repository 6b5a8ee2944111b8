//! Sphere covers of link shapes: a few balls whose union *contains* the shape (not
//! approximates it), so "every ball is clear of an obstacle by the padding" proves the
//! shape is, and the exact convex query is needed only where a ball is in contact —
//! the broad phase VAMP gets from its spheres, without its spheres' misses (a sphere
//! model that only approximates a mesh lets paths graze it).

use tabula_geom::Vec3;
use tabula_geom::parry::bounding_volume::Aabb;
use tabula_geom::parry::shape::SharedShape;

/// Balls `(centre, radius)` in the shape's frame whose union contains the shape, and
/// the shape's local box.
#[derive(Clone, Debug)]
pub(super) struct Cover {
    pub local_aabb: Aabb,
    pub spheres: Vec<(Vec3, f64)>,
}

/// Most balls per shape: beyond that the ball tests cost what the exact query saves.
const MAX_SLABS: usize = 8;

impl Cover {
    pub fn of(shape: &SharedShape) -> Self {
        let local_aabb = shape.compute_local_aabb();
        let spheres = if let Some(b) = shape.as_ball() {
            vec![(Vec3::ZERO, b.radius)]
        } else if let Some(c) = shape.as_compound() {
            c.shapes()
                .iter()
                .flat_map(|(pose, part)| {
                    Cover::of(part)
                        .spheres
                        .into_iter()
                        .map(move |(centre, r)| (*pose * centre, r))
                })
                .collect()
        } else if let Some(p) = shape.as_convex_polyhedron() {
            let edges: Vec<[u32; 2]> = p.edges().iter().map(|e| e.vertices).collect();
            slab_spheres(p.points(), &edges, &local_aabb)
        } else {
            // Boxes exactly, and cylinders, capsules, cones, anything else through their
            // box (which contains them).
            slab_spheres(&box_corners(&local_aabb), &BOX_EDGES, &local_aabb)
        };
        Self {
            local_aabb,
            spheres,
        }
    }

    /// The cover of the same shape placed at `pose` in a parent frame.
    pub fn placed(self, pose: &tabula_geom::Pose) -> Self {
        Self {
            local_aabb: self.local_aabb.transform_by(pose),
            spheres: self
                .spheres
                .into_iter()
                .map(|(c, r)| (*pose * c, r))
                .collect(),
        }
    }
}

/// The corners of a box, corner `i` taking the upper bound on axis `k` where bit `k` of
/// `i` is set.
pub(super) fn box_corners(b: &Aabb) -> [Vec3; 8] {
    std::array::from_fn(|i| {
        Vec3::new(
            if i & 1 == 0 { b.mins.x } else { b.maxs.x },
            if i & 2 == 0 { b.mins.y } else { b.maxs.y },
            if i & 4 == 0 { b.mins.z } else { b.maxs.z },
        )
    })
}

/// The twelve edges of [`box_corners`]: corners one bit apart.
const BOX_EDGES: [[u32; 2]; 12] = [
    [0, 1],
    [2, 3],
    [4, 5],
    [6, 7],
    [0, 2],
    [1, 3],
    [4, 6],
    [5, 7],
    [0, 4],
    [1, 5],
    [2, 6],
    [3, 7],
];

/// The convex hull of `points` (with its `edges`) cut into slabs across its longest
/// side; each slab's piece is the hull of the points inside it and the edges' crossings
/// of its two planes, so the ball around those contains the piece.
fn slab_spheres(points: &[Vec3], edges: &[[u32; 2]], aabb: &Aabb) -> Vec<(Vec3, f64)> {
    let extent = aabb.maxs - aabb.mins;
    let axis = if extent.x >= extent.y && extent.x >= extent.z {
        0
    } else if extent.y >= extent.z {
        1
    } else {
        2
    };
    let mut sides = [extent.x, extent.y, extent.z];
    sides.sort_by(f64::total_cmp);
    let (long, width) = (sides[2], sides[1].max(1e-9));
    let slabs = ((long / width).round() as usize).clamp(1, MAX_SLABS);
    let (lo, hi) = (aabb.mins[axis], aabb.maxs[axis]);
    let step = (hi - lo) / slabs as f64;
    (0..slabs)
        .filter_map(|k| {
            let (a, b) = (
                lo + step * k as f64,
                if k + 1 == slabs {
                    hi
                } else {
                    lo + step * (k + 1) as f64
                },
            );
            let mut piece: Vec<Vec3> = points
                .iter()
                .filter(|p| p[axis] >= a && p[axis] <= b)
                .copied()
                .collect();
            for &[i, j] in edges {
                let (p, q) = (points[i as usize], points[j as usize]);
                for plane in [a, b] {
                    let (s, t) = (p[axis] - plane, q[axis] - plane);
                    if (s < 0.0) != (t < 0.0) && s != t {
                        piece.push(p + (q - p) * (s / (s - t)));
                    }
                }
            }
            bounding_ball(&piece)
        })
        .collect()
}

/// A ball containing `points` (centred on their box; not the smallest, always valid).
fn bounding_ball(points: &[Vec3]) -> Option<(Vec3, f64)> {
    let first = *points.first()?;
    let (lo, hi) = points
        .iter()
        .fold((first, first), |(lo, hi), p| (lo.min(*p), hi.max(*p)));
    let centre = (lo + hi) / 2.0;
    let r = points
        .iter()
        .map(|p| (*p - centre).length())
        .fold(0.0, f64::max);
    // A hair more than the farthest point, so rounding cannot leave it outside.
    Some((centre, r * (1.0 + 1e-9) + 1e-12))
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{RngExt, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// Every point of the shape (sampled inside its box, kept when inside the shape) is
    /// inside some ball of its cover — for boxes, cylinders, capsules and random hulls
    /// of every proportion.
    #[test]
    fn covers_contain_their_shapes() {
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let mut shapes = vec![
            SharedShape::cuboid(0.4, 0.02, 0.05),
            SharedShape::cuboid(0.1, 0.1, 0.1),
            SharedShape::cylinder(0.3, 0.03),
            SharedShape::capsule_z(0.2, 0.05),
            SharedShape::cone(0.2, 0.1),
        ];
        for _ in 0..20 {
            let s = Vec3::new(
                rng.random_range(0.01..0.5),
                rng.random_range(0.01..0.5),
                rng.random_range(0.01..0.5),
            );
            let pts: Vec<Vec3> = (0..40)
                .map(|_| {
                    Vec3::new(
                        rng.random_range(-1.0..1.0),
                        rng.random_range(-1.0..1.0),
                        rng.random_range(-1.0..1.0),
                    ) * s
                })
                .collect();
            shapes.push(SharedShape::convex_hull(&pts).expect("hull"));
        }
        for shape in &shapes {
            let cover = Cover::of(shape);
            assert!(!cover.spheres.is_empty() && cover.spheres.len() <= MAX_SLABS);
            let bb = shape.compute_local_aabb();
            let mut inside = 0;
            for _ in 0..20_000 {
                let p = Vec3::new(
                    rng.random_range(bb.mins.x..=bb.maxs.x),
                    rng.random_range(bb.mins.y..=bb.maxs.y),
                    rng.random_range(bb.mins.z..=bb.maxs.z),
                );
                if !shape.contains_local_point(p) {
                    continue;
                }
                inside += 1;
                assert!(
                    cover.spheres.iter().any(|(c, r)| (p - *c).length() <= *r),
                    "point {p:?} of {:?} outside its cover",
                    shape.shape_type()
                );
            }
            assert!(inside > 100);
        }
    }

    #[test]
    fn long_shapes_get_several_balls_tighter_than_one() {
        let shape = SharedShape::cuboid(0.4, 0.03, 0.03);
        let cover = Cover::of(&shape);
        assert!(cover.spheres.len() >= 4);
        let one = shape.compute_local_bounding_sphere().radius();
        assert!(cover.spheres.iter().all(|(_, r)| *r < one / 2.0));
    }
}
