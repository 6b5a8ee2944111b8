//! The driver traits over zenoh: a robot served in another process or on another
//! machine (`tabula serve`, or a ROS 2 stack answering tabula's driver services) driven
//! exactly as the simulator in this process is. Every command waits for its answer, so
//! the task's view of the robot is as current as with a local driver.

use crate::msgs::{CallRequest, CallResponse};
use crate::node::{Client, Node, NodeConfig, RosError};
use crate::protocol::{
    Answer, CALL_TYPE, CAPTURE_SERVICE, CAPTURE_TYPE, CaptureRequest, CaptureResponse, Command,
    DRIVER_SERVICE, Description, WireDriverError, pose_from_array,
};
use std::sync::Arc;
use std::time::Duration;
use tabula_geom::{Pose, Vec3};
use tabula_robot::driver::{
    Annotations, Arms, BaseControl, CameraFrame, Cameras, DriverError, GripState, Grippers,
    HeadControl, JointState, JointStates, JointTrajectory, stop_requested,
};

/// A robot behind tabula's driver services.
pub struct ZenohDriver {
    pub node: Arc<Node>,
    call: Client<CallRequest, CallResponse>,
    capture: Client<CaptureRequest, CaptureResponse>,
    /// How long a command may take beyond its own duration (a trajectory's).
    pub timeout: Duration,
    description: Description,
}

pub(crate) fn hardware(e: RosError) -> DriverError {
    DriverError::Hardware(e.to_string())
}

impl ZenohDriver {
    /// Connects as `config` says and waits up to `wait` for the robot's services.
    pub fn connect(config: NodeConfig, wait: Duration) -> Result<Self, RosError> {
        let domain = config.domain;
        let node = Node::open(config)?;
        let call = node.client(DRIVER_SERVICE, CALL_TYPE)?;
        let capture = node.client(CAPTURE_SERVICE, CAPTURE_TYPE)?;
        call.wait_for_server(domain, wait)?;
        let mut driver = Self {
            node,
            call,
            capture,
            timeout: Duration::from_secs(60),
            description: Description {
                robot: String::new(),
                cameras: Vec::new(),
                time: 0.0,
            },
        };
        match driver.send(&Command::Describe, Duration::ZERO) {
            Ok(Answer::Description(d)) => driver.description = d,
            Ok(other) => {
                return Err(RosError::Remote(
                    DRIVER_SERVICE.into(),
                    format!("unexpected answer {other:?}"),
                ));
            }
            Err(e) => return Err(RosError::Remote(DRIVER_SERVICE.into(), e.to_string())),
        }
        Ok(driver)
    }

    /// The served robot's name and cameras.
    pub fn description(&self) -> &Description {
        &self.description
    }

    /// The served world as a scene file (TOML).
    pub fn scene(&self) -> Result<String, DriverError> {
        match self.send(&Command::Scene, Duration::ZERO)? {
            Answer::Scene { toml } => Ok(toml),
            other => Err(unexpected(other)),
        }
    }

    /// Sends one command; `extra` is how long it is expected to run.
    fn send(&self, command: &Command, extra: Duration) -> Result<Answer, DriverError> {
        send(&self.call, command, self.timeout + extra)
    }

    fn done(&self, command: &Command, extra: Duration) -> Result<(), DriverError> {
        match self.send(command, extra)? {
            Answer::Done => Ok(()),
            other => Err(unexpected(other)),
        }
    }

    fn grip(&self, command: &Command) -> Result<GripState, DriverError> {
        match self.send(command, Duration::ZERO)? {
            Answer::Grip { width, holding } => Ok(GripState { width, holding }),
            other => Err(unexpected(other)),
        }
    }
}

/// Sends one command on `call` and waits up to `timeout` for its answer; a command
/// that moves the robot is not sent once Ctrl+C was pressed.
pub(crate) fn send(
    call: &Client<CallRequest, CallResponse>,
    command: &Command,
    timeout: Duration,
) -> Result<Answer, DriverError> {
    if stop_requested() && command.moves() {
        return Err(DriverError::Stopped);
    }
    let request = CallRequest {
        request: serde_json::to_string(command)
            .map_err(|e| DriverError::Hardware(e.to_string()))?,
    };
    let response = call.call(&request, timeout).map_err(hardware)?;
    if response.ok {
        serde_json::from_str(&response.response)
            .map_err(|e| DriverError::Hardware(format!("malformed answer: {e}")))
    } else {
        let e: WireDriverError = serde_json::from_str(&response.response)
            .map_err(|_| DriverError::Hardware(response.response.clone()))?;
        Err(e.into())
    }
}

pub(crate) fn unexpected(a: Answer) -> DriverError {
    DriverError::Hardware(format!("unexpected answer {a:?}"))
}

