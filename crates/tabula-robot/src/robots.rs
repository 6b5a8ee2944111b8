//! The robots shipped in `robots/`, compiled into the binary so `tabula` runs anywhere.

use crate::description::RobotDescription;
use crate::{RobotError, RobotModel};
use std::path::Path;
use tabula_geom::input::Format;

/// Golem-III (seed 001): torso lift and rotation, two arms per SPEC §2.1, pan/tilt head.
pub const GOLEM3_URDF: &str = include_str!("../../../robots/golem3.urdf");
/// A Barrett WAM-like 7-DOF arm with seed 002's gripper (SPEC §3, §6).
pub const WAM_URDF: &str = include_str!("../../../robots/wam.urdf");
/// A PR2-like mobile manipulator with seed 000's gripper boxes (SPEC §1, §6).
pub const PR2_URDF: &str = include_str!("../../../robots/pr2.urdf");

const GOLEM3_TOML: &str = include_str!("../../../robots/golem3.toml");
const WAM_TOML: &str = include_str!("../../../robots/wam.toml");
const PR2_TOML: &str = include_str!("../../../robots/pr2.toml");

/// A loaded robot with its description (groups, grippers, head, base).
#[derive(Debug, Clone)]
pub struct NamedRobot {
    pub model: RobotModel,
    pub description: RobotDescription,
    /// The chain the tools use when none is named: the first arm's.
    pub default_base: String,
    pub default_tip: String,
    /// `golem3`, `wam`, `pr2`, or the file path.
    pub label: String,
}

impl NamedRobot {
    /// A robot from its model and description.
    pub fn new(model: RobotModel, description: RobotDescription, label: &str) -> Self {
        let (default_base, default_tip) = description
            .arms
            .first()
            .map(|a| (a.base.clone(), a.tip.clone()))
            .unwrap_or_default();
        Self {
            model,
            description,
            default_base,
            default_tip,
            label: label.into(),
        }
    }
}

/// Loads `golem3`, `wam`, `pr2`, or a URDF or xacro file path. A file's description is
/// the `<stem>.toml` beside it when there is one (for `arm.urdf.xacro`: `arm.urdf.toml`
/// or `arm.toml`); otherwise one arm runs from its root to its deepest leaf.
pub fn load(name_or_path: &str) -> Result<NamedRobot, RobotError> {
    let builtin = |urdf: &str, toml: &str| -> Result<NamedRobot, RobotError> {
        let model = RobotModel::from_urdf_str(urdf, None)?;
        let description = RobotDescription::from_toml(toml, &model)?;
        Ok(NamedRobot::new(model, description, name_or_path))
    };
    match name_or_path {
        "golem3" => builtin(GOLEM3_URDF, GOLEM3_TOML),
        "wam" => builtin(WAM_URDF, WAM_TOML),
        "pr2" => builtin(PR2_URDF, PR2_TOML),
        path if Path::new(path)
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("urdf") || e.eq_ignore_ascii_case("xacro"))
            || Path::new(path).exists() =>
        {
            let model = RobotModel::from_urdf_file(path)?;
            // `arm.urdf` → `arm.toml`; `arm.urdf.xacro` → `arm.urdf.toml` or `arm.toml`.
            let p = Path::new(path);
            let stem = p.with_extension("");
            let beside = [p.with_extension("toml"), stem.with_extension("toml")]
                .into_iter()
                .find(|c| c.is_file())
                .unwrap_or_else(|| p.with_extension("toml"));
            let description = if beside.is_file() {
                let text = tabula_geom::input::read_text(&beside, Format::Robot)?;
                RobotDescription::from_toml(&text, &model)
                    .map_err(|e| RobotError::Description(format!("{}: {e}", beside.display())))?
            } else {
                RobotDescription::minimal(&model, &model.name)
            };
            Ok(NamedRobot::new(model, description, path))
        }
        other => Err(RobotError::UnknownRobot(other.into())),
    }
}
