//! How fast things can come together along one straight joint-space segment — per
//! body against the world, per pair of bodies against each other.
//!
//! One bound for the whole robot (every joint's lever to the farthest point) lets the
//! wrist's own pairs, always centimetres apart, hold conservative advancement to
//! centimetre steps even while the arm swings through open space. Two wrist links move
//! relative to each other only by the joints between them, over their short levers:
//! each checked pair gets its own rate, so each pair's margin is spent at its own pace.

use super::CollisionWorld;

/// Per-body displacement bounds along one segment a→b (metres over the whole segment).
pub struct SweepRates {
    /// Per body, per chain element `k`: how far the body's points can move over the
    /// segment by elements `0..=k` (a prefix sum; zero past the body's own element).
    prefix: Vec<f64>,
    elements: usize,
    /// Each body's chain element (`None`: it does not move with the chain).
    anchor: Vec<Option<usize>>,
    /// The whole robot's bound, for chains the bodies could not be anchored to.
    whole: f64,
}

impl SweepRates {
    /// How far any point of body `b` (and what it holds) can move in the world.
    pub fn body(&self, b: usize) -> f64 {
        match self.anchor.get(b).copied().flatten() {
            Some(m) => self.prefix[b * self.elements + m],
            None if self.anchor.is_empty() => self.whole,
            None => 0.0,
        }
    }

    /// How far the points of `a` and `b` can move relative to each other: by the
    /// joints between their elements only.
    pub fn pair(&self, a: usize, b: usize) -> f64 {
        if self.anchor.is_empty() {
            return self.whole;
        }
        // Unanchored bodies sit before every element.
        let order = |m: Option<usize>| m.map_or(0, |k| k + 1);
        let (earlier, later) = if order(self.anchor[a]) <= order(self.anchor[b]) {
            (a, b)
        } else {
            (b, a)
        };
        let Some(m) = self.anchor[later] else {
            return 0.0;
        };
        let row = &self.prefix[later * self.elements..(later + 1) * self.elements];
        row[m] - self.anchor[earlier].map_or(0.0, |k| row[k])
    }

    /// The largest rate of any body (the whole robot's bound where anchored).
    pub fn fastest(&self) -> f64 {
        (0..self.anchor.len()).map(|b| self.body(b)).fold(
            if self.anchor.is_empty() {
                self.whole
            } else {
                0.0
            },
            f64::max,
        )
    }
}

impl CollisionWorld {
    /// The displacement bounds of the segment a→b, per body and per pair.
    pub fn sweep_rates(&self, a: &[f64], b: &[f64]) -> SweepRates {
        let whole = self.displacement_bound(a, b);
        let n = self.bodies.len();
        let elements = self.chain.elements.len();
        if self.element_joints.is_none() || self.levers.len() != n * elements {
            return SweepRates {
                prefix: Vec::new(),
                elements,
                anchor: Vec::new(),
                whole,
            };
        }
        let mut prefix = vec![0.0; n * elements];
        for body in 0..n {
            let mut sum = 0.0;
            for (k, e) in self.chain.elements.iter().enumerate() {
                sum += (b[e.var] - a[e.var]).abs() * self.reach(k, body);
                prefix[body * elements + k] = sum;
            }
        }
        SweepRates {
            prefix,
            elements,
            anchor: self.anchors.iter().map(|a| a.element).collect(),
            whole,
        }
    }

    /// How far one unit of chain element `k`'s variable can move any point of `body`
    /// (a prismatic joint's travel, a revolute one's lever to the body's points; needs
    /// the lever table).
    pub(super) fn reach(&self, k: usize, body: usize) -> f64 {
        let e = &self.chain.elements[k];
        let lever = if e.prismatic {
            1.0
        } else {
            self.levers[k * self.bodies.len() + body]
        };
        e.multiplier.abs() * lever
    }

    /// With anchors known, bound each joint's lever arm by the bodies actually beyond it
    /// (chain offsets up to the body's element, plus the body's own extent, plus what it
    /// holds) instead of the whole chain plus a generous margin — per body (for
    /// [`SweepRates`]) and per joint (for [`Self::displacement_bound`]).
    pub(super) fn tighten_motion_radius(&mut self) {
        let Some(levers) = self.lever_table() else {
            self.levers.clear();
            return;
        };
        let n = self.bodies.len();
        let mut radius = vec![0.0f64; self.chain.dof()];
        for (k, ek) in self.chain.elements.iter().enumerate() {
            let lever = levers[k * n..(k + 1) * n]
                .iter()
                .copied()
                .fold(0.0, f64::max);
            let r = if ek.prismatic { 1.0 } else { lever } * ek.multiplier.abs();
            radius[ek.var] = radius[ek.var].max(r);
        }
        self.motion_radius = radius;
        self.levers = levers;
    }

