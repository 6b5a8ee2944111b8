//! Grasp candidates for one arm — the skills' side and top grasps kept where the arm's
//! IK reaches the grasp, a pre-grasp and a placement — and the lines into and out of
//! grasps and placements.

use super::scene::Scene;
use super::{PickPlaceError, PickPlaceParams, PickPlaceRequest};
use crate::skills::{GraspCandidate, GraspKind, GraspPlanner, Hand};
use tabula_geom::{Pose, Quat, Vec2, Vec3};
use tabula_motion::{CollisionWorld, MoveGroup};

/// What every candidate of a run is planned for.
pub(super) struct Job<'a> {
    pub(super) scene: &'a Scene,
    pub(super) request: &'a PickPlaceRequest,
    pub(super) params: &'a PickPlaceParams,
    /// The arm's joint values at the start.
    pub(super) start: &'a [f64],
    /// The arm's world with both supports taken away, where a placement's arm pose is
    /// checked: the held object lands on the place support, but the arm must not (the
    /// Panda's forearm meets the table under a tilted side placement).
    pub(super) landing: &'a CollisionWorld,
}

impl Job<'_> {
    /// `world` without the slabs under the object and the target.
    pub(super) fn landing_world(world: &CollisionWorld) -> Result<CollisionWorld, PickPlaceError> {
        let mut landing = world.clone();
        for support in ["pick_support", "place_support"] {
            landing
                .remove_object(support)
                .map_err(|e| PickPlaceError::Driver(e.to_string()))?;
        }
        Ok(landing)
    }
}

/// A way to put the held object down: `(rank, world_from_object, world_from_tool, level
/// approach)`, the rank how far it turns from facing the target.
pub(super) type Placement = (u64, Pose, Pose, Vec3);

/// Grasps worth planning, best first: the planner's side grasps (the approach level or
/// tilted down a little, around the direction from the arm to the object), then top
/// grasps; each only if the arm's IK reaches both the grasp and a pre-grasp and the
/// object can be put down holding it so. IK is cheap next to planning (microseconds
/// for an analytic solver), so many are tried and only the best few planned.
pub(super) fn grasp_candidates(
    group: &MoveGroup,
    job: &Job<'_>,
    hand: &Hand,
) -> Result<Vec<GraspCandidate>, PickPlaceError> {
    let base = group
        .world
        .world_from_chain_base()
        .map_err(|e| PickPlaceError::Driver(e.to_string()))?;
    let planner = job.params.grasp_planner();
    let target = job.scene.object.grasp_target_from(Some(base.translation));
    // Cheapest check first: each is an IK solution, a miss a numeric solver's budget.
    let reachable = |grasp: &GraspCandidate| {
        let r = grasp.world_from_tool().rotation;
        let some_pre = || {
            pregrasp_offsets(grasp, job.params).into_iter().any(|back| {
                let pre = Pose::from_parts(grasp.world_from_tool().translation + back, r);
                // Collision-free: a pre-grasp in the scene (the Panda's wrist on the
                // table under a low side grasp) ends every plan at its first step.
                group.valid_ik(&pre, job.start).is_ok()
            })
        };
        group.valid_ik(&grasp.world_from_tool(), job.start).is_ok()
            && some_pre()
            && can_place(group, job, grasp, job.start)
    };
    let found: Vec<GraspCandidate> = planner
        .candidates(&target, hand, Vec3::Z)
        .into_iter()
        .filter(|g| reachable(g))
        .take(job.params.max_planned_grasps)
        .collect();
    let narrowest = planner.narrowest(&target);
    if found.is_empty() && narrowest + 2.0 * job.params.min_finger_clearance > hand.open_width {
        return Err(PickPlaceError::TooWide(narrowest));
    }
    Ok(found)
}

/// Poses where the held object can be put down (and the tool poses that do it), each
/// with an IK solution whose arm is clear of the scene ([`Job::landing`]), nearest the
/// direction facing the target first: `(rank, world_from_object, world_from_tool, level
/// approach)`.
pub(super) fn placements(
    group: &MoveGroup,
    job: &Job<'_>,
    grasp: &GraspCandidate,
    seed: &[f64],
) -> Vec<Placement> {
    ranked_placements(group, job, grasp, seed).collect()
}

