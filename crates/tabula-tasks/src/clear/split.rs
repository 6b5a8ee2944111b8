//! Split pushes: the try left for an object no grasp takes — seen longer than the hand
//! opens, with no grasp across it that fits or that held when tried. Such a segment is
//! often two objects touching with a seam the overhead camera cannot resolve (two tiles
//! on edge end to end, a tile against a standing prism, a bar beside an arch, tops a
//! few millimetres apart: blocks seeds 154, 183, 127). Pushing one half of it with the
//! closed fingers — an end sideways, or a side along the seam — parts them, or turns a
//! single object, and the next frame sees which it was: interactive perception's
//! singulation push. Each half, each way, is checked as the seed's pushes are: the
//! half's own points swept against the other objects, the hand's path, the table's edge.

use super::decide::{Decider, Decision};
use super::predicates::{Geometry, TableView};
use super::push::Push;
use super::{ActionKind, DIRECTIONS, SeenObject};
use crate::scene::tabletop::seen_standing;
use tabula_geom::{Vec2, Vec3};

/// Fewer seen points than this in one half say too little of where its faces are.
const MIN_HALF_POINTS: usize = 20;

impl TableView<'_> {
    /// How `o` would be parted, when it is too long for the open hand: the axis its
    /// halves lie along and the push directions (indices) that move one half. A
    /// segment longer than the hand but no wider is objects end to end: one end goes
    /// sideways. One wider than the hand both ways, when each object fits the hand, is
    /// objects side by side across its short axis (a bar beside an arch, blocks seed
    /// 127), which an end push would move together: one side slides along the seam.
    fn split_axis(&self, o: &SeenObject) -> Option<(Vec2, [usize; 2])> {
        let (major, minor) = o.rect.principal_axes();
        let open = self.hand.open_width;
        if o.rect.extent_along(major) <= open {
            None
        } else if o.rect.extent_along(minor) <= open {
            Some((major, [2, 3]))
        } else {
            Some((minor, [0, 1]))
        }
    }

    /// The half of `o` on `side` (±1) of its middle along `axis`, as an object of its
    /// own: its seen points standing where `o` stands.
    fn half_of(o: &SeenObject, axis: Vec2, side: f64) -> Option<SeenObject> {
        let points: Vec<Vec3> = o
            .points
            .iter()
            .filter(|q| (q.truncate() - o.rect.center).dot(axis) * side > 0.0)
            .copied()
            .collect();
        if points.len() < MIN_HALF_POINTS {
            return None;
        }
        seen_standing(points, o.bottom)
    }

    /// The feasible split pushes of object `b` as (direction index, push): either half
    /// (see [`Self::split_axis`]) pushed either way past its own size and `split_gap`.
    pub(super) fn split_pushes(&self, b: usize) -> Vec<(usize, Push)> {
        let (o, params) = (&self.objects[b], self.params);
        let Some((axis, dirs)) = self.split_axis(o) else {
            return Vec::new();
        };
        let mut out = Vec::new();
        for side in [1.0, -1.0] {
            let Some(half) = Self::half_of(o, axis, side) else {
                continue;
            };
            for k in dirs {
                let d = o.direction(k);
                let length =
                    (half.rect.extent_along(d) + params.split_gap).min(params.push_max_length);
                let p = Push {
                    direction: d,
                    length,
                    chain: Vec::new(),
                    gain: 0,
                    split: true,
                    // The closed fingers one behind the other: a narrow pusher that
                    // meets this half only.
                    start: self.push_start(&half, d, true, self.highest_ahead(b, d)),
                    feasible: true,
                };
                if self.split_is_free(b, &half, &p) {
                    out.push((k, p));
                }
            }
        }
        out
    }

    /// Whether the half `half` of object `b` pushed along `p` stays on the table and
    /// runs into nothing, and the hand meets nothing on its way.
    fn split_is_free(&self, b: usize, half: &SeenObject, p: &Push) -> bool {
        let sweep = self.sweep_of(p.direction3(), p.length);
        self.stays_on_table(half, p.direction, p.length)
            && (0..self.objects.len())
                .filter(|&a| a != b)
                .all(|a| !self.collides(half, &sweep, a))
            && self
                .gripper_hits(b, &self.hand_path(p, p.travel(self.params)))
                .is_empty()
    }
}

impl Decider<'_> {
    /// When the seed's actions cannot go on: a split push of an object no grasp takes
    /// (none fits, or it failed every time) that is longer than the open hand, at most
    /// `max_split_pushes` per tracked object — the push that ends nearest the arm
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
                "(push_{} o{}) [split: one half]",
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
