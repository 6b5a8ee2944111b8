//! What every closed-form solver does: read the chain's axes at zero, then map the
//! candidates to chain variables within the limits (the whole turn nearest the seed),
//! keep those that forward kinematics confirms, drop duplicates, and rank them nearest
//! the seed first.

use super::screws::{Candidate, MAX_CANDIDATES, Screws};
use super::{IkError, IkMode, IkSolution, joint_distance, validate_request};
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

/// `v` rounded to the nearest integer, half away from zero, for |v| < 2⁶³ (the std's
/// `round` is a call into compiler-builtins without SSE4.1, 200 instructions).
#[inline]
fn round(v: f64) -> f64 {
    (if v >= 0.0 { v + 0.5 } else { v - 0.5 }) as i64 as f64
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
        // The multiplier is ±1 (see `axes_at_zero`): its own inverse.
        let q = (theta[i] - e.offset) * e.multiplier;
        let (lo, hi) = (chain.lower[i] - 1e-9, chain.upper[i] + 1e-9);
        // The whole turn of q nearest the seed, else the nearest one inside.
        let near = q + round((seed[i] - q) * (1.0 / tau)) * tau;
        let best = if (lo..=hi).contains(&near) {
            near
        } else {
            // The seed is outside the limits or `near` just past one: the nearer turn
            // inside, else any.
            let (below, above) = (near - tau, near + tau);
            match ((lo..=hi).contains(&below), (lo..=hi).contains(&above)) {
                (true, true) if (above - seed[i]).abs() < (below - seed[i]).abs() => above,
                (true, _) => below,
                (false, true) => above,
                (false, false) => (-4..=4)
                    .map(|k| q + f64::from(k) * tau)
                    .find(|v| (lo..=hi).contains(v))?,
            }
        };
        out[i] = best.clamp(chain.lower[i], chain.upper[i]);
    }
    Some(out)
}

/// The candidates that reach `target` (by [`Screws::check`]) with every joint within
/// its limits, as chain variables (the turn nearest the seed), duplicates dropped,
/// nearest the seed first. At most [`MAX_CANDIDATES`] are looked at.
pub(crate) fn verified<const N: usize>(
    screws: &Screws<N>,
    chain: &Chain,
    candidates: &[Candidate<N>],
    target: &Pose,
    seed: &[f64],
) -> Vec<IkSolution> {
    let mut check = screws.check(target);
    let mut found: Vec<IkSolution> = Vec::with_capacity(candidates.len());
    // Distances to the seed of `found`, kept sorted with it (insertion: ≤ 8 entries).
    let mut distances = [0.0; MAX_CANDIDATES];
    for candidate in candidates.iter().take(MAX_CANDIDATES) {
        // The limits first: they are cheaper, and reject most on arms with narrow ones.
        let Some(joints) = within_limits(chain, &candidate.angles, seed) else {
            continue;
        };
        let (position_error, rotation_error) = check.errors(&candidate.turns);
        if position_error > ACCEPT || rotation_error > ACCEPT {
            continue;
        }
        // Both mapped to the turn nearest the seed: equal answers have equal values.
        let same = |s: &IkSolution| {
            let d2: f64 = s
                .joints
                .iter()
                .zip(&joints)
                .map(|(a, b)| (a - b) * (a - b))
                .sum();
            d2 < 1e-12
        };
        if found.iter().any(same) {
            continue;
        }
        let distance = joint_distance(chain, &joints, seed);
        let at = distances[..found.len()].partition_point(|d| *d <= distance);
        distances.copy_within(at..found.len(), at + 1);
        distances[at] = distance;
        let solution = IkSolution {
            joints: joints.to_vec(),
            position_error,
            rotation_error,
        };
        found.insert(at, solution);
    }
    found
}

/// A complete closed form's answer: the verified candidates, or no solution (none
/// exists: the candidates were every branch).
pub(crate) fn answer<const N: usize>(
    screws: &Screws<N>,
    chain: &Chain,
    candidates: &[Candidate<N>],
    target: &Pose,
    seed: &[f64],
) -> Result<Vec<IkSolution>, IkError> {
    let found = verified(screws, chain, candidates, target, seed);
    if found.is_empty() {
        return Err(IkError::NoSolution);
    }
    Ok(found)
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
