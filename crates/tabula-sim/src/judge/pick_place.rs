//! Judging a pick-and-place run: did the object end where and how the task meant it to,
//! did anything else move, did the robot touch the furniture.

use super::{ContactWatch, Judge, nearest_object};
use crate::SimDriver;
use crate::world::{SimError, SimWorld};
use tabula_geom::{Pose, Vec2, Vec3};

/// What physics says about a placement.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct PlaceVerdict {
    /// Within `tolerance` of the target, upright, resting, nothing held, no furniture
    /// touched.
    pub success: bool,
    pub object: String,
    /// Horizontal distance of the object's origin from the target (m).
    pub target_error: f64,
    /// Angle between the object's up axis before and after (rad).
    pub tilt: f64,
    pub resting: bool,
    /// Robot–furniture contacts seen during the motions (link or held object, furniture).
    pub furniture_contacts: Vec<(String, String)>,
    /// Other objects moved by more than 1 cm.
    pub disturbed: Vec<String>,
    /// x y z roll pitch yaw of the object at the end.
    pub final_pose: [f64; 6],
}

/// Pass/fail limits of a placement (the integral test's: 2 cm, upright, resting).
#[derive(Debug, Clone, Copy)]
pub struct PlaceTolerance {
    pub position: f64,
    pub tilt: f64,
    pub speed: f64,
}

impl Default for PlaceTolerance {
    fn default() -> Self {
        Self {
            position: 0.02,
            tilt: 0.1,
            speed: 0.01,
        }
    }
}

/// Judges a placement of `moved` (an object and the pose it started at) at `target`
/// (xy), after the world has settled.
pub fn judge_placement(
    world: &SimWorld,
    robot: &str,
    (object, start): (&str, &Pose),
    target: Vec2,
    before: &[(String, Pose)],
    furniture_contacts: Vec<(String, String)>,
    tolerance: PlaceTolerance,
) -> Result<PlaceVerdict, SimError> {
    let now = world.pose(object)?;
    let tilt = (now.rotation * Vec3::Z).angle_between(start.rotation * Vec3::Z);
    let target_error = (now.translation.truncate() - target).length();
    let resting = world
        .physics
        .bodies
        .iter()
        .all(|(_, b)| !b.is_dynamic() || b.linvel().length() < tolerance.speed);
    let disturbed: Vec<String> = before
        .iter()
        .filter(|(n, _)| n != object)
        .filter(|(n, p)| {
            world
                .pose(n)
                .is_ok_and(|q| (q.translation - p.translation).length() > 0.01)
        })
        .map(|(n, _)| n.clone())
        .collect();
    let rpy = tabula_geom::rpy_from_quat(now.rotation);
    let t = now.translation;
    Ok(PlaceVerdict {
        success: target_error <= tolerance.position
            && tilt <= tolerance.tilt
            && resting
            && furniture_contacts.is_empty()
            && !world.held_objects(robot).iter().any(|h| h == object),
        object: object.to_string(),
        target_error,
        tilt,
        resting,
        furniture_contacts,
        disturbed,
        final_pose: [t.x, t.y, t.z, rpy[0], rpy[1], rpy[2]],
    })
}

/// A judge of moving the object nearest `pick` to `target` (xy): the furniture the
/// robot touches on the way, where the object ends, what else moved.
pub struct PlacementJudge {
    robot: String,
    object: String,
    start: Pose,
    target: Vec2,
    before: Vec<(String, Pose)>,
    watch: ContactWatch,
}

impl PlacementJudge {
    pub fn new(world: &SimWorld, robot: &str, pick: Vec3, target: Vec2) -> Result<Self, SimError> {
        let before = world.object_poses();
        let (object, start) = nearest_object(&before, pick)
            .ok_or_else(|| SimError::UnknownEntity("any object".into()))?;
        Ok(Self {
            robot: robot.into(),
            object,
            start,
            target,
            before,
            watch: ContactWatch::default(),
        })
    }
}

impl Judge for PlacementJudge {
    type Verdict = PlaceVerdict;
    type Told = ();

    fn watch(&mut self, driver: &mut SimDriver) {
        driver.observe(self.watch.observer(&self.robot));
    }

    fn verdict(self, world: &SimWorld, (): ()) -> Result<PlaceVerdict, SimError> {
        judge_placement(
            world,
            &self.robot,
            (&self.object, &self.start),
            self.target,
            &self.before,
            self.watch.seen(),
            PlaceTolerance::default(),
        )
    }
}
