//! Setting a world up from outside descriptions (a planning scene): joint values by
//! name, frames of links, and the configuration the chain is in.

use super::{CollisionWorld, WorldError};
use tabula_geom::Pose;
use tabula_robot::model::JointKind;

impl CollisionWorld {
    /// Sets joints by name (the chain's too: [`Self::chain_values`] reads them back).
    /// Values of fixed joints are ignored; their names are returned. A name the robot
    /// lacks is an error.
    pub fn set_joint_values(
        &mut self,
        joints: &[(String, f64)],
    ) -> Result<Vec<String>, WorldError> {
        let mut ignored = Vec::new();
        let mut values = self.values.clone();
        for (name, v) in joints {
            let j = self
                .model
                .joints
                .iter()
                .position(|j| &j.name == name)
                .ok_or_else(|| WorldError::Robot(format!("the robot has no joint `{name}`")))?;
            if !v.is_finite() {
                return Err(WorldError::NonFinite);
            }
            if self.model.joints[j].kind == JointKind::Fixed {
                if !ignored.contains(name) {
                    ignored.push(name.clone());
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
