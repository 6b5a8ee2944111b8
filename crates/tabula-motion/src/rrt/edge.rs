//! Edge checks: fixed spacing, and certification by conservative advancement.

use super::linf;
use crate::world::{CollisionWorld, Keep};

/// True when the straight segment a→b is valid: configurations are checked at most
/// `resolution` rad apart (max over joints) and close enough that no point of the robot
/// moves more than the world's `max_step_displacement` between two — so with that much
/// padding, nothing in between can touch. Checked in bisection order so a collision in
/// the middle is found early.
pub fn segment_valid(world: &CollisionWorld, a: &[f64], b: &[f64], resolution: f64) -> bool {
    segment_valid_spaced(world, a, b, resolution, world.params.max_step_displacement)
}

/// Whether the padding covers half the world's step (`max_step_displacement`), so that
/// fixed spacing certifies an edge: every configuration between two samples is within
/// half a step of one. Certified edges then keep each link's padding at their samples
/// and all but half a step of it between ([`Keep::LinkPaddings`]) — what fixed spacing
/// guarantees, measured by conservative advancement in far fewer samples. Under that
/// (an exact world: MotionBenchMaker's grasps sit millimetres from the object) they
/// keep the whole padding everywhere. The tasks' 8 mm padding with a 10 mm step is of
/// the first kind.
pub fn spacing_certifies(world: &CollisionWorld) -> bool {
    world.max_padding() >= 0.5 * world.params.max_step_displacement
}

/// Whether the straight segment a→b is valid *everywhere*, not only at its samples:
/// conservative advancement ([`segment_valid_advancing`]) after a coarse look
/// ([`refused_early`]) that turns most blocked segments away for a fraction of the cost.
pub fn segment_certified(world: &CollisionWorld, a: &[f64], b: &[f64], resolution: f64) -> bool {
    !refused_early(world, a, b, resolution) && segment_valid_advancing(world, a, b, resolution)
}

/// Whether a configuration on a→b is invalid among a few: four times the world's step
/// and the angular resolution apart, in bisection order. A segment that fails here
/// cannot be certified (certified, it would be valid at every configuration), so
/// conservative advancement would give the same answer — after distance queries at
/// every configuration it bisects to, where these are boolean checks. Only worth it
/// in an exact world (not [`spacing_certifies`]), where blocked segments are many and
/// advancement keeping the whole padding is slow: a free segment pays the look on top
/// (in the own WAM benchmark's padded world, a median plan of 0.095 ms became 0.25).
pub(super) fn refused_early(world: &CollisionWorld, a: &[f64], b: &[f64], resolution: f64) -> bool {
    const COARSE: f64 = 4.0;
    if spacing_certifies(world) {
        return false;
    }
    let spacing = COARSE * world.params.max_step_displacement;
    !segment_valid_spaced(world, a, b, COARSE * resolution, spacing)
}

/// Most configurations one certification may measure: an edge that needs more is
/// treated as blocked.
const MAX_ADVANCES: usize = 20_000;

/// Conservative advancement along a→b, in bisection order: the margin `m` measured at
/// a configuration (in the segment's length, [`CollisionWorld::margin`]: each pair's
/// distance beyond what it keeps over how fast that pair can close) keeps the stretch
/// within `m` of it clear by that much, so a stretch whose two ends' margins together
/// cover its length is certified whole; any other is split at its middle. Long
/// stretches of open space are certified in a few queries, a contact in the middle is
/// met early, and the whole segment keeps what [`spacing_certifies`] says, not only its
/// samples. Near an obstacle the stretches shrink; one with less than 10 µm of motion
/// in its margins is checked at fixed spacing where the padding certifies that, and is
/// blocked otherwise.
pub fn segment_valid_advancing(
    world: &CollisionWorld,
    a: &[f64],
    b: &[f64],
    resolution: f64,
) -> bool {
    let spaced_fallback = spacing_certifies(world);
    // Where the padding certifies fixed spacing, samples keep each link's padding and
    // the stretches between them all but half a step of it, as fixed spacing's do.
    let keep = if spaced_fallback {
        Keep::LinkPaddings {
            spend: 0.5 * world.params.max_step_displacement,
        }
    } else {
        Keep::Padding(world.max_padding())
    };
    let rates = world.sweep_rates(a, b);
    let fastest = rates.fastest();
    // Margins beyond 10 cm of motion buy little but cost distance queries.
    let cap = 0.1;
    let mut q = a.to_vec();
    let mut margin_at = |t: f64| -> Option<f64> {
        for k in 0..a.len() {
            q[k] = a[k] + (b[k] - a[k]) * t;
        }
        let m = world.margin(&q, &rates, keep, cap).ok()?;
        (m > 0.0).then_some(m)
    };
    let (Some(ma), Some(mb)) = (margin_at(0.0), margin_at(1.0)) else {
        return false;
    };
    let mut pending = std::collections::VecDeque::from([(0.0, 1.0, ma, mb)]);
    let mut measured = 2;
    while let Some((t0, t1, m0, m1)) = pending.pop_front() {
        if t1 - t0 <= m0 + m1 {
            continue;
        }
        if (m0 + m1) * fastest < 1e-5 || measured >= MAX_ADVANCES {
            // Hugging an obstacle: where the padding certifies fixed spacing, check the
            // stretch that way; otherwise it is blocked.
            if !spaced_fallback {
                return false;
            }
            let at =
                |t: f64| -> Vec<f64> { a.iter().zip(b).map(|(x, y)| x + (y - x) * t).collect() };
            if !segment_valid(world, &at(t0), &at(t1), resolution) {
                return false;
            }
            continue;
        }
        let tm = 0.5 * (t0 + t1);
        let Some(mm) = margin_at(tm) else {
            return false;
        };
        measured += 1;
        pending.push_back((t0, tm, m0, mm));
        pending.push_back((tm, t1, mm, m1));
    }
    true
}

/// 1..=n in van der Corput order (by their bits reversed: n/2 first, then the
/// quarters, …), generated without sorting.
fn van_der_corput(n: usize) -> impl Iterator<Item = usize> {
    let n = n.min(u32::MAX as usize >> 1) as u32;
    let bits = 32 - n.leading_zeros();
    (0..1u64 << bits)
        .map(move |j| {
            (j as u32)
                .reverse_bits()
                .checked_shr(32 - bits)
                .unwrap_or(0) as usize
        })
        .filter(move |&i| (1..=n as usize).contains(&i))
}

pub(super) fn segment_valid_spaced(
    world: &CollisionWorld,
    a: &[f64],
    b: &[f64],
    resolution: f64,
    displacement: f64,
) -> bool {
    let by_angle = linf(a, b) / resolution.max(1e-9);
    let by_motion = world.displacement_bound(a, b) / displacement.max(1e-4);
    let steps = by_angle.max(by_motion).ceil() as usize;
    if steps <= 1 {
        return world.is_valid(b);
    }
    let mut q = vec![0.0; a.len()];
    for i in van_der_corput(steps) {
        let t = i as f64 / steps as f64;
        for k in 0..a.len() {
            q[k] = a[k] + (b[k] - a[k]) * t;
        }
        if !world.is_valid(&q) {
            return false;
        }
    }
    true
}

#[cfg(test)]
mod tests {
    #[test]
    fn van_der_corput_is_the_bit_reversed_sort() {
        for n in 0..300usize {
            let mut sorted: Vec<usize> = (1..=n).collect();
            sorted.sort_by_key(|&i| (i as u32).reverse_bits());
            assert_eq!(
                super::van_der_corput(n).collect::<Vec<_>>(),
                sorted,
                "n = {n}"
            );
        }
    }
}
