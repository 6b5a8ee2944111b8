//! Deciding the next action of a frame: plan with the seed's domain, check IK for the
//! first action only, backtrack by `ik_unfeasible_*` facts (SPEC §3.5).

use super::first::{Urgency, first_step};
use super::predicates::Geometry;
use super::problem::{action_of, infeasible_atom, planner, problem};
use super::push::Push;
use super::track::Track;
use super::{ActionKind, ClearParams, ClearReport, FrameReport, SeenObject};
use crate::skills::GraspCandidate;
use crate::skills::world::{load_objects, without};
use std::time::Duration;
use tabula_geom::{Pose, Vec3};
use tabula_motion::MoveGroup;
use tabula_motion::group::thread_cpu;
use tabula_pddl::{Budget, Domain, NoPlan, Plan, Planner, SearchMode};
use tabula_robot::driver::JointState;
use tabula_robot::robots::NamedRobot;

/// What a frame decided.
pub(super) enum Decision {
    /// Object index, action, the IK solution found for its first pose, and the
    /// neighbours a nudge grasp pushes aside (empty otherwise).
    Act(usize, ActionKind, Vec<f64>, Vec<usize>),
    NoPlan,
    NothingRemovable,
}

/// What a decision works with: the frame's objects and their tracks, the arm's move
/// group (its world holds the objects' hulls while deciding) and where the arm is.
pub(super) struct Decider<'a> {
    pub(super) objects: &'a [SeenObject],
    pub(super) tracks: &'a [Track],
    pub(super) group: &'a mut MoveGroup,
    pub(super) robot: &'a NamedRobot,
    pub(super) state: &'a JointState,
    /// The table's height (world z).
    pub(super) table_z: f64,
    pub(super) params: &'a ClearParams,
    pub(super) frame: &'a mut FrameReport,
}

/// The poses an action must reach, first one first: pre-grasp and grasp, or pre-push,
/// push start and push end.
fn action_poses(
    kind: ActionKind,
    grasp: Option<&GraspCandidate>,
    push: &[Push; 4],
    yaw: usize,
    params: &ClearParams,
) -> Vec<Pose> {
    let up = Vec3::Z;
    let above = |p: &Pose, height: f64| Pose::from_parts(p.translation + up * height, p.rotation);
    match kind {
        ActionKind::Grasp => {
            let Some(g) = grasp.map(|g| g.poses[yaw]) else {
                return Vec::new();
            };
            vec![above(&g, params.pregrasp), g]
        }
        ActionKind::Push(k) => {
            let p = &push[k];
            let end = Pose::from_parts(
                p.start.translation + p.direction3() * p.travel(params),
                p.start.rotation,
            );
            vec![above(&p.start, params.pre_push_height), p.start, end]
        }
    }
}

