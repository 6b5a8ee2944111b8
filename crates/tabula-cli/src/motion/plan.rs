//! `tabula motion plan`: MoveIt's core question as a command — plan a motion for this
//! robot's group in this scene, from a start to a goal. The scene is a tabula scene
//! (TOML) or a MoveIt planning scene (YAML); the goal is joints, a pose, a named state
//! or a MoveIt motion plan request (YAML). Prints the timed trajectory; exit 2 with the
//! reason when there is none.

use crate::arm::NoSolution;
use anyhow::{Context, Result, anyhow, bail};
use clap::Args;
use std::path::PathBuf;
use tabula_bench::motion_plan::{
    Goal, MotionAnswer, MotionQuery, PlanJson, RobotSource, Start, plan_motion, planning_params,
};
use tabula_geom::input::{Format, read_text};
use tabula_geom::pose_from_xyz_rpy;
use tabula_motion::moveit::{Limits, MotionRequest};

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

pub fn run(a: PlanArgs) -> Result<()> {
    if a.print_params {
        return crate::tasks::print_toml(&planning_params(None)?);
    }
    let mut params = planning_params(a.params.as_deref())?;
    if let Some(seed) = a.seed {
        params.planner.seed = seed;
    }
    let start = match (&a.start, &a.start_named) {
        (Some(q), _) => Start::Joints(q.clone()),
        (None, Some(n)) => Start::Named(n.clone()),
        (None, None) => Start::Current,
    };
    let goal = if let Some(q) = &a.goal_joints {
        Goal::Joints(q.clone())
    } else if let Some(p) = &a.goal_pose {
        Goal::Pose(pose_from_xyz_rpy([p[0], p[1], p[2]], [p[3], p[4], p[5]]))
    } else if let Some(n) = &a.goal_named {
        Goal::Named(n.clone())
    } else {
        let p = a
            .request
            .as_deref()
            .ok_or_else(|| anyhow!("no goal given"))?;
        Goal::Request(
            MotionRequest::from_yaml(&read_text(p, Format::Scene)?, &Limits::default())
                .with_context(|| p.display().to_string())?,
        )
    };
    let tabula_scene = a
        .scene
        .as_deref()
        .and_then(std::path::Path::extension)
        .is_some_and(|e| e.eq_ignore_ascii_case("toml"));
    if a.robot.is_none() && !tabula_scene {
        bail!(
            "--robot is required (a URDF or xacro file, or wam/pr2/golem3) unless the scene is a tabula scene"
        );
    }
    let query = MotionQuery {
        robot: RobotSource::Named(a.robot.as_deref()),
        scene: a.scene.as_deref(),
        group: a.group.as_deref(),
        start,
        goal,
        params,
        timeout: a.timeout,
    };
    match plan_motion(query)? {
        MotionAnswer::Planned(plan) => print_plan(a.json, &plan),
        MotionAnswer::NoPlan(no) => {
            if a.json {
                println!("{}", serde_json::to_string(&no)?);
            }
            Err(NoSolution(no.message).into())
        }
    }
}

fn print_plan(json: bool, plan: &PlanJson) -> Result<()> {
    if json {
        println!("{}", serde_json::to_string(plan)?);
        return Ok(());
    }
    println!(
        "planned group `{}`: {} waypoints, path length {:.3} rad, {:.2} s trajectory ({} samples), planning {:.2} ms",
        plan.group,
        plan.path.len(),
        plan.path_length,
        plan.duration,
        plan.points.len(),
        plan.planning_us * 1e-3
    );
    println!("  joints: {}", plan.joint_names.join(" "));
    for q in &plan.path {
        let row: Vec<String> = q.iter().map(|v| format!("{v:+.4}")).collect();
        println!("  {}", row.join(" "));
    }
    Ok(())
}
