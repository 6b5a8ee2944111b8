//! Robots in the simulator: joints that follow timed trajectories, links as kinematic
//! bodies that push objects, a parallel gripper that holds what it closes on (the role
//! of the seeds' Gazebo grasp plugin), a base that drives in the world frame and a head
//! that turns under its limits.

use super::{EntityKind, SimError, SimWorld};
use rapier3d_f64::prelude::*;
use tabula_geom::{Pose, Vec3};
use tabula_robot::RobotDescription;
use tabula_robot::driver::JointTrajectory;

/// An object held by a gripper: it rides with `link` at `link_from_object`.
#[derive(Debug, Clone)]
pub struct Attachment {
    pub robot: String,
    pub object: String,
    pub link: String,
    pub link_from_object: Pose,
}

/// A robot in the world.
#[derive(Debug, Clone)]
pub struct PlacedRobot {
    pub name: String,
    pub model: tabula_robot::RobotModel,
    pub description: RobotDescription,
    /// The robot's SRDF, when it has one (planners use its collision matrix).
    pub srdf: Option<tabula_robot::srdf::Srdf>,
    pub world_from_root: Pose,
    /// Every joint's value, model order.
    pub values: Vec<f64>,
}

impl SimWorld {
    pub(crate) fn robot_index(&self, robot: &str) -> Result<usize, SimError> {
        self.robots
            .iter()
            .position(|r| r.name == robot)
            .ok_or_else(|| SimError::UnknownEntity(robot.into()))
    }

    /// The robot called `name`.
    pub fn robot(&self, name: &str) -> Result<&PlacedRobot, SimError> {
        Ok(&self.robots[self.robot_index(name)?])
    }

    fn joint_index(&self, ri: usize, joint: &str) -> Result<usize, SimError> {
        let r = &self.robots[ri];
        r.model
            .joint(joint)
            .ok_or_else(|| SimError::Robot(format!("robot `{}` has no joint `{joint}`", r.name)))
    }

    /// Current value of a robot joint.
    pub fn joint(&self, robot: &str, joint: &str) -> Result<f64, SimError> {
        let ri = self.robot_index(robot)?;
        let j = self.joint_index(ri, joint)?;
        let r = &self.robots[ri];
        Ok(r.model.joint_value(&r.values, j))
    }

