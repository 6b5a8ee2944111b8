//! Jogging the tool (MoveIt Servo's job; seed 000 §1.6's Module 0): one step of the
//! tool along or about an axis, in the robot's base frame or the tool's own, as a
//! Cartesian path through the arm's IK from the current joints, checked against the
//! joints' limits and the scene; the torso's lift; the gripper; the head turned to the
//! gripper. Through the driver traits: the same steps drive the simulator or a robot.

use super::SkillError;
use tabula_geom::{Pose, Quat, Vec3};
use tabula_motion::MoveError;
use tabula_motion::group::MoveGroup;
use tabula_robot::driver::{DriverError, GripState, JointTrajectory, RobotDriver};
use tabula_robot::model::JointKind;
use tabula_robot::robots::NamedRobot;

/// Which frame a step is taken in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum JogFrame {
    /// The robot's base (odometry) frame.
    Base,
    /// The tool's own frame.
    Tool,
}

/// One of the arm's joints as the jog reports it: name, value, lower and upper limit.
pub type JointReading = (String, f64, f64, f64);

/// A jogged arm: the driver, the robot, the arm's move group over the scene.
pub struct Jog<D> {
    pub driver: D,
    pub robot: NamedRobot,
    pub arm: String,
    /// The arm over the scene's furniture and objects; its allowed-collision matrix is
    /// sampled once, each step only takes the new joint state.
    pub group: MoveGroup,
    pub frame: JogFrame,
}

fn robot_error(e: impl std::fmt::Display) -> SkillError {
    SkillError::Robot(e.to_string())
}

impl<D: RobotDriver> Jog<D> {
    /// The arm's joint values now, the group set to the driver's state.
    fn current(&mut self) -> Result<(Vec<f64>, tabula_robot::driver::JointState), SkillError> {
        let state = self.driver.joint_state()?;
        self.group.set_state(&self.robot, &state)?;
        Ok((self.group.arm_values(&state), state))
    }

    /// The tool's pose in the robot's base frame and the arm's joints.
    pub fn status(&mut self) -> Result<(Pose, Vec<JointReading>), SkillError> {
        let (q, _) = self.current()?;
        let base_from_tool = self.driver.world_from_root()?.inverse() * self.group.tip_pose(&q)?;
        let model = &self.robot.model;
        let joints = self
            .group
            .joint_names()
            .iter()
            .zip(&q)
            .map(|(n, v)| {
                let l = model.joint(n).map(|j| model.joints[j].limits);
                let (lo, hi) = l.map_or((f64::NAN, f64::NAN), |l| (l.lower, l.upper));
                (n.clone(), *v, lo, hi)
            })
            .collect();
        Ok((base_from_tool, joints))
    }

    /// One step: `translation` (m) and `rotation` (a rotation vector, rad) in the
    /// current frame, executed, or refused with the reason.
    pub fn step(&mut self, translation: Vec3, rotation: Vec3) -> Result<(), SkillError> {
        let (q, _) = self.current()?;
        let world_from_tool = self.group.tip_pose(&q)?;
        let target = match self.frame {
            JogFrame::Base => {
                let r = self.driver.world_from_root()?.rotation;
                Pose::from_parts(
                    world_from_tool.translation + r * translation,
                    Quat::from_scaled_axis(r * rotation) * world_from_tool.rotation,
                )
            }
            JogFrame::Tool => {
                world_from_tool * Pose::from_parts(translation, Quat::from_scaled_axis(rotation))
            }
        };
        let plan = self.group.cartesian(&q, &target)?;
        self.driver.execute(&plan.trajectory)?;
        Ok(())
    }

    /// Moves the torso's lift joint by `delta` (m), inside its limits and only if the
    /// arm stays clear of the scene there; the lift's new height.
    pub fn torso(&mut self, delta: f64) -> Result<f64, SkillError> {
        let model = &self.robot.model;
        let lift = self
            .robot
            .description
            .torso_joints
            .iter()
            .find(|n| {
                model
                    .joint(n)
                    .is_some_and(|j| model.joints[j].kind == JointKind::Prismatic)
            })
            .cloned()
            .ok_or_else(|| robot_error("this robot has no torso lift"))?;
        let j = model
            .joint(&lift)
            .ok_or_else(|| robot_error(format!("no joint {lift}")))?;
        let limits = model.joints[j].limits;
        let state = self.driver.joint_state()?;
        let now = state.get(&lift).unwrap_or(0.0);
        let goal = now + delta;
        if goal < limits.lower - 1e-9 || goal > limits.upper + 1e-9 {
            return Err(robot_error(format!(
                "{lift} would leave its limits [{:.3}, {:.3}] m",
                limits.lower, limits.upper
            )));
        }
        let mut after = state.clone();
        if let Some(i) = after.names.iter().position(|n| *n == lift) {
            after.positions[i] = goal;
        }
        self.group.set_state(&self.robot, &after)?;
        let clash = self
            .group
            .world
            .first_collision(&self.group.arm_values(&after))
            .map_err(MoveError::from)?;
        self.group.set_state(&self.robot, &state)?;
        if let Some((a, b)) = clash {
            return Err(SkillError::Motion(format!("{a} would touch {b}")));
        }
        let v = limits.velocity.clamp(0.01, 0.1);
        self.driver.execute(&JointTrajectory {
            joint_names: vec![lift],
            times: vec![0.0, delta.abs() / v],
            positions: vec![vec![now], vec![goal]],
        })?;
        Ok(goal)
    }

    /// Opens the arm's gripper (`None`), or closes it squeezing with `effort` (N per
    /// finger; the joint's limit caps it) and says what it holds.
    pub fn gripper(&mut self, close_effort: Option<f64>) -> Result<Option<GripState>, SkillError> {
        let group = self.robot.description.arm(&self.arm).map_err(robot_error)?;
        let g = self
            .robot
            .description
            .gripper_of(group)
            .map(|g| g.name.clone())
            .ok_or_else(|| robot_error(format!("arm `{}` has no gripper", self.arm)))?;
        let state = match close_effort {
            None => {
                self.driver.open(&g)?;
                None
            }
            Some(effort) => Some(self.driver.close_with_effort(&g, effort)?),
        };
        Ok(state)
    }

    /// Turns the head to the gripper; how far off it stays (rad).
    pub fn look_at_gripper(&mut self) -> Result<f64, SkillError> {
        let (q, _) = self.current()?;
        let at = self.group.tip_pose(&q)?.translation;
        let off: Result<f64, DriverError> = self.driver.look_at(at);
        Ok(off?)
    }
}
