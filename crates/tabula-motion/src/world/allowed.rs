//! The allowed-collision matrix: link pairs never checked against each other —
//! adjacent links, pairs the SRDF disables, or (without one) pairs sampling shows never
//! or always collide, as MoveIt's setup assistant finds them — and a planning scene's
//! own matrix over that.

use super::{CollisionWorld, WorldError};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use tabula_geom::Pose;
use tabula_geom::parry::query;

/// `moveit_msgs/AllowedCollisionMatrix`: `allowed[i][j]` for `names[i]`, `names[j]`,
/// and per-name defaults for pairs the matrix does not list.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct AllowedCollisions {
    pub names: Vec<String>,
    pub allowed: Vec<Vec<bool>>,
    pub defaults: Vec<(String, bool)>,
}

impl CollisionWorld {
    /// MoveIt-style allowed collision matrix: adjacent links (through fixed joints too),
    /// pairs that never collide over many random configurations, and pairs that always do.
    pub(super) fn compute_allowed_collisions(&mut self) {
        let n = self.bodies.len();
        let body_of_link: std::collections::HashMap<usize, usize> = self
            .bodies
            .iter()
            .enumerate()
            .map(|(b, lb)| (lb.link, b))
            .collect();
        // Adjacent: the nearest ancestor with geometry.
        for (b, lb) in self.bodies.iter().enumerate() {
            let mut l = lb.link;
            while let Some(j) = self.model.links[l].parent_joint {
                l = self.model.joints[j].parent;
                if let Some(&p) = body_of_link.get(&l) {
                    self.allowed.insert((b.min(p), b.max(p)));
                    break;
                }
            }
        }
        // Rigidly joined (fixed joints only between them, as MoveIt's setup assistant
        // counts adjacency): they never move apart, so their contact never changes — a
        // pedestal and the base plate bolted on it.
        let anchors: Vec<usize> = self
            .bodies
            .iter()
            .map(|b| self.rigid_anchor(b.link))
            .collect();
        for a in 0..n {
            for b in a + 1..n {
                if anchors[a] == anchors[b] {
                    self.allowed.insert((a, b));
                }
            }
        }
        if let Some(srdf) = self
            .params
            .srdf
            .as_ref()
            .filter(|s| s.has_collision_matrix())
        {
            for a in 0..n {
                for b in a + 1..n {
                    if srdf.allows(&self.bodies[a].name, &self.bodies[b].name) {
                        self.allowed.insert((a, b));
                    }
                }
            }
            return;
        }
        let mut collided = vec![0usize; n * n];
        let mut rng = ChaCha8Rng::seed_from_u64(self.params.acm_seed);
        let samples = self.params.acm_samples.max(1);
        let active = self.model.active_joints();
        let mut values = self.values.clone();
        for _ in 0..samples {
            for &j in &active {
                let l = self.model.joints[j].limits;
                let (lo, hi) = if l.lower.is_finite() && l.upper.is_finite() {
                    (l.lower, l.upper)
                } else {
                    (-std::f64::consts::PI, std::f64::consts::PI)
                };
                values[j] = if hi > lo {
                    rand::RngExt::random_range(&mut rng, lo..=hi)
                } else {
                    lo
                };
            }
            let poses = self.model.forward_kinematics(&values).unwrap_or_default();
            for a in 0..n {
                for b in a + 1..n {
                    if self.bodies_touch(&poses, a, b, self.params.padding) {
                        collided[a * n + b] += 1;
                    }
                }
            }
        }
        // "Always" as MoveIt's setup assistant counts it: in ≥ 95 % of the samples.
        for a in 0..n {
            for b in a + 1..n {
                let c = collided[a * n + b];
                if c == 0 || c as f64 >= self.params.always_fraction * samples as f64 {
                    self.allowed.insert((a, b));
                }
            }
        }
    }

    /// The link `link` is welded to: up through fixed joints to the first link a moving
    /// joint carries (or the root).
    fn rigid_anchor(&self, mut link: usize) -> usize {
        while let Some(j) = self.model.links[link].parent_joint {
            let joint = &self.model.joints[j];
            if joint.kind != tabula_robot::model::JointKind::Fixed {
                break;
            }
            link = joint.parent;
        }
        link
    }

