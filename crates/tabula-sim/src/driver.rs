//! The simulator behind the driver traits of `tabula_robot::driver`: one robot of a
//! [`SimWorld`], driven the way a real one is — by joint trajectories, gripper commands,
//! head and base goals — with cameras that capture where their link is now. The world
//! stays reachable (`world`) for verdicts from ground truth; tasks never see it.

use crate::camera::capture;
use crate::world::{SimError, SimWorld};
use tabula_geom::{Pose, Vec3};
use tabula_robot::driver::{
    Annotations, Arms, BaseControl, CameraFrame, Cameras, DriverError, GripState, Grippers,
    HeadControl, JointState, JointStates, JointTrajectory, stop_requested,
};

/// One simulated robot behind the driver traits.
pub struct SimDriver {
    pub world: SimWorld,
    robot: String,
    /// Seed of the camera noise; each capture uses the next one.
    noise_seed: u64,
    /// Called after every physics step of a command (e.g. to record a replay or watch
    /// for contacts), in the order they were added; each gets the world after the step.
    #[allow(clippy::type_complexity)]
    observers: Vec<Box<dyn FnMut(&SimWorld) + Send>>,
}

impl From<SimError> for DriverError {
    fn from(e: SimError) -> Self {
        match e {
            SimError::Blocked { by, link, .. } => DriverError::Blocked { by, link },
            SimError::NonFinite => DriverError::NonFinite,
            other => DriverError::Hardware(other.to_string()),
        }
    }
}

impl SimDriver {
    /// Drives robot `robot` of `world`; camera noise starts from `noise_seed`.
    pub fn new(world: SimWorld, robot: &str, noise_seed: u64) -> Result<Self, SimError> {
        world.robot(robot)?;
        Ok(Self {
            world,
            robot: robot.into(),
            noise_seed,
            observers: Vec::new(),
        })
    }

    /// The camera noise seed of the next capture (each capture takes the next one), for
    /// whoever captures on this driver's behalf (a server publishing its frames).
    pub fn next_noise_seed(&mut self) -> u64 {
        self.noise_seed = self.noise_seed.wrapping_add(1);
        self.noise_seed
    }

    /// The robot's name in the world.
    pub fn robot_name(&self) -> &str {
        &self.robot
    }

    /// Watches every physics step of the commands that follow, beside the observers
    /// already watching (a judge's contact watch and a replay recorder, say).
    pub fn observe(&mut self, observer: impl FnMut(&SimWorld) + Send + 'static) {
        self.observers.push(Box::new(observer));
    }

    /// Runs `f` on the world, then lets the observer see it; nothing once the operator
    /// has stopped the robot.
    fn run<T>(
        &mut self,
        f: impl FnOnce(&mut SimWorld, &str) -> Result<T, SimError>,
    ) -> Result<T, DriverError> {
        if stop_requested() {
            return Err(DriverError::Stopped);
        }
        let out = f(&mut self.world, &self.robot);
        for obs in &mut self.observers {
            obs(&self.world);
        }
        Ok(out?)
    }
}

impl JointStates for SimDriver {
    fn joint_state(&self) -> Result<JointState, DriverError> {
        let r = self.world.robot(&self.robot)?;
        let mut state = JointState {
            stamp: self.world.time(),
            ..Default::default()
        };
        for (j, joint) in r.model.joints.iter().enumerate() {
            if joint.kind.is_single_axis() {
                state.names.push(joint.name.clone());
                state.positions.push(r.model.joint_value(&r.values, j));
            }
        }
        Ok(state)
    }

    fn world_from_root(&self) -> Result<Pose, DriverError> {
        Ok(self.world.robot(&self.robot)?.world_from_root)
    }
}

impl Cameras for SimDriver {
    fn capture(&mut self, camera: &str) -> Result<CameraFrame, DriverError> {
        if stop_requested() {
            return Err(DriverError::Stopped);
        }
        let cam = self.world.camera(camera)?;
        let seed = self.next_noise_seed();
        let frame = capture(&self.world, &cam, seed);
        Ok(CameraFrame {
            cloud: frame.cloud,
            world_from_camera: frame.world_from_camera,
            stamp: self.world.time(),
        })
    }
}

impl Arms for SimDriver {
    fn execute(&mut self, trajectory: &JointTrajectory) -> Result<(), DriverError> {
        trajectory.validate()?;
        if self.observers.is_empty() {
            return self.run(|w, r| w.follow_trajectory(r, trajectory).map(|_| ()));
        }
        // With an observer, step through the trajectory so it sees every step; a stop
        // then holds the arm where the last step left it (inside the joints' limits,
        // as every sample of a valid trajectory is).
        let dt = self.world.physics.integration_parameters.dt;
        let mut t = 0.0;
        let mut start = trajectory.positions.first().cloned().unwrap_or_default();
        while t < trajectory.duration() {
            let next = (t + dt).min(trajectory.duration());
            let goal = trajectory.sample(next).unwrap_or_default();
            let piece = JointTrajectory {
                joint_names: trajectory.joint_names.clone(),
                times: vec![0.0, next - t],
                positions: vec![start, goal.clone()],
            };
            self.run(|w, r| w.follow_trajectory(r, &piece).map(|_| ()))?;
            start = goal;
            t = next;
        }
        Ok(())
    }
}

