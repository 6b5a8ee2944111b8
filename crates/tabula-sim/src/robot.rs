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

    /// Follows a joint trajectory: `waypoints[k][i]` is joint `joints[i]` at waypoint k,
    /// each segment at the velocity limits. Returns the physics steps taken.
    pub fn follow_trajectory(
        &mut self,
        robot: &str,
        joints: &[&str],
        waypoints: &[Vec<f64>],
    ) -> Result<usize, SimError> {
        let mut steps = 0;
        for (k, w) in waypoints.iter().enumerate() {
            if w.len() != joints.len() {
                return Err(SimError::Robot(format!(
                    "waypoint {k} has {} values for {} joints",
                    w.len(),
                    joints.len()
                )));
            }
            let targets: Vec<(&str, f64)> = joints.iter().copied().zip(w.iter().copied()).collect();
            steps += self.move_joints(robot, &targets)?;
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
        self.first_contact(body, *body.position(), EntityKind::Object, 1e-4)
    }

    /// The first entity of `kind` that `body` placed at `world_from_body` comes within
    /// `max_distance` of (negative: penetrates by more than that).
    fn first_contact(
        &self,
        body: &RigidBody,
        world_from_body: Pose,
        kind: EntityKind,
        max_distance: f64,
    ) -> Option<String> {
        for &ch in body.colliders() {
            let c = &self.physics.colliders[ch];
            let pose = world_from_body * *c.position_wrt_parent().unwrap_or(&Pose::IDENTITY);
            for other in self.entities.iter().filter(|o| o.kind == kind) {
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
                    if contact.is_some_and(|k| k.dist <= max_distance) {
                        return Some(other.name.clone());
                    }
                }
            }
        }
        None
    }
}

impl SimWorld {
    /// The entity a robot link penetrates by more than a millimetre among fixed furniture
    /// and walls (not the floor).
    fn robot_blocked(&self, robot: &str) -> Option<String> {
        let prefix = format!("{robot}/");
        self.entities
            .iter()
            .filter(|e| e.kind == EntityKind::RobotLink && e.name.starts_with(&prefix))
            .find_map(|link| {
                let body = &self.physics.bodies[link.body];
                self.first_contact(body, *body.next_position(), EntityKind::Furniture, -1e-3)
            })
    }

    /// Drives a planar mobile base to (x, y, θ) in the world the way seed 000 did
    /// (SPEC §1.4): turn towards the goal, drive straight, turn to the final heading,
    /// at the joints' velocity limits. The base collides with furniture: it stops at the
    /// first contact and reports what it hit. Joint names are the PR2 model's.
    pub fn drive_base(&mut self, robot: &str, x: f64, y: f64, theta: f64) -> Result<(), SimError> {
        if !(x.is_finite() && y.is_finite() && theta.is_finite()) {
            return Err(SimError::NonFinite);
        }
        let (jx, jy, jt) = ("base_x_joint", "base_y_joint", "base_theta_joint");
        let (x0, y0, t0) = (
            self.joint(robot, jx)?,
            self.joint(robot, jy)?,
            self.joint(robot, jt)?,
        );
        let (dx, dy) = (x - x0, y - y0);
        let distance = dx.hypot(dy);
        let mut legs: Vec<Vec<(&str, f64)>> = Vec::new();
        let mut heading = t0;
        if distance > 1e-4 {
            let face = t0 + tabula_geom::wrap_angle(dy.atan2(dx) - t0);
            legs.push(vec![(jt, face)]);
            legs.push(vec![(jx, x), (jy, y)]);
            heading = face;
        }
        legs.push(vec![(
            jt,
            heading + tabula_geom::wrap_angle(theta - heading),
        )]);
        for leg in legs {
            self.move_joints_guarded(robot, &leg)?;
        }
        Ok(())
    }

