//! Looking around with the head camera: at the object and the target at the perception
//! leaf, then a sweep over the arm's working height at the collision voxel's resolution
//! (seed 000 swept its head too) — the motions between pass through space the camera
//! must have seen, or the planner would take unseen furniture for free space.

use super::{PickPlaceError, PickPlaceParams, PickPlaceReport, PickPlaceRequest};
use crate::observe::{robot_solids, world_points};
use crate::skills::phase::{Clock, timed};
use tabula_geom::Vec3;
use tabula_motion::group::thread_cpu;
use tabula_robot::driver::{DriverError, RobotDriver};
use tabula_robot::robots::NamedRobot;

/// What the head saw.
pub(super) struct Views {
    /// Points off the robot (world).
    pub(super) points: Vec<Vec3>,
    /// The camera each point was seen from (to give surfaces thickness behind them).
    pub(super) origins: Vec<Vec3>,
    /// CPU seconds spent turning frames into points (part of the decision).
    pub(super) cpu: f64,
}

/// Where to look, in order: (phase name, point looked at, perception leaf).
fn looks(
    robot: &NamedRobot,
    request: &PickPlaceRequest,
    params: &PickPlaceParams,
    world_from_root: tabula_geom::Pose,
) -> Vec<(String, Vec3, f64)> {
    let obs = &params.observe;
    let mut looks = vec![
        ("look at object".to_string(), request.pick, obs.leaf),
        ("look at target".to_string(), request.place, obs.leaf),
    ];
    if robot.description.head.is_none() {
        return looks;
    }
    let height = (request.pick.z + request.place.z) / 2.0;
    let centre = world_from_root.translation;
    let f = world_from_root.rotation * Vec3::X;
    let heading = f.y.atan2(f.x);
    for &rise in &params.sweep_rises {
        for &a in &params.sweep_angles {
            let dir = Vec3::new((heading + a).cos(), (heading + a).sin(), 0.0);
            let at = Vec3::new(centre.x, centre.y, height + rise) + dir * params.sweep_radius;
            looks.push((
                format!("sweep {:+.0}° {:+.2} m", a.to_degrees(), rise),
                at,
                obs.voxel / 2.0,
            ));
        }
    }
    looks
}

/// Looks at the object, the target and around, each view a phase of `report`.
pub(super) fn look_around(
    driver: &mut impl RobotDriver,
    robot: &NamedRobot,
    request: &PickPlaceRequest,
    params: &PickPlaceParams,
    report: &mut PickPlaceReport,
) -> Result<Views, PickPlaceError> {
    let mut views = Views {
        points: Vec::new(),
        origins: Vec::new(),
        cpu: 0.0,
    };
    let world_from_root = driver.world_from_root()?;
    for (k, (name, at, leaf)) in looks(robot, request, params, world_from_root)
        .into_iter()
        .enumerate()
    {
        if k == 1 {
            // The head has looked at the object: a moment for the record.
            driver.annotate("looked at the object");
        }
        timed(&mut report.phases, "pick-place", &name, Clock::Wall, || {
            match driver.look_at(at) {
                Ok(_) | Err(DriverError::Unsupported(_)) => {}
                Err(e) => return Err(e.into()),
            }
            let frame = driver.capture(&params.camera)?;
            let c0 = thread_cpu();
            let state = driver.joint_state()?;
            let solids = robot_solids(
                &robot.model,
                &state.model_values(&robot.model),
                driver.world_from_root()?,
            );
            let seen = world_points(&frame, &solids, &params.observe, leaf);
            views.origins.extend(std::iter::repeat_n(
                frame.world_from_camera.translation,
                seen.len(),
            ));
            views.points.extend(seen);
            views.cpu += thread_cpu() - c0;
            Ok::<(), PickPlaceError>(())
        })?;
    }
    Ok(views)
}
