//! The scan's views (Alg. 1): the held object turned before the head camera, at the
//! scan position and, for the views the arm cannot show there, with the hand held aside.

use super::PlaceError;
use super::model::NearClusters;
use super::run::Run;
use tabula_geom::{Pose, Quat, Vec3};
use tabula_motion::MoveGroup;
use tabula_robot::driver::{JointState, RobotDriver};

/// A scan under way: the arm's move group (the protective sphere attached), the
/// camera's position, the object's points so far (tool frame) and the scene's (world).
pub(super) struct Scan {
    pub(super) group: MoveGroup,
    pub(super) tool_link: String,
    pub(super) cam: Vec3,
    pub(super) model: Vec<Vec3>,
    pub(super) scene: Vec<Vec3>,
    pub(super) used: usize,
    /// The arm's states before each view's move, from the scan position on: the way
    /// back from shifted views.
    pub(super) trail: Vec<JointState>,
    /// Seen points farther than this from where the hand is held stay out of the
    /// scene (m).
    pub(super) keep_within: f64,
}

impl Run<'_> {
    /// Shows the object to the camera from each of `views` (indices into
    /// `scan_views`) with the tool held at `target`; returns the views the arm could
    /// not show there.
    pub(super) fn scan_views_at(
        &mut self,
        driver: &mut impl RobotDriver,
        scan: &mut Scan,
        target: Vec3,
        views: &[usize],
    ) -> Result<Vec<usize>, PlaceError> {
        let robot = self.robot;
        let to_camera = (scan.cam - target).normalize_or(Vec3::Z);
        let mut unreached = Vec::new();
        for &k in views {
            let v = Vec3::from_array(self.params.scan_views[k]).normalize_or(Vec3::X);
            let state = driver.joint_state()?;
            scan.group.set_state(robot, &state)?;
            let start = scan.group.arm_values(&state);
            let view = Quat::from_rotation_arc(v, to_camera);
            let Some(plan) = self.plan_view(&mut scan.group, &start, target, view, to_camera, k)
            else {
                unreached.push(k);
                continue;
            };
            scan.trail.push(state);
            driver.execute(&plan.trajectory)?;
            let seen = self.scan_view(
                driver,
                &scan.tool_link,
                target,
                (&mut scan.scene, scan.keep_within, NearClusters::Dropped),
            )?;
            self.mark(&format!(
                "scan view {k} at {target:.2?}: {} points",
                seen.len()
            ));
            if seen.is_empty() {
                // Too near the camera, or hidden behind the hand: try it elsewhere.
                unreached.push(k);
                continue;
            }
            scan.used += 1;
            scan.model.extend(seen);
        }
        Ok(unreached)
    }

    /// Shows the views the arm could not show at the scan position (`unseen`; fingers
    /// pointing back at the camera, say) with the hand held elsewhere (`scan_shifts`
    /// from `target`, along the base's `forward`), then brings the arm back: those
    /// views show the faces a grip near the object's end hides, which are what the
    /// object rests on when the hand must stay clear of the table.
    pub(super) fn scan_shifted(
        &mut self,
        driver: &mut impl RobotDriver,
        scan: &mut Scan,
        (target, forward): (Vec3, Vec3),
        mut unseen: Vec<usize>,
    ) -> Result<(), PlaceError> {
        let robot = self.robot;
        let left = Vec3::Z.cross(forward);
        scan.trail = vec![driver.joint_state()?];
        // Only what the arm and the object could sweep about a shifted hold enters the
        // scene: these looks aim elsewhere than the sweep's, and their far points (a
        // table across the room seen at a slant, centimetres of range noise) would
        // stand on the surface as obstacles where the object is to go.
        scan.keep_within = self.params.reach + self.params.crop_radius;
        for shift in &self.params.scan_shifts {
            if unseen.is_empty() {
                break;
            }
            let at = target + forward * shift[0] + left * shift[1] + Vec3::Z * shift[2];
            // Look there first: the space enters the scene before the arm goes there.
            self.scan_view(
                driver,
                &scan.tool_link,
                at,
                (&mut scan.scene, scan.keep_within, NearClusters::Scene),
            )?;
            let state = driver.joint_state()?;
            scan.group.set_state(robot, &state)?;
            self.occupy(&mut scan.group, &scan.scene, None);
            unseen = self.scan_views_at(driver, scan, at, &unseen)?;
        }
        let trail = std::mem::take(&mut scan.trail);
        if trail.len() > 1 {
            self.return_along(driver, &mut scan.group, &trail)?;
        }
        Ok(())
    }

    /// Moves the arm back to where the views at the scan position left it (the first
    /// state of `trail`): a view from a shifted hold can wring the wrist so far that
    /// what the hand holds lies against the forearm, and no carry or placement starts
    /// there. Straight back when a plan is found, else the way it came, state by state
    /// (each was reached from the one before, so a plan between them exists). Staying
    /// put when neither works is no failure: the later plans say so.
    fn return_along(
        &mut self,
        driver: &mut impl RobotDriver,
        group: &mut MoveGroup,
        trail: &[JointState],
    ) -> Result<(), PlaceError> {
        let Some(home) = trail.first() else {
            return Ok(());
        };
        if self.move_arm_to(driver, group, home)? {
            return Ok(());
        }
        for state in trail.iter().rev() {
            if !self.move_arm_to(driver, group, state)? {
                self.mark("no way back from the shifted scan views");
                break;
            }
        }
        Ok(())
    }

    /// Plans the arm from where it is to its values in `goal` and moves it there;
    /// whether a plan was found.
    fn move_arm_to(
        &mut self,
        driver: &mut impl RobotDriver,
        group: &mut MoveGroup,
        goal: &JointState,
    ) -> Result<bool, PlaceError> {
        let state = driver.joint_state()?;
        group.set_state(self.robot, &state)?;
        let start = group.arm_values(&state);
        let goal = group.arm_values(goal);
        match self.decide(|_| group.plan_to_joints(&start, &[goal])) {
            Ok(plan) => {
                driver.execute(&plan.trajectory)?;
                Ok(true)
            }
            Err(e) => {
                self.mark(&format!("no plan back from a shifted scan view: {e}"));
                Ok(false)
            }
        }
    }

    /// A plan from `start` that holds the tool at `target` turned by `view` (then
    /// twisted about the line to the camera, `scan_twists` ways, until one plans);
    /// `None` when no twist can be reached (view `k`, logged).
    fn plan_view(
        &mut self,
        group: &mut MoveGroup,
        start: &[f64],
        target: Vec3,
        view: Quat,
        to_camera: Vec3,
        k: usize,
    ) -> Option<tabula_motion::Plan> {
        let mut why = String::new();
        let plan = self.decide(|r| {
            let twists = r.params.scan_twists.max(1);
            (0..twists).find_map(|t| {
                let angle = std::f64::consts::TAU * t as f64 / twists as f64;
                let twist = Quat::from_axis_angle(to_camera, angle);
                let pose = Pose::from_parts(target, twist * view);
                group
                    .plan_to_pose(start, &pose)
                    .map_err(|e| why = e.to_string())
                    .ok()
            })
        });
        if plan.is_none() {
            self.mark(&format!("scan view {k} unreachable: {why}"));
        }
        plan
    }
}
