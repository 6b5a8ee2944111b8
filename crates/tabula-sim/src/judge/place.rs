//! Judging a stable placement (seed 000): the held object let go resting on a surface,
//! inside its edges, as planned, nothing else moved, no furniture hit.

use super::{ContactWatch, Judge, furniture_bounds};
use crate::SimDriver;
use crate::world::{SimError, SimWorld};
use std::sync::{Arc, Mutex};
use tabula_geom::Pose;

/// What physics says about placing a held object stably (seed 000): SPEC §1's
/// outcome, judged from ground truth.
#[derive(Debug, Clone, Default, serde::Serialize, serde::Deserialize)]
pub struct StablePlaceVerdict {
    /// Resting on a surface, inside its edges, within 5° of the planned pose, moved
    /// < 1 cm after release, nothing else moved > 1 cm, nothing held, no furniture hit.
    pub success: bool,
    pub object: String,
    /// The furniture it rests on (`None`: on the floor or nothing).
    pub surface: Option<String>,
    pub inside_edges: bool,
    /// Angle between the planned and the final orientation (deg).
    pub orientation_error_deg: f64,
    /// Distance between the predicted and the final position (m).
    pub position_error_m: f64,
    /// How far it slid (horizontally) between release and rest (m): the fall from the
    /// release height is planned and counted apart.
    pub moved_after_release_m: f64,
    /// How far it fell between release and rest (m).
    pub dropped_m: f64,
    pub released: bool,
    pub disturbed: Vec<String>,
    pub furniture_contacts: Vec<(String, String)>,
    /// Poses as x y z qx qy qz qw (world).
    pub predicted_pose: Option<[f64; 7]>,
    pub final_pose: [f64; 7],
}

/// Pass/fail limits of a stable placement (SPEC §1 via the issue: 5°, 1 cm, 1 cm).
/// "Moved after release" is the slide: the fall from the release height (SPEC §6: 8 mm)
/// is the plan, not a move.
#[derive(Debug, Clone, Copy)]
pub struct StablePlaceTolerance {
    pub orientation_deg: f64,
    pub moved_after_release: f64,
    pub disturbed: f64,
    /// The object's lowest point within this of the surface's top (m).
    pub contact: f64,
}

impl Default for StablePlaceTolerance {
    fn default() -> Self {
        Self {
            orientation_deg: 5.0,
            moved_after_release: 0.01,
            disturbed: 0.01,
            contact: 0.015,
        }
    }
}

fn pose7(p: &Pose) -> [f64; 7] {
    let (t, q) = (p.translation, p.rotation);
    [t.x, t.y, t.z, q.x, q.y, q.z, q.w]
}

/// A judge of placing the object the robot holds: furniture contacts and the moment
/// the object is let go are watched at every step; the verdict is against the tool
/// pose the task planned (`world_from_tool` with the object resting, `None` when it
/// planned nothing).
pub struct StablePlaceJudge {
    robot: String,
    object: String,
    tool_from_object: Pose,
    /// The other objects' poses at the start.
    before: Vec<(String, Pose)>,
    watch: ContactWatch,
    /// Where the object was when the hand let go of it.
    release: Arc<Mutex<Option<Pose>>>,
}

impl StablePlaceJudge {
    /// A judge of `robot` placing what it holds in `world`.
    pub fn new(world: &SimWorld, robot: &str) -> Result<Self, SimError> {
        let object = world
            .held_objects(robot)
            .into_iter()
            .next()
            .ok_or_else(|| SimError::Robot(format!("robot `{robot}` holds nothing")))?;
        let start_object = world.pose(&object)?;
        // The tool holding it: the gripper tool frame nearest the object.
        let grippers = world.robot(robot)?.description.grippers.clone();
        let tool = grippers
            .iter()
            .filter_map(|g| world.link_pose(robot, &g.tool_link).ok())
            .min_by(|a, b| {
                a.translation
                    .distance(start_object.translation)
                    .total_cmp(&b.translation.distance(start_object.translation))
            })
            .ok_or_else(|| SimError::Robot(format!("robot `{robot}` has no gripper")))?;
        let before = world
            .object_poses()
            .into_iter()
            .filter(|(n, _)| *n != object)
            .collect();
        Ok(Self {
            robot: robot.into(),
            tool_from_object: tool.inverse() * start_object,
            object,
            before,
            watch: ContactWatch::default(),
            release: Arc::default(),
        })
    }

