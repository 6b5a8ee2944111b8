//! The task layer needs nothing but the driver traits: a mock robot (commands copied
//! into states, as ros2_control's mock components do; a camera that returns a fixed
//! cloud) runs a whole pick and place, and what it was asked to do is checked.

use tabula_geom::{PointCloud, Pose, Vec3};
use tabula_robot::driver::{
    Annotations, Arms, BaseControl, CameraFrame, Cameras, DriverError, GripState, Grippers,
    HeadControl, JointState, JointStates, JointTrajectory,
};
use tabula_robot::robots::{self, NamedRobot};
use tabula_tasks::pick_place::{PickPlaceParams, PickPlaceRequest, pick_place};

struct MockRobot {
    state: JointState,
    cloud: Vec<Vec3>,
    executed: Vec<JointTrajectory>,
    gripper_log: Vec<String>,
    /// Grippers closed on something.
    holding: Vec<String>,
}

impl MockRobot {
    fn new(robot: &NamedRobot, cloud: Vec<Vec3>) -> Self {
        let mut state = JointState::default();
        let mid = robot.model.mid_configuration();
        for (j, joint) in robot.model.joints.iter().enumerate() {
            if joint.kind.is_single_axis() {
                state.names.push(joint.name.clone());
                state.positions.push(mid[j]);
            }
        }
        for (name, v) in [
            ("torso_lift_joint", -0.05),
            ("right_arm_joint4", 0.3),
            ("left_arm_joint4", 0.3),
        ] {
            if let Some(i) = state.names.iter().position(|n| n == name) {
                state.positions[i] = v;
            }
        }
        Self {
            state,
            cloud,
            executed: Vec::new(),
            gripper_log: Vec::new(),
            holding: Vec::new(),
        }
    }
}

impl Annotations for MockRobot {}

impl JointStates for MockRobot {
    fn joint_state(&self) -> Result<JointState, DriverError> {
        Ok(self.state.clone())
    }
    fn world_from_root(&self) -> Result<Pose, DriverError> {
        Ok(Pose::IDENTITY)
    }
}

impl Cameras for MockRobot {
    /// A camera at head height above the robot (its frame only shifted from the world's).
    fn capture(&mut self, _camera: &str) -> Result<CameraFrame, DriverError> {
        let world_from_camera = Pose::from_translation(Vec3::new(0.1, 0.0, 1.6));
        Ok(CameraFrame {
            cloud: PointCloud::unorganized(
                self.cloud
                    .iter()
                    .map(|p| world_from_camera.inverse_transform_point(*p))
                    .collect(),
            ),
            world_from_camera,
            stamp: self.state.stamp,
        })
    }
}

impl Arms for MockRobot {
    fn execute(&mut self, t: &JointTrajectory) -> Result<(), DriverError> {
        t.validate()?;
        let last = t.positions.last().cloned().unwrap_or_default();
        for (name, v) in t.joint_names.iter().zip(last) {
            let i = self
                .state
                .names
                .iter()
                .position(|n| n == name)
                .ok_or_else(|| DriverError::UnknownJoint(name.clone()))?;
            self.state.positions[i] = v;
        }
        self.state.stamp += t.duration();
        self.executed.push(t.clone());
        Ok(())
    }
}

impl Grippers for MockRobot {
    fn open(&mut self, g: &str) -> Result<(), DriverError> {
        self.gripper_log.push(format!("open {g}"));
        self.holding.retain(|h| h != g);
        Ok(())
    }
    fn close(&mut self, g: &str) -> Result<GripState, DriverError> {
        self.gripper_log.push(format!("close {g}"));
        self.holding.push(g.to_string());
        Ok(GripState {
            width: 0.066,
            holding: true,
        })
    }
    fn grip_state(&self, g: &str) -> Result<GripState, DriverError> {
        let holding = self.holding.iter().any(|h| h == g);
        Ok(GripState {
            width: if holding { 0.066 } else { 0.09 },
            holding,
        })
    }
}

impl HeadControl for MockRobot {
    fn look_at(&mut self, _p: Vec3) -> Result<f64, DriverError> {
        Err(DriverError::Unsupported("head"))
    }
}

impl BaseControl for MockRobot {
    fn drive_to(&mut self, _x: f64, _y: f64, _t: f64) -> Result<(), DriverError> {
        Err(DriverError::Unsupported("mobile base"))
    }
}