/// Whether the object held by `grasp` can be put down at all: the first of
/// [`placements`] only (each costs an IK solution; a miss, a numeric solver's whole
/// budget).
fn can_place(group: &MoveGroup, job: &Job<'_>, grasp: &GraspCandidate, seed: &[f64]) -> bool {
    ranked_placements(group, job, grasp, seed).next().is_some()
}

/// [`placements`] lazily, best rank first (turns of 0, +1, −1, +2, … yaw steps).
fn ranked_placements<'a>(
    group: &'a MoveGroup,
    job: &'a Job<'_>,
    grasp: &'a GraspCandidate,
    seed: &'a [f64],
) -> impl Iterator<Item = Placement> + 'a {
    let (object, support) = (&job.scene.object, &job.scene.support);
    let (request, params) = (job.request, job.params);
    let base = group.world.world_from_chain_base().ok();
    let world_from_object = object.world_from_object();
    let tool_from_object = grasp.world_from_tool().inverse() * world_from_object;
    let toward = request.place.truncate() - base.map_or(Vec2::ZERO, |b| b.translation.truncate());
    let facing = toward.y.atan2(toward.x);
    let current_yaw = grasp.approach.y.atan2(grasp.approach.x);
    let steps = (params.yaw_range / params.yaw_step.max(1e-3)).ceil() as i64;
    let ranks = std::iter::once(0).chain((1..=steps).flat_map(|m| [m, -m]));
    // No chain base, no placements.
    ranks
        .take_while(move |_| base.is_some())
        .filter_map(move |k| {
            // Side grasps turn the held object about the vertical with the approach; top
            // grasps may turn it freely.
            let turn = match grasp.kind {
                GraspKind::Side => {
                    tabula_geom::wrap_angle(facing + k as f64 * params.yaw_step - current_yaw)
                }
                GraspKind::Top => k as f64 * params.yaw_step,
            };
            let spin = Quat::from_rotation_z(turn);
            let placed_object = Pose::from_parts(
                Vec3::new(
                    request.place.x,
                    request.place.y,
                    support.z + params.release_height,
                ),
                spin * world_from_object.rotation,
            );
            let place_tool = placed_object * tool_from_object.inverse();
            let lands = group
                .ik(&place_tool, seed)
                .is_ok_and(|sols| sols.iter().any(|q| job.landing.is_valid(q)));
            let a = spin * grasp.approach;
            lands.then(|| {
                (
                    k.unsigned_abs(),
                    placed_object,
                    place_tool,
                    Vec3::new(a.x, a.y, 0.0).normalize_or(Vec3::X),
                )
            })
        })
}

/// Straight lines out of a pose: `back` along the level approach and up by each rise
/// offset; a top grasp backs straight up. Arms like Golem-III's reach few level lines,
/// so lines that also rise are tried.
pub(super) fn lines_out(
    kind: GraspKind,
    level: Vec3,
    backs: &[f64],
    params: &PickPlaceParams,
) -> Vec<Vec3> {
    let mut v = Vec::new();
    for &b in backs {
        for &r in &params.rise_offsets {
            v.push(match kind {
                GraspKind::Side => -level * b + Vec3::Z * r,
                GraspKind::Top => Vec3::Z * (b + r),
            });
        }
    }
    v
}

/// Where a pre-grasp may be relative to the grasp: straight back along the tool's own
/// approach axis (SPEC §3.2's 10 cm, or less of it — MoveIt Task Constructor's approach
/// takes a minimum and a desired distance), then the level and rising alternatives.
pub(super) fn pregrasp_offsets(grasp: &GraspCandidate, params: &PickPlaceParams) -> Vec<Vec3> {
    let level = Vec3::new(grasp.approach.x, grasp.approach.y, 0.0).normalize_or(Vec3::X);
    [1.0, 0.7, 0.5, 0.3]
        .iter()
        .map(|f| -grasp.approach * params.pregrasp_distance * f)
        .chain(lines_out(
            grasp.kind,
            level,
            &[params.pregrasp_distance, 0.0],
            params,
        ))
        .filter(|o| o.length() >= 0.025)
        .collect()
}
