//! Placing an unknown object stably (seed 000, SPEC §1): the robot holds an object it
//! has no model of. It scans the object in its gripper before the head camera (Alg. 1),
//! finds how the scan rests stably with the gripper clear of the surface (Algs 2–7),
//! sweeps its head for surfaces (Alg. 9), finds a free spot where the resting
//! footprint fits away from edges and objects, drives its base to the surface when
//! it is out of reach (Alg. 10), and puts the object down (Algs 11–12): candidates are
//! free spots × roll angles, the first whose IK and motion plans all succeed is
//! executed, the gripper opens a few millimetres above the surface and backs away
//! along its approach.
//!
//! Stages report their time and, on failure, a typed reason, as MoveIt Task
//! Constructor's stages do.

use crate::observe::{ObserveParams, clusters, robot_solids, world_points, world_points_unthinned};
use crate::pick_place::Phase;
use crate::stable::{StableParams, StablePose, of_cloud};
use std::time::Instant;
use tabula_geom::input::{
    Validate, check_count, check_in, check_non_negative, check_positive, nested,
};
use tabula_geom::parry::shape::SharedShape;
use tabula_geom::polygon::{convex_hull_2d, inside_convex};
use tabula_geom::{PointCloud, Pose, Quat, Vec2, Vec3};
use tabula_motion::group::thread_cpu;
use tabula_motion::{CollisionWorld, MoveError, MoveGroup, MoveGroupParams, Plan};
use tabula_perception::freespace::{FreeSpaceMap, FreeSpaceParams};
use tabula_perception::selffilter::{PlacedSolid, Solid};
use tabula_perception::surfaces::{Surface, SurfaceParams, find_surfaces, surfaces_on};
use tabula_robot::driver::{DriverError, JointState, RobotDriver};
use tabula_robot::robots::NamedRobot;

/// Parameters of placing (SPEC §1 and §6).
#[derive(Debug, Clone, serde::Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct PlaceParams {
    pub observe: ObserveParams,
    pub motion: MoveGroupParams,
    pub stable: StableParams,
    pub surfaces: SurfaceParams,
    pub free_space: FreeSpaceParams,
    /// The head camera.
    pub camera: String,
    /// Where the object is held to be scanned: this far in front of the camera (m) …
    pub scan_distance: f64,
    /// … and this far below it (m).
    pub scan_drop: f64,
    /// Directions (in the tool frame) the camera looks at the object from: SPEC §1.1's
    /// lateral views, the top, and views from below the hand.
    pub scan_views: Vec<[f64; 3]>,
    /// Twists about the line of sight tried per view (the arm reaches some).
    pub scan_twists: usize,
    /// Points farther than this from the tool are not the object (m), SPEC §1.1: 40 cm.
    pub crop_radius: f64,
    /// The scan is downsampled to this leaf (m), SPEC §6: 5 mm.
    pub scan_leaf: f64,
    /// A cluster with a point this close to the tool frame is the held object (m).
    pub grip_reach: f64,
    /// Protective sphere radius while the object is unknown (m), SPEC §6: 0.20 m.
    pub protective_radius: f64,
    /// Stable poses whose topple tilt is below this are not used (deg): the seed's
    /// objects placed near an edge of their support fell when the gripper opened.
    pub min_topple_deg: f64,
    /// The gripper must stay this far above the surface at release (m), Alg. 6.
    pub gripper_clearance: f64,
    /// Stable poses tried, best first.
    pub poses_tried: usize,
    /// Head pan angles of the surface sweep (rad), SPEC §6: −90°…+90° in 45° steps …
    pub sweep_pans: Vec<f64>,
    /// … looking at points this far out (m) at this height (m).
    pub sweep_distance: f64,
    pub sweep_height: f64,
    /// Surface search leaf (m) and range (m): the seed worked to 3.5 m.
    pub search_leaf: f64,
    pub search_range: f64,
    /// Surface points seen from at most this far (m) draw the free-space map's edges
    /// once there are enough of them: a depth camera's range noise grows with the
    /// square of the range (Kinect σ ≈ 1.5 mm·z², SPEC §5: 4 mm at 1.6 m, 13 mm at
    /// 3 m), and a table seen from across the room reaches centimetres past its edge.
    pub edge_range: f64,
    /// Search frames keep every `search_decimate`-th pixel of every such row.
    pub search_decimate: usize,
    /// Looks at an accepted surface's centroid that refine it, SPEC §6: 3 (at most) …
    pub refine_looks: usize,
    /// … stopping once a look moves the centroid less than this (m): the next look
    /// would be aimed at the same spot and see the same. Not in the seed.
    pub refine_converged: f64,
    /// Turn the base around and sweep again when nothing fits in front.
    pub turn_around: bool,
    /// Spots farther than this from the arm's shoulder are out of reach (m), Alg. 11.
    pub reach: f64,
    /// Gap kept between the base and the surface's edge when driving up to it (m).
    pub standoff: f64,
    /// The base turns to face the surface this far back from its goal, then drives
    /// straight in (m).
    pub approach_run: f64,
    /// Roll angles about the support normal per spot, SPEC §6: 10.
    pub roll_samples: usize,
    /// The object's lowest point this far above the surface when released (m), SPEC
    /// §6: 8 mm.
    pub release_height: f64,
    /// Free margin around the resting footprint: to edges, objects, unseen cells (m).
    pub place_margin: f64,
    /// Approach from above the spot: desired and minimum (m), SPEC §6: 0.2 / 0.1.
    pub approach_desired: f64,
    pub approach_min: f64,
    /// Retreat after release: desired and minimum (m), SPEC §6: 0.25 / 0.1.
    pub retreat_desired: f64,
    pub retreat_min: f64,
    /// Spots (with IK) planned at most before giving up.
    pub max_planned: usize,
    /// Raise the torso fully before anything else, seed 000 §1.6 (its `torso_up`
    /// defaults to true, following Willow Garage's advice for the PR2).
    pub raise_torso: bool,
    /// The finger gap grows at most this fast when releasing (m/s): a gentle release,
    /// fingers parting from the object rather than snapping off it.
    pub release_speed: f64,
}

impl Default for PlaceParams {
    fn default() -> Self {
        let s = std::f64::consts::FRAC_1_SQRT_2;
        Self {
            observe: ObserveParams {
                max_range: 3.5,
                ..ObserveParams::default()
            },
            motion: MoveGroupParams {
                cartesian_tolerance: 0.01,
                ..MoveGroupParams::default()
            },
            stable: StableParams::default(),
            surfaces: SurfaceParams {
                height_range: [0.25, 1.3],
                ..SurfaceParams::default()
            },
            free_space: FreeSpaceParams::default(),
            camera: "head".into(),
            scan_distance: 0.6,
            scan_drop: 0.3,
            scan_views: vec![
                [0.0, 1.0, 0.0],
                [0.0, -1.0, 0.0],
                [0.0, 0.0, 1.0],
                [0.0, 0.0, -1.0],
                [1.0, 0.0, 0.0],
                [-0.5, 0.87, 0.0],
                [-0.5, -0.87, 0.0],
                [-0.5, 0.0, 0.87],
                [-0.5, 0.0, -0.87],
                [s, s, 0.0],
                [s, -s, 0.0],
            ],
            scan_twists: 4,
            crop_radius: 0.4,
            scan_leaf: 0.005,
            grip_reach: 0.05,
            protective_radius: 0.20,
            min_topple_deg: 8.0,
            gripper_clearance: 0.003,
            poses_tried: 3,
            sweep_pans: [-90.0f64, -45.0, 0.0, 45.0, 90.0]
                .iter()
                .map(|d| d.to_radians())
                .collect(),
            sweep_distance: 1.6,
            sweep_height: 0.45,
            search_leaf: 0.01,
            search_range: 3.5,
            edge_range: 1.6,
            search_decimate: 2,
            refine_looks: 3,
            refine_converged: 0.01,
            turn_around: true,
            reach: 0.75,
            standoff: 0.06,
            approach_run: 0.5,
            roll_samples: 10,
            release_height: 0.008,
            place_margin: 0.02,
            approach_desired: 0.2,
            approach_min: 0.1,
            retreat_desired: 0.25,
            retreat_min: 0.1,
            max_planned: 12,
            raise_torso: true,
            release_speed: 0.02,
        }
    }
}

/// What to do: which arm holds the object (`None`: the one whose gripper is closed).
#[derive(Debug, Clone, Default)]
pub struct PlaceRequest {
    pub arm: Option<String>,
}

/// Why placing failed (typed, for `--json`'s `error`).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PlaceError {
    #[error("no arm holds an object")]
    NotHolding,
    #[error("the object could not be modelled: {0}")]
    Model(String),
    #[error("no stable pose leaves the gripper clear of the surface: {0}")]
    NoStablePose(String),
    #[error("no surface found: {0}")]
    NoSurface(String),
    #[error("no free spot fits the object: {0}")]
    NoRoom(String),
    #[error("the base could not get to the surface: {0}")]
    ApproachBlocked(String),
    #[error("unreachable: no spot the arm reaches")]
    Unreachable,
    #[error("no collision-free path: {0}")]
    NoPath(String),
    #[error("robot: {0}")]
    Driver(String),
}

