//! Closed-form IK of 6R arms shaped like Universal Robots' (and Kinova's, Doosan's,
//! Techman's): axes 2, 3 and 4 parallel, axes 5 and 6 intersecting. Detected from the
//! chain's geometry, not from names or DH tables, and solved by Paden–Kahan subproblems
//! as IK-Geo does (Elias & Wen, 2022): every solution, up to eight.
//!
//! With the joints in product-of-exponentials form (axis `h_i` through point `o_i` at
//! zero), and the points on axes 5 and 6 both taken at their intersection:
//! 1. `h·R1ᵀ(p_0T − o_1 − R06 p_6T) = h·(o_5 − o_1)` (rotations about the parallel
//!    axis `h` keep the component along it): subproblem 4 in θ1;
//! 2. `h·R5 h6 = h·R1ᵀ R06 h6`: subproblem 4 in θ5;
//! 3. `R6 R06ᵀ R1 h = R5ᵀ h`: subproblem 1 in θ6; then θ2+θ3+θ4 from `R234`;
//! 4. the planar part `R2(p_23 + R3 p_34) = δ`: subproblem 3 in θ3, 1 in θ2; θ4 last.
//!
//! Every candidate is checked by forward kinematics before it is returned.

use super::closed_form::{answer, axes_at_zero, check_full_pose};
use super::screws::{Candidate, MAX_CANDIDATES, Screws};
use super::subproblems::{TOL, any_perpendicular, intersection, subproblem1, subproblem4};
use super::{IkError, IkMode, IkSolution, IkSolver};
use crate::Chain;
use tabula_geom::{Mat3, Pose, Vec3};

/// The solver of one matching chain.
#[derive(Debug, Clone)]
pub struct ThreeParallelIk {
    chain: Chain,
    /// Joint axes and points at zero (base frame), the points on axes 5 and 6 moved to
    /// their intersection, and the tip at zero.
    screws: Screws<6>,
    /// The tip's position and rotation at zero.
    tip_zero: Pose,
}

impl ThreeParallelIk {
    /// The solver for `chain`, or `None` when the chain is not of this family (six
    /// revolute joints, one variable each with multiplier ±1, axes 2–4 parallel, axes 1
    /// and 2 not, axes 5 and 6 meeting in a point).
    pub fn new(chain: &Chain) -> Option<Self> {
        let (h, mut o, tip_zero) = axes_at_zero::<6>(chain)?;
        let parallel = |a: Vec3, b: Vec3| a.cross(b).length() < TOL;
        if !(parallel(h[1], h[2]) && parallel(h[1], h[3])) || parallel(h[0], h[1]) {
            return None;
        }
        if parallel(h[4], h[5]) || parallel(h[1], h[4]) {
            return None;
        }
        let meet = intersection(o[4], h[4], o[5], h[5])?;
        o[4] = meet;
        o[5] = meet;
        Some(Self {
            chain: chain.clone(),
            screws: Screws::new(h, o, &tip_zero, 1),
            tip_zero,
        })
    }

    /// Joint angles (θ, before multiplier and offset) reaching `target`, unchecked: at
    /// most 2 (θ1) × 2 (θ5) × 2 (θ3).
    fn candidates(&self, target: &Pose) -> ([Candidate<6>; MAX_CANDIDATES], usize) {
        let (h, o) = (&self.screws.h, &self.screws.o);
        let k = h[1];
        let r06 = Mat3::from_quat(target.rotation.normalize())
            * Mat3::from_quat(self.tip_zero.rotation).transpose();
        let p_6t = self.tip_zero.translation - o[5];
        let x = target.translation - o[0] - r06 * p_6t;
        let (p23, p34) = (o[2] - o[1], o[3] - o[2]);
        let v = any_perpendicular(k);
        let mut out = ([Candidate::default(); MAX_CANDIDATES], 0);
        // 1: hᵀ rot(h1, −θ1) x = h·(o5 − o1)  ⇔  hᵀ rot(−h1, θ1) x = d.
        for t1 in subproblem4(k, x, -h[0], k.dot(o[4] - o[0])) {
            let a1 = t1.angle();
            let r1 = t1.about(h[0]);
            let r16 = r1.transpose() * r06;
            // 4's right side, δ = R1ᵀ x − p_12 − R234 p_45, before R234.
            let x1 = r1.transpose() * x - (o[1] - o[0]);
            // 2: hᵀ rot(h5, θ5) h6 = hᵀ R1ᵀ R06 h6.
            for t5 in subproblem4(k, h[5], h[4], k.dot(r16 * h[5])) {
                // 3: rot(h6, θ6) (R06ᵀ R1 h) = R5ᵀ h.
                let r5_t_k = t5.inverse().rotate(h[4], k);
                let Some(t6) = subproblem1(r16.transpose() * k, r5_t_k, h[5]) else {
                    continue;
                };
                let (a5, a6) = (t5.angle(), t6.angle());
                let r234 = r16 * t6.about(h[5]).transpose() * t5.about(h[4]).transpose();
                let Some(t234) = subproblem1(v, r234 * v, k) else {
                    continue;
                };
                let a234 = t234.angle();
                // 4: δ = R2 (p_23 + R3 p_34).
                let delta = x1 - r234 * (o[4] - o[3]);
                let d =
                    (delta.length_squared() - p23.length_squared() - p34.length_squared()) / 2.0;
                for t3 in subproblem4(p23, p34, h[2], d) {
                    let arm = p23 + t3.rotate(h[2], p34);
                    let Some(t2) = subproblem1(arm, delta, h[1]) else {
                        continue;
                    };
                    if out.1 < MAX_CANDIDATES {
                        let (a2, a3) = (t2.angle(), t3.angle());
                        out.0[out.1] = Candidate {
                            turns: [t1, t2, t3, t234.minus(t2).minus(t3), t5, t6],
                            angles: [a1, a2, a3, a234 - a2 - a3, a5, a6],
                        };
                        out.1 += 1;
                    }
                }
            }
        }
        out
    }
}

impl IkSolver for ThreeParallelIk {
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
