//! Closed-form IK of 6R arms with a spherical wrist — axes 4, 5 and 6 meeting in a point
//! W — whose first three joints place W by subproblems: axes 2 and 3 parallel (most
//! industrial arms: ABB, KUKA, FANUC, Yaskawa, Comau) or axes 1 and 2 meeting (Stäubli's
//! TX, PUMA-like arms without shoulder offset). IK-Geo's `spherical_two_parallel` and
//! `spherical_two_intersecting` families (Elias & Wen, 2022); every solution, up to eight.
//!
//! E4–E6 turn about axes through W, so `E1 E2 E3 W = W_T`, the wrist point of the
//! target (`T M⁻¹ W`):
//! * 2 ∥ 3 (direction k): `k·R1ᵀ(W_T − o1) = k·(W − o1)` is subproblem 4 in θ1;
//!   `|E3 W − o2| = |E1⁻¹ W_T − o2|` subproblem 3 in θ3; subproblem 1 in θ2;
//! * 1 ∩ 2 in S: `|E3 W − S| = |W_T − S|` is subproblem 3 in θ3; `E1 E2 (E3 W − S) =
//!   W_T − S` subproblem 2 in θ1, θ2.
//!
//! Then `R4 R5 R6 = R_W` (the rest of the target's rotation): `R5 h6 = R4ᵀ R_W h6` is
//! subproblem 2 in θ4, θ5, and subproblem 1 gives θ6. Every candidate is checked by
//! forward kinematics before it is returned.

use super::closed_form::{answer, axes_at_zero, check_full_pose};
use super::screws::{Candidate, MAX_CANDIDATES, Screws};
use super::subproblems::{
    TOL, Turn, any_perpendicular, intersection, subproblem1, subproblem2, subproblem3, subproblem4,
};
use super::{IkError, IkMode, IkSolution, IkSolver};
use crate::Chain;
use tabula_geom::{Mat3, Pose, Vec3};

/// How the first three joints place the wrist point.
#[derive(Debug, Clone, Copy)]
enum Shoulder {
    /// Axes 2 and 3 parallel.
    TwoParallel,
    /// Axes 1 and 2 meeting at this point.
    TwoIntersecting(Vec3),
}

/// The solver of one matching chain.
#[derive(Debug, Clone)]
pub struct SphericalWristIk {
    chain: Chain,
    /// Joint axes and points at zero (base frame), the points on axes 4–6 moved to W.
    screws: Screws<6>,
    shoulder: Shoulder,
    wrist: Vec3,
    tip_zero: Pose,
}

impl SphericalWristIk {
    /// The solver for `chain`, or `None` when the chain is not of this family (six
    /// revolute joints, one variable each with multiplier ±1, axes 4–6 meeting in one
    /// point, and axes 2 ∥ 3 or axes 1 ∩ 2, the wrist point off axis 3).
    pub fn new(chain: &Chain) -> Option<Self> {
        let (h, mut o, tip_zero) = axes_at_zero::<6>(chain)?;
        let parallel = |a: Vec3, b: Vec3| a.cross(b).length() < TOL;
        if parallel(h[3], h[4]) || parallel(h[4], h[5]) || parallel(h[0], h[1]) {
            return None;
        }
        let wrist = intersection(o[3], h[3], o[4], h[4])?;
        if (intersection(o[4], h[4], o[5], h[5])? - wrist).length() > 1e-7 {
            return None;
        }
        let off_axis = |p: Vec3, i: usize| (p - o[i]).cross(h[i]).length();
        // W on axis 3: joint 3 could not change where it is.
        if off_axis(wrist, 2) < 1e-6 {
            return None;
        }
        let shoulder = if parallel(h[1], h[2]) {
            Shoulder::TwoParallel
        } else {
            let s = intersection(o[0], h[0], o[1], h[1])?;
            // Axis 3 through S: joint 3 could not change |W − S|.
            if off_axis(s, 2) < 1e-6 {
                return None;
            }
            Shoulder::TwoIntersecting(s)
        };
        o[3] = wrist;
        o[4] = wrist;
        o[5] = wrist;
        Some(Self {
            chain: chain.clone(),
            // Candidates branch on the arm's joints first, the wrist's innermost.
            screws: Screws::new(h, o, &tip_zero, 3),
            shoulder,
            wrist,
            tip_zero,
        })
    }

