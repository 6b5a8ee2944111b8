//! Carrying the held object: the arm tucked with it for the drive or the search.

use super::PlaceError;
use super::body::{shoulder_lateral, shoulder_position, world_from_base};
use super::run::Run;
use tabula_geom::parry::shape::SharedShape;
use tabula_geom::{Pose, Quat, Vec3};
use tabula_robot::driver::RobotDriver;

impl Run<'_> {
    /// Moves the holding arm to the side, level with the shoulder, out of the head's
    /// forward view; the object's hull rides along in the collision world.
    pub(super) fn carry(
        &mut self,
        driver: &mut impl RobotDriver,
        arm: &str,
        hull: &SharedShape,
        scene: &[Vec3],
    ) -> Result<(), PlaceError> {
        let robot = self.robot;
        let state = driver.joint_state()?;
        let root = driver.world_from_root()?;
        let mut group = self.group(arm, &state, root)?;
        self.occupy(&mut group, scene, None);
        group.attach("object", hull.clone(), Pose::IDENTITY)?;
        let start = group.arm_values(&state);
        let world_base = world_from_base(robot, driver)?;
        let side = if shoulder_lateral(robot, arm) >= 0.0 {
            1.0
        } else {
            -1.0
        };
        // High beside the head: the sweep looks down at surfaces, below it.
        let camera_z = driver
            .capture(&self.params.camera)?
            .world_from_camera
            .translation
            .z;
        let trace = self.trace;
        let shoulder = shoulder_position(robot, arm, &state, root).ok();
        let approach = group.gripper.as_ref().map_or(Vec3::X, |g| g.approach());
        let plan = self.decide(|_| {
            let mut why = Vec::new();
            for (x, y, z) in [
                (0.25, 0.35, 0.15),
                (0.2, 0.45, 0.1),
                (0.3, 0.5, 0.0),
                (0.15, 0.55, 0.2),
                (0.35, 0.55, -0.1),
            ] {
                let at = world_base.transform_point(Vec3::new(x, side * y, 0.0))
                    + Vec3::Z * (camera_z + z - world_base.translation.z);
                // Pointing ahead, up and ahead, out to the side, up; the hand pointing
                // most nearly away from the shoulder first — how an arm reaching that
                // far holds it — since an IK search that finds nothing costs its whole
                // budget.
                let mut turns = [
                    Quat::IDENTITY,
                    Quat::from_rotation_y(-0.8),
                    Quat::from_rotation_z(side * 0.8),
                    Quat::from_rotation_y(-1.4),
                ]
                .map(|t| world_base.rotation * t);
                if let Some(shoulder) = shoulder {
                    let out = (at - shoulder).normalize_or_zero();
                    turns.sort_by(|a, b| {
                        (*b * approach)
                            .dot(out)
                            .total_cmp(&(*a * approach).dot(out))
                    });
                }
                for r in turns {
                    match group.plan_to_pose(&start, &Pose::from_parts(at, r)) {
                        Ok(plan) => return Some(plan),
                        Err(e) => why.push(e.to_string()),
                    }
                }
            }
            if trace {
                tracing::debug!("place: no carry pose: {:?}", &why[..why.len().min(4)]);
            }
            None
        });
        // A carry pose is a convenience: staying where the scan ended is no failure.
        if let Some(plan) = plan {
            driver.execute(&plan.trajectory)?;
        }
        Ok(())
    }
}
