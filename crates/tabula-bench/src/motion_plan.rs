//! One motion query answered — MoveIt's core question: plan a motion for this robot's
//! group in this scene, from a start to a goal. The scene is a tabula scene (TOML) or a
//! MoveIt planning scene (YAML); the goal is joints, a pose, a named state or a MoveIt
//! motion plan request. `tabula motion plan` and the Python package's `plan_motion`
//! both ask here, so they give the same answer in the same JSON.

use crate::scene_robot_named;
use anyhow::{Context, Result, anyhow, bail};
use serde::Serialize;
use std::path::Path;
use tabula_geom::Pose;
use tabula_geom::input::{Format, read_text};
use tabula_motion::group::{MoveError, MoveGroup, MoveGroupParams, Plan};
use tabula_motion::moveit::{Limits, MotionRequest, PlanningScene, Problem};
use tabula_robot::driver::JointState;
use tabula_robot::robots::{self, NamedRobot};
use tabula_sim::{PhysicsParams, Scene, SimWorld};

/// Padding of a motion query without parameters: 1 mm, with every edge certified by
/// conservative advancement, and thinner where a start or goal lies within it. MoveIt
/// plans on the exact geometry, and MotionBenchMaker's grasp goals sit millimetres from
/// the object, where the tasks' 1 cm would refuse them.
pub const PLANNING_PADDING: f64 = 0.001;

/// The parameters of `path` (TOML) when given, else the defaults with
/// [`PLANNING_PADDING`] and the padding shrunk to fit the endpoints.
pub fn planning_params(path: Option<&Path>) -> Result<MoveGroupParams> {
    if path.is_some() {
        return Ok(tabula_geom::input::load_params(path)?);
    }
    let mut params = MoveGroupParams::default();
    params.world.padding = PLANNING_PADDING;
    params.planner.shrink_padding_to_endpoints = true;
    Ok(params)
}

/// Where the motion starts.
#[derive(Clone, Debug, Default)]
pub enum Start {
    /// The scene's state (a request's start state when it has one).
    #[default]
    Current,
    /// The group's joint values, in its order.
    Joints(Vec<f64>),
    /// A named state of the group (SRDF group state).
    Named(String),
}

/// Where the motion goes.
#[derive(Clone, Debug)]
pub enum Goal {
    /// The group's joint values, in its order.
    Joints(Vec<f64>),
    /// The group's tip in the world.
    Pose(Pose),
    /// A named state of the group.
    Named(String),
    /// A MoveIt motion plan request: its group, start state, goal constraints, planning
    /// time and velocity scaling.
    Request(MotionRequest),
}

/// The robot of a query.
#[derive(Clone, Copy)]
pub enum RobotSource<'a> {
    /// A URDF or xacro file or a built-in name; with a tabula scene, the name of one of
    /// its robots (None: its first).
    Named(Option<&'a str>),
    /// A robot already loaded (not used with a tabula scene, which has its own).
    Loaded(&'a NamedRobot),
}

/// One motion query.
pub struct MotionQuery<'a> {
    pub robot: RobotSource<'a>,
    /// A tabula scene (`.toml`) or a MoveIt planning scene (`.yaml`); None: the robot alone.
    pub scene: Option<&'a Path>,
    /// The planning group: an arm of the description or a chain group of its SRDF
    /// (default: the request's, else the first).
    pub group: Option<&'a str>,
    pub start: Start,
    pub goal: Goal,
    pub params: MoveGroupParams,
    /// Planning time limit (s); default: the request's, else the parameters'.
    pub timeout: Option<f64>,
}

/// One sample of the trajectory.
#[derive(Serialize, Clone, Debug)]
pub struct PointJson {
    pub time: f64,
    pub positions: Vec<f64>,
    pub velocities: Vec<f64>,
}

/// A planned motion, as `motion plan --json` prints it.
#[derive(Serialize, Clone, Debug)]
pub struct PlanJson {
    pub solved: bool,
    pub group: String,
    pub joint_names: Vec<String>,
    /// The path's waypoints (joint space), before timing.
    pub path: Vec<Vec<f64>>,
    pub points: Vec<PointJson>,
    pub planning_us: f64,
    /// Joint-space length of the path (rad, Euclidean).
    pub path_length: f64,
    pub duration: f64,
    pub notes: Vec<String>,
}

/// No motion: the kind of failure as a key scripts can branch on, and the message.
#[derive(Serialize, Clone, Debug)]
pub struct NoPlanJson {
    pub solved: bool,
    pub reason: &'static str,
    pub message: String,
}

/// The answer to a query that was well posed.
pub enum MotionAnswer {
    Planned(PlanJson),
    NoPlan(NoPlanJson),
}

