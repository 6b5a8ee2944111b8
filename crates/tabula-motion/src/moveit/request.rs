//! A MoveIt motion plan request (`moveit_msgs/MotionPlanRequest` as YAML): the group,
//! the start state, and the goal — joint constraints, or a link's position (the centre
//! of the constraint region) with or without its orientation.

use super::scene::joint_state;
use super::yaml::Node;
use super::{Limits, MoveItError, parse_yaml};
use tabula_geom::{Quat, Vec3};

/// One set of goal constraints (a request may give several: any one is a goal).
#[derive(Clone, Debug, PartialEq)]
pub enum Goal {
    /// Joint positions by name.
    Joints(Vec<(String, f64)>),
    /// `link` with its point `link_offset` (link frame) at `position`, and the link's
    /// orientation when given; both in `frame_id` (empty: the planning frame).
    Pose {
        link: String,
        frame_id: String,
        position: Vec3,
        link_offset: Vec3,
        orientation: Option<Quat>,
    },
}

/// A motion plan request.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MotionRequest {
    pub group: String,
    /// The start state's joint values by name (empty: the scene's state).
    pub start: Vec<(String, f64)>,
    pub goals: Vec<Goal>,
    /// `allowed_planning_time` (s), when positive.
    pub allowed_planning_time: Option<f64>,
    /// `max_velocity_scaling_factor`, when in (0, 1].
    pub velocity_scaling: Option<f64>,
}

impl MotionRequest {
    pub fn from_yaml(text: &str, limits: &Limits) -> Result<Self, MoveItError> {
        let tree = parse_yaml(text, limits)?;
        let root = Node::root(&tree);
        if root.value.as_mapping().is_none() {
            return Err(root.error("a motion plan request is a map"));
        }
        let group = root.need("group_name")?.text()?.to_string();
        let start = match root.get("start_state") {
            Some(s) => joint_state(&s)?,
            None => Vec::new(),
        };
        let sets = root.list("goal_constraints")?;
        if sets.len() > limits.objects {
            return Err(MoveItError::TooLarge(format!(
                "{} goal constraint sets, over the limit of {}",
                sets.len(),
                limits.objects
            )));
        }
        let goals = sets.iter().map(goal).collect::<Result<Vec<_>, _>>()?;
        if goals.is_empty() {
            return Err(root.error("no `goal_constraints`"));
        }
        let positive = |key: &str, max: f64| -> Result<Option<f64>, MoveItError> {
            match root.get(key) {
                None => Ok(None),
                Some(n) => {
                    let v = n.number()?;
                    Ok((v > 0.0).then_some(v.min(max)))
                }
            }
        };
        Ok(Self {
            group,
            start,
            goals,
            allowed_planning_time: positive("allowed_planning_time", f64::INFINITY)?,
            velocity_scaling: positive("max_velocity_scaling_factor", 1.0)?,
        })
    }
}

fn goal(set: &Node) -> Result<Goal, MoveItError> {
    let joints = set.list("joint_constraints")?;
    let positions = set.list("position_constraints")?;
    let orientations = set.list("orientation_constraints")?;
    if !set.list("visibility_constraints")?.is_empty() {
        return Err(set.error("visibility constraints are not supported"));
    }
    if !joints.is_empty() {
        if !positions.is_empty() || !orientations.is_empty() {
            return Err(set.error(
                "joint constraints mixed with position or orientation constraints are not supported",
            ));
        }
        return joints
            .iter()
            .map(|j| {
                Ok((
                    j.need("joint_name")?.text()?.to_string(),
                    j.need("position")?.number()?,
                ))
            })
            .collect::<Result<_, MoveItError>>()
            .map(Goal::Joints);
    }
    let [position] = positions.as_slice() else {
        return Err(set.error(
            "a goal is joint constraints, or one position constraint (with at most one orientation constraint)",
        ));
    };
    let link = position.need("link_name")?.text()?.to_string();
    let frame_id = match position.get("header").and_then(|h| h.get("frame_id")) {
        Some(f) => f.text()?.to_string(),
        None => String::new(),
    };
    let region = position.need("constraint_region")?;
    let centre = region
        .list("primitive_poses")?
        .first()
        .ok_or_else(|| region.error("the constraint region has no primitive pose"))?
        .pose()?
        .translation;
    let link_offset = match position.get("target_point_offset") {
        Some(o) => o.vec3()?,
        None => Vec3::ZERO,
    };
    let orientation = match orientations.as_slice() {
        [] => None,
        [o] => {
            let other = o.need("link_name")?.text()?;
            if other != link {
                return Err(o.error(format!(
                    "orientation of `{other}` but position of `{link}`: one link per goal"
                )));
            }
            Some(o.need("orientation")?.quat()?)
        }
        _ => return Err(set.error("more than one orientation constraint")),
    };
    Ok(Goal::Pose {
        link,
        frame_id,
        position: centre,
        link_offset,
        orientation,
    })
}
