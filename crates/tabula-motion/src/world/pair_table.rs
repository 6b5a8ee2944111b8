//! The robot's own close pairs, remembered: two wrist links move relative to each other
//! by one or two joints only, so their distance is a function on a small grid of those
//! joints' values. Each cell holds the exact distance at its centre (measured the first
//! time a query lands there); anywhere in the cell the distance is at least that less
//! the most the pair can close from the centre (the joints' half-widths times their
//! levers, [`super::SweepRates`]' bound), a few millimetres. Pairs the bound clears are
//! never put through GJK — on a 7-joint arm those pairs are centimetres apart in every
//! configuration, so their covers always meet and they cost a third of a check.
//!
//! A table depends on the robot only (shapes, anchors), not on the scene: clones of a
//! world share it, so what one problem measured serves the next.

use super::{CollisionWorld, gjk};
use std::sync::Arc;
use std::sync::atomic::{AtomicU32, Ordering};
use tabula_geom::parry::query;
use tabula_geom::{Pose, Quat};

/// The most any pair's bound may give away (m).
const SLACK: f64 = 0.008;
/// Cells per table at most (4 bytes each).
const MAX_CELLS: usize = 1 << 18;
/// Cells of all a world's tables at most (16 MB): a robot of hundreds of links keeps
/// tables for its first pairs only.
const MAX_TOTAL_CELLS: usize = 1 << 22;
/// Offsets this close are the same (anchors are recomputed through forward kinematics
/// at other joint values, which rounds differently); the floor gives this much more.
const SAME: f64 = 1e-7;
/// Distances beyond this are recorded as this (a floor still).
const FAR: f64 = 1.0;
/// A cell not measured yet.
const EMPTY: u32 = u32::MAX;

/// One joint of a table: its chain element and variable, and the grid along it.
struct Axis {
    element: usize,
    var: usize,
    lower: f64,
    width: f64,
    count: usize,
}

/// The distance between bodies `a` (earlier in the chain) and `b` over the joints
/// between them.
struct PairTable {
    a: usize,
    b: usize,
    axes: Vec<Axis>,
    slack: f64,
    /// `a`'s link frame from the frame before the first axis' element.
    a_from_before: Pose,
    b_offset: Pose,
    cells: Vec<AtomicU32>,
}

/// Every table of a world, and which body pair has which.
#[derive(Clone, Default)]
pub(super) struct PairTables {
    bodies: usize,
    /// `a · bodies + b` (both orders) → table.
    index: Arc<Vec<u32>>,
    tables: Vec<Arc<PairTable>>,
}

impl PairTables {
    /// Tables for every checked-or-not pair of bodies moving relative to each other by
    /// one or two distinct joints (the matrix may change; the tables need not). Tables
    /// of the world's current set that describe the same pair the same way are kept,
    /// with what they have measured (a request that sets the fingers to where they
    /// were changes nothing).
    pub(super) fn build(world: &CollisionWorld) -> Self {
        let n = world.bodies.len();
        let elements = world.chain.elements.len();
        if world.element_joints.is_none() || world.levers.len() != n * elements {
            return Self::default();
        }
        let mut index = vec![u32::MAX; n * n];
        let mut tables = Vec::new();
        let mut total = 0;
        for a in 0..n {
            for b in 0..n {
                let (ea, eb) = (world.anchors[a].element, world.anchors[b].element);
                let Some(eb) = eb else { continue };
                let first = ea.map_or(0, |k| k + 1);
                if first > eb || eb - first >= 2 || index[a * n + b] != u32::MAX {
                    continue;
                }
                let Some(t) = PairTable::new(world, a, b, first..=eb) else {
                    continue;
                };
                total += t.cells.len();
                if total <= MAX_TOTAL_CELLS {
                    index[a * n + b] = tables.len() as u32;
                    index[b * n + a] = tables.len() as u32;
                    let kept = world.pair_tables.tables.iter().find(|old| old.same_as(&t));
                    tables.push(kept.cloned().unwrap_or_else(|| Arc::new(t)));
                }
            }
        }
        Self {
            bodies: n,
            index: Arc::new(index),
            tables,
        }
    }

