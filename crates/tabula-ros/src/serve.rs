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
    DRIVER_SERVICE, Description, JudgedTask, WireDriverError, ground, pose_from_array,
    pose_to_array,
};
use crate::wire::Qos;
use std::sync::Arc;
use std::sync::mpsc::{Receiver, Sender, channel};
use std::time::{Duration, Instant};
use tabula_geom::Vec2;
use tabula_geom::Vec3;
use tabula_robot::driver::{
    Annotations, Arms, BaseControl, DriverError, Grippers, HeadControl, JointStates,
};
use tabula_sim::judge::{self, ClearJudge, PlacementJudge, StablePlaceJudge, TidyStart};
use tabula_sim::{PhysicsParams, SimDriver, SimWorld};

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
    robot: String,
    /// Camera noise seed of commands outside judged runs (judged runs bring theirs).
    seed: u64,
    /// Noise seeds of the frames published on the server's own schedule: apart from
    /// the driver's, so that publishing never changes what a task's captures see.
    frame_seed: u64,
    work: Receiver<Work>,
    joint_states: Publisher<JointStateMsg>,
    tf: Publisher<TfMessage>,
    clouds: Vec<(String, Publisher<PointCloud2>)>,
    _endpoints: (Vec<Service>, Vec<Subscription>),
    rates: Rates,
    next_state: Instant,
    next_camera: Instant,
}

/// Why the command loop handed control back.
enum End {
    Stopped,
    /// A judged run's client went quiet for [`ABANDONED_AFTER`]: it crashed or lost
    /// the network, and the robot must not wait for it forever.
    Abandoned,
    Begin(Request<CallRequest>, JudgedTask),
    Finish(Request<CallRequest>, Option<[f64; 7]>),
}

/// How long a judged run waits for its client's next command.
const ABANDONED_AFTER: Duration = Duration::from_secs(300);

/// A clearing judge's hook, or none.
type Hook<'a> = dyn FnMut(&mut SimDriver, Option<(Vec3, Vec<Vec3>)>) + 'a;

fn reply_ok(r: Request<CallRequest>, answer: &Answer) {
    r.reply(&CallResponse {
        ok: true,
        response: serde_json::to_string(answer).unwrap_or_default(),
    });
}

fn reply_err(r: Request<CallRequest>, e: &DriverError) {
    r.reply(&CallResponse {
        ok: false,
        response: serde_json::to_string(&WireDriverError::from(e)).unwrap_or_default(),
    });
}

fn sim_err(e: tabula_sim::SimError) -> RosError {
    RosError::Zenoh(e.to_string())
}

fn header(stamp: f64, frame: &str) -> Header {
    Header {
        stamp: Time::from_secs(stamp),
        frame_id: frame.into(),
    }
}

