//! MoveIt's messages as files: planning scenes and motion plan requests in YAML (what
//! MoveIt, `ros2 topic echo` and MotionBenchMaker write), read with bounded size and
//! counts, and turned into a [`CollisionWorld`], a start and goals for it.

mod request;
mod scene;
mod yaml;

pub use crate::world::AllowedCollisions;
pub use request::{Goal, MotionRequest};
pub use scene::{AttachedObject, PlanningScene, SceneObject};

use crate::world::CollisionWorld;
use tabula_geom::Pose;

/// Why a scene or a request was refused.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MoveItError {
    #[error("YAML: {0}")]
    Yaml(String),
    #[error("`{path}`: {why}")]
    Field { path: String, why: String },
    #[error("too large: {0}")]
    TooLarge(String),
    /// The scene does not fit the robot (a frame or joint it lacks).
    #[error("{0}")]
    Scene(String),
    /// The request does not fit the robot or its group.
    #[error("{0}")]
    Request(String),
}

/// Bounds on what one file may hold.
#[derive(Debug, Clone)]
pub struct Limits {
    /// Text size (bytes) parsed at all.
    pub bytes: usize,
    /// Collision objects in a scene (and goal sets in a request).
    pub objects: usize,
    /// Shapes (primitives and meshes) over all objects of a scene.
    pub parts: usize,
    /// Vertices of one mesh.
    pub mesh_vertices: usize,
    /// Largest dimension of a primitive (m).
    pub max_size: f64,
}

impl Default for Limits {
    /// A scene of ten thousand objects is already far beyond a workcell (MBM's have 4–30);
    /// beyond that an occupancy map is the right model.
    fn default() -> Self {
        Self {
            bytes: tabula_geom::input::Format::Scene.max_bytes() as usize,
            objects: 10_000,
            parts: 50_000,
            mesh_vertices: 1_000_000,
            max_size: 1e3,
        }
    }
}

/// The YAML tree of `text`, refused above the size limit. serde_yaml bounds nesting
/// depth and alias expansion (a "billion laughs" document is an error, not a hang).
fn parse_yaml(text: &str, limits: &Limits) -> Result<serde_yaml::Value, MoveItError> {
    if text.len() > limits.bytes {
        return Err(MoveItError::TooLarge(format!(
            "{} bytes of YAML, over the limit of {}",
            text.len(),
            limits.bytes
        )));
    }
    check_flow_depth(text)?;
    serde_yaml::from_str(text).map_err(|e| MoveItError::Yaml(e.to_string()))
}

/// Deepest nesting of `[` and `{` accepted. serde_yaml stops at 128 levels, but its
/// scanner first spends time quadratic in the depth (100,000 `[` took 19 s).
const MAX_FLOW_DEPTH: usize = 100;

/// Refuses flow collections nested deeper than [`MAX_FLOW_DEPTH`], in one pass before
/// parsing. Brackets inside quotes and comments do not count; a quote is taken to end
/// with its line (an apostrophe in plain text must not hide the rest of the file).
fn check_flow_depth(text: &str) -> Result<(), MoveItError> {
    let mut depth = 0usize;
    for (line, l) in text.lines().enumerate() {
        let mut quote = None;
        for ch in l.chars() {
            match (quote, ch) {
                (Some(q), c) if c == q => quote = None,
                (Some(_), _) => {}
                (None, '#') => break,
                (None, '\'' | '"') => quote = Some(ch),
                (None, '[' | '{') => {
                    depth += 1;
                    if depth > MAX_FLOW_DEPTH {
                        return Err(MoveItError::Yaml(format!(
                            "line {}: brackets nested deeper than {MAX_FLOW_DEPTH}",
                            line + 1
                        )));
                    }
                }
                (None, ']' | '}') => depth = depth.saturating_sub(1),
                _ => {}
            }
        }
    }
    Ok(())
}

/// A request made concrete for a world whose chain is the request's group: the start
/// configuration and every goal configuration (joint goals) or tip pose (pose goals).
#[derive(Debug, Clone, PartialEq)]
pub struct Problem {
    pub start: Vec<f64>,
    pub joint_goals: Vec<Vec<f64>>,
    /// `world_from_tip` targets.
    pub pose_goals: Vec<Pose>,
    /// What was ignored on the way (values of fixed joints).
    pub notes: Vec<String>,
}

impl MotionRequest {
    /// Applies the start state to `world` (joints outside the group move the rest of
    /// the robot) and resolves the goals against its chain: every group joint named in
    /// a joint goal, no other; a pose goal's link the tip or fixed to it.
    pub fn problem(&self, world: &mut CollisionWorld) -> Result<Problem, MoveItError> {
        let ignored = world
            .set_joint_values(&self.start)
            .map_err(|e| MoveItError::Request(format!("start state: {e}")))?;
        let mut notes = ignored.notes("the start state");
        let mut start = world.chain_values();
        if world.bring_within_limits(&mut start) {
            notes.push(
                "the start state was brought within the joint limits (whole turns, rounding)"
                    .into(),
            );
        }
        let names = world.chain.joint_names.clone();
        let mut joint_goals = Vec::new();
        let mut pose_goals = Vec::new();
        for goal in &self.goals {
            match goal {
                Goal::Joints(values) => {
                    let mut q = joint_goal(&names, values, &mut notes, world)?;
                    if world.bring_within_limits(&mut q) {
                        notes.push(
                            "a joint goal was brought within the joint limits (whole turns, rounding)"
                                .into(),
                        );
                    }
                    joint_goals.push(q);
                }
                Goal::Pose {
                    link,
                    frame_id,
                    position,
                    link_offset,
                    orientation,
                } => {
                    let orientation = orientation.ok_or_else(|| {
                        MoveItError::Request(format!(
                            "the goal for `{link}` gives a position only; give its orientation too"
                        ))
                    })?;
                    let tip_from_link = world.tip_from_link(link).ok_or_else(|| {
                        MoveItError::Request(format!(
                            "goal link `{link}` is not the group's tip `{}` nor fixed to it",
                            world.chain.tip_link
                        ))
                    })?;
                    let frame = if frame_id.is_empty() || frame_id == "world" {
                        world.world_from_root()
                    } else {
                        world
                            .world_from_link(frame_id.trim_start_matches('/'))
                            .map_err(|_| {
                                MoveItError::Request(format!(
                                    "goal frame `{frame_id}` is not a link of the robot"
                                ))
                            })?
                    };
                    let frame_from_link =
                        Pose::from_parts(*position - orientation * *link_offset, orientation);
                    pose_goals.push(frame * frame_from_link * tip_from_link.inverse());
                }
            }
        }
        Ok(Problem {
            start,
            joint_goals,
            pose_goals,
            notes,
        })
    }
}

fn joint_goal(
    names: &[String],
    values: &[(String, f64)],
    notes: &mut Vec<String>,
    world: &CollisionWorld,
) -> Result<Vec<f64>, MoveItError> {
    let mut q = vec![None; names.len()];
    for (name, v) in values {
        match names.iter().position(|n| n == name) {
            Some(i) => q[i] = Some(*v),
            None if world.joint_is_fixed(name) => notes.push(format!(
                "the goal gives a value for fixed joint `{name}`: ignored"
            )),
            None => {
                return Err(MoveItError::Request(format!(
                    "goal joint `{name}` is not in the group ({})",
                    names.join(", ")
                )));
            }
        }
    }
    names
        .iter()
        .zip(q)
        .map(|(n, v)| {
            v.ok_or_else(|| MoveItError::Request(format!("the joint goal does not give `{n}`")))
        })
        .collect()
}
