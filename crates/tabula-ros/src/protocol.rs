//! tabula's driver service (`/tabula/driver`, type `tabula_msgs/srv/Call`): every
//! driver-trait command as one JSON request, its answer or a typed error as the JSON
//! response. Camera frames travel apart, as CDR `sensor_msgs/msg/PointCloud2` in
//! `/tabula/capture` (`tabula_msgs/srv/Capture`): 5 MB of JSON per frame would not do.

use serde::{Deserialize, Serialize};
use tabula_geom::{Pose, Quat, Vec3};
use tabula_robot::driver::{DriverError, GripState, JointState, JointTrajectory};

/// The driver service's name.
pub const DRIVER_SERVICE: &str = "/tabula/driver";
/// The capture service's name.
pub const CAPTURE_SERVICE: &str = "/tabula/capture";
pub const CALL_TYPE: &str = "tabula_msgs/srv/Call";
pub const CAPTURE_TYPE: &str = "tabula_msgs/srv/Capture";
pub const PERCEIVE_TYPE: &str = "tabula_msgs/srv/Perceive";

/// One command of the driver traits.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "op", rename_all = "snake_case")]
pub enum Command {
    /// Which robot is served, its cameras, and the clock.
    Describe,
    JointState,
    WorldFromRoot,
    Execute {
        joint_names: Vec<String>,
        times: Vec<f64>,
        positions: Vec<Vec<f64>>,
    },
    Open {
        gripper: String,
    },
    OpenSlowly {
        gripper: String,
        speed: f64,
    },
    OpenTo {
        gripper: String,
        width: f64,
    },
    Close {
        gripper: String,
        effort: Option<f64>,
    },
    GripState {
        gripper: String,
    },
    LookAt {
        point: [f64; 3],
    },
    DriveTo {
        x: f64,
        y: f64,
        theta: f64,
    },
    Annotate {
        label: String,
    },
    /// The served world as a scene file (TOML): what `--save-scene` writes.
    Scene,
    /// Starts a run the server judges from its ground truth, as a run in one process
    /// is judged: the commands that follow are the task's, until `finish`.
    Begin {
        task: JudgedTask,
    },
    /// A clearing task's moment for its judge: before an action (where the target and
    /// what it shoves were seen) or, with no target, after it.
    ClearEvent {
        target: Option<[f64; 3]>,
        shoved: Vec<[f64; 3]>,
    },
    /// Ends the judged run; a placing task gives the object's planned resting pose
    /// (x y z qx qy qz qw). The answer is the verdict.
    Finish {
        planned: Option<[f64; 7]>,
    },
}

/// A judged run a server is asked to start: the task's name (its `Task::NAME`:
/// `place`, `pick-place`, `clear`, `tidy`), the camera-noise seed, and what its judge
/// must know of the workcell besides the world, as JSON (see [`ground`]). A name the
/// server has no judge for is refused with the names it has.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct JudgedTask {
    pub task: String,
    pub seed: u64,
    #[serde(default)]
    pub ground: serde_json::Value,
}

impl JudgedTask {
    pub fn new(task: &str, seed: u64, ground: impl Serialize) -> Self {
        Self {
            task: task.into(),
            seed,
            ground: serde_json::to_value(ground).unwrap_or(serde_json::Value::Null),
        }
    }

    /// The judge's ground as the task's type; a message naming the task when it is not.
    pub fn ground<T: serde::de::DeserializeOwned>(&self) -> Result<T, String> {
        serde_json::from_value(self.ground.clone())
            .map_err(|e| format!("`{}`'s judge cannot read its ground: {e}", self.task))
    }
}

/// What each task's judge is told besides the world.
pub mod ground {
    use serde::{Deserialize, Serialize};

    /// Pick and place: where the object is picked and where it goes (world, m).
    #[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
    pub struct PickPlace {
        pub pick: [f64; 3],
        pub place: [f64; 3],
    }

    /// Clearing: the furniture cleared and the bin it is cleared into.
    #[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
    pub struct Clear {
        pub table: String,
        pub bin: String,
    }

    /// Tidying: the furniture cleared.
    #[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
    pub struct Tidy {
        pub source: String,
    }
}

/// What `describe` answers.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Description {
    pub robot: String,
    pub cameras: Vec<String>,
    pub time: f64,
}

/// The answers, one shape per command kind.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Answer {
    Done,
    Description(Description),
    JointState {
        names: Vec<String>,
        positions: Vec<f64>,
        stamp: f64,
    },
    Pose {
        pose: [f64; 7],
    },
    Grip {
        width: f64,
        holding: bool,
    },
    Angle {
        rad: f64,
    },
    Scene {
        toml: String,
    },
    /// A judged run began.
    Begun,
    /// A judged run's verdict (the task's verdict type, as JSON).
    Verdict {
        verdict: serde_json::Value,
    },
}

