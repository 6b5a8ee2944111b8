//! Random shortcutting of a found path.

use super::edge::{segment_certified, segment_valid_spaced};
use super::{Path, PlannerParams};
use crate::world::CollisionWorld;
use rand::RngExt;
use rand_chacha::ChaCha8Rng;

/// Random shortcutting: replace the stretch between two random waypoints by the
/// straight segment whenever that segment is valid.
/// Random shortcutting of a certified path: every shortcut taken is certified too.
pub fn shortcut(world: &CollisionWorld, path: &mut Path, p: &PlannerParams, rng: &mut ChaCha8Rng) {
    shortcut_with(path, p, rng, |a, b| {
        segment_certified(world, a, b, p.resolution)
    });
}

/// Shortcutting with edges checked at `spacing` (the trees' coarse checks).
pub(super) fn shortcut_spaced(
    world: &CollisionWorld,
    path: &mut Path,
    p: &PlannerParams,
    rng: &mut ChaCha8Rng,
    spacing: f64,
) {
    shortcut_with(path, p, rng, |a, b| {
        segment_valid_spaced(world, a, b, p.resolution, spacing)
    });
}

/// Replaces the stretch between two random waypoints by the straight segment whenever
/// `segment_ok` accepts it, `shortcut_attempts` times. A pair of waypoints refused once
/// is refused again until the path changes, so it is not checked again (a path of three
/// waypoints has one pair: it was drawn fifty times); once every pair is refused the
/// path is final. The answer is the one checking every draw gives.
fn shortcut_with(
    path: &mut Path,
    p: &PlannerParams,
    rng: &mut ChaCha8Rng,
    segment_ok: impl Fn(&[f64], &[f64]) -> bool,
) {
    let mut refused: Vec<(usize, usize)> = Vec::new();
    for _ in 0..p.shortcut_attempts {
        let n = path.waypoints.len();
        if n < 3 || refused.len() >= (n - 1) * (n - 2) / 2 {
            return;
        }
        let i = rng.random_range(0..n - 2);
        let j = rng.random_range(i + 2..n);
        if refused.contains(&(i, j)) {
            continue;
        }
        if segment_ok(&path.waypoints[i], &path.waypoints[j]) {
            path.waypoints.drain(i + 1..j);
            refused.clear();
        } else {
            refused.push((i, j));
        }
    }
}