    fn bodies_touch(&self, root_from_link: &[Pose], a: usize, b: usize, margin: f64) -> bool {
        let (la, lb) = (&self.bodies[a], &self.bodies[b]);
        for (sa, pa) in &la.shapes {
            let wa = root_from_link[la.link] * *pa;
            for (sb, pb) in &lb.shapes {
                let wb = root_from_link[lb.link] * *pb;
                if query::contact(&wa, sa.as_ref(), &wb, sb.as_ref(), margin)
                    .ok()
                    .flatten()
                    .is_some()
                {
                    return true;
                }
            }
        }
        false
    }

    /// Link pairs the matrix allows, by name (for inspection and tests).
    pub fn allowed_pairs(&self) -> Vec<(String, String)> {
        let mut v: Vec<(String, String)> = self
            .allowed
            .iter()
            .map(|&(a, b)| (self.bodies[a].name.clone(), self.bodies[b].name.clone()))
            .collect();
        v.sort();
        v
    }

    pub(super) fn rebuild_allowed_matrix(&mut self) {
        let n = self.bodies.len();
        self.allowed_matrix = vec![false; n * n];
        for &(a, b) in &self.allowed {
            self.allowed_matrix[a * n + b] = true;
            self.allowed_matrix[b * n + a] = true;
        }
        self.rebuild_body_index();
    }

    /// What a check reads of the bodies, after the matrix, the bodies or the moving
    /// bodies changed: the pairs it tests and how many entries placing them all takes.
    pub(super) fn rebuild_body_index(&mut self) {
        self.pieces = self
            .bodies
            .iter()
            .map(|b| b.shapes.len() + usize::from(b.outer.is_some()))
            .sum();
        let n = self.bodies.len();
        self.checked_pairs = (0..n)
            .flat_map(|a| (a + 1..n).map(move |b| (a, b)))
            .filter(|&(a, b)| self.self_pair_checked(a, b))
            .collect();
    }

    /// Takes a planning scene's matrix: pairs of robot links it settles (listed both, or
    /// by their default entries, MoveIt's rule: a pair with two defaults is allowed only
    /// if both allow it) replace the robot's own answer; pairs it does not mention keep
    /// it. Entries pairing a world object with a link let them touch. Returns the names
    /// the matrix gives that are neither a link with geometry nor an object.
    pub fn set_allowed_collisions(
        &mut self,
        acm: &AllowedCollisions,
    ) -> Result<Vec<String>, WorldError> {
        let body = |w: &Self, name: &str| w.bodies.iter().position(|b| b.name == name);
        let object = |w: &Self, name: &str| w.objects.iter().position(|o| o.name == name);
        let mut unknown = Vec::new();
        for name in acm.names.iter().chain(acm.defaults.iter().map(|(n, _)| n)) {
            if body(self, name).is_none()
                && object(self, name).is_none()
                && self.model.link(name).is_err()
                && !unknown.contains(name)
            {
                unknown.push(name.clone());
            }
        }
        let default = |name: &str| acm.defaults.iter().find(|(n, _)| n == name).map(|d| d.1);
        let n = self.bodies.len();
        for a in 0..n {
            for b in a + 1..n {
                let (na, nb) = (&self.bodies[a].name, &self.bodies[b].name);
                let listed = acm
                    .names
                    .iter()
                    .position(|x| x == na)
                    .zip(acm.names.iter().position(|x| x == nb));
                let verdict = match listed {
                    Some((i, k)) => Some(acm.allowed[i][k] || acm.allowed[k][i]),
                    None => match (default(na), default(nb)) {
                        (Some(x), Some(y)) => Some(x && y),
                        (Some(x), None) | (None, Some(x)) => Some(x),
                        (None, None) => None,
                    },
                };
                match verdict {
                    Some(true) => {
                        self.allowed.insert((a, b));
                    }
                    Some(false) => {
                        self.allowed.remove(&(a, b));
                    }
                    None => {}
                }
            }
        }
        for (i, name) in acm.names.iter().enumerate() {
            let Some(o) = object(self, name) else {
                continue;
            };
            for (k, other) in acm.names.iter().enumerate() {
                if (acm.allowed[i][k] || acm.allowed[k][i])
                    && let Some(b) = body(self, other)
                {
                    self.objects[o].allowed_bodies.push(b);
                }
            }
        }
        self.rebuild_allowed_matrix();
        Ok(unknown)
    }
}
