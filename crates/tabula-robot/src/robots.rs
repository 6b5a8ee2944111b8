//! The robots shipped in `robots/`, compiled into the binary so `tabula` runs anywhere.

use crate::description::RobotDescription;
use crate::packages::PackagePaths;
use crate::srdf::Srdf;
use crate::{RobotError, RobotModel};
use std::path::{Path, PathBuf};
use std::sync::OnceLock;
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

/// How a robot file is loaded: xacro arguments, where packages are, its SRDF.
#[derive(Debug, Clone, Default)]
pub struct LoadOptions {
    /// `name:=value` arguments for xacro.
    pub xacro_args: Vec<(String, String)>,
    pub packages: PackagePaths,
    /// The SRDF; when `None`, `<stem>.srdf` beside the file is used if there is one.
    pub srdf: Option<PathBuf>,
}

static DEFAULT_OPTIONS: OnceLock<LoadOptions> = OnceLock::new();

/// Sets the options [`load`] uses (the CLI's `--xacro-arg`, `--package-path`,
/// `--srdf`); only the first call counts.
pub fn set_default_options(options: LoadOptions) {
    let _ = DEFAULT_OPTIONS.set(options);
}

/// The options [`load`] uses.
pub fn default_options() -> &'static LoadOptions {
    DEFAULT_OPTIONS.get_or_init(LoadOptions::default)
}

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
    /// The robot's SRDF, when it has one (its allowed-collision matrix is used).
    pub srdf: Option<Srdf>,
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
            srdf: None,
        }
    }
}

/// Loads `golem3`, `wam`, `pr2`, or a URDF or xacro file path, with the options the
/// binary set ([`set_default_options`]). A file's description comes from its SRDF
/// (`--srdf`, or `<stem>.srdf` beside it) and the `<stem>.toml` beside it (for
/// `arm.urdf.xacro`: `arm.urdf.toml` or `arm.toml`), the TOML adding what SRDF lacks
/// (gripper widths, camera, self-filter boxes); with neither, one arm runs from the
/// root to the tool the URDF most likely means ([`RobotDescription::minimal`]).
pub fn load(name_or_path: &str) -> Result<NamedRobot, RobotError> {
    load_with(
        name_or_path,
        DEFAULT_OPTIONS.get_or_init(LoadOptions::default),
    )
}

/// [`load`] with explicit options.
pub fn load_with(name_or_path: &str, options: &LoadOptions) -> Result<NamedRobot, RobotError> {
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
            load_file(Path::new(path), options)
        }
        other => Err(RobotError::UnknownRobot(other.into())),
    }
}

fn load_file(p: &Path, options: &LoadOptions) -> Result<NamedRobot, RobotError> {
    let mut model = RobotModel::from_file_with(p, &options.xacro_args, &options.packages)?;
    // `arm.urdf` → `arm.toml`; `arm.urdf.xacro` → `arm.urdf.toml` or `arm.toml`.
    let stem = p.with_extension("");
    let beside = |ext: &str| {
        [p.with_extension(ext), stem.with_extension(ext)]
            .into_iter()
            .find(|c| c.is_file())
    };
    let srdf_path = options.srdf.clone().or_else(|| beside("srdf"));
    let srdf = match &srdf_path {
        Some(s) => Some(Srdf::from_file_with(
            s,
            &model,
            &options.xacro_args,
            &options.packages,
        )?),
        None => None,
    };
    // What MoveIt would skip with a warning, said once per load.
    for w in srdf.iter().flat_map(|s| &s.warnings) {
        tracing::warn!("SRDF {}: {w}", srdf_path.as_deref().unwrap_or(p).display());
    }
    let toml = match beside("toml") {
        Some(t) => {
            let text = tabula_geom::input::read_text(&t, Format::Robot)?;
            Some(
                RobotDescription::from_toml(&text, &model).map_err(|e| match e {
                    RobotError::Description(m) => {
                        RobotError::Description(format!("{}: {m}", t.display()))
                    }
                    other => RobotError::Description(format!("{}: {other}", t.display())),
                })?,
            )
        }
        None => None,
    };
    let description = match (toml, &srdf) {
        (Some(mut d), Some(s)) => {
            // The TOML's arms win; the SRDF's named states join arms of the same name,
            // and its other arm groups are added.
            for arm in s.arms(&model) {
                match d.arms.iter_mut().find(|a| a.name == arm.name) {
                    Some(a) => a.named.extend(arm.named),
                    None => d.arms.push(arm),
                }
            }
            d
        }
        (Some(d), None) => d,
        (None, Some(s)) if !s.arms(&model).is_empty() => RobotDescription {
            arms: s.arms(&model),
            ..RobotDescription::minimal(&model, &model.name)
        },
        (None, _) => RobotDescription::minimal(&model, &model.name),
    };
    let mut description = description;
    if let Some(s) = &srdf {
        crate::description::attach_grippers(&mut model, s, &mut description);
    }
    let mut robot = NamedRobot::new(model, description, &p.display().to_string());
    robot.srdf = srdf;
    Ok(robot)
}