impl PlaceError {
    /// The short type name in JSON.
    pub fn kind(&self) -> &'static str {
        match self {
            Self::NotHolding => "not holding",
            Self::Model(_) => "model",
            Self::NoStablePose(_) => "no stable pose",
            Self::NoSurface(_) => "no surface",
            Self::NoRoom(_) => "no room",
            Self::ApproachBlocked(_) => "approach blocked",
            Self::Unreachable => "unreachable",
            Self::NoPath(_) => "no collision-free path",
            Self::Driver(_) => "driver",
        }
    }
}

impl From<DriverError> for PlaceError {
    fn from(e: DriverError) -> Self {
        Self::Driver(e.to_string())
    }
}

impl From<MoveError> for PlaceError {
    fn from(e: MoveError) -> Self {
        match e {
            MoveError::Unreachable => Self::Unreachable,
            MoveError::World(w) => Self::Driver(w),
            other => Self::NoPath(other.to_string()),
        }
    }
}

/// The scanned model.
#[derive(Debug, Clone, Default, serde::Serialize)]
pub struct ModelReport {
    /// Views captured (of those tried).
    pub views: usize,
    pub views_tried: usize,
    /// Points of the model after downsampling.
    pub points: usize,
    pub hull_volume_m3: f64,
    /// Extent of the model in the tool frame (m).
    pub size: [f64; 3],
}

/// The surface chosen.
#[derive(Debug, Clone, serde::Serialize)]
pub struct SurfaceReport {
    /// Height of the surface at its centroid (m).
    pub height: f64,
    pub centroid: [f64; 3],
    pub area_m2: f64,
    pub tilt_deg: f64,
}

/// What a placement did.
#[derive(Debug, Clone, Default, serde::Serialize)]
pub struct PlaceReport {
    pub arm: Option<String>,
    pub model: Option<ModelReport>,
    /// Stable poses of the scanned model, and the one used.
    pub poses_found: usize,
    pub stable_pose: Option<StablePose>,
    pub surfaces_found: usize,
    pub surface: Option<SurfaceReport>,
    /// Where the base drove to (x, y, θ), when it did.
    pub base_goal: Option<[f64; 3]>,
    /// The tool's planned pose with the object resting on the surface (world): the
    /// object's predicted pose is this times its pose in the tool.
    pub planned_world_from_tool: Option<[f64; 7]>,
    pub phases: Vec<Phase>,
    /// CPU ms of every decision: modelling's processing, stable poses, surface search,
    /// free space, IK and motion planning — not the time the robot moves or the camera
    /// renders.
    pub decision_ms: f64,
    /// CPU ms of the scan's processing (self-filter, crop, accumulate, its motions).
    pub scan_cpu_ms: f64,
    pub candidates_tried: usize,
    pub rejected: Vec<String>,
    /// The model in the tool frame (for tests and reports).
    #[serde(skip)]
    pub model_points: Vec<Vec3>,
    /// The last surface's free-space map as the decision saw it (for reports).
    #[serde(skip)]
    pub top_view: Option<PlaceTopView>,
}

/// What the placement saw of the surface it chose: its free-space map and outline, the
/// objects on it (their points), and the footprint of the object resting where it was
/// planned to go (world, on the surface).
#[derive(Debug, Clone)]
pub struct PlaceTopView {
    pub map: FreeSpaceMap,
    pub outline: Vec<Vec3>,
    pub objects: Vec<Vec<Vec3>>,
    pub spot: Option<Vec<Vec3>>,
}

/// A placement's report and, when it failed, why.
#[derive(Debug, Clone)]
pub struct PlaceOutcome {
    pub report: PlaceReport,
    pub error: Option<PlaceError>,
}

/// Places the held object through `driver`.
pub fn place(
    driver: &mut impl RobotDriver,
    robot: &NamedRobot,
    request: &PlaceRequest,
    params: &PlaceParams,
) -> PlaceOutcome {
    let mut run = Run {
        robot,
        params,
        report: PlaceReport::default(),
        decision_cpu: 0.0,
        scan_cpu: 0.0,
        trace: tracing::enabled!(tracing::Level::DEBUG),
        template: None,
        scene_keys: Default::default(),
        near: Vec::new(),
        near_keys: Default::default(),
        held_reach: params.protective_radius,
    };
    let error = run.run(driver, request).err();
    let mut report = run.report;
    report.decision_ms = (run.decision_cpu - run.scan_cpu) * 1e3;
    report.scan_cpu_ms = run.scan_cpu * 1e3;
    PlaceOutcome { report, error }
}

fn pose_array(p: &Pose) -> [f64; 7] {
    let (t, q) = (p.translation, p.rotation);
    [t.x, t.y, t.z, q.x, q.y, q.z, q.w]
}

/// A spot the object may go: the tool pose that puts it there resting.
#[derive(Debug, Clone, Copy)]
struct Spot {
    world_from_tool: Pose,
    score: f64,
}

struct Run<'a> {
    robot: &'a NamedRobot,
    params: &'a PlaceParams,
    report: PlaceReport,
    decision_cpu: f64,
    /// CPU of the scan's own processing (Alg. 1), which the decision leaves out.
    scan_cpu: f64,
    trace: bool,
    /// The first move group: its allowed-collision matrix is sampled once per robot
    /// (MoveIt keeps it in the SRDF), so it is setup, not part of a decision.
    template: Option<MoveGroup>,
    /// The voxels the scene already has a point in.
    scene_keys: rustc_hash::FxHashSet<u64>,
    /// The scene's points seen from within `edge_range`, one per voxel.
    near: Vec<Vec3>,
    near_keys: rustc_hash::FxHashSet<u64>,
    /// How far from the tool frame what the hand holds reaches (m): the protective
    /// sphere while scanning, then the larger of it and the model.
    held_reach: f64,
}

