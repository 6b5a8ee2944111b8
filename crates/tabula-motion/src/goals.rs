//! Goals given as poses (IK solutions as goal configurations) and Cartesian straight-line
//! approach and retreat paths.

use crate::rrt::{PlanError, PlannerParams, segment_valid};
use crate::world::CollisionWorld;
use tabula_geom::Pose;
use tabula_robot::ik::{IkMode, IkSolver, NumericIk, NumericIkParams};

/// Up to `count` distinct collision-free IK solutions for `world_from_tip`, nearest to
/// `seed` first.
pub fn pose_goals(
    world: &CollisionWorld,
    world_from_tip: &Pose,
    seed: &[f64],
    count: usize,
    rng_seed: u64,
) -> Result<Vec<Vec<f64>>, PlanError> {
    let base = world
        .world_from_chain_base()
        .map_err(|e| PlanError::World(e.to_string()))?;
    let target = base.inverse() * *world_from_tip;
    let ik = NumericIk::new(
        world.chain.clone(),
        NumericIkParams {
            timeout_s: None,
            max_attempts: 200,
            max_solutions: count.max(1) * 3,
            random_seed: rng_seed,
            ..NumericIkParams::default()
        },
    );
    let sols = ik
        .solve(&target, IkMode::Full, seed)
        .map_err(|e| PlanError::GoalInvalid(e.to_string()))?;
    let valid: Vec<Vec<f64>> = sols
        .into_iter()
        .map(|s| s.joints)
        .filter(|q| world.is_valid(q))
        .take(count.max(1))
        .collect();
    if valid.is_empty() {
        return Err(PlanError::NoValidGoal);
    }
    Ok(valid)
}

/// A Cartesian straight-line path of the tip from its pose at `start` to `goal`
/// (translation linear, rotation by slerp), IK at every `step` metres seeded by the
/// previous solution. Stops where IK fails, a joint would jump more than `max_jump` rad
/// between steps (a branch flip), or the segment collides. Returns the waypoints and the
/// fraction of the line achieved (MoveIt's `computeCartesianPath` convention).
pub fn cartesian_path(
    world: &CollisionWorld,
    start: &[f64],
    goal: &Pose,
    step: f64,
    max_jump: f64,
    p: &PlannerParams,
) -> Result<(Vec<Vec<f64>>, f64), PlanError> {
    let from = world
        .tip_pose(start)
        .map_err(|e| PlanError::StartInvalid(e.to_string()))?;
    if !world.is_valid(start) {
        return Err(PlanError::StartInvalid(
            "start configuration collides or is out of limits".into(),
        ));
    }
    let base = world
        .world_from_chain_base()
        .map_err(|e| PlanError::World(e.to_string()))?
        .inverse();
    let length = (goal.translation - from.translation).length();
    let angle = tabula_geom::rotation_angle_between(from.rotation, goal.rotation);
    let n = ((length / step.max(1e-4)).max(angle / 0.05))
        .ceil()
        .max(1.0) as usize;
    let ik = NumericIk::new(
        world.chain.clone(),
        NumericIkParams {
            timeout_s: None,
            max_attempts: 1,
            ..NumericIkParams::default()
        },
    );
    let mut waypoints = vec![start.to_vec()];
    for i in 1..=n {
        let s = i as f64 / n as f64;
        let pose = Pose::from_parts(
            from.translation.lerp(goal.translation, s),
            from.rotation.slerp(goal.rotation, s),
        );
        let prev = waypoints.last().cloned().unwrap_or_default();
        let Ok(sols) = ik.solve(&(base * pose), IkMode::Full, &prev) else {
            break;
        };
        let q = sols[0].joints.clone();
        let jump = q
            .iter()
            .zip(&prev)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        if jump > max_jump || !segment_valid(world, &prev, &q, p.resolution) {
            break;
        }
        waypoints.push(q);
    }
    let fraction = (waypoints.len() - 1) as f64 / n as f64;
    Ok((waypoints, fraction))
}