/// Answers `query`: `Err` when the query itself is wrong (a file, a group, a joint count),
/// [`MotionAnswer::NoPlan`] when it is right and there is no motion.
pub fn plan_motion(mut query: MotionQuery<'_>) -> Result<MotionAnswer> {
    let request = match &query.goal {
        Goal::Request(r) => Some(r.clone()),
        _ => None,
    };
    if let Some(r) = &request {
        if let Some(g) = query.group
            && g != r.group
        {
            bail!("group `{g}` but the request plans for group `{}`", r.group);
        }
        if let Some(s) = r.velocity_scaling {
            query.params.velocity_scaling = s.max(1e-3);
        }
    }
    query.params.planner.timeout_s = query
        .timeout
        .or(request.as_ref().and_then(|r| r.allowed_planning_time))
        .unwrap_or(query.params.planner.timeout_s);
    let group_name = query
        .group
        .map(str::to_string)
        .or(request.as_ref().map(|r| r.group.clone()));
    let (robot, mut group, mut notes) = setup(&query, group_name.as_deref())?;
    let (start, goals) = start_and_goals(&query, &robot, &mut group, &mut notes)?;
    for n in &notes {
        tracing::warn!("{n}");
    }
    let plan = match goals {
        Goals::Joints(goals) => group.plan_to_joints(&start, &goals),
        Goals::Poses(poses) => plan_to_poses(&group, &start, &poses),
    };
    Ok(match plan {
        Ok(plan) => MotionAnswer::Planned(plan_json(&group, &plan, notes)),
        Err(e) => MotionAnswer::NoPlan(NoPlanJson {
            solved: false,
            reason: reason(&e),
            message: e.to_string(),
        }),
    })
}

/// The kind of failure, as a key scripts can branch on.
fn reason(e: &MoveError) -> &'static str {
    match e {
        MoveError::Unreachable => "unreachable",
        MoveError::GoalInCollision(_) => "goal_in_collision",
        MoveError::JointGoalInvalid(_) => "goal_invalid",
        MoveError::StartInvalid(_) => "start_invalid",
        MoveError::NoPath(_) => "no_path",
        MoveError::CartesianIncomplete { .. } => "cartesian_incomplete",
        MoveError::World(_) => "world",
    }
}

/// A robot that is either borrowed or loaded here.
enum RobotHere<'a> {
    Borrowed(&'a NamedRobot),
    Owned(Box<NamedRobot>),
}

impl std::ops::Deref for RobotHere<'_> {
    type Target = NamedRobot;
    fn deref(&self) -> &NamedRobot {
        match self {
            RobotHere::Borrowed(r) => r,
            RobotHere::Owned(r) => r,
        }
    }
}

fn is_tabula_scene(scene: Option<&Path>) -> bool {
    scene
        .and_then(Path::extension)
        .is_some_and(|e| e.eq_ignore_ascii_case("toml"))
}

/// The robot and its move group over the scene; notes on what the scene ignored.
fn setup<'a>(
    q: &MotionQuery<'a>,
    group: Option<&str>,
) -> Result<(RobotHere<'a>, MoveGroup, Vec<String>)> {
    if let Some(path) = q.scene.filter(|_| is_tabula_scene(q.scene)) {
        let scene = Scene::load(path)?;
        let world = SimWorld::from_scene(&scene, PhysicsParams::default())
            .with_context(|| path.display().to_string())?;
        let wanted = match q.robot {
            RobotSource::Named(n) => n,
            RobotSource::Loaded(r) => Some(r.label.as_str()),
        };
        let (name, robot) = scene_robot_named(&world, wanted)?;
        let arm = arm_name(&robot, group)?;
        let state = world.robot(&name)?;
        let js = JointState::of_model(&state.model, &state.values);
        let mut g = MoveGroup::new(&robot, &arm, &js, state.world_from_root, q.params.clone())?;
        for (k, (obj, shape, pose)) in world.planning_scene(&name).into_iter().enumerate() {
            g.add_object(&format!("{obj}#{k}"), shape, pose)?;
        }
        return Ok((RobotHere::Owned(Box::new(robot)), g, Vec::new()));
    }
    let robot = match q.robot {
        RobotSource::Loaded(r) => RobotHere::Borrowed(r),
        RobotSource::Named(Some(n)) => RobotHere::Owned(Box::new(robots::load(n)?)),
        RobotSource::Named(None) => bail!(
            "a robot is required (a URDF or xacro file, or wam/pr2/golem3) unless the scene is a tabula scene"
        ),
    };
    let arm = arm_name(&robot, group)?;
    let default = JointState::default();
    let mut g = MoveGroup::new(&robot, &arm, &default, Pose::IDENTITY, q.params.clone())?;
    let mut notes = Vec::new();
    if let Some(path) = q.scene {
        let text = read_text(path, Format::Scene)?;
        let scene = PlanningScene::from_yaml(&text, &Limits::default())
            .with_context(|| path.display().to_string())?;
        notes = scene
            .apply(&mut g.world)
            .with_context(|| path.display().to_string())?;
    }
    Ok((robot, g, notes))
}

