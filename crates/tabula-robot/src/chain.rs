//! Kinematic chains between any two links, forward kinematics and the geometric Jacobian.
//!
//! A chain may climb from `base` up to the common ancestor and descend to `tip`
//! (e.g. from one gripper to the other); climbing a joint inverts it, which is the same
//! motion with the axis negated followed by the inverse origin. Every chain is
//! normalised into [`Element`]s "fixed pose, then motion about one axis", so FK is one
//! pose product per moving joint whatever the URDF looks like.

use crate::RobotError;
use crate::model::{JointKind, RobotModel};
use rand::{Rng, RngExt};
use tabula_geom::{Pose, Quat, Vec3};

/// One moving joint of a chain: a fixed pose followed by a motion.
#[derive(Debug, Clone)]
pub struct Element {
    /// Fixed transform from the previous element's moved frame to this joint's frame.
    pub pre: Pose,
    /// Unit axis in this joint's frame, negated when the joint is climbed.
    pub axis: Vec3,
    pub prismatic: bool,
    /// Index of the chain variable that drives this joint.
    pub var: usize,
    /// Joint value = multiplier * variable + offset (mimic joints).
    pub multiplier: f64,
    pub offset: f64,
}

/// A serial chain from `base` to `tip` with one variable per independent moving joint.
#[derive(Debug, Clone)]
pub struct Chain {
    pub base_link: String,
    pub tip_link: String,
    /// URDF names of the variables, in chain order.
    pub joint_names: Vec<String>,
    /// Indices of those joints in the model.
    pub joint_indices: Vec<usize>,
    pub lower: Vec<f64>,
    pub upper: Vec<f64>,
    pub velocity: Vec<f64>,
    /// True where the variable is a prismatic joint (metres, not radians).
    pub var_prismatic: Vec<bool>,
    pub elements: Vec<Element>,
    /// Fixed transform from the last element's moved frame to the tip.
    pub tip_offset: Pose,
}

impl Chain {
    /// The chain of `model` from link `base` to link `tip`.
    pub fn new(model: &RobotModel, base: &str, tip: &str) -> Result<Self, RobotError> {
        let b = model.link(base)?;
        let t = model.link(tip)?;
        let up_path = |mut l: usize| {
            let mut path = vec![l];
            while let Some(j) = model.links[l].parent_joint {
                l = model.joints[j].parent;
                path.push(l);
            }
            path
        };
        let from_base = up_path(b);
        let from_tip = up_path(t);
        let common = from_base
            .iter()
            .position(|l| from_tip.contains(l))
            .ok_or_else(|| RobotError::Disconnected {
                base: base.to_string(),
                tip: tip.to_string(),
            })?;
        let ancestor = from_base[common];
        let climb: Vec<usize> = from_base[..common]
            .iter()
            .map(|&l| {
                model.links[l]
                    .parent_joint
                    .expect("below the common ancestor")
            })
            .collect();
        let mut descend: Vec<usize> = from_tip
            [..from_tip.iter().position(|&l| l == ancestor).unwrap_or(0)]
            .iter()
            .map(|&l| {
                model.links[l]
                    .parent_joint
                    .expect("below the common ancestor")
            })
            .collect();
        descend.reverse();

        let mut chain = Chain {
            base_link: base.to_string(),
            tip_link: tip.to_string(),
            joint_names: Vec::new(),
            joint_indices: Vec::new(),
            lower: Vec::new(),
            upper: Vec::new(),
            velocity: Vec::new(),
            var_prismatic: Vec::new(),
            elements: Vec::new(),
            tip_offset: Pose::IDENTITY,
        };
        let mut pending = Pose::IDENTITY;
        // Joints on the path: a mimic joint met before its master (climbing out of a
        // finger, say) still follows it.
        let on_path: std::collections::HashSet<usize> =
            climb.iter().chain(descend.iter()).copied().collect();
        let steps = climb
            .iter()
            .map(|&j| (j, true))
            .chain(descend.iter().map(|&j| (j, false)));
        for (j, climbing) in steps {
            let joint = &model.joints[j];
            if let JointKind::MultiAxis(kind) = joint.kind {
                return Err(RobotError::UnsupportedJoint {
                    base: base.to_string(),
                    tip: tip.to_string(),
                    joint: joint.name.clone(),
                    kind,
                });
            }
            if !climbing {
                pending *= joint.parent_from_joint;
            }
            if joint.kind.is_single_axis() {
                let master = joint.mimic.as_ref().map_or(j, |m| m.master);
                let (multiplier, offset) = joint
                    .mimic
                    .as_ref()
                    .map_or((1.0, 0.0), |m| (m.multiplier, m.offset));
                let var = match chain.joint_indices.iter().position(|&k| k == master) {
                    Some(v) => Some(v),
                    // A mimic joint whose master is outside the chain stays at its offset.
                    None if joint.mimic.is_some() && !on_path.contains(&master) => None,
                    None => {
                        let m = &model.joints[master];
                        chain.joint_names.push(m.name.clone());
                        chain.joint_indices.push(master);
                        chain.lower.push(m.limits.lower);
                        chain.upper.push(m.limits.upper);
                        chain.velocity.push(m.limits.velocity);
                        chain.var_prismatic.push(m.kind == JointKind::Prismatic);
                        Some(chain.joint_indices.len() - 1)
                    }
                };
                let sign = if climbing { -1.0 } else { 1.0 };
                match var {
                    Some(var) => {
                        chain.elements.push(Element {
                            pre: pending,
                            axis: joint.axis * sign,
                            prismatic: joint.kind == JointKind::Prismatic,
                            var,
                            multiplier,
                            offset,
                        });
                        pending = Pose::IDENTITY;
                    }
                    None => {
                        pending *= crate::model::joint_motion(joint.kind, joint.axis * sign, offset)
                    }
                }
            }
            if climbing {
                pending *= joint.parent_from_joint.inverse();
            }
        }
        chain.tip_offset = pending;
        Ok(chain)
    }

