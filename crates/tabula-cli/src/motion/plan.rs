//! `tabula motion plan`: MoveIt's core question as a command — plan a motion for this
//! robot's group in this scene, from a start to a goal. The scene is a tabula scene
//! (TOML) or a MoveIt planning scene (YAML); the goal is joints, a pose, a named state
//! or a MoveIt motion plan request (YAML). Prints the timed trajectory; exit 2 with the
//! reason when there is none.

use crate::arm::NoSolution;
use crate::tasks::{load_world, scene_robot_named};
use anyhow::{Context, Result, anyhow, bail};
use clap::Args;
use serde::Serialize;
use std::path::{Path, PathBuf};
use tabula_geom::input::{Format, read_text};
use tabula_geom::{Pose, pose_from_xyz_rpy};
use tabula_motion::group::{MoveError, MoveGroup, MoveGroupParams, Plan};
use tabula_motion::moveit::{Limits, MotionRequest, PlanningScene, Problem};
use tabula_robot::driver::JointState;
use tabula_robot::robots::{self, NamedRobot};

#[derive(Args)]
#[command(group(clap::ArgGroup::new("goal").required(true).args(["goal_joints", "goal_pose", "goal_named", "request", "print_params"])))]
pub struct PlanArgs {
    /// The robot: a URDF or xacro file or a built-in name (`wam`, `pr2`, `golem3`).
    /// With a tabula scene, the name of one of its robots (default: its first).
    #[arg(long)]
    robot: Option<String>,
    /// The planning group: an arm of the robot's description or a chain group of its
    /// SRDF (default: the first).
    #[arg(long)]
    group: Option<String>,
    /// A tabula scene (`.toml`) or a MoveIt planning scene (`.yaml`); none: the robot alone.
    #[arg(long)]
    scene: Option<PathBuf>,
    /// Start joint values (the group's joints in order; default: the scene's state).
    #[arg(long, num_args = 1.., allow_negative_numbers = true, value_parser = crate::args::finite, conflicts_with = "start_named")]
    start: Option<Vec<f64>>,
    /// Start at a named state of the group (SRDF group state).
    #[arg(long)]
    start_named: Option<String>,
    /// Goal joint values (the group's joints in order).
    #[arg(long, num_args = 1.., allow_negative_numbers = true, value_parser = crate::args::finite)]
    goal_joints: Option<Vec<f64>>,
    /// Goal pose of the group's tip in the world: x y z (m) roll pitch yaw (rad).
    #[arg(long, num_args = 6, allow_negative_numbers = true, value_names = ["X", "Y", "Z", "ROLL", "PITCH", "YAW"], value_parser = crate::args::finite)]
    goal_pose: Option<Vec<f64>>,
    /// Goal at a named state of the group.
    #[arg(long)]
    goal_named: Option<String>,
    /// A MoveIt motion plan request (YAML): its group, start state and goal constraints.
    #[arg(long)]
    request: Option<PathBuf>,
    /// Motion parameters (TOML, `MoveGroupParams`; default: 1 mm padding, every edge
    /// certified by conservative advancement).
    #[arg(long)]
    params: Option<PathBuf>,
    /// Print the parameters `--params` takes, with their defaults (SPEC's values), as
    /// TOML to start a file from, and exit.
    #[arg(long, exclusive = true)]
    print_params: bool,
    /// Planning time limit (s); default: the request's, else the parameters' (1 s).
    #[arg(long, value_parser = crate::args::seconds)]
    timeout: Option<f64>,
    #[arg(long, value_parser = crate::args::seed)]
    seed: Option<u64>,
    #[arg(long)]
    json: bool,
}

/// One sample of the trajectory.
#[derive(Serialize)]
struct PointJson {
    time: f64,
    positions: Vec<f64>,
    velocities: Vec<f64>,
}

/// What `motion plan --json` prints.
#[derive(Serialize)]
struct PlanJson {
    solved: bool,
    group: String,
    joint_names: Vec<String>,
    /// The path's waypoints (joint space), before timing.
    path: Vec<Vec<f64>>,
    points: Vec<PointJson>,
    planning_us: f64,
    /// Joint-space length of the path (rad, Euclidean).
    path_length: f64,
    duration: f64,
    notes: Vec<String>,
}