impl Run<'_> {
    /// Adds seen points to the scene, one per search-leaf voxel: views overlap, and
    /// every later step (surface search, free space, occupancy) works on the scene.
    fn add_scene(&mut self, scene: &mut Vec<Vec3>, points: Vec<Vec3>) {
        for q in points {
            if self
                .scene_keys
                .insert(tabula_geom::packed_voxel_key(q, self.params.search_leaf))
            {
                scene.push(q);
            }
        }
    }

    /// A move group for `arm` at `state`, without world objects.
    fn group(
        &mut self,
        arm: &str,
        state: &JointState,
        root: Pose,
    ) -> Result<MoveGroup, PlaceError> {
        let robot = self.robot;
        if self.template.is_none() {
            self.template = Some(MoveGroup::new(
                robot,
                arm,
                state,
                root,
                self.params.motion.clone(),
            )?);
        }
        let t = self.template.as_ref().ok_or(PlaceError::NotHolding)?;
        let mut g = t.for_arm(robot, arm)?;
        g.set_state(robot, state)?;
        Ok(g)
    }

    fn mark(&self, what: &str) {
        if self.trace {
            tracing::debug!("place: {what}");
        }
    }

    /// Runs `f` as a named stage (wall-clock ms; CPU counted by the caller).
    fn phase<T>(
        &mut self,
        name: &str,
        f: impl FnOnce(&mut Self) -> Result<T, PlaceError>,
    ) -> Result<T, PlaceError> {
        let (t0, cpu0) = (Instant::now(), self.decision_cpu);
        self.mark(&format!("phase {name}"));
        let out = f(self);
        tracing::info!(
            phase = name,
            ms = t0.elapsed().as_secs_f64() * 1e3,
            decision_cpu_ms = (self.decision_cpu - cpu0) * 1e3,
            ok = out.is_ok(),
            "place"
        );
        self.report.phases.push(Phase {
            name: name.into(),
            ms: t0.elapsed().as_secs_f64() * 1e3,
            ok: out.is_ok(),
            // The decision CPU spent in this stage.
            plan_ms: Some((self.decision_cpu - cpu0) * 1e3),
        });
        if let Err(e) = &out {
            self.mark(&format!("{name} failed: {e}"));
        }
        out
    }

    /// Runs CPU work counted toward the decision.
    fn decide<T>(&mut self, f: impl FnOnce(&mut Self) -> T) -> T {
        let c0 = thread_cpu();
        let out = f(self);
        self.decision_cpu += thread_cpu() - c0;
        out
    }

    fn run(
        &mut self,
        driver: &mut impl RobotDriver,
        request: &PlaceRequest,
    ) -> Result<(), PlaceError> {
        let robot = self.robot;
        let state = driver.joint_state()?;
        let arm = match &request.arm {
            Some(a) => {
                robot
                    .description
                    .arm(a)
                    .map_err(|e| PlaceError::Driver(e.to_string()))?;
                a.clone()
            }
            None => holding_arm(robot, &state).ok_or(PlaceError::NotHolding)?,
        };
        self.report.arm = Some(arm.clone());
        if self.params.raise_torso {
            self.phase("raise torso", |_| {
                crate::torso::raise_torso(driver, robot)?;
                Ok(())
            })?;
        }
        // ---- Object modelling (Alg. 1): scanning, not deciding.
        let c0 = self.decision_cpu;
        let modelled = self.phase("model object", |r| r.model_object(driver, &arm));
        self.scan_cpu += self.decision_cpu - c0;
        let (model, seen) = modelled?;
        driver.annotate("scanned the object in the hand");
        // ---- Stable poses (Algs 2–7) with the gripper clear of the surface.
        let poses = self.phase("stable poses", |r| {
            r.decide(|r| r.stable_poses(&arm, &model))
        })?;
        let hull = SharedShape::convex_hull(&model)
            .ok_or_else(|| PlaceError::Model("the scan has no solid hull".into()))?;
        // ---- Carry the object out of the camera's way, then look for surfaces.
        self.phase("carry", |r| r.carry(driver, &arm, &hull, &seen))?;
        driver.annotate("carrying it out of the camera's view");
        let mut scene = seen;
        let mut turned = false;
        loop {
            let found = self
                .phase("surface search", |r| {
                    r.search_surfaces(driver, &arm, &hull, &mut scene)
                })
                .and_then(|surfaces| {
                    driver.annotate(&format!("found {} surface(s)", surfaces.len()));
                    self.report.surfaces_found = self.report.surfaces_found.max(surfaces.len());
                    self.try_surfaces(driver, &arm, &hull, &poses, &surfaces, &mut scene)
                });
            match found {
                Ok(()) => return Ok(()),
                Err(e) if self.params.turn_around && !turned && retry_behind(&e) => {
                    // Nothing usable in front: turn around and look behind.
                    turned = true;
                    let base = world_from_base(robot, driver)?;
                    let heading = heading(&base) + std::f64::consts::PI;
                    self.phase("turn around", |_| {
                        driver.drive_to(base.translation.x, base.translation.y, heading)?;
                        Ok(())
                    })?;
                }
                Err(e) => return Err(e),
            }
        }
    }

    /// Alg. 1: hold the object before the head camera and look at it from many sides;
    /// returns the model in the tool frame and the scene points seen meanwhile.
    fn model_object(
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
        let first = self.scan_view(driver, &tool_link, tool_now.translation, &mut scene)?;
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
        self.scan_view(driver, &tool_link, target, &mut scene)?;
        // The other arms out of the way (the seed's first step).
        self.decide(|r| r.occupy(&mut group, &scene, None));
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
                self.occupy(&mut g, &scene, None);
                let plan = self.decide(|_| g.plan_to_joints(&start, &[goal]));
                if let Ok(plan) = plan {
                    driver.execute(&plan.trajectory)?;
                }
            }
        }
        // The views: the tool turned so the camera sees the object from each direction.
        let mut state = driver.joint_state()?;
        group.set_state(robot, &state)?;
        self.occupy(&mut group, &scene, None);
        group.attach(
            "protective sphere",
            protective,
            Pose::from_translation(sphere_centre),
        )?;
        let mut used = 0usize;
        let to_camera = (cam - target).normalize_or(Vec3::Z);
        for (k, v) in p.scan_views.iter().enumerate() {
            let v = Vec3::from_array(*v).normalize_or(Vec3::X);
            let base = Quat::from_rotation_arc(v, to_camera);
            let start = group.arm_values(&state);
            let mut why = String::new();
            let plan = self.decide(|r| {
                (0..r.params.scan_twists.max(1)).find_map(|t| {
                    let twist = Quat::from_axis_angle(
                        to_camera,
                        std::f64::consts::TAU * t as f64 / r.params.scan_twists.max(1) as f64,
                    );
                    let pose = Pose::from_parts(target, twist * base);
                    group
                        .plan_to_pose(&start, &pose)
                        .map_err(|e| why = e.to_string())
                        .ok()
                })
            });
            let Some(plan) = plan else {
                self.mark(&format!("scan view {k} unreachable: {why}"));
                continue;
            };
            driver.execute(&plan.trajectory)?;
            let seen = self.scan_view(driver, &tool_link, target, &mut scene)?;
            if !seen.is_empty() {
                used += 1;
            }
            model.extend(seen);
            state = driver.joint_state()?;
        }
        // The views overlap: one point per leaf (SPEC §1.1 downsamples).
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
        Ok((model, scene))
    }

    /// Looks at `at`, captures, and returns the held object's points in the tool frame;
    /// everything else seen goes into `scene` (world frame).
    fn scan_view(
        &mut self,
        driver: &mut impl RobotDriver,
        tool_link: &str,
        at: Vec3,
        scene: &mut Vec<Vec3>,
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
            let (near, far): (Vec<Vec3>, Vec<Vec3>) = points
                .into_iter()
                .partition(|q| q.distance(tool) <= p.crop_radius);
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
                } else if closest > p.protective_radius {
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
    fn occupy(&self, group: &mut MoveGroup, scene: &[Vec3], keep_out: Option<(Vec3, f64)>) {
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
    fn stable_poses(&mut self, arm: &str, model: &[Vec3]) -> Result<Vec<StablePose>, PlaceError> {
        let p = self.params;
        let found = of_cloud(model, &p.stable).map_err(|e| PlaceError::Model(e.to_string()))?;
        if let Some(m) = self.report.model.as_mut() {
            m.hull_volume_m3 = found.hull_volume_m3;
        }
        self.report.poses_found = found.poses.len();
        let gripper = gripper_points(self.robot, arm);
        let com = Vec3::from_array(found.center_of_mass);
        // Ranked by the tilt that topples them, weighed by how much of the support the
        // object really touches (a bridge over a concavity rests on edges).
        let mut usable: Vec<(f64, StablePose)> = found
            .poses
            .iter()
            .filter(|s| s.topple_deg >= p.min_topple_deg)
            // At release the object hangs `release_height` above the surface: the hand
            // may reach below the object's support plane by less than that.
            .filter(|s| s.clear_of(&gripper, p.gripper_clearance - p.release_height))
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
                (s.topple_deg * (0.4 + 0.6 * fill) * rocking, s.clone())
            })
            .collect();
        usable.sort_by(|a, b| b.0.total_cmp(&a.0));
        let usable: Vec<StablePose> = usable
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
            usable[0].support_normal,
            usable[0].topple_deg
        ));
        Ok(usable)
    }

    /// Moves the holding arm to the side, level with the shoulder, out of the head's
    /// forward view; the object's hull rides along in the collision world.
    fn carry(
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

    /// Alg. 9: sweep the head, merge the views in the world frame (minus the robot and
    /// the held object), search planes, refine each accepted one by looking at it.
    fn search_surfaces(
        &mut self,
        driver: &mut impl RobotDriver,
        arm: &str,
        hull: &SharedShape,
        scene: &mut Vec<Vec3>,
    ) -> Result<Vec<Surface>, PlaceError> {
        let p = self.params;
        let root = world_from_base(self.robot, driver)?;
        let h = heading(&root);
        self.mark(&format!(
            "sweep from ({:.2}, {:.2}) heading {:.0}°",
            root.translation.x,
            root.translation.y,
            h.to_degrees()
        ));
        let looks: Vec<Vec3> = p
            .sweep_pans
            .iter()
            .map(|a| {
                let d = Vec3::new((h + a).cos(), (h + a).sin(), 0.0);
                Vec3::new(root.translation.x, root.translation.y, p.sweep_height)
                    + d * p.sweep_distance
            })
            .collect();
        for at in looks {
            self.look_and_add(driver, arm, hull, at, scene)?;
        }
        let mut surfaces = self.decide(|r| r.find(scene));
        // Refinement: look at each accepted surface again, search near its height, until
        // a look no longer moves its centroid (the next one would see the same).
        for surface in surfaces.iter_mut() {
            for _ in 0..p.refine_looks {
                let c = surface.centroid;
                self.look_and_add(driver, arm, hull, c, scene)?;
                let again = self.decide(|r| r.find_again(scene, surface));
                if let Some(best) = again
                    .into_iter()
                    .min_by(|a, b| a.centroid.distance(c).total_cmp(&b.centroid.distance(c)))
                {
                    *surface = best;
                }
                if surface.centroid.distance(c) < p.refine_converged {
                    break;
                }
            }
        }
        // Merged views may find one surface twice.
        let mut unique: Vec<Surface> = Vec::new();
        for s in surfaces {
            if !unique.iter().any(|u| {
                (u.centroid.z - s.centroid.z).abs() < 0.03 && Outline::of(u).over(s.centroid)
            }) {
                unique.push(s);
            }
        }
        self.mark(&format!("{} surfaces", unique.len()));
        if unique.is_empty() {
            return Err(PlaceError::NoSurface(format!(
                "no horizontal surface of {:.0} cm² or more at {:.2}–{:.2} m",
                p.surfaces.min_area * 1e4,
                p.surfaces.height_range[0],
                p.surfaces.height_range[1]
            )));
        }
        Ok(unique)
    }

    /// Horizontal surfaces in the merged scene.
    fn find(&self, scene: &[Vec3]) -> Vec<Surface> {
        let p = self.params;
        let cloud = self.reachable_heights(scene);
        let search = find_surfaces(&cloud, None, &p.surfaces, false);
        if self.trace {
            for t in &search.trials {
                tracing::debug!(
                    "place: plane of {} points at {:.2} m, tilt {:.2}: {:?} ({} points searched)",
                    t.points,
                    t.height,
                    t.tilt,
                    t.verdict,
                    cloud.points.len()
                );
            }
        }
        search
            .surfaces
            .into_iter()
            .filter(|s| s.area >= p.surfaces.min_area)
            .collect()
    }

    /// `surface` in the merged scene again after another look at it: the points within
    /// the refinement threshold of its plane, refined, split and checked as a search
    /// would (the plane needs no new search).
    fn find_again(&self, scene: &[Vec3], surface: &Surface) -> Vec<Surface> {
        let p = self.params;
        let cloud = self.reachable_heights(scene);
        let keep: Vec<bool> = cloud
            .points
            .iter()
            .map(|q| surface.plane.distance(*q).abs() <= p.surfaces.refine_threshold)
            .collect();
        surfaces_on(&cloud, Some(&keep), surface.plane, &p.surfaces)
            .into_iter()
            .filter(|s| s.area >= p.surfaces.min_area)
            .collect()
    }

    /// The scene's points at heights a reachable surface can have. Gravity is known
    /// (the world frame), so the floor (most of a sweep) is not searched at all — the
    /// seed peeled it off plane by plane and then rejected it by height.
    fn reachable_heights(&self, scene: &[Vec3]) -> PointCloud {
        let [lo, hi] = self.params.surfaces.height_range;
        PointCloud::unorganized(
            scene
                .iter()
                .copied()
                .filter(|q| q.z >= lo - 0.05 && q.z <= hi + 0.05)
                .collect(),
        )
    }

    fn look_and_add(
        &mut self,
        driver: &mut impl RobotDriver,
        arm: &str,
        hull: &SharedShape,
        at: Vec3,
        scene: &mut Vec<Vec3>,
    ) -> Result<(), PlaceError> {
        look_at(driver, at)?;
        let frame = driver.capture(&self.params.camera)?;
        let state = driver.joint_state()?;
        let root = driver.world_from_root()?;
        let robot = self.robot;
        self.decide(|r| {
            let mut solids = robot_solids(&robot.model, &state.model_values(&robot.model), root);
            // The held object is the robot's too.
            if let Some(tool_link) = arm_gripper(robot, arm).map(|g| g.tool_link.as_str())
                && let Ok(world_from_tool) = tool_pose(robot, &state, root, tool_link)
                && let Some(points) = hull.as_convex_polyhedron().map(|c| c.points().to_vec())
                && let Some(solid) = Solid::convex_hull(&points)
            {
                solids.push(PlacedSolid {
                    world_from_solid: world_from_tool,
                    solid,
                });
            }
            let mut obs = r.params.observe.clone();
            obs.max_range = r.params.search_range;
            // Every other pixel: at a surface's range neighbouring pixels are a few
            // millimetres apart, well inside the search's centimetre leaf.
            let frame = tabula_robot::driver::CameraFrame {
                cloud: frame.cloud.decimated(r.params.search_decimate.max(1)),
                ..frame
            };
            // One point per search leaf is kept below, over every view at once.
            let seen = world_points_unthinned(&frame, &solids, &obs);
            let eye = frame.world_from_camera.translation;
            let range2 = r.params.edge_range * r.params.edge_range;
            // Neighbouring pixels often share a voxel: a run needs no hash lookups.
            let mut last = None;
            for q in seen {
                let key = tabula_geom::packed_voxel_key(q, r.params.search_leaf);
                if last.replace(key) == Some(key) {
                    continue;
                }
                if q.distance_squared(eye) <= range2 && r.near_keys.insert(key) {
                    r.near.push(q);
                }
                if r.scene_keys.insert(key) {
                    scene.push(q);
                }
            }
        });
        Ok(())
    }

    /// Tries the surfaces nearest first: a free spot, the base driven up to it if out
    /// of reach, then the placement.
    fn try_surfaces(
        &mut self,
        driver: &mut impl RobotDriver,
        arm: &str,
        hull: &SharedShape,
        poses: &[StablePose],
        surfaces: &[Surface],
        scene: &mut Vec<Vec3>,
    ) -> Result<(), PlaceError> {
        let me = world_from_base(self.robot, driver)?.translation.truncate();
        let mut order: Vec<(f64, &Surface)> = surfaces
            .iter()
            .map(|s| (Outline::of(s).distance(me), s))
            .collect();
        order.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mut last = PlaceError::NoRoom("no surface was tried".into());
        for (_, surface) in order {
            self.report.surface = Some(SurfaceReport {
                height: surface.centroid.z,
                centroid: surface.centroid.to_array(),
                area_m2: surface.area,
                tilt_deg: surface.plane.normal.angle_between(Vec3::Z).to_degrees(),
            });
            match self.place_on(driver, arm, hull, poses, surface, scene) {
                Ok(()) => return Ok(()),
                Err(e @ PlaceError::Driver(_)) => return Err(e),
                Err(e) => {
                    self.report
                        .rejected
                        .push(format!("surface at {:.2} m: {e}", surface.centroid.z));
                    last = e;
                }
            }
        }
        Err(last)
    }

    fn place_on(
        &mut self,
        driver: &mut impl RobotDriver,
        arm: &str,
        hull: &SharedShape,
        poses: &[StablePose],
        surface: &Surface,
        scene: &mut Vec<Vec3>,
    ) -> Result<(), PlaceError> {
        let p = self.params;
        // Free spots for each usable pose (the footprint of the object resting so).
        let spots_of =
            |r: &mut Self, scene: &[Vec3]| -> Result<Vec<(usize, Vec3, f64, f64)>, PlaceError> {
                r.phase("free space", |r| {
                    r.decide(|r| r.free_spots(poses, surface, scene))
                })
            };
        let mut spots = spots_of(self, scene)?;
        if spots.is_empty() {
            return Err(PlaceError::NoRoom(format!(
                "the surface at {:.2} m has no room for the object's footprint with {:.0} mm to spare",
                surface.centroid.z,
                p.place_margin * 1e3
            )));
        }
        // ---- Approach (Alg. 10) when the spots are out of the arm's reach.
        let mut sh = shoulder_position(
            self.robot,
            arm,
            &driver.joint_state()?,
            driver.world_from_root()?,
        )?;
        let reachable =
            |sh: Vec3, s: &(usize, Vec3, f64, f64), reach: f64| s.1.distance(sh) <= reach;
        if !spots.iter().any(|s| reachable(sh, s, p.reach)) {
            let base = world_from_base(self.robot, driver)?;
            let state = driver.joint_state()?;
            let root = driver.world_from_root()?;
            // How far the robot reaches forward below the surface's top (an elbow
            // hanging low, a tucked arm): that, not the base's edge, meets the edge.
            let front = forward_extent(self.robot, &state, root, base, surface.centroid.z + 0.05)
                .max(base_half_extent(self.robot));
            self.mark(&format!(
                "robot reaches {front:.2} m forward below the surface"
            ));
            let goal = self.decide(|r| r.base_goal(base, front, arm, surface, &spots, scene))?;
            self.report.base_goal = Some(goal);
            self.phase("approach", |r| {
                // Turn while still clear of the surface, then drive straight in: a base
                // turning at the edge would sweep its corners into it.
                let (c, s) = (goal[2].cos(), goal[2].sin());
                let back = r.params.approach_run;
                driver.drive_to(goal[0] - c * back, goal[1] - s * back, goal[2])?;
                driver.drive_to(goal[0], goal[1], goal[2])?;
                let base = world_from_base(r.robot, driver)?;
                let off = base
                    .translation
                    .truncate()
                    .distance(Vec2::new(goal[0], goal[1]));
                if off > 0.05 {
                    return Err(PlaceError::ApproachBlocked(format!(
                        "stopped {:.2} m short of ({:.2}, {:.2})",
                        off, goal[0], goal[1]
                    )));
                }
                // Look at the surface from here: what is near it now counts.
                let c = surface.centroid;
                r.look_and_add(driver, arm, hull, c, scene)?;
                Ok(())
            })?;
            spots = spots_of(self, scene)?;
            sh = shoulder_position(
                self.robot,
                arm,
                &driver.joint_state()?,
                driver.world_from_root()?,
            )?;
        }
        // ---- Place (Algs 11–12).
        let state = driver.joint_state()?;
        let root = driver.world_from_root()?;
        let robot = self.robot;
        let mut group = self.group(arm, &state, root)?;
        let plan = self.phase("plan placement", |r| {
            r.decide(|r| {
                // The surface itself is an exact slab at its measured height (seed 000
                // added the found surface to the planning scene), not occupancy voxels
                // that would stand up to a voxel above it.
                let outline = Outline::of(surface);
                let rest: Vec<Vec3> = scene
                    .iter()
                    .copied()
                    .filter(|q| {
                        let h = outline.height(*q);
                        !(h > -0.025 && h < 0.015 && outline.distance(q.truncate()) < 0.02)
                    })
                    .collect();
                r.occupy(&mut group, &rest, None);
                if let Some(slab) = surface_slab(surface, 0.0) {
                    group.add_object("surface", slab, Pose::IDENTITY)?;
                }
                // What stays of it while the hand is within millimetres of it (lowering,
                // releasing, backing out): the slab sunk by the padding, so the fingers
                // may pass just above the top and the wrist still cannot sweep through.
                let sunk = group.world.params.padding + 0.004;
                if let Some(slab) = surface_slab(surface, sunk) {
                    group.add_object("surface below", slab, Pose::IDENTITY)?;
                }
                r.plan_placement(&mut group, &state, hull, poses, surface, &spots, sh)
            })
        })?;
        let (seq, spot, pose_index) = plan;
        self.report.stable_pose = Some(poses[pose_index].clone());
        self.report.planned_world_from_tool = Some(pose_array(&spot.world_from_tool));
        if let Some(view) = self.report.top_view.as_mut() {
            // The object's outline resting at the spot, as the map sees it.
            let resting: Vec<Vec3> = self
                .report
                .model_points
                .iter()
                .map(|q| spot.world_from_tool.transform_point(*q))
                .collect();
            let flat: Vec<Vec2> = resting.iter().map(|q| q.truncate()).collect();
            let z = surface.centroid.z;
            view.spot = Some(
                convex_hull_2d(&flat)
                    .into_iter()
                    .map(|i| flat[i].extend(z))
                    .collect(),
            );
        }
        let gripper = robot
            .description
            .arm(arm)
            .ok()
            .and_then(|a| a.gripper.clone())
            .ok_or(PlaceError::NotHolding)?;
        self.phase("move above spot", |_| {
            Ok(driver.execute(&seq.to_above.trajectory)?)
        })?;
        self.phase("lower", |_| Ok(driver.execute(&seq.lower.trajectory)?))?;
        let speed = self.params.release_speed;
        self.phase("release", |_| Ok(driver.open_slowly(&gripper, speed)?))?;
        self.phase("retreat", |_| Ok(driver.execute(&seq.retreat.trajectory)?))?;
        if let Some(aside) = &seq.aside {
            self.phase("arm aside", |_| Ok(driver.execute(&aside.trajectory)?))?;
        }
        Ok(())
    }

    /// Free spots on `surface` for each usable pose: (pose index, world position of the
    /// footprint origin, yaw in the world, score), best first.
    fn free_spots(
        &mut self,
        poses: &[StablePose],
        surface: &Surface,
        scene: &[Vec3],
    ) -> Result<Vec<(usize, Vec3, f64, f64)>, PlaceError> {
        let p = self.params;
        let pts = scene;
        // Objects on the surface: what stands above it inside its outline.
        let outline = Outline::of(surface);
        let above: Vec<Vec3> = pts
            .iter()
            .copied()
            .filter(|q| {
                let h = outline.height(*q);
                h > p.observe.object_clearance + 0.004 && h < 0.5 && outline.over(*q)
            })
            .collect();
        let objects: Vec<Vec<Vec3>> = clusters(&above, p.observe.cluster_gap)
            .into_iter()
            .filter(|c| c.len() >= 3)
            .map(|c| c.into_iter().map(|i| above[i]).collect())
            .collect();
        let mut fs = p.free_space.clone();
        fs.yaw_samples = p.roll_samples.max(1);
        // The surface's seen cells: its points in the merged scene (the search ran on
        // another sampling of it).
        let on_surface =
            |q: Vec3| outline.height(q).abs() <= p.surfaces.ransac.threshold && outline.over(q);
        let mut seen = surface.clone();
        // From near, once near views cover a footprint's worth of it: the far points'
        // range noise would carry its edges outward.
        let near: Vec<usize> = (0..self.near.len())
            .filter(|&i| on_surface(self.near[i]))
            .collect();
        let cell = p.search_leaf * p.search_leaf;
        let footprint_cells = poses
            .iter()
            .map(|s| s.area_m2 / cell)
            .fold(f64::INFINITY, f64::min);
        let edge_points = if near.len() as f64 >= 4.0 * footprint_cells.max(25.0) {
            seen.inliers = near;
            &self.near
        } else {
            seen.inliers = (0..pts.len()).filter(|&i| on_surface(pts[i])).collect();
            pts
        };
        let map = FreeSpaceMap::build(&seen, edge_points, &objects, &fs)
            .map_err(|e| PlaceError::NoRoom(e.to_string()))?;
        self.report.top_view = Some(PlaceTopView {
            map: map.clone(),
            outline: surface.hull.clone(),
            objects,
            spot: None,
        });
        let u_yaw = map.u.y.atan2(map.u.x);
        let mut out = Vec::new();
        for (k, pose) in poses.iter().enumerate() {
            let footprint = footprint_of(pose, &self.report.model_points);
            // Spots all over the surface: which the arm reaches decides later.
            for pl in map.places(&footprint, p.place_margin, 400, 0.04) {
                out.push((k, pl.position, pl.yaw + u_yaw, pl.clearance));
            }
        }
        Ok(out)
    }

    /// Alg. 10: a base pose facing the surface, the shoulder in front of the best free
    /// spot, the base's front `standoff` from the surface's edge.
    fn base_goal(
        &self,
        base: Pose,
        front: f64,
        arm: &str,
        surface: &Surface,
        spots: &[(usize, Vec3, f64, f64)],
        scene: &[Vec3],
    ) -> Result<[f64; 3], PlaceError> {
        let p = self.params;
        let me = base.translation.truncate();
        let hull2: Vec<Vec2> = surface.hull.iter().map(|q| q.truncate()).collect();
        let half = base_half_extent(self.robot);
        // The shoulder's offset in the base frame (left/right of the centre line).
        let lateral = shoulder_lateral(self.robot, arm);
        let mut best: Option<(f64, [f64; 3])> = None;
        // The shoulder stands about the base's half-length and the standoff from the
        // edge: spots deeper in than the rest of the reach cannot be placed from there.
        let depth = p.reach - front - p.standoff - 0.05;
        for s in spots {
            let spot = s.1.truncate();
            // Nearest point of the outline to the spot: the edge to stand at.
            let (edge, outward) = nearest_edge(&hull2, spot);
            if edge.distance(spot) > depth {
                continue;
            }
            let along = Vec2::new(-outward.y, outward.x);
            let facing = -outward;
            let theta = facing.y.atan2(facing.x);
            // Base centre: out from the edge; shifted so the shoulder faces the spot.
            let side_shift = (spot - edge).dot(along);
            let centre = edge + outward * (front + p.standoff) + along * side_shift
                - Vec2::new(-facing.y, facing.x) * lateral;
            let cost = me.distance(centre);
            if best.is_some_and(|(c, _)| cost >= c) {
                continue;
            }
            // The base must not sweep through anything seen on the way.
            let run_up = centre - facing * p.approach_run;
            let blocked = path_blocked(me, run_up, half * std::f64::consts::SQRT_2, scene)
                || path_blocked(run_up, centre, half, scene);
            let cost = cost + if blocked { 100.0 } else { 0.0 };
            if best.is_none_or(|(c, _)| cost < c) {
                best = Some((cost, [centre.x, centre.y, theta]));
            }
        }
        match best {
            Some((c, g)) if c < 100.0 => Ok(g),
            Some((_, g)) => Err(PlaceError::ApproachBlocked(format!(
                "something stands between the robot and ({:.2}, {:.2})",
                g[0], g[1]
            ))),
            None => Err(PlaceError::NoRoom("no spot to approach".into())),
        }
    }

    /// Algs 11–12: spots in reach × roll angles, IK, then the motions: to above the
    /// spot (object attached), down to release height, and the retreat.
    #[allow(clippy::too_many_arguments)]
    fn plan_placement(
        &mut self,
        group: &mut MoveGroup,
        state: &JointState,
        hull: &SharedShape,
        poses: &[StablePose],
        surface: &Surface,
        spots: &[(usize, Vec3, f64, f64)],
        shoulder: Vec3,
    ) -> Result<(Sequence, Spot, usize), PlaceError> {
        let p = self.params;
        let start = group.arm_values(state);
        let n = surface.plane.normal;
        let offset = surface.centroid.dot(n);
        // Spots in reach, better poses first, then nearer the shoulder, then roomier.
        let mut cands: Vec<(usize, Spot)> = spots
            .iter()
            .filter(|s| s.1.distance(shoulder) <= p.reach)
            .map(|&(k, position, yaw, clearance)| {
                let pose = &poses[k];
                let rotation = pose.resting_rotation(yaw);
                let c = Vec3::from_array(pose.contact_centroid);
                // On the plane under `position`, raised by the release height.
                let on_plane = position - n * (position.dot(n) - offset);
                let world_from_tool = Pose::from_parts(
                    on_plane + Vec3::Z * p.release_height - rotation * c,
                    rotation,
                );
                let score = k as f64 * 10.0 + position.distance(shoulder) - 0.5 * clearance;
                (
                    k,
                    Spot {
                        world_from_tool,
                        score,
                    },
                )
            })
            .collect();
        if cands.is_empty() {
            return Err(PlaceError::Unreachable);
        }
        cands.sort_by(|a, b| a.1.score.total_cmp(&b.1.score));
        let full = group.world.clone();
        let mut last = PlaceError::Unreachable;
        let mut planned = 0usize;
        for (k, spot) in cands {
            if planned >= p.max_planned {
                break;
            }
            // IK first: cheap, and most spots fail here.
            if group.ik(&spot.world_from_tool, &start).is_err() {
                continue;
            }
            planned += 1;
            self.report.candidates_tried += 1;
            group.world = full.clone();
            match plan_sequence(group, &full, hull, &spot, &start, p) {
                Ok(seq) => return Ok((seq, spot, k)),
                Err(e) => {
                    let t = spot.world_from_tool.translation;
                    self.report.rejected.push(format!(
                        "pose {k} at ({:.2}, {:.2}, {:.2}): {e}",
                        t.x, t.y, t.z
                    ));
                    if !matches!(e, PlaceError::Unreachable) {
                        last = e;
                    }
                }
            }
        }
        group.world = full;
        Err(last)
    }
}

