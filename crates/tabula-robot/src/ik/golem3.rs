//! Closed-form IK of the Golem-III arm (seed 001, SPEC §2.1–2.3).
//!
//! Convention (the DH table is the robot): standard DH
//! `A_i = Rot_z(θ_i + offset_i) · Trans_z(d_i) · Trans_x(a_i) · Rot_x(α_i)` with the
//! rows of SPEC §2.1, frame 0 = `torso_lift_link` (the robot base at lift 0; targets
//! are given in it, so it rides with the torso lift), tool frame per row 6′. In closed form, with γ = θ1+θ2+θ3 (the seed's "roll"), φ = −θ4−θ5
//! ("pitch"), ψ = θ6 (the seed's "yaw", a rotation about x) and
//! `l3 = l4 sin(θ4+ρ) + l5 sin(θ4+θ5) + l6 cos(θ4+θ5)`:
//!
//! ```text
//! x = l1 sin θ1 + l2 sin(θ1+θ2) + l3 cos γ
//! y = −l1 cos θ1 − l2 cos(θ1+θ2) + l3 sin γ
//! z = h − l4 cos(θ4+ρ) − l5 cos(θ4+θ5) + l6 sin(θ4+θ5)      (the seed prints cos θ4: a typo)
//! R = Rz(γ) · Ry(φ) · Rx(ψ)
//! ```
//!
//! Full-pose IK: both Euler sets of R (the second, (γ+π, π−φ, ψ+π), is the same
//! rotation), two signs of θ4+ρ from z, two elbow signs of the planar 2-link (θ1, θ2):
//! up to 8 branches, each checked against the limits and verified by FK. Arguments of
//! acos within 1e-9 outside [−1, 1] are rounding (a target on the boundary of the
//! workspace), so they are clamped instead of losing the solution — the seed's 6 %.
//! ψ is taken from the residual rotation `Ry(−φ) Rz(−γ) R`, so near φ = ±π/2 an error
//! in γ is absorbed by θ6 instead of showing up in the pose.
//!
//! Position-only IK is a 1-D search over the pitch s = θ4+θ5 (ordered outward from the
//! seed's), each step closed form: z gives θ4 (two signs) and the horizontal reach l3,
//! the feasible roll interval comes from the law of cosines, and the planar 2-link gives
//! θ1, θ2. The seed swept roll and pitch in 2-D.
//!
//! The left arm is the right arm mirrored in the x–z plane: a left target is mirrored,
//! solved as a right target, and θ1 (the shared torso rotation) changes sign.

use super::{IkError, IkMode, IkSolution, IkSolver, pose_error, sort_and_dedup, validate_request};
use crate::{Chain, RobotError, RobotModel};
use std::f64::consts::PI;
use tabula_geom::{Mat3, Pose, Quat, Vec3, wrap_angle};

/// Which arm.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ArmSide {
    Right,
    Left,
}

impl ArmSide {
    pub fn prefix(self) -> &'static str {
        match self {
            ArmSide::Right => "right",
            ArmSide::Left => "left",
        }
    }
}

/// Golem-III arm geometry; defaults are the DH table of SPEC §2.1.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Golem3Params {
    /// Shoulder height h (m), SPEC §2.1 row 1.
    pub h: f64,
    pub l1: f64,
    pub l2: f64,
    pub l4: f64,
    pub l5: f64,
    pub l6: f64,
    /// ρ (rad): 13.43°, SPEC §2.1 rows 4–5.
    pub rho: f64,
    /// A branch is kept only if FK(solution) is this close to the target (m and rad).
    pub verify_tolerance: f64,
    /// Step of the pitch search of position-only IK (rad).
    pub position_pitch_step: f64,
}

impl Default for Golem3Params {
    fn default() -> Self {
        Self {
            h: 1.283,
            l1: 0.1225,
            l2: 0.212,
            l4: 0.256,
            l5: 0.034,
            l6: 0.4,
            rho: 13.43f64.to_radians(),
            verify_tolerance: 1e-6,
            position_pitch_step: 0.01,
        }
    }
}

