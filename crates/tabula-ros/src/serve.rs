//! The simulator served as a ROS 2 robot (`tabula serve`): one node, `tabula_sim`, that
//! publishes each camera's organized `sensor_msgs/msg/PointCloud2` (x y z rgb) at
//! `/<camera>/points`, `sensor_msgs/msg/JointState` at `/joint_states` and
//! `tf2_msgs/msg/TFMessage` at `/tf`; executes `trajectory_msgs/msg/JointTrajectory`
//! on `/<arm>/joint_trajectory` and `control_msgs/msg/GripperCommand` on
//! `/<gripper>/gripper_command`; and answers tabula's driver and capture services, so
//! that a task in another process drives it as it would drive the simulator in its own.
//!
//! The world belongs to one thread: zenoh's callbacks only queue work, the loop in
//! [`Server::run`] does it in arrival order and answers.

use crate::msgs::{CallRequest, CallResponse};
use crate::msgs::{
    GripperCommand, Header, JointState as JointStateMsg, JointTrajectory as TrajectoryMsg,
    PointCloud2, TfMessage, Time, Transform, TransformStamped,
};
use crate::node::{Node, NodeConfig, Publisher, Request, RosError, Service, Subscription};
use crate::protocol::{
    Answer, CALL_TYPE, CAPTURE_SERVICE, CAPTURE_TYPE, CaptureRequest, CaptureResponse, Command,
    DRIVER_SERVICE, Description, WireDriverError, pose_to_array,
};
use crate::wire::Qos;
use std::sync::Arc;
use std::sync::mpsc::{Receiver, Sender, channel};
use std::time::{Duration, Instant};
use tabula_geom::Vec3;
use tabula_robot::driver::{
    Annotations, Arms, BaseControl, DriverError, Grippers, HeadControl, JointStates,
};
use tabula_sim::{SimDriver, SimWorld};

/// How often the server publishes on its own (0: only after commands).
#[derive(Debug, Clone, Copy)]
pub struct Rates {
    /// `/joint_states` and `/tf` (Hz).
    pub state_hz: f64,
    /// Each camera's `/<camera>/points` (Hz): a frame costs ~20 ms of ray casting.
    pub camera_hz: f64,
}

impl Default for Rates {
    fn default() -> Self {
        Self {
            state_hz: 10.0,
            camera_hz: 1.0,
        }
    }
}

enum Work {
    Call(Request<CallRequest>),
    Capture(Request<CaptureRequest>),
    Trajectory(TrajectoryMsg),
    Gripper(String, GripperCommand),
}

/// A served simulator.
pub struct Server {
    pub node: Arc<Node>,
    driver: SimDriver,
    work: Receiver<Work>,
    joint_states: Publisher<JointStateMsg>,
    tf: Publisher<TfMessage>,
    clouds: Vec<(String, Publisher<PointCloud2>)>,
    _endpoints: (Vec<Service>, Vec<Subscription>),
    rates: Rates,
}

fn header(stamp: f64, frame: &str) -> Header {
    Header {
        stamp: Time::from_secs(stamp),
        frame_id: frame.into(),
    }
}

impl Server {
    /// Serves robot `robot` of `world` (settled first, as every judged run starts);
    /// camera noise starts from `seed`.
    pub fn new(
        mut world: SimWorld,
        robot: &str,
        seed: u64,
        config: NodeConfig,
        rates: Rates,
    ) -> Result<Self, RosError> {
        world.settle();
        let description = world
            .robot(robot)
            .map_err(|e| RosError::Zenoh(e.to_string()))?
            .description
            .clone();
        let cameras: Vec<String> = world.cameras.iter().map(|c| c.name.to_string()).collect();
        let mut driver =
            SimDriver::new(world, robot, seed).map_err(|e| RosError::Zenoh(e.to_string()))?;
        // Step trajectories one physics step at a time, as every judged run in one
        // process does (its contact watch is an observer), so that a task driven from
        // another process meets the same physics.
        driver.observe(|_| {});
        let node = Node::open(config)?;
        let (tx, work) = channel::<Work>();
        let mut services = Vec::new();
        let mut subscriptions = Vec::new();
        let send = |tx: &Sender<Work>| tx.clone();
        {
            let tx = send(&tx);
            services.push(node.service_queue(DRIVER_SERVICE, CALL_TYPE, move |r| {
                let _ = tx.send(Work::Call(r));
            })?);
        }
        {
            let tx = send(&tx);
            services.push(node.service_queue(CAPTURE_SERVICE, CAPTURE_TYPE, move |r| {
                let _ = tx.send(Work::Capture(r));
            })?);
        }
        for arm in &description.arms {
            let tx = send(&tx);
            subscriptions.push(node.subscribe(
                &format!("/{}/joint_trajectory", arm.name),
                "trajectory_msgs/msg/JointTrajectory",
                Qos::default(),
                move |msg: TrajectoryMsg, _| {
                    let _ = tx.send(Work::Trajectory(msg));
                },
            )?);
        }
        for gripper in &description.grippers {
            let tx = send(&tx);
            let name = gripper.name.clone();
            subscriptions.push(node.subscribe(
                &format!("/{}/gripper_command", gripper.name),
                "control_msgs/msg/GripperCommand",
                Qos::default(),
                move |msg: GripperCommand, _| {
                    let _ = tx.send(Work::Gripper(name.clone(), msg));
                },
            )?);
        }
        let joint_states = node.publisher(
            "/joint_states",
            "sensor_msgs/msg/JointState",
            Qos::default(),
        )?;
        let tf = node.publisher("/tf", "tf2_msgs/msg/TFMessage", Qos::default())?;
        let clouds = cameras
            .iter()
            .map(|c| {
                node.publisher(
                    &format!("/{c}/points"),
                    "sensor_msgs/msg/PointCloud2",
                    Qos::sensor_data(),
                )
                .map(|p| (c.clone(), p))
            })
            .collect::<Result<Vec<_>, _>>()?;
        Ok(Self {
            node,
            driver,
            work,
            joint_states,
            tf,
            clouds,
            _endpoints: (services, subscriptions),
            rates,
        })
    }

