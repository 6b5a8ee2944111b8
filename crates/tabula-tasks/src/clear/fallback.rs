//! When the seed's actions cannot go on (packed objects, pairs blocking each other's
//! grasp): chain pushes ranked by a one-step look-ahead, then nudge grasps.

use super::decide::{Decider, Decision};
use super::predicates::{Geometry, descent_poses};
use super::{ActionKind, DIRECTIONS, SeenObject, Table};
use crate::skills::Hand;
use tabula_geom::parry::bounding_volume::BoundingVolume;
use tabula_geom::parry::query;
use tabula_geom::parry::shape::SharedShape;
use tabula_geom::{Pose, Vec2, Vec3};

/// How deep (m) `shapes` at any of `poses` reach into `other`'s hull (0 when apart).
pub(super) fn penetration(
    shapes: &[(SharedShape, Pose)],
    poses: &[Pose],
    other: &SeenObject,
) -> f64 {
    let mut deepest: f64 = 0.0;
    for pose in poses {
        for (s, p) in shapes {
            let w = *pose * *p;
            if !s.compute_aabb(&w).intersects(&other.aabb) {
                continue;
            }
            if let Ok(Some(c)) =
                query::contact(&w, s.as_ref(), &Pose::IDENTITY, other.hull.as_ref(), 0.0)
            {
                deepest = deepest.max(-c.dist);
            }
        }
    }
    deepest
}

impl Decider<'_> {
    /// Where the arm stands on the table (world xy of its chain's base).
    pub(super) fn arm_xy(&self) -> Vec2 {
        self.group
            .world
            .world_from_chain_base()
            .map(|b| Vec2::new(b.translation.x, b.translation.y))
            .unwrap_or(Vec2::ZERO)
    }

    /// The chain-push fallback (packed objects, where the seed's actions are stuck): the
    /// domain cannot tell what a push that shoves others along achieves, so the pushes
    /// are ranked by a one-step look-ahead in geometry — how many objects each makes
    /// graspable, then how few it shoves — and the first whose poses have IK is taken.
    pub(super) fn decide_chain(&mut self, g: &Geometry) -> Decision {
        let mut candidates: Vec<(usize, usize)> = Vec::new();
        for (i, o) in self.objects.iter().enumerate() {
            let track = self.tracks.iter().find(|t| t.id == o.id);
            let stacked = g.on.iter().any(|&(a, b)| a == i || b == i);
            for k in 0..4 {
                let p = &g.pushes[i][k];
                let ruled_out = track.is_some_and(|t| t.rules_out(p.direction, self.params));
                let blocked = g.block_push[k].iter().any(|&(_, b)| b == i);
                if p.feasible && !ruled_out && !stacked && !blocked {
                    candidates.push((i, k));
                }
            }
        }
        // Of pushes equally worth it, the one that leaves the pushed object nearest the
        // arm: a push whose good is unknown (a cluster seen as one object) must not walk
        // it out of the arm's reach at the table's far edge.
        let arm_xy = self.arm_xy();
        let from_arm = |i: usize, k: usize| {
            let p = &g.pushes[i][k];
            (self.objects[i].rect.center + p.direction * p.length).distance(arm_xy)
        };
        candidates.sort_by(|&(i, k), &(j, l)| {
            let (p, q) = (&g.pushes[i][k], &g.pushes[j][l]);
            (std::cmp::Reverse(p.gain), p.chain.len())
                .cmp(&(std::cmp::Reverse(q.gain), q.chain.len()))
                .then(from_arm(i, k).total_cmp(&from_arm(j, l)))
        });
        let _ = self.group.set_state(self.robot, self.state);
        let seed = self.group.arm_values(self.state);
        for (i, k) in candidates {
            self.frame.plan = vec![format!(
                "(push_{} o{}) [chain]",
                DIRECTIONS[k], self.objects[i].id
            )];
            match self.first_pose_ik(i, ActionKind::Push(k), g, &seed, &[]) {
                Some(q) => return Decision::Act(i, ActionKind::Push(k), q, Vec::new()),
                None => self.frame.ik_backtracks += 1,
            }
        }
        Decision::NothingRemovable
    }

    /// The last resort (see [`super::ClearParams::nudge_depth`]): grasps of objects
    /// nothing stands on whose open fingers, at the grasp and on the way down to it,
    /// reach at most `nudge_depth` into their blockers' hulls — shallowest first, the
    /// first with IK.
    pub(super) fn decide_nudge(&mut self, g: &Geometry, hand: &Hand, table: &Table) -> Decision {
        let candidates = self.nudge_candidates(g, hand, table.up);
        let _ = self.group.set_state(self.robot, self.state);
        let seed = self.group.arm_values(self.state);
        for (depth, i, nudged) in candidates {
            self.frame.plan = vec![format!(
                "(grasp o{}) [nudging {} by {:.1} mm]",
                self.objects[i].id,
                nudged
                    .iter()
                    .map(|&a| format!("o{}", self.objects[a].id))
                    .collect::<Vec<_>>()
                    .join(" "),
                depth * 1e3
            )];
            match self.first_pose_ik(i, ActionKind::Grasp, g, &seed, &nudged) {
                Some(q) => return Decision::Act(i, ActionKind::Grasp, q, nudged),
                None => self.frame.ik_backtracks += 1,
            }
        }
        Decision::NothingRemovable
    }

    /// Nudge grasps: (depth into the deepest blocker, object, its blockers), shallowest
    /// first.
    fn nudge_candidates(
        &self,
        g: &Geometry,
        hand: &Hand,
        up: Vec3,
    ) -> Vec<(f64, usize, Vec<usize>)> {
        let params = self.params;
        let mut candidates: Vec<(f64, usize, Vec<usize>)> = Vec::new();
        for (i, o) in self.objects.iter().enumerate() {
            let Some(grasp) = &g.grasps[i] else { continue };
            let tried_enough = self
                .tracks
                .iter()
                .find(|t| t.id == o.id)
                .is_some_and(|t| t.grasp_ruled_out(params));
            if tried_enough || g.on.iter().any(|&(_, under)| under == i) {
                continue;
            }
            let blockers: Vec<usize> = g
                .block_grasp
                .iter()
                .filter(|&&(_, b)| b == i)
                .map(|&(a, _)| a)
                .collect();
            if blockers.is_empty() {
                continue;
            }
            let poses = descent_poses(&grasp.poses[0], up, params.pregrasp);
            let shapes = hand.open_for(grasp.width).1;
            let depth = blockers
                .iter()
                .map(|&a| penetration(shapes, &poses, &self.objects[a]))
                .fold(0.0, f64::max);
            if depth <= params.nudge_depth {
                candidates.push((depth, i, blockers));
            }
        }
        candidates.sort_by(|a, b| a.0.total_cmp(&b.0));
        candidates
    }
}