/// Closed-form solver for one Golem-III arm, chain `torso_lift_link` → `<side>_tool_link`.
#[derive(Debug, Clone)]
pub struct Golem3Ik {
    side: ArmSide,
    pub params: Golem3Params,
    chain: Chain,
    /// Limits in the right-arm convention (θ1 mirrored for the left arm).
    lower: [f64; 6],
    upper: [f64; 6],
    reach_center: Vec3,
    reach_bound: f64,
}

/// Slack on acos arguments and joint limits that is rounding, not geometry.
const ROUNDING: f64 = 1e-9;

impl Golem3Ik {
    /// Builds the solver for `side` of a Golem-III model, taking the joint limits from
    /// the URDF, and checks the model's FK against the DH table so a different robot
    /// is refused rather than solved wrongly.
    pub fn new(
        model: &RobotModel,
        side: ArmSide,
        params: Golem3Params,
    ) -> Result<Self, RobotError> {
        let tip = format!("{}_tool_link", side.prefix());
        let chain = Chain::new(model, "torso_lift_link", &tip)?;
        let not_golem = |why: &'static str| RobotError::NotGolem3 {
            tip: tip.clone(),
            why,
        };
        if chain.dof() != 6 {
            return Err(not_golem("it does not have 6 joints"));
        }
        let mut lower = [0.0; 6];
        let mut upper = [0.0; 6];
        lower.copy_from_slice(&chain.lower);
        upper.copy_from_slice(&chain.upper);
        if side == ArmSide::Left {
            (lower[0], upper[0]) = (-upper[0], -lower[0]);
        }
        let solver = Self {
            side,
            params,
            reach_center: chain.reach_center(),
            reach_bound: chain.reach_bound() + ROUNDING,
            chain,
            lower,
            upper,
        };
        for k in 0..8 {
            let q: Vec<f64> = (0..6)
                .map(|i| 0.3 * ((i * 7 + k * 3) % 11) as f64 / 11.0 - 0.1)
                .collect();
            let urdf = solver.chain.fk_unchecked(&q);
            let dh = solver.fk(&q);
            if (urdf.translation - dh.translation).length() > 1e-9
                || tabula_geom::rotation_angle_between(urdf.rotation, dh.rotation) > 1e-9
            {
                return Err(not_golem(
                    "its forward kinematics differ from the DH table of SPEC 2.1",
                ));
            }
        }
        Ok(solver)
    }

    pub fn side(&self) -> ArmSide {
        self.side
    }

    /// Closed-form FK (`torso_lift_link` → tool) in this arm's own joint convention.
    pub fn fk(&self, q: &[f64]) -> Pose {
        let mut q6 = [0.0; 6];
        q6.copy_from_slice(&q[..6]);
        if self.side == ArmSide::Left {
            q6[0] = -q6[0];
        }
        let (p, r) = self.fk_right(&q6);
        let pose = Pose::from_parts(p, Quat::from_mat3(&r));
        if self.side == ArmSide::Left {
            mirror(&pose)
        } else {
            pose
        }
    }

    fn fk_right(&self, q: &[f64; 6]) -> (Vec3, Mat3) {
        let p = &self.params;
        let gamma = q[0] + q[1] + q[2];
        let s = q[3] + q[4];
        let (ss, cs) = s.sin_cos();
        let (sa, ca) = (q[3] + p.rho).sin_cos();
        let l3 = p.l4 * sa + p.l5 * ss + p.l6 * cs;
        let (sg, cg) = gamma.sin_cos();
        let x = p.l1 * q[0].sin() + p.l2 * (q[0] + q[1]).sin() + l3 * cg;
        let y = -p.l1 * q[0].cos() - p.l2 * (q[0] + q[1]).cos() + l3 * sg;
        let z = p.h - p.l4 * ca - p.l5 * cs + p.l6 * ss;
        let r =
            Mat3::from_rotation_z(gamma) * Mat3::from_rotation_y(-s) * Mat3::from_rotation_x(q[5]);
        (Vec3::new(x, y, z), r)
    }

    fn within(&self, q: &[f64; 6]) -> bool {
        (0..6).all(|i| q[i] >= self.lower[i] - ROUNDING && q[i] <= self.upper[i] + ROUNDING)
    }

    /// All right-arm branches for position `p` and rotation `r` (right-arm frame).
    fn solve_full_right(&self, p: Vec3, r: &Mat3, out: &mut Vec<[f64; 6]>) {
        let m = |i: usize, j: usize| r.col(j)[i];
        let phi = (-m(2, 0)).atan2(m(0, 0).hypot(m(1, 0)));
        let gamma = m(1, 0).atan2(m(0, 0));
        for (gamma, phi) in [(gamma, phi), (gamma + PI, PI - phi)] {
            let residual = Mat3::from_rotation_y(-phi) * Mat3::from_rotation_z(-gamma) * *r;
            let psi = residual.col(1)[2].atan2(residual.col(2)[2]);
            let theta6 = wrap_angle(psi);
            if theta6 < self.lower[5] - ROUNDING || theta6 > self.upper[5] + ROUNDING {
                continue;
            }
            for (theta4, theta5, l3) in self.wrist(p.z, -phi) {
                self.planar(p, gamma, l3, [theta4, theta5, theta6], out);
            }
        }
    }

    /// (θ4, θ5, l3) for tool height `z` and pitch sum s = θ4+θ5: z fixes cos(θ4+ρ),
    /// both signs of its sine are branches, and l3 is the horizontal reach they give.
    fn wrist(&self, z: f64, s: f64) -> impl Iterator<Item = (f64, f64, f64)> + '_ {
        let prm = &self.params;
        let (ss, cs) = s.sin_cos();
        let c4 = -(z - prm.h - prm.l6 * ss + prm.l5 * cs) / prm.l4;
        robust_acos(c4)
            .into_iter()
            .flat_map(branches)
            .map(move |alpha| {
                let theta4 = wrap_angle(alpha - prm.rho);
                let l3 = prm.l4 * alpha.sin() + prm.l5 * ss + prm.l6 * cs;
                (theta4, wrap_angle(s - theta4), l3)
            })
    }

    /// θ1, θ2, θ3 for roll γ and horizontal reach l3, both elbow signs.
    fn planar(
        &self,
        p: Vec3,
        gamma: f64,
        l3: f64,
        wrist: [f64; 3],
        out: &mut Vec<[f64; 6]>,
    ) -> bool {
        let prm = &self.params;
        let (sg, cg) = gamma.sin_cos();
        let u = p.x - l3 * cg;
        let v = -(p.y - l3 * sg);
        let c2 = (u * u + v * v - prm.l1 * prm.l1 - prm.l2 * prm.l2) / (2.0 * prm.l1 * prm.l2);
        let Some(acos2) = robust_acos(c2) else {
            return false;
        };
        let mut found = false;
        for theta2 in branches(acos2) {
            let theta1 = u.atan2(v) - (prm.l2 * theta2.sin()).atan2(prm.l1 + prm.l2 * theta2.cos());
            let q = [
                wrap_angle(theta1),
                wrap_angle(theta2),
                wrap_angle(gamma - theta1 - theta2),
                wrist[0],
                wrist[1],
                wrist[2],
            ];
            if self.within(&q) {
                out.push(q);
                found = true;
            }
        }
        found
    }

    /// Position-only IK (right-arm frame): 1-D search over the pitch, closed form inside.
    fn solve_position_right(&self, p: Vec3, seed: &[f64; 6], step: f64, out: &mut Vec<[f64; 6]>) {
        let prm = &self.params;
        let (s_min, s_max) = (self.lower[3] + self.lower[4], self.upper[3] + self.upper[4]);
        let s0 = (seed[3] + seed[4]).clamp(s_min, s_max);
        let gamma0 = seed[0] + seed[1] + seed[2];
        let theta6 = seed[5].clamp(self.lower[5], self.upper[5]);
        let (r_min, r_max) = ((prm.l1 - prm.l2).abs(), prm.l1 + prm.l2);
        let w = p.x.hypot(p.y);
        let phi_w = p.y.atan2(p.x);
        let steps = ((s_max - s_min) / step).ceil() as i64 + 1;
        for k in 0..2 * steps {
            // s0, s0+Δ, s0−Δ, s0+2Δ, …
            let offset = if k % 2 == 1 {
                (k / 2 + 1) as f64
            } else {
                -((k / 2) as f64)
            };
            let s = s0 + offset * step;
            if s < s_min - ROUNDING || s > s_max + ROUNDING {
                continue;
            }
            for (theta4, theta5, l3) in self.wrist(p.z, s) {
                if theta4 < self.lower[3] - ROUNDING
                    || theta4 > self.upper[3] + ROUNDING
                    || theta5 < self.lower[4] - ROUNDING
                    || theta5 > self.upper[4] + ROUNDING
                {
                    continue;
                }
                for gamma in roll_candidates(w, phi_w, l3, r_min, r_max, gamma0) {
                    if self.planar(p, gamma, l3, [theta4, theta5, theta6], out) {
                        return;
                    }
                }
            }
        }
    }

    fn to_right(&self, target: &Pose) -> Pose {
        if self.side == ArmSide::Left {
            mirror(target)
        } else {
            *target
        }
    }

    fn seed_right(&self, seed: &[f64]) -> [f64; 6] {
        let mut s = [0.0; 6];
        s.copy_from_slice(&seed[..6]);
        if self.side == ArmSide::Left {
            s[0] = -s[0];
        }
        s
    }

    fn finish(
        &self,
        raw: Vec<[f64; 6]>,
        target: &Pose,
        mode: IkMode,
        seed: &[f64],
    ) -> Result<Vec<IkSolution>, IkError> {
        let tol = self.params.verify_tolerance;
        let mut sols = Vec::with_capacity(raw.len());
        for mut q in raw {
            if self.side == ArmSide::Left {
                q[0] = -q[0];
            }
            let reached = self.fk(&q);
            let (position_error, rotation_error) = pose_error(&reached, target, mode);
            if position_error <= tol && rotation_error <= tol {
                let mut joints = q.to_vec();
                self.chain.clamp(&mut joints);
                sols.push(IkSolution {
                    joints,
                    position_error,
                    rotation_error,
                });
            }
        }
        if sols.is_empty() {
            return Err(IkError::NoSolution);
        }
        Ok(sort_and_dedup(&self.chain, sols, seed, 1e-6))
    }
}