impl Server {
    /// A server for robot `robot` of `world` (its arms, grippers and cameras become
    /// topics); camera noise outside judged runs starts from `seed`.
    pub fn new(
        world: &SimWorld,
        robot: &str,
        seed: u64,
        config: NodeConfig,
        rates: Rates,
    ) -> Result<Self, RosError> {
        let description = world.robot(robot).map_err(sim_err)?.description.clone();
        let cameras: Vec<String> = world.cameras.iter().map(|c| c.name.to_string()).collect();
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
            robot: robot.into(),
            seed,
            frame_seed: seed ^ 0x005E_EDF4_A3E5_u64,
            work,
            joint_states,
            tf,
            clouds,
            _endpoints: (services, subscriptions),
            rates,
            next_state: Instant::now(),
            next_camera: Instant::now(),
        })
    }

    /// The driver of the served robot, stepping trajectories one physics step at a
    /// time as every judged run does (its watch is an observer), so that a task
    /// driven from another process meets the same physics as in one.
    fn driver(&self, world: SimWorld, seed: u64) -> Result<SimDriver, RosError> {
        let mut driver = SimDriver::new(world, &self.robot, seed).map_err(sim_err)?;
        driver.observe(|_| {});
        Ok(driver)
    }

    /// Serves `world` until `stop()` says so (checked at least every 50 ms); judged
    /// runs begin and end as clients ask. Returns the world as it is then.
    pub fn serve(
        &mut self,
        world: SimWorld,
        stop: &dyn Fn() -> bool,
    ) -> Result<SimWorld, RosError> {
        let mut world = world;
        loop {
            let mut driver = self.driver(world, self.seed)?;
            let end = self.run_loop(&mut driver, false, None, stop);
            world = driver.world;
            match end {
                End::Stopped => return Ok(world),
                End::Abandoned => {}
                End::Finish(r, _) => {
                    reply_err(r, &DriverError::Hardware("no judged run has begun".into()))
                }
                End::Begin(r, task) => world = self.judged(world, task, r, stop)?,
            }
        }
    }

    /// One judged run: the runner the CLI uses in one process wraps the command loop,
    /// so the same judge watches the same physics; `finish` gets the verdict.
    fn judged(
        &mut self,
        world: SimWorld,
        task: JudgedTask,
        begin: Request<CallRequest>,
        stop: &dyn Fn() -> bool,
    ) -> Result<SimWorld, RosError> {
        let ground = match Ground::of(&task) {
            Ok(g) => g,
            Err(e) => {
                reply_err(
                    begin,
                    &DriverError::Hardware(format!("cannot judge this run: {e}")),
                );
                return Ok(world);
            }
        };
        // A runner that refuses the world (a hand holding nothing, an unknown bin)
        // consumes it: keep the scene to rebuild it.
        let backup = world.to_scene();
        let robot = self.robot.clone();
        let mut begin = Some(begin);
        let mut finish: Option<Request<CallRequest>> = None;
        let mut serve_task =
            |server: &mut Self, driver: &mut SimDriver, hook: Option<&mut Hook<'_>>| {
                if let Some(r) = begin.take() {
                    reply_ok(r, &Answer::Begun);
                }
                match server.run_loop(driver, true, hook, stop) {
                    End::Finish(r, planned) => {
                        finish = Some(r);
                        planned.and_then(|p| pose_from_array(&p))
                    }
                    _ => None,
                }
            };
        let seed = task.seed;
        let judged = match ground {
            Ground::Place => {
                let judge = |w: &SimWorld| StablePlaceJudge::new(w, &robot);
                judge::run(world, &robot, seed, judge, |d, _| {
                    ((), serve_task(self, d, None))
                })
                .map(|((), v, w)| (serde_json::to_value(v), w))
            }
            Ground::PickPlace(g) => {
                let (pick, target) = (Vec3::from_array(g.pick), Vec2::new(g.place[0], g.place[1]));
                let judge = |w: &SimWorld| PlacementJudge::new(w, &robot, pick, target);
                judge::run(world, &robot, seed, judge, |d, _| {
                    serve_task(self, d, None);
                    ((), ())
                })
                .map(|((), v, w)| (serde_json::to_value(v), w))
            }
            Ground::Clear(g) => {
                let judge = |w: &SimWorld| ClearJudge::new(w, &robot, (&g.table, &g.bin));
                judge::run(world, &robot, seed, judge, |d, hook| {
                    serve_task(self, d, Some(hook));
                    ((), ())
                })
                .map(|((), v, w)| (serde_json::to_value(v), w))
            }
            Ground::Tidy(g) => {
                let judge = |w: &SimWorld| TidyStart::of(w, &g.source);
                judge::run(world, &robot, seed, judge, |d, _| {
                    serve_task(self, d, None);
                    ((), ())
                })
                .map(|((), v, w)| (serde_json::to_value(v), w))
            }
        };
        match judged {
            Ok((verdict, world)) => {
                if let Some(r) = finish {
                    match verdict {
                        Ok(verdict) => reply_ok(r, &Answer::Verdict { verdict }),
                        Err(e) => reply_err(r, &DriverError::Hardware(e.to_string())),
                    }
                }
                Ok(world)
            }
            Err(e) => {
                let e = DriverError::Hardware(format!("cannot judge this run: {e}"));
                if let Some(r) = begin.take().or(finish) {
                    reply_err(r, &e);
                }
                SimWorld::from_scene(&backup, PhysicsParams::default()).map_err(sim_err)
            }
        }
    }

    /// Does the work that arrives, in order, until `stop()`, or a judged run begins
    /// (outside one) or finishes (inside one: `hook` is then its clearing judge, if
    /// any).
    fn run_loop(
        &mut self,
        driver: &mut SimDriver,
        judged: bool,
        mut hook: Option<&mut Hook<'_>>,
        stop: &dyn Fn() -> bool,
    ) -> End {
        let period = |hz: f64| (hz > 0.0).then(|| Duration::from_secs_f64(1.0 / hz));
        let (state_period, camera_period) =
            (period(self.rates.state_hz), period(self.rates.camera_hz));
        let mut last_work = Instant::now();
        while !stop() {
            if judged && last_work.elapsed() > ABANDONED_AFTER {
                tracing::warn!("the judged run's client went quiet: run abandoned");
                return End::Abandoned;
            }
            let work = self.work.recv_timeout(Duration::from_millis(50));
            if work.is_ok() {
                last_work = Instant::now();
            }
            match work {
                Ok(Work::Call(r)) => match serde_json::from_str::<Command>(&r.request.request) {
                    Ok(Command::Begin { task }) if !judged => return End::Begin(r, task),
                    Ok(Command::Finish { planned }) if judged => return End::Finish(r, planned),
                    Ok(Command::Begin { .. }) => reply_err(
                        r,
                        &DriverError::Hardware("a judged run is already under way".into()),
                    ),
                    Ok(Command::ClearEvent { target, shoved }) => {
                        if let Some(h) = hook.as_mut() {
                            h(
                                driver,
                                target.map(|t| {
                                    (
                                        Vec3::from_array(t),
                                        shoved.iter().map(|s| Vec3::from_array(*s)).collect(),
                                    )
                                }),
                            );
                        }
                        reply_ok(r, &Answer::Done);
                    }
                    Ok(command) => {
                        match self.command(driver, command) {
                            Ok(a) => reply_ok(r, &a),
                            Err(e) => reply_err(r, &e),
                        }
                        self.publish_state(driver);
                    }
                    Err(e) => reply_err(
                        r,
                        &DriverError::Hardware(format!("not a driver command: {e}")),
                    ),
                },
                Ok(work) => self.handle(driver, work),
                Err(std::sync::mpsc::RecvTimeoutError::Timeout) => {}
                Err(std::sync::mpsc::RecvTimeoutError::Disconnected) => return End::Stopped,
            }
            let now = Instant::now();
            if let Some(p) = state_period
                && now >= self.next_state
            {
                self.publish_state(driver);
                self.next_state = now + p;
            }
            if let Some(p) = camera_period
                && now >= self.next_camera
            {
                for k in 0..self.clouds.len() {
                    let camera = self.clouds[k].0.clone();
                    self.frame_seed = self.frame_seed.wrapping_add(1);
                    let _ = self.capture(driver, &camera, self.frame_seed);
                }
                self.next_camera = now + p;
            }
        }
        End::Stopped
    }

    /// The ROS-facing topics' commands (fire and forget, as joint_trajectory_controller
    /// and the gripper controllers take them) and frame requests.
    fn handle(&mut self, driver: &mut SimDriver, work: Work) {
        match work {
            Work::Call(r) => reply_err(r, &DriverError::Hardware("unexpected call".into())),
            Work::Capture(r) => {
                let seed = driver.next_noise_seed();
                let answer = match self.capture(driver, &r.request.camera, seed) {
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
                    .and_then(|t| driver.execute(&t));
                if let Err(e) = result {
                    tracing::warn!("joint_trajectory: {e}");
                }
                self.publish_state(driver);
            }
            Work::Gripper(name, cmd) => {
                if let Err(e) = gripper_command(driver, &name, cmd) {
                    tracing::warn!("{name}/gripper_command: {e}");
                }
                self.publish_state(driver);
            }
        }
    }

    fn command(&self, d: &mut SimDriver, command: Command) -> Result<Answer, DriverError> {
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
            Command::OpenTo { gripper, width } => {
                d.open_to(&gripper, width)?;
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
            Command::Begin { .. } | Command::Finish { .. } | Command::ClearEvent { .. } => {
                return Err(DriverError::Hardware("not a plain command".into()));
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
    fn capture(
        &self,
        driver: &SimDriver,
        camera: &str,
        seed: u64,
    ) -> Result<(PointCloud2, Transform), DriverError> {
        let cam = driver.world.camera(camera)?;
        let frame = tabula_sim::camera::capture(&driver.world, &cam, seed);
        let colors: Vec<[u8; 3]> = frame
            .labels
            .iter()
            .map(|&l| {
                let c = l
                    .checked_sub(1)
                    .and_then(|i| driver.world.entities.get(i as usize))
                    .map_or([0.7; 3], |e| e.color);
                c.map(|v| (v * 255.0).clamp(0.0, 255.0) as u8)
            })
            .collect();
        let msg = PointCloud2::from_cloud(
            &frame.cloud,
            Some(&colors),
            header(driver.world.time(), &camera_frame(driver, camera)),
        );
        if let Some((_, publisher)) = self.clouds.iter().find(|(c, _)| c == camera)
            && let Err(e) = publisher.publish(&msg)
        {
            tracing::warn!("{camera}/points: {e}");
        }
        Ok((msg, Transform::from_pose(&frame.world_from_camera)))
    }

    /// `/joint_states`, and `/tf` as robot_state_publisher gives it: `world` → the
    /// URDF's root (where the base stands), then every joint's parent → child link.
    fn publish_state(&self, d: &SimDriver) {
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
        let model = &robot.model;
        let pose = |link: usize| d.world.link_pose(d.robot_name(), &model.links[link].name);
        let stamped = |parent: &str, child: &str, p: &tabula_geom::Pose| TransformStamped {
            header: header(state.stamp, parent),
            child_frame_id: child.into(),
            transform: Transform::from_pose(p),
        };
        let mut transforms: Vec<TransformStamped> = model
            .roots
            .iter()
            .filter_map(|&r| Some(stamped("world", &model.links[r].name, &pose(r).ok()?)))
            .collect();
        // Cameras not on the robot's links: their optical frames, fixed in the world.
        transforms.extend(self.clouds.iter().filter_map(|(camera, _)| {
            let frame = camera_frame(d, camera);
            if model.link(&frame).is_ok() {
                return None;
            }
            let cam = d.world.camera(camera).ok()?;
            Some(stamped("world", &frame, &cam.world_from_camera))
        }));
        transforms.extend(model.joints.iter().filter_map(|j| {
            let parent_from_child = pose(j.parent).ok()?.inverse() * pose(j.child).ok()?;
            Some(stamped(
                &model.links[j.parent].name,
                &model.links[j.child].name,
                &parent_from_child,
            ))
        }));
        if let Err(e) = self.tf.publish(&TfMessage { transforms }) {
            tracing::warn!("tf: {e}");
        }
    }
}

/// The TF frame a camera's clouds are in: the link it is mounted on (its optical
/// frame: z forward, x right, y down), or `<camera>_optical_frame` for a camera fixed in
/// the world (published under `world`).
fn camera_frame(d: &SimDriver, camera: &str) -> String {
    d.world
        .cameras
        .iter()
        .find(|c| c.name.get_ref() == camera)
        .and_then(|c| match (&c.robot, &c.link) {
            (Some(r), Some(link)) if r == d.robot_name() => Some(link.clone()),
            _ => None,
        })
        .unwrap_or_else(|| format!("{camera}_optical_frame"))
}

/// control_msgs' gripper command: a gap at least half open opens, else closes (with the
/// effort limit when one is given).
fn gripper_command(d: &mut SimDriver, name: &str, cmd: GripperCommand) -> Result<(), DriverError> {
    if !(cmd.position.is_finite() && cmd.max_effort.is_finite()) {
        return Err(DriverError::NonFinite);
    }
    let r = d.world.robot(d.robot_name())?;
    let g = r
        .description
        .grippers
        .iter()
        .find(|g| g.name == name)
        .ok_or_else(|| DriverError::Hardware(format!("no gripper `{name}`")))?;
    if cmd.position >= 0.5 * (g.open_width + g.closed_width) {
        d.open(name)
    } else if cmd.max_effort > 0.0 {
        d.close_with_effort(name, cmd.max_effort).map(|_| ())
    } else {
        d.close(name).map(|_| ())
    }
}

/// What a judged run's judge is told, by task.
enum Ground {
    Place,
    PickPlace(ground::PickPlace),
    Clear(ground::Clear),
    Tidy(ground::Tidy),
}

impl Ground {
    /// The ground of `task`, read by its name; a message when the server has no judge
    /// for that name or the ground is not the task's.
    fn of(task: &JudgedTask) -> Result<Self, String> {
        match task.task.as_str() {
            "place" => Ok(Ground::Place),
            "pick-place" => task.ground().map(Ground::PickPlace),
            "clear" => task.ground().map(Ground::Clear),
            "tidy" => task.ground().map(Ground::Tidy),
            other => Err(format!(
                "no judge for a task `{other}` (judged here: place, pick-place, clear, tidy)"
            )),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn judged_runs_are_asked_by_task_name_with_a_json_ground() {
        let clear = JudgedTask::new(
            "clear",
            7,
            ground::Clear {
                table: "table".into(),
                bin: "bin".into(),
            },
        );
        let wire = serde_json::to_string(&Command::Begin { task: clear }).unwrap();
        assert!(wire.contains("\"task\":\"clear\""), "{wire}");
        let Command::Begin { task } = serde_json::from_str(&wire).unwrap() else {
            panic!("{wire}")
        };
        assert!(matches!(Ground::of(&task), Ok(Ground::Clear(g)) if g.bin == "bin"));
        assert!(matches!(
            Ground::of(&JudgedTask::new("place", 1, ())),
            Ok(Ground::Place)
        ));
        let tidy = JudgedTask::new(
            "tidy",
            1,
            ground::Tidy {
                source: "desk".into(),
            },
        );
        assert!(matches!(Ground::of(&tidy), Ok(Ground::Tidy(g)) if g.source == "desk"));
        // A name with no judge, and a ground that is not the task's, say so.
        let e = Ground::of(&JudgedTask::new("dance", 1, ())).err().unwrap();
        assert!(e.contains("`dance`") && e.contains("pick-place"), "{e}");
        let e = Ground::of(&JudgedTask::new(
            "pick-place",
            1,
            ground::Tidy { source: "x".into() },
        ))
        .err()
        .unwrap();
        assert!(e.contains("pick-place") && e.contains("ground"), "{e}");
    }
}