/// What `motion plan --json` prints when there is no plan.
#[derive(Serialize)]
struct NoPlanJson<'a> {
    solved: bool,
    reason: &'static str,
    message: &'a str,
}

pub fn run(a: PlanArgs) -> Result<()> {
    if a.print_params {
        return crate::tasks::print_toml(&super::planning_params(None)?);
    }
    let mut params: MoveGroupParams = super::planning_params(a.params.as_deref())?;
    if let Some(seed) = a.seed {
        params.planner.seed = seed;
    }
    let request = match &a.request {
        Some(p) => Some(
            MotionRequest::from_yaml(&read_text(p, Format::Scene)?, &Limits::default())
                .with_context(|| p.display().to_string())?,
        ),
        None => None,
    };
    if let Some(r) = &request {
        if let Some(g) = &a.group
            && g != &r.group
        {
            bail!("--group {g} but the request plans for group `{}`", r.group);
        }
        if let Some(s) = r.velocity_scaling {
            params.velocity_scaling = s.max(1e-3);
        }
    }
    params.planner.timeout_s = a
        .timeout
        .or(request.as_ref().and_then(|r| r.allowed_planning_time))
        .unwrap_or(params.planner.timeout_s);
    let group_name = a
        .group
        .clone()
        .or(request.as_ref().map(|r| r.group.clone()));
    let (robot, mut group, mut notes) = setup(&a, group_name.as_deref(), &params)?;
    let (start, goals) = start_and_goals(&a, &robot, &mut group, request.as_ref(), &mut notes)?;
    for n in &notes {
        tracing::warn!("{n}");
    }
    let plan = match goals {
        Goals::Joints(goals) => group.plan_to_joints(&start, &goals),
        Goals::Poses(poses) => plan_to_poses(&group, &start, &poses),
    };
    match plan {
        Ok(plan) => print_plan(&a, &group, &plan, notes),
        Err(e) => {
            if a.json {
                let message = e.to_string();
                let json = NoPlanJson {
                    solved: false,
                    reason: reason(&e),
                    message: &message,
                };
                println!("{}", serde_json::to_string(&json)?);
            }
            Err(NoSolution(e.to_string()).into())
        }
    }
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

/// The robot and its move group over the scene; notes on what the scene ignored.
fn setup(
    a: &PlanArgs,
    group: Option<&str>,
    params: &MoveGroupParams,
) -> Result<(NamedRobot, MoveGroup, Vec<String>)> {
    let is_toml = a
        .scene
        .as_deref()
        .and_then(Path::extension)
        .is_some_and(|e| e.eq_ignore_ascii_case("toml"));
    if is_toml {
        let path = a.scene.as_deref().unwrap_or(Path::new(""));
        let (_, world) = load_world(path)?;
        let (name, robot) = scene_robot_named(&world, a.robot.as_deref())?;
        let arm = arm_name(&robot, group)?;
        let state = world.robot(&name)?;
        let js = tabula_robot::driver::JointState::of_model(&state.model, &state.values);
        let mut g = MoveGroup::new(&robot, &arm, &js, state.world_from_root, params.clone())?;
        for (k, (obj, shape, pose)) in world.planning_scene(&name).into_iter().enumerate() {
            g.add_object(&format!("{obj}#{k}"), shape, pose)?;
        }
        return Ok((robot, g, Vec::new()));
    }
    let robot_name = a
        .robot
        .as_deref()
        .ok_or_else(|| anyhow!("--robot is required (a URDF or xacro file, or wam/pr2/golem3) unless the scene is a tabula scene"))?;
    let robot = robots::load(robot_name)?;
    let arm = arm_name(&robot, group)?;
    let mut g = MoveGroup::new(
        &robot,
        &arm,
        &JointState::default(),
        Pose::IDENTITY,
        params.clone(),
    )?;
    let mut notes = Vec::new();
    if let Some(path) = &a.scene {
        let scene = PlanningScene::from_yaml(&read_text(path, Format::Scene)?, &Limits::default())
            .with_context(|| path.display().to_string())?;
        notes = scene
            .apply(&mut g.world)
            .with_context(|| path.display().to_string())?;
    }
    Ok((robot, g, notes))
}

/// The group asked for (an arm of the description), or the first arm.
fn arm_name(robot: &NamedRobot, group: Option<&str>) -> Result<String> {
    match group {
        Some(g) => {
            robot.description.arm(g).map_err(|_| {
                let known: Vec<&str> = robot
                    .description
                    .arms
                    .iter()
                    .map(|a| a.name.as_str())
                    .collect();
                anyhow!("no planning group `{g}`; groups: {}", known.join(", "))
            })?;
            Ok(g.to_string())
        }
        None => robot
            .description
            .arms
            .first()
            .map(|a| a.name.clone())
            .ok_or_else(|| {
                anyhow!("the robot has no planning group (give an SRDF with a chain group)")
            }),
    }
}

enum Goals {
    Joints(Vec<Vec<f64>>),
    Poses(Vec<Pose>),
}

/// The start configuration and the goals from the flags or the request.
fn start_and_goals(
    a: &PlanArgs,
    robot: &NamedRobot,
    group: &mut MoveGroup,
    request: Option<&MotionRequest>,
    notes: &mut Vec<String>,
) -> Result<(Vec<f64>, Goals)> {
    let arm = group.arm.name.clone();
    let names = group.joint_names().to_vec();
    let dof = names.len();
    let mut problem: Option<Problem> = None;
    if let Some(r) = request {
        let p = r.problem(&mut group.world)?;
        notes.extend(p.notes.iter().cloned());
        problem = Some(p);
    }
    let current = group.world.chain_values();
    let start = match (&a.start, &a.start_named) {
        (Some(q), _) => {
            check_length("--start", q, &names)?;
            q.clone()
        }
        (None, Some(n)) => robot
            .description
            .arm(&arm)?
            .named_configuration(n, &names, &current)?,
        (None, None) => current.clone(),
    };
    let goals = if let Some(q) = &a.goal_joints {
        check_length("--goal-joints", q, &names)?;
        Goals::Joints(vec![q.clone()])
    } else if let Some(p) = &a.goal_pose {
        Goals::Poses(vec![pose_from_xyz_rpy(
            [p[0], p[1], p[2]],
            [p[3], p[4], p[5]],
        )])
    } else if let Some(n) = &a.goal_named {
        Goals::Joints(vec![
            robot
                .description
                .arm(&arm)?
                .named_configuration(n, &names, &start)?,
        ])
    } else {
        let p = problem.ok_or_else(|| anyhow!("no goal given"))?;
        if !p.joint_goals.is_empty() {
            Goals::Joints(p.joint_goals)
        } else {
            Goals::Poses(p.pose_goals)
        }
    };
    debug_assert_eq!(start.len(), dof);
    Ok((start, goals))
}

fn check_length(flag: &str, q: &[f64], names: &[String]) -> Result<()> {
    if q.len() != names.len() {
        bail!(
            "{flag} needs {} values ({}), got {}",
            names.len(),
            names.join(", "),
            q.len()
        );
    }
    Ok(())
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

fn print_plan(a: &PlanArgs, group: &MoveGroup, plan: &Plan, notes: Vec<String>) -> Result<()> {
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
    let duration = t.times.last().copied().unwrap_or(0.0);
    if a.json {
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
        let json = PlanJson {
            solved: true,
            group: group.arm.name.clone(),
            joint_names: t.joint_names.clone(),
            path: plan.path.clone(),
            points,
            planning_us: plan.planning_time * 1e6,
            path_length,
            duration,
            notes,
        };
        println!("{}", serde_json::to_string(&json)?);
        return Ok(());
    }
    println!(
        "planned group `{}`: {} waypoints, path length {path_length:.3} rad, {duration:.2} s trajectory ({} samples), planning {:.2} ms",
        group.arm.name,
        plan.path.len(),
        t.times.len(),
        plan.planning_time * 1e3
    );
    println!("  joints: {}", t.joint_names.join(" "));
    for q in &plan.path {
        let row: Vec<String> = q.iter().map(|v| format!("{v:+.4}")).collect();
        println!("  {}", row.join(" "));
    }
    Ok(())
}
