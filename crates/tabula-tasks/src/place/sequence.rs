//! Planning and executing a placement (Algs 11–12): the approach, the line down, the
//! release and the back-away.

use super::run::{FreeSpot, Run, Spot, Target};
use super::{PlaceError, PlaceParams};
use tabula_geom::parry::shape::SharedShape;
use tabula_geom::{Pose, Vec3};
use tabula_motion::{CollisionWorld, MoveGroup, Plan};
use tabula_robot::driver::JointState;

impl Run<'_> {
    /// Algs 11–12: spots in reach × roll angles, IK, then the motions: to above the
    /// spot (object attached), down to release height, and the retreat.
    pub(super) fn plan_placement(
        &mut self,
        group: &mut MoveGroup,
        state: &JointState,
        t: Target<'_>,
        spots: &[FreeSpot],
        shoulder: Vec3,
    ) -> Result<(Sequence, Spot, usize), PlaceError> {
        let (p, hull, poses, surface) = (self.params, t.hull, t.poses, t.surface);
        let start = group.arm_values(state);
        let n = surface.plane.normal;
        let offset = surface.centroid.dot(n);
        // Spots in reach, better poses first, then nearer the shoulder, then roomier.
        let mut cands: Vec<(usize, Spot)> = spots
            .iter()
            .filter(|s| s.1.distance(shoulder) <= p.reach)
            .map(|&(k, position, yaw, clearance)| {
                let resting = &poses[k];
                let rotation = resting.pose.resting_rotation(yaw);
                let c = Vec3::from_array(resting.pose.contact_centroid);
                // On the plane under `position`, raised by the release height.
                let on_plane = position - n * (position.dot(n) - offset);
                let world_from_tool = Pose::from_parts(
                    on_plane + Vec3::Z * resting.release_height - rotation * c,
                    rotation,
                );
                let score = k as f64 * 10.0 + position.distance(shoulder) - 0.5 * clearance;
                (
                    k,
                    Spot {
                        world_from_tool,
                        score,
                    },
                )
            })
            .collect();
        if cands.is_empty() {
            return Err(PlaceError::Unreachable);
        }
        cands.sort_by(|a, b| a.1.score.total_cmp(&b.1.score));
        let full = group.world.clone();
        let mut last = PlaceError::Unreachable;
        let mut planned = 0usize;
        for (k, spot) in cands {
            if planned >= p.max_planned {
                break;
            }
            // IK first: cheap, and most spots fail here.
            if group.ik(&spot.world_from_tool, &start).is_err() {
                continue;
            }
            planned += 1;
            self.report.candidates_tried += 1;
            group.world = full.clone();
            match plan_sequence(group, &full, hull, &spot, &start, p) {
                Ok(seq) => return Ok((seq, spot, k)),
                Err(e) => {
                    let t = spot.world_from_tool.translation;
                    self.report.rejected.push(format!(
                        "pose {k} at ({:.2}, {:.2}, {:.2}): {e}",
                        t.x, t.y, t.z
                    ));
                    if !matches!(e, PlaceError::Unreachable) {
                        last = e;
                    }
                }
            }
        }
        group.world = full;
        Err(last)
    }
}

/// Every motion of one placement.
pub(super) struct Sequence {
    pub(super) to_above: Plan,
    pub(super) lower: Plan,
    pub(super) retreat: Plan,
    pub(super) aside: Option<Plan>,
}