impl JointStates for ZenohDriver {
    fn joint_state(&self) -> Result<JointState, DriverError> {
        match self.send(&Command::JointState, Duration::ZERO)? {
            Answer::JointState {
                names,
                positions,
                stamp,
            } if names.len() == positions.len() => Ok(JointState {
                names,
                positions,
                stamp,
            }),
            other => Err(unexpected(other)),
        }
    }

    fn world_from_root(&self) -> Result<Pose, DriverError> {
        match self.send(&Command::WorldFromRoot, Duration::ZERO)? {
            Answer::Pose { pose } => pose_from_array(&pose).ok_or(DriverError::NonFinite),
            other => Err(unexpected(other)),
        }
    }
}

impl Cameras for ZenohDriver {
    fn capture(&mut self, camera: &str) -> Result<CameraFrame, DriverError> {
        if stop_requested() {
            return Err(DriverError::Stopped);
        }
        let r = self
            .capture
            .call(
                &CaptureRequest {
                    camera: camera.into(),
                },
                self.timeout,
            )
            .map_err(hardware)?;
        if !r.ok {
            let e: WireDriverError = serde_json::from_str(&r.error)
                .map_err(|_| DriverError::Hardware(r.error.clone()))?;
            return Err(e.into());
        }
        let cloud = r
            .cloud
            .to_cloud()
            .map_err(|e| DriverError::Hardware(e.to_string()))?;
        let world_from_camera = r
            .world_from_camera
            .to_pose()
            .ok_or(DriverError::NonFinite)?;
        Ok(CameraFrame {
            cloud,
            world_from_camera,
            stamp: r.cloud.header.stamp.secs(),
        })
    }
}

impl Arms for ZenohDriver {
    fn execute(&mut self, trajectory: &JointTrajectory) -> Result<(), DriverError> {
        trajectory.validate()?;
        // A simulator may run slower than real time: allow ten times the duration.
        let extra = Duration::from_secs_f64((trajectory.duration() * 10.0).clamp(0.0, 3600.0));
        self.done(&Command::execute(trajectory), extra)
    }
}

impl Grippers for ZenohDriver {
    fn open(&mut self, gripper: &str) -> Result<(), DriverError> {
        self.done(
            &Command::Open {
                gripper: gripper.into(),
            },
            Duration::ZERO,
        )
    }

    fn close(&mut self, gripper: &str) -> Result<GripState, DriverError> {
        self.grip(&Command::Close {
            gripper: gripper.into(),
            effort: None,
        })
    }

    fn open_slowly(&mut self, gripper: &str, speed: f64) -> Result<(), DriverError> {
        if !(speed.is_finite() && speed > 0.0) {
            return Err(DriverError::NonFinite);
        }
        self.done(
            &Command::OpenSlowly {
                gripper: gripper.into(),
                speed,
            },
            Duration::from_secs_f64((1.0 / speed).min(600.0)),
        )
    }

    fn open_to(&mut self, gripper: &str, width: f64) -> Result<(), DriverError> {
        if !width.is_finite() {
            return Err(DriverError::NonFinite);
        }
        self.done(
            &Command::OpenTo {
                gripper: gripper.into(),
                width,
            },
            Duration::ZERO,
        )
    }

    fn grip_state(&self, gripper: &str) -> Result<GripState, DriverError> {
        self.grip(&Command::GripState {
            gripper: gripper.into(),
        })
    }

    fn close_with_effort(&mut self, gripper: &str, effort: f64) -> Result<GripState, DriverError> {
        if !(effort.is_finite() && effort >= 0.0) {
            return Err(DriverError::NonFinite);
        }
        self.grip(&Command::Close {
            gripper: gripper.into(),
            effort: Some(effort),
        })
    }
}

impl HeadControl for ZenohDriver {
    fn look_at(&mut self, world_point: Vec3) -> Result<f64, DriverError> {
        if !world_point.is_finite() {
            return Err(DriverError::NonFinite);
        }
        match self.send(
            &Command::LookAt {
                point: world_point.to_array(),
            },
            Duration::ZERO,
        )? {
            Answer::Angle { rad } => Ok(rad),
            other => Err(unexpected(other)),
        }
    }
}

impl BaseControl for ZenohDriver {
    fn drive_to(&mut self, x: f64, y: f64, theta: f64) -> Result<(), DriverError> {
        if !(x.is_finite() && y.is_finite() && theta.is_finite()) {
            return Err(DriverError::NonFinite);
        }
        self.done(&Command::DriveTo { x, y, theta }, Duration::from_secs(60))
    }
}

impl Annotations for ZenohDriver {
    fn annotate(&mut self, label: &str) {
        if let Err(e) = self.done(
            &Command::Annotate {
                label: label.into(),
            },
            Duration::ZERO,
        ) {
            tracing::warn!("annotation `{label}` not sent: {e}");
        }
    }
}
