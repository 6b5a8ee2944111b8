//! Planning one grasp candidate stage by stage (MoveIt Task Constructor's pick/place):
//! approach, lift, retreat, then for each placement the line down onto the target, the
//! hand backing away, the transfer and the way home — each stage in the collision world
//! it needs (the object touchable, held, or placed; the supports there or not).

use super::grasps::{Job, Placement, lines_out, placements, pregrasp_offsets};
use super::{PickPlaceError, motion_error};
use crate::skills::GraspCandidate;
use tabula_geom::parry::shape::SharedShape;
use tabula_geom::{Pose, Vec3};
use tabula_motion::{CollisionWorld, MoveGroup, Plan};

/// Everything planned for one candidate, in execution order.
pub(super) struct Sequence {
    pub(super) to_pregrasp: Plan,
    pub(super) approach: Plan,
    pub(super) lift: Plan,
    pub(super) retreat: Plan,
    pub(super) transfer: Plan,
    pub(super) place: Plan,
    pub(super) release_retreat: Plan,
    pub(super) home: Plan,
    pub(super) planned_object: Pose,
}

/// The stages after the placement is chosen.
struct Placed {
    transfer: Plan,
    place: Plan,
    release_retreat: Plan,
}

fn shifted(p: &Pose, d: Vec3) -> Pose {
    Pose::from_parts(p.translation + d, p.rotation)
}

fn world_error(e: tabula_motion::WorldError) -> PickPlaceError {
    PickPlaceError::Driver(e.to_string())
}

/// One candidate's stages and the worlds they plan in.
struct Stages<'a> {
    job: &'a Job<'a>,
    grasp: &'a GraspCandidate,
    /// The group's whole world.
    full: &'a CollisionWorld,
    shape: SharedShape,
    object_from_shape: Pose,
    /// The object's core, shrunk by the padding and a few mm: while the hand is at the
    /// object (approaching, backing away) it may touch it, but not sweep through it.
    core: SharedShape,
    core_offset: Pose,
    tool_from_object: Pose,
    /// The level direction of the approach.
    level: Vec3,
    touching_target: CollisionWorld,
    with_target: CollisionWorld,
    without_pick_support: CollisionWorld,
    without_both: CollisionWorld,
}

/// Plans every stage of one grasp candidate; `full` is the group's whole world (the
/// stages plan in variants of it and leave the group's world changed); `stage` names
/// the stage being planned (the failing one on error).
pub(super) fn plan_sequence(
    group: &mut MoveGroup,
    full: &CollisionWorld,
    job: &Job<'_>,
    grasp: &GraspCandidate,
    stage: &mut &'static str,
) -> Result<Sequence, PickPlaceError> {
    let s = Stages::new(group, full, job, grasp)?;
    // 1–2. A pre-grasp whose straight approach works, then a path to it.
    let (to_pregrasp, approach) = s.approach(group, stage)?;
    // 3. Lift the object off its support.
    *stage = "lift";
    let lift = s.lift(group, approach.end())?;
    // 4. Retreat out of the shelf (side) or further up (top).
    *stage = "retreat";
    let retreat = s.retreat(group, &lift)?;
    // 5. Placements reachable by IK, nearest the direction facing the target first.
    *stage = "placement IK";
    let mut last = PickPlaceError::Unreachable;
    let mut planned = 0;
    for placement in placements(group, job, grasp, retreat.end()) {
        if planned >= job.params.max_planned_grasps {
            break;
        }
        let (counted, found) = s.place(group, retreat.end(), &placement, stage, &mut last)?;
        if counted {
            planned += 1;
        }
        let Some(placed) = found else {
            continue;
        };
        // 8. Back to where the arm started.
        *stage = "return";
        group.world = s.after(&placement)?;
        let home = match group.plan_to_joints(placed.release_retreat.end(), &[job.start.to_vec()]) {
            Ok(h) => h,
            Err(e) => {
                last = motion_error(e);
                continue;
            }
        };
        return Ok(Sequence {
            to_pregrasp,
            approach,
            lift,
            retreat,
            transfer: placed.transfer,
            place: placed.place,
            release_retreat: placed.release_retreat,
            home,
            planned_object: placement.1,
        });
    }
    Err(last)
}