/// Every motion of one placement.
struct Sequence {
    to_above: Plan,
    lower: Plan,
    retreat: Plan,
    aside: Option<Plan>,
}

/// Plans one spot: above it (the approach distance up, desired then minimum), a path
/// there holding the object's hull, the straight line down, the straight line back up
/// after release (the object left on the surface as an obstacle), and the arm aside.
fn plan_sequence(
    group: &mut MoveGroup,
    full: &CollisionWorld,
    hull: &SharedShape,
    spot: &Spot,
    start: &[f64],
    p: &PlaceParams,
) -> Result<Sequence, PlaceError> {
    let shifted = |d: f64| {
        Pose::from_parts(
            spot.world_from_tool.translation + Vec3::Z * d,
            spot.world_from_tool.rotation,
        )
    };
    {
        group.world = full.clone();
        group.attach("object", hull.clone(), Pose::IDENTITY)
    }?;
    let holding = group.world.clone();
    let _ = group.world.remove_object("surface");
    let goal_ok = group.valid_ik(&spot.world_from_tool, start);
    let mut last = match goal_ok {
        Ok(_) => PlaceError::Unreachable,
        Err(e) => return Err(e.into()),
    };
    // The ways down from the first approach distance that has any (desired first, then
    // shorter; every IK branch), then one RRT-Connect to all of their tops at once: a
    // failed search is the costly part, and one that cannot reach any top need not be
    // run again per top. A shorter approach is only a fallback (MoveIt's place stage
    // takes the same desired-then-minimum range), so it is not tried once one works.
    let mut ways: Vec<(Vec<f64>, Plan)> = Vec::new();
    for d in [
        p.approach_desired,
        (p.approach_desired + p.approach_min) / 2.0,
        p.approach_min,
    ] {
        if !ways.is_empty() {
            break;
        }
        let above = shifted(d);
        group.world = holding.clone();
        let goals = match group.valid_ik(&above, start) {
            Ok(g) => g,
            Err(e) => {
                last = e.into();
                continue;
            }
        };
        for q_above in goals.into_iter().take(3) {
            // Down to millimetres above the surface: closer than the padding, so only
            // the sunk slab stays for the line down and the line back out (the stable
            // pose keeps the gripper clear of the top, Alg. 6).
            group.world = holding.clone();
            let _ = group.world.remove_object("surface");
            match group.cartesian(&q_above, &spot.world_from_tool) {
                Ok(lower) => ways.push((q_above, lower)),
                Err(e) => last = e.into(),
            }
        }
    }
    if ways.is_empty() {
        return Err(last);
    }
    group.world = holding.clone();
    let tops: Vec<Vec<f64>> = ways.iter().map(|(q, _)| q.clone()).collect();
    let to_above = group.plan_to_joints(start, &tops)?;
    let reached = to_above.end().to_vec();
    let nearest = ways
        .iter()
        .enumerate()
        .min_by(|a, b| {
            let da: f64 = a.1.0.iter().zip(&reached).map(|(x, y)| (x - y).abs()).sum();
            let db: f64 = b.1.0.iter().zip(&reached).map(|(x, y)| (x - y).abs()).sum();
            da.total_cmp(&db)
        })
        .map(|(i, _)| i)
        .unwrap_or(0);
    let (_, lower) = ways.swap_remove(nearest);
    {
        {
            // After release: the object stays, the hand backs straight up.
            let mut released = full.clone();
            let object_pose = released
                .tip_pose(lower.end())
                .map_err(|e| PlaceError::Driver(e.to_string()))?;
            // Left behind it is an obstacle, given room: it may have settled a little
            // differently from the scan, and a brush topples a tall object.
            let grown = hull
                .as_convex_polyhedron()
                .and_then(|c| {
                    let pts = c.points();
                    let centre = pts.iter().copied().sum::<Vec3>() / pts.len().max(1) as f64;
                    let out: Vec<Vec3> = pts
                        .iter()
                        .map(|q| {
                            let d = *q - centre;
                            centre + d + d.normalize_or_zero() * 0.02
                        })
                        .collect();
                    SharedShape::convex_hull(&out)
                })
                .unwrap_or_else(|| hull.clone());
            let _ = released.add_object("placed object", grown, object_pose);
            group.world = full.clone();
            let _ = group.world.remove_object("surface");
            // Out of the grasp the way the fingers went in (back along the tool's own
            // approach axis, seed 000's retreat), so an opened finger under an overhang
            // cannot drag the object along; straight up when that line is blocked.
            let back = -(spot.world_from_tool.rotation
                * group.gripper.as_ref().map_or(Vec3::X, |g| g.approach()));
            let mut retreat = None;
            'lines: for dir in [back, Vec3::Z] {
                for r in [
                    p.retreat_desired,
                    (p.retreat_desired + p.retreat_min) / 2.0,
                    p.retreat_min,
                ] {
                    let goal = Pose::from_parts(
                        spot.world_from_tool.translation + dir * r,
                        spot.world_from_tool.rotation,
                    );
                    if let Ok(pl) = group.cartesian(lower.end(), &goal) {
                        retreat = Some(pl);
                        break 'lines;
                    }
                }
            }
            let Some(retreat) = retreat else {
                return Err(PlaceError::NoPath(
                    "no straight retreat from the released object".into(),
                ));
            };
            group.world = released;
            let aside = group.plan_to_joints(retreat.end(), &[start.to_vec()]).ok();
            Ok(Sequence {
                to_above,
                lower,
                retreat,
                aside,
            })
        }
    }
}

