//! Goals given as poses (IK solutions as goal configurations) and Cartesian straight-line
//! approach and retreat paths.

use crate::rrt::{PlanError, PlannerParams, segment_certified};
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

/// Where a straight line of the tip stopped short: the fraction done and why.
#[derive(Debug, Clone, PartialEq)]
pub struct LineStop {
    pub fraction: f64,
    pub why: String,
}

/// The one straight-line follower: the tip from its pose at `start` to `goal`
/// (translation linear, rotation by slerp), one IK solution (`ik(world_from_tip, seed)`)
/// every `step` metres or 0.05 rad, seeded by the previous one. Stops where IK fails, a
/// joint would jump more than `max_jump` rad (a branch flip), or a segment collides.
/// Returns the waypoints reached and, if it stopped, where and why.
pub fn follow_line(
    world: &CollisionWorld,
    start: &[f64],
    goal: &Pose,
    step: f64,
    max_jump: f64,
    resolution: f64,
    ik: impl Fn(&Pose, &[f64]) -> Option<Vec<f64>>,
) -> (Vec<Vec<f64>>, Option<LineStop>) {
    let from = match world.tip_pose(start) {
        Ok(p) => p,
        Err(e) => {
            let why = e.to_string();
            return (vec![start.to_vec()], Some(LineStop { fraction: 0.0, why }));
        }
    };
    let length = (goal.translation - from.translation).length();
    let angle = tabula_geom::rotation_angle_between(from.rotation, goal.rotation);
    let n = ((length / step.max(1e-4)).max(angle / 0.05))
        .ceil()
        .clamp(1.0, 10_000.0) as usize;
    let mut waypoints = vec![start.to_vec()];
    for i in 1..=n {
        let s = i as f64 / n as f64;
        let pose = Pose::from_parts(
            from.translation.lerp(goal.translation, s),
            from.rotation.slerp(goal.rotation, s),
        );
        let prev = waypoints.last().cloned().unwrap_or_default();
        let stop = |why: String| {
            Some(LineStop {
                fraction: (i - 1) as f64 / n as f64,
                why,
            })
        };
        let Some(q) = ik(&pose, &prev) else {
            return (waypoints, stop("no IK solution on the line".into()));
        };
        let jump = q
            .iter()
            .zip(&prev)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        if jump > max_jump {
            return (waypoints, stop(format!("a joint would jump {jump:.2} rad")));
        }
        if !segment_certified(world, &prev, &q, resolution) {
            let why = match world.first_collision(&q) {
                Ok(Some((a, b))) => format!("{a} touches {b}"),
                _ => "the segment collides".into(),
            };
            return (waypoints, stop(why));
        }
        waypoints.push(q);
    }
    (waypoints, None)
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
    world
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
    let ik = NumericIk::new(
        world.chain.clone(),
        NumericIkParams {
            timeout_s: None,
            max_attempts: 1,
            ..NumericIkParams::default()
        },
    );
    let (waypoints, stop) = follow_line(
        world,
        start,
        goal,
        step,
        max_jump,
        p.resolution,
        |pose, seed| {
            ik.solve(&(base * *pose), IkMode::Full, seed)
                .ok()
                .map(|sols| sols[0].joints.clone())
        },
    );
    Ok((waypoints, stop.map_or(1.0, |s| s.fraction)))
}