impl IkSolver for Golem3Ik {
    fn chain(&self) -> &Chain {
        &self.chain
    }

    fn solve(&self, target: &Pose, mode: IkMode, seed: &[f64]) -> Result<Vec<IkSolution>, IkError> {
        validate_request(&self.chain, target, mode, seed)?;
        let target = Pose::from_parts(target.translation, target.rotation.normalize());
        // Beyond every configuration's reach: no branch can exist, and position-only
        // would otherwise sweep its whole pitch range to say so.
        if (target.translation - self.reach_center).length() > self.reach_bound {
            return Err(IkError::NoSolution);
        }
        let right = self.to_right(&target);
        let mut raw = Vec::with_capacity(8);
        match mode {
            IkMode::Full => {
                self.solve_full_right(
                    right.translation,
                    &Mat3::from_quat(right.rotation),
                    &mut raw,
                );
            }
            IkMode::PositionOnly => {
                let seed_r = self.seed_right(seed);
                let step = self.params.position_pitch_step;
                self.solve_position_right(right.translation, &seed_r, step, &mut raw);
                if raw.is_empty() {
                    // Narrow feasible regions near the workspace boundary: search finer.
                    self.solve_position_right(right.translation, &seed_r, step / 16.0, &mut raw);
                }
            }
            IkMode::PositionAxis { .. } => {
                return Err(IkError::UnsupportedMode(
                    "position+axis (use the numeric solver)",
                ));
            }
        }
        self.finish(raw, &target, mode, seed)
    }
}