    /// Number of variables (degrees of freedom).
    pub fn dof(&self) -> usize {
        self.joint_names.len()
    }

    fn check_len(&self, q: &[f64]) -> Result<(), RobotError> {
        if q.len() == self.dof() {
            Ok(())
        } else {
            Err(RobotError::WrongJointCount {
                expected: self.dof(),
                got: q.len(),
            })
        }
    }

    #[inline]
    fn motion(e: &Element, q: &[f64]) -> Pose {
        let v = e.multiplier * q[e.var] + e.offset;
        if e.prismatic {
            Pose::from_translation(e.axis * v)
        } else {
            Pose::from_rotation(Quat::from_axis_angle(e.axis, v))
        }
    }

    /// Pose of the tip in the base frame (`base_from_tip`).
    pub fn fk(&self, q: &[f64]) -> Result<Pose, RobotError> {
        self.check_len(q)?;
        Ok(self.fk_unchecked(q))
    }

    /// [`Self::fk`] without the length check, for solvers that own `q`.
    pub fn fk_unchecked(&self, q: &[f64]) -> Pose {
        let mut t = Pose::IDENTITY;
        for e in &self.elements {
            t = t * e.pre * Self::motion(e, q);
        }
        t * self.tip_offset
    }

    /// Tip pose and the 6×dof geometric Jacobian in the base frame, written column by
    /// column into `columns` (`[vx, vy, vz, wx, wy, wz]` per variable).
    pub fn fk_and_jacobian(&self, q: &[f64], columns: &mut Vec<[f64; 6]>) -> Pose {
        columns.clear();
        columns.resize(self.dof(), [0.0; 6]);
        // Joint frames first, then the tip, then one pass for the columns.
        let mut frames: [(Vec3, Vec3, bool, usize, f64); 16] =
            [(Vec3::ZERO, Vec3::ZERO, false, 0, 0.0); 16];
        let mut heap = Vec::new();
        let mut t = Pose::IDENTITY;
        for (i, e) in self.elements.iter().enumerate() {
            t *= e.pre;
            let item = (
                t.translation,
                t.rotation * e.axis,
                e.prismatic,
                e.var,
                e.multiplier,
            );
            if i < 16 {
                frames[i] = item
            } else {
                heap.push(item)
            }
            t *= Self::motion(e, q);
        }
        let tip = t * self.tip_offset;
        let n = self.elements.len();
        for i in 0..n {
            let (origin, w, prismatic, var, mult) = if i < 16 { frames[i] } else { heap[i - 16] };
            let c = &mut columns[var];
            if prismatic {
                c[0] += mult * w.x;
                c[1] += mult * w.y;
                c[2] += mult * w.z;
            } else {
                let v = w.cross(tip.translation - origin);
                c[0] += mult * v.x;
                c[1] += mult * v.y;
                c[2] += mult * v.z;
                c[3] += mult * w.x;
                c[4] += mult * w.y;
                c[5] += mult * w.z;
            }
        }
        tip
    }

    /// The 6×dof geometric Jacobian (rows vx vy vz wx wy wz) as a nalgebra matrix.
    pub fn jacobian(&self, q: &[f64]) -> Result<nalgebra::DMatrix<f64>, RobotError> {
        self.check_len(q)?;
        let mut cols = Vec::new();
        self.fk_and_jacobian(q, &mut cols);
        Ok(nalgebra::DMatrix::from_fn(6, self.dof(), |r, c| cols[c][r]))
    }

