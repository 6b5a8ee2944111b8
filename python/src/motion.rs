//! `tabula.plan_motion`: MoveIt's core question in process — the same query and the same
//! JSON as `tabula motion plan --json` (both answered by `tabula_bench::motion_plan`).

use crate::robot::Robot;
use crate::{pose_of_rows, value_error};
use pyo3::prelude::*;
use std::path::PathBuf;
use tabula_bench::motion_plan::{
    Goal, MotionAnswer, MotionQuery, RobotSource, Start, plan_motion as answer, planning_params,
};
use tabula_geom::input::{Format, read_text};
use tabula_motion::group::MoveGroupParams;
use tabula_motion::moveit::{Limits, MotionRequest};

/// Where the motion starts or ends, as the Python half sorted it out.
#[derive(FromPyObject)]
pub enum Target {
    /// A named state of the group.
    Named(String),
    /// A (4, 4) pose of the group's tip in the world (goals only).
    Pose(Vec<Vec<f64>>),
    /// The group's joint values.
    Joints(Vec<f64>),
}

/// The robot: a loaded `tabula.Robot`, or a file, a built-in name, or (with a tabula
/// scene) one of its robots by name.
#[derive(FromPyObject)]
pub enum RobotArg<'py> {
    Loaded(PyRef<'py, Robot>),
    Named(String),
}

/// Plans a motion; returns `motion plan --json`'s text (`solved` false with `reason`
/// and `message` when there is no motion). Errors of the query raise `ValueError`.
#[pyfunction]
#[pyo3(signature = (robot, scene=None, start=None, goal=None, group=None, request=None, params=None, timeout=None, seed=None))]
#[allow(clippy::too_many_arguments)]
pub fn plan_motion(
    py: Python<'_>,
    robot: Option<RobotArg<'_>>,
    scene: Option<PathBuf>,
    start: Option<Target>,
    goal: Option<Target>,
    group: Option<String>,
    request: Option<PathBuf>,
    params: Option<(String, String)>,
    timeout: Option<f64>,
    seed: Option<u64>,
) -> PyResult<String> {
    let mut params: MoveGroupParams = match &params {
        Some((kind, text)) => crate::params::parse(kind, text)?,
        None => planning_params(None).map_err(value_error)?,
    };
    if let Some(s) = seed {
        params.planner.seed = s;
    }
    if let Some(t) = timeout
        && !(t.is_finite() && t > 0.0 && t <= 1e6)
    {
        return Err(value_error(format!(
            "timeout must be a positive number of seconds, not {t}"
        )));
    }
    let start = match start {
        None => Start::Current,
        Some(Target::Named(n)) => Start::Named(n),
        Some(Target::Joints(q)) => Start::Joints(q),
        Some(Target::Pose(_)) => {
            return Err(value_error(
                "start must be joint values or a named state, not a pose",
            ));
        }
    };
    let goal = match (goal, &request) {
        (Some(_), Some(_)) => return Err(value_error("give a goal or a request, not both")),
        (None, None) => {
            return Err(value_error(
                "give a goal (joints, a pose or a named state) or a request",
            ));
        }
        (None, Some(path)) => Goal::Request(
            read_text(path, Format::Scene)
                .map_err(value_error)
                .and_then(|t| {
                    MotionRequest::from_yaml(&t, &Limits::default())
                        .map_err(|e| value_error(format!("{}: {e}", path.display())))
                })?,
        ),
        (Some(Target::Named(n)), None) => Goal::Named(n),
        (Some(Target::Joints(q)), None) => Goal::Joints(q),
        (Some(Target::Pose(rows)), None) => Goal::Pose(pose_of_rows(&rows)?),
    };
    let robot_source = match &robot {
        Some(RobotArg::Loaded(r)) => RobotSource::Loaded(r.named()),
        Some(RobotArg::Named(n)) => RobotSource::Named(Some(n.as_str())),
        None => RobotSource::Named(None),
    };
    let query = MotionQuery {
        robot: robot_source,
        scene: scene.as_deref(),
        group: group.as_deref(),
        start,
        goal,
        params,
        timeout,
    };
    let answer = py.detach(|| answer(query)).map_err(value_error)?;
    let text = match answer {
        MotionAnswer::Planned(p) => serde_json::to_string(&p),
        MotionAnswer::NoPlan(n) => serde_json::to_string(&n),
    };
    text.map_err(value_error)
}
