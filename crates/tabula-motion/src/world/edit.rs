//! Setting a world up from outside descriptions (a planning scene): joint values by
//! name, frames of links, and the configuration the chain is in.

use super::{CollisionWorld, WorldError};
use tabula_geom::Pose;
use tabula_robot::model::JointKind;

/// How far outside a joint limit (rad or m) a given value is taken as on the limit:
/// problem files round (MotionBenchMaker's Fetch goals sit 3e-6 rad beyond ±3.14159).
pub const BOUNDS_TOLERANCE: f64 = 1e-4;

/// Joint values [`CollisionWorld::set_joint_values`] did not use.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct IgnoredJoints {
    pub fixed: Vec<String>,
    pub unknown: Vec<String>,
}

impl IgnoredJoints {
    /// Notes naming them (none when nothing was ignored); `what` names the message.
    pub fn notes(&self, what: &str) -> Vec<String> {
        let mut notes = Vec::new();
        if !self.fixed.is_empty() {
            notes.push(format!(
                "{what} gives values for fixed joints ({}): ignored",
                self.fixed.join(", ")
            ));
        }
        if !self.unknown.is_empty() {
            notes.push(format!(
                "{what} names joints the robot lacks ({}): ignored",
                self.unknown.join(", ")
            ));
        }
        notes
    }
}

impl CollisionWorld {
    /// Sets joints by name (the chain's too: [`Self::chain_values`] reads them back).
    /// Values of fixed joints, and of joints the robot lacks (a state recorded on a fuller
    /// model of it: Fetch's wheels in MotionBenchMaker), are not used; both are
    /// returned by name for the caller to report.
    pub fn set_joint_values(
        &mut self,
        joints: &[(String, f64)],
    ) -> Result<IgnoredJoints, WorldError> {
        let mut ignored = IgnoredJoints::default();
        let mut values = self.values.clone();
        for (name, v) in joints {
            let Some(j) = self.model.joints.iter().position(|j| &j.name == name) else {
                if !ignored.unknown.contains(name) {
                    ignored.unknown.push(name.clone());
                }
                continue;
            };
            if !v.is_finite() {
                return Err(WorldError::NonFinite);
            }
            if self.model.joints[j].kind == JointKind::Fixed {
                if !ignored.fixed.contains(name) {
                    ignored.fixed.push(name.clone());
                }
                continue;
            }
            values[j] = *v;
        }
        if values != self.values {
            self.values = values;
            self.compute_anchors()?;
        }
        Ok(ignored)
    }

    /// Brings a configuration from outside into the chain's limits where that changes
    /// no link pose, or none measurably: values of joints that turn all the way round
    /// (continuous, or revolute with a range of a full turn, as Fetch's rolls are in
    /// VAMP's URDF) are wrapped by whole turns, and values within `BOUNDS_TOLERANCE` of
    /// a limit are put on it (MoveIt's start-state bounds fixing does the same, with a
    /// wider margin). Returns whether anything changed.
    pub fn bring_within_limits(&self, q: &mut [f64]) -> bool {
        let tau = std::f64::consts::TAU;
        let mut changed = false;
        for (i, v) in q.iter_mut().enumerate() {
            let (lo, hi) = (self.chain.lower[i], self.chain.upper[i]);
            if !v.is_finite() || (*v >= lo && *v <= hi) {
                continue;
            }
            let before = *v;
            if hi - lo >= tau - 1e-4 {
                *v = lo + (*v - lo).rem_euclid(tau);
            }
            if *v < lo && lo - *v <= BOUNDS_TOLERANCE {
                *v = lo;
            } else if *v > hi && *v - hi <= BOUNDS_TOLERANCE {
                *v = hi;
            }
            changed |= *v != before;
        }
        changed
    }

    /// The chain's joints at the world's joint values.
    pub fn chain_values(&self) -> Vec<f64> {
        self.chain
            .joint_indices
            .iter()
            .map(|&j| self.values[j])
            .collect()
    }

    /// `world_from_link` at the world's joint values.
    pub fn world_from_link(&self, link: &str) -> Result<Pose, WorldError> {
        let poses = self.model.forward_kinematics(&self.values)?;
        Ok(self.world_from_root * poses[self.model.link(link)?])
    }

    /// `tip_from_link` when `link` is rigidly fixed to the chain's tip (the tip itself,
    /// or joined to it by fixed joints only, below or above it).
    pub fn tip_from_link(&self, link: &str) -> Option<Pose> {
        let l = self.model.link(link).ok()?;
        let tip = self.model.link(&self.chain.tip_link).ok()?;
        let fixed_path = |from: usize, to: usize| {
            let mut at = from;
            while at != to {
                let Some(j) = self.model.links[at].parent_joint else {
                    return false;
                };
                if self.model.joints[j].kind != JointKind::Fixed {
                    return false;
                }
                at = self.model.joints[j].parent;
            }
            true
        };
        if !(fixed_path(l, tip) || fixed_path(tip, l)) {
            return None;
        }
        let poses = self.model.forward_kinematics(&self.values).ok()?;
        Some(poses[tip].inverse() * poses[l])
    }

    /// Whether the robot has a fixed joint of this name.
    pub fn joint_is_fixed(&self, name: &str) -> bool {
        self.model
            .joints
            .iter()
            .any(|j| j.name == name && j.kind == JointKind::Fixed)
    }
}
