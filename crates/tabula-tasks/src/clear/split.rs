//! Split pushes: the try left for an object no grasp takes — seen longer than the hand
//! opens, with no grasp across it that fits or that held when tried. Such a segment is
//! often two objects touching end to end with a seam the overhead camera cannot resolve
//! (two tiles on edge end to end, a tile against a standing prism, tops a few
//! millimetres apart: blocks seeds 154, 183, 199). Pushing one end sideways with the
//! closed fingers parts them, or turns a single object, and the next frame sees which
//! it was: interactive perception's singulation push. Each end, each way, is checked
//! as the seed's pushes are: the end's own points swept against the other objects, the
//! hand's path, the table's edge.

use super::decide::{Decider, Decision};
use super::predicates::{Geometry, TableView};
use super::push::Push;
use super::{ActionKind, DIRECTIONS, SeenObject};
use crate::scene::tabletop::seen_standing;
use tabula_geom::Vec3;

/// Fewer seen points than this at one end say too little of where that end's face is.
const MIN_END_POINTS: usize = 20;

impl TableView<'_> {
    /// Whether `o` is shaped like objects end to end: longer than the open hand, no
    /// wider across than it. A segment too wide both ways is objects side by side as
    /// well (a bar beside an arch, blocks seed 127), and pushing one end of it moves
    /// both.
    fn too_long(&self, o: &SeenObject) -> bool {
        let (major, minor) = o.rect.principal_axes();
        o.rect.extent_along(major) > self.hand.open_width
            && o.rect.extent_along(minor) <= self.hand.open_width
    }

    /// The end of `o` on `side` (±1) of its middle along its long axis, as an object
    /// of its own: its seen points standing where `o` stands.
    fn end_of(o: &SeenObject, side: f64) -> Option<SeenObject> {
        let (major, _) = o.rect.principal_axes();
        let points: Vec<Vec3> = o
            .points
            .iter()
            .filter(|q| (q.truncate() - o.rect.center).dot(major) * side > 0.0)
            .copied()
            .collect();
        if points.len() < MIN_END_POINTS {
            return None;
        }
        seen_standing(points, o.bottom)
    }

    /// The feasible split pushes of object `b` as (direction index, push): either end
    /// pushed either way across the long axis by its own width and `split_gap`.
    pub(super) fn split_pushes(&self, b: usize) -> Vec<(usize, Push)> {
        let (o, params) = (&self.objects[b], self.params);
        if !self.too_long(o) {
            return Vec::new();
        }
        let mut out = Vec::new();
        for side in [1.0, -1.0] {
            let Some(end) = Self::end_of(o, side) else {
                continue;
            };
            for k in [2, 3] {
                let d = o.direction(k);
                let length =
                    (end.rect.extent_along(d) + params.split_gap).min(params.push_max_length);
                let p = Push {
                    direction: d,
                    length,
                    chain: Vec::new(),
                    gain: 0,
                    split: true,
                    // The closed fingers one behind the other: a narrow pusher that
                    // meets this end only.
                    start: self.push_start(&end, d, true, self.highest_ahead(b, d)),
                    feasible: true,
                };
                if self.split_is_free(b, &end, &p) {
                    out.push((k, p));
                }
            }
        }
        out
    }

    /// Whether the end `end` of object `b` pushed along `p` stays on the table and
    /// runs into nothing, and the hand meets nothing on its way.
    fn split_is_free(&self, b: usize, end: &SeenObject, p: &Push) -> bool {
        let sweep = self.sweep_of(p.direction3(), p.length);
        self.stays_on_table(end, p.direction, p.length)
            && (0..self.objects.len())
                .filter(|&a| a != b)
                .all(|a| !self.collides(end, &sweep, a))
            && self
                .gripper_hits(b, &self.hand_path(p, p.travel(self.params)))
                .is_empty()
    }
}

impl Decider<'_> {
    /// When the seed's actions cannot go on: a split push of an object no grasp takes
    /// (none fits, or it failed every time) that is longer than the open hand, at most
    /// `max_split_pushes` per tracked object — the end that stays nearest the arm
    /// first, the first with IK. The chosen push takes its direction's place in `g`.
    pub(super) fn decide_split(&mut self, view: &TableView<'_>, g: &mut Geometry) -> Decision {
        let params = self.params;
        let arm_xy = self.arm_xy();
        let mut candidates: Vec<(f64, usize, usize, Push)> = Vec::new();
        for (i, o) in self.objects.iter().enumerate() {
            let track = self.tracks.iter().find(|t| t.id == o.id);
            let no_grasp =
                g.grasps[i].is_none() || track.is_some_and(|t| t.grasp_ruled_out(params));
            let stacked = g.on.iter().any(|&(a, b)| a == i || b == i);
            let splits_left = track.is_none_or(|t| t.splits < params.max_split_pushes);
            if !no_grasp || stacked || !splits_left {
                continue;
            }
            for (k, p) in view.split_pushes(i) {
                let end = p.start.translation.truncate() + p.direction * p.travel(params);
                candidates.push((end.distance(arm_xy), i, k, p));
            }
        }
        candidates.sort_by(|a, b| a.0.total_cmp(&b.0));
        let _ = self.group.set_state(self.robot, self.state);
        let seed = self.group.arm_values(self.state);
        for (_, i, k, p) in candidates {
            self.frame.plan = vec![format!(
                "(push_{} o{}) [split: one end]",
                DIRECTIONS[k], self.objects[i].id
            )];
            let seed_push = std::mem::replace(&mut g.pushes[i][k], p);
            match self.first_pose_ik(i, ActionKind::Push(k), g, &seed, &[]) {
                Some(q) => return Decision::Act(i, ActionKind::Push(k), q, Vec::new()),
                None => {
                    self.frame.ik_backtracks += 1;
                    g.pushes[i][k] = seed_push;
                }
            }
        }
        Decision::NothingRemovable
    }
}