/// Plans one spot: above it (the approach distance up, desired then minimum), a path
/// there holding the object's hull, the straight line down, the straight line back up
/// after release (the object left on the surface as an obstacle), and the arm aside.
pub(super) fn plan_sequence(
    group: &mut MoveGroup,
    full: &CollisionWorld,
    hull: &SharedShape,
    spot: &Spot,
    start: &[f64],
    p: &PlaceParams,
) -> Result<Sequence, PlaceError> {
    let shifted = |d: f64| {
        Pose::from_parts(
            spot.world_from_tool.translation + Vec3::Z * d,
            spot.world_from_tool.rotation,
        )
    };
    {
        group.world = full.clone();
        group.attach("object", hull.clone(), Pose::IDENTITY)
    }?;
    let holding = group.world.clone();
    let _ = group.world.remove_object("surface");
    let goal_ok = group.valid_ik(&spot.world_from_tool, start);
    let mut last = match goal_ok {
        Ok(_) => PlaceError::Unreachable,
        Err(e) => return Err(e.into()),
    };
    // The ways down from the first approach distance that has any (desired first, then
    // shorter; every IK branch), then one RRT-Connect to all of their tops at once: a
    // failed search is the costly part, and one that cannot reach any top need not be
    // run again per top. A shorter approach is only a fallback (MoveIt's place stage
    // takes the same desired-then-minimum range), so it is not tried once one works.
    let mut ways: Vec<(Vec<f64>, Plan)> = Vec::new();
    for d in [
        p.approach_desired,
        (p.approach_desired + p.approach_min) / 2.0,
        p.approach_min,
    ] {
        if !ways.is_empty() {
            break;
        }
        let above = shifted(d);
        group.world = holding.clone();
        let goals = match group.valid_ik(&above, start) {
            Ok(g) => g,
            Err(e) => {
                last = e.into();
                continue;
            }
        };
        for q_above in goals.into_iter().take(3) {
            // Down to millimetres above the surface: closer than the padding, so only
            // the sunk slab stays for the line down and the line back out (the stable
            // pose keeps the gripper clear of the top, Alg. 6).
            group.world = holding.clone();
            let _ = group.world.remove_object("surface");
            match group.cartesian(&q_above, &spot.world_from_tool) {
                Ok(lower) => ways.push((q_above, lower)),
                Err(e) => last = e.into(),
            }
        }
    }
    if ways.is_empty() {
        return Err(last);
    }
    group.world = holding.clone();
    let tops: Vec<Vec<f64>> = ways.iter().map(|(q, _)| q.clone()).collect();
    let to_above = group.plan_to_joints(start, &tops)?;
    let reached = to_above.end().to_vec();
    let nearest = ways
        .iter()
        .enumerate()
        .min_by(|a, b| {
            let da: f64 = a.1.0.iter().zip(&reached).map(|(x, y)| (x - y).abs()).sum();
            let db: f64 = b.1.0.iter().zip(&reached).map(|(x, y)| (x - y).abs()).sum();
            da.total_cmp(&db)
        })
        .map(|(i, _)| i)
        .unwrap_or(0);
    let (_, lower) = ways.swap_remove(nearest);
    let retreat = retreat(group, full, spot, &lower, p)?;
    // After release the object stays behind, an obstacle to the arm going aside.
    let mut released = full.clone();
    let object_pose = released
        .tip_pose(lower.end())
        .map_err(|e| PlaceError::Driver(e.to_string()))?;
    let _ = released.add_object("placed object", grown(hull, 0.02), object_pose);
    group.world = released;
    let aside = group.plan_to_joints(retreat.end(), &[start.to_vec()]).ok();
    Ok(Sequence {
        to_above,
        lower,
        retreat,
        aside,
    })
}

/// `hull` grown by `by` away from its centre: a placed object may have settled a
/// little differently from the scan, and a brush topples a tall one.
fn grown(hull: &SharedShape, by: f64) -> SharedShape {
    hull.as_convex_polyhedron()
        .and_then(|c| {
            let pts = c.points();
            let centre = pts.iter().copied().sum::<Vec3>() / pts.len().max(1) as f64;
            let out: Vec<Vec3> = pts
                .iter()
                .map(|q| {
                    let d = *q - centre;
                    centre + d + d.normalize_or_zero() * by
                })
                .collect();
            SharedShape::convex_hull(&out)
        })
        .unwrap_or_else(|| hull.clone())
}

/// Out of the grasp after release the way the fingers went in (back along the tool's
/// own approach axis, seed 000's retreat), so an opened finger under an overhang cannot
/// drag the object along; straight up when that line is blocked.
fn retreat(
    group: &mut MoveGroup,
    full: &CollisionWorld,
    spot: &Spot,
    lower: &Plan,
    p: &PlaceParams,
) -> Result<Plan, PlaceError> {
    group.world = full.clone();
    let _ = group.world.remove_object("surface");
    let back =
        -(spot.world_from_tool.rotation * group.gripper.as_ref().map_or(Vec3::X, |g| g.approach()));
    for dir in [back, Vec3::Z] {
        for r in [
            p.retreat_desired,
            (p.retreat_desired + p.retreat_min) / 2.0,
            p.retreat_min,
        ] {
            let goal = Pose::from_parts(
                spot.world_from_tool.translation + dir * r,
                spot.world_from_tool.rotation,
            );
            if let Ok(pl) = group.cartesian(lower.end(), &goal) {
                return Ok(pl);
            }
        }
    }
    Err(PlaceError::NoPath(
        "no straight retreat from the released object".into(),
    ))
}
