//! `tabula arm`: a manipulation service on the command line (seed 001 §3.3): move an
//! arm to joint values, its tool to a pose, to a named pose of the robot description,
//! open or close a gripper — planned collision-free against the scene's furniture and
//! objects, executed in the simulator or, with `--dry-run`, through a fake driver that
//! only integrates the commands (MoveIt's fake controllers): the same plan either way.

use crate::tasks::{load_params, load_world, scene_robot_named};
use anyhow::{Context, Result, anyhow, bail};
use clap::{Args, Subcommand, ValueEnum};
use serde::Serialize;
use std::path::PathBuf;
use tabula_geom::{Pose, pose_from_xyz_rpy};
use tabula_motion::group::{MoveGroup, MoveGroupParams};
use tabula_robot::driver::{JointTrajectory, RobotDriver};
use tabula_robot::fake::FakeDriver;
use tabula_robot::robots::NamedRobot;
use tabula_sim::{SimDriver, SimWorld};

#[derive(Args)]
pub struct ArmArgs {
    #[arg(long, required_unless_present = "print_params")]
    scene: Option<PathBuf>,
    /// The robot to command when the scene has several.
    #[arg(long)]
    robot: Option<String>,
    /// Execute through a fake driver that only integrates commands (no physics).
    #[arg(long)]
    dry_run: bool,
    /// Motion parameters (TOML, `MoveGroupParams`).
    #[arg(long)]
    params: Option<PathBuf>,
    /// Print the parameters `--params` takes, with their defaults (SPEC's values), as
    /// TOML to start a file from, and exit.
    #[arg(long, exclusive = true)]
    print_params: bool,
    #[arg(long)]
    json: bool,
    /// Write the world afterwards as a scene file (simulator only).
    #[arg(long)]
    save_scene: Option<PathBuf>,
    #[command(subcommand)]
    action: Option<ArmAction>,
}

#[derive(Subcommand, Clone)]
enum ArmAction {
    /// Move an arm to joint values (the arm's joints in order; `tabula ik info` lists them).
    MoveJoints {
        /// The arm (a name from the robot's description; default: its first).
        #[arg(long)]
        arm: Option<String>,
        #[arg(required = true, allow_negative_numbers = true, value_parser = crate::args::finite)]
        values: Vec<f64>,
    },
    /// Move an arm's tool to a pose in the world: x y z (m) roll pitch yaw (rad).
    MovePose {
        #[arg(long)]
        arm: Option<String>,
        #[arg(num_args = 6, required = true, allow_negative_numbers = true, value_names = ["X", "Y", "Z", "ROLL", "PITCH", "YAW"], value_parser = crate::args::finite)]
        pose: Vec<f64>,
    },
    /// Move an arm to a named pose of the robot description (`tuck`).
    Named {
        #[arg(long)]
        arm: Option<String>,
        name: String,
    },
    /// Open or close a gripper (default: the first arm's).
    Gripper {
        #[arg(long)]
        gripper: Option<String>,
        command: GripCommand,
        /// Close squeezing with at most this force (N per finger, capped at the finger
        /// joint's limit): the object is held only if friction carries it.
        #[arg(long, value_parser = crate::args::finite)]
        effort: Option<f64>,
        /// Open gently: the finger gap grows at most this fast (m/s).
        #[arg(long, value_parser = crate::args::finite)]
        speed: Option<f64>,
    },
}

#[derive(ValueEnum, Clone, Copy, PartialEq, Eq, Debug)]
enum GripCommand {
    Open,
    Close,
}

/// What `arm` prints with `--json`.
#[derive(Serialize)]
struct ArmJson {
    driver: &'static str,
    action: String,
    arm: Option<String>,
    /// The executed trajectory (moves only).
    trajectory: Option<TrajectoryJson>,
    planning_ms: Option<f64>,
    /// Every joint of the robot afterwards.
    joints: Vec<(String, f64)>,
    /// The arm's tool in the world afterwards: x y z qx qy qz qw.
    tool_pose: Option<[f64; 7]>,
    /// Gripper commands: the fingers' gap afterwards (m) and whether they hold something.
    grip: Option<(f64, bool)>,
}