/// The surface as a 2 cm slab whose top is its plane lowered by `sunk`: its outline's
/// prism.
fn surface_slab(surface: &Surface, sunk: f64) -> Option<SharedShape> {
    let n = surface.plane.normal;
    let offset = surface.centroid.dot(n) - sunk;
    let pts: Vec<Vec3> = surface
        .hull
        .iter()
        .flat_map(|q| {
            let on = *q - n * (q.dot(n) - offset);
            [on, on - n * 0.02]
        })
        .collect();
    SharedShape::convex_hull(&pts)
}

/// Points the head at `at`; a robot without a head looks where it looks.
fn look_at(driver: &mut impl RobotDriver, at: Vec3) -> Result<(), PlaceError> {
    match driver.look_at(at) {
        Ok(_) | Err(DriverError::Unsupported(_)) => Ok(()),
        Err(e) => Err(e.into()),
    }
}

/// The protective sphere (SPEC §1.1) around the first view of the held object (the
/// ball at `centre`, tool frame), cut by the plane the held object cannot reach behind:
/// the palm's front face (`palm_front` along the approach axis), else 3 cm behind the
/// deepest point seen. A whole ball around a long object held at one end reaches back
/// over the wrist, and then no view is free of the arm's own links (the palm and
/// fingers may touch it, the wrist may not).
fn protective_shape(
    first: &[Vec3],
    approach: Vec3,
    palm_front: Option<f64>,
    centre: Vec3,
    radius: f64,
) -> SharedShape {
    let deepest = first
        .iter()
        .map(|q| q.dot(approach))
        .fold(f64::INFINITY, f64::min);
    let cut = match palm_front {
        Some(f) => f,
        None if first.len() >= 10 => deepest - 0.03,
        None => f64::NEG_INFINITY,
    } - centre.dot(approach);
    // No cut through the ball, or one in front of all of it (what was seen lies behind
    // the palm: something is off, keep the whole ball).
    if !cut.is_finite() || cut.abs() >= radius * 0.95 {
        return SharedShape::ball(radius);
    }
    // The ball's points, those behind the plane pressed onto it: their hull holds the
    // ball's part in front of the plane.
    let (u, v) = (
        approach.any_orthonormal_vector(),
        approach.cross(approach.any_orthonormal_vector()),
    );
    let grown = radius / (std::f64::consts::PI / 24.0).cos().powi(2);
    let mut points = Vec::new();
    for i in 0..=12 {
        let polar = std::f64::consts::PI * i as f64 / 12.0;
        for j in 0..24 {
            let azimuth = std::f64::consts::TAU * j as f64 / 24.0;
            let d = approach * polar.cos() + (u * azimuth.cos() + v * azimuth.sin()) * polar.sin();
            // The polygon's chords fall inside the ball: the points are pushed out
            // (`grown`) so the hull holds it.
            let q = d * grown;
            let along = q.dot(approach);
            points.push(q + approach * (cut - along).max(0.0));
        }
    }
    // And the rim where the plane cuts the (grown) ball.
    let rim = (grown * grown - cut * cut).max(0.0).sqrt();
    for j in 0..24 {
        let azimuth = std::f64::consts::TAU * j as f64 / 24.0;
        points
            .push(approach * cut + (u * azimuth.cos() + v * azimuth.sin()) * rim * grown / radius);
    }
    SharedShape::convex_hull(&points).unwrap_or_else(|| SharedShape::ball(radius))
}

