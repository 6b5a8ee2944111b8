//! Clearance along a segment: how far conservative advancement may step from a
//! configuration, each pair [`CollisionWorld::first_collision`] would test weighed by
//! how fast it can close. Sphere covers bound a pair's distance from below for a few
//! multiplications, so the exact (GJK) distance is computed only for pairs whose cover
//! comes closer than the best found so far allows.

use super::gjk::{self, Hull};
use super::placed::{OnDemand, Placed, body_piece_pairs};
use super::{CollisionWorld, Scratch, SweepRates, WorldError, WorldObject};
use tabula_geom::parry::bounding_volume::{Aabb, BoundingVolume};
use tabula_geom::parry::query;
use tabula_geom::parry::shape::SharedShape;
use tabula_geom::{Pose, Vec3};

/// One convex thing placed for a distance query.
struct Solid<'a> {
    pose: Pose,
    shape: &'a SharedShape,
    hull: Option<&'a Hull>,
}

impl<'a> Solid<'a> {
    fn of(p: &super::Placed<'a>) -> Self {
        Self {
            pose: p.pose,
            shape: p.shape,
            hull: p.hull,
        }
    }

    /// The distance to `other`, or `limit` when it is at least that.
    fn distance(&self, other: &Solid, limit: f64) -> f64 {
        match (
            gjk::support(self.shape, self.hull),
            gjk::support(other.shape, other.hull),
        ) {
            (Some(a), Some(b)) => {
                gjk::distance_within(&self.pose, a, &other.pose, b, limit).unwrap_or(limit)
            }
            _ => query::distance(
                &self.pose,
                self.shape.as_ref(),
                &other.pose,
                other.shape.as_ref(),
            )
            .map_or(0.0, |d| d.distance),
        }
    }
}

/// A lower bound on the distance from balls to an object (0 when a ball reaches it).
fn balls_to_object(balls: &[(Vec3, f64)], o: &WorldObject, best: f64) -> f64 {
    let mut lb = f64::INFINITY;
    for (c, r) in balls {
        let reach = r + best;
        let near = Aabb::new(*c - Vec3::splat(reach), *c + Vec3::splat(reach));
        if !near.intersects(&o.aabb) {
            continue;
        }
        lb = lb.min(o.shape.distance_to_point(&o.world_from_object, *c, true) - r);
    }
    lb.max(0.0)
}

/// A lower bound on the distance between two sets of balls.
fn balls_to_balls(a: &[(Vec3, f64)], b: &[(Vec3, f64)]) -> f64 {
    let mut lb = f64::INFINITY;
    for (ca, ra) in a {
        for (cb, rb) in b {
            lb = lb.min((*ca - *cb).length() - ra - rb);
        }
    }
    lb.max(0.0)
}

/// The share of the margin still possible (`limit` less what the pair keeps) that a piece's
/// cover must give for its lower bound to stand for the exact distance to an object.
/// Measured: 0.1–0.5 alike (WAM median 0.15 → 0.10 ms); 1 (never) is the slowest.
pub(super) const BALLS_ENOUGH: f64 = 0.3;

/// Rates at or below this count as "does not move": a pair that cannot come closer
/// along the segment needs only its distance above the padding.
const STILL: f64 = 1e-12;

/// What a margin keeps between each pair, at `q` and along the stretch it allows.
#[derive(Clone, Copy, Debug)]
pub enum Keep {
    /// `pad` everywhere: the margin is `(distance − pad) / rate`.
    Padding(f64),
    /// Each pair's own padding at `q` (as [`CollisionWorld::first_collision`] asks), and
    /// along the stretch that padding less `spend`: the margin is `(distance − (own −
    /// spend)) / rate`. With `spend` half the world's step this is what fixed spacing
    /// certifies (every configuration between two samples is within half a step of
    /// one), in far fewer samples where things are far apart.
    LinkPaddings { spend: f64 },
}

impl Keep {
    /// The distance below which `q` is refused, for a pair whose padding is `own`.
    fn floor(self, own: f64) -> f64 {
        match self {
            Keep::Padding(pad) => pad,
            Keep::LinkPaddings { .. } => own,
        }
    }

    /// The distance not spent along the stretch.
    fn kept(self, own: f64) -> f64 {
        match self {
            Keep::Padding(pad) => pad,
            Keep::LinkPaddings { spend } => (own - spend).max(0.0),
        }
    }

    /// The distance up to which a pair must be measured while `best` is the margin:
    /// beyond it the pair neither refuses `q` nor shortens the margin.
    fn limit(self, own: f64, best: f64, rate: f64) -> f64 {
        self.floor(own).max(self.kept(own) + best * rate)
    }

