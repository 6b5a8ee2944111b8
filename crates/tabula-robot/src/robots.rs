//! The robots shipped in `robots/`, compiled into the binary so `tabula` runs anywhere.

use crate::{RobotError, RobotModel};
use std::path::Path;

/// Golem-III (seed 001): torso lift and rotation, two arms per SPEC §2.1, pan/tilt head.
pub const GOLEM3_URDF: &str = include_str!("../../../robots/golem3.urdf");
/// A Barrett WAM-like 7-DOF arm with seed 002's gripper (SPEC §3, §6).
pub const WAM_URDF: &str = include_str!("../../../robots/wam.urdf");
/// A PR2-like mobile manipulator with seed 000's gripper boxes (SPEC §1, §6).
pub const PR2_URDF: &str = include_str!("../../../robots/pr2.urdf");

/// A loaded robot together with the chain the tools use when none is named.
#[derive(Debug, Clone)]
pub struct NamedRobot {
    pub model: RobotModel,
    pub default_base: String,
    pub default_tip: String,
    /// `golem3`, `wam`, `pr2`, or the file path.
    pub label: String,
}

/// Loads `golem3`, `wam`, `pr2`, or a URDF file path. For a file the default chain
/// runs from its root to its deepest leaf.
pub fn load(name_or_path: &str) -> Result<NamedRobot, RobotError> {
    let builtin = |urdf: &str, base: &str, tip: &str| -> Result<NamedRobot, RobotError> {
        Ok(NamedRobot {
            model: RobotModel::from_urdf_str(urdf, None)?,
            default_base: base.into(),
            default_tip: tip.into(),
            label: name_or_path.into(),
        })
    };
    match name_or_path {
        "golem3" => builtin(GOLEM3_URDF, "torso_lift_link", "right_tool_link"),
        "wam" => builtin(WAM_URDF, "base_link", "wam_tool"),
        "pr2" => builtin(PR2_URDF, "torso_lift_link", "r_gripper_tool_frame"),
        path if Path::new(path)
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("urdf"))
            || Path::new(path).exists() =>
        {
            let model = RobotModel::from_urdf_file(path)?;
            let root = model.roots.first().copied().unwrap_or(0);
            let leaf = model.deepest_leaf();
            Ok(NamedRobot {
                default_base: model.links[root].name.clone(),
                default_tip: model.links[leaf].name.clone(),
                model,
                label: path.into(),
            })
        }
        other => Err(RobotError::UnknownRobot(other.into())),
    }
}