    /// Places the robot's links for its joint values at once; with `kinematic_step`
    /// the links are driven there through the next physics step, so they push what
    /// they meet, instead of teleporting.
    fn place_robot(&mut self, ri: usize, kinematic_step: bool) -> Result<(), SimError> {
        let r = &self.robots[ri];
        let root_from_link = r
            .model
            .forward_kinematics(&r.values)
            .map_err(|e| SimError::Robot(e.to_string()))?;
        let link_poses: Vec<(String, Pose)> = r
            .model
            .links
            .iter()
            .enumerate()
            .map(|(li, link)| {
                (
                    format!("{}/{}", r.name, link.name),
                    r.world_from_root * root_from_link[li],
                )
            })
            .collect();
        let robot_name = r.name.clone();
        let set = |w: &mut SimWorld, entity: &str, pose: Pose| {
            if let Some(i) = w.entity(entity) {
                let b = &mut w.physics.bodies[w.entities[i].body];
                if kinematic_step {
                    b.set_next_kinematic_position(pose);
                } else {
                    b.set_position(pose, true);
                }
            }
        };
        for (entity, pose) in &link_poses {
            set(self, entity, *pose);
        }
        for a in self.attachments.clone() {
            let link = format!("{}/{}", a.robot, a.link);
            if a.robot == robot_name
                && let Some((_, world_from_link)) = link_poses.iter().find(|(n, _)| *n == link)
            {
                set(self, &a.object, *world_from_link * a.link_from_object);
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

    /// Writes joint values (clamped to the limits) without placing the links.
    fn write_joints(&mut self, ri: usize, targets: &[(&str, f64)]) -> Result<(), SimError> {
        for &(joint, value) in targets {
            let j = self.joint_index(ri, joint)?;
            if !value.is_finite() {
                return Err(SimError::NonFinite);
            }
            let l = self.robots[ri].model.joints[j].limits;
            self.robots[ri].values[j] = value.clamp(l.lower, l.upper);
        }
        Ok(())
    }

    /// A straight joint-space motion to `targets` with all joints arriving together,
    /// the slowest at its velocity limit.
    fn straight_motion(
        &self,
        ri: usize,
        targets: &[(&str, f64)],
    ) -> Result<JointTrajectory, SimError> {
        let mut names = Vec::new();
        let (mut start, mut goal) = (Vec::new(), Vec::new());
        let mut longest: f64 = 0.0;
        for &(joint, target) in targets {
            let j = self.joint_index(ri, joint)?;
            if !target.is_finite() {
                return Err(SimError::NonFinite);
            }
            let l = self.robots[ri].model.joints[j].limits;
            let (a, b) = (self.robots[ri].values[j], target.clamp(l.lower, l.upper));
            let speed = if l.velocity.is_finite() && l.velocity > 0.0 {
                l.velocity
            } else {
                1.0
            };
            longest = longest.max((b - a).abs() / speed);
            names.push(joint.to_string());
            start.push(a);
            goal.push(b);
        }
        Ok(JointTrajectory {
            joint_names: names,
            times: vec![0.0, longest],
            positions: vec![start, goal],
        })
    }

    /// Moves joints to `targets` under their velocity limits, stepping the physics: the
    /// position-controlled joint motion of a real arm. Returns the steps taken.
    pub fn move_joints(&mut self, robot: &str, targets: &[(&str, f64)]) -> Result<usize, SimError> {
        let ri = self.robot_index(robot)?;
        let motion = self.straight_motion(ri, targets)?;
        self.run_trajectory(ri, &motion, false)
    }

    /// Follows a timed joint trajectory (a planner's output, with its own timing): at
    /// every physics step the joints take the trajectory's value at that time, and the
    /// links push what they meet. Returns the physics steps taken.
    pub fn follow_trajectory(
        &mut self,
        robot: &str,
        trajectory: &JointTrajectory,
    ) -> Result<usize, SimError> {
        let ri = self.robot_index(robot)?;
        trajectory
            .validate()
            .map_err(|e| SimError::Robot(e.to_string()))?;
        self.run_trajectory(ri, trajectory, false)
    }

    /// Plays a trajectory step by step; `guarded` stops (and steps back) before a link
    /// would enter furniture.
    fn run_trajectory(
        &mut self,
        ri: usize,
        trajectory: &JointTrajectory,
        guarded: bool,
    ) -> Result<usize, SimError> {
        for name in &trajectory.joint_names {
            self.joint_index(ri, name)?;
        }
        if trajectory.positions.is_empty() {
            return Ok(0);
        }
        let dt = self.physics.integration_parameters.dt;
        let duration = trajectory.duration();
        if !duration.is_finite() || duration / dt > 1e7 {
            return Err(SimError::Robot(format!(
                "trajectory of {duration} s is too long to simulate"
            )));
        }
        let steps = ((duration / dt).ceil() as usize).max(1);
        let names: Vec<&str> = trajectory.joint_names.iter().map(String::as_str).collect();
        let at = |t: f64| -> Vec<(&str, f64)> {
            let q = trajectory.sample(t).unwrap_or_default();
            names.iter().copied().zip(q).collect()
        };
        for k in 1..=steps {
            let t = (k as f64 * dt).min(duration);
            self.write_joints(ri, &at(t))?;
            // Without physics nothing would carry a kinematic target to the links.
            self.place_robot(ri, !self.kinematic_only)?;
            if guarded && let Some((link, hit)) = self.robot_blocked(ri) {
                let before = ((k - 1) as f64 * dt).min(duration);
                self.write_joints(ri, &at(before))?;
                self.place_robot(ri, false)?;
                return Err(SimError::Blocked {
                    robot: self.robots[ri].name.clone(),
                    by: hit,
                    link,
                });
            }
            self.step();
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
        self.close_gripper_with_effort(robot, finger_joint, fingers, palm, None)
    }

    /// [`Self::close_gripper`] squeezing with at most `effort` (N per finger, capped at
    /// the finger joint's URDF effort limit): the fingers stop on the object either way,
    /// but it is held only if friction can carry it, 2·μ·F ≥ m·g (μ: the object's and
    /// the fingers' friction averaged, as the physics combines them). `None` holds
    /// whatever both fingers touch, as the seeds' Gazebo grasp plugin did.
    pub fn close_gripper_with_effort(
        &mut self,
        robot: &str,
        finger_joint: &str,
        fingers: [&str; 2],
        palm: &str,
        effort: Option<f64>,
    ) -> Result<Option<String>, SimError> {
        let physical = !self.kinematic_only;
        self.close_fingers(robot, finger_joint, fingers, palm, effort, physical)
    }

    /// [`Self::close_gripper_with_effort`], the fingers closing `through_physics` (the
    /// first to touch pushes the object towards the other, as a real gripper centres
    /// what it closes on) or placed at once, as for a scene's initial grip.
    pub(super) fn close_fingers(
        &mut self,
        robot: &str,
        finger_joint: &str,
        fingers: [&str; 2],
        palm: &str,
        effort: Option<f64>,
        through_physics: bool,
    ) -> Result<Option<String>, SimError> {
        if effort.is_some_and(|e| !(e.is_finite() && e >= 0.0)) {
            return Err(SimError::NonFinite);
        }
        let ri = self.robot_index(robot)?;
        let j = self.joint_index(ri, finger_joint)?;
        let (lower, start) = (
            self.robots[ri].model.joints[j].limits.lower,
            self.robots[ri].values[j],
        );
        let steps = 40;
        for k in 1..=steps {
            let q = start + (lower - start) * k as f64 / steps as f64;
            self.write_joints(ri, &[(finger_joint, q)])?;
            self.place_robot(ri, through_physics)?;
            if through_physics {
                self.step();
            }
            let touched: Vec<Option<String>> = fingers
                .iter()
                .map(|f| self.touching_object(&format!("{robot}/{f}")))
                .collect();
            if let [Some(a), Some(b)] = &touched[..]
                && a == b
            {
                let object = a.clone();
                if let Some(effort) = effort
                    && !self.friction_carries(
                        ri,
                        j,
                        &format!("{robot}/{}", fingers[0]),
                        &object,
                        effort,
                    )
                {
                    // Squeezed, not carried: the fingers rest on it.
                    return Ok(None);
                }
                let world_from_palm = self.link_pose(robot, palm)?;
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

    /// Whether two fingers squeezing with `effort` (capped at joint `j`'s limit) carry
    /// `object` by friction.
    fn friction_carries(
        &self,
        ri: usize,
        j: usize,
        finger: &str,
        object: &str,
        effort: f64,
    ) -> bool {
        let limit = self.robots[ri].model.joints[j].limits.effort;
        let force = if limit.is_finite() && limit > 0.0 {
            effort.min(limit)
        } else {
            effort
        };
        let friction_of = |name: &str| -> Option<(f64, f64)> {
            let e = self.entity(name)?;
            let body = self.physics.bodies.get(self.entities[e].body)?;
            let c = body.colliders().first()?;
            Some((self.physics.colliders.get(*c)?.friction(), body.mass()))
        };
        let (Some((mu_object, mass)), Some((mu_finger, _))) =
            (friction_of(object), friction_of(finger))
        else {
            return true;
        };
        let mu = 0.5 * (mu_object + mu_finger);
        let g = self.physics.gravity.length();
        2.0 * mu * force >= mass * g
    }

    /// Opens the gripper: what it holds is released to the physics (what another
    /// gripper of the robot holds stays held).
    pub fn open_gripper(&mut self, robot: &str, finger_joint: &str) -> Result<(), SimError> {
        self.open_gripper_at(robot, finger_joint, None)
    }

    /// [`Self::open_gripper`] with the finger joint moving at most `speed` (its own
    /// units per second) and the physics stepping meanwhile: what it held is free from
    /// the first step, and the fingers part from it instead of vanishing from its sides.
    /// `None` opens at once.
    pub fn open_gripper_at(
        &mut self,
        robot: &str,
        finger_joint: &str,
        speed: Option<f64>,
    ) -> Result<(), SimError> {
        let ri = self.robot_index(robot)?;
        let j = self.joint_index(ri, finger_joint)?;
        let upper = self.robots[ri].model.joints[j].limits.upper;
        self.open_gripper_to(robot, finger_joint, upper, speed)
    }

    /// [`Self::open_gripper_at`] to the finger joint value `target` (clamped to its
    /// limits) instead of fully open: a pre-grasp posture. What it held is let go.
    pub fn open_gripper_to(
        &mut self,
        robot: &str,
        finger_joint: &str,
        target: f64,
        speed: Option<f64>,
    ) -> Result<(), SimError> {
        if speed.is_some_and(|v| !(v.is_finite() && v > 0.0)) || !target.is_finite() {
            return Err(SimError::NonFinite);
        }
        let ri = self.robot_index(robot)?;
        let j = self.joint_index(ri, finger_joint)?;
        let limits = self.robots[ri].model.joints[j].limits;
        let upper = target.clamp(limits.lower, limits.upper);
        // Objects ride on the palm the gripper closed with: the description's gripper
        // of this finger joint names it (a robot without one releases everything).
        let gripper = self.robots[ri]
            .description
            .grippers
            .iter()
            .find(|g| g.finger_joint == finger_joint)
            .cloned();
        let mine =
            |a: &Attachment| a.robot == robot && gripper.as_ref().is_none_or(|g| g.palm == a.link);
        let released: Vec<Attachment> = self
            .attachments
            .iter()
            .filter(|a| mine(a))
            .cloned()
            .collect();
        self.attachments.retain(|a| !mine(a));
        if speed.is_some() {
            // The squeeze lets go at once (the fingers' own compliance): they back off
            // until neither overlaps what they held, so a paced opening starts from
            // touch rather than from inside the object, which the solver would eject.
            let fingers: Vec<String> = gripper
                .iter()
                .flat_map(|g| g.fingers.iter().map(|f| format!("{robot}/{f}")))
                .collect();
            let lower = self.robots[ri].model.joints[j].limits.lower;
            let step = (upper - lower).abs() / 400.0;
            while self.robots[ri].values[j] < upper
                && fingers.iter().any(|f| {
                    released
                        .iter()
                        .any(|a| self.overlap(f, &a.object).is_some_and(|d| d < 0.0))
                })
            {
                let q = (self.robots[ri].values[j] + step).min(upper);
                self.write_joints(ri, &[(finger_joint, q)])?;
                self.place_robot(ri, false)?;
            }
        }
        for a in released {
            if let Some(i) = self.entity(&a.object) {
                let b = &mut self.physics.bodies[self.entities[i].body];
                b.set_body_type(RigidBodyType::Dynamic, true);
                b.set_linvel(Vec3::ZERO, true);
                b.set_angvel(Vec3::ZERO, true);
            }
        }
        match speed {
            Some(v) => {
                let from = self.robots[ri].values[j];
                let motion = JointTrajectory {
                    joint_names: vec![finger_joint.to_string()],
                    times: vec![0.0, ((upper - from).abs() / v).max(1e-3)],
                    positions: vec![vec![from], vec![upper]],
                };
                self.run_trajectory(ri, &motion, false).map(|_| ())
            }
            None => {
                self.write_joints(ri, &[(finger_joint, upper)])?;
                self.place_robot(ri, false)
            }
        }
    }

    /// The objects a robot holds.
    pub fn held_objects(&self, robot: &str) -> Vec<String> {
        self.attachments
            .iter()
            .filter(|a| a.robot == robot)
            .map(|a| a.object.clone())
            .collect()
    }

    /// The signed distance between two entities' shapes (negative: they overlap by
    /// that much), if both exist and are within a centimetre.
    pub(super) fn overlap(&self, a: &str, b: &str) -> Option<f64> {
        let body = |name: &str| {
            let e = self.entity(name)?;
            self.physics.bodies.get(self.entities[e].body)
        };
        let (ba, bb) = (body(a)?, body(b)?);
        let mut nearest: Option<f64> = None;
        for &ca in ba.colliders() {
            let ca = &self.physics.colliders[ca];
            let pa = *ba.position() * *ca.position_wrt_parent().unwrap_or(&Pose::IDENTITY);
            for &cb in bb.colliders() {
                let cb = &self.physics.colliders[cb];
                let pb = *bb.position() * *cb.position_wrt_parent().unwrap_or(&Pose::IDENTITY);
                if let Ok(Some(k)) =
                    rapier3d_f64::parry::query::contact(&pa, ca.shape(), &pb, cb.shape(), 0.01)
                {
                    nearest = Some(nearest.map_or(k.dist, |n: f64| n.min(k.dist)));
                }
            }
        }
        nearest
    }

    /// An object in contact with (or penetrating) the entity's shapes.
    fn touching_object(&self, entity: &str) -> Option<String> {
        let e = self.entity(entity)?;
        let body = &self.physics.bodies[self.entities[e].body];
        self.first_contact(body, *body.position(), &[EntityKind::Object], 1e-4)
    }

    /// The first entity of one of `kinds` that `body` placed at `world_from_body` comes
    /// within `max_distance` of (negative: penetrates by more than that).
    fn first_contact(
        &self,
        body: &RigidBody,
        world_from_body: Pose,
        kinds: &[EntityKind],
        max_distance: f64,
    ) -> Option<String> {
        self.contacts(body, world_from_body, kinds, max_distance, true)
            .pop()
    }

    /// Every entity of one of `kinds` that `body` at `world_from_body` comes within
    /// `max_distance` of, or only the first when `first`.
    fn contacts(
        &self,
        body: &RigidBody,
        world_from_body: Pose,
        kinds: &[EntityKind],
        max_distance: f64,
        first: bool,
    ) -> Vec<String> {
        let mut out: Vec<String> = Vec::new();
        let held: Vec<&str> = self.attachments.iter().map(|a| a.object.as_str()).collect();
        for &ch in body.colliders() {
            let c = &self.physics.colliders[ch];
            let pose = world_from_body * *c.position_wrt_parent().unwrap_or(&Pose::IDENTITY);
            for other in self
                .live_entities()
                .filter(|o| kinds.contains(&o.kind) && !held.contains(&o.name.as_str()))
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
                        max_distance.max(0.0),
                    )
                    .ok()
                    .flatten();
                    if contact.is_some_and(|k| k.dist <= max_distance) && !out.contains(&other.name)
                    {
                        out.push(other.name.clone());
                        if first {
                            return out;
                        }
                    }
                }
            }
        }
        out
    }

    /// The objects (not held ones) within `within` m of entity `name`'s shapes.
    pub fn objects_near(&self, name: &str, within: f64) -> Vec<String> {
        let Some(i) = self.entity(name) else {
            return Vec::new();
        };
        let body = &self.physics.bodies[self.entities[i].body];
        self.contacts(body, *body.position(), &[EntityKind::Object], within, false)
            .into_iter()
            .filter(|o| o != name)
            .collect()
    }

    /// What a robot's links (and what they hold) touch now among `kinds`, penetrating
    /// by more than `depth` m: `(link or held object, entity)` pairs. The verdict on
    /// "no contact with furniture during any motion" samples this.
    pub fn robot_contacts(
        &self,
        robot: &str,
        kinds: &[EntityKind],
        depth: f64,
    ) -> Result<Vec<(String, String)>, SimError> {
        let prefix = format!("{robot}/");
        let mut out = Vec::new();
        let held = self.held_objects(robot);
        for e in self.live_entities().filter(|e| {
            (e.kind == EntityKind::RobotLink && e.name.starts_with(&prefix))
                || held.contains(&e.name)
        }) {
            let body = &self.physics.bodies[e.body];
            for hit in self.contacts(body, *body.position(), kinds, -depth, false) {
                out.push((e.name.clone(), hit));
            }
        }
        Ok(out)
    }

    /// A robot link (name without the robot prefix) and the furniture or wall it
    /// penetrates by more than a millimetre.
    fn robot_blocked(&self, ri: usize) -> Option<(String, String)> {
        let prefix = format!("{}/", self.robots[ri].name);
        self.live_entities()
            .filter(|e| e.kind == EntityKind::RobotLink && e.name.starts_with(&prefix))
            .find_map(|link| {
                let body = &self.physics.bodies[link.body];
                self.first_contact(body, *body.next_position(), &[EntityKind::Furniture], -1e-3)
                    .map(|f| (link.name[prefix.len()..].to_string(), f))
            })
    }

    /// Drives a planar mobile base to `(x, y, θ)` **in the world frame** the way seed 000
    /// did (SPEC §1.4): turn towards the goal, drive straight, turn to the final
    /// heading, at the joints' velocity limits. The base joints come from the robot's
    /// description and move the base relative to the robot's root pose, so the goal is
    /// turned into that frame first. The base collides with furniture: it stops at the
    /// first contact and reports what it hit.
    pub fn drive_base(&mut self, robot: &str, x: f64, y: f64, theta: f64) -> Result<(), SimError> {
        if !(x.is_finite() && y.is_finite() && theta.is_finite()) {
            return Err(SimError::NonFinite);
        }
        let ri = self.robot_index(robot)?;
        let base = self.robots[ri]
            .description
            .base
            .clone()
            .ok_or_else(|| SimError::Robot(format!("robot `{robot}` has no mobile base")))?;
        let (jx, jy, jt) = (
            base.x_joint.as_str(),
            base.y_joint.as_str(),
            base.theta_joint.as_str(),
        );
        let world_from_goal = Pose::from_parts(
            Vec3::new(x, y, 0.0),
            tabula_geom::Quat::from_rotation_z(theta),
        );
        let root_from_goal = self.robots[ri].world_from_root.inverse() * world_from_goal;
        let (gx, gy) = (root_from_goal.translation.x, root_from_goal.translation.y);
        let heading_of = |p: &Pose| {
            let f = p.rotation * Vec3::X;
            f.y.atan2(f.x)
        };
        let g_theta = heading_of(&root_from_goal);
        let (x0, y0, t0) = (
            self.joint(robot, jx)?,
            self.joint(robot, jy)?,
            self.joint(robot, jt)?,
        );
        let (dx, dy) = (gx - x0, gy - y0);
        let mut legs: Vec<Vec<(&str, f64)>> = Vec::new();
        let mut heading = t0;
        // A goal straight behind, facing the same way, is reached backing up (a base
        // that turned round at a table's edge would sweep its corners into it).
        let along = dx * t0.cos() + dy * t0.sin();
        let across = -dx * t0.sin() + dy * t0.cos();
        let reverse = along < 0.0
            && across.abs() <= 0.01 * dx.hypot(dy).max(0.1)
            && tabula_geom::wrap_angle(g_theta - t0).abs() < 0.02;
        if reverse {
            legs.push(vec![(jx, gx), (jy, gy)]);
        } else if dx.hypot(dy) > 1e-4 {
            let face = t0 + tabula_geom::wrap_angle(dy.atan2(dx) - t0);
            legs.push(vec![(jt, face)]);
            legs.push(vec![(jx, gx), (jy, gy)]);
            heading = face;
        }
        legs.push(vec![(
            jt,
            heading + tabula_geom::wrap_angle(g_theta - heading),
        )]);
        for leg in legs {
            let motion = self.straight_motion(ri, &leg)?;
            self.run_trajectory(ri, &motion, true)?;
        }
        Ok(())
    }

    /// Pan and tilt that point `camera_link`'s optical axis (z) through `point`
    /// (world): Gauss–Newton on the image-plane offset, within the joints' limits.
    /// The robot is left as it was.
    fn look_at_solution(
        &mut self,
        ri: usize,
        pan: &str,
        tilt: &str,
        camera_link: &str,
        point: Vec3,
    ) -> Result<[f64; 2], SimError> {
        let saved = self.robots[ri].values.clone();
        let robot = self.robots[ri].name.clone();
        let offset = |w: &SimWorld| -> Result<(f64, f64, f64), SimError> {
            let cam = w.link_pose(&robot, camera_link)?;
            let p = cam.inverse_transform_point(point);
            Ok((p.x.atan2(p.z), p.y.atan2(p.z), p.angle_between(Vec3::Z)))
        };
        // Gauss–Newton only converges from a guess that sees the point in front of the
        // camera: start from the best of a coarse grid over both joints' ranges.
        let range = |w: &SimWorld, joint: &str| -> Result<(f64, f64), SimError> {
            let j = w.joint_index(ri, joint)?;
            let l = w.robots[ri].model.joints[j].limits;
            Ok(if l.lower.is_finite() && l.upper.is_finite() {
                (l.lower, l.upper)
            } else {
                (-std::f64::consts::PI, std::f64::consts::PI)
            })
        };
        let (pan_range, tilt_range) = (range(self, pan)?, range(self, tilt)?);
        let mut best = (f64::INFINITY, 0.0, 0.0);
        for i in 0..=24 {
            let p = pan_range.0 + (pan_range.1 - pan_range.0) * i as f64 / 24.0;
            for k in 0..=12 {
                let t = tilt_range.0 + (tilt_range.1 - tilt_range.0) * k as f64 / 12.0;
                self.write_joints(ri, &[(pan, p), (tilt, t)])?;
                let angle = offset(self)?.2;
                if angle < best.0 {
                    best = (angle, p, t);
                }
            }
        }
        self.write_joints(ri, &[(pan, best.1), (tilt, best.2)])?;
        for _ in 0..20 {
            let (ex, ey, angle) = offset(self)?;
            if angle < 1e-6 {
                break;
            }
            let q = [self.joint(&robot, pan)?, self.joint(&robot, tilt)?];
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
        let solution = [self.joint(&robot, pan)?, self.joint(&robot, tilt)?];
        self.robots[ri].values = saved;
        Ok(solution)
    }

    /// Turns a pan/tilt head so that `camera_link`'s optical axis goes through `point`
    /// (world), moving the joints under their velocity limits (physics steps in
    /// between). Returns the remaining angle between axis and point (rad).
    pub fn look_at(
        &mut self,
        robot: &str,
        pan: &str,
        tilt: &str,
        camera_link: &str,
        point: Vec3,
    ) -> Result<f64, SimError> {
        if !point.is_finite() {
            return Err(SimError::NonFinite);
        }
        let ri = self.robot_index(robot)?;
        let [p, t] = self.look_at_solution(ri, pan, tilt, camera_link, point)?;
        self.move_joints(robot, &[(pan, p), (tilt, t)])?;
        let cam = self.link_pose(robot, camera_link)?;
        Ok(cam.inverse_transform_point(point).angle_between(Vec3::Z))
    }
}
