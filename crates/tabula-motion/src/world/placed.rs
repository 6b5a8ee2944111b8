//! What one query places, and only where it must: a body's pieces at their poses with
//! their boxes and covers' balls (the hull of a decomposed link's pieces in front of
//! them) once the body's bounding ball comes near something; the cheap tests on balls
//! that spare the exact ones.

use super::cover::{Cover, box_corners};
use super::gjk::Hull;
use super::{CollisionWorld, Scratch, WorldObject};
use tabula_geom::parry::bounding_volume::{Aabb, BoundingVolume};
use tabula_geom::parry::shape::SharedShape;
use tabula_geom::{Mat3, Pose, Vec3};

impl CollisionWorld {
    /// Appends body `b`'s entries at `world_from_link` (its outer hull first, then its
    /// pieces) to `placed`, their balls to `balls`.
    pub(super) fn place_body<'a>(
        &'a self,
        b: usize,
        world_from_link: &Pose,
        padded: bool,
        balls: &mut Vec<(Vec3, f64)>,
        placed: &mut Vec<Placed<'a>>,
    ) {
        let lb = &self.bodies[b];
        // The body's rotation as a matrix once: every box and ball of its pieces is
        // placed by it (a quaternion per point costs twice as much).
        let at = Frame::of(world_from_link);
        let grow = if padded { lb.padding } else { 0.0 };
        if let Some(o) = &lb.outer {
            let first = balls.len();
            at.place_balls(&o.cover.spheres, balls);
            placed.push(Placed {
                body: b,
                outer: true,
                pose: *world_from_link,
                shape: &o.shape,
                hull: o.hull.as_ref(),
                aabb: at.place_aabb(&o.cover.local_aabb, grow),
                balls: first..balls.len(),
            });
        }
        for (((s, p), cover), hull) in lb.shapes.iter().zip(&lb.covers).zip(&lb.hulls) {
            let first = balls.len();
            at.place_balls(&cover.spheres, balls);
            placed.push(Placed {
                body: b,
                outer: false,
                pose: *world_from_link * *p,
                shape: s,
                hull: hull.as_ref(),
                aabb: at.place_aabb(&cover.local_aabb, grow),
                balls: first..balls.len(),
            });
        }
    }
}

/// The bodies of one check placed on demand: a body's pieces, boxes and balls are
/// placed the first time a test needs them — most bodies of most checks are clear of
/// everything by their bounding ball alone and are never placed.
pub(super) struct OnDemand<'a, 'b> {
    world: &'a CollisionWorld,
    /// The check's chain frames (or every body's pose: [`CollisionWorld::frames_into`]).
    frames: &'b [Pose],
    poses: &'b [Pose],
    pub balls: &'b mut Vec<(Vec3, f64)>,
    pub placed: Vec<Placed<'a>>,
    /// Boxes and bounding balls grown by each body's padding.
    padded: bool,
    /// Per body: its entries in `placed` once placed.
    spans: &'b mut Vec<Option<std::ops::Range<usize>>>,
    /// Per body: its bounding ball in the world (grown by its padding if `padded`).
    bounds: &'b mut Vec<Option<(Vec3, f64)>>,
}

impl<'a, 'b> OnDemand<'a, 'b> {
    /// Nothing placed yet; every body's bounding ball at the frames in `scratch`.
    pub fn new(world: &'a CollisionWorld, scratch: &'b mut Scratch, padded: bool) -> Self {
        let Scratch {
            frames,
            poses,
            balls,
            spans,
            bounds,
        } = scratch;
        spans.clear();
        spans.resize(world.bodies.len(), None);
        bounds.clear();
        bounds.extend(world.bodies.iter().enumerate().map(|(b, lb)| {
            let grow = if padded { lb.padding } else { 0.0 };
            world
                .body_bound(b, frames, poses)
                .map(|(c, r)| (c, r + grow))
        }));
        Self {
            world,
            frames,
            poses,
            balls,
            placed: Vec::new(),
            padded,
            spans,
            bounds,
        }
    }

    /// Body `b`'s pose in the world.
    pub fn pose(&self, b: usize) -> Pose {
        self.world.body_pose(b, self.frames, self.poses)
    }