    /// The margin after a pair closing at `rate` measured `d` apart: not above 0 when
    /// `d` is under the pair's floor (`own`: its padding). A distance measured up to a
    /// limit comes back as the limit when it is at least that, and the limit may be
    /// the floor itself: that is clear.
    fn after(self, best: f64, d: f64, own: f64, rate: f64) -> f64 {
        let m = best.min((d - self.kept(own)) / rate);
        if d < self.floor(own) { m.min(0.0) } else { m }
    }
}

/// What a margin is asked along: how fast each pair closes, and what it keeps.
#[derive(Clone, Copy)]
struct Along<'r> {
    rates: &'r SweepRates,
    keep: Keep,
}

impl CollisionWorld {
    /// The margin of `q` along a segment, in the segment's own length (0 at its start,
    /// 1 at its end): the smallest `(distance − pad) / rate` over every pair that
    /// [`Self::first_collision`] would test, each pair's rate the most its distance can
    /// shrink over the whole segment (`rates`, [`SweepRates`]). From `q`, a stretch of
    /// the segment that long keeps every pair apart by `pad`. Capped where the fastest
    /// body has moved `cap` metres (far things cost distance queries and buy little);
    /// negative when `q` is out of limits or some pair is within `pad`.
    pub fn time_margin(
        &self,
        q: &[f64],
        rates: &SweepRates,
        pad: f64,
        cap: f64,
    ) -> Result<f64, WorldError> {
        self.margin(q, rates, Keep::Padding(pad), cap)
    }

    /// The margin of `q` keeping what `keep` says ([`Self::time_margin`] is
    /// `Keep::Padding`): non-positive when `q` is out of limits or refused.
    pub fn margin(
        &self,
        q: &[f64],
        rates: &SweepRates,
        keep: Keep,
        cap: f64,
    ) -> Result<f64, WorldError> {
        self.with_bodies_at(q, |scratch, outside| match outside {
            Some(_) => -1.0,
            None => self.margin_of_placed(q, scratch, rates, keep, cap),
        })
    }

    /// [`Self::margin`] of the bodies at the poses in `scratch`: a body is placed only
    /// where its bounding ball comes closer to something than the best margin so far
    /// allows. Each part returns the margin left, non-positive once `q` is refused.
    fn margin_of_placed(
        &self,
        q: &[f64],
        scratch: &mut Scratch,
        rates: &SweepRates,
        keep: Keep,
        cap: f64,
    ) -> f64 {
        let best = cap / rates.fastest().max(STILL);
        let mut bodies = OnDemand::new(self, scratch, false);
        let along = Along { rates, keep };
        let best = self.objects_margin(&mut bodies, along, best);
        if best <= 0.0 {
            return best;
        }
        let best = self.own_pairs_margin(q, &mut bodies, along, best);
        if best <= 0.0 || self.attached.is_empty() {
            return best;
        }
        self.attached_margin(&mut bodies, along, best)
    }

    /// The margin against the world's objects.
    fn objects_margin(&self, bodies: &mut OnDemand, along: Along, mut best: f64) -> f64 {
        let Along { rates, keep } = along;
        for b in (0..self.bodies.len()).filter(|&b| self.bodies[b].moving) {
            let Some((centre, radius)) = bodies.bound(b) else {
                continue;
            };
            let rate = rates.body(b).max(STILL);
            let own = self.bodies[b].padding;
            let reach = radius + keep.limit(own, best, rate);
            let around = Aabb::new(centre - Vec3::splat(reach), centre + Vec3::splat(reach));
            for i in self.object_indices_near(&around) {
                let o = &self.objects[i];
                let limit = keep.limit(own, best, rate);
                if o.allowed_bodies.contains(&b)
                    || o.shape
                        .distance_to_point(&o.world_from_object, centre, true)
                        - radius
                        >= limit
                {
                    continue;
                }
                let range = bodies.body(b);
                let floors = (keep.floor(own), keep.kept(own));
                let d =
                    self.entries_distance(&bodies.placed[range], bodies.balls, o, floors, limit);
                best = keep.after(best, d, own, rate);
                if best <= 0.0 {
                    return best;
                }
            }
        }
        best
    }

