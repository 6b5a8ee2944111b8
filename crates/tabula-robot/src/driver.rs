//! The driver boundary: the only way the task layer touches a robot (the role of
//! ros2_control's hardware interfaces and of seed 000's "RobotDriver"). The simulator
//! implements these traits, a zenoh bridge can implement them for a robot in another
//! process, and tests implement them with a mock that copies commands into states —
//! so nothing above this line names the simulator.
//!
//! Everything is in tabula's own types; joints and links are named as in the robot's
//! URDF and description, poses say their frames.

use tabula_geom::{PointCloud, Pose, Vec3};

/// Why a driver command failed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum DriverError {
    /// The robot stopped before the goal because it would have hit something.
    /// `link` of the robot would have entered `by`.
    #[error("blocked by `{by}` (its link `{link}`)")]
    Blocked { by: String, link: String },
    #[error("unknown joint `{0}`")]
    UnknownJoint(String),
    #[error("values must be finite")]
    NonFinite,
    #[error("malformed trajectory: {0}")]
    BadTrajectory(String),
    #[error("this robot has no {0}")]
    Unsupported(&'static str),
    #[error("{0}")]
    Hardware(String),
    /// The operator stopped the robot (Ctrl+C): it holds where it is.
    #[error("stopped by the operator")]
    Stopped,
}

/// The operator's stop (Ctrl+C), process-wide as an emergency stop is: once asked,
/// drivers finish no motion and start none, and tasks end with [`DriverError::Stopped`].
static STOP: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// Asks every driver of this process to stop (a signal handler may call it).
pub fn request_stop() {
    STOP.store(true, std::sync::atomic::Ordering::SeqCst);
}

/// Whether a stop was asked for.
pub fn stop_requested() -> bool {
    STOP.load(std::sync::atomic::Ordering::SeqCst)
}

/// Positions of named joints at a time (s, the driver's clock).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct JointState {
    pub names: Vec<String>,
    pub positions: Vec<f64>,
    pub stamp: f64,
}

impl JointState {
    /// Every single-axis joint of `model` at `values` (mimic joints as their masters
    /// move them), as a driver reports its state.
    pub fn of_model(model: &crate::RobotModel, values: &[f64]) -> Self {
        let mut js = Self::default();
        for (j, joint) in model.joints.iter().enumerate() {
            if joint.kind.is_single_axis() {
                js.names.push(joint.name.clone());
                js.positions.push(model.joint_value(values, j));
            }
        }
        js
    }

    /// The position of `name`, if the state has it.
    pub fn get(&self, name: &str) -> Option<f64> {
        self.names
            .iter()
            .position(|n| n == name)
            .map(|i| self.positions[i])
    }

    /// Values for every joint of `model`, in model order; joints the state lacks are at
    /// mid-range, where the simulator starts them.
    pub fn model_values(&self, model: &crate::RobotModel) -> Vec<f64> {
        let mut values = model.mid_configuration();
        for (n, v) in self.names.iter().zip(&self.positions) {
            if let Some(j) = model.joint(n) {
                values[j] = *v;
            }
        }
        values
    }
}

/// A timed joint trajectory (trajectory_msgs/JointTrajectory's shape): `positions[k][i]`
/// is joint `joint_names[i]` at `times[k]` seconds from the start.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct JointTrajectory {
    pub joint_names: Vec<String>,
    pub times: Vec<f64>,
    pub positions: Vec<Vec<f64>>,
}

impl JointTrajectory {
    /// Checks shape, finiteness and that time never runs backwards.
    pub fn validate(&self) -> Result<(), DriverError> {
        if self.times.len() != self.positions.len() {
            return Err(DriverError::BadTrajectory(format!(
                "{} times for {} points",
                self.times.len(),
                self.positions.len()
            )));
        }
        for (k, p) in self.positions.iter().enumerate() {
            if p.len() != self.joint_names.len() {
                return Err(DriverError::BadTrajectory(format!(
                    "point {k} has {} values for {} joints",
                    p.len(),
                    self.joint_names.len()
                )));
            }
            if p.iter().any(|v| !v.is_finite()) {
                return Err(DriverError::NonFinite);
            }
        }
        if self.times.iter().any(|t| !t.is_finite()) {
            return Err(DriverError::NonFinite);
        }
        if self.times.windows(2).any(|w| w[1] < w[0]) {
            return Err(DriverError::BadTrajectory("time runs backwards".into()));
        }
        Ok(())
    }

    pub fn duration(&self) -> f64 {
        self.times.last().copied().unwrap_or(0.0)
    }

