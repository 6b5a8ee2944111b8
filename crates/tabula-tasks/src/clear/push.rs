//! Pushes in geometry: where the closed fingers start, how long a push must be for the
//! object's grasp to come free (SPEC §3.7), what it runs into — and chain pushes,
//! which shove what is in front along (packed objects).

use super::predicates::{TableView, descent_poses};
use super::{ClearParams, DIRECTIONS, SeenObject, hits, hulls_collide, translated};
use crate::skills::GraspCandidate;
use crate::skills::hand::extent_along;
use tabula_geom::parry::bounding_volume::{Aabb, BoundingVolume};
use tabula_geom::polygon::{distance_to_boundary, exit_distance, inside_convex};
use tabula_geom::{Pose, Vec2, Vec3};

/// A push worked out in geometry.
#[derive(Debug, Clone)]
pub(super) struct Push {
    pub(super) direction: Vec2,
    pub(super) length: f64,
    /// Objects this push shoves along (a chain push; empty for the seed's pushes).
    pub(super) chain: Vec<usize>,
    /// For chain pushes: how many objects it makes graspable.
    pub(super) gain: usize,
    /// A push of one half of the object only ([`super::split`]): what may be two
    /// objects seen as one is parted.
    pub(super) split: bool,
    /// Tool pose where the push starts, and the fingertip height.
    pub(super) start: Pose,
    pub(super) feasible: bool,
}

impl Push {
    /// How far the fingers travel: to the object, then the push.
    pub(super) fn travel(&self, params: &ClearParams) -> f64 {
        self.length + params.push_distance
    }

    /// The push direction in 3D (horizontal).
    pub(super) fn direction3(&self) -> Vec3 {
        Vec3::new(self.direction.x, self.direction.y, 0.0)
    }
}

