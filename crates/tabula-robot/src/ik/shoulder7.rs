//! Closed-form IK of 7R arms with a spherical shoulder — axes 1, 2 and 3 meeting in a
//! point S — and axes 5 and 6 meeting in a point W: Franka's Panda (its wrist offset
//! is between axes 6 and 7), KUKA's iiwa and Barrett's WAM (axes 5–7 meet). Detected
//! from the chain's geometry. The arm is redundant; the last joint's angle is the
//! parameter (as in He & Liu's Panda solution, 2021): for each value every solution
//! comes from Paden–Kahan subproblems, as IK-Geo solves its 6R families.
//!
//! In product-of-exponentials form, with `G = T M⁻¹ E7⁻¹` (T the target, M the tip at
//! zero, E7 the last joint's motion) the first six joints must give `E1…E6 = G`:
//! 1. E5 and E6 fix W, E1–E3 fix S, so `|G W − S| = |E4 W − S|`: subproblem 3 in θ4;
//! 2. `E5 E6 (G⁻¹ S) = E4⁻¹ S`, rotations about axes through W: subproblem 2 in θ5, θ6;
//! 3. `R1 R2 R3 = R_G R6ᵀ R5ᵀ R4ᵀ`: subproblem 2 in θ1, θ2 on axis 3's direction,
//!    subproblem 1 in θ3.
//!
//! Up to eight solutions per value of the last joint. The value is swept from the
//! seed's outward until one is found, so the answer is on the seed's side of the
//! self-motion; every candidate is checked by forward kinematics.

use super::closed_form::{axes_at_zero, check_full_pose, verified};
use super::screws::{Candidate, MAX_CANDIDATES, Screws};
use super::subproblems::{
    Turn, any_perpendicular, intersection, subproblem1, subproblem2, subproblem3,
};
use super::{IkError, IkMode, IkSolution, IkSolver};
use crate::Chain;
use tabula_geom::{Mat3, Pose, Vec3};

/// Step of the sweep over the last joint (rad): 0.05 finds every pose whose solutions
/// span more than that much of the joint (the numeric solver takes what is left).
const SWEEP_STEP: f64 = 0.05;
/// The first pass takes every fourth step (0.2 rad).
const COARSE: i64 = 4;

/// The solver of one matching chain.
#[derive(Debug, Clone)]
pub struct SphericalShoulderIk {
    chain: Chain,
    /// Joint axes at zero (base frame), a point on each (S on axes 1–3, W on axes 5
    /// and 6) and the tip at zero.
    screws: Screws<7>,
    shoulder: Vec3,
    wrist: Vec3,
    /// No configuration puts the tip farther than this from S (m).
    reach: f64,
}

impl SphericalShoulderIk {
    /// The solver for `chain`, or `None` when the chain is not of this family (seven
    /// revolute joints, one variable each with multiplier ±1, axes 1–3 meeting in one
    /// point, axes 5 and 6 meeting, axis 4 through neither point).
    pub fn new(chain: &Chain) -> Option<Self> {
        let (h, mut o, tip_zero) = axes_at_zero::<7>(chain)?;
        // Axes 1 and 3 may be one line at zero (Z–Y–Z shoulders): 1∩2 and 2∩3 suffice.
        let shoulder = intersection(o[0], h[0], o[1], h[1])?;
        let s23 = intersection(o[1], h[1], o[2], h[2])?;
        if (shoulder - s23).length() > 1e-7 {
            return None;
        }
        let wrist = intersection(o[4], h[4], o[5], h[5])?;
        // Axis 4 through S (or W): the elbow would not change the distance |SW|.
        let off_axis = |p: Vec3| (p - o[3]).cross(h[3]).length();
        if off_axis(shoulder) < 1e-6 || off_axis(wrist) < 1e-6 {
            return None;
        }
        o[..3].fill(shoulder);
        o[4] = wrist;
        o[5] = wrist;
        // |SW| varies only with joint 4; |W tip| only with joint 7 (5 and 6 turn about W).
        let reach = farthest(shoulder, wrist, o[3], h[3])
            + farthest(wrist, tip_zero.translation, o[6], h[6]);
        Some(Self {
            reach,
            chain: chain.clone(),
            screws: Screws::new(h, o, &tip_zero, 0),
            shoulder,
            wrist,
        })
    }