    /// Per chain element `k` and body `b` (index `k · bodies + b`): how far any point of
    /// `b` (and of what it holds) can be from element `k`'s joint origin; 0 when `b` is
    /// not beyond `k`. `None` when the bodies could not be anchored.
    fn lever_table(&self) -> Option<Vec<f64>> {
        self.element_joints.as_ref()?;
        let elements = &self.chain.elements;
        let n = self.bodies.len();
        let mut extent = vec![0.0f64; n];
        for (b, body) in self.bodies.iter().enumerate() {
            let a = self.anchors[b];
            for (shape, p) in &body.shapes {
                let sphere = shape.compute_local_bounding_sphere();
                extent[b] =
                    extent[b].max((a.offset * (*p * sphere.center())).length() + sphere.radius());
            }
        }
        for att in &self.attached {
            let a = self.anchors[att.body];
            let sphere = att.shape.compute_local_bounding_sphere();
            let reach =
                (a.offset * (att.link_from_object * sphere.center())).length() + sphere.radius();
            extent[att.body] = extent[att.body].max(reach);
        }
        let mut table = vec![0.0f64; elements.len() * n];
        for k in 0..elements.len() {
            for (b, a) in self.anchors.iter().enumerate() {
                let Some(m) = a.element else { continue };
                if m < k {
                    continue;
                }
                // Fixed offsets, plus the travel of any prismatic joint in between.
                let lever: f64 = elements[k + 1..=m]
                    .iter()
                    .map(|e| {
                        let travel = if e.prismatic {
                            e.multiplier.abs()
                                * self.chain.lower[e.var]
                                    .abs()
                                    .max(self.chain.upper[e.var].abs())
                                + e.offset.abs()
                        } else {
                            0.0
                        };
                        e.pre.translation.length() + travel
                    })
                    .sum();
                table[k * n + b] = lever + extent[b];
            }
        }
        Some(table)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::WorldParams;
    use crate::world::test_worlds::every_arm;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;
    use tabula_geom::{Pose, Vec3};

    /// Points of each body in its link frame: its hulls' vertices, else its shapes'
    /// bounding spheres' centres.
    fn body_points(world: &CollisionWorld) -> Vec<Vec<Vec3>> {
        world
            .bodies
            .iter()
            .map(|b| {
                b.shapes
                    .iter()
                    .flat_map(|(s, p)| match s.as_convex_polyhedron() {
                        Some(c) => c.points().iter().map(|v| *p * *v).collect::<Vec<_>>(),
                        None => vec![*p * s.compute_local_bounding_sphere().center()],
                    })
                    .collect()
            })
            .collect()
    }

    /// Along random segments of every arm of three robots (a 7R arm, a mimic-free
    /// tree with a torso lift, one with a prismatic torso), no point of a body moves
    /// farther than its rate, and no point of a pair's later body moves farther than
    /// the pair's rate in the earlier body's frame — the bounds conservative
    /// advancement trusts.
    #[test]
    fn rates_bound_every_body_and_every_pair() {
        let mut rng = ChaCha8Rng::seed_from_u64(11);
        let params = WorldParams {
            acm_samples: 10,
            ..WorldParams::default()
        };
        for (name, world) in every_arm(&params) {
            assert!(!world.levers.is_empty(), "{name} anchored");
            let points = body_points(&world);
            let n = world.bodies.len();
            let sample = |rng: &mut ChaCha8Rng| world.chain.random_configuration(rng);
            for _ in 0..40 {
                let (a, b) = (sample(&mut rng), sample(&mut rng));
                let rates = world.sweep_rates(&a, &b);
                let at = |t: f64| -> Vec<Pose> {
                    let q: Vec<f64> = a.iter().zip(&b).map(|(x, y)| x + (y - x) * t).collect();
                    world.body_poses(&q).expect("poses")
                };
                let start = at(0.0);
                for step in 1..=20 {
                    let now = at(step as f64 / 20.0);
                    for i in 0..n {
                        for x in &points[i] {
                            let moved = (now[i] * *x - start[i] * *x).length();
                            assert!(moved <= rates.body(i) + 1e-9, "{name}: body {i}");
                        }
                        for k in 0..n {
                            let order = |m: Option<usize>| m.map_or(0, |e| e + 1);
                            if order(world.anchors[k].element) < order(world.anchors[i].element) {
                                continue;
                            }
                            let rel = |p: &[Pose], x: Vec3| p[i].inverse() * (p[k] * x);
                            for x in &points[k] {
                                let moved = (rel(&now, *x) - rel(&start, *x)).length();
                                assert!(
                                    moved <= rates.pair(i, k) + 1e-9,
                                    "{name}: pair {i} {k}: {moved} > {}",
                                    rates.pair(i, k)
                                );
                            }
                        }
                    }
                }
                assert!(rates.fastest() <= world.displacement_bound(&a, &b) + 1e-9);
            }
        }
    }
}
