//! Robot descriptions: what MoveIt's SRDF says beside a URDF — arm groups with their IK
//! solver and named poses, grippers, the head and its camera, the mobile base — as TOML
//! next to the URDF. The built-in robots carry theirs (`robots/*.toml`); a user URDF
//! reads `<stem>.toml` beside it when there is one, and otherwise gets one arm from its
//! root to its deepest leaf. Every joint and link name the task layer uses comes from
//! here, so no other crate spells a robot's joint names.

mod check;
mod end_effector;

pub use end_effector::{attach_grippers, gripper_from_end_effector};

use crate::ik::{ArmSide, Golem3Ik, Golem3Params, IkSolver, NumericIk, NumericIkParams};
use crate::{Chain, RobotError, RobotModel};
use std::collections::BTreeMap;
use tabula_geom::Vec3;

/// Which inverse-kinematics solver an arm uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Deserialize, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum IkKind {
    /// Damped least squares with restarts: any chain; closed form instead for full
    /// poses when the chain is UR-type (axes 2–4 parallel, 5 and 6 meeting).
    Numeric,
    /// The closed form of seed 001 (SPEC §2.2), right arm.
    Golem3Right,
    /// The closed form of seed 001 (SPEC §2.2), left arm (mirrored).
    Golem3Left,
}

/// An arm group: the chain from `base` to `tip`, its solver, its named poses.
#[derive(Debug, Clone, serde::Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct ArmGroup {
    pub name: String,
    pub base: String,
    pub tip: String,
    pub ik: IkKind,
    /// The gripper at this arm's tip (a name in `grippers`).
    pub gripper: Option<String>,
    /// Joint values of the arm folded out of the way (SRDF's `tuck_arms` state).
    #[serde(default)]
    pub tucked: BTreeMap<String, f64>,
    /// Named joint values of this arm (SRDF's group states: `ready`, `home`, …).
    #[serde(default)]
    pub named: BTreeMap<String, BTreeMap<String, f64>>,
}

/// An axis-aligned box in a link's frame (m): SPEC §6's gripper self-filter boxes.
#[derive(Debug, Clone, Copy, PartialEq, serde::Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct LinkBox {
    pub center: [f64; 3],
    pub size: [f64; 3],
}

/// A parallel gripper: one finger joint drives both fingers (the other mimics it).
#[derive(Debug, Clone, serde::Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct Gripper {
    pub name: String,
    /// The grasp frame: x is the approach direction, y the closing direction.
    pub tool_link: String,
    pub palm: String,
    pub finger_joint: String,
    pub fingers: [String; 2],
    /// Gap between the fingers at the finger joint's lower and upper limit (m).
    pub closed_width: f64,
    pub open_width: f64,
    /// Approach direction in the tool frame (x for PR2 and Golem-III, z for the WAM).
    #[serde(default = "x_axis")]
    pub approach_axis: [f64; 3],
    /// Direction the fingers close along, in the tool frame.
    #[serde(default = "y_axis")]
    pub closing_axis: [f64; 3],
    /// Boxes in the tool frame that model the gripper for the self-filter (SPEC §6).
    #[serde(default)]
    pub self_filter_boxes: Vec<LinkBox>,
}

fn x_axis() -> [f64; 3] {
    [1.0, 0.0, 0.0]
}

fn y_axis() -> [f64; 3] {
    [0.0, 1.0, 0.0]
}

impl Gripper {
    pub fn approach(&self) -> Vec3 {
        Vec3::from_array(self.approach_axis).normalize_or(Vec3::X)
    }

    pub fn closing(&self) -> Vec3 {
        Vec3::from_array(self.closing_axis).normalize_or(Vec3::Y)
    }

    /// Finger gap (m) at a finger joint value, linear between the limits' widths.
    pub fn width_at(&self, model: &RobotModel, finger_value: f64) -> f64 {
        match model.joint(&self.finger_joint) {
            Some(j) => {
                let l = model.joints[j].limits;
                let span = (l.upper - l.lower).max(1e-12);
                self.closed_width
                    + (self.open_width - self.closed_width) * (finger_value - l.lower) / span
            }
            None => f64::NAN,
        }
    }
}

/// A pan/tilt head with a depth camera.
#[derive(Debug, Clone, serde::Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct Head {
    pub pan_joint: String,
    pub tilt_joint: String,
    /// The camera's optical frame (z forward, x right, y down).
    pub camera_link: String,
}

/// A planar mobile base moved by three joints (x, y in the parent frame, heading).
#[derive(Debug, Clone, serde::Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct MobileBase {
    pub x_joint: String,
    pub y_joint: String,
    pub theta_joint: String,
}

/// Everything the task layer needs to know about a robot beyond its URDF.
#[derive(Debug, Clone, serde::Deserialize, serde::Serialize)]
#[serde(deny_unknown_fields)]
pub struct RobotDescription {
    pub name: String,
    #[serde(default, rename = "arm")]
    pub arms: Vec<ArmGroup>,
    #[serde(default, rename = "gripper")]
    pub grippers: Vec<Gripper>,
    pub head: Option<Head>,
    pub base: Option<MobileBase>,
    /// Joints of a torso that moves several groups at once (Golem-III's θ1 and lift).
    #[serde(default)]
    pub torso_joints: Vec<String>,
}