    /// Body `b`'s entries in [`Self::placed`], placing it if it is not yet.
    pub fn body(&mut self, b: usize) -> std::ops::Range<usize> {
        if let Some(r) = &self.spans[b] {
            return r.clone();
        }
        if self.placed.capacity() == 0 {
            // Sized once: growing it is a good part of a check that places anything.
            self.placed.reserve(self.world.pieces);
        }
        let first = self.placed.len();
        let pose = self.pose(b);
        self.world
            .place_body(b, &pose, self.padded, self.balls, &mut self.placed);
        self.spans[b] = Some(first..self.placed.len());
        first..self.placed.len()
    }

    /// The ball around body `b` in the world (`None`: no shapes).
    pub fn bound(&self, b: usize) -> Option<(Vec3, f64)> {
        self.bounds[b]
    }

    /// Places every body (for the tests that need them all: attached objects).
    pub fn place_all(&mut self) {
        for b in 0..self.spans.len() {
            self.body(b);
        }
    }
}

/// Index pairs of two bodies' placed entries (`ra`, `rb`: their ranges in `placed`,
/// a decomposed body's outer hull first) whose boxes, grown by `margin`, meet, pushed
/// to `out`; where either is decomposed, only when `outers_meet` on the two outer
/// shapes (a body of one piece is its own outer shape).
pub(super) fn body_piece_pairs(
    placed: &[Placed<'_>],
    ra: std::ops::Range<usize>,
    rb: std::ops::Range<usize>,
    margin: f64,
    outers_meet: impl Fn(&Placed<'_>, &Placed<'_>) -> bool,
    out: &mut Vec<(usize, usize)>,
) {
    let (Some(pa), Some(pb)) = (placed.get(ra.start), placed.get(rb.start)) else {
        return;
    };
    // The outer hull's box holds its pieces' boxes; a lone piece's box is the body's.
    if !pa.aabb.loosened(margin).intersects(&pb.aabb) {
        return;
    }
    if (pa.outer || pb.outer) && !outers_meet(pa, pb) {
        return;
    }
    let pieces = |r: std::ops::Range<usize>, outer: bool| (r.start + outer as usize)..r.end;
    for i in pieces(ra, pa.outer) {
        let piece = placed[i].aabb.loosened(margin);
        for k in pieces(rb.clone(), pb.outer) {
            if piece.intersects(&placed[k].aabb) {
                out.push((i, k));
            }
        }
    }
}

/// The smallest ball around a set of balls (centre of their box): `None` for none.
pub(super) fn ball_around(balls: impl Iterator<Item = (Vec3, f64)> + Clone) -> Option<(Vec3, f64)> {
    let (lo, hi) = balls.clone().fold(
        (Vec3::splat(f64::INFINITY), Vec3::splat(f64::NEG_INFINITY)),
        |(lo, hi), (c, r)| (lo.min(c - Vec3::splat(r)), hi.max(c + Vec3::splat(r))),
    );
    if !lo.is_finite() {
        return None;
    }
    let centre = (lo + hi) * 0.5;
    let radius = balls
        .map(|(c, r)| (c - centre).length() + r)
        .fold(0.0, f64::max);
    Some((centre, radius))
}

/// A pose as a rotation matrix and a translation, for placing many points and boxes.
struct Frame {
    rotation: Mat3,
    abs_rotation: Mat3,
    translation: Vec3,
}

impl Frame {
    fn of(pose: &Pose) -> Self {
        let rotation = Mat3::from_quat(pose.rotation);
        Self {
            abs_rotation: rotation.abs(),
            rotation,
            translation: pose.translation,
        }
    }

    /// Appends `local` balls placed in this frame to `out`.
    fn place_balls(&self, local: &[(Vec3, f64)], out: &mut Vec<(Vec3, f64)>) {
        out.extend(
            local
                .iter()
                .map(|(c, r)| (self.rotation * *c + self.translation, *r)),
        );
    }

    /// The box of a `local` box placed in this frame, grown by `grow` on every side
    /// (as `Aabb::transform_by`, with the matrix made once).
    fn place_aabb(&self, local: &Aabb, grow: f64) -> Aabb {
        let centre = self.rotation * local.center() + self.translation;
        let half = self.abs_rotation * local.half_extents() + Vec3::splat(grow);
        Aabb::new(centre - half, centre + half)
    }
}

/// The convex hull of a link's pieces, in the link frame.
#[derive(Clone)]
pub(super) struct Outer {
    pub shape: SharedShape,
    pub cover: Cover,
    pub hull: Option<Hull>,
}

impl Outer {
    /// `None` for a link of one piece (its piece is its own outer shape).
    pub(super) fn of(shapes: &[(SharedShape, Pose)]) -> Option<Self> {
        if shapes.len() < 2 {
            return None;
        }
        let mut points = Vec::new();
        for (s, p) in shapes {
            // A mesh hull's vertices; any other shape through its box's corners.
            let local: Vec<Vec3> = match s.as_convex_polyhedron() {
                Some(c) => c.points().to_vec(),
                None => box_corners(&s.compute_local_aabb()).to_vec(),
            };
            points.extend(local.into_iter().map(|v| *p * v));
        }
        let shape = SharedShape::convex_hull(&points)?;
        Some(Self {
            cover: Cover::of(&shape),
            hull: shape.as_convex_polyhedron().and_then(Hull::of),
            shape,
        })
    }
}

/// A body shape placed for one query.
pub(super) struct Placed<'a> {
    pub body: usize,
    /// The hull of a decomposed body's pieces (placed just before them), not a piece.
    pub outer: bool,
    pub pose: Pose,
    pub shape: &'a SharedShape,
    pub hull: Option<&'a Hull>,
    pub aabb: Aabb,
    /// Its cover's balls in the query's ball list.
    pub balls: std::ops::Range<usize>,
}

