//! A robot with no body: commands are integrated into its joint state and nothing else
//! (MoveIt's fake controllers), so a task or a manipulation command can be tried dry —
//! same planning, same trajectories, no physics and no sensors.

use crate::driver::{
    Annotations, Arms, BaseControl, CameraFrame, Cameras, DriverError, GripState, Grippers,
    HeadControl, JointState, JointStates, JointTrajectory, stop_requested,
};
use crate::robots::NamedRobot;
use tabula_geom::{Pose, Quat, Vec3};

/// The fake robot: a joint state, where its root is, and what it was asked to do.
pub struct FakeDriver {
    robot: NamedRobot,
    state: JointState,
    world_from_root: Pose,
    /// Clock (s): advanced by each trajectory's duration.
    time: f64,
    /// Every trajectory executed, in order.
    pub executed: Vec<JointTrajectory>,
    /// Gripper commands and annotations, in order (`open right_gripper`, …).
    pub log: Vec<String>,
}

impl FakeDriver {
    /// `robot` at `state` with its root at `world_from_root`.
    pub fn new(robot: NamedRobot, state: JointState, world_from_root: Pose) -> Self {
        Self {
            robot,
            state,
            world_from_root,
            time: 0.0,
            executed: Vec::new(),
            log: Vec::new(),
        }
    }

    fn set(&mut self, name: &str, value: f64) -> Result<(), DriverError> {
        let j = self
            .robot
            .model
            .joint(name)
            .ok_or_else(|| DriverError::UnknownJoint(name.into()))?;
        let limits = self.robot.model.joints[j].limits;
        let value = value.clamp(limits.lower, limits.upper);
        match self.state.names.iter().position(|n| n == name) {
            Some(i) => self.state.positions[i] = value,
            None => {
                self.state.names.push(name.into());
                self.state.positions.push(value);
            }
        }
        Ok(())
    }

    fn gripper(&self, name: &str) -> Result<crate::description::Gripper, DriverError> {
        self.robot
            .description
            .grippers
            .iter()
            .find(|g| g.name == name)
            .cloned()
            .ok_or_else(|| DriverError::Hardware(format!("no gripper `{name}`")))
    }

    /// A gripper's description and its finger joint's index in the model.
    fn finger_joint(
        &self,
        gripper: &str,
    ) -> Result<(crate::description::Gripper, usize), DriverError> {
        let g = self.gripper(gripper)?;
        let j = self
            .robot
            .model
            .joint(&g.finger_joint)
            .ok_or_else(|| DriverError::UnknownJoint(g.finger_joint.clone()))?;
        Ok((g, j))
    }

    /// The finger gap now.
    fn width(&self, gripper: &str) -> Result<f64, DriverError> {
        let (g, j) = self.finger_joint(gripper)?;
        let value = self
            .state
            .get(&g.finger_joint)
            .unwrap_or_else(|| self.robot.model.mid_configuration()[j]);
        Ok(g.width_at(&self.robot.model, value))
    }

    fn finger(&mut self, gripper: &str, open: bool) -> Result<f64, DriverError> {
        if stop_requested() {
            return Err(DriverError::Stopped);
        }
        let (g, j) = self.finger_joint(gripper)?;
        let l = self.robot.model.joints[j].limits;
        // The description's widths map the finger joint's limits (lower = closed).
        let value = if open { l.upper } else { l.lower };
        self.set(&g.finger_joint, value)?;
        self.log
            .push(format!("{} {gripper}", if open { "open" } else { "close" }));
        Ok(g.width_at(&self.robot.model, value))
    }
}

impl JointStates for FakeDriver {
    fn joint_state(&self) -> Result<JointState, DriverError> {
        Ok(JointState {
            stamp: self.time,
            ..self.state.clone()
        })
    }

    fn world_from_root(&self) -> Result<Pose, DriverError> {
        Ok(self.world_from_root)
    }
}