/// The front face of a gripper's palm along its approach axis (tool frame): the front
/// of the rearmost of its self-filter boxes (axis-aligned in the tool frame), which
/// nothing the fingers hold can reach behind.
fn palm_front(g: &tabula_robot::description::Gripper) -> Option<f64> {
    let a = g.approach();
    g.self_filter_boxes
        .iter()
        .map(|b| {
            let (c, h) = (Vec3::from_array(b.center), Vec3::from_array(b.size) / 2.0);
            (c.dot(a), c.dot(a) + h.dot(a.abs()))
        })
        .min_by(|x, y| x.0.total_cmp(&y.0))
        .map(|(_, front)| front)
}

/// Whether a failure means "nothing here": worth turning around for.
fn retry_behind(e: &PlaceError) -> bool {
    matches!(
        e,
        PlaceError::NoSurface(_) | PlaceError::NoRoom(_) | PlaceError::Unreachable
    )
}

fn heading(p: &Pose) -> f64 {
    let f = p.rotation * Vec3::X;
    f.y.atan2(f.x)
}

fn heading_vector(p: &Pose) -> Vec3 {
    let h = heading(p);
    Vec3::new(h.cos(), h.sin(), 0.0)
}

/// The gripper at the tip of `arm`.
fn arm_gripper<'r>(
    robot: &'r NamedRobot,
    arm: &str,
) -> Option<&'r tabula_robot::description::Gripper> {
    let name = robot.description.arm(arm).ok()?.gripper.as_ref()?;
    robot.description.grippers.iter().find(|g| &g.name == name)
}

