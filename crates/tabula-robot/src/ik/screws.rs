//! Forward kinematics for checking closed-form candidates, in product-of-exponentials
//! form — `T(θ) = E1(θ1)…EN(θN) M`, each `Ei` a turn about axis `h_i` through `o_i` —
//! taking the candidates' cosines and sines as they are (no trigonometric call), and
//! sharing between consecutive candidates what they share: the target is carried back
//! through the first joints (`E_m⁻¹…E1⁻¹ T`), the tip's frame forward through the rest
//! (`E_{m+1}…EN M`), and the two compared, so that a candidate on the branch of the
//! first joints or of the last that the one before it was on reuses that side. The check is exact: every turn is an
//! isometry, so the distances are those of the base frame.

use super::subproblems::Turn;
use tabula_geom::{Mat3, Pose, Vec3};

/// Candidates per solve of a closed form (2 × 2 × 2 branches).
pub(crate) const MAX_CANDIDATES: usize = 8;
/// Joints of the chains the closed forms solve.
const MAX_JOINTS: usize = 7;

/// One candidate answer of a closed form: each joint's angle θ (before multiplier and
/// offset) and its cosine and sine.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Candidate<const N: usize> {
    pub turns: [Turn; N],
    pub angles: [f64; N],
}

impl<const N: usize> Default for Candidate<N> {
    fn default() -> Self {
        Self {
            turns: [Turn::default(); N],
            angles: [0.0; N],
        }
    }
}

/// A pose as its origin and its three axes (base frame): what the turns move.
#[derive(Debug, Clone, Copy, Default)]
struct Frame {
    origin: Vec3,
    axes: [Vec3; 3],
}

impl Frame {
    fn new(rotation: &Mat3, origin: Vec3) -> Self {
        Self {
            origin,
            axes: [rotation.x_axis, rotation.y_axis, rotation.z_axis],
        }
    }

    /// Position distance (m) and rotation angle (rad) between two frames; the angle from
    /// the Frobenius distance `‖A − B‖ = 2√2 sin(θ/2)`, exact for small angles where the
    /// trace's `acos` loses them.
    #[inline]
    fn distance(&self, other: &Self) -> (f64, f64) {
        let d: f64 = (0..3)
            .map(|i| (self.axes[i] - other.axes[i]).length_squared())
            .sum();
        let angle = 2.0
            * (d.sqrt() / (2.0 * std::f64::consts::SQRT_2))
                .min(1.0)
                .asin();
        ((self.origin - other.origin).length(), angle)
    }
}

/// The chain's joints in product-of-exponentials form and where the check meets.
#[derive(Debug, Clone)]
pub(crate) struct Screws<const N: usize> {
    pub h: [Vec3; N],
    /// A point on each axis (any point of the line: the turn is the same).
    pub o: [Vec3; N],
    pub tip_rotation: Mat3,
    pub tip_translation: Vec3,
    /// Joints `0..meet` are undone from the target's side, the rest carry the tip.
    meet: usize,
}

impl<const N: usize> Screws<N> {
    /// `meet`: how many of the first joints to undo from the target — those the
    /// solver's outer loop branches on (the rest of the candidates' joints should vary
    /// innermost-first from the tip's side backwards).
    pub(crate) fn new(h: [Vec3; N], o: [Vec3; N], tip_zero: &Pose, meet: usize) -> Self {
        const { assert!(N <= MAX_JOINTS) };
        Self {
            h,
            o,
            tip_rotation: Mat3::from_quat(tip_zero.rotation),
            tip_translation: tip_zero.translation,
            meet: meet.min(N),
        }
    }

    /// `frame` turned by joint `i` at `turn`: x ↦ R (x − o) + o.
    #[inline]
    fn turn(&self, i: usize, turn: Turn, frame: &Frame) -> Frame {
        let (h, o) = (self.h[i], self.o[i]);
        Frame {
            origin: turn.rotate(h, frame.origin - o) + o,
            axes: [
                turn.rotate(h, frame.axes[0]),
                turn.rotate(h, frame.axes[1]),
                turn.rotate(h, frame.axes[2]),
            ],
        }
    }

    /// A check of candidates against `target`, one after another.
    pub(crate) fn check(&self, target: &Pose) -> Check<'_, N> {
        let mut left = [Frame::default(); MAX_JOINTS + 1];
        let mut right = [Frame::default(); MAX_JOINTS + 1];
        left[0] = Frame::new(
            &Mat3::from_quat(target.rotation.normalize()),
            target.translation,
        );
        right[N] = Frame::new(&self.tip_rotation, self.tip_translation);
        Check {
            screws: self,
            left,
            right,
            previous: None,
        }
    }
}