    /// The positions at time `t`, linear between samples (clamped at the ends).
    pub fn sample(&self, t: f64) -> Option<Vec<f64>> {
        let last = self.positions.len().checked_sub(1)?;
        let k = self.times.partition_point(|&x| x <= t);
        if k == 0 {
            return Some(self.positions[0].clone());
        }
        if k > last {
            return Some(self.positions[last].clone());
        }
        let (t0, t1) = (self.times[k - 1], self.times[k]);
        let s = if t1 > t0 { (t - t0) / (t1 - t0) } else { 1.0 };
        Some(
            self.positions[k - 1]
                .iter()
                .zip(&self.positions[k])
                .map(|(a, b)| a + (b - a) * s)
                .collect(),
        )
    }
}

/// One depth frame: an organized cloud in the camera's optical frame, where the camera
/// was when it was taken, and when.
#[derive(Debug, Clone)]
pub struct CameraFrame {
    pub cloud: PointCloud,
    pub world_from_camera: Pose,
    pub stamp: f64,
}

/// What a gripper reports after closing.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GripState {
    /// Finger gap (m).
    pub width: f64,
    /// The fingers stopped on something before closing fully.
    pub holding: bool,
}

/// Reads every joint of the robot, and where its root is in the world.
pub trait JointStates {
    fn joint_state(&self) -> Result<JointState, DriverError>;
    /// `world_from_root` of the robot's URDF root (a mobile base's odometry origin).
    fn world_from_root(&self) -> Result<Pose, DriverError>;
}

/// Depth cameras by name.
pub trait Cameras {
    fn capture(&mut self, camera: &str) -> Result<CameraFrame, DriverError>;
}

/// Position-controlled joints that follow timed trajectories.
pub trait Arms {
    fn execute(&mut self, trajectory: &JointTrajectory) -> Result<(), DriverError>;
}

/// Parallel grippers by name (as in the robot description).
pub trait Grippers {
    fn open(&mut self, gripper: &str) -> Result<(), DriverError>;
    fn close(&mut self, gripper: &str) -> Result<GripState, DriverError>;
    /// Opens with the finger gap growing at most `speed` m/s, so a released object is
    /// not flicked by fingers snapping open. Drivers that cannot pace the fingers open
    /// as [`Self::open`] does.
    fn open_slowly(&mut self, gripper: &str, speed: f64) -> Result<(), DriverError> {
        if !(speed.is_finite() && speed > 0.0) {
            return Err(DriverError::NonFinite);
        }
        self.open(gripper)
    }
    /// Opens to a finger gap of `width` metres (clamped to the gripper's range), and
    /// lets go of what it held — a pre-grasp posture: fingers opened just wider than
    /// the object fit between its neighbours in clutter (what a gripper action's
    /// `position` sets). Drivers that cannot set the gap open fully, as
    /// [`Self::open`] does.
    fn open_to(&mut self, gripper: &str, width: f64) -> Result<(), DriverError> {
        if !width.is_finite() {
            return Err(DriverError::NonFinite);
        }
        self.open(gripper)
    }
    /// The gripper now: its gap, and whether it holds something — the fingers stopped
    /// on an object when it last closed and it has not opened since (what a gripper
    /// action reports as stalled rather than reached).
    fn grip_state(&self, gripper: &str) -> Result<GripState, DriverError>;
    /// Closes squeezing with at most `effort` newtons per finger (capped at the finger
    /// joint's limit), so a gentle grip does not crush and a weak one may not hold.
    /// Drivers that cannot limit the force close as [`Self::close`] does.
    fn close_with_effort(&mut self, gripper: &str, effort: f64) -> Result<GripState, DriverError> {
        if !(effort.is_finite() && effort >= 0.0) {
            return Err(DriverError::NonFinite);
        }
        self.close(gripper)
    }
}

/// A pan/tilt head.
pub trait HeadControl {
    /// Turns the camera's optical axis towards `world_point`, moving under the joints'
    /// limits; returns the angle left between axis and point (rad).
    fn look_at(&mut self, world_point: Vec3) -> Result<f64, DriverError>;
}

/// A planar mobile base.
pub trait BaseControl {
    /// Drives to `(x, y, θ)` in the world: turns to face the goal, drives, turns to θ —
    /// except that a goal straight behind with the same heading is reached by backing
    /// up. [`DriverError::Blocked`] if it had to stop.
    fn drive_to(&mut self, x: f64, y: f64, theta: f64) -> Result<(), DriverError>;
}

/// Labels for moments of a task ("scanned the object", "pushed o3"), as a rosbag's
/// markers: a recorder takes pictures there, a real robot's driver may log or publish
/// them. Nothing moves; drivers that keep no record ignore them.
pub trait Annotations {
    fn annotate(&mut self, _label: &str) {}
}

/// Everything a task uses. Robots without a head or a base answer
/// [`DriverError::Unsupported`].
pub trait RobotDriver:
    JointStates + Cameras + Arms + Grippers + HeadControl + BaseControl + Annotations
{
}

impl<T: JointStates + Cameras + Arms + Grippers + HeadControl + BaseControl + Annotations>
    RobotDriver for T
{
}