impl<'a> Stages<'a> {
    fn new(
        group: &MoveGroup,
        full: &'a CollisionWorld,
        job: &'a Job<'a>,
        grasp: &'a GraspCandidate,
    ) -> Result<Self, PickPlaceError> {
        let object = &job.scene.object;
        let world_from_object = object.world_from_object();
        let (shape, object_from_shape) = object.collision_shape();
        let core_margin = group.world.params.padding + 0.004;
        let (core, core_offset) = object.shrunk_shape(core_margin);
        let mut touching_target = full.clone();
        touching_target
            .add_object("target core", core.clone(), world_from_object * core_offset)
            .map_err(world_error)?;
        let mut with_target = full.clone();
        with_target
            .add_object(
                "target",
                shape.clone(),
                world_from_object * object_from_shape,
            )
            .map_err(world_error)?;
        let mut without_pick_support = full.clone();
        without_pick_support
            .remove_object("pick_support")
            .map_err(world_error)?;
        let mut without_both = without_pick_support.clone();
        without_both
            .remove_object("place_support")
            .map_err(world_error)?;
        Ok(Self {
            job,
            grasp,
            full,
            shape,
            object_from_shape,
            core,
            core_offset,
            tool_from_object: grasp.world_from_tool().inverse() * world_from_object,
            level: Vec3::new(grasp.approach.x, grasp.approach.y, 0.0).normalize_or(Vec3::X),
            touching_target,
            with_target,
            without_pick_support,
            without_both,
        })
    }

    /// Straight lines out of (or into) a pose: `back` along the level direction `level`
    /// and up by each rise offset.
    fn lines(&self, level: Vec3, backs: &[f64]) -> Vec<Vec3> {
        lines_out(self.grasp.kind, level, backs, self.job.params)
    }

    /// The group in `world`, holding the object.
    fn holding(&self, group: &mut MoveGroup, world: &CollisionWorld) -> Result<(), PickPlaceError> {
        group.world = world.clone();
        group
            .attach(
                "target",
                self.shape.clone(),
                self.tool_from_object * self.object_from_shape,
            )
            .map_err(motion_error)
    }

    /// A pre-grasp whose straight approach works (the hand may touch the object on the
    /// way in), then a path to it that avoids the object.
    fn approach(
        &self,
        group: &mut MoveGroup,
        stage: &mut &'static str,
    ) -> Result<(Plan, Plan), PickPlaceError> {
        let start = self.job.start;
        let grasp_pose = self.grasp.world_from_tool();
        *stage = "approach";
        let mut last = PickPlaceError::Unreachable;
        for offset in pregrasp_offsets(self.grasp, self.job.params) {
            let pregrasp = shifted(&grasp_pose, offset);
            group.world = self.with_target.clone();
            let Ok(goals) = group.valid_ik(&pregrasp, start) else {
                continue;
            };
            for q_pre in goals.into_iter().take(3) {
                group.world = self.touching_target.clone();
                let approach = match group.cartesian(&q_pre, &grasp_pose) {
                    Ok(a) => a,
                    Err(e) => {
                        last = motion_error(e);
                        continue;
                    }
                };
                group.world = self.with_target.clone();
                *stage = "move to pre-grasp";
                match group.plan_to_joints(start, &[q_pre]) {
                    Ok(to) => return Ok((to, approach)),
                    Err(e) => last = motion_error(e),
                }
                *stage = "approach";
            }
        }
        Err(last)
    }

    /// Lifts the object off its support (backing out a little as it rises is fine).
    fn lift(&self, group: &mut MoveGroup, from: &[f64]) -> Result<Plan, PickPlaceError> {
        self.holding(group, &self.without_pick_support)?;
        let mut lifted_plan = Err(PickPlaceError::Unreachable);
        for back in [0.0, 0.02, 0.04] {
            let up = Vec3::Z * self.job.params.lift - self.level * back;
            let lifted = shifted(&self.grasp.world_from_tool(), up);
            lifted_plan = group.cartesian(from, &lifted).map_err(motion_error);
            if lifted_plan.is_ok() {
                break;
            }
        }
        lifted_plan
    }