/// Checks candidates against one target, keeping the frames the last one computed:
/// `left[k] = E_k⁻¹…E1⁻¹ T` and `right[k] = E_{k+1}…EN M` (0-based joints).
pub(crate) struct Check<'a, const N: usize> {
    screws: &'a Screws<N>,
    left: [Frame; MAX_JOINTS + 1],
    right: [Frame; MAX_JOINTS + 1],
    previous: Option<[Turn; N]>,
}

impl<const N: usize> Check<'_, N> {
    /// Position (m) and rotation (rad) error of the tip at `turns` against the target.
    pub(crate) fn errors(&mut self, turns: &[Turn; N]) -> (f64, f64) {
        let (s, m) = (self.screws, self.screws.meet);
        // Levels still valid from the previous candidate: its equal first and last joints.
        let (left_valid, right_valid) = match &self.previous {
            None => (0, N),
            Some(p) => (
                (0..m).take_while(|&i| p[i] == turns[i]).count(),
                N - (m..N).rev().take_while(|&i| p[i] == turns[i]).count(),
            ),
        };
        for (k, turn) in turns.iter().enumerate().take(m).skip(left_valid) {
            self.left[k + 1] = s.turn(k, turn.inverse(), &self.left[k]);
        }
        for (k, turn) in turns.iter().enumerate().take(right_valid).skip(m).rev() {
            self.right[k] = s.turn(k, *turn, &self.right[k + 1]);
        }
        self.previous = Some(*turns);
        self.left[m].distance(&self.right[m])
    }
}

#[cfg(test)]
mod tests {
    use super::super::closed_form::axes_at_zero;
    use super::*;
    use crate::{Chain, robots};
    use rand::{RngExt, SeedableRng};

    /// Every meeting point gives the chain's own FK: a candidate at random angles checked
    /// against the chain's FK there has no error; moved 1e-5 m or turned 1e-5 rad, it
    /// has that error. Consecutive candidates share joints, as a solver's do.
    #[test]
    fn the_check_is_the_chains_forward_kinematics() {
        let r = robots::load("wam").expect("robot");
        let chain = Chain::new(&r.model, &r.default_base, &r.default_tip).expect("chain");
        let (h, o, tip) = axes_at_zero::<7>(&chain).expect("seven revolute joints");
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(4);
        for meet in 0..=7 {
            let screws = Screws::new(h, o, &tip, meet);
            let mut candidates = [Candidate::<7>::default(); MAX_CANDIDATES];
            for n in 0..MAX_CANDIDATES {
                for j in 0..7 {
                    // Odd candidates share joints 0, 1, 5 and 6 with the one before.
                    candidates[n].angles[j] = if n % 2 == 1 && !(2..5).contains(&j) {
                        candidates[n - 1].angles[j]
                    } else {
                        rng.random_range(-3.0..3.0)
                    };
                }
                candidates[n].turns = candidates[n].angles.map(Turn::new);
            }
            for n in 0..MAX_CANDIDATES {
                let q: Vec<f64> = (0..7)
                    .map(|j| {
                        (candidates[n].angles[j] - chain.elements[j].offset)
                            / chain.elements[j].multiplier
                    })
                    .collect();
                let target = chain.fk(&q).expect("fk");
                let errors = |target: &Pose| {
                    // The candidates before this one first, as a solver's run.
                    let mut check = screws.check(target);
                    (0..=n)
                        .map(|i| check.errors(&candidates[i].turns))
                        .last()
                        .expect("one")
                };
                let (p, r) = errors(&target);
                assert!(
                    p < 1e-12 && r < 1e-12,
                    "meet {meet}, candidate {n}: {p} m {r} rad"
                );
                let moved = Pose::from_parts(target.translation + Vec3::X * 1e-5, target.rotation);
                let (p, r) = errors(&moved);
                assert!((p - 1e-5).abs() < 1e-12 && r < 1e-12, "{p} {r}");
                let turned = Pose::from_parts(
                    target.translation,
                    target.rotation * tabula_geom::Quat::from_rotation_z(1e-5),
                );
                let (p, r) = errors(&turned);
                assert!(p < 1e-12 && (r - 1e-5).abs() < 1e-11, "{p} {r}");
            }
        }
    }
}