    /// How many bodies the tables were built for.
    pub(super) fn bodies(&self) -> usize {
        self.bodies
    }

    /// A lower bound on the distance between bodies `a` and `b` at `q`, or `None` when
    /// the pair has no table.
    pub(super) fn floor(
        &self,
        world: &CollisionWorld,
        a: usize,
        b: usize,
        q: &[f64],
    ) -> Option<f64> {
        let i = *self.index.get(a * self.bodies + b)?;
        let t = self.tables.get(i as usize)?;
        Some(t.floor(world, q))
    }
}

impl PairTable {
    fn new(
        world: &CollisionWorld,
        a: usize,
        b: usize,
        span: std::ops::RangeInclusive<usize>,
    ) -> Option<Self> {
        let share = SLACK / span.clone().count() as f64;
        let mut axes: Vec<Axis> = Vec::new();
        let (mut cells, mut slack) = (1usize, 0.0);
        for k in span.clone() {
            let e = &world.chain.elements[k];
            if axes.iter().any(|x| x.var == e.var) {
                return None;
            }
            let (lower, upper) = (world.chain.lower[e.var], world.chain.upper[e.var]);
            let reach = world.reach(k, b);
            let range = upper - lower;
            if !(range.is_finite() && range > 0.0 && reach > 0.0) {
                return None;
            }
            // Half a cell times the reach is this joint's share of the slack.
            let count = (range * reach / (2.0 * share)).ceil().max(1.0);
            if count > MAX_CELLS as f64 {
                return None;
            }
            cells *= count as usize;
            let width = range / count;
            slack += 0.5 * width * reach;
            axes.push(Axis {
                element: k,
                var: e.var,
                lower,
                width,
                count: count as usize,
            });
        }
        if cells > MAX_CELLS {
            return None;
        }
        let before = match world.anchors[a].element {
            Some(_) => Pose::IDENTITY,
            None => world.world_from_chain_base,
        };
        Some(Self {
            a,
            b,
            axes,
            slack,
            a_from_before: world.anchors[a].offset.inverse() * before,
            b_offset: world.anchors[b].offset,
            cells: (0..cells).map(|_| AtomicU32::new(EMPTY)).collect(),
        })
    }

    /// Whether `other` is this table, measured or not: same pair, grid and offsets.
    fn same_as(&self, other: &PairTable) -> bool {
        let axes_match = self.axes.len() == other.axes.len()
            && self.axes.iter().zip(&other.axes).all(|(x, y)| {
                (x.element, x.var, x.count, x.lower, x.width)
                    == (y.element, y.var, y.count, y.lower, y.width)
            });
        (self.a, self.b) == (other.a, other.b)
            && (self.slack - other.slack).abs() <= SAME * 1e-2
            && axes_match
            && near(&self.a_from_before, &other.a_from_before)
            && near(&self.b_offset, &other.b_offset)
    }

    fn floor(&self, world: &CollisionWorld, q: &[f64]) -> f64 {
        let mut cell = 0usize;
        let mut centre = [0.0f64; 2];
        for (i, x) in self.axes.iter().enumerate() {
            let k = ((q[x.var] - x.lower) / x.width).floor();
            let k = (k.max(0.0) as usize).min(x.count - 1);
            cell = cell * x.count + k;
            centre[i] = x.lower + (k as f64 + 0.5) * x.width;
        }
        let stored = self.cells[cell].load(Ordering::Relaxed);
        let d = if stored == EMPTY {
            let d = self.distance_at(world, &centre[..self.axes.len()]);
            // Shrunk before rounding into f32 (relative error 6e-8): the floor must not rise.
            let d = (d.max(0.0) * (1.0 - 1e-6)) as f32;
            self.cells[cell].store(d.to_bits(), Ordering::Relaxed);
            d as f64
        } else {
            f32::from_bits(stored) as f64
        };
        d - self.slack - SAME
    }