    /// The furniture the object (at `now`) rests on — its top within reach of the
    /// object's lowest point, its centre over the top's outline — and whether the object
    /// lies inside its edges.
    fn surface_under(
        &self,
        world: &SimWorld,
        now: &Pose,
        tol: &StablePlaceTolerance,
    ) -> (Option<String>, bool) {
        let bounds = world.entity_bounds(&self.object);
        let mut surface = None;
        let mut inside_edges = false;
        if let Some(b) = &bounds {
            for name in world
                .furniture_shapes()
                .into_iter()
                .map(|(n, _, _)| n)
                .collect::<std::collections::BTreeSet<_>>()
            {
                let Some(f) = furniture_bounds(world, &name) else {
                    continue;
                };
                let c = now.translation;
                let over = c.x >= f.mins.x && c.x <= f.maxs.x && c.y >= f.mins.y && c.y <= f.maxs.y;
                if tracing::enabled!(tracing::Level::DEBUG) {
                    tracing::debug!(
                        "verdict: `{name}` top {:.3}, object bottom {:.3}, over {over}",
                        f.maxs.z,
                        b.mins.z
                    );
                }
                if over && (b.mins.z - f.maxs.z).abs() <= tol.contact {
                    inside_edges = b.mins.x >= f.mins.x
                        && b.maxs.x <= f.maxs.x
                        && b.mins.y >= f.mins.y
                        && b.maxs.y <= f.maxs.y;
                    surface = Some(name);
                    break;
                }
            }
        }
        (surface, inside_edges)
    }
}

impl Judge for StablePlaceJudge {
    type Verdict = StablePlaceVerdict;
    type Told = Option<Pose>;

    fn watch(&mut self, driver: &mut SimDriver) {
        let mut contacts = self.watch.observer(&self.robot);
        let (r2, obj2, robot2) = (
            self.release.clone(),
            self.object.clone(),
            self.robot.clone(),
        );
        driver.observe(move |w: &SimWorld| {
            contacts(w);
            if let Ok(mut r) = r2.lock() {
                if r.is_none() && !w.held_objects(&robot2).contains(&obj2) {
                    *r = w.pose(&obj2).ok();
                }
                if let (Some(at), Ok(now)) = (*r, w.pose(&obj2))
                    && tracing::enabled!(tracing::Level::DEBUG)
                    && (w.time() * 10.0).fract() < 0.01
                {
                    tracing::debug!(
                        "t = {:.2} s: object {:.3} m from its release pose, turned {:.1}°",
                        w.time(),
                        now.translation.distance(at.translation),
                        tabula_geom::rotation_angle_between(at.rotation, now.rotation).to_degrees()
                    );
                }
            }
        });
    }

    fn verdict(
        self,
        world: &SimWorld,
        planned: Option<Pose>,
    ) -> Result<StablePlaceVerdict, SimError> {
        let (robot, object, before) = (&self.robot, self.object.clone(), &self.before);
        let now = world.pose(&object)?;
        let released_at = self.release.lock().ok().and_then(|r| *r);
        let predicted = planned.map(|p| p * self.tool_from_object);
        let tol = StablePlaceTolerance::default();
        let (surface, inside_edges) = self.surface_under(world, &now, &tol);
        let orientation_error_deg = predicted.map_or(180.0, |p| {
            tabula_geom::rotation_angle_between(p.rotation, now.rotation).to_degrees()
        });
        let position_error_m =
            predicted.map_or(f64::INFINITY, |p| p.translation.distance(now.translation));
        let moved_after_release_m = released_at.map_or(f64::INFINITY, |r| {
            r.translation
                .truncate()
                .distance(now.translation.truncate())
        });
        let dropped_m = released_at.map_or(f64::INFINITY, |r| r.translation.z - now.translation.z);
        let disturbed: Vec<String> = before
            .iter()
            .filter(|(n, p)| {
                world
                    .pose(n)
                    .is_ok_and(|q| q.translation.distance(p.translation) > tol.disturbed)
            })
            .map(|(n, _)| n.clone())
            .collect();
        let furniture_contacts = self.watch.seen();
        let released = released_at.is_some() && !world.held_objects(robot).contains(&object);
        Ok(StablePlaceVerdict {
            success: surface.is_some()
                && inside_edges
                && orientation_error_deg <= tol.orientation_deg
                && moved_after_release_m < tol.moved_after_release
                && disturbed.is_empty()
                && furniture_contacts.is_empty()
                && released,
            object,
            surface,
            inside_edges,
            orientation_error_deg,
            position_error_m,
            moved_after_release_m,
            dropped_m,
            released,
            disturbed,
            furniture_contacts,
            predicted_pose: predicted.map(|p| pose7(&p)),
            final_pose: pose7(&now),
        })
    }
}
