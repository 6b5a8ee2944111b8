//! The predicates of SPEC §3.3 computed from geometry: what stands on what, which
//! objects are in the way of which grasp and which push — with the poses of SPEC §3.2
//! those actions would take.

use super::push::Push;
use super::{ClearParams, SeenObject, Table, on_pairs};
use crate::skills::pick::grasp_blockers;
use crate::skills::{GraspCandidate, GraspPlanner, Hand};

/// Everything the predicates computed for one frame.
#[derive(Clone)]
pub(super) struct Geometry {
    pub(super) on: Vec<(usize, usize)>,
    pub(super) block_grasp: Vec<(usize, usize)>,
    pub(super) block_push: [Vec<(usize, usize)>; 4],
    /// The least-blocked grasp of each object; `None` when it fits the gripper no way.
    pub(super) grasps: Vec<Option<GraspCandidate>>,
    pub(super) pushes: Vec<[Push; 4]>,
}

/// The table as one frame shows it, with the hand that acts on it: what every
/// predicate is computed over.
#[derive(Clone, Copy)]
pub(super) struct TableView<'a> {
    pub(super) objects: &'a [SeenObject],
    pub(super) table: &'a Table,
    pub(super) hand: &'a Hand,
    pub(super) params: &'a ClearParams,
}

pub(super) use crate::skills::pick::descent_poses;

impl<'a> TableView<'a> {
    /// The same table and hand with other objects (where they would be after a push).
    pub(super) fn with_objects(&self, objects: &'a [SeenObject]) -> Self {
        Self { objects, ..*self }
    }

    /// Grasps of `o` that fit the hand, best first (see [`ClearParams::grasp_planner`]).
    pub(super) fn grasps_of(&self, o: &SeenObject) -> Vec<GraspCandidate> {
        self.params
            .grasp_planner()
            .candidates(&o.grasp_target(), self.hand, self.table.up)
    }

    /// The objects the open gripper meets at `grasp` or on its way down from the
    /// pre-grasp, except those `skip` names.
    pub(super) fn grasp_blockers(
        &self,
        grasp: &GraspCandidate,
        skip: &dyn Fn(usize) -> bool,
    ) -> Vec<usize> {
        let p = self.params;
        let reach = (self.table.up, p.pregrasp, p.clearance);
        grasp_blockers(self.objects, grasp, self.hand, reach, skip)
    }

    /// Which objects could be grasped now: nothing on them, and a grasp nothing is in
    /// the way of.
    pub(super) fn graspable(&self, on: &[(usize, usize)]) -> Vec<bool> {
        (0..self.objects.len())
            .map(|b| self.graspable_one(on, b))
            .collect()
    }

    /// Whether object `b` could be grasped now (see [`Self::graspable`]).
    pub(super) fn graspable_one(&self, on: &[(usize, usize)], b: usize) -> bool {
        let skip = |a: usize| a == b || on.contains(&(a, b)) || on.contains(&(b, a));
        !on.iter().any(|&(_, under)| under == b)
            && self
                .grasps_of(&self.objects[b])
                .iter()
                .any(|g| self.grasp_blockers(g, &skip).is_empty())
    }

    /// Each object's grasp with the fewest objects in its way, and `block_grasp` pairs
    /// for those in the way (objects on it block it through `on`, not the gripper).
    fn grasp_predicates(
        &self,
        on: &[(usize, usize)],
    ) -> (Vec<Option<GraspCandidate>>, Vec<(usize, usize)>) {
        let mut grasps = Vec::with_capacity(self.objects.len());
        let mut block_grasp = Vec::new();
        for (b, o) in self.objects.iter().enumerate() {
            let skip = |a: usize| a == b || on.contains(&(a, b)) || on.contains(&(b, a));
            let best = self
                .grasps_of(o)
                .into_iter()
                .map(|g| {
                    let by = self.grasp_blockers(&g, &skip);
                    (g, by)
                })
                .min_by_key(|(_, by)| by.len());
            match best {
                Some((g, by)) => {
                    block_grasp.extend(by.into_iter().map(|a| (a, b)));
                    grasps.push(Some(g));
                }
                None => grasps.push(None),
            }
        }
        (grasps, block_grasp)
    }

    /// The predicates of SPEC §3.3 and the poses of SPEC §3.2 for every object; with
    /// `with_chain`, pushes are chain pushes (each may shove what is in front of it
    /// along), the fallback when the seed's actions cannot clear the table (packed
    /// objects).
    pub(super) fn predicates(&self, with_chain: bool) -> Geometry {
        let on = on_pairs(self.objects, self.table.z, &|o| {
            !self.grasps_of(o).is_empty()
        });
        let (grasps, block_grasp) = self.grasp_predicates(&on);
        // Which objects are graspable now (only needed for chain pushes).
        let mut graspable_now: Option<Vec<bool>> = None;
        let mut block_push: [Vec<(usize, usize)>; 4] = Default::default();
        let mut pushes = Vec::with_capacity(self.objects.len());
        for b in 0..self.objects.len() {
            // The grasps `b` is in the way of: a push of it must clear them too.
            let frees: Vec<&GraspCandidate> = block_grasp
                .iter()
                .filter(|&&(a, _)| a == b)
                .filter_map(|&(_, x)| grasps[x].as_ref())
                .collect();
            let mut dirs: [Push; 4] = std::array::from_fn(|k| self.seed_push(&on, (b, k), &frees));
            for (k, p) in dirs.iter_mut().enumerate() {
                let blockers = if with_chain {
                    let (chained, blockers) = self.chain_push(&on, b, p, &mut graspable_now);
                    *p = chained;
                    blockers
                } else {
                    self.seed_push_blockers(b, k, p)
                };
                block_push[k].extend(blockers.into_iter().map(|a| (a, b)));
            }
            pushes.push(dirs);
        }
        Geometry {
            on,
            block_grasp,
            block_push,
            grasps,
            pushes,
        }
    }
}