/// Whether every ball is farther than `pad` from the object (so the shape they cover is).
pub(super) fn balls_clear_of(balls: &[(Vec3, f64)], o: &WorldObject, pad: f64) -> bool {
    balls.iter().all(|(c, r)| {
        let reach = r + pad;
        let near = Aabb::new(*c - Vec3::splat(reach), *c + Vec3::splat(reach));
        !near.intersects(&o.aabb)
            || o.shape.distance_to_point(&o.world_from_object, *c, true) > reach
    })
}

/// Whether every ball of one cover is farther than `pad` from every ball of the other.
pub(super) fn balls_apart(a: &[(Vec3, f64)], b: &[(Vec3, f64)], pad: f64) -> bool {
    a.iter().all(|(ca, ra)| {
        b.iter().all(|(cb, rb)| {
            let reach = ra + rb + pad;
            (*ca - *cb).length_squared() > reach * reach
        })
    })
}

#[cfg(test)]
mod tests {
    use crate::world::test_worlds::every_arm;
    use crate::world::{CollisionWorld, Keep, SweepRates, WorldParams};
    use rand::{RngExt, SeedableRng};
    use rand_chacha::ChaCha8Rng;
    use tabula_geom::parry::query;
    use tabula_geom::{Pose, Quat, Vec3};

    /// The padding of the test's worlds, which margins keep.
    const PAD: f64 = 0.01;
    /// What `Keep::LinkPaddings` may spend of it between samples.
    const SPEND: f64 = 0.004;

    /// The least of each kind over every pair a check tests.
    struct Least {
        /// Distance beyond the pair's padding.
        gap: f64,
        /// Margin along the rates keeping `PAD` (`Keep::Padding`), capped as
        /// `time_margin` caps it.
        margin: f64,
        /// Margin keeping the pair's padding less `SPEND` (`Keep::LinkPaddings`).
        between: f64,
    }

