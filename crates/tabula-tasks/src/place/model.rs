//! Modelling the held object: scanning it before the head camera (Alg. 1) and finding
//! how the model rests stably with the gripper clear (Algs 2–7).

use super::body::{
    gripper_points, heading_vector, look_at, palm_front, protective_shape, tool_pose,
    world_from_base,
};
use super::run::Run;
use super::views::Scan;
use super::{ModelReport, PlaceError};
use crate::observe::{clusters, robot_solids, world_points};
use crate::stable::{StablePose, of_cloud};
use tabula_geom::{Pose, Vec3};
use tabula_motion::MoveGroup;
use tabula_robot::driver::RobotDriver;

/// What a view makes of the clusters near the hand (within `crop_radius`, beyond the
/// protective sphere) that do not reach into it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum NearClusters {
    /// They are the scene: the hand is not yet where the view looks, or this is the
    /// first look at the object.
    Scene,
    /// They are dropped: a view of the held object, whose parts a finger's shadow cuts
    /// off would stand in the air as obstacles (a drill's body 20 cm from the grip,
    /// beyond a sphere sized from the first view's glimpse). The look taken before the
    /// hand came has put what really is around the hand into the scene.
    Dropped,
}

/// A stable pose the object can be set down in with the gripper where it holds it.
#[derive(Debug, Clone)]
pub(super) struct Resting {
    pub(super) pose: StablePose,
    /// How high above the surface it is let go (m): as low as the hand's clearance of
    /// the surface allows, within `release_height_min`…`release_height`.
    pub(super) release_height: f64,
}

impl Resting {
    /// `pose` let go as low as `gripper` (points in the object's frame) stays
    /// `gripper_clearance` above the surface.
    pub(super) fn new(pose: StablePose, gripper: &[Vec3], p: &super::PlaceParams) -> Self {
        let release_height = (p.gripper_clearance - pose.hand_margin(gripper))
            .clamp(p.release_height_min, p.release_height);
        Self {
            pose,
            release_height,
        }
    }
}