/// The arm whose gripper is closed the most (below 80 % of its opening).
fn holding_arm(robot: &NamedRobot, state: &JointState) -> Option<String> {
    let mut best: Option<(f64, String)> = None;
    for a in &robot.description.arms {
        let Some(g) = arm_gripper(robot, &a.name) else {
            continue;
        };
        let (Some(j), Some(v)) = (
            robot.model.joint(&g.finger_joint),
            state.get(&g.finger_joint),
        ) else {
            continue;
        };
        let l = robot.model.joints[j].limits;
        let open = (v - l.lower) / (l.upper - l.lower).max(1e-9);
        if open < 0.8 && best.as_ref().is_none_or(|(o, _)| open < *o) {
            best = Some((open, a.name.clone()));
        }
    }
    best.map(|(_, n)| n)
}

/// Where the mobile base is (world): the link its planar joints move, or the robot's
/// root when it has no base.
fn world_from_base(robot: &NamedRobot, driver: &impl RobotDriver) -> Result<Pose, PlaceError> {
    let root = driver.world_from_root()?;
    let Some(base) = &robot.description.base else {
        return Ok(root);
    };
    let Some(j) = robot.model.joint(&base.theta_joint) else {
        return Ok(root);
    };
    let state = driver.joint_state()?;
    let fk = robot
        .model
        .forward_kinematics(&state.model_values(&robot.model))
        .map_err(|e| PlaceError::Driver(e.to_string()))?;
    Ok(root * fk[robot.model.joints[j].child])
}

/// The world pose of a link at a joint state.
fn tool_pose(
    robot: &NamedRobot,
    state: &JointState,
    root: Pose,
    link: &str,
) -> Result<Pose, PlaceError> {
    let l = robot
        .model
        .link(link)
        .map_err(|e| PlaceError::Driver(e.to_string()))?;
    let fk = robot
        .model
        .forward_kinematics(&state.model_values(&robot.model))
        .map_err(|e| PlaceError::Driver(e.to_string()))?;
    Ok(root * fk[l])
}

/// The arm's shoulder (the child link of its second joint, else its first) in the
/// world.
fn shoulder_position(
    robot: &NamedRobot,
    arm: &str,
    state: &JointState,
    root: Pose,
) -> Result<Vec3, PlaceError> {
    let group = robot
        .description
        .arm(arm)
        .map_err(|e| PlaceError::Driver(e.to_string()))?;
    let chain = group
        .chain(&robot.model)
        .map_err(|e| PlaceError::Driver(e.to_string()))?;
    let fk = robot
        .model
        .forward_kinematics(&state.model_values(&robot.model))
        .map_err(|e| PlaceError::Driver(e.to_string()))?;
    let j = chain
        .joint_indices
        .get(1)
        .or(chain.joint_indices.first())
        .ok_or(PlaceError::Unreachable)?;
    Ok(root * fk[robot.model.joints[*j].child].translation)
}

/// The shoulder's lateral offset from the base's centre line (m, left positive), at
/// the robot's mid configuration.
fn shoulder_lateral(robot: &NamedRobot, arm: &str) -> f64 {
    let state = JointState {
        names: robot.model.joints.iter().map(|j| j.name.clone()).collect(),
        positions: robot.model.mid_configuration(),
        ..Default::default()
    };
    shoulder_position(robot, arm, &state, Pose::IDENTITY)
        .map(|p| p.y)
        .unwrap_or(0.0)
}

/// Half the base's footprint diagonal extent along its front (m): the base link's
/// collision box, else 0.35.
fn base_half_extent(robot: &NamedRobot) -> f64 {
    robot
        .model
        .link("base_link")
        .ok()
        .and_then(|l| {
            robot.model.links[l]
                .collision
                .iter()
                .find_map(|s| match &s.geometry {
                    tabula_robot::model::Geometry::Box { half_extents } => {
                        Some(half_extents.x.max(half_extents.y))
                    }
                    _ => None,
                })
        })
        .unwrap_or(0.35)
}

/// The robot's forward reach (m, along the base's x from its centre) of every
/// collision shape whose bottom is below `below` (world z).
fn forward_extent(
    robot: &NamedRobot,
    state: &JointState,
    root: Pose,
    base: Pose,
    below: f64,
) -> f64 {
    let Ok(fk) = robot
        .model
        .forward_kinematics(&state.model_values(&robot.model))
    else {
        return 0.0;
    };
    let base_from_world = base.inverse();
    let mut front: f64 = 0.0;
    for (l, link) in robot.model.links.iter().enumerate() {
        for s in &link.collision {
            let Ok((shape, shape_pose)) = s.geometry.collision_shape(false) else {
                continue;
            };
            let world = root * fk[l] * s.link_from_shape * shape_pose;
            if shape.compute_aabb(&world).mins.z >= below {
                continue;
            }
            let x = shape.compute_aabb(&(base_from_world * world)).maxs.x;
            if tracing::enabled!(tracing::Level::DEBUG) && x > 0.4 {
                tracing::debug!("place: link {} reaches {x:.2} m forward", link.name);
            }
            front = front.max(x);
        }
    }
    front
}