    /// The served world now.
    pub fn world(&self) -> &SimWorld {
        &self.driver.world
    }

    /// Serves until `stop()` says so (checked at least every 50 ms).
    pub fn run(&mut self, stop: impl Fn() -> bool) {
        let period = |hz: f64| (hz > 0.0).then(|| Duration::from_secs_f64(1.0 / hz));
        let (state_period, camera_period) =
            (period(self.rates.state_hz), period(self.rates.camera_hz));
        let mut next_state = Instant::now();
        let mut next_camera = Instant::now();
        while !stop() {
            match self.work.recv_timeout(Duration::from_millis(50)) {
                Ok(work) => self.handle(work),
                Err(std::sync::mpsc::RecvTimeoutError::Timeout) => {}
                Err(std::sync::mpsc::RecvTimeoutError::Disconnected) => break,
            }
            let now = Instant::now();
            if let Some(p) = state_period
                && now >= next_state
            {
                self.publish_state();
                next_state = now + p;
            }
            if let Some(p) = camera_period
                && now >= next_camera
            {
                for k in 0..self.clouds.len() {
                    let camera = self.clouds[k].0.clone();
                    let _ = self.capture(&camera);
                }
                next_camera = now + p;
            }
        }
    }

    fn handle(&mut self, work: Work) {
        match work {
            Work::Call(r) => {
                let answer = match self.command(&r.request) {
                    Ok(a) => CallResponse {
                        ok: true,
                        response: serde_json::to_string(&a).unwrap_or_default(),
                    },
                    Err(e) => CallResponse {
                        ok: false,
                        response: serde_json::to_string(&WireDriverError::from(&e))
                            .unwrap_or_default(),
                    },
                };
                r.reply(&answer);
                self.publish_state();
            }
            Work::Capture(r) => {
                let answer = match self.capture(&r.request.camera) {
                    Ok((cloud, world_from_camera)) => CaptureResponse {
                        ok: true,
                        error: String::new(),
                        cloud,
                        world_from_camera,
                    },
                    Err(e) => CaptureResponse {
                        ok: false,
                        error: serde_json::to_string(&WireDriverError::from(&e))
                            .unwrap_or_default(),
                        cloud: PointCloud2::from_cloud(
                            &tabula_geom::PointCloud::unorganized(Vec::new()),
                            None,
                            Header::default(),
                        ),
                        world_from_camera: Transform::from_pose(&tabula_geom::Pose::IDENTITY),
                    },
                };
                r.reply(&answer);
            }
            Work::Trajectory(msg) => {
                let result = msg
                    .to_trajectory()
                    .map_err(|e| DriverError::BadTrajectory(e.to_string()))
                    .and_then(|t| self.driver.execute(&t));
                if let Err(e) = result {
                    tracing::warn!("joint_trajectory: {e}");
                }
                self.publish_state();
            }
            Work::Gripper(name, cmd) => {
                let result = self.gripper_command(&name, cmd);
                if let Err(e) = result {
                    tracing::warn!("{name}/gripper_command: {e}");
                }
                self.publish_state();
            }
        }
    }

    /// control_msgs' gripper command: a gap at least half open opens, else closes
    /// (with the effort limit when one is given).
    fn gripper_command(&mut self, name: &str, cmd: GripperCommand) -> Result<(), DriverError> {
        if !(cmd.position.is_finite() && cmd.max_effort.is_finite()) {
            return Err(DriverError::NonFinite);
        }
        let r = self.driver.world.robot(self.driver.robot_name())?;
        let g = r
            .description
            .grippers
            .iter()
            .find(|g| g.name == name)
            .ok_or_else(|| DriverError::Hardware(format!("no gripper `{name}`")))?;
        if cmd.position >= 0.5 * (g.open_width + g.closed_width) {
            self.driver.open(name)
        } else if cmd.max_effort > 0.0 {
            self.driver
                .close_with_effort(name, cmd.max_effort)
                .map(|_| ())
        } else {
            self.driver.close(name).map(|_| ())
        }
    }

