//! The exact narrow phase, built for yes/no questions: "are these two convex shapes
//! within `pad` of each other?" answered by GJK stopped as soon as a separating
//! direction proves more than `pad` (or contact is certain), rather than the full
//! distance; and link hulls whose support point is found by hill climbing over the
//! hull's vertex graph from the last answer, not by a pass over every vertex (a mesh
//! hull has hundreds; a linear function's maximum over a convex polytope is reached by
//! climbing its edges).

use std::cell::Cell;
use tabula_geom::parry::query::gjk::{self, CsoPoint, GJKResult, VoronoiSimplex};
use tabula_geom::parry::shape::{ConvexPolyhedron, SharedShape, SupportMap};
use tabula_geom::{Pose, Vec3};

/// A convex hull with its vertex adjacency, for hill-climbing support queries.
#[derive(Clone, Debug)]
pub(super) struct Hull {
    points: Vec<Vec3>,
    /// Neighbours of vertex `i`: `neighbours[offsets[i]..offsets[i + 1]]`.
    offsets: Vec<u32>,
    neighbours: Vec<u32>,
    /// Where the last climb ended: GJK asks in slowly turning directions.
    last: Cell<u32>,
    /// The extreme vertex along −x, +x, −y, +y, −z, +z: a start near any direction's
    /// answer when the last one is far from it.
    extremes: [u32; 6],
}

impl Hull {
    pub fn of(p: &ConvexPolyhedron) -> Option<Self> {
        let points = p.points().to_vec();
        if points.is_empty() {
            return None;
        }
        let mut lists = vec![Vec::new(); points.len()];
        for e in p.edges() {
            let [a, b] = e.vertices;
            lists[a as usize].push(b);
            lists[b as usize].push(a);
        }
        let mut offsets = Vec::with_capacity(points.len() + 1);
        let mut neighbours = Vec::new();
        offsets.push(0);
        for l in lists {
            neighbours.extend(l);
            offsets.push(neighbours.len() as u32);
        }
        let extreme = |axis: usize, sign: f64| {
            (0..points.len())
                .max_by(|&a, &b| (sign * points[a][axis]).total_cmp(&(sign * points[b][axis])))
                .unwrap_or(0) as u32
        };
        let extremes = [
            extreme(0, -1.0),
            extreme(0, 1.0),
            extreme(1, -1.0),
            extreme(1, 1.0),
            extreme(2, -1.0),
            extreme(2, 1.0),
        ];
        Some(Self {
            points,
            offsets,
            neighbours,
            last: Cell::new(0),
            extremes,
        })
    }
}

impl SupportMap for Hull {
    fn local_support_point(&self, dir: Vec3) -> Vec3 {
        // Start from the better of the last answer and the extreme vertex along the
        // direction's largest component; the climb reaches the maximum from anywhere.
        let abs = dir.abs();
        let axis = if abs.x >= abs.y && abs.x >= abs.z {
            0
        } else if abs.y >= abs.z {
            1
        } else {
            2
        };
        let guess = self.extremes[2 * axis + usize::from(dir[axis] > 0.0)] as usize;
        let mut at = self.last.get() as usize;
        let mut best = self.points[at].dot(dir);
        let guessed = self.points[guess].dot(dir);
        if guessed > best {
            (at, best) = (guess, guessed);
        }
        // Bounded: each step strictly increases the dot product, so no vertex repeats.
        for _ in 0..self.points.len() {
            let (from, to) = (self.offsets[at] as usize, self.offsets[at + 1] as usize);
            let mut moved = false;
            for &n in &self.neighbours[from..to] {
                let d = self.points[n as usize].dot(dir);
                if d > best {
                    best = d;
                    at = n as usize;
                    moved = true;
                }
            }
            if !moved {
                break;
            }
        }
        self.last.set(at as u32);
        self.points[at]
    }
}

/// A shape's support map for GJK: the climbing hull when there is one.
pub(super) fn support<'a>(
    shape: &'a SharedShape,
    hull: Option<&'a Hull>,
) -> Option<&'a dyn SupportMap> {
    match hull {
        Some(h) => Some(h),
        None => shape.as_support_map(),
    }
}