    /// The exact distance between the two bodies with the table's joints at `values`.
    fn distance_at(&self, world: &CollisionWorld, values: &[f64]) -> f64 {
        let mut a_from_b = self.a_from_before;
        for (x, v) in self.axes.iter().zip(values) {
            let e = &world.chain.elements[x.element];
            let v = e.multiplier * v + e.offset;
            let motion = if e.prismatic {
                Pose::from_translation(e.axis * v)
            } else {
                Pose::from_rotation(Quat::from_axis_angle(e.axis, v))
            };
            a_from_b = a_from_b * e.pre * motion;
        }
        self.exact(world, &(a_from_b * self.b_offset))
    }

    /// The exact distance between the two bodies, `b` placed at `a_from_b`: GJK on the
    /// climbing hulls where there are some, less its tolerance.
    fn exact(&self, world: &CollisionWorld, a_from_b: &Pose) -> f64 {
        let (body_a, body_b) = (&world.bodies[self.a], &world.bodies[self.b]);
        let mut best = f64::INFINITY;
        for ((sa, pa), ha) in body_a.shapes.iter().zip(&body_a.hulls) {
            for ((sb, pb), hb) in body_b.shapes.iter().zip(&body_b.hulls) {
                let pose_b = *a_from_b * *pb;
                let d = match (gjk::support(sa, ha.as_ref()), gjk::support(sb, hb.as_ref())) {
                    (Some(ga), Some(gb)) => {
                        gjk::distance_within(pa, ga, &pose_b, gb, FAR).unwrap_or(FAR) - 1e-6
                    }
                    _ => query::distance(pa, sa.as_ref(), &pose_b, sb.as_ref())
                        .map_or(0.0, |d| d.distance),
                };
                best = best.min(d);
            }
        }
        best
    }
}

/// Whether two poses differ by at most [`SAME`] in translation and in rotation
/// (quaternion components: radians at that size), so a body placed by either lies
/// within a few `SAME` of the other over its lever.
fn near(p: &Pose, q: &Pose) -> bool {
    p.translation.distance(q.translation) <= SAME * 1e-2
        && (p.rotation.dot(q.rotation).abs() - 1.0).abs() <= SAME * 1e-4
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::WorldParams;
    use crate::world::test_worlds::every_arm;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;

    /// The pair's distance by parry's own queries (independent of the climbing hulls).
    fn parry_distance(world: &CollisionWorld, t: &PairTable, a_from_b: &Pose) -> f64 {
        let mut best = f64::INFINITY;
        for (sa, pa) in &world.bodies[t.a].shapes {
            for (sb, pb) in &world.bodies[t.b].shapes {
                let pose_b = *a_from_b * *pb;
                let d = query::distance(pa, sa.as_ref(), &pose_b, sb.as_ref()).expect("distance");
                best = best.min(d.distance);
            }
        }
        best
    }

    /// At random configurations of every arm of three robots, each table's floor is at
    /// most the exact distance of its pair, and the world answers every check as it
    /// does without tables (they only spare work).
    #[test]
    fn floors_bound_the_distance_and_change_no_verdict() {
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        let params = WorldParams {
            acm_samples: 200,
            padding: 0.004,
            ..WorldParams::default()
        };
        for (name, world) in every_arm(&params) {
            assert!(!world.pair_tables.tables.is_empty(), "{name}: tables");
            let mut bare = world.clone();
            bare.pair_tables = PairTables::default();
            let (mut floors, mut differ) = (0, 0);
            for _ in 0..400 {
                let q = world.chain.random_configuration(&mut rng);
                let poses = world.body_poses(&q).expect("poses");
                for t in world.pair_tables.tables.iter() {
                    let floor = t.floor(&world, &q);
                    let a_from_b = poses[t.a].inverse() * poses[t.b];
                    let exact = parry_distance(&world, t, &a_from_b);
                    assert!(floor <= exact, "{name} {} {}: {floor} > {exact}", t.a, t.b);
                    floors += 1;
                }
                let with = world.first_collision(&q).expect("check");
                let without = bare.first_collision(&q).expect("check");
                differ += usize::from(with.is_some() != without.is_some());
            }
            assert!(floors > 0);
            assert_eq!(differ, 0, "{name}: verdicts differ");
        }
    }
}
