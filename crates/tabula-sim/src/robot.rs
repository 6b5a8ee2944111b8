//! Robots in the simulator: joint motion under velocity limits, links as kinematic
//! bodies that push objects, and a parallel gripper that holds what it closes on — the
//! role of the seeds' Gazebo grasp plugin.

use crate::world::{EntityKind, SimError, SimWorld};
use rapier3d_f64::prelude::*;
use tabula_geom::Pose;

/// An object held by a gripper: it rides with `link` at `link_from_object`.
#[derive(Debug, Clone)]
pub struct Attachment {
    pub robot: String,
    pub object: String,
    pub link: String,
    pub link_from_object: Pose,
}

impl SimWorld {
    fn robot_index(&self, robot: &str) -> Result<usize, SimError> {
        self.robots
            .iter()
            .position(|r| r.0 == robot)
            .ok_or_else(|| SimError::UnknownEntity(robot.into()))
    }

    /// Current value of a robot joint.
    pub fn joint(&self, robot: &str, joint: &str) -> Result<f64, SimError> {
        let r = &self.robots[self.robot_index(robot)?];
        let j = r
            .1
            .joint(joint)
            .ok_or_else(|| SimError::Robot(format!("robot `{robot}` has no joint `{joint}`")))?;
        Ok(r.1.joint_value(&r.3, j))
    }

    /// Places the robot's links for the given joint values at once (clamped to the
    /// limits); with `kinematic_step` the links are driven there through the next physics
    /// step, so they push what they meet, instead of teleporting.
    fn place_robot(&mut self, ri: usize, kinematic_step: bool) -> Result<(), SimError> {
        let (name, model, world_from_root, values) = &self.robots[ri];
        let root_from_link = model
            .forward_kinematics(values)
            .map_err(|e| SimError::Robot(e.to_string()))?;
        let mut link_poses = Vec::new();
        for (li, link) in model.links.iter().enumerate() {
            link_poses.push((
                format!("{name}/{}", link.name),
                *world_from_root * root_from_link[li],
            ));
        }
        for (entity, pose) in &link_poses {
            if let Some(i) = self.entity(entity) {
                let b = &mut self.physics.bodies[self.entities[i].body];
                if kinematic_step {
                    b.set_next_kinematic_position(*pose);
                } else {
                    b.set_position(*pose, true);
                }
            }
        }
        for a in self.attachments.clone() {
            if let Some((_, world_from_link)) = link_poses
                .iter()
                .find(|(n, _)| *n == format!("{}/{}", a.robot, a.link))
                && let Some(i) = self.entity(&a.object)
            {
                let pose = *world_from_link * a.link_from_object;
                let b = &mut self.physics.bodies[self.entities[i].body];
                if kinematic_step {
                    b.set_next_kinematic_position(pose);
                } else {
                    b.set_position(pose, true);
                }
            }
        }
        Ok(())
    }

    /// Sets joints at once (no physics in between): for initial states and tests.
    pub fn set_joints(&mut self, robot: &str, targets: &[(&str, f64)]) -> Result<(), SimError> {
        let ri = self.robot_index(robot)?;
        self.write_joints(ri, targets)?;
        self.place_robot(ri, false)
    }

    fn write_joints(&mut self, ri: usize, targets: &[(&str, f64)]) -> Result<(), SimError> {
        for &(joint, value) in targets {
            let model = &self.robots[ri].1;
            let j = model.joint(joint).ok_or_else(|| {
                SimError::Robot(format!(
                    "robot `{}` has no joint `{joint}`",
                    self.robots[ri].0
                ))
            })?;
            if !value.is_finite() {
                return Err(SimError::NonFinite);
            }
            let l = model.joints[j].limits;
            self.robots[ri].3[j] = value.clamp(l.lower, l.upper);
        }
        Ok(())
    }

    /// Moves joints to `targets` under their velocity limits, stepping the physics: the
    /// position-controlled joint trajectory of a real arm. Returns the steps taken.
    pub fn move_joints(&mut self, robot: &str, targets: &[(&str, f64)]) -> Result<usize, SimError> {
        let ri = self.robot_index(robot)?;
        let dt = self.physics.integration_parameters.dt;
        let mut starts = Vec::new();
        let mut longest: f64 = 0.0;
        for &(joint, target) in targets {
            let model = &self.robots[ri].1;
            let j = model.joint(joint).ok_or_else(|| {
                SimError::Robot(format!("robot `{robot}` has no joint `{joint}`"))
            })?;
            if !target.is_finite() {
                return Err(SimError::NonFinite);
            }
            let l = model.joints[j].limits;
            let target = target.clamp(l.lower, l.upper);
            let start = self.robots[ri].3[j];
            let speed = if l.velocity.is_finite() {
                l.velocity
            } else {
                1.0
            };
            longest = longest.max((target - start).abs() / speed);
            starts.push((joint, start, target));
        }
        // All joints arrive together, the slowest at its limit.
        let steps = ((longest / dt).ceil() as usize).max(1);
        for k in 1..=steps {
            let s = k as f64 / steps as f64;
            let now: Vec<(&str, f64)> = starts
                .iter()
                .map(|&(j, a, b)| (j, a + (b - a) * s))
                .collect();
            self.write_joints(ri, &now)?;
            self.place_robot(ri, true)?;
            self.physics.step();
        }
        Ok(steps)
    }