#[derive(Serialize)]
struct TrajectoryJson {
    joint_names: Vec<String>,
    times: Vec<f64>,
    positions: Vec<Vec<f64>>,
}

impl From<&JointTrajectory> for TrajectoryJson {
    fn from(t: &JointTrajectory) -> Self {
        Self {
            joint_names: t.joint_names.clone(),
            times: t.times.clone(),
            positions: t.positions.clone(),
        }
    }
}

pub fn run(a: ArmArgs) -> Result<()> {
    if a.print_params {
        return crate::tasks::print_params::<MoveGroupParams>();
    }
    let Some(action) = &a.action else {
        return Err(crate::args::Usage(
            "'tabula arm' requires a subcommand: move-joints, move-pose, named or gripper".into(),
        )
        .into());
    };
    let params: MoveGroupParams = load_params(a.params.as_deref())?;
    let (_, world) = load_world(crate::args::given(&a.scene, "--scene")?)?;
    let (robot_name, robot) = scene_robot_named(&world, a.robot.as_deref())?;
    let obstacles = world.planning_scene(&robot_name);
    let out = if a.dry_run {
        let state = world.robot(&robot_name)?;
        let js = tabula_robot::driver::JointState::of_model(&state.model, &state.values);
        let mut fake = FakeDriver::new(robot.clone(), js, state.world_from_root);
        act(&mut fake, &robot, &obstacles, action, &params, "fake")?
    } else {
        let mut sim = SimDriver::new(world, &robot_name, 1)?;
        let out = act(&mut sim, &robot, &obstacles, action, &params, "simulator")?;
        save_scene(&sim.world, a.save_scene.as_ref())?;
        out
    };
    if a.dry_run && a.save_scene.is_some() {
        bail!("--save-scene needs the simulator (a dry run changes no world)");
    }
    if a.json {
        println!("{}", serde_json::to_string_pretty(&out)?);
    } else {
        println!(
            "arm ({}): {}{}",
            out.driver,
            out.action,
            out.arm
                .as_ref()
                .map_or(String::new(), |a| format!(" (arm {a})"))
        );
        if let (Some(t), Some(ms)) = (&out.trajectory, out.planning_ms) {
            println!(
                "  planned in {ms:.1} ms: {} points over {:.2} s",
                t.positions.len(),
                t.times.last().copied().unwrap_or(0.0)
            );
        }
        if let Some(p) = out.tool_pose {
            println!(
                "  tool at ({:.4}, {:.4}, {:.4}), quaternion ({:.4}, {:.4}, {:.4}, {:.4})",
                p[0], p[1], p[2], p[3], p[4], p[5], p[6]
            );
        }
        if let Some((width, holding)) = out.grip {
            println!(
                "  fingers {:.1} mm apart{}",
                width * 1e3,
                if holding { ", holding something" } else { "" }
            );
        }
    }
    Ok(())
}

/// Writes `world` as a scene file (`--save-scene`), when a path was given.
pub fn save_scene(world: &SimWorld, path: Option<&PathBuf>) -> Result<()> {
    if let Some(path) = path {
        let text = world
            .to_scene()
            .to_toml()
            .map_err(|e| anyhow!("cannot write the scene: {e}"))?;
        std::fs::write(path, text).with_context(|| format!("cannot write {}", path.display()))?;
    }
    Ok(())
}

/// A shape of the planning scene: name, shape, world pose.
pub type Obstacle = (String, tabula_geom::parry::shape::SharedShape, Pose);

/// The arm called `wanted`, or the description's first.
pub fn arm_name(robot: &NamedRobot, wanted: Option<&String>) -> Result<String> {
    match wanted {
        Some(a) => Ok(robot.description.arm(a)?.name.clone()),
        None => robot
            .description
            .arms
            .first()
            .map(|a| a.name.clone())
            .ok_or_else(|| anyhow!("the robot has no arm")),
    }
}