    /// Every pair a check tests, measured by parry with nothing skipped.
    fn measured(world: &CollisionWorld, q: &[f64], rates: &SweepRates) -> Least {
        let poses = world.body_poses(q).expect("poses");
        let pieces = |b: usize| {
            world.bodies[b]
                .shapes
                .iter()
                .map(|(s, p)| (s, poses[b] * *p))
                .collect::<Vec<_>>()
        };
        let cap = 0.1 / rates.fastest();
        let mut least = Least {
            gap: f64::INFINITY,
            margin: cap,
            between: cap,
        };
        let mut pair = |d: f64, pad: f64, rate: f64| {
            least.gap = least.gap.min(d - pad);
            least.margin = least.margin.min((d - PAD) / rate);
            least.between = least.between.min((d - (pad - SPEND)) / rate);
        };
        for (b, body) in world.bodies.iter().enumerate().filter(|(_, b)| b.moving) {
            for o in world
                .objects
                .iter()
                .filter(|o| !o.allowed_bodies.contains(&b))
            {
                for (s, pose) in pieces(b) {
                    let d =
                        query::distance(&pose, s.as_ref(), &o.world_from_object, o.shape.as_ref())
                            .expect("distance")
                            .distance;
                    pair(d, body.padding, rates.body(b));
                }
            }
        }
        for &(a, b) in &world.checked_pairs {
            let pad = world.bodies[a].padding.max(world.bodies[b].padding);
            for (sa, pa) in pieces(a) {
                for (sb, pb) in pieces(b) {
                    let d = query::distance(&pa, sa.as_ref(), &pb, sb.as_ref())
                        .expect("distance")
                        .distance;
                    pair(d, pad, rates.pair(a, b));
                }
            }
        }
        least
    }

    /// A margin stepped by the world against the least measured: never more, and where
    /// a cover's bound stood for a distance, at least its share of it; not above 0
    /// where the least is not.
    fn stepped_within(name: &str, stepped: f64, least: f64) {
        if least > 1e-7 {
            // GJK stops within its tolerance (micrometres here; parry's distance
            // converges further).
            let share = super::super::clearance::BALLS_ENOUGH;
            assert!(
                stepped <= least + 1e-3 * least.max(1e-3),
                "{name}: {stepped} > {least}"
            );
            assert!(
                stepped >= share * least * (1.0 - 1e-3),
                "{name}: {stepped} ≪ {least}"
            );
        } else {
            assert!(stepped <= 1e-7, "{name}: {stepped} with {least}");
        }
    }

    /// With boxes strewn around every arm of three robots, at random configurations:
    /// a check that places bodies only where their bounding balls reach something gives
    /// the verdict of measuring every pair, and the margin conservative advancement
    /// steps by is at most the least over every pair (and not much less).
    #[test]
    fn bodies_placed_on_demand_answer_as_every_pair_measured() {
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let params = WorldParams {
            acm_samples: 200,
            padding: PAD,
            ..WorldParams::default()
        };
        for (name, mut world) in every_arm(&params) {
            let (centre, reach) = world.moving_bound().expect("anchored");
            for i in 0..8 {
                let at = centre
                    + Vec3::new(
                        rng.random_range(-1.0..1.0),
                        rng.random_range(-1.0..1.0),
                        rng.random_range(-1.0..1.0),
                    ) * reach;
                let size = Vec3::new(
                    rng.random_range(0.02..0.3),
                    rng.random_range(0.02..0.3),
                    rng.random_range(0.02..0.3),
                );
                let turn = Quat::from_rotation_z(rng.random_range(-3.0..3.0));
                world
                    .add_box(&format!("box{i}"), size, Pose::from_parts(at, turn))
                    .expect("box");
            }
            let (mut valid, mut invalid) = (0, 0);
            for _ in 0..300 {
                let q = world.chain.random_configuration(&mut rng);
                let to = world.chain.random_configuration(&mut rng);
                let rates = world.sweep_rates(&q, &to);
                let least = measured(&world, &q, &rates);
                let gap = least.gap;
                if gap.abs() < 1e-7 {
                    continue;
                }
                let hit = world.first_collision(&q).expect("check");
                assert_eq!(hit.is_some(), gap < 0.0, "{name}: gap {gap}, hit {hit:?}");
                let stepped = world.time_margin(&q, &rates, PAD, 0.1).expect("margin");
                stepped_within(&name, stepped, least.margin);
                // Keeping each pair's padding at `q`: refused exactly where the check
                // is, else stepped by what is left after spending `SPEND`.
                let keep = Keep::LinkPaddings { spend: SPEND };
                let between = world.margin(&q, &rates, keep, 0.1).expect("margin");
                if gap < 0.0 {
                    assert!(between <= 0.0, "{name}: {between} where the check refuses");
                } else {
                    stepped_within(&name, between, least.between);
                }
                if gap < 0.0 { invalid += 1 } else { valid += 1 }
            }
            assert!(
                valid > 20 && invalid > 20,
                "{name}: {valid} valid, {invalid} not"
            );
        }
    }
}
