//! What other hands already hold: it stays held, moves with them, and is carried in the
//! planning scene — not left in it as an obstacle.

use super::PickPlaceParams;
use super::look::Views;
use tabula_geom::parry::shape::SharedShape;
use tabula_geom::{Pose, Vec3};
use tabula_robot::robots::NamedRobot;

/// Something a gripper holds, as the planning scene carries it.
pub(super) struct HeldElsewhere {
    pub(super) gripper: tabula_robot::description::Gripper,
    /// In the tool frame.
    pub(super) shape: SharedShape,
    /// Points the camera saw of it.
    pub(super) points: usize,
}

/// What the grippers in `full` hold, as the camera saw it: the points between the
/// fingers and everything joined to them (neighbours within the cluster gap) up to
/// `held_reach` from the tool point. Those points leave `views`: they
/// move with the hand, they are not scene. Unseen, the held thing is a ball a little
/// wider than the finger gap.
pub(super) fn held_in_grippers(
    robot: &NamedRobot,
    full: &[tabula_robot::description::Gripper],
    state: &tabula_robot::driver::JointState,
    world_from_root: Pose,
    views: &mut Views,
    params: &PickPlaceParams,
) -> Vec<HeldElsewhere> {
    let (points, origins) = (&mut views.points, &mut views.origins);
    let values = state.model_values(&robot.model);
    let Ok(fk) = robot.model.forward_kinematics(&values) else {
        return Vec::new();
    };
    let gap = params.observe.cluster_gap;
    let mut held = Vec::new();
    for g in full {
        let (Some(j), Some(tool)) = (
            robot.model.joint(&g.finger_joint),
            robot.model.link(&g.tool_link).ok(),
        ) else {
            continue;
        };
        let width = g.width_at(&robot.model, values[j]);
        let world_from_tool = world_from_root * fk[tool];
        let tool_from_world = world_from_tool.inverse();
        let (approach, closing) = (g.approach(), g.closing());
        let third = approach.cross(closing);
        let near: Vec<usize> = (0..points.len())
            .filter(|&i| points[i].distance(world_from_tool.translation) <= params.held_reach)
            .collect();
        // Flood the occupied cells from those between the fingertips.
        let cell_of = |q: Vec3| tabula_geom::voxel_key(q, gap);
        let cells: rustc_hash::FxHashSet<[i64; 3]> =
            near.iter().map(|&i| cell_of(points[i])).collect();
        let mut reached: rustc_hash::FxHashSet<[i64; 3]> = near
            .iter()
            .map(|&i| points[i])
            .filter(|q| {
                let t = tool_from_world * *q;
                t.dot(closing).abs() <= width / 2.0 + gap
                    && t.dot(approach).abs() <= 0.03
                    && t.dot(third).abs() <= 0.03
            })
            .map(cell_of)
            .collect();
        let mut frontier: Vec<[i64; 3]> = reached.iter().copied().collect();
        while let Some(c) = frontier.pop() {
            for dx in -1..=1 {
                for dy in -1..=1 {
                    for dz in -1..=1 {
                        let n = [c[0] + dx, c[1] + dy, c[2] + dz];
                        if cells.contains(&n) && reached.insert(n) {
                            frontier.push(n);
                        }
                    }
                }
            }
        }
        let mine: rustc_hash::FxHashSet<usize> = near
            .into_iter()
            .filter(|&i| reached.contains(&cell_of(points[i])))
            .collect();
        let in_tool: Vec<Vec3> = mine.iter().map(|&i| tool_from_world * points[i]).collect();
        let hull = (in_tool.len() >= 10)
            .then(|| SharedShape::convex_hull(&in_tool))
            .flatten();
        let shape = hull.unwrap_or_else(|| SharedShape::ball(width / 2.0 + params.held_margin));
        let (kept, kept_origins): (Vec<Vec3>, Vec<Vec3>) = points
            .iter()
            .zip(origins.iter())
            .enumerate()
            .filter(|(i, _)| !mine.contains(i))
            .map(|(_, (p, o))| (*p, *o))
            .unzip();
        *points = kept;
        *origins = kept_origins;
        held.push(HeldElsewhere {
            gripper: g.clone(),
            shape,
            points: in_tool.len(),
        });
    }
    held
}
