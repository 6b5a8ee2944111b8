//! The one tabletop observer every task perceives with: a frame from the named camera,
//! the robot's own body filtered out, decimated, the tabletop pipeline, objects with
//! their hulls.

use super::tabletop::{filtered_cloud, perceive};
use super::{SceneError, SeenObject, Table};
use tabula_motion::group::thread_cpu;
use tabula_perception::tabletop::TabletopParams;
use tabula_robot::driver::{CameraFrame, DriverError, JointState, RobotDriver};
use tabula_robot::robots::NamedRobot;

/// How a task looks at a table: which camera, how coarse, how much of the robot's body
/// to filter (SPEC §1.1), and the tabletop pipeline's parameters (for full frames).
pub struct Observer<'p> {
    pub camera: &'p str,
    pub decimate: usize,
    pub self_filter_padding: f64,
    /// The tabletop parameters scaled to the decimated frames.
    tabletop: TabletopParams,
}

/// A frame as the driver gave it, with the joint state it was taken at.
pub struct Captured {
    pub frame: CameraFrame,
    pub state: JointState,
    pub world_from_root: tabula_geom::Pose,
}

/// What one frame shows and its CPU cost (s): in all, and of the transform and
/// self-filter alone.
pub struct Observation {
    pub table: Table,
    pub objects: Vec<SeenObject>,
    pub cpu_s: f64,
    pub filter_cpu_s: f64,
}

impl<'p> Observer<'p> {
    pub fn new(
        camera: &'p str,
        decimate: usize,
        self_filter_padding: f64,
        tabletop: &TabletopParams,
    ) -> Self {
        Self {
            camera,
            decimate,
            self_filter_padding,
            tabletop: tabletop.at_stride(decimate),
        }
    }

    /// Takes a frame (the driver's part: no perception yet).
    pub fn capture(&self, driver: &mut impl RobotDriver) -> Result<Captured, DriverError> {
        let frame = driver.capture(self.camera)?;
        let state = driver.joint_state()?;
        let world_from_root = driver.world_from_root()?;
        Ok(Captured {
            frame,
            state,
            world_from_root,
        })
    }

    /// Captures a frame and perceives it.
    pub fn observe(
        &self,
        driver: &mut impl RobotDriver,
        robot: &NamedRobot,
    ) -> Result<Observation, SceneError> {
        let captured = self
            .capture(driver)
            .map_err(|e| SceneError::Driver(e.to_string()))?;
        self.perceive(robot, &captured)
    }

    /// A captured frame's points (world), the robot's own body (padded) blanked out:
    /// what a check of the hand's surroundings looks at without the tabletop pipeline.
    pub fn world_cloud(&self, robot: &NamedRobot, c: &Captured) -> tabula_geom::PointCloud {
        filtered_cloud(
            &c.frame,
            robot,
            &c.state,
            c.world_from_root,
            self.decimate,
            self.self_filter_padding,
        )
    }

    /// Perceives the table and its objects in a captured frame; ids numbered in order
    /// (a tracker may renumber them).
    pub fn perceive(&self, robot: &NamedRobot, c: &Captured) -> Result<Observation, SceneError> {
        let c0 = thread_cpu();
        let cloud = self.world_cloud(robot, c);
        let filter_cpu_s = thread_cpu() - c0;
        let viewpoint = c.frame.world_from_camera.translation;
        let (table, mut objects) = perceive(&cloud, viewpoint, &self.tabletop)?;
        for (k, o) in objects.iter_mut().enumerate() {
            o.id = k;
        }
        Ok(Observation {
            table,
            objects,
            cpu_s: thread_cpu() - c0,
            filter_cpu_s,
        })
    }
}