/// A table top at `z` (a 0.6 m square around `center`) with an upright can of radius
/// 3.3 cm and height 12 cm standing at `can`, sampled every 4 mm as a camera above
/// would see them (top surfaces and the can's side).
fn table_with_can(center: [f64; 2], z: f64, can: [f64; 2]) -> Vec<Vec3> {
    let mut pts = Vec::new();
    let step = 0.004;
    let n = (0.6 / step) as i32;
    for i in 0..n {
        for k in 0..n {
            let p = Vec3::new(
                center[0] - 0.3 + i as f64 * step,
                center[1] - 0.3 + k as f64 * step,
                z,
            );
            if (p.truncate() - Vec3::new(can[0], can[1], 0.0).truncate()).length() > 0.035 {
                pts.push(p);
            }
        }
    }
    let (r, h) = (0.033, 0.12);
    for a in 0..80 {
        let t = a as f64 / 80.0 * std::f64::consts::TAU;
        for k in 0..30 {
            pts.push(Vec3::new(
                can[0] + r * t.cos(),
                can[1] + r * t.sin(),
                z + h * k as f64 / 30.0,
            ));
        }
    }
    for i in -8..=8 {
        for k in -8..=8 {
            let (dx, dy) = (i as f64 * step, k as f64 * step);
            if dx.hypot(dy) <= r {
                pts.push(Vec3::new(can[0] + dx, can[1] + dy, z + h));
            }
        }
    }
    pts
}

#[test]
fn a_pick_and_place_through_a_mock_driver() {
    let robot = robots::load("golem3").unwrap();
    // Golem-III's right arm reaches a level side grasp here (0.85–0.9 m out, ~1 m up).
    let can = [0.62, -0.55];
    let cloud = table_with_can([0.82, -0.35], 1.0, can);
    let mut mock = MockRobot::new(&robot, cloud);
    let request = PickPlaceRequest {
        arm: Some("right".into()),
        pick: Vec3::new(can[0], can[1], 1.06),
        place: Vec3::new(0.75, -0.35, 1.06),
    };
    let out = pick_place(&mut mock, &robot, &request, &PickPlaceParams::default());
    assert!(
        out.error.is_none(),
        "{:?}\n{:#?}",
        out.error,
        out.report.rejected
    );
    let object = out.report.object.as_ref().unwrap();
    assert!(
        (object.position[0] - can[0]).abs() < 0.01 && (object.position[1] - can[1]).abs() < 0.01
    );
    assert!((object.size[2] - 0.12).abs() < 0.01, "{:?}", object.size);
    // Both hands open (as planned), close on the can, open to release — in that order.
    assert_eq!(
        mock.gripper_log,
        [
            "open right_gripper",
            "open left_gripper",
            "close right_gripper",
            "open right_gripper"
        ]
    );
    // Every motion started where the last one ended and the arm ended where it began.
    assert_eq!(mock.executed.len(), 8);
    for w in mock.executed.windows(2) {
        let (a, b) = (w[0].positions.last().unwrap(), &w[1].positions[0]);
        assert!(a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-9));
    }
    let start = &mock.executed[0].positions[0];
    let end = mock.executed.last().unwrap().positions.last().unwrap();
    assert!(start.iter().zip(end).all(|(x, y)| (x - y).abs() < 1e-6));
    // Where the can was planned to go is where it was asked to go.
    let planned = out.report.planned_object_position.unwrap();
    assert!((planned[0] - 0.75).abs() < 1e-9 && (planned[1] + 0.35).abs() < 1e-9);
    assert!((planned[2] - 1.008).abs() < 0.005, "{planned:?}");
}

#[test]
fn nothing_at_the_pick_position_is_a_typed_failure() {
    let robot = robots::load("golem3").unwrap();
    let cloud = table_with_can([0.82, -0.35], 1.0, [0.62, -0.55]);
    let mut mock = MockRobot::new(&robot, cloud);
    let request = PickPlaceRequest {
        arm: None,
        pick: Vec3::new(0.9, -0.2, 1.06),
        place: Vec3::new(0.75, -0.35, 1.06),
    };
    let out = pick_place(&mut mock, &robot, &request, &PickPlaceParams::default());
    assert_eq!(
        out.error.as_ref().map(|e| e.kind()),
        Some("object not found")
    );
    assert!(mock.executed.is_empty());
    let nan = PickPlaceRequest {
        pick: Vec3::NAN,
        ..request
    };
    assert!(
        pick_place(&mut mock, &robot, &nan, &PickPlaceParams::default())
            .error
            .is_some()
    );
}
