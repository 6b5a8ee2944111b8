//! Where a robot the user brings stands in the clearing cell: the stand's height and
//! place chosen so its arm reaches down onto every part of the table's region and above
//! the bin (as a cell integrator would place it), and a start pose out of the overhead
//! camera's view. Nothing about the robot is written in code: its arm, gripper and named
//! poses come from its description (SRDF or TOML).

use anyhow::{Result, anyhow};
use std::collections::BTreeMap;
use tabula_geom::{Pose, Vec3};
use tabula_robot::description::ArmGroup;
use tabula_robot::ik::{IkMode, NumericIkParams};
use tabula_robot::robots::NamedRobot;
use tabula_sim::generate::{
    CLEAR_BIN_CENTER, CLEAR_BIN_HEIGHT, CLEAR_REGION_CENTER, CLEAR_REGION_HALF, CLEAR_TABLE_CENTER,
    CLEAR_TABLE_SIZE, RobotMount, TABLE_TOP,
};
use tabula_tasks::skills::hand::tool_rotation;

/// Stand heights tried (m): from well below the table top to well above it.
const STAND_HEIGHTS: [f64; 13] = [
    0.40, 0.45, 0.50, 0.55, 0.60, 0.65, 0.70, 0.75, 0.80, 0.85, 0.90, 0.95, 1.00,
];
/// Stand positions along the table's long axis (m): the stand is 0.3 m across and the
/// table starts at x = 0.27, so at most 0.12.
const STAND_X: [f64; 3] = [0.0, 0.06, 0.12];
/// Grasp-frame heights above the table tried at each point of the region (m): at a low
/// object's middle and where a lift ends.
const REACH_HEIGHTS: [f64; 2] = [0.03, 0.2];
/// Grasp-frame height above the bin's rim for a release (m).
const ABOVE_BIN: f64 = 0.25;
/// A link origin over the table must stay this far above its top (m).
const TABLE_CLEARANCE: f64 = 0.02;
/// The overhead camera of the cell (`clearing_scene`).
const CAMERA_HEIGHT: f64 = 1.75;

/// The stand and start pose for `robot` in the clearing cell; `file` is how the scene
/// names the robot (its path), `srdf` and `xacro_args` as it was loaded.
pub fn clearing_mount(
    robot: &NamedRobot,
    file: &str,
    srdf: Option<&str>,
    xacro_args: &[(String, String)],
) -> Result<RobotMount> {
    let arm = robot
        .description
        .arms
        .iter()
        .find(|a| robot.description.gripper_of(a).is_some())
        .ok_or_else(|| {
            anyhow!(
                "robot {file}: no arm with a parallel gripper (give it an SRDF whose end \
                 effector is one, or a [[gripper]] in its TOML)"
            )
        })?;
    let reach = Reach::new(robot, arm)?;
    let mut best: Option<(usize, f64, [f64; 3])> = None;
    for &z in &STAND_HEIGHTS {
        for &x in &STAND_X {
            let at = [x, 0.0, z];
            let reached = reach.count(at);
            let closer = (z - TABLE_TOP).abs();
            let better = best.is_none_or(|(n, c, _)| reached > n || (reached == n && closer < c));
            if better {
                best = Some((reached, closer, at));
            }
        }
    }
    let (reached, _, xyz) = best.expect("stand candidates are not empty");
    if reached < reach.targets.len() {
        tracing::warn!(
            "robot {file}: from its best stand ({xyz:?}) the arm `{}` reaches {reached} of {} \
             test poses over the table and the bin",
            arm.name,
            reach.targets.len()
        );
    }
    Ok(RobotMount {
        urdf: file.to_string(),
        srdf: srdf.map(str::to_string),
        xacro_args: xacro_args.to_vec(),
        xyz,
        joints: start_pose(robot, arm, xyz)?,
    })
}

/// The arm's reach test: top-down grasp-frame targets over the region and the bin.
struct Reach<'a> {
    robot: &'a NamedRobot,
    solver: Box<dyn tabula_robot::ik::IkSolver + Send + Sync>,
    chain: tabula_robot::Chain,
    seed: Vec<f64>,
    tool_axis: Vec3,
    /// World poses of the grasp frame.
    targets: Vec<Pose>,
}

impl<'a> Reach<'a> {
    fn new(robot: &'a NamedRobot, arm: &ArmGroup) -> Result<Self> {
        let gripper = robot
            .description
            .gripper_of(arm)
            .ok_or_else(|| anyhow!("arm `{}` has no gripper", arm.name))?;
        let numeric = NumericIkParams {
            timeout_s: None,
            max_attempts: 20,
            ..Default::default()
        };
        let solver = arm.ik_solver(&robot.model, numeric)?;
        let chain = arm.chain(&robot.model)?;
        let down = tool_rotation(gripper.approach(), gripper.closing(), -Vec3::Z, Vec3::X);
        let mut targets = Vec::new();
        for i in [-1.0, 0.0, 1.0] {
            for j in [-1.0, 0.0, 1.0] {
                for h in REACH_HEIGHTS {
                    let p = Vec3::new(
                        CLEAR_REGION_CENTER[0] + i * CLEAR_REGION_HALF[0],
                        CLEAR_REGION_CENTER[1] + j * CLEAR_REGION_HALF[1],
                        TABLE_TOP + h,
                    );
                    targets.push(Pose::from_parts(p, down));
                }
            }
        }
        let bin = Vec3::new(
            CLEAR_BIN_CENTER[0],
            CLEAR_BIN_CENTER[1],
            CLEAR_BIN_HEIGHT + ABOVE_BIN,
        );
        targets.push(Pose::from_parts(bin, down));
        Ok(Self {
            robot,
            seed: chain.mid_configuration(),
            solver,
            chain,
            tool_axis: gripper.approach(),
            targets,
        })
    }