impl RobotDescription {
    /// Parses a description and checks every name against `model`.
    /// Every number is checked first (finite, within the policy's magnitude), then
    /// the names, the ranges and the axes ([`check`]), each error naming its key.
    pub fn from_toml(text: &str, model: &RobotModel) -> Result<Self, RobotError> {
        tabula_geom::input::check_toml_numbers(text).map_err(RobotError::Description)?;
        let d: Self = toml::from_str(text)
            .map_err(|e| RobotError::Description(tabula_geom::input::toml_error(text, &e)))?;
        check::check(&d, model)?;
        Ok(d)
    }

    /// One arm from the model's root to the tool it most likely has
    /// ([`RobotModel::default_tool`]), numeric IK, nothing else: what a bare URDF says.
    pub fn minimal(model: &RobotModel, name: &str) -> Self {
        let root = model.roots.first().copied().unwrap_or(0);
        let leaf = model.default_tool();
        Self {
            name: name.into(),
            arms: vec![ArmGroup {
                name: "arm".into(),
                base: model
                    .links
                    .get(root)
                    .map(|l| l.name.clone())
                    .unwrap_or_default(),
                tip: model
                    .links
                    .get(leaf)
                    .map(|l| l.name.clone())
                    .unwrap_or_default(),
                ik: IkKind::Numeric,
                gripper: None,
                tucked: BTreeMap::new(),
                named: BTreeMap::new(),
            }],
            grippers: Vec::new(),
            head: None,
            base: None,
            torso_joints: Vec::new(),
        }
    }

    /// The arm group called `name`.
    pub fn arm(&self, name: &str) -> Result<&ArmGroup, RobotError> {
        self.arms.iter().find(|a| a.name == name).ok_or_else(|| {
            RobotError::Description(format!(
                "no arm `{name}`; arms: {}",
                self.arms
                    .iter()
                    .map(|a| a.name.as_str())
                    .collect::<Vec<_>>()
                    .join(", ")
            ))
        })
    }

    /// The gripper of an arm.
    pub fn gripper_of(&self, arm: &ArmGroup) -> Option<&Gripper> {
        let g = arm.gripper.as_ref()?;
        self.grippers.iter().find(|x| &x.name == g)
    }

    /// The gripper whose `tool_link` is `link`.
    pub fn gripper_at(&self, link: &str) -> Option<&Gripper> {
        self.grippers.iter().find(|g| g.tool_link == link)
    }
}

impl ArmGroup {
    /// The configuration named `name` (SRDF group states; `tuck` for a description's
    /// tucked pose) over `joint_names`; joints it leaves out keep their value in
    /// `current`. An unknown name lists the known ones.
    pub fn named_configuration(
        &self,
        name: &str,
        joint_names: &[String],
        current: &[f64],
    ) -> Result<Vec<f64>, RobotError> {
        let named = match (self.named.get(name), name) {
            (Some(state), _) => state,
            (None, "tuck" | "tucked") if !self.tucked.is_empty() => &self.tucked,
            (None, other) => {
                let mut known: Vec<&str> = self.named.keys().map(String::as_str).collect();
                if !self.tucked.is_empty() {
                    known.push("tuck");
                }
                let known = if known.is_empty() {
                    "none".to_string()
                } else {
                    known.join(", ")
                };
                return Err(RobotError::Description(format!(
                    "no named pose `{other}` for arm `{}`; named poses: {known}",
                    self.name
                )));
            }
        };
        Ok(joint_names
            .iter()
            .zip(current)
            .map(|(n, s)| named.get(n).copied().unwrap_or(*s))
            .collect())
    }

    /// The arm's chain.
    pub fn chain(&self, model: &RobotModel) -> Result<Chain, RobotError> {
        Chain::new(model, &self.base, &self.tip)
    }

    /// The arm's own IK solver: analytic where the description says so.
    pub fn ik_solver(
        &self,
        model: &RobotModel,
        numeric: NumericIkParams,
    ) -> Result<Box<dyn IkSolver + Send + Sync>, RobotError> {
        Ok(match self.ik {
            // Closed form where the chain allows it (UR-type and spherical-wrist 6R arms),
            // numeric otherwise.
            IkKind::Numeric => Box::new(crate::ik::AutoIk::new(NumericIk::new(
                self.chain(model)?,
                numeric,
            ))),
            IkKind::Golem3Right => Box::new(Golem3Ik::new(
                model,
                ArmSide::Right,
                Golem3Params::default(),
            )?),
            IkKind::Golem3Left => Box::new(Golem3Ik::new(
                model,
                ArmSide::Left,
                Golem3Params::default(),
            )?),
        })
    }
}

impl LinkBox {
    /// True when `p` (in the box's link frame) is inside the box grown by `padding`.
    pub fn contains(&self, p: Vec3, padding: f64) -> bool {
        (0..3).all(|k| (p[k] - self.center[k]).abs() <= self.size[k] / 2.0 + padding)
    }
}