impl Grippers for SimDriver {
    fn open(&mut self, gripper: &str) -> Result<(), DriverError> {
        let g = self.gripper(gripper)?;
        self.run(|w, r| w.open_gripper(r, &g.finger_joint))
    }

    fn close(&mut self, gripper: &str) -> Result<GripState, DriverError> {
        self.close_limited(gripper, None)
    }

    fn open_to(&mut self, gripper: &str, width: f64) -> Result<(), DriverError> {
        if !width.is_finite() {
            return Err(DriverError::NonFinite);
        }
        let g = self.gripper(gripper)?;
        let l = self.finger_limits(&g)?;
        // The gap is linear in the finger joint (see `Gripper::width_at`).
        let span = g.open_width - g.closed_width;
        let share = if span.abs() > 1e-12 {
            ((width - g.closed_width) / span).clamp(0.0, 1.0)
        } else {
            1.0
        };
        let target = l.lower + (l.upper - l.lower) * share;
        self.run(|w, r| w.open_gripper_to(r, &g.finger_joint, target, None))
    }

    fn open_slowly(&mut self, gripper: &str, speed: f64) -> Result<(), DriverError> {
        if !(speed.is_finite() && speed > 0.0) {
            return Err(DriverError::NonFinite);
        }
        let g = self.gripper(gripper)?;
        // The gap is linear in the finger joint (see `Gripper::width_at`).
        let l = self.finger_limits(&g)?;
        let per_joint = (g.open_width - g.closed_width).abs() / (l.upper - l.lower).max(1e-12);
        let joint_speed = speed / per_joint.max(1e-12);
        self.run(|w, r| w.open_gripper_at(r, &g.finger_joint, Some(joint_speed)))
    }

    fn close_with_effort(&mut self, gripper: &str, effort: f64) -> Result<GripState, DriverError> {
        if !(effort.is_finite() && effort >= 0.0) {
            return Err(DriverError::NonFinite);
        }
        self.close_limited(gripper, Some(effort))
    }

    fn grip_state(&self, gripper: &str) -> Result<GripState, DriverError> {
        let g = self.gripper(gripper)?;
        let value = self.world.joint(&self.robot, &g.finger_joint)?;
        let r = self.world.robot(&self.robot)?;
        Ok(GripState {
            width: g.width_at(&r.model, value),
            holding: self
                .world
                .attachments
                .iter()
                .any(|a| a.robot == self.robot && a.link == g.palm),
        })
    }
}

impl SimDriver {
    fn close_limited(
        &mut self,
        gripper: &str,
        effort: Option<f64>,
    ) -> Result<GripState, DriverError> {
        let g = self.gripper(gripper)?;
        let held = self.run(|w, r| {
            w.close_gripper_with_effort(
                r,
                &g.finger_joint,
                [g.fingers[0].as_str(), g.fingers[1].as_str()],
                &g.palm,
                effort,
            )
        })?;
        let value = self.world.joint(&self.robot, &g.finger_joint)?;
        let r = self.world.robot(&self.robot)?;
        Ok(GripState {
            width: g.width_at(&r.model, value),
            holding: held.is_some(),
        })
    }
}

impl SimDriver {
    /// The limits of a gripper's finger joint.
    fn finger_limits(
        &self,
        g: &tabula_robot::description::Gripper,
    ) -> Result<tabula_robot::model::JointLimits, DriverError> {
        let r = self.world.robot(&self.robot)?;
        let j = r
            .model
            .joint(&g.finger_joint)
            .ok_or_else(|| DriverError::UnknownJoint(g.finger_joint.clone()))?;
        Ok(r.model.joints[j].limits)
    }

    fn gripper(&self, name: &str) -> Result<tabula_robot::description::Gripper, DriverError> {
        let r = self.world.robot(&self.robot)?;
        r.description
            .grippers
            .iter()
            .find(|g| g.name == name)
            .cloned()
            .ok_or_else(|| DriverError::Hardware(format!("no gripper `{name}`")))
    }
}

impl HeadControl for SimDriver {
    fn look_at(&mut self, world_point: Vec3) -> Result<f64, DriverError> {
        let head = self
            .world
            .robot(&self.robot)?
            .description
            .head
            .clone()
            .ok_or(DriverError::Unsupported("head"))?;
        self.run(|w, r| {
            w.look_at(
                r,
                &head.pan_joint,
                &head.tilt_joint,
                &head.camera_link,
                world_point,
            )
        })
    }
}

impl Annotations for SimDriver {
    /// Kept in the world's notes (with the simulated time) for its observers.
    fn annotate(&mut self, label: &str) {
        let time = self.world.time();
        self.world.notes.push((time, label.to_string()));
        for obs in &mut self.observers {
            obs(&self.world);
        }
    }
}

impl BaseControl for SimDriver {
    fn drive_to(&mut self, x: f64, y: f64, theta: f64) -> Result<(), DriverError> {
        if self.world.robot(&self.robot)?.description.base.is_none() {
            return Err(DriverError::Unsupported("mobile base"));
        }
        self.run(|w, r| w.drive_base(r, x, y, theta))
    }
}