/// acos that treats arguments within [`ROUNDING`] outside [−1, 1] as ±1.
fn robust_acos(c: f64) -> Option<f64> {
    if c.is_nan() || c.abs() > 1.0 + ROUNDING {
        None
    } else {
        Some(c.clamp(-1.0, 1.0).acos())
    }
}

/// ±a, or just a when both signs are the same angle.
fn branches(a: f64) -> impl Iterator<Item = f64> {
    let two = a > 1e-12 && a < PI - 1e-12;
    std::iter::once(a).chain(two.then_some(-a))
}

/// Rolls γ worth trying for horizontal target distance `w` (azimuth `phi_w`) and
/// forearm reach `l3`: where the remaining 2-link can reach at all (law of cosines),
/// the seed's roll projected into that set first, then spread over it.
fn roll_candidates(w: f64, phi_w: f64, l3: f64, r_min: f64, r_max: f64, gamma0: f64) -> Vec<f64> {
    const SAMPLES: usize = 8;
    let k = 2.0 * l3 * w;
    let base = w * w + l3 * l3;
    let mut intervals: Vec<(f64, f64)> = Vec::with_capacity(2);
    if k.abs() < 1e-12 {
        if base >= r_min * r_min - ROUNDING && base <= r_max * r_max + ROUNDING {
            intervals.push((-PI, PI));
        }
    } else {
        // |W − l3 e(γ)|² = base − k cos(γ − φ_w) must lie in [r_min², r_max²].
        let (mut lo, mut hi) = ((base - r_max * r_max) / k, (base - r_min * r_min) / k);
        if k < 0.0 {
            std::mem::swap(&mut lo, &mut hi);
        }
        if lo > 1.0 + ROUNDING || hi < -1.0 - ROUNDING {
            return Vec::new();
        }
        let (a_min, a_max) = (hi.clamp(-1.0, 1.0).acos(), lo.clamp(-1.0, 1.0).acos());
        intervals.push((phi_w + a_min, phi_w + a_max));
        intervals.push((phi_w - a_max, phi_w - a_min));
    }
    let mut out = Vec::with_capacity(2 + 2 * (SAMPLES + 1));
    let mut best = (f64::INFINITY, gamma0);
    for &(a, b) in &intervals {
        let mid = 0.5 * (a + b);
        let half = 0.5 * (b - a);
        let d = wrap_angle(gamma0 - mid).clamp(-half, half);
        let g = mid + d;
        let dist = wrap_angle(gamma0 - g).abs();
        if dist < best.0 {
            best = (dist, g);
        }
    }
    if best.0.is_finite() {
        out.push(best.1);
    }
    for &(a, b) in &intervals {
        for i in 0..=SAMPLES {
            out.push(a + (b - a) * (i as f64 + 0.5) / (SAMPLES as f64 + 1.0));
        }
    }
    out
}

/// Reflection in the x–z plane applied to a pose (`M T M`, M = diag(1, −1, 1)).
fn mirror(t: &Pose) -> Pose {
    let m = Mat3::from_diagonal(Vec3::new(1.0, -1.0, 1.0));
    let r = m * Mat3::from_quat(t.rotation) * m;
    Pose::from_parts(
        Vec3::new(t.translation.x, -t.translation.y, t.translation.z),
        Quat::from_mat3(&r),
    )
}