    /// Joint angles (θ) reaching `target` with the last joint at `theta7`, unchecked.
    fn candidates(&self, target: &Pose, theta7: f64) -> ([Candidate<7>; MAX_CANDIDATES], usize) {
        let (h, o, s, w) = (&self.screws.h, &self.screws.o, self.shoulder, self.wrist);
        let (tip_rotation, tip_translation) =
            (self.screws.tip_rotation, self.screws.tip_translation);
        let mut out = ([Candidate::default(); MAX_CANDIDATES], 0);
        // G = T M⁻¹ E7⁻¹ as x ↦ R_G x + t_G.
        let t7 = Turn::new(theta7);
        let r7 = t7.about(h[6]);
        let rt = Mat3::from_quat(target.rotation.normalize());
        let rtm = rt * tip_rotation.transpose();
        let rg = rtm * r7.transpose();
        let g_of = |x: Vec3| {
            rtm * (r7.transpose() * (x - o[6]) + o[6] - tip_translation) + target.translation
        };
        let g_inv_of = |y: Vec3| {
            r7 * (rtm.transpose() * (y - target.translation) + tip_translation - o[6]) + o[6]
        };
        let gw = g_of(w);
        let g_inv_s = g_inv_of(s) - w;
        let x = any_perpendicular(h[2]);
        // 1: |rot(h4, θ4)(W − o4) − (S − o4)| = |G W − S|.
        for t4 in subproblem3(w - o[3], s - o[3], h[3], (gw - s).length()) {
            let (r4, a4) = (t4.about(h[3]), t4.angle());
            let e4_inv_s = r4.transpose() * (s - o[3]) + o[3] - w;
            // 2: rot(h5, θ5) rot(h6, θ6) (G⁻¹S − W) = E4⁻¹S − W.
            for (t6, minus_t5) in subproblem2(g_inv_s, h[5], e4_inv_s, h[4]) {
                let t5 = minus_t5.inverse();
                let (a5, a6) = (t5.angle(), t6.angle());
                let r56 = t5.about(h[4]) * t6.about(h[5]);
                let rh = rg * r56.transpose() * r4.transpose();
                // 3: rot(h1, θ1) rot(h2, θ2) h3 = R_H h3.
                for (t2, minus_t1) in subproblem2(h[2], h[1], rh * h[2], h[0]) {
                    let t1 = minus_t1.inverse();
                    let r12 = t1.about(h[0]) * t2.about(h[1]);
                    let Some(t3) = subproblem1(x, r12.transpose() * rh * x, h[2]) else {
                        continue;
                    };
                    if out.1 < MAX_CANDIDATES {
                        out.0[out.1] = Candidate {
                            turns: [t1, t2, t3, t4, t5, t6, t7],
                            angles: [t1.angle(), t2.angle(), t3.angle(), a4, a5, a6, theta7],
                        };
                        out.1 += 1;
                    }
                }
            }
        }
        out
    }

    /// The values of the last joint's variable to try: the seed's, then outward in both
    /// directions within its limits (a turn either way for a continuous joint), every
    /// [`COARSE`]th step first so that a narrow band of solutions far from the seed is
    /// reached early.
    fn sweep(&self, seed7: f64) -> impl Iterator<Item = f64> + use<> {
        let pi = std::f64::consts::PI;
        let (mut lo, mut hi) = (self.chain.lower[6], self.chain.upper[6]);
        // A continuous joint (or limits wider than a turn): a turn either way.
        if hi - lo > 2.0 * pi || !(hi - lo).is_finite() {
            (lo, hi) = (seed7 - pi, seed7 + pi);
        }
        let start = seed7.clamp(lo, hi);
        let reach = ((start - lo).max(hi - start) / SWEEP_STEP).ceil() as i64;
        let coarse = (0..=reach).step_by(COARSE as usize);
        let fine = (1..=reach).filter(|k| k % COARSE != 0);
        coarse
            .chain(fine)
            .flat_map(move |k| {
                let d = k as f64 * SWEEP_STEP;
                [start + d, start - d]
                    .into_iter()
                    .take(if k == 0 { 1 } else { 2 })
            })
            .filter(move |q| (lo..=hi).contains(q))
    }
}