    /// Joint angles (θ, before multiplier and offset) reaching `target`, unchecked: at
    /// most 2 × 2 for the arm times 2 for the wrist.
    fn candidates(&self, target: &Pose) -> ([Candidate<6>; MAX_CANDIDATES], usize) {
        let (h, w) = (&self.screws.h, self.wrist);
        // R_T M_Rᵀ, and where the target puts the wrist point.
        let r_target = Mat3::from_quat(target.rotation.normalize())
            * Mat3::from_quat(self.tip_zero.rotation).transpose();
        let w_target = target.translation + r_target * (w - self.tip_zero.translation);
        let mut out = ([Candidate::default(); MAX_CANDIDATES], 0);
        for arm in self.arm(w_target) {
            let [t1, t2, t3] = arm;
            let r123 = t1.about(h[0]) * t2.about(h[1]) * t3.about(h[2]);
            let r_wrist = r123.transpose() * r_target;
            // rot(h5, θ5) h6 = rot(h4, −θ4) R_W h6.
            for (t5, minus_t4) in subproblem2(h[5], h[4], r_wrist * h[5], h[3]) {
                let t4 = minus_t4.inverse();
                let r45 = t4.about(h[3]) * t5.about(h[4]);
                let v = any_perpendicular(h[5]);
                let Some(t6) = subproblem1(v, r45.transpose() * r_wrist * v, h[5]) else {
                    continue;
                };
                if out.1 < MAX_CANDIDATES {
                    let turns = [t1, t2, t3, t4, t5, t6];
                    out.0[out.1] = Candidate {
                        turns,
                        angles: turns.map(Turn::angle),
                    };
                    out.1 += 1;
                }
            }
        }
        out
    }

    /// (θ1, θ2, θ3) putting the wrist point at `w_target`: up to four.
    fn arm(&self, w_target: Vec3) -> impl Iterator<Item = [Turn; 3]> + use<> {
        let (h, o, w) = (self.screws.h, self.screws.o, self.wrist);
        let mut out = [[Turn::default(); 3]; 4];
        let mut n = 0;
        match self.shoulder {
            Shoulder::TwoParallel => {
                let k = h[1];
                let x = w_target - o[0];
                // kᵀ rot(h1, −θ1) x = k·(W − o1)  ⇔  kᵀ rot(−h1, θ1) x = d.
                for t1 in subproblem4(k, x, -h[0], k.dot(w - o[0])) {
                    let y = t1.inverse().rotate(h[0], x) + o[0] - o[1];
                    for t3 in subproblem3(w - o[2], o[1] - o[2], h[2], y.length()) {
                        let e3w = t3.rotate(h[2], w - o[2]) + o[2] - o[1];
                        if let Some(t2) = subproblem1(e3w, y, h[1]) {
                            out[n] = [t1, t2, t3];
                            n += 1;
                        }
                    }
                }
            }
            Shoulder::TwoIntersecting(s) => {
                let b = w_target - s;
                for t3 in subproblem3(w - o[2], s - o[2], h[2], b.length()) {
                    let a = t3.rotate(h[2], w - o[2]) + o[2] - s;
                    // rot(h2, θ2) a = rot(h1, −θ1) b.
                    for (t2, minus_t1) in subproblem2(a, h[1], b, h[0]) {
                        out[n] = [minus_t1.inverse(), t2, t3];
                        n += 1;
                    }
                }
            }
        }
        out.into_iter().take(n)
    }
}

impl IkSolver for SphericalWristIk {
    fn chain(&self) -> &Chain {
        &self.chain
    }

    fn solve(&self, target: &Pose, mode: IkMode, seed: &[f64]) -> Result<Vec<IkSolution>, IkError> {
        check_full_pose(&self.chain, target, mode, seed)?;
        let (candidates, count) = self.candidates(target);
        answer(
            &self.screws,
            &self.chain,
            &candidates[..count],
            target,
            seed,
        )
    }
}