    /// Closes a parallel gripper (its finger joint closes towards its lower limit); if
    /// both fingers touch the same object it is held until [`Self::open_gripper`].
    /// Returns the held object.
    pub fn close_gripper(
        &mut self,
        robot: &str,
        finger_joint: &str,
        fingers: [&str; 2],
        palm: &str,
    ) -> Result<Option<String>, SimError> {
        let ri = self.robot_index(robot)?;
        let model = &self.robots[ri].1;
        let j = model.joint(finger_joint).ok_or_else(|| {
            SimError::Robot(format!("robot `{robot}` has no joint `{finger_joint}`"))
        })?;
        let (lower, start) = (model.joints[j].limits.lower, self.robots[ri].3[j]);
        let steps = 40;
        for k in 1..=steps {
            let q = start + (lower - start) * k as f64 / steps as f64;
            self.write_joints(ri, &[(finger_joint, q)])?;
            self.place_robot(ri, false)?;
            let touched: Vec<Option<String>> = fingers
                .iter()
                .map(|f| self.touching_object(&format!("{robot}/{f}")))
                .collect();
            if let [Some(a), Some(b)] = &touched[..]
                && a == b
            {
                let object = a.clone();
                let world_from_palm = self.pose(&format!("{robot}/{palm}"))?;
                let world_from_object = self.pose(&object)?;
                let oi = self
                    .entity(&object)
                    .ok_or_else(|| SimError::UnknownEntity(object.clone()))?;
                let b = &mut self.physics.bodies[self.entities[oi].body];
                b.set_body_type(RigidBodyType::KinematicPositionBased, true);
                self.attachments.push(Attachment {
                    robot: robot.into(),
                    object: object.clone(),
                    link: palm.into(),
                    link_from_object: world_from_palm.inverse() * world_from_object,
                });
                return Ok(Some(object));
            }
        }
        Ok(None)
    }

    /// Opens the gripper: held objects are released to the physics.
    pub fn open_gripper(&mut self, robot: &str, finger_joint: &str) -> Result<(), SimError> {
        let ri = self.robot_index(robot)?;
        let upper = {
            let model = &self.robots[ri].1;
            let j = model.joint(finger_joint).ok_or_else(|| {
                SimError::Robot(format!("robot `{robot}` has no joint `{finger_joint}`"))
            })?;
            model.joints[j].limits.upper
        };
        let released: Vec<Attachment> = self
            .attachments
            .iter()
            .filter(|a| a.robot == robot)
            .cloned()
            .collect();
        self.attachments.retain(|a| a.robot != robot);
        for a in released {
            if let Some(i) = self.entity(&a.object) {
                let b = &mut self.physics.bodies[self.entities[i].body];
                b.set_body_type(RigidBodyType::Dynamic, true);
            }
        }
        self.write_joints(ri, &[(finger_joint, upper)])?;
        self.place_robot(ri, false)
    }

    /// An object in contact with (or penetrating) the entity's shapes.
    fn touching_object(&self, entity: &str) -> Option<String> {
        let e = self.entity(entity)?;
        let body = &self.physics.bodies[self.entities[e].body];
        let world_from_body = *body.position();
        for &ch in body.colliders() {
            let c = &self.physics.colliders[ch];
            let pose = world_from_body * *c.position_wrt_parent().unwrap_or(&Pose::IDENTITY);
            for other in self
                .entities
                .iter()
                .filter(|o| o.kind == EntityKind::Object)
            {
                let ob = &self.physics.bodies[other.body];
                for &oc in ob.colliders() {
                    let occ = &self.physics.colliders[oc];
                    let opose =
                        *ob.position() * *occ.position_wrt_parent().unwrap_or(&Pose::IDENTITY);
                    let contact = rapier3d_f64::parry::query::contact(
                        &pose,
                        c.shape(),
                        &opose,
                        occ.shape(),
                        0.0,
                    )
                    .ok()
                    .flatten();
                    if contact.is_some_and(|k| k.dist <= 1e-4) {
                        return Some(other.name.clone());
                    }
                }
            }
        }
        None
    }
}