    /// How many targets the arm reaches from a base at `xyz` without dipping a link
    /// into the table.
    fn count(&self, xyz: [f64; 3]) -> usize {
        let world_from_base = Pose::from_translation(Vec3::from_array(xyz));
        let base_from_world = world_from_base.inverse();
        let mode = IkMode::PositionAxis {
            tool_axis: self.tool_axis,
        };
        self.targets
            .iter()
            .filter(|t| {
                let Ok(solutions) = self
                    .solver
                    .solve(&(base_from_world * **t), mode, &self.seed)
                else {
                    return false;
                };
                solutions
                    .iter()
                    .any(|s| self.clear_of_table(world_from_base, &s.joints))
            })
            .count()
    }

    fn clear_of_table(&self, world_from_base: Pose, arm_joints: &[f64]) -> bool {
        let model = &self.robot.model;
        let mut values = vec![0.0; model.joints.len()];
        for (&j, &q) in self.chain.joint_indices.iter().zip(arm_joints) {
            values[j] = q;
        }
        let Ok(fk) = model.forward_kinematics(&values) else {
            return false;
        };
        let base = model
            .link(&self.chain.base_link)
            .map(|b| fk[b])
            .unwrap_or(Pose::IDENTITY);
        let world_from_root = world_from_base * base.inverse();
        fk.iter().all(|root_from_link| {
            let p = world_from_root.transform_point(root_from_link.translation);
            !over_table(p) || p.z >= TABLE_TOP + TABLE_CLEARANCE
        })
    }
}

fn over_table(p: Vec3) -> bool {
    (p.x - CLEAR_TABLE_CENTER[0]).abs() <= CLEAR_TABLE_SIZE[0] / 2.0
        && (p.y - CLEAR_TABLE_CENTER[1]).abs() <= CLEAR_TABLE_SIZE[1] / 2.0
}

/// The arm's start (and home between actions): its tucked pose, else the named pose (or
/// all joints at zero) whose links the overhead camera sees least of over the region.
fn start_pose(robot: &NamedRobot, arm: &ArmGroup, xyz: [f64; 3]) -> Result<BTreeMap<String, f64>> {
    if !arm.tucked.is_empty() {
        return Ok(arm.tucked.clone());
    }
    let chain = arm.chain(&robot.model)?;
    let mid: BTreeMap<String, f64> = chain
        .joint_names
        .iter()
        .zip(chain.mid_configuration())
        .map(|(n, mid)| (n.clone(), mid))
        .collect();
    let mut candidates: Vec<&BTreeMap<String, f64>> = arm.named.values().collect();
    candidates.push(&mid);
    let world_from_base = Pose::from_translation(Vec3::from_array(xyz));
    let seen = |state: &BTreeMap<String, f64>| -> usize {
        let model = &robot.model;
        let mut values = vec![0.0; model.joints.len()];
        for (name, &q) in state {
            if let Some(j) = model.joint(name) {
                values[j] = q;
            }
        }
        let Ok(fk) = model.forward_kinematics(&values) else {
            return usize::MAX;
        };
        let base = model
            .link(&chain.base_link)
            .map(|b| fk[b])
            .unwrap_or(Pose::IDENTITY);
        let world_from_root = world_from_base * base.inverse();
        fk.iter()
            .filter(|l| in_view(world_from_root.transform_point(l.translation)))
            .count()
    };
    let best = candidates
        .into_iter()
        .min_by_key(|s| seen(s))
        .cloned()
        .unwrap_or_default();
    Ok(best)
}

/// Whether the overhead camera sees `p` in front of the region (with a margin).
fn in_view(p: Vec3) -> bool {
    if p.z >= CAMERA_HEIGHT || p.z < TABLE_TOP - 0.01 {
        return false;
    }
    let camera = Vec3::new(CLEAR_TABLE_CENTER[0], CLEAR_TABLE_CENTER[1], CAMERA_HEIGHT);
    let t = (CAMERA_HEIGHT - TABLE_TOP) / (CAMERA_HEIGHT - p.z);
    let hit = camera + (p - camera) * t;
    (hit.x - CLEAR_REGION_CENTER[0]).abs() <= CLEAR_REGION_HALF[0] + 0.05
        && (hit.y - CLEAR_REGION_CENTER[1]).abs() <= CLEAR_REGION_HALF[1] + 0.05
}