/// The group asked for (an arm of the description), or the first arm.
fn arm_name(robot: &NamedRobot, group: Option<&str>) -> Result<String> {
    let arms = &robot.description.arms;
    match group {
        Some(g) => {
            robot.description.arm(g).map_err(|_| {
                let known: Vec<&str> = arms.iter().map(|a| a.name.as_str()).collect();
                anyhow!("no planning group `{g}`; groups: {}", known.join(", "))
            })?;
            Ok(g.to_string())
        }
        None => arms.first().map(|a| a.name.clone()).ok_or_else(|| {
            anyhow!("the robot has no planning group (give an SRDF with a chain group)")
        }),
    }
}

enum Goals {
    Joints(Vec<Vec<f64>>),
    Poses(Vec<Pose>),
}

/// The start configuration and the goals of the query.
fn start_and_goals(
    q: &MotionQuery<'_>,
    robot: &NamedRobot,
    group: &mut MoveGroup,
    notes: &mut Vec<String>,
) -> Result<(Vec<f64>, Goals)> {
    let arm = robot.description.arm(&group.arm.name)?;
    let names = group.joint_names().to_vec();
    let mut problem: Option<Problem> = None;
    if let Goal::Request(r) = &q.goal {
        let p = r.problem(&mut group.world)?;
        notes.extend(p.notes.iter().cloned());
        problem = Some(p);
    }
    let current = group.world.chain_values();
    let start = match &q.start {
        Start::Joints(v) => check_length("the start", v, &names)?,
        Start::Named(n) => arm.named_configuration(n, &names, &current)?,
        Start::Current => current.clone(),
    };
    let goals = match &q.goal {
        Goal::Joints(v) => Goals::Joints(vec![check_length("the goal", v, &names)?]),
        Goal::Pose(p) => Goals::Poses(vec![*p]),
        Goal::Named(n) => Goals::Joints(vec![arm.named_configuration(n, &names, &start)?]),
        Goal::Request(_) => {
            let p = problem.ok_or_else(|| anyhow!("no goal given"))?;
            if p.joint_goals.is_empty() {
                Goals::Poses(p.pose_goals)
            } else {
                Goals::Joints(p.joint_goals)
            }
        }
    };
    Ok((start, goals))
}

fn check_length(what: &str, q: &[f64], names: &[String]) -> Result<Vec<f64>> {
    if q.len() != names.len() {
        bail!(
            "{what} needs {} values ({}), got {}",
            names.len(),
            names.join(", "),
            q.len()
        );
    }
    if let Some(v) = q.iter().find(|v| !v.is_finite()) {
        bail!("{what}: every joint value must be finite, not {v}");
    }
    Ok(q.to_vec())
}

/// The first pose goal with a plan (MoveIt's goal region over several constraint sets).
fn plan_to_poses(group: &MoveGroup, start: &[f64], poses: &[Pose]) -> Result<Plan, MoveError> {
    let mut last = MoveError::Unreachable;
    for pose in poses {
        match group.plan_to_pose(start, pose) {
            Ok(plan) => return Ok(plan),
            Err(e) => last = e,
        }
    }
    Err(last)
}

fn plan_json(group: &MoveGroup, plan: &Plan, notes: Vec<String>) -> PlanJson {
    let path_length: f64 = plan
        .path
        .windows(2)
        .map(|w| {
            w[0].iter()
                .zip(&w[1])
                .map(|(x, y)| (x - y).powi(2))
                .sum::<f64>()
                .sqrt()
        })
        .sum();
    let t = &plan.trajectory;
    let points = t
        .times
        .iter()
        .zip(&t.positions)
        .zip(&plan.velocities)
        .map(|((time, p), v)| PointJson {
            time: *time,
            positions: p.clone(),
            velocities: v.clone(),
        })
        .collect();
    PlanJson {
        solved: true,
        group: group.arm.name.clone(),
        joint_names: t.joint_names.clone(),
        path: plan.path.clone(),
        points,
        planning_us: plan.planning_time * 1e6,
        path_length,
        duration: t.times.last().copied().unwrap_or(0.0),
        notes,
    }
}