    /// True when every variable is within its limits (plus `tolerance`).
    pub fn within_limits(&self, q: &[f64], tolerance: f64) -> bool {
        q.len() == self.dof()
            && q.iter()
                .zip(self.lower.iter().zip(&self.upper))
                .all(|(v, (lo, hi))| v.is_finite() && *v >= lo - tolerance && *v <= hi + tolerance)
    }

    /// Clamps `q` into the limits in place.
    pub fn clamp(&self, q: &mut [f64]) {
        for (v, (lo, hi)) in q.iter_mut().zip(self.lower.iter().zip(&self.upper)) {
            *v = v.clamp(*lo, *hi);
        }
    }

    /// Range used to sample variable `i`: its limits, or (-π, π] for continuous joints.
    pub fn sample_range(&self, i: usize) -> (f64, f64) {
        let (lo, hi) = (self.lower[i], self.upper[i]);
        if lo.is_finite() && hi.is_finite() {
            (lo, hi)
        } else {
            (-std::f64::consts::PI, std::f64::consts::PI)
        }
    }

    /// A uniformly random configuration within the limits.
    pub fn random_configuration(&self, rng: &mut impl Rng) -> Vec<f64> {
        (0..self.dof())
            .map(|i| {
                let (lo, hi) = self.sample_range(i);
                if hi > lo {
                    rng.random_range(lo..=hi)
                } else {
                    lo
                }
            })
            .collect()
    }

    /// The middle of every range (0 for continuous joints): the usual neutral seed.
    pub fn mid_configuration(&self) -> Vec<f64> {
        (0..self.dof())
            .map(|i| {
                let (lo, hi) = self.sample_range(i);
                0.5 * (lo + hi)
            })
            .collect()
    }

    /// Where the first joint sits in the base frame: every tip position is within
    /// [`Self::reach_bound`] of it.
    pub fn reach_center(&self) -> Vec3 {
        self.elements
            .first()
            .map_or(self.tip_offset.translation, |e| e.pre.translation)
    }

    /// An upper bound on the distance from [`Self::reach_center`] to the tip over all
    /// configurations: the sum of every later fixed offset plus the prismatic travel.
    /// Rotations preserve lengths, so no configuration can reach farther.
    pub fn reach_bound(&self) -> f64 {
        let mut bound = self.tip_offset.translation.length();
        for (i, e) in self.elements.iter().enumerate() {
            if i > 0 {
                bound += e.pre.translation.length();
            }
            if e.prismatic {
                let (lo, hi) = (self.lower[e.var], self.upper[e.var]);
                bound += e.multiplier.abs() * lo.abs().max(hi.abs()) + e.offset.abs();
            }
        }
        bound
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::robots;
    use rand::SeedableRng;

    /// Every Jacobian column matches central finite differences of FK, linear and angular.
    #[test]
    fn jacobian_matches_finite_differences() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(1);
        for (name, base, tip) in [
            ("wam", "base_link", "wam_tool"),
            ("pr2", "base_link", "l_gripper_tool_frame"),
        ] {
            let robot = robots::load(name).unwrap();
            let chain = Chain::new(&robot.model, base, tip).unwrap();
            for _ in 0..20 {
                let q = chain.random_configuration(&mut rng);
                let jac = chain.jacobian(&q).unwrap();
                for i in 0..chain.dof() {
                    let h = 1e-6;
                    let (mut qp, mut qm) = (q.clone(), q.clone());
                    qp[i] += h;
                    qm[i] -= h;
                    let (tp, tm) = (chain.fk(&qp).unwrap(), chain.fk(&qm).unwrap());
                    let v = (tp.translation - tm.translation) / (2.0 * h);
                    let w = tabula_geom::rotation_vector(tp.rotation * tm.rotation.inverse())
                        / (2.0 * h);
                    for r in 0..3 {
                        assert!((jac[(r, i)] - v[r]).abs() < 1e-6, "{name} v col {i}");
                        assert!((jac[(r + 3, i)] - w[r]).abs() < 1e-6, "{name} w col {i}");
                    }
                }
            }
        }
    }

    #[test]
    fn reach_bound_is_never_exceeded() {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(2);
        for name in ["golem3", "wam", "pr2"] {
            let robot = robots::load(name).unwrap();
            let chain = Chain::new(&robot.model, &robot.default_base, &robot.default_tip).unwrap();
            for _ in 0..2000 {
                let t = chain.fk(&chain.random_configuration(&mut rng)).unwrap();
                assert!(
                    (t.translation - chain.reach_center()).length() <= chain.reach_bound() + 1e-12
                );
            }
        }
    }
}
