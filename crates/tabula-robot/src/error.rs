//! Typed errors of the robot crate.

use std::path::PathBuf;

/// Everything that can go wrong loading a robot or building a chain.
#[derive(Debug, thiserror::Error)]
pub enum RobotError {
    #[error(transparent)]
    Input(#[from] tabula_geom::input::InputError),
    #[error("malformed URDF{}: {message}", path.as_ref().map(|p| format!(" {}", p.display())).unwrap_or_default())]
    Parse {
        path: Option<PathBuf>,
        message: String,
    },
    #[error("URDF has no links")]
    NoLinks,
    #[error("URDF names link `{0}` twice")]
    DuplicateLink(String),
    #[error("URDF names joint `{0}` twice")]
    DuplicateJoint(String),
    #[error("joint `{joint}` refers to link `{link}`, which the URDF does not define")]
    JointMissingLink { joint: String, link: String },
    #[error("link `{link}` is the child of two joints (`{first}` and `{second}`)")]
    MultipleParents {
        link: String,
        first: String,
        second: String,
    },
    #[error("joint `{0}` connects a link to itself")]
    SelfLoop(String),
    #[error("the joints form a cycle through link `{0}`; a URDF must be a tree")]
    Cycle(String),
    #[error("joint `{joint}`: {field} is {value}, which is not a finite number")]
    NonFinite {
        joint: String,
        field: &'static str,
        value: f64,
    },
    #[error("`{joint}`: {field} is {value}, beyond the ±1e6 any robot part can have")]
    OutOfRange {
        joint: String,
        field: &'static str,
        value: f64,
    },
    #[error("`{owner}`: mesh `{filename}` {problem}")]
    BadMesh {
        owner: String,
        filename: String,
        problem: String,
    },
    #[error("the XML is nested {0} elements deep; a URDF needs a handful (limit 256)")]
    TooDeep(usize),
    #[error("joint `{joint}`: lower limit {lower} is above upper limit {upper}")]
    InvertedLimits {
        joint: String,
        lower: f64,
        upper: f64,
    },
    #[error("joint `{joint}`: axis has zero length")]
    ZeroAxis { joint: String },
    #[error("joint `{joint}` mimics `{master}`, which is {problem}")]
    BadMimic {
        joint: String,
        master: String,
        problem: &'static str,
    },
    #[error("link `{name}` is not in robot `{robot}`; links are: {known}")]
    UnknownLink {
        name: String,
        robot: String,
        known: String,
    },
    #[error("no chain from `{base}` to `{tip}`: they are in different trees of the URDF")]
    Disconnected { base: String, tip: String },
    #[error(
        "chain from `{base}` to `{tip}` crosses {kind} joint `{joint}`, which has no single axis"
    )]
    UnsupportedJoint {
        base: String,
        tip: String,
        joint: String,
        kind: &'static str,
    },
    #[error("expected {expected} joint values, got {got}")]
    WrongJointCount { expected: usize, got: usize },
    #[error("`torso_lift_link` → `{tip}` is not a Golem-III arm: {why}")]
    NotGolem3 { tip: String, why: &'static str },
    #[error("robot description: {0}")]
    Description(String),
    #[error("unknown robot `{0}`: use golem3, wam, pr2 or a path to a .urdf file")]
    UnknownRobot(String),
}