/// A driver error as it crosses the wire.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "error", rename_all = "snake_case")]
pub enum WireDriverError {
    Blocked { by: String, link: String },
    UnknownJoint { joint: String },
    NonFinite,
    BadTrajectory { message: String },
    Unsupported { what: String },
    Hardware { message: String },
    Stopped,
}

impl From<&DriverError> for WireDriverError {
    fn from(e: &DriverError) -> Self {
        match e {
            DriverError::Blocked { by, link } => Self::Blocked {
                by: by.clone(),
                link: link.clone(),
            },
            DriverError::UnknownJoint(j) => Self::UnknownJoint { joint: j.clone() },
            DriverError::NonFinite => Self::NonFinite,
            DriverError::BadTrajectory(m) => Self::BadTrajectory { message: m.clone() },
            DriverError::Unsupported(w) => Self::Unsupported {
                what: (*w).to_string(),
            },
            DriverError::Hardware(m) => Self::Hardware { message: m.clone() },
            DriverError::Stopped => Self::Stopped,
        }
    }
}

impl From<WireDriverError> for DriverError {
    fn from(e: WireDriverError) -> Self {
        match e {
            WireDriverError::Blocked { by, link } => DriverError::Blocked { by, link },
            WireDriverError::UnknownJoint { joint } => DriverError::UnknownJoint(joint),
            WireDriverError::NonFinite => DriverError::NonFinite,
            WireDriverError::BadTrajectory { message } => DriverError::BadTrajectory(message),
            // The trait's `Unsupported` names a static part; the few parts a robot can
            // lack are named here so the message survives the trip.
            WireDriverError::Unsupported { what } => {
                DriverError::Unsupported(match what.as_str() {
                    "head" => "head",
                    "mobile base" => "mobile base",
                    "camera" => "camera",
                    _ => "such part",
                })
            }
            WireDriverError::Hardware { message } => DriverError::Hardware(message),
            WireDriverError::Stopped => DriverError::Stopped,
        }
    }
}

pub fn pose_to_array(p: &Pose) -> [f64; 7] {
    let (t, q) = (p.translation, p.rotation);
    [t.x, t.y, t.z, q.x, q.y, q.z, q.w]
}

/// A pose from `[x y z qx qy qz qw]`, the rotation normalised; `None` if not finite.
pub fn pose_from_array(a: &[f64; 7]) -> Option<Pose> {
    let q = Quat::from_xyzw(a[3], a[4], a[5], a[6]);
    let len = q.length();
    let t = Vec3::new(a[0], a[1], a[2]);
    (len.is_finite() && len > 1e-9 && t.is_finite()).then(|| Pose::from_parts(t, q / len))
}

impl Command {
    /// Whether the command moves the robot (refused once the operator stopped it;
    /// reading state, annotating and ending a judged run still go through).
    pub fn moves(&self) -> bool {
        matches!(
            self,
            Command::Execute { .. }
                | Command::Open { .. }
                | Command::OpenSlowly { .. }
                | Command::OpenTo { .. }
                | Command::Close { .. }
                | Command::LookAt { .. }
                | Command::DriveTo { .. }
                | Command::Begin { .. }
        )
    }

    pub fn execute(t: &JointTrajectory) -> Self {
        Command::Execute {
            joint_names: t.joint_names.clone(),
            times: t.times.clone(),
            positions: t.positions.clone(),
        }
    }
}

impl Answer {
    pub fn joint_state(s: &JointState) -> Self {
        Answer::JointState {
            names: s.names.clone(),
            positions: s.positions.clone(),
            stamp: s.stamp,
        }
    }

    pub fn grip(g: GripState) -> Self {
        Answer::Grip {
            width: g.width,
            holding: g.holding,
        }
    }
}

/// `tabula_msgs/srv/Capture` request.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CaptureRequest {
    pub camera: String,
}

/// `tabula_msgs/srv/Capture` response: the frame (optical frame, organized), where the
/// camera was, or why there is none.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CaptureResponse {
    pub ok: bool,
    pub error: String,
    pub cloud: crate::msgs::PointCloud2,
    pub world_from_camera: crate::msgs::Transform,
}

/// `tabula_msgs/srv/Perceive` request: a cloud, and where it was taken when known
/// (else its frame is found from the cloud: an optical frame's support plane).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PerceiveRequest {
    pub cloud: crate::msgs::PointCloud2,
    pub has_pose: bool,
    pub world_from_cloud: crate::msgs::Transform,
}
