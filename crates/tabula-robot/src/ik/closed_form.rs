//! What every closed-form solver does: read the chain's axes at zero, then with its
//! candidate angles map them to chain variables within the limits (the whole turn
//! nearest the seed), keep those that forward kinematics confirms, drop duplicates, and
//! rank them nearest the seed first.

use super::{IkError, IkMode, IkSolution, joint_distance, pose_error, validate_request};
use crate::Chain;
use tabula_geom::{Pose, Vec3};

/// The chain in product-of-exponentials form: each joint's axis and a point on it at
/// zero (base frame), and the tip at zero — `None` unless the chain has `N` revolute
/// joints, one variable each in order, with multiplier ±1 (what the closed forms
/// assume).
pub(crate) fn axes_at_zero<const N: usize>(chain: &Chain) -> Option<([Vec3; N], [Vec3; N], Pose)> {
    if chain.elements.len() != N || chain.dof() != N {
        return None;
    }
    let mut frame = Pose::IDENTITY;
    let (mut h, mut o) = ([Vec3::ZERO; N], [Vec3::ZERO; N]);
    for (i, e) in chain.elements.iter().enumerate() {
        if e.prismatic || e.var != i || (e.multiplier.abs() - 1.0).abs() > 1e-12 {
            return None;
        }
        frame *= e.pre;
        h[i] = (frame.rotation * e.axis).normalize();
        o[i] = frame.translation;
    }
    Some((h, o, frame * chain.tip_offset))
}

/// A returned solution reaches the target within this (m, rad).
pub(crate) const ACCEPT: f64 = 1e-6;

/// Chain variables from joint angles (θ, before each element's multiplier and offset):
/// the 2π-equivalent nearest the seed within the limits, `None` if a joint has none.
pub(crate) fn within_limits<const N: usize>(
    chain: &Chain,
    theta: &[f64; N],
    seed: &[f64],
) -> Option<[f64; N]> {
    let tau = std::f64::consts::TAU;
    let mut out = [0.0; N];
    for i in 0..N {
        let e = &chain.elements[i];
        let q = (theta[i] - e.offset) / e.multiplier;
        let (lo, hi) = (chain.lower[i] - 1e-9, chain.upper[i] + 1e-9);
        // The whole turn of q nearest the seed, else the nearest one inside.
        let near = q + ((seed[i] - q) / tau).round() * tau;
        let best = [near, near - tau, near + tau]
            .into_iter()
            .filter(|v| (lo..=hi).contains(v))
            .min_by(|a, b| (a - seed[i]).abs().total_cmp(&(b - seed[i]).abs()))
            .or_else(|| {
                (-4..=4)
                    .map(|k| q + f64::from(k) * tau)
                    .find(|v| (lo..=hi).contains(v))
            })?;
        out[i] = best.clamp(chain.lower[i], chain.upper[i]);
    }
    Some(out)
}

/// Adds the candidate to `found` when it is within the limits, reaches `target` (by the
/// chain's own FK) and is not already there.
fn keep_verified<const N: usize>(
    chain: &Chain,
    theta: &[f64; N],
    target: &Pose,
    seed: &[f64],
    found: &mut Vec<IkSolution>,
) {
    let Some(joints) = within_limits(chain, theta, seed) else {
        return;
    };
    let reached = chain.fk_unchecked(&joints);
    let (position_error, rotation_error) = pose_error(&reached, target, IkMode::Full);
    if position_error > ACCEPT || rotation_error > ACCEPT {
        return;
    }
    if found
        .iter()
        .any(|s| joint_distance(chain, &s.joints, &joints) < 1e-6)
    {
        return;
    }
    found.push(IkSolution {
        joints: joints.to_vec(),
        position_error,
        rotation_error,
    });
}

/// Nearest the seed first.
fn rank(chain: &Chain, found: &mut [IkSolution], seed: &[f64]) {
    found.sort_by(|a, b| {
        joint_distance(chain, &a.joints, seed).total_cmp(&joint_distance(chain, &b.joints, seed))
    });
}

/// The front door of a closed form: a valid request for a full pose.
pub(crate) fn check_full_pose(
    chain: &Chain,
    target: &Pose,
    mode: IkMode,
    seed: &[f64],
) -> Result<(), IkError> {
    validate_request(chain, target, mode, seed)?;
    if mode != IkMode::Full {
        return Err(IkError::UnsupportedMode(
            "orientation-free goals (closed form is for full poses)",
        ));
    }
    Ok(())
}

/// The candidates that are solutions ([`keep_verified`]), nearest the seed first.
pub(crate) fn verified<const N: usize>(
    chain: &Chain,
    candidates: &[[f64; N]],
    target: &Pose,
    seed: &[f64],
) -> Vec<IkSolution> {
    let mut found = Vec::with_capacity(candidates.len());
    for theta in candidates {
        keep_verified(chain, theta, target, seed, &mut found);
    }
    rank(chain, &mut found, seed);
    found
}