    /// Retreats out of the shelf (side) or further up (top); the transfer's planner
    /// takes it from there — or from where the lift ended when no line out works.
    fn retreat(&self, group: &mut MoveGroup, lift: &Plan) -> Result<Plan, PickPlaceError> {
        let lifted_pose = group.tip_pose(lift.end()).map_err(motion_error)?;
        // With the object lifted clear of its support, the support is an obstacle
        // again.
        self.holding(group, self.full)?;
        let r = self.job.params.retreat;
        for offset in self.lines(self.level, &[r, r / 2.0, 0.0]) {
            if offset.length() < 0.03 {
                continue;
            }
            if let Ok(p) = group.cartesian(lift.end(), &shifted(&lifted_pose, offset)) {
                return Ok(p);
            }
        }
        group
            .timed(lift.end(), vec![lift.end().to_vec()], 0.0)
            .map_err(motion_error)
    }

    /// The world after the object is placed: the pick support gone, the object where it
    /// was put.
    fn after(&self, placement: &Placement) -> Result<CollisionWorld, PickPlaceError> {
        let mut after = self.without_pick_support.clone();
        after
            .add_object(
                "placed",
                self.shape.clone(),
                placement.1 * self.object_from_shape,
            )
            .map_err(world_error)?;
        Ok(after)
    }

    /// A pre-place whose straight line down onto the target works, the hand backing
    /// away from the placed object, then the transfer to it (last: it is the costly
    /// plan). Returns whether any pre-place had IK (the placement counts as planned)
    /// and the stages when all worked; `last` keeps the latest failure.
    fn place(
        &self,
        group: &mut MoveGroup,
        from: &[f64],
        placement: &Placement,
        stage: &mut &'static str,
        last: &mut PickPlaceError,
    ) -> Result<(bool, Option<Placed>), PickPlaceError> {
        let (_, _, place_tool, place_level) = *placement;
        let params = self.job.params;
        *stage = "place";
        let after = self.after(placement)?;
        let mut counted = false;
        for offset in self.lines(place_level, &[params.place_approach, 0.0]) {
            if offset.z < 0.0 || offset.length() < 0.05 {
                continue;
            }
            let pre_place = shifted(&place_tool, offset);
            self.holding(group, &self.without_pick_support)?;
            let Ok(goals) = group.valid_ik(&pre_place, from) else {
                continue;
            };
            counted = true;
            for q_pp in goals.into_iter().take(2) {
                // The line down onto the target, holding the object.
                self.holding(group, &self.without_both)?;
                let place = match group.cartesian(&q_pp, &place_tool) {
                    Ok(p) => p,
                    Err(e) => {
                        *last = motion_error(e);
                        continue;
                    }
                };
                *stage = "retreat from object";
                let Some(release_retreat) = self.back_away(group, placement, &place, &after)?
                else {
                    *last = PickPlaceError::NoPath(
                        "the hand cannot back away from the placed object".into(),
                    );
                    continue;
                };
                *stage = "transfer";
                self.holding(group, self.full)?;
                match group.plan_to_joints(from, &[q_pp]) {
                    Ok(transfer) => {
                        let placed = Placed {
                            transfer,
                            place,
                            release_retreat,
                        };
                        return Ok((counted, Some(placed)));
                    }
                    Err(e) => *last = motion_error(e),
                }
                *stage = "place";
            }
        }
        Ok((counted, None))
    }

    /// Released, the hand backs away far enough that the placed object is an obstacle
    /// again: straight back, back and up, or (side placements) straight up past the
    /// object's top with the fingers open around it.
    fn back_away(
        &self,
        group: &mut MoveGroup,
        placement: &Placement,
        place: &Plan,
        after: &CollisionWorld,
    ) -> Result<Option<Plan>, PickPlaceError> {
        let (_, placed_object, place_tool, place_level) = *placement;
        let r = self.job.params.place_retreat;
        group.world = self.without_both.clone();
        group
            .add_object(
                "placed core",
                self.core.clone(),
                placed_object * self.core_offset,
            )
            .map_err(motion_error)?;
        Ok(self
            .lines(place_level, &[r, r / 2.0, 0.0])
            .into_iter()
            .filter(|o| o.z >= 0.0 && o.length() >= 0.03)
            .find_map(|o| {
                group
                    .cartesian(place.end(), &shifted(&place_tool, o))
                    .ok()
                    .filter(|p| after.is_valid(p.end()))
            }))
    }
}
