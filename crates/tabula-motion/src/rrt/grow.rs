//! The two trees of RRT-Connect and their growth, with dynamic-domain sampling and
//! balanced trees as VAMP's RRT-Connect.

use super::edge::segment_valid_spaced;
use super::shortcut::shortcut_spaced;
use super::{Path, PlannerParams, linf};
use crate::world::CollisionWorld;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::time::Instant;

struct Tree {
    nodes: Vec<Vec<f64>>,
    parent: Vec<usize>,
    /// Each node's dynamic-domain radius (infinite until an extension from it fails).
    radius: Vec<f64>,
}

impl Tree {
    fn new(roots: Vec<Vec<f64>>) -> Self {
        let n = roots.len();
        Self {
            nodes: roots,
            parent: vec![usize::MAX; n],
            radius: vec![f64::INFINITY; n],
        }
    }

    /// The nearest node and its squared Euclidean distance.
    fn nearest(&self, q: &[f64]) -> (usize, f64) {
        let mut best = (0, f64::INFINITY);
        for (i, n) in self.nodes.iter().enumerate() {
            let d: f64 = n.iter().zip(q).map(|(x, y)| (x - y) * (x - y)).sum();
            if d < best.1 {
                best = (i, d);
            }
        }
        best
    }

    fn push(&mut self, q: Vec<f64>, parent: usize) -> usize {
        self.nodes.push(q);
        self.parent.push(parent);
        self.radius.push(f64::INFINITY);
        self.nodes.len() - 1
    }

    /// Whether a sample at squared distance `d2` from node `near` lies in its domain.
    fn in_domain(&self, near: usize, d2: f64) -> bool {
        let r = self.radius[near];
        r.is_infinite() || r * r >= d2
    }

    /// An extension from `near` failed: its domain starts at `domain_radius` and
    /// shrinks at each further failure, down to `domain_min_radius`.
    fn failed_from(&mut self, near: usize, p: &PlannerParams) {
        let r = &mut self.radius[near];
        *r = if r.is_finite() {
            (*r * (1.0 - p.domain_alpha)).max(p.domain_min_radius)
        } else {
            p.domain_radius
        };
    }

    /// An extension from `near` succeeded: a bounded domain grows.
    fn succeeded_from(&mut self, near: usize, p: &PlannerParams) {
        if self.radius[near].is_finite() {
            self.radius[near] *= 1.0 + p.domain_alpha;
        }
    }

    fn path_to_root(&self, mut i: usize) -> Vec<Vec<f64>> {
        let mut out = vec![self.nodes[i].clone()];
        while self.parent[i] != usize::MAX {
            i = self.parent[i];
            out.push(self.nodes[i].clone());
        }
        out
    }
}

enum Extend {
    Trapped,
    Advanced(usize),
    Reached(usize),
}

/// Extends `tree` from its nearest node towards `q`; with `domain`, a sample outside
/// the nearest node's dynamic domain is skipped and the node's radius follows the
/// outcome.
fn extend(
    world: &CollisionWorld,
    tree: &mut Tree,
    q: &[f64],
    p: &PlannerParams,
    spacing: f64,
    domain: bool,
) -> Extend {
    let (near, d2) = tree.nearest(q);
    if domain && !tree.in_domain(near, d2) {
        return Extend::Trapped;
    }
    let from = tree.nodes[near].clone();
    let d = linf(&from, q);
    let (target, reached) = if d <= p.range {
        (q.to_vec(), true)
    } else {
        let s = p.range / d;
        (
            from.iter().zip(q).map(|(a, b)| a + (b - a) * s).collect(),
            false,
        )
    };
    if !segment_valid_spaced(world, &from, &target, p.resolution, spacing) {
        if domain {
            tree.failed_from(near, p);
        }
        return Extend::Trapped;
    }
    if domain {
        tree.succeeded_from(near, p);
    }
    let i = tree.push(target, near);
    if reached {
        Extend::Reached(i)
    } else {
        Extend::Advanced(i)
    }
}

/// The RRT-Connect loop with edges checked at `spacing`; `None` at the deadline. The
/// straight line is not tried: the caller has certified it or found it blocked, and a
/// coarse check passing it again would hand back the same refused path every round.
pub(super) fn grow(
    world: &CollisionWorld,
    start: &[f64],
    goals: &[Vec<f64>],
    p: &PlannerParams,
    spacing: f64,
    deadline: Instant,
) -> Option<Path> {
    let mut rng = ChaCha8Rng::seed_from_u64(p.seed);
    let mut a = Tree::new(vec![start.to_vec()]);
    let mut b = Tree::new(goals.to_vec());
    // Swapped before each round: the start tree grows first.
    std::mem::swap(&mut a, &mut b);
    let mut a_is_start = false;
    let chain = &world.chain;
    let mut q = vec![0.0; start.len()];
    let mut iter = 0usize;
    loop {
        iter += 1;
        if iter.is_multiple_of(16) && Instant::now() >= deadline {
            return None;
        }
        // Alternate, unless one tree is over twice the other: then the smaller grows.
        let (na, nb) = (a.nodes.len() as f64, b.nodes.len() as f64);
        if !p.balance || (na - nb).abs() < na {
            std::mem::swap(&mut a, &mut b);
            a_is_start = !a_is_start;
        }
        for (i, v) in q.iter_mut().enumerate() {
            let (lo, hi) = chain.sample_range(i);
            *v = rng.random_range(lo..=hi);
        }
        let new = match extend(world, &mut a, &q, p, spacing, p.dynamic_domain) {
            Extend::Trapped => None,
            Extend::Advanced(i) | Extend::Reached(i) => Some(i),
        };
        if let Some(ai) = new {
            // Connect the other tree towards the new node greedily.
            let target = a.nodes[ai].clone();
            loop {
                match extend(world, &mut b, &target, p, spacing, false) {
                    Extend::Trapped => break,
                    Extend::Advanced(_) => continue,
                    Extend::Reached(bi) => {
                        let mut from_a = a.path_to_root(ai);
                        from_a.reverse();
                        let from_b = b.path_to_root(bi);
                        let mut waypoints = from_a;
                        waypoints.extend(from_b.into_iter().skip(1));
                        if !a_is_start {
                            waypoints.reverse();
                        }
                        let mut path = Path {
                            waypoints,
                            planning_time: 0.0,
                            tree_nodes: a.nodes.len() + b.nodes.len(),
                        };
                        shortcut_spaced(world, &mut path, p, &mut rng, spacing);
                        return Some(path);
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_node_that_failed_takes_only_near_samples_until_it_succeeds_again() {
        let p = PlannerParams {
            domain_alpha: 0.5,
            ..PlannerParams::default()
        };
        let mut t = Tree::new(vec![vec![0.0, 0.0]]);
        assert!(t.in_domain(0, 1e6), "unbounded before any failure");
        t.failed_from(0, &p);
        assert_eq!(t.radius[0], p.domain_radius);
        assert!(t.in_domain(0, 3.9 * 3.9) && !t.in_domain(0, 4.1 * 4.1));
        for _ in 0..10 {
            t.failed_from(0, &p);
        }
        assert_eq!(
            t.radius[0], p.domain_min_radius,
            "shrinks to the floor, no further"
        );
        t.succeeded_from(0, &p);
        assert_eq!(t.radius[0], 1.5);
        let i = t.push(vec![1.0, 0.0], 0);
        assert!(t.radius[i].is_infinite() && t.parent[i] == 0);
        let (near, d2) = t.nearest(&[0.9, 0.1]);
        assert!(near == 1 && (d2 - 0.02).abs() < 1e-12);
    }
}