    /// [`Self::move_joints`] that stops before a link would enter furniture.
    fn move_joints_guarded(
        &mut self,
        robot: &str,
        targets: &[(&str, f64)],
    ) -> Result<(), SimError> {
        let ri = self
            .robots
            .iter()
            .position(|r| r.0 == robot)
            .ok_or_else(|| SimError::UnknownEntity(robot.into()))?;
        let dt = self.physics.integration_parameters.dt;
        let mut plan = Vec::new();
        let mut longest: f64 = 0.0;
        for &(joint, target) in targets {
            let start = self.joint(robot, joint)?;
            let model = &self.robots[ri].1;
            let j = model
                .joint(joint)
                .ok_or_else(|| SimError::Robot(format!("no joint `{joint}`")))?;
            let v = model.joints[j].limits.velocity;
            longest = longest.max((target - start).abs() / if v.is_finite() { v } else { 1.0 });
            plan.push((joint, start, target));
        }
        let steps = ((longest / dt).ceil() as usize).max(1);
        for k in 1..=steps {
            let s = k as f64 / steps as f64;
            let now: Vec<(&str, f64)> =
                plan.iter().map(|&(j, a, b)| (j, a + (b - a) * s)).collect();
            let before: Vec<(&str, f64)> = plan
                .iter()
                .map(|&(j, a, b)| (j, a + (b - a) * (k - 1) as f64 / steps as f64))
                .collect();
            self.write_joints(ri, &now)?;
            self.place_robot(ri, true)?;
            if let Some(hit) = self.robot_blocked(robot) {
                self.write_joints(ri, &before)?;
                self.place_robot(ri, false)?;
                return Err(SimError::Blocked {
                    robot: robot.into(),
                    by: hit,
                });
            }
            self.physics.step();
        }
        Ok(())
    }

    /// Points a pan/tilt head so that `camera_link`'s optical axis (z) goes through
    /// `point` (world): Gauss–Newton on the image-plane offset of the point, within the
    /// joints' limits. Returns the remaining angle between axis and point (rad).
    pub fn look_at(
        &mut self,
        robot: &str,
        pan: &str,
        tilt: &str,
        camera_link: &str,
        point: tabula_geom::Vec3,
    ) -> Result<f64, SimError> {
        if !point.is_finite() {
            return Err(SimError::NonFinite);
        }
        let ri = self
            .robots
            .iter()
            .position(|r| r.0 == robot)
            .ok_or_else(|| SimError::UnknownEntity(robot.into()))?;
        let offset = |w: &SimWorld| -> Result<(f64, f64, f64), SimError> {
            let cam = w.link_pose(robot, camera_link)?;
            let p = cam.inverse_transform_point(point);
            let angle = p.angle_between(tabula_geom::Vec3::Z);
            Ok((p.x.atan2(p.z), p.y.atan2(p.z), angle))
        };
        for _ in 0..20 {
            let (ex, ey, angle) = offset(self)?;
            if angle < 1e-6 {
                break;
            }
            let q = [self.joint(robot, pan)?, self.joint(robot, tilt)?];
            let mut jac = [[0.0; 2]; 2];
            for (k, name) in [pan, tilt].iter().enumerate() {
                let h = 1e-6;
                self.write_joints(ri, &[(name, q[k] + h)])?;
                let (fx, fy, _) = offset(self)?;
                self.write_joints(ri, &[(name, q[k])])?;
                jac[0][k] = (fx - ex) / h;
                jac[1][k] = (fy - ey) / h;
            }
            let det = jac[0][0] * jac[1][1] - jac[0][1] * jac[1][0];
            if det.abs() < 1e-12 {
                break;
            }
            let d0 = -(jac[1][1] * ex - jac[0][1] * ey) / det;
            let d1 = -(-jac[1][0] * ex + jac[0][0] * ey) / det;
            self.write_joints(ri, &[(pan, q[0] + d0), (tilt, q[1] + d1)])?;
        }
        self.place_robot(ri, false)?;
        Ok(offset(self)?.2)
    }
}