impl SphericalShoulderIk {
    /// The verified solutions with the last joint's variable at `q7`, nearest the seed
    /// first.
    fn solutions_at(&self, target: &Pose, q7: f64, seed: &[f64]) -> Vec<IkSolution> {
        let e7 = &self.chain.elements[6];
        let (candidates, count) = self.candidates(target, e7.multiplier * q7 + e7.offset);
        verified(
            &self.screws,
            &self.chain,
            &candidates[..count],
            target,
            seed,
        )
    }
}

impl IkSolver for SphericalShoulderIk {
    fn chain(&self) -> &Chain {
        &self.chain
    }

    fn solve(&self, target: &Pose, mode: IkMode, seed: &[f64]) -> Result<Vec<IkSolution>, IkError> {
        check_full_pose(&self.chain, target, mode, seed)?;
        if (target.translation - self.shoulder).length() > self.reach + 1e-6 {
            return Err(IkError::NoSolution);
        }
        for q7 in self.sweep(seed[6]) {
            let found = self.solutions_at(target, q7, seed);
            if !found.is_empty() {
                return Ok(found);
            }
        }
        Err(IkError::NoSolution)
    }
}

/// The largest distance from `p` to `q` turned about the axis through `o` along `h`.
fn farthest(p: Vec3, q: Vec3, o: Vec3, h: Vec3) -> f64 {
    let (p, q) = (p - o, q - o);
    let radial = |v: Vec3| (v - h * h.dot(v)).length();
    (radial(p) + radial(q)).hypot(h.dot(p) - h.dot(q))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::robots;
    use rand::SeedableRng;

    fn solver(name: &str) -> SphericalShoulderIk {
        let r = robots::load(name).expect("robot");
        let chain = Chain::new(&r.model, &r.default_base, &r.default_tip).expect("chain");
        SphericalShoulderIk::new(&chain).expect("a spherical-shoulder 7R arm")
    }

    #[test]
    fn the_wam_is_of_the_family_and_every_answer_reaches_its_target() {
        let ik = solver("wam");
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(3);
        let mut solved = 0;
        for _ in 0..500 {
            let q = ik.chain.random_configuration(&mut rng);
            let seed = ik.chain.random_configuration(&mut rng);
            let target = ik.chain.fk(&q).expect("fk");
            if let Ok(sols) = ik.solve(&target, IkMode::Full, &seed) {
                solved += 1;
                for s in &sols {
                    let (p, r) = super::super::pose_error(
                        &ik.chain.fk(&s.joints).expect("fk"),
                        &target,
                        IkMode::Full,
                    );
                    assert!(p < 1e-6 && r < 1e-6, "{p} {r}");
                }
            }
        }
        assert!(solved >= 495, "{solved} of 500");
    }

    #[test]
    fn a_target_at_the_seed_gives_the_seed_first() {
        let ik = solver("wam");
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(5);
        for _ in 0..50 {
            let q = ik.chain.random_configuration(&mut rng);
            let target = ik.chain.fk(&q).expect("fk");
            let sols = ik.solve(&target, IkMode::Full, &q).expect("solved");
            let d = super::super::joint_distance(&ik.chain, &sols[0].joints, &q);
            assert!(d < 1e-6, "first solution {d} rad from the seed");
        }
    }

    #[test]
    fn other_arms_are_not_taken_for_it() {
        for name in ["pr2", "golem3"] {
            let r = robots::load(name).expect("robot");
            let chain = Chain::new(&r.model, &r.default_base, &r.default_tip).expect("chain");
            assert!(SphericalShoulderIk::new(&chain).is_none(), "{name}");
        }
    }
}