impl Run<'_> {
    /// Alg. 1: hold the object before the head camera and look at it from many sides;
    /// returns the model in the tool frame and the scene points seen meanwhile.
    pub(super) fn model_object(
        &mut self,
        driver: &mut impl RobotDriver,
        arm: &str,
    ) -> Result<(Vec<Vec3>, Vec<Vec3>), PlaceError> {
        let p = self.params;
        let robot = self.robot;
        let state = driver.joint_state()?;
        let root = driver.world_from_root()?;
        let mut group = self.group(arm, &state, root)?;
        let tool_link = group
            .gripper
            .as_ref()
            .map(|g| g.tool_link.clone())
            .ok_or(PlaceError::NotHolding)?;
        let mut model: Vec<Vec3> = Vec::new();
        let mut scene: Vec<Vec3> = Vec::new();
        // A first look at the hand where it is: the object's rough size, and what is
        // around the arms before they move.
        let tool_now = tool_pose(robot, &state, root, &tool_link)?;
        let first = self.scan_view(
            driver,
            &tool_link,
            tool_now.translation,
            (&mut scene, f64::INFINITY, NearClusters::Scene),
        )?;
        // The protective sphere (SPEC §1.1) around what this first view shows of the
        // object, a little larger than it: the seed's fixed 20 cm ball around the palm
        // would hold the wrist inside it and let no view be planned.
        let (sphere_centre, radius) = if first.len() >= 10 {
            let c = first.iter().copied().sum::<Vec3>() / first.len() as f64;
            let r = first.iter().map(|q| q.distance(c)).fold(0.0, f64::max);
            (c, (r + 0.03).min(p.protective_radius))
        } else {
            (Vec3::ZERO, p.protective_radius)
        };
        let approach = group
            .gripper
            .as_ref()
            .map_or(Vec3::X, tabula_robot::description::Gripper::approach);
        let palm_front = group.gripper.as_ref().and_then(palm_front);
        let protective = protective_shape(&first, approach, palm_front, sphere_centre, radius);
        model.extend(first);
        self.held_reach = sphere_centre.length() + radius;
        let cam = driver.capture(&p.camera)?.world_from_camera.translation;
        let forward = heading_vector(&world_from_base(robot, driver)?);
        let target = Vec3::new(cam.x, cam.y, cam.z - p.scan_drop) + forward * p.scan_distance;
        self.mark(&format!(
            "scan at {target:?}, protective radius {radius:.3}"
        ));
        // A look where the hand will be held: that space enters the scene (occupancy)
        // before the arm moves there. What it sees of the object (still where it was)
        // is not kept: the scan proper starts at the observation pose.
        let sink = (&mut scene, f64::INFINITY, NearClusters::Scene);
        self.scan_view(driver, &tool_link, target, sink)?;
        // The other arms out of the way (the seed's first step).
        self.decide(|r| r.occupy(&mut group, &scene, None));
        self.tuck_other_arms(driver, arm, &group, &scene)?;
        // The views: the tool turned so the camera sees the object from each direction.
        let state = driver.joint_state()?;
        group.set_state(robot, &state)?;
        self.occupy(&mut group, &scene, None);
        group.attach(
            "protective sphere",
            protective,
            Pose::from_translation(sphere_centre),
        )?;
        let mut scan = Scan {
            group,
            tool_link,
            cam,
            model,
            scene,
            used: 0,
            trail: Vec::new(),
            keep_within: f64::INFINITY,
        };
        let all: Vec<usize> = (0..p.scan_views.len()).collect();
        let unseen = self.scan_views_at(driver, &mut scan, target, &all)?;
        self.scan_shifted(driver, &mut scan, (target, forward), unseen)?;
        let (model, scene) = (scan.model, scan.scene);
        let model = self.finish_model(model, scan.used)?;
        Ok((model, scene))
    }

    /// Tucks every other arm that has a tucked pose, where a collision-free plan gets
    /// it there.
    fn tuck_other_arms(
        &mut self,
        driver: &mut impl RobotDriver,
        arm: &str,
        group: &MoveGroup,
        scene: &[Vec3],
    ) -> Result<(), PlaceError> {
        let robot = self.robot;
        for other in &robot.description.arms {
            if other.name == arm || other.tucked.is_empty() {
                continue;
            }
            let Ok(mut g) = group.for_arm(robot, &other.name) else {
                continue;
            };
            let state = driver.joint_state()?;
            let start = g.arm_values(&state);
            let goal: Vec<f64> = g
                .joint_names()
                .iter()
                .zip(&start)
                .map(|(n, s)| other.tucked.get(n).copied().unwrap_or(*s))
                .collect();
            if g.world.is_valid(&start) && g.world.is_valid(&goal) {
                self.occupy(&mut g, scene, None);
                let plan = self.decide(|_| g.plan_to_joints(&start, &[goal]));
                if let Ok(plan) = plan {
                    driver.execute(&plan.trajectory)?;
                }
            }
        }
        Ok(())
    }

    /// The scan's points thinned to one per leaf (the views overlap; SPEC §1.1
    /// downsamples), reported; too few is an error.
    fn finish_model(&mut self, model: Vec<Vec3>, used: usize) -> Result<Vec<Vec3>, PlaceError> {
        let p = self.params;
        let model = self.decide(|r| {
            tabula_perception::filters::voxel_grid(&model, r.params.scan_leaf).unwrap_or(model)
        });
        let (lo, hi) = tabula_geom::bounds(&model);
        self.report.model = Some(ModelReport {
            views: used,
            views_tried: p.scan_views.len(),
            points: model.len(),
            hull_volume_m3: 0.0,
            size: if model.is_empty() {
                [0.0; 3]
            } else {
                (hi - lo).to_array()
            },
        });
        if model.len() < 10 {
            return Err(PlaceError::Model(format!(
                "{} points of the object were seen",
                model.len()
            )));
        }
        self.report.model_points = model.clone();
        self.held_reach = model
            .iter()
            .map(|q| q.length())
            .fold(self.held_reach, f64::max);
        Ok(model)
    }

    /// Looks at `at`, captures, and returns the held object's points in the tool frame;
    /// everything else seen within `keep_within` of `at` goes into `scene` (world frame),
    /// clusters near the hand as `near` says.
    pub(super) fn scan_view(
        &mut self,
        driver: &mut impl RobotDriver,
        tool_link: &str,
        at: Vec3,
        (scene, keep_within, near_clusters): (&mut Vec<Vec3>, f64, NearClusters),
    ) -> Result<Vec<Vec3>, PlaceError> {
        look_at(driver, at)?;
        let frame = driver.capture(&self.params.camera)?;
        let state = driver.joint_state()?;
        let root = driver.world_from_root()?;
        let robot = self.robot;
        self.decide(|r| {
            let p = r.params;
            let solids = robot_solids(&robot.model, &state.model_values(&robot.model), root);
            let points = world_points(&frame, &solids, &p.observe, p.scan_leaf);
            let world_from_tool = tool_pose(robot, &state, root, tool_link)?;
            let tool = world_from_tool.translation;
            let (near, mut far): (Vec<Vec3>, Vec<Vec3>) = points
                .into_iter()
                .partition(|q| q.distance(tool) <= p.crop_radius);
            far.retain(|q| q.distance(at) <= keep_within);
            r.add_scene(scene, far);
            // The held object: clusters that reach into the hand.
            let parts = clusters(&near, p.observe.cluster_gap);
            let mut object = Vec::new();
            for c in parts {
                let closest = c
                    .iter()
                    .map(|&i| near[i].distance(tool))
                    .fold(f64::INFINITY, f64::min);
                if closest <= p.grip_reach {
                    object.extend(c.iter().map(|&i| near[i]));
                } else if closest > p.protective_radius && near_clusters == NearClusters::Scene {
                    r.add_scene(scene, c.iter().map(|&i| near[i]).collect());
                }
                // Between: pieces of the object the fingers' shadow cut off, or
                // something right beside it; neither model nor obstacle.
            }
            let tool_from_world = world_from_tool.inverse();
            if r.trace {
                let (lo, hi) = object.iter().fold(
                    (Vec3::splat(f64::INFINITY), Vec3::splat(f64::NEG_INFINITY)),
                    |(a, b), q| {
                        let t = tool_from_world.transform_point(*q);
                        (a.min(t), b.max(t))
                    },
                );
                tracing::debug!(
                    "place: view of {} object points, tool-frame box {lo:.3?} – {hi:.3?}",
                    object.len()
                );
            }
            Ok(object
                .into_iter()
                .map(|q| tool_from_world.transform_point(q))
                .collect())
        })
    }

    /// The collision world of `group`: the seen scene as occupancy, minus what lies
    /// within the held object's reach of the tool. Only the part the arm and what it
    /// holds can ever reach is modelled: a sweep's scene holds the whole room, and
    /// the occupancy of a floor and walls far away only costs time.
    pub(super) fn occupy(
        &self,
        group: &mut MoveGroup,
        scene: &[Vec3],
        keep_out: Option<(Vec3, f64)>,
    ) {
        let _ = group.world.remove_object("scene");
        let reach = group.world.moving_bound().map(|(c, r)| {
            let r = r + self.held_reach + 2.0 * self.params.observe.voxel;
            (c, r * r)
        });
        let pts: Vec<Vec3> = scene
            .iter()
            .copied()
            .filter(|q| reach.is_none_or(|(c, r2)| q.distance_squared(c) <= r2))
            .filter(|q| keep_out.is_none_or(|(c, r)| q.distance(c) > r))
            .collect();
        let _ = group
            .world
            .add_occupancy("scene", &pts, self.params.observe.voxel);
    }

    /// Stable poses of the model usable with the gripper where it is, best first.
    pub(super) fn stable_poses(
        &mut self,
        arm: &str,
        model: &[Vec3],
    ) -> Result<Vec<Resting>, PlaceError> {
        let p = self.params;
        let found = of_cloud(model, &p.stable).map_err(|e| PlaceError::Model(e.to_string()))?;
        if let Some(m) = self.report.model.as_mut() {
            m.hull_volume_m3 = found.hull_volume_m3;
        }
        self.report.poses_found = found.poses.len();
        let gripper = gripper_points(self.robot, arm);
        let com = Vec3::from_array(found.center_of_mass);
        // At release the object hangs `release_height` above the surface: the hand may
        // reach below the object's support plane by less than that.
        let hand_clearance = p.gripper_clearance - p.release_height;
        if self.trace {
            for s in &found.poses {
                tracing::debug!(
                    "place: found pose {:?} topple {:.1}° hand margin {:.1} mm (needs {:.1})",
                    s.support_normal,
                    s.topple_deg,
                    s.hand_margin(&gripper) * 1e3,
                    hand_clearance * 1e3
                );
            }
        }
        // Ranked by the tilt that topples them, weighed by how much of the support the
        // object really touches (a bridge over a concavity rests on edges).
        let mut usable: Vec<(f64, Resting)> = found
            .poses
            .iter()
            .filter(|s| s.topple_deg >= p.min_topple_deg)
            .filter(|s| s.clear_of(&gripper, hand_clearance))
            .map(|s| {
                let fill = s.contact_fill(model, p.stable.cloud_contact_tolerance, p.scan_leaf);
                // Rocking: a pose on a curved contact (a bottle or a ball on its side)
                // rolls to wherever its facets end instead of resting as planned.
                let rocking = s.rocking(model, com).clamp(0.0, 1.0);
                tracing::debug!(
                    "place: pose {:?} topple {:.1}° fill {fill:.2} rocking {rocking:.2}",
                    s.support_normal,
                    s.topple_deg
                );
                (
                    s.topple_deg * (0.4 + 0.6 * fill) * rocking,
                    Resting::new(s.clone(), &gripper, p),
                )
            })
            .collect();
        usable.sort_by(|a, b| b.0.total_cmp(&a.0));
        let usable: Vec<Resting> = usable
            .into_iter()
            .take(p.poses_tried.max(1))
            .map(|(_, s)| s)
            .collect();
        if usable.is_empty() {
            return Err(PlaceError::NoStablePose(format!(
                "{} poses, none tilts {:.0}° before toppling with the gripper {:.0} mm clear",
                found.poses.len(),
                p.min_topple_deg,
                p.gripper_clearance * 1e3
            )));
        }
        self.mark(&format!(
            "{} stable poses, best normal {:?} topple {:.1}°",
            found.poses.len(),
            usable[0].pose.support_normal,
            usable[0].pose.topple_deg
        ));
        Ok(usable)
    }
}