impl TableView<'_> {
    /// Where the closed fingers start a push of `o` along `d`: `push_distance` behind
    /// the object, their base at the object's top (or higher, for the palm to pass
    /// above the objects along the path, up to `palm_over`), their tips no lower than
    /// the clearance.
    pub(super) fn push_start(
        &self,
        o: &SeenObject,
        d: Vec2,
        along_major: bool,
        palm_over: f64,
    ) -> Pose {
        let (hand, params, up) = (self.hand, self.params, self.table.up);
        let d3 = Vec3::new(d.x, d.y, 0.0);
        let across = Vec3::new(-d.y, d.x, 0.0);
        // SPEC §3.2: closing parallel to the push along the principal axis (narrow
        // footprint), across it otherwise (a wide pusher keeps a long object from
        // turning) — but only where the wide pusher fits the object's face with a
        // centimetre to spare on each side: a wider pusher would drag the neighbours
        // beside the path.
        let width_across = |closing: Vec3| {
            let probe = hand.pose(Vec3::ZERO, closing, up);
            let (lo, hi) = extent_along(&hand.closed_fingers, probe.rotation.inverse() * across);
            hi - lo
        };
        let closing = if along_major
            || width_across(across) + 0.02 > o.rect.extent_along(across.truncate())
        {
            d3
        } else {
            across
        };
        // The palm above the neighbours along the path (`palm_over`) while the fingers
        // still cover at least the object's top 2 cm.
        let palm_clear = (palm_over + params.clearance - hand.beyond_palm).min(o.top - 0.02);
        let tip_z = (o.top - hand.beyond_palm)
            .max(o.bottom + params.fingertip_clearance)
            .max(palm_clear);
        let probe = hand.pose(Vec3::ZERO, closing, up);
        // How far the fingers reach toward the object from the tool axis.
        let (_, reach) = extent_along(&hand.closed_fingers, probe.rotation.inverse() * d3);
        let back = o.rect.extent_along(d) / 2.0 + params.push_distance + reach;
        let tips = Vec3::new(o.rect.center.x, o.rect.center.y, tip_z) - d3 * back;
        hand.pose(tips, closing, up)
    }

    /// The top of the highest object along the path of a push of `b` along `d`, which
    /// the palm passes above where the fingers can still reach `b` below it.
    pub(super) fn highest_ahead(&self, b: usize, d: Vec2) -> f64 {
        let o = &self.objects[b];
        let ahead = o.rect.extent_along(d) + self.params.push_max_length.min(0.15);
        self.objects
            .iter()
            .enumerate()
            .filter(|&(a, x)| {
                let rel = x.rect.center - o.rect.center;
                a != b && rel.dot(d) > -0.1 && rel.dot(d) < ahead && rel.dot(d.perp()).abs() < 0.09
            })
            .map(|(_, x)| x.top)
            .fold(f64::NEG_INFINITY, f64::max)
    }

    /// Whether `x` pushed `length` along `d` keeps its footprint's centre half its size
    /// and 2 cm from the table's edge, and `push_edge_clearance` more from the edge
    /// ahead (where it rolls or slides on).
    pub(super) fn stays_on_table(&self, x: &SeenObject, d: Vec2, length: f64) -> bool {
        let outline = &self.table.outline;
        let end = x.rect.center + d * length;
        let half = x.rect.extent_along(d) / 2.0;
        inside_convex(outline, end)
            && distance_to_boundary(outline, end) > half + 0.02
            && exit_distance(outline, end, d) > half + self.params.push_edge_clearance
    }

    /// The seed's push of object `b` in direction `k`: until its grasp is free (SPEC
    /// §3.7) and it is out of the way of `frees` — the grasps of the objects it blocks
    /// now, whose `block_grasp` facts the domain's push deletes (a push only as long as
    /// its own grasp needed left a tile's grasp blocked by the pushed block: blocks seed
    /// 166) — else as long as its own grasp needs, else k × its box (the seed), no
    /// longer than `push_max_length`.
    pub(super) fn seed_push(
        &self,
        on: &[(usize, usize)],
        (b, k): (usize, usize),
        frees: &[&GraspCandidate],
    ) -> Push {
        let (o, params) = (&self.objects[b], self.params);
        let d = o.direction(k);
        let d3 = Vec3::new(d.x, d.y, 0.0);
        let start = self.push_start(o, d, k < 2, self.highest_ahead(b, d));
        let others = |a: usize| a != b && !on.contains(&(a, b)) && !on.contains(&(b, a));
        let steps = (params.push_max_length / params.push_resolution).floor() as usize;
        let (mut length, mut own_free) = (None, None);
        for s in 1..=steps {
            let by = d3 * (s as f64 * params.push_resolution);
            if (0..self.objects.len())
                .filter(|&a| others(a))
                .any(|a| hulls_collide(o, by, &self.objects[a], params.sweep_tolerance))
            {
                break;
            }
            let here = s as f64 * params.push_resolution + params.push_margin;
            if own_free.is_none() {
                // Only its grasp is asked about: the hull need not move.
                let moved = translated(o, by, false);
                let skip = |a: usize| !others(a);
                let free = self
                    .grasps_of(&moved)
                    .iter()
                    .any(|g| self.grasp_blockers(g, &skip).is_empty());
                own_free = free.then_some(here);
            }
            if own_free.is_some() && self.out_of_the_way(o, by, frees) {
                length = Some(here);
                break;
            }
        }
        let length = length
            .or(own_free)
            .unwrap_or(params.push_factor * o.rect.extent_along(d))
            .min(params.push_max_length);
        Push {
            direction: d,
            length,
            chain: Vec::new(),
            gain: 0,
            split: false,
            start,
            feasible: self.stays_on_table(o, d, length),
        }
    }

    /// Whether `o` moved by `by` is out of the way of every grasp of `grasps`: the open
    /// hand coming down to each (moved back by `by` instead) meets its hull nowhere.
    fn out_of_the_way(&self, o: &SeenObject, by: Vec3, grasps: &[&GraspCandidate]) -> bool {
        let (up, params) = (self.table.up, self.params);
        grasps.iter().all(|g| {
            let shapes = self.hand.open_for(g.width).1;
            descent_poses(&g.poses[0], up, params.pregrasp)
                .iter()
                .all(|p| {
                    let back = Pose::from_parts(p.translation - by, p.rotation);
                    !hits(shapes, &back, o, params.clearance)
                })
        })
    }

    /// The closed hand coming down to push `p` and along it for `travel`.
    pub(super) fn hand_path(&self, p: &Push, travel: f64) -> Vec<Pose> {
        let steps = (travel / self.params.push_resolution).ceil().max(1.0) as usize;
        let mut path = descent_poses(&p.start, self.table.up, self.params.pre_push_height);
        path.extend((1..=steps).map(|s| {
            Pose::from_parts(
                p.start.translation + p.direction3() * (travel * s as f64 / steps as f64),
                p.start.rotation,
            )
        }));
        path
    }

    /// The objects other than `b` the closed hand meets along `path`.
    pub(super) fn gripper_hits(&self, b: usize, path: &[Pose]) -> Vec<usize> {
        let pad = self.params.clearance;
        (0..self.objects.len())
            .filter(|&a| a != b)
            .filter(|&a| {
                path.iter()
                    .any(|h| hits(&self.hand.closed, h, &self.objects[a], pad))
            })
            .collect()
    }

    /// The offsets of an object along a push `length` along `d3`, a sweep step apart.
    pub(super) fn sweep_of(&self, d3: Vec3, length: f64) -> Vec<Vec3> {
        let steps = (length / self.params.push_resolution).ceil().max(1.0) as usize;
        (1..=steps)
            .map(|s| d3 * (length * s as f64 / steps as f64))
            .collect()
    }

    /// Whether `x` swept along `sweep` runs into object `a`.
    pub(super) fn collides(&self, x: &SeenObject, sweep: &[Vec3], a: usize) -> bool {
        let tolerance = self.params.sweep_tolerance;
        sweep
            .iter()
            .any(|by| hulls_collide(x, *by, &self.objects[a], tolerance))
    }

    /// The objects blocking the seed's push `p` of `b` (direction `k`): what its hull
    /// runs into along the push, and what the hand meets on its way.
    pub(super) fn seed_push_blockers(&self, b: usize, k: usize, p: &Push) -> Vec<usize> {
        let solo_hits = self.gripper_hits(b, &self.hand_path(p, p.travel(self.params)));
        let sweep = self.sweep_of(p.direction3(), p.length);
        let o = &self.objects[b];
        (0..self.objects.len())
            .filter(|&a| a != b)
            .filter(|&a| {
                let swept = self.collides(o, &sweep, a);
                let gripper = solo_hits.contains(&a);
                if (swept || gripper) && tracing::enabled!(tracing::Level::DEBUG) {
                    tracing::debug!(
                        "block_{} o{} o{}: swept {swept} gripper {gripper} (push {:.2} m along ({:.2}, {:.2}))",
                        DIRECTIONS[k],
                        self.objects[a].id,
                        o.id,
                        p.length,
                        p.direction.x,
                        p.direction.y
                    );
                }
                swept || gripper
            })
            .collect()
    }

    /// What the sweep of `b` pushed `length` along `d3` runs into, and what that runs
    /// into, transitively.
    fn chain_of(&self, b: usize, d3: Vec3, length: f64) -> Vec<usize> {
        let mut chain: Vec<usize> = Vec::new();
        let mut frontier = vec![b];
        let sweep = self.sweep_of(d3, length);
        while let Some(x) = frontier.pop() {
            for a in 0..self.objects.len() {
                if a != b && !chain.contains(&a) && self.collides(&self.objects[x], &sweep, a) {
                    chain.push(a);
                    frontier.push(a);
                }
            }
        }
        chain
    }

    /// The chain variant of the seed's push `p` of `b`: what the sweep runs into moves
    /// along (and what that runs into, up to `max_chain`); only the gripper and what
    /// the chain runs into block it. Lengths are multiples of the box's size along the
    /// push (the seed's k × size); the one that makes the most objects graspable is
    /// kept (then the shortest). Returns the push and its blockers.
    pub(super) fn chain_push(
        &self,
        on: &[(usize, usize)],
        b: usize,
        p: &Push,
        graspable_now: &mut Option<Vec<bool>>,
    ) -> (Push, Vec<usize>) {
        let (o, params) = (&self.objects[b], self.params);
        let d3 = p.direction3();
        let mut best: Option<(Push, Vec<usize>)> = None;
        for &factor in &params.chain_push_factors {
            let length = (factor * o.rect.extent_along(p.direction)).min(params.push_max_length);
            let chain = self.chain_of(b, d3, length);
            let mut c = p.clone();
            c.length = length;
            c.feasible = chain.len() <= params.max_chain
                && self.stays_on_table(o, p.direction, length)
                && chain
                    .iter()
                    .all(|&a| self.stays_on_table(&self.objects[a], p.direction, length));
            let hits = self.gripper_hits(b, &self.hand_path(p, length + params.push_distance));
            let blockers: Vec<usize> = hits.into_iter().filter(|a| !chain.contains(a)).collect();
            if c.feasible && blockers.is_empty() {
                let now = graspable_now.get_or_insert_with(|| self.graspable(on));
                c.gain = self.gain(on, b, &chain, d3 * length, now);
            }
            c.chain = chain;
            let score =
                |(c, blockers): &(Push, Vec<usize>)| (c.feasible && blockers.is_empty(), c.gain);
            let candidate = (c, blockers);
            if best
                .as_ref()
                .is_none_or(|bst| score(&candidate) > score(bst))
            {
                best = Some(candidate);
            }
        }
        best.unwrap_or_else(|| (p.clone(), Vec::new()))
    }

    /// What a chain push of `b` shoving `chain` along by `by` is worth: how many
    /// objects it makes graspable that are not now (shoving a pair along together may
    /// help nothing).
    fn gain(
        &self,
        on: &[(usize, usize)],
        b: usize,
        chain: &[usize],
        by: Vec3,
        graspable_now: &[bool],
    ) -> usize {
        let n = self.objects.len();
        let moves = |a: usize| a == b || chain.contains(&a);
        let moved: Vec<SeenObject> = self
            .objects
            .iter()
            .enumerate()
            .map(|(a, x)| {
                if moves(a) {
                    translated(x, by, true)
                } else {
                    x.clone()
                }
            })
            .collect();
        // Only objects near what moved (within an open hand's reach of where it was or
        // went) can change.
        let reach = self.hand.open_width + 0.05;
        let moved_boxes: Vec<Aabb> = (0..n)
            .filter(|&a| moves(a))
            .map(|a| self.objects[a].aabb.merged(&moved[a].aabb).loosened(reach))
            .collect();
        let after = self.with_objects(&moved);
        (0..n)
            .filter(|&a| !graspable_now[a])
            .filter(|&a| moved_boxes.iter().any(|m| m.intersects(&moved[a].aabb)))
            .filter(|&a| after.graspable_one(on, a))
            .count()
    }
}