/// Points bounding `arm`'s gripper in its tool frame (the corners, edge midpoints and
/// face centres of its self-filter boxes): what must stay clear of a support plane.
pub fn gripper_points(robot: &NamedRobot, arm: &str) -> Vec<Vec3> {
    let Some(g) = arm_gripper(robot, arm) else {
        return vec![Vec3::ZERO];
    };
    let mut out = Vec::new();
    for b in &g.self_filter_boxes {
        let c = Vec3::from_array(b.center);
        let h = Vec3::from_array(b.size) / 2.0;
        for i in 0..27 {
            let s = Vec3::new(
                (i % 3) as f64 - 1.0,
                ((i / 3) % 3) as f64 - 1.0,
                (i / 9) as f64 - 1.0,
            );
            out.push(c + h * s);
        }
    }
    if out.is_empty() {
        out.push(Vec3::ZERO);
    }
    out
}

/// The object's footprint resting in `pose` (yaw 0), relative to the contact centroid.
fn footprint_of(pose: &StablePose, model: &[Vec3]) -> Vec<Vec2> {
    let r = pose.resting_rotation(0.0);
    let c = r * Vec3::from_array(pose.contact_centroid);
    let flat: Vec<Vec2> = model.iter().map(|q| (r * *q - c).truncate()).collect();
    convex_hull_2d(&flat).into_iter().map(|i| flat[i]).collect()
}

/// A surface's plane and outline seen from above (counter-clockwise), built once: the
/// scene's points are tested against it one by one.
struct Outline {
    normal: Vec3,
    offset: f64,
    poly: Vec<Vec2>,
}

impl Outline {
    fn of(surface: &Surface) -> Self {
        let mut poly: Vec<Vec2> = surface.hull.iter().map(|p| p.truncate()).collect();
        if tabula_geom::polygon::polygon_area(&poly) < 0.0 {
            poly.reverse();
        }
        let normal = surface.plane.normal;
        Self {
            normal,
            offset: surface.centroid.dot(normal),
            poly,
        }
    }

    /// Height of `q` above the surface's plane (m).
    fn height(&self, q: Vec3) -> f64 {
        q.dot(self.normal) - self.offset
    }

    /// Whether `q` is over the outline.
    fn over(&self, q: Vec3) -> bool {
        inside_convex(&self.poly, q.truncate())
    }

    /// Horizontal distance from `q` to the outline (0 over it).
    fn distance(&self, q: Vec2) -> f64 {
        if inside_convex(&self.poly, q) {
            0.0
        } else {
            tabula_geom::polygon::distance_to_boundary(&self.poly, q)
        }
    }
}

/// The outline's point nearest `q` and the edge's outward normal there.
fn nearest_edge(poly: &[Vec2], q: Vec2) -> (Vec2, Vec2) {
    let mut p: Vec<Vec2> = poly.to_vec();
    if tabula_geom::polygon::polygon_area(&p) < 0.0 {
        p.reverse();
    }
    let n = p.len();
    let mut best = (f64::INFINITY, q, Vec2::X);
    for i in 0..n {
        let (a, b) = (p[i], p[(i + 1) % n]);
        let ab = b - a;
        let t = if ab.length_squared() > 0.0 {
            ((q - a).dot(ab) / ab.length_squared()).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let c = a + ab * t;
        let d = c.distance(q);
        if d < best.0 {
            // Counter-clockwise: outward is to the right of the edge.
            let out = Vec2::new(ab.y, -ab.x).normalize_or(Vec2::X);
            best = (d, c, out);
        }
    }
    (best.1, best.2)
}

/// Whether the base (its half-width plus 2 cm, as it drives front first) would sweep
/// through seen obstacles (points between 5 cm and 1.5 m high) going straight from
/// `from` to `to`.
fn path_blocked(from: Vec2, to: Vec2, half: f64, scene: &[Vec3]) -> bool {
    let radius = half + 0.02;
    let seg = to - from;
    let len2 = seg.length_squared();
    scene.iter().any(|q| {
        if q.z < 0.05 || q.z > 1.5 {
            return false;
        }
        let p = q.truncate();
        let t = if len2 > 0.0 {
            ((p - from).dot(seg) / len2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        (from + seg * t).distance(p) < radius
    })
}

impl Validate for PlaceParams {
    fn check(&self, at: &str) -> Result<(), String> {
        self.observe.check(&nested(at, "observe"))?;
        self.motion.check(&nested(at, "motion"))?;
        self.stable.check(&nested(at, "stable"))?;
        self.surfaces.check(&nested(at, "surfaces"))?;
        self.free_space.check(&nested(at, "free_space"))?;
        for (name, v) in [
            ("scan_distance", self.scan_distance),
            ("crop_radius", self.crop_radius),
            ("scan_leaf", self.scan_leaf),
            ("search_leaf", self.search_leaf),
            ("search_range", self.search_range),
            ("edge_range", self.edge_range),
            ("reach", self.reach),
            ("approach_desired", self.approach_desired),
            ("retreat_desired", self.retreat_desired),
            ("release_speed", self.release_speed),
        ] {
            check_positive(at, name, v)?;
        }
        for (name, v) in [
            ("scan_drop", self.scan_drop),
            ("refine_converged", self.refine_converged),
            ("grip_reach", self.grip_reach),
            ("protective_radius", self.protective_radius),
            ("gripper_clearance", self.gripper_clearance),
            ("sweep_distance", self.sweep_distance),
            ("sweep_height", self.sweep_height),
            ("standoff", self.standoff),
            ("approach_run", self.approach_run),
            ("release_height", self.release_height),
            ("place_margin", self.place_margin),
            ("approach_min", self.approach_min),
            ("retreat_min", self.retreat_min),
        ] {
            check_non_negative(at, name, v)?;
        }
        check_in(at, "min_topple_deg", self.min_topple_deg, 0.0, 90.0)?;
        check_in(
            at,
            "approach_min",
            self.approach_min,
            0.0,
            self.approach_desired,
        )?;
        check_in(
            at,
            "retreat_min",
            self.retreat_min,
            0.0,
            self.retreat_desired,
        )?;
        check_count(at, "scan_twists", self.scan_twists, 1)?;
        check_count(at, "poses_tried", self.poses_tried, 1)?;
        check_count(at, "search_decimate", self.search_decimate, 1)?;
        check_count(at, "roll_samples", self.roll_samples, 1)?;
        check_count(at, "max_planned", self.max_planned, 1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_protective_shape_holds_the_object_but_not_the_wrist_behind_the_palm() {
        // A 25 cm bottle held by its neck from the side (the tool frame's x is the
        // approach, the fingers close along y), hanging down along −z; the camera saw
        // its front half, the palm against its back 3 cm behind the tool point.
        let first: Vec<Vec3> = (0..=50)
            .flat_map(|i| {
                (0..8).map(move |k| {
                    let a = std::f64::consts::PI * k as f64 / 7.0;
                    Vec3::new(
                        0.005 + 0.035 * a.sin(),
                        0.035 * a.cos(),
                        0.02 - 0.005 * i as f64,
                    )
                })
            })
            .collect();
        let centre = first.iter().copied().sum::<Vec3>() / first.len() as f64;
        let radius = first.iter().map(|q| q.distance(centre)).fold(0.0, f64::max) + 0.03;
        // A PR2's palm: its front face 4.6 cm behind the tool point.
        let g = tabula_robot::robots::load("pr2")
            .unwrap()
            .description
            .grippers[0]
            .clone();
        let front = palm_front(&g).unwrap();
        assert!((front + 0.046).abs() < 1e-9, "{front}");
        let shape = protective_shape(&first, Vec3::X, Some(front), centre, radius);
        let at = Pose::from_translation(centre);
        let inside = |q: Vec3| shape.contains_point(&at, q);
        // All of the ball in front of the cut, the unseen back of the bottle included.
        for q in &first {
            let back = Vec3::new(0.01 - q.x, q.y, q.z);
            assert!(inside(*q) && inside(back), "{q:?}");
        }
        for k in 0..200 {
            let d = Vec3::new(
                (k as f64 * 0.37).sin(),
                (k as f64 * 1.13).cos(),
                (k as f64 * 2.71).sin(),
            )
            .normalize();
            let q = centre + d * radius * 0.999;
            if q.x >= front {
                assert!(inside(q), "{q:?} of the ball in front of the cut");
            }
        }
        // Behind the deepest point seen by more than the margin (where the wrist is),
        // nothing, though the whole ball would reach there.
        assert!(centre.x - radius < -0.12, "{centre:?} {radius}");
        for y in [-0.05, 0.0, 0.05] {
            for x in [-0.05, -0.07, -0.12] {
                assert!(!inside(Vec3::new(x, y, centre.z)), "{x} {y}");
            }
        }
        // No palm known: 3 cm behind the deepest point seen.
        let seen = protective_shape(&first, Vec3::X, None, centre, radius);
        assert!(seen.contains_point(&at, Vec3::new(-0.02, 0.0, centre.z)));
        assert!(!seen.contains_point(&at, Vec3::new(-0.03, 0.0, centre.z)));
        // Nor enough points to know where the object is: the whole ball.
        let ball = protective_shape(&first[..5], Vec3::X, None, centre, radius);
        let back = centre - Vec3::X * radius * 0.99;
        assert!(ball.contains_point(&at, back));
    }
}