    fn command(&mut self, request: &CallRequest) -> Result<Answer, DriverError> {
        let command: Command = serde_json::from_str(&request.request)
            .map_err(|e| DriverError::Hardware(format!("not a driver command: {e}")))?;
        let d = &mut self.driver;
        Ok(match command {
            Command::Describe => Answer::Description(Description {
                robot: d.robot_name().to_string(),
                cameras: self.clouds.iter().map(|(c, _)| c.clone()).collect(),
                time: d.world.time(),
            }),
            Command::JointState => Answer::joint_state(&d.joint_state()?),
            Command::WorldFromRoot => Answer::Pose {
                pose: pose_to_array(&d.world_from_root()?),
            },
            Command::Execute {
                joint_names,
                times,
                positions,
            } => {
                d.execute(&tabula_robot::driver::JointTrajectory {
                    joint_names,
                    times,
                    positions,
                })?;
                Answer::Done
            }
            Command::Open { gripper } => {
                d.open(&gripper)?;
                Answer::Done
            }
            Command::OpenSlowly { gripper, speed } => {
                d.open_slowly(&gripper, speed)?;
                Answer::Done
            }
            Command::Close { gripper, effort } => Answer::grip(match effort {
                Some(e) => d.close_with_effort(&gripper, e)?,
                None => d.close(&gripper)?,
            }),
            Command::GripState { gripper } => Answer::grip(d.grip_state(&gripper)?),
            Command::LookAt { point } => {
                let p = Vec3::from_array(point);
                if !p.is_finite() {
                    return Err(DriverError::NonFinite);
                }
                Answer::Angle { rad: d.look_at(p)? }
            }
            Command::DriveTo { x, y, theta } => {
                d.drive_to(x, y, theta)?;
                Answer::Done
            }
            Command::Annotate { label } => {
                d.annotate(&label);
                Answer::Done
            }
            Command::Scene => {
                Answer::Scene {
                    toml: d.world.to_scene().to_toml().map_err(|e| {
                        DriverError::Hardware(format!("cannot write the scene: {e}"))
                    })?,
                }
            }
        })
    }

    /// Captures `camera` (the next noise seed, as the simulator's own driver does),
    /// publishes the frame on `/<camera>/points` and returns it.
    fn capture(&mut self, camera: &str) -> Result<(PointCloud2, Transform), DriverError> {
        let cam = self.driver.world.camera(camera)?;
        let seed = self.driver.next_noise_seed();
        let frame = tabula_sim::camera::capture(&self.driver.world, &cam, seed);
        let colors: Vec<[u8; 3]> = frame
            .labels
            .iter()
            .map(|&l| {
                let c = l
                    .checked_sub(1)
                    .and_then(|i| self.driver.world.entities.get(i as usize))
                    .map_or([0.7; 3], |e| e.color);
                c.map(|v| (v * 255.0).clamp(0.0, 255.0) as u8)
            })
            .collect();
        let msg = PointCloud2::from_cloud(
            &frame.cloud,
            Some(&colors),
            header(self.driver.world.time(), &format!("{camera}_optical_frame")),
        );
        if let Some((_, publisher)) = self.clouds.iter().find(|(c, _)| c == camera)
            && let Err(e) = publisher.publish(&msg)
        {
            tracing::warn!("{camera}/points: {e}");
        }
        Ok((msg, Transform::from_pose(&frame.world_from_camera)))
    }

    /// `/joint_states`, and `/tf` with the world → root transform and every link's
    /// pose in the world (a flat tree: each link a child of `world`).
    fn publish_state(&self) {
        let d = &self.driver;
        let Ok(state) = d.joint_state() else {
            return;
        };
        let msg = JointStateMsg {
            header: header(state.stamp, ""),
            name: state.names.clone(),
            position: state.positions.clone(),
            velocity: Vec::new(),
            effort: Vec::new(),
        };
        if let Err(e) = self.joint_states.publish(&msg) {
            tracing::warn!("joint_states: {e}");
        }
        let Ok(robot) = d.world.robot(d.robot_name()) else {
            return;
        };
        let transforms = robot
            .model
            .links
            .iter()
            .filter_map(|l| {
                let pose = d.world.link_pose(d.robot_name(), &l.name).ok()?;
                Some(TransformStamped {
                    header: header(state.stamp, "world"),
                    child_frame_id: l.name.clone(),
                    transform: Transform::from_pose(&pose),
                })
            })
            .collect();
        if let Err(e) = self.tf.publish(&TfMessage { transforms }) {
            tracing::warn!("tf: {e}");
        }
    }
}