impl Decider<'_> {
    /// Plans, then checks IK for the first action only; an infeasible action becomes an
    /// `ik_unfeasible_*` fact and the planner runs again (SPEC §3.5). Facts the tracks
    /// already know (pushes back, too many pushes or grasp attempts, grasps too wide,
    /// pushes off the table) are set before the first plan: every lazily discovered
    /// infeasibility is an `ik_unfeasible_*` fact to the domain.
    pub(super) fn decide(
        &mut self,
        g: &Geometry,
        domain: &Domain,
        report: &mut ClearReport,
    ) -> Decision {
        let n = self.objects.len();
        // Objects no grasp of this gripper can hold never leave the table: out of the
        // goal.
        let goal: Vec<usize> = (0..n).filter(|&i| g.grasps[i].is_some()).collect();
        report.dropped_from_goal = report.dropped_from_goal.max(n - goal.len());
        if goal.is_empty() {
            return Decision::NothingRemovable;
        }
        self.trace(g);
        let Some(mut planner) = problem(domain, self.objects, g, &goal)
            .ok()
            .and_then(|p| planner(domain, p))
        else {
            return Decision::NoPlan;
        };
        // Which objects' grasps are `ik_unfeasible` now (a push first clears it).
        let mut no_grasp = self.known_infeasible(&mut planner, g);
        self.load_objects();
        let seed = self.group.arm_values(self.state);
        for _ in 0..(5 * n + 5) {
            let plan = match self.plan(&planner, n) {
                Ok(p) => p,
                Err(NoPlan::Unsolvable) => {
                    // Objects that can never be removed leave the goal (SPEC §3.5) —
                    // again after every IK backtrack that makes more of them so.
                    match planner.drop_unreachable_goals(self.budget(self.params.plan_max_expanded))
                    {
                        Ok(d) if !d.is_empty() => {
                            report.dropped_from_goal = report.dropped_from_goal.max(d.len());
                            if planner.goal_atoms().is_some_and(|a| a.is_empty()) {
                                return Decision::NothingRemovable;
                            }
                            continue;
                        }
                        _ => return Decision::NothingRemovable,
                    }
                }
                Err(_) => return Decision::NoPlan,
            };
            if plan.steps.is_empty() {
                return Decision::NothingRemovable;
            }
            let mut steps = plan.steps;
            let k = first_step(
                &steps,
                g,
                |i| self.urgency(i),
                |s| {
                    action_of(s, self.objects)
                        .map(|(i, _)| i)
                        .filter(|&i| !no_grasp[i])
                },
            );
            steps[..=k].rotate_right(1);
            self.frame.plan = steps.iter().map(|s| s.to_string()).collect();
            let first = &steps[0];
            let Some((i, kind)) = action_of(first, self.objects) else {
                return Decision::NoPlan;
            };
            match self.first_pose_ik(i, kind, g, &seed, &[]) {
                Some(q) => return Decision::Act(i, kind, q, Vec::new()),
                None => {
                    self.frame.ik_backtracks += 1;
                    if kind == ActionKind::Grasp {
                        no_grasp[i] = true;
                    }
                    let _ = planner.set_fact(&infeasible_atom(kind, self.objects[i].id), true);
                }
            }
        }
        Decision::NoPlan
    }

    /// A plan of the frame's problem: optimal (A* + LM-cut) up to `optimal_up_to` objects
    /// while it stays within `optimal_max_expanded`, else greedy. On the pile suite's
    /// frames of 20–31 objects A* expands at most 40 states where greedy search expands
    /// up to 26,000 (0.5 s) and returns longer plans; on one frame it is the other way
    /// round (A* past 10,000, greedy 32), hence the fallback.
    fn plan(&self, planner: &Planner, n: usize) -> Result<Plan, NoPlan> {
        let params = self.params;
        if n <= params.optimal_up_to {
            let budget = self.budget(params.optimal_max_expanded.min(params.plan_max_expanded));
            match planner.plan_within(SearchMode::Optimal, budget) {
                Err(NoPlan::Timeout) => {
                    tracing::debug!(objects = n, "clear: A* over its budget, greedy search");
                }
                done => return done,
            }
        }
        let plan = planner.plan_within(SearchMode::Fast, self.budget(params.plan_max_expanded));
        if let Ok(p) = &plan {
            tracing::debug!(expanded = p.expanded, objects = n, "clear: greedy plan");
        }
        plan
    }

    /// A search's budget: `max_expanded` states, with the wall-clock net.
    fn budget(&self, max_expanded: usize) -> Budget {
        Budget {
            timeout: Some(Duration::from_secs_f64(
                self.params.plan_timeout_s.max(1e-3),
            )),
            max_expanded: Some(max_expanded),
        }
    }

    /// How urgent lifting object `i` now is (see [`first_step`]).
    fn urgency(&self, i: usize) -> Urgency {
        let (risk, below) = (&self.params.at_risk, &self.objects[i]);
        Urgency {
            props_up: self
                .objects
                .iter()
                .enumerate()
                .any(|(j, above)| j != i && risk.props_up(below, above, self.table_z)),
            risk: risk.of(below, self.table_z),
        }
    }

    /// The objects as the decision sees them (debug log).
    fn trace(&self, g: &Geometry) {
        if !tracing::enabled!(tracing::Level::DEBUG) {
            return;
        }
        for (i, o) in self.objects.iter().enumerate() {
            tracing::debug!(
                "o{}: centre ({:.3}, {:.3}) rect {:.3} × {:.3}, bottom {:.3} top {:.3}, risk {:.3}, grasp {}",
                o.id,
                o.rect.center.x,
                o.rect.center.y,
                o.rect.size.x,
                o.rect.size.y,
                o.bottom,
                o.top,
                self.params.at_risk.of(o, self.table_z),
                match &g.grasps[i] {
                    Some(c) => {
                        let t = c.world_from_tool().translation;
                        format!(
                            "at ({:.4}, {:.4}, {:.4}) opening {:.4}",
                            t.x, t.y, t.z, c.width
                        )
                    }
                    None => "too wide".into(),
                }
            );
        }
        tracing::debug!(
            "on {:?}; block_grasp {:?}; block_push {:?}",
            g.on,
            g.block_grasp,
            g.block_push
        );
    }

    /// Sets the `ik_unfeasible_*` facts known before planning: no grasp fits, grasps
    /// tried enough, pushes off the table or ruled out by the track. Returns which
    /// objects' grasps are set so.
    fn known_infeasible(&self, planner: &mut Planner, g: &Geometry) -> Vec<bool> {
        let params = self.params;
        let mut no_grasp = vec![false; self.objects.len()];
        for (i, o) in self.objects.iter().enumerate() {
            let track = self.tracks.iter().find(|t| t.id == o.id);
            let mut set = |kind: ActionKind| {
                let _ = planner.set_fact(&infeasible_atom(kind, o.id), true);
            };
            if g.grasps[i].is_none() || track.is_some_and(|t| t.grasp_ruled_out(params)) {
                set(ActionKind::Grasp);
                no_grasp[i] = true;
            }
            for k in 0..4 {
                let p = &g.pushes[i][k];
                if !p.feasible || track.is_some_and(|t| t.rules_out(p.direction, params)) {
                    set(ActionKind::Push(k));
                }
            }
        }
        no_grasp
    }

    /// The group at the arm's state with this frame's objects' hulls in its world (the
    /// target is taken out per pose by [`Self::first_pose_ik`]).
    fn load_objects(&mut self) {
        let _ = self.group.set_state(self.robot, self.state);
        load_objects(self.group, self.objects);
    }

    /// IK (collision-free, the target object out of the world) for every pose of the
    /// action, the gripper at either yaw; the solution of the first pose when all have
    /// one. Its CPU time counts as the frame's IK time.
    pub(super) fn first_pose_ik(
        &mut self,
        i: usize,
        kind: ActionKind,
        g: &Geometry,
        seed: &[f64],
        nudged: &[usize],
    ) -> Option<Vec<f64>> {
        let c = thread_cpu();
        let objects = self.objects;
        // The target, what a chain push shoves along and what a nudge grasp pushes aside
        // move: out of the world here.
        let mut moving = vec![i];
        moving.extend(nudged);
        if let ActionKind::Push(k) = kind {
            moving.extend(&g.pushes[i][k].chain);
        }
        let yaws: &[usize] = match kind {
            ActionKind::Grasp => &[0, 1],
            ActionKind::Push(_) => &[0],
        };
        let params = self.params;
        let found = without(self.group, objects, &moving, |group| {
            yaws.iter().find_map(|&yaw| {
                let poses = action_poses(kind, g.grasps[i].as_ref(), &g.pushes[i], yaw, params);
                chain_ik(group, &poses, seed, |p, e| {
                    if tracing::enabled!(tracing::Level::DEBUG) {
                        tracing::debug!(
                            "IK {} o{} yaw {yaw} at ({:.3}, {:.3}, {:.3}): {e}",
                            kind.pddl(),
                            objects[i].id,
                            p.translation.x,
                            p.translation.y,
                            p.translation.z
                        );
                    }
                })
            })
        });
        self.frame.ik_ms += (thread_cpu() - c) * 1e3;
        found
    }
}

/// Collision-free IK for `poses` in turn, each seeded by the last; the first pose's
/// solution when all have one (`failed` is told the pose that has none).
fn chain_ik(
    group: &MoveGroup,
    poses: &[Pose],
    seed: &[f64],
    failed: impl Fn(&Pose, &tabula_motion::MoveError),
) -> Option<Vec<f64>> {
    let mut first = None;
    let mut from = seed.to_vec();
    for p in poses {
        match group.valid_ik(p, &from) {
            Ok(sols) => {
                from = sols[0].clone();
                first.get_or_insert(sols[0].clone());
            }
            Err(e) => {
                failed(p, &e);
                return None;
            }
        }
    }
    first
}