/// Plans and executes `action` through `driver`.
fn act(
    driver: &mut impl RobotDriver,
    robot: &NamedRobot,
    obstacles: &[Obstacle],
    action: &ArmAction,
    params: &MoveGroupParams,
    driver_name: &'static str,
) -> Result<ArmJson> {
    let state = driver.joint_state()?;
    let mut out = ArmJson {
        driver: driver_name,
        action: String::new(),
        arm: None,
        trajectory: None,
        planning_ms: None,
        joints: Vec::new(),
        tool_pose: None,
        grip: None,
    };
    let arm = match action {
        ArmAction::Gripper {
            gripper,
            command,
            effort,
            speed,
        } => {
            let g = match gripper {
                Some(g) => g.clone(),
                None => {
                    let arm = arm_name(robot, None)?;
                    let group = robot.description.arm(&arm)?;
                    robot
                        .description
                        .gripper_of(group)
                        .map(|g| g.name.clone())
                        .ok_or_else(|| anyhow!("arm `{arm}` has no gripper"))?
                }
            };
            out.action = format!(
                "{} {g}",
                if *command == GripCommand::Open {
                    "open"
                } else {
                    "close"
                }
            );
            match command {
                GripCommand::Open => {
                    match speed {
                        Some(v) if *v <= 0.0 => bail!("--speed must be positive"),
                        Some(v) => driver.open_slowly(&g, *v)?,
                        None => driver.open(&g)?,
                    }
                    let grip = driver.grip_state(&g)?;
                    out.grip = Some((grip.width, grip.holding));
                }
                GripCommand::Close => {
                    let grip = match effort {
                        Some(e) if *e < 0.0 => bail!("--effort must not be negative"),
                        Some(e) => driver.close_with_effort(&g, *e)?,
                        None => driver.close(&g)?,
                    };
                    out.grip = Some((grip.width, grip.holding));
                }
            }
            None
        }
        ArmAction::MoveJoints { arm, .. }
        | ArmAction::MovePose { arm, .. }
        | ArmAction::Named { arm, .. } => Some(arm_name(robot, arm.as_ref())?),
    };
    if let Some(arm) = &arm {
        let mut group = MoveGroup::at_driver(driver, (robot, arm), obstacles, params)?;
        let start = group.arm_values(&state);
        let plan = match action {
            ArmAction::MoveJoints { values, .. } => {
                let names = group.joint_names();
                if values.len() != names.len() {
                    bail!(
                        "arm `{arm}` has {} joints ({}), {} values given",
                        names.len(),
                        names.join(", "),
                        values.len()
                    );
                }
                out.action = format!("move-joints {values:?}");
                group.plan_to_joints(&start, std::slice::from_ref(values))
            }
            ArmAction::MovePose { pose, .. } => {
                out.action = format!("move-pose {pose:?}");
                let target =
                    pose_from_xyz_rpy([pose[0], pose[1], pose[2]], [pose[3], pose[4], pose[5]]);
                group.plan_to_pose(&start, &target)
            }
            ArmAction::Named { name, .. } => {
                let goal = robot.description.arm(arm)?.named_configuration(
                    name,
                    group.joint_names(),
                    &start,
                )?;
                out.action = format!("named {name}");
                group.plan_to_joints(&start, &[goal])
            }
            ArmAction::Gripper { .. } => unreachable!("handled above"),
        };
        let plan = plan.map_err(|e| NoSolution(e.to_string()))?;
        driver.execute(&plan.trajectory)?;
        out.planning_ms = Some(plan.planning_time * 1e3);
        out.trajectory = Some((&plan.trajectory).into());
        let after = driver.joint_state()?;
        group.set_state(robot, &after)?;
        let tool = group.tip_pose(&group.arm_values(&after))?;
        let (t, q) = (tool.translation, tool.rotation);
        out.tool_pose = Some([t.x, t.y, t.z, q.x, q.y, q.z, q.w]);
    }
    out.arm = arm;
    let after = driver.joint_state()?;
    out.joints = after.names.into_iter().zip(after.positions).collect();
    Ok(out)
}

/// No plan for the command: exit status 2, like every "no solution".
#[derive(Debug)]
pub struct NoSolution(pub String);

impl std::fmt::Display for NoSolution {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "no plan: {}", self.0)
    }
}

impl std::error::Error for NoSolution {}