    /// The margin between the robot's own bodies (the pairs the matrix checks).
    fn own_pairs_margin(
        &self,
        q: &[f64],
        bodies: &mut OnDemand,
        along: Along,
        mut best: f64,
    ) -> f64 {
        let Along { rates, keep } = along;
        let mut pairs = Vec::new();
        for &(a, b) in &self.checked_pairs {
            let (Some((ca, ra)), Some((cb, rb))) = (bodies.bound(a), bodies.bound(b)) else {
                continue;
            };
            let rate = rates.pair(a, b).max(STILL);
            let own = self.bodies[a].padding.max(self.bodies[b].padding);
            let limit = keep.limit(own, best, rate);
            if (ca - cb).length() - ra - rb >= limit
                || self
                    .pair_tables
                    .floor(self, a, b, q)
                    .is_some_and(|d| d >= limit)
            {
                continue;
            }
            let (sa, sb) = (bodies.body(a), bodies.body(b));
            let balls = &*bodies.balls;
            let apart = |pi: &Placed, pk: &Placed, limit: f64| {
                balls_to_balls(&balls[pi.balls.clone()], &balls[pk.balls.clone()]) >= limit
            };
            pairs.clear();
            body_piece_pairs(
                &bodies.placed,
                sa,
                sb,
                limit,
                |pi, pk| {
                    !apart(pi, pk, limit) && Solid::of(pi).distance(&Solid::of(pk), limit) < limit
                },
                &mut pairs,
            );
            for &(i, k) in &pairs {
                let (pi, pk) = (&bodies.placed[i], &bodies.placed[k]);
                let limit = keep.limit(own, best, rate);
                if !pi.aabb.loosened(limit).intersects(&pk.aabb) || apart(pi, pk, limit) {
                    continue;
                }
                let d = Solid::of(pi).distance(&Solid::of(pk), limit);
                best = keep.after(best, d, own, rate);
                if best <= 0.0 {
                    return best;
                }
            }
        }
        best
    }

    /// The margin of the objects the robot holds, against the world and the robot.
    fn attached_margin(&self, bodies: &mut OnDemand, along: Along, mut best: f64) -> f64 {
        let Along { rates, keep } = along;
        bodies.place_all();
        let placed = &bodies.placed;
        for att in &self.attached {
            let held = Solid {
                pose: bodies.pose(att.body) * att.link_from_object,
                shape: &att.shape,
                hull: None,
            };
            let own = self.bodies[att.body].padding;
            let aabb = att.shape.compute_aabb(&held.pose);
            let rate = rates.body(att.body).max(STILL);
            let limit = keep.limit(own, best, rate);
            for o in self.objects_near(&aabb.loosened(limit)) {
                let limit = keep.limit(own, best, rate);
                let d = self.object_distance(&held, &aabb.loosened(limit), o, limit);
                best = keep.after(best, d, own, rate);
                if best <= 0.0 {
                    return best;
                }
            }
            for p in placed.iter().filter(|p| !p.outer) {
                let rate = rates.pair(att.body, p.body).max(STILL);
                let limit = keep.limit(own, best, rate);
                if !att.touch.contains(&p.body) && aabb.loosened(limit).intersects(&p.aabb) {
                    let d = held.distance(&Solid::of(p), limit);
                    best = keep.after(best, d, own, rate);
                    if best <= 0.0 {
                        return best;
                    }
                }
            }
        }
        best
    }

    /// Distance from one body's placed entries to object `o` (or `limit` when at least
    /// that): a decomposed body's pieces only when its outer hull comes within `limit`.
    fn entries_distance(
        &self,
        entries: &[Placed],
        balls: &[(Vec3, f64)],
        o: &WorldObject,
        (floor, kept): (f64, f64),
        limit: f64,
    ) -> f64 {
        let distance = |p: &Placed, limit: f64| {
            if !p.aabb.loosened(limit).intersects(&o.aabb) {
                return limit;
            }
            let lb = balls_to_object(&balls[p.balls.clone()], o, limit);
            if lb >= limit {
                return limit;
            }
            // The balls' bound stands for the distance when it gives a good part of
            // the margin asked for: a shorter step, but no GJK.
            if !p.outer && lb > floor && lb - kept >= BALLS_ENOUGH * (limit - kept) {
                return lb;
            }
            self.object_distance(&Solid::of(p), &p.aabb.loosened(limit), o, limit)
        };
        let Some(first) = entries.first() else {
            return limit;
        };
        if !first.outer {
            return entries.iter().fold(limit, |d, p| d.min(distance(p, d)));
        }
        if distance(first, limit) >= limit {
            return limit;
        }
        entries[1..]
            .iter()
            .fold(limit, |d, p| d.min(distance(p, d)))
    }

    /// Distance from a solid to an object (or `limit` when at least that); of a
    /// compound (an occupancy map) only the parts within `near` count.
    fn object_distance(&self, s: &Solid, near: &Aabb, o: &WorldObject, limit: f64) -> f64 {
        let Some(c) = o.shape.as_compound() else {
            return s.distance(
                &Solid {
                    pose: o.world_from_object,
                    shape: &o.shape,
                    hull: None,
                },
                limit,
            );
        };
        let local = near.transform_by(&o.world_from_object.inverse());
        c.bvh()
            .intersect_aabb(&local)
            .map(|i| {
                let (part_pose, part) = &c.shapes()[i as usize];
                s.distance(
                    &Solid {
                        pose: o.world_from_object * *part_pose,
                        shape: part,
                        hull: None,
                    },
                    limit,
                )
            })
            .fold(f64::INFINITY, f64::min)
    }
}
