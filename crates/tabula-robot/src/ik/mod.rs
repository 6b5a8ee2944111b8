//! Inverse kinematics: one [`IkSolver`] trait, a numeric solver for any chain and the
//! closed-form Golem-III solver of seed 001.

mod auto;
pub mod bench;
mod closed_form;
mod golem3;
mod numeric;
mod parallel3;
mod screws;
mod shoulder7;
mod spherical6;
mod subproblems;

pub use auto::AutoIk;
pub use golem3::{ArmSide, Golem3Ik, Golem3Params};
pub use numeric::{NumericIk, NumericIkParams};
pub use parallel3::ThreeParallelIk;
pub use shoulder7::SphericalShoulderIk;
pub use spherical6::SphericalWristIk;

use crate::{Chain, RobotError};
use tabula_geom::{Pose, Vec3, pose_is_finite, rotation_angle_between, wrap_angle};

/// What part of the target pose must be met.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum IkMode {
    /// Position and orientation.
    Full,
    /// Position of the tip only; orientation is free.
    PositionOnly,
    /// Position, and the tip axis `tool_axis` (tip frame) along the target's same axis;
    /// rotation about that axis is free (e.g. a symmetric gripper's roll).
    PositionAxis { tool_axis: Vec3 },
}

/// One solution: joint values in chain order and its error against the target.
#[derive(Debug, Clone, PartialEq)]
pub struct IkSolution {
    pub joints: Vec<f64>,
    /// Distance from the reached tip position to the target (m).
    pub position_error: f64,
    /// Rotation angle between reached and target orientation (rad); for
    /// [`IkMode::PositionAxis`] the angle between the constrained axes, 0 for position only.
    pub rotation_error: f64,
}

/// Why a solve gave no solution.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum IkError {
    /// The target is valid but no configuration within limits reaches it (in the budget).
    #[error("no solution: the target is out of reach within the joint limits")]
    NoSolution,
    /// A numeric solver found none within its budget; unlike [`IkError::NoSolution`]
    /// this proves nothing (another start, more time, might find one).
    #[error(
        "no solution found in {attempts} attempts (a numeric solver cannot prove that none exists)"
    )]
    NotFound { attempts: usize },
    #[error("target pose is not finite (NaN or infinite component)")]
    NonFiniteTarget,
    #[error("seed has {got} joint values, the chain has {expected}")]
    WrongSeedLength { expected: usize, got: usize },
    #[error("seed joint values must be finite")]
    NonFiniteSeed,
    #[error("this solver does not support {0}")]
    UnsupportedMode(&'static str),
    #[error("{0}")]
    Robot(String),
}

impl From<RobotError> for IkError {
    fn from(e: RobotError) -> Self {
        IkError::Robot(e.to_string())
    }
}

/// Inverse kinematics of one chain.
pub trait IkSolver {
    /// The chain this solver inverts (joint order of every solution).
    fn chain(&self) -> &Chain;

    /// Solutions for `base_from_tip` target in `mode`, sorted by distance to `seed`
    /// (nearest first). Never empty: no solution is [`IkError::NoSolution`].
    fn solve(
        &self,
        base_from_tip: &Pose,
        mode: IkMode,
        seed: &[f64],
    ) -> Result<Vec<IkSolution>, IkError>;
}

/// Checks target and seed: the shared front door of every solver.
pub(crate) fn validate_request(
    chain: &Chain,
    target: &Pose,
    mode: IkMode,
    seed: &[f64],
) -> Result<(), IkError> {
    if !pose_is_finite(target) || target.rotation.length() < 1e-6 {
        return Err(IkError::NonFiniteTarget);
    }
    if let IkMode::PositionAxis { tool_axis } = mode
        && (!tool_axis.is_finite() || tool_axis.length() < 1e-9)
    {
        return Err(IkError::NonFiniteTarget);
    }
    if seed.len() != chain.dof() {
        return Err(IkError::WrongSeedLength {
            expected: chain.dof(),
            got: seed.len(),
        });
    }
    if seed.iter().any(|v| !v.is_finite()) {
        return Err(IkError::NonFiniteSeed);
    }
    Ok(())
}

/// Error of `reached` against `target` as (position m, rotation rad) for `mode`.
pub fn pose_error(reached: &Pose, target: &Pose, mode: IkMode) -> (f64, f64) {
    let p = (reached.translation - target.translation).length();
    let r = match mode {
        IkMode::Full => rotation_angle_between(reached.rotation, target.rotation.normalize()),
        IkMode::PositionOnly => 0.0,
        IkMode::PositionAxis { tool_axis } => {
            let a = tool_axis.normalize();
            let cur = reached.rotation * a;
            let want = target.rotation.normalize() * a;
            cur.cross(want).length().atan2(cur.dot(want))
        }
    };
    (p, r)
}

/// Joint-space distance used to rank solutions: Euclidean, with revolute
/// differences wrapped when the joint is continuous.
#[inline]
pub fn joint_distance(chain: &Chain, a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .enumerate()
        .map(|(i, (x, y))| {
            let d = x - y;
            let d = if chain.lower[i].is_finite() || chain.var_prismatic[i] {
                d
            } else {
                wrap_angle(d)
            };
            d * d
        })
        .sum::<f64>()
        .sqrt()
}

/// Sorts by distance to `seed`, nearest first, and drops near-duplicates.
pub(crate) fn sort_and_dedup(
    chain: &Chain,
    mut sols: Vec<IkSolution>,
    seed: &[f64],
    min_separation: f64,
) -> Vec<IkSolution> {
    sols.sort_by(|a, b| {
        joint_distance(chain, &a.joints, seed).total_cmp(&joint_distance(chain, &b.joints, seed))
    });
    let mut out: Vec<IkSolution> = Vec::with_capacity(sols.len());
    for s in sols {
        // Closer than `min_separation` two solutions are one configuration (a stretched
        // elbow gives θ = ±4e-8 for the same target; near a singularity a numeric solver
        // lands anywhere along a shallow valley).
        if !out
            .iter()
            .any(|o| joint_distance(chain, &o.joints, &s.joints) < min_separation)
        {
            out.push(s);
        }
    }
    out
}