impl Arms for FakeDriver {
    /// The trajectory is checked (joints known, times increasing, values finite) and its
    /// last point becomes the state, as a perfectly tracking controller would leave it.
    fn execute(&mut self, trajectory: &JointTrajectory) -> Result<(), DriverError> {
        if stop_requested() {
            return Err(DriverError::Stopped);
        }
        trajectory.validate()?;
        for n in &trajectory.joint_names {
            if self.robot.model.joint(n).is_none() {
                return Err(DriverError::UnknownJoint(n.clone()));
            }
        }
        if let Some(last) = trajectory.positions.last() {
            for (n, v) in trajectory.joint_names.iter().zip(last) {
                self.set(n, *v)?;
            }
        }
        self.time += trajectory.duration();
        self.executed.push(trajectory.clone());
        Ok(())
    }
}

impl Grippers for FakeDriver {
    fn open(&mut self, gripper: &str) -> Result<(), DriverError> {
        self.finger(gripper, true).map(|_| ())
    }

    /// Closes fully: with nothing in the world, nothing is ever held.
    fn close(&mut self, gripper: &str) -> Result<GripState, DriverError> {
        let width = self.finger(gripper, false)?;
        Ok(GripState {
            width,
            holding: false,
        })
    }

    fn grip_state(&self, gripper: &str) -> Result<GripState, DriverError> {
        Ok(GripState {
            width: self.width(gripper)?,
            holding: false,
        })
    }
}

impl Cameras for FakeDriver {
    fn capture(&mut self, _camera: &str) -> Result<CameraFrame, DriverError> {
        Err(DriverError::Unsupported("camera in a dry run"))
    }
}

impl HeadControl for FakeDriver {
    fn look_at(&mut self, _world_point: Vec3) -> Result<f64, DriverError> {
        Err(DriverError::Unsupported("head in a dry run"))
    }
}

impl BaseControl for FakeDriver {
    /// The base arrives where it was sent.
    fn drive_to(&mut self, x: f64, y: f64, theta: f64) -> Result<(), DriverError> {
        if stop_requested() {
            return Err(DriverError::Stopped);
        }
        if self.robot.description.base.is_none() {
            return Err(DriverError::Unsupported("mobile base"));
        }
        if ![x, y, theta].iter().all(|v| v.is_finite()) {
            return Err(DriverError::NonFinite);
        }
        let z = self.world_from_root.translation.z;
        self.world_from_root = Pose::from_parts(Vec3::new(x, y, z), Quat::from_rotation_z(theta));
        Ok(())
    }
}

impl Annotations for FakeDriver {
    fn annotate(&mut self, label: &str) {
        self.log.push(format!("note {label}"));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn wam() -> FakeDriver {
        let robot = crate::robots::load("wam").unwrap();
        let mut state = JointState::default();
        for j in &robot.model.joints {
            if j.kind.is_single_axis() {
                state.names.push(j.name.clone());
                state.positions.push(0.0);
            }
        }
        FakeDriver::new(robot, state, Pose::IDENTITY)
    }

    #[test]
    fn commands_are_integrated_and_checked() {
        let mut d = wam();
        let t = JointTrajectory {
            joint_names: vec!["wam_joint2".into(), "wam_joint4".into()],
            times: vec![0.0, 1.0, 2.5],
            positions: vec![vec![0.0, 0.0], vec![0.3, 0.5], vec![0.6, 1.0]],
        };
        d.execute(&t).unwrap();
        let s = d.joint_state().unwrap();
        assert_eq!(s.get("wam_joint2"), Some(0.6));
        assert_eq!(s.get("wam_joint4"), Some(1.0));
        assert_eq!(s.stamp, 2.5);
        assert_eq!(d.executed.len(), 1);
        let unknown = JointTrajectory {
            joint_names: vec!["elbow".into()],
            times: vec![0.0, 1.0],
            positions: vec![vec![0.0], vec![1.0]],
        };
        assert_eq!(
            d.execute(&unknown),
            Err(DriverError::UnknownJoint("elbow".into()))
        );
        let g = d.close("gripper").unwrap();
        assert!((g.width - 0.03).abs() < 1e-12 && !g.holding);
        d.open("gripper").unwrap();
        assert_eq!(d.log, ["close gripper", "open gripper"]);
        assert!(matches!(
            d.capture("overhead"),
            Err(DriverError::Unsupported(_))
        ));
        assert!(matches!(
            d.drive_to(1.0, 0.0, 0.0),
            Err(DriverError::Unsupported(_))
        ));
    }
}