/// Whether two convex shapes at their poses are within `pad` (touching or
/// overlapping included).
pub(super) fn within(
    p1: &Pose,
    g1: &dyn SupportMap,
    p2: &Pose,
    g2: &dyn SupportMap,
    pad: f64,
) -> bool {
    distance_within(p1, g1, p2, g2, pad).is_some()
}

/// The distance between two convex shapes at their poses (0 when they touch) when it
/// is at most `limit`, else `None` — GJK stops as soon as a direction proves the gap
/// wider. A converged search is judged by the distance it found, never by GJK's early
/// "proximity" answer, which a stalled search can give for a wider gap.
pub(super) fn distance_within(
    p1: &Pose,
    g1: &dyn SupportMap,
    p2: &Pose,
    g2: &dyn SupportMap,
    limit: f64,
) -> Option<f64> {
    let pos12 = p1.inverse() * *p2;
    let dir = -pos12.translation;
    let dir = if dir.length_squared() > 1e-20 {
        dir.normalize()
    } else {
        Vec3::X
    };
    let mut simplex = VoronoiSimplex::new();
    simplex.reset(CsoPoint::from_shapes(&pos12, g1, g2, dir));
    match gjk::closest_points(&pos12, g1, g2, limit, true, &mut simplex) {
        GJKResult::ClosestPoints(a, b, _) => Some((a - b).length()).filter(|d| *d <= limit),
        GJKResult::NoIntersection(_) => None,
        GJKResult::Intersection | GJKResult::Proximity(_) => Some(0.0),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{RngExt, SeedableRng};
    use rand_chacha::ChaCha8Rng;
    use tabula_geom::parry::query;

    /// The climbing support agrees with parry's full pass, and the early-stopping test
    /// agrees with the exact distance, on random hulls at random poses.
    #[test]
    fn climbing_and_early_stopping_agree_with_exact_answers() {
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let mut checked = (0, 0);
        for _ in 0..200 {
            let hull = |rng: &mut ChaCha8Rng| {
                let pts: Vec<Vec3> = (0..rng.random_range(8..200))
                    .map(|_| {
                        Vec3::new(
                            rng.random_range(-0.1..0.1),
                            rng.random_range(-0.2..0.2),
                            rng.random_range(-0.05..0.05),
                        )
                    })
                    .collect();
                SharedShape::convex_hull(&pts).expect("hull")
            };
            let (a, b) = (hull(&mut rng), hull(&mut rng));
            let (ha, hb) = (
                Hull::of(a.as_convex_polyhedron().expect("polyhedron")).expect("hull"),
                Hull::of(b.as_convex_polyhedron().expect("polyhedron")).expect("hull"),
            );
            for _ in 0..5 {
                let dir = Vec3::new(
                    rng.random_range(-1.0..1.0),
                    rng.random_range(-1.0..1.0),
                    rng.random_range(-1.0..1.0),
                );
                let full = a
                    .as_support_map()
                    .expect("support")
                    .local_support_point(dir);
                assert!((ha.local_support_point(dir).dot(dir) - full.dot(dir)).abs() < 1e-12);
            }
            let pose = |rng: &mut ChaCha8Rng| {
                tabula_geom::pose_from_xyz_rpy(
                    [
                        rng.random_range(-0.3..0.3),
                        rng.random_range(-0.3..0.3),
                        rng.random_range(-0.3..0.3),
                    ],
                    [
                        rng.random_range(-3.0..3.0),
                        rng.random_range(-3.0..3.0),
                        rng.random_range(-3.0..3.0),
                    ],
                )
            };
            let (pa, pb) = (pose(&mut rng), pose(&mut rng));
            let exact = query::distance(&pa, a.as_ref(), &pb, b.as_ref())
                .expect("distance")
                .distance;
            let pad = 0.01;
            if (exact - pad).abs() < 1e-6 {
                continue;
            }
            assert_eq!(
                within(&pa, &ha, &pb, &hb, pad),
                exact <= pad,
                "distance {exact}"
            );
            if exact <= pad {
                checked.0 += 1
            } else {
                checked.1 += 1
            }
        }
        assert!(checked.0 > 20 && checked.1 > 20, "{checked:?}");
    }
}
