//! Pick and place by coordinates — seed 001's integral test (SPEC §2.5): given the
//! approximate world position of an object and a target position, look at both with
//! the head camera, find the object and the surfaces, choose an arm and a grasp (side
//! or top; shelf boards leave only side grasps), plan every motion — approach, grasp,
//! lift, retreat, transfer, place, release, retreat, home — without touching anything
//! but the object, then execute it through the driver.
//!
//! The shape follows MoveIt Task Constructor's pick/place: the grasp generator proposes
//! candidates, each candidate is planned stage by stage, the first that plans whole is
//! executed, and every stage reports its time and, on failure, why.

use crate::observe::{
    ObserveError, ObserveParams, SeenObject, Support, object_near, robot_solids, support_under,
    voxel_keys, world_points,
};
use crate::skills::hand::tool_rotation;
use std::time::Instant;
use tabula_geom::input::{Validate, check_count, check_non_negative, check_positive, nested};
use tabula_geom::parry::shape::SharedShape;
use tabula_geom::{Pose, Quat, Vec2, Vec3};
use tabula_motion::group::thread_cpu;
use tabula_motion::{CollisionWorld, MoveError, MoveGroup, MoveGroupParams, Plan};
use tabula_robot::driver::{DriverError, RobotDriver};
use tabula_robot::robots::NamedRobot;

/// Parameters of pick and place (SPEC §3.2 and §6 where the seeds give a number).
#[derive(Debug, Clone, serde::Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct PickPlaceParams {
    pub observe: ObserveParams,
    pub motion: MoveGroupParams,
    /// Camera used to look (the robot's head camera in the scene).
    pub camera: String,
    /// Pre-grasp distance back along the approach (m), SPEC §3.2: 10 cm.
    pub pregrasp_distance: f64,
    /// Lift after closing (m): enough to clear the board, not to hit the one above.
    pub lift: f64,
    /// Retreat out of the shelf along the approach after lifting (m).
    pub retreat: f64,
    /// Height of the object's bottom above the surface when released (m), SPEC §6: 8 mm.
    pub release_height: f64,
    /// Distance of the pre-place pose back along the approach (m), SPEC §6: 0.1 m min.
    pub place_approach: f64,
    /// Retreat after opening (m), SPEC §6: 0.1 m min.
    pub place_retreat: f64,
    /// Room left between each open finger and the object (m).
    pub finger_clearance: f64,
    /// The tool point stays at least this far above the support (m): the fingertips
    /// must not scrape the board.
    pub min_grasp_height: f64,
    /// Approach yaws tried within ± this of the direction from the arm to the object
    /// (rad) …
    pub yaw_range: f64,
    /// … this far apart (rad): narrow arms such as Golem-III's reach a level grasp
    /// only in narrow bands of yaw.
    pub yaw_step: f64,
    /// Downward tilts of a side grasp's approach (rad): lower boards need some.
    pub side_tilts: Vec<f64>,
    /// Head pan angles (rad, from the robot's heading) of the sweep that maps the
    /// workspace, SPEC §6: −90°…+90° in 45° steps …
    pub sweep_angles: Vec<f64>,
    /// … looking at points this far out (m) at the working height and at these heights
    /// above it (the arm's motions rise above what a level sweep sees).
    pub sweep_radius: f64,
    pub sweep_rises: Vec<f64>,
    /// Grasps (and, per grasp, placements) planned at most, best first.
    pub max_planned_grasps: usize,
    /// Straight lines into and out of a grasp or a placement may also rise by these
    /// (m): an arm whose level lines are short still gets in and out.
    pub rise_offsets: Vec<f64>,
    /// The grasp point may also sit this far deeper (+) or shallower (−) along the
    /// approach than the object's centre (m).
    pub grasp_depth_offsets: Vec<f64>,
    /// Margin around the object's footprint that must be free at the target (m).
    pub place_margin: f64,
    /// What a full gripper holds is seen up to this far from its tool point (m) …
    pub held_reach: f64,
    /// … and, unseen, is a ball this much wider than the finger gap (m).
    pub held_margin: f64,
}

impl Default for PickPlaceParams {
    fn default() -> Self {
        Self {
            observe: ObserveParams::default(),
            motion: MoveGroupParams {
                cartesian_tolerance: 0.01,
                ..MoveGroupParams::default()
            },
            camera: "head".into(),
            pregrasp_distance: 0.10,
            lift: 0.04,
            retreat: 0.15,
            release_height: 0.008,
            place_approach: 0.10,
            place_retreat: 0.10,
            finger_clearance: 0.01,
            min_grasp_height: 0.035,
            yaw_range: 1.5,
            yaw_step: 0.05,
            side_tilts: vec![0.0, 0.2, 0.4],
            max_planned_grasps: 8,
            sweep_angles: [-90.0f64, -45.0, 0.0, 45.0, 90.0]
                .iter()
                .map(|d| d.to_radians())
                .collect(),
            sweep_radius: 0.8,
            sweep_rises: vec![0.0, 0.45],
            rise_offsets: vec![0.0, 0.03, 0.06, 0.09, 0.12],
            grasp_depth_offsets: vec![0.015, -0.01],
            place_margin: 0.01,
            held_reach: 0.3,
            held_margin: 0.02,
        }
    }
}

/// What to do: an arm (`None`: whichever can), where the object is, where it goes —
/// both approximate world positions (the object's centre; the surfaces are found
/// under them).
#[derive(Debug, Clone)]
pub struct PickPlaceRequest {
    pub arm: Option<String>,
    pub pick: Vec3,
    pub place: Vec3,
}

/// How an object is grasped.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum GraspKind {
    /// Approach horizontal, fingers closing horizontally.
    Side,
    /// Approach from above.
    Top,
}

/// Why a pick and place failed (typed, for `--json`'s `error`).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PickPlaceError {
    #[error("the object was not found: {0}")]
    ObjectNotFound(String),
    #[error("no surface at the target: {0}")]
    NoSurface(String),
    #[error("the target is occupied: {points} points stand there, around ({:.3}, {:.3}, {:.3})", at[0], at[1], at[2])]
    TargetOccupied { points: usize, at: [f64; 3] },
    #[error("the object ({0:.3} m across) is wider than the gripper opens")]
    TooWide(f64),
    #[error("unreachable: no arm reaches a grasp and a placement")]
    Unreachable,
    #[error("no collision-free path: {0}")]
    NoPath(String),
    #[error("grasp slipped: the gripper closed on nothing")]
    GraspSlipped,
    #[error("the {0} arm's gripper already holds something")]
    HandFull(String),
    #[error("robot: {0}")]
    Driver(String),
}

impl PickPlaceError {
    /// The short type name in JSON (`unreachable`, `no collision-free path`, …).
    pub fn kind(&self) -> &'static str {
        match self {
            Self::ObjectNotFound(_) => "object not found",
            Self::NoSurface(_) => "no surface",
            Self::TargetOccupied { .. } => "target occupied",
            Self::TooWide(_) => "too wide",
            Self::Unreachable => "unreachable",
            Self::NoPath(_) => "no collision-free path",
            Self::GraspSlipped => "grasp slipped",
            Self::HandFull(_) => "hand full",
            Self::Driver(_) => "driver",
        }
    }
}

impl From<DriverError> for PickPlaceError {
    fn from(e: DriverError) -> Self {
        Self::Driver(e.to_string())
    }
}

/// One stage: its name, how long it took (planning stages: CPU ms; execution stages:
/// wall-clock ms), whether it succeeded.
#[derive(Debug, Clone, serde::Serialize)]
pub struct Phase {
    pub name: String,
    pub ms: f64,
    pub ok: bool,
    /// For a motion: CPU ms spent planning it.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub plan_ms: Option<f64>,
}

/// The object as perceived.
#[derive(Debug, Clone, serde::Serialize)]
pub struct ObjectReport {
    /// Footprint centre at the object's bottom (world).
    pub position: [f64; 3],
    /// Footprint sides and height (m).
    pub size: [f64; 3],
    pub points: usize,
}

/// What a pick and place did.
#[derive(Debug, Clone, Default, serde::Serialize)]
pub struct PickPlaceReport {
    pub arm: Option<String>,
    pub grasp: Option<GraspKind>,
    pub object: Option<ObjectReport>,
    /// Height of the target surface (m).
    pub target_surface: Option<f64>,
    /// Where the object's bottom centre was planned to be released (world).
    pub planned_object_position: Option<[f64; 3]>,
    pub phases: Vec<Phase>,
    /// CPU ms from the first frame to the last motion plan (perceive → grasp choice →
    /// every plan), not counting the one-off allowed-collision sampling.
    pub decision_cpu_ms: f64,
    /// Grasp candidates planned before one planned whole.
    pub candidates_tried: usize,
    /// Why each rejected candidate failed (arm, grasp, stage, reason), as MoveIt Task
    /// Constructor's stages explain their failures.
    pub rejected: Vec<String>,
    /// Grippers found holding something at the start; it stays held, and planning
    /// carries it with them.
    pub held_elsewhere: Vec<String>,
    /// Every motion executed, in order (for replays and checks).
    #[serde(skip)]
    pub trajectories: Vec<tabula_robot::driver::JointTrajectory>,
}

/// A pick and place's report and, when it failed, why.
#[derive(Debug, Clone)]
pub struct PickPlaceOutcome {
    pub report: PickPlaceReport,
    pub error: Option<PickPlaceError>,
}

/// A grasp: where the tool goes and how it holds the object.
#[derive(Debug, Clone, Copy)]
struct Grasp {
    kind: GraspKind,
    world_from_tool: Pose,
    /// Approach direction (world, unit).
    approach: Vec3,
}

/// Everything planned for one candidate, in execution order.
struct Sequence {
    to_pregrasp: Plan,
    approach: Plan,
    lift: Plan,
    retreat: Plan,
    transfer: Plan,
    place: Plan,
    release_retreat: Plan,
    home: Plan,
    planned_object: Pose,
}

/// The collision world's view of the surroundings: occupancy of everything seen,
/// except the supports under the object and under the target, which are exact slabs at
/// their measured height (seed 000 added the found surface to the planning scene) —
/// so the fingers may pass a centimetre above a board, and the slab can be taken away
/// while the object leaves it or arrives on it.
struct Occupancy {
    scene: Vec<Vec3>,
    pick_support: Option<(SharedShape, Pose)>,
    place_support: Option<(SharedShape, Pose)>,
}

/// A slab whose top is at `z`, under the seen surface points of a column.
fn support_slab(points: &[Vec3], z: f64) -> Option<(SharedShape, Pose)> {
    let near: Vec<Vec2> = points
        .iter()
        .filter(|q| (q.z - z).abs() <= 0.015)
        .map(|q| q.truncate())
        .collect();
    if near.len() < 10 {
        return None;
    }
    let lo = near
        .iter()
        .fold(Vec2::splat(f64::INFINITY), |a, b| a.min(*b));
    let hi = near
        .iter()
        .fold(Vec2::splat(f64::NEG_INFINITY), |a, b| a.max(*b));
    let half = ((hi - lo) / 2.0).max(Vec2::splat(0.005));
    let thickness = 0.02;
    Some((
        SharedShape::cuboid(half.x, half.y, thickness / 2.0),
        Pose::from_translation(((lo + hi) / 2.0).extend(z - thickness / 2.0)),
    ))
}

fn in_column(q: Vec3, center: Vec2, radius: f64, z: f64) -> bool {
    (q.truncate() - center).length() <= radius && q.z >= z - 0.06 && q.z <= z + 0.03
}

/// Runs a pick and place through `driver`.
pub fn pick_place(
    driver: &mut impl RobotDriver,
    robot: &NamedRobot,
    request: &PickPlaceRequest,
    params: &PickPlaceParams,
) -> PickPlaceOutcome {
    let mut report = PickPlaceReport::default();
    let error = run(driver, robot, request, params, &mut report).err();
    PickPlaceOutcome { report, error }
}

fn timed_phase<T>(
    report: &mut PickPlaceReport,
    name: &str,
    cpu: bool,
    f: impl FnOnce() -> Result<T, PickPlaceError>,
) -> Result<T, PickPlaceError> {
    let (t0, c0) = (Instant::now(), thread_cpu());
    let out = f();
    let ms = if cpu {
        (thread_cpu() - c0) * 1e3
    } else {
        t0.elapsed().as_secs_f64() * 1e3
    };
    tracing::info!(phase = name, ms, ok = out.is_ok(), "pick-place");
    report.phases.push(Phase {
        name: name.into(),
        ms,
        ok: out.is_ok(),
        plan_ms: None,
    });
    out
}

fn run(
    driver: &mut impl RobotDriver,
    robot: &NamedRobot,
    request: &PickPlaceRequest,
    params: &PickPlaceParams,
    report: &mut PickPlaceReport,
) -> Result<(), PickPlaceError> {
    if !(request.pick.is_finite() && request.place.is_finite()) {
        return Err(PickPlaceError::ObjectNotFound(
            "positions must be finite".into(),
        ));
    }
    let obs = &params.observe;
    // ---- Hands that already hold something stay closed, pick nothing, and what they
    // hold is carried in the planning scene (with a shared torso joint it turns too).
    let mut full = Vec::new();
    for g in &robot.description.grippers {
        if driver.grip_state(&g.name)?.holding {
            full.push(g.clone());
        }
    }
    let holding = |g: &tabula_robot::description::Gripper| full.iter().any(|f| f.name == g.name);
    if let Some(a) = &request.arm {
        let group = robot
            .description
            .arm(a)
            .map_err(|e| PickPlaceError::Driver(e.to_string()))?;
        if robot.description.gripper_of(group).is_some_and(holding) {
            return Err(PickPlaceError::HandFull(a.clone()));
        }
    }
    // ---- Look at the object and at the target with the head camera.
    let mut points = Vec::new();
    // The camera each point was seen from (to give surfaces thickness behind them).
    let mut origins = Vec::new();
    let mut decision_cpu = 0.0;
    // The object and the target at the perception leaf, then a sweep of the head over
    // the arm's working height at the collision voxel's resolution (seed 000 swept its
    // head too): the motions between pass through space the camera must have seen, or
    // the planner would take unseen furniture for free space.
    let height = (request.pick.z + request.place.z) / 2.0;
    let state = driver.joint_state()?;
    let root = driver.world_from_root()?;
    let sweep_center = root.translation;
    let mut looks = vec![
        ("look at object".to_string(), request.pick, obs.leaf),
        ("look at target".to_string(), request.place, obs.leaf),
    ];
    if robot.description.head.is_some() {
        let heading = {
            let f = root.rotation * Vec3::X;
            f.y.atan2(f.x)
        };
        for &rise in &params.sweep_rises {
            for &a in &params.sweep_angles {
                let dir = Vec3::new((heading + a).cos(), (heading + a).sin(), 0.0);
                let at = Vec3::new(sweep_center.x, sweep_center.y, height + rise)
                    + dir * params.sweep_radius;
                looks.push((
                    format!("sweep {:+.0}° {:+.2} m", a.to_degrees(), rise),
                    at,
                    obs.voxel / 2.0,
                ));
            }
        }
    }
    let _ = state;
    for (k, (name, at, leaf)) in looks.into_iter().enumerate() {
        if k == 1 {
            // The head has looked at the object: a moment for the record.
            driver.annotate("looked at the object");
        }
        timed_phase(report, &name, false, || {
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
            let seen = world_points(&frame, &solids, obs, leaf);
            origins.extend(std::iter::repeat_n(
                frame.world_from_camera.translation,
                seen.len(),
            ));
            points.extend(seen);
            decision_cpu += thread_cpu() - c0;
            Ok(())
        })?;
    }
    let decision_start = thread_cpu();
    let trace = tracing::enabled!(tracing::Level::DEBUG);
    let mark = |what: &str| {
        if trace {
            tracing::debug!("{:>9.1} ms  {what}", (thread_cpu() - decision_start) * 1e3);
        }
    };
    // ---- What the other hands hold moves with them: it is carried in the planning
    // scene, not left in it as an obstacle.
    let held_elsewhere = held_in_grippers(
        robot,
        &full,
        &driver.joint_state()?,
        driver.world_from_root()?,
        &mut points,
        &mut origins,
        params,
    );
    for h in &held_elsewhere {
        report.held_elsewhere.push(h.gripper.name.clone());
        mark(&format!(
            "{} holds something ({} points seen)",
            h.gripper.name, h.points
        ));
    }
    // ---- The object, the target surface, the occupancy around them.
    let object = timed_phase(report, "perceive object", true, || {
        object_near(&points, request.pick, obs).map_err(|e| match e {
            ObserveError::NoSurface(..) | ObserveError::NoObject(..) => {
                PickPlaceError::ObjectNotFound(e.to_string())
            }
        })
    })?;
    let world_from_object = object.world_from_object();
    report.object = Some(ObjectReport {
        position: world_from_object.translation.to_array(),
        size: [
            object.footprint.size.x,
            object.footprint.size.y,
            object.height(),
        ],
        points: object.points.len(),
    });
    let object_keys = voxel_keys(&object.points, obs.cluster_gap);
    // A box around the object first: most points are nowhere near it.
    let (lo, hi) = tabula_geom::bounds(&object.points);
    let (lo, hi) = (
        lo - Vec3::splat(2.0 * obs.cluster_gap),
        hi + Vec3::splat(2.0 * obs.cluster_gap),
    );
    let near_object = |q: &Vec3| {
        if q.cmplt(lo).any() || q.cmpgt(hi).any() {
            return false;
        }
        let k = tabula_geom::voxel_key(*q, obs.cluster_gap);
        (-1..=1).any(|dx| {
            (-1..=1).any(|dy| {
                (-1..=1).any(|dz| object_keys.contains(&[k[0] + dx, k[1] + dy, k[2] + dz]))
            })
        })
    };
    let others: Vec<Vec3> = points.iter().copied().filter(|q| !near_object(q)).collect();
    // What stands behind a seen surface is solid for a few centimetres: a shelf's side
    // panel seen only by its front edge, a board seen from above, are thick.
    // Occupancy needs no more than a few points per voxel: thin them first (the views
    // overlap, and the perception leaf is finer than the collision voxel).
    let mut keep = rustc_hash::FxHashSet::default();
    let cell = obs.voxel / 2.0;
    let solid: Vec<Vec3> = points
        .iter()
        .zip(&origins)
        .filter(|(q, _)| keep.insert(tabula_geom::voxel_key(**q, cell)) && !near_object(q))
        .flat_map(|(q, o)| {
            let ray = (*q - *o).normalize_or(Vec3::ZERO);
            obs.thickness_steps(*q, ray)
        })
        .collect();
    let support = timed_phase(report, "perceive target", true, || {
        let s = support_under(&others, request.place, request.place.z + 0.03, obs).ok_or_else(
            || {
                PickPlaceError::NoSurface(format!(
                    "nothing horizontal under ({:.3}, {:.3}, {:.3})",
                    request.place.x, request.place.y, request.place.z
                ))
            },
        )?;
        // Free: nothing stands within the object's footprint (and margin) there.
        let radius = object.footprint.size.length() / 2.0 + params.place_margin;
        let blocking: Vec<Vec3> = others
            .iter()
            .copied()
            .filter(|q| {
                (q.truncate() - request.place.truncate()).length() <= radius
                    && q.z > s.z + obs.object_clearance + 0.01
                    && q.z < s.z + object.height()
            })
            .collect();
        if blocking.len() >= obs.min_object_points / 2 {
            let c = blocking.iter().sum::<Vec3>() / blocking.len() as f64;
            return Err(PickPlaceError::TargetOccupied {
                points: blocking.len(),
                at: c.to_array(),
            });
        }
        Ok(s)
    })?;
    report.target_surface = Some(support.z);
    mark("perceived");
    let column_radius = object.footprint.size.length() / 2.0 + 0.04;
    let pick_xy = object.footprint.center;
    let place_xy = request.place.truncate();
    let in_pick = |q: &Vec3| in_column(*q, pick_xy, column_radius, object.bottom);
    let in_place = |q: &Vec3| in_column(*q, place_xy, column_radius, support.z);
    let pick_column: Vec<Vec3> = others.iter().copied().filter(|q| in_pick(q)).collect();
    let place_column: Vec<Vec3> = others
        .iter()
        .copied()
        .filter(|q| in_place(q) && !in_pick(q))
        .collect();
    mark(&format!("{} solid points", solid.len()));
    let occupancy = Occupancy {
        scene: solid
            .iter()
            .copied()
            .filter(|q| !in_pick(q) && !in_place(q))
            .collect(),
        pick_support: support_slab(&pick_column, object.bottom),
        place_support: support_slab(&place_column, support.z),
    };
    // ---- Arms to try, nearest first. Plans are made with every empty gripper open, as
    // it will be (it opens before the first motion); a full one stays closed.
    let mut state = driver.joint_state()?;
    for g in robot.description.grippers.iter().filter(|g| !holding(g)) {
        if let (Some(j), Some(i)) = (
            robot.model.joint(&g.finger_joint),
            state.names.iter().position(|n| *n == g.finger_joint),
        ) {
            state.positions[i] = robot.model.joints[j].limits.upper;
        }
    }
    let world_from_root = driver.world_from_root()?;
    let arms: Vec<String> = match &request.arm {
        Some(a) => vec![a.clone()],
        None => {
            let mut v: Vec<(f64, String)> = robot
                .description
                .arms
                .iter()
                .filter(|a| robot.description.gripper_of(a).is_some_and(|g| !holding(g)))
                .filter_map(|a| {
                    let chain = a.chain(&robot.model).ok()?;
                    let fk = robot
                        .model
                        .forward_kinematics(&state.model_values(&robot.model))
                        .ok()?;
                    let first = chain.joint_indices.get(1).or(chain.joint_indices.first())?;
                    let shoulder =
                        world_from_root * fk[robot.model.joints[*first].child].translation;
                    Some(((shoulder - request.pick).length(), a.name.clone()))
                })
                .collect();
            v.sort_by(|a, b| a.0.total_cmp(&b.0));
            v.into_iter().map(|(_, n)| n).collect()
        }
    };
    // The allowed-collision matrix is sampled once per robot (MoveIt keeps it in the
    // SRDF); it is setup, not part of a decision.
    let c0 = thread_cpu();
    let first = arms.first().ok_or(PickPlaceError::Unreachable)?;
    let mut template = MoveGroup::new(robot, first, &state, world_from_root, params.motion.clone())
        .map_err(|e| PickPlaceError::Driver(e.to_string()))?;
    for (k, h) in held_elsewhere.iter().enumerate() {
        template
            .attach_to_gripper(
                &h.gripper,
                &format!("held {k}"),
                h.shape.clone(),
                Pose::IDENTITY,
            )
            .map_err(motion_error)?;
    }
    let setup_cpu = thread_cpu() - c0;
    mark("allowed collisions sampled");
    add_occupancy(&mut template.world, &occupancy, obs.voxel)
        .map_err(|e| PickPlaceError::Driver(e.to_string()))?;
    mark("move group");
    let mut last_error = PickPlaceError::Unreachable;
    let mut chosen: Option<(MoveGroup, Sequence, GraspKind)> = None;
    'arms: for arm in &arms {
        let mut group = match template.for_arm(robot, arm) {
            Ok(g) => g,
            Err(e) => {
                last_error = PickPlaceError::Driver(e.to_string());
                continue;
            }
        };
        let Some(gripper) = group.gripper.clone() else {
            continue;
        };
        let start = group.arm_values(&state);
        let candidates = grasp_candidates(
            &group,
            &object,
            &support,
            request,
            &start,
            params,
            gripper.open_width,
        )?;
        mark(&format!("{} grasp candidates for {arm}", candidates.len()));
        for grasp in candidates {
            report.candidates_tried += 1;
            let mut stage = "";
            let full = group.world.clone();
            let planned = plan_sequence(
                &mut group, &full, &object, &support, request, &grasp, &start, params, &mut stage,
            );
            group.world = full;
            match planned {
                Ok(seq) => {
                    chosen = Some((group, seq, grasp.kind));
                    break 'arms;
                }
                Err(e) => {
                    mark(&format!("candidate failed at {stage}"));
                    let a = grasp.approach;
                    report.rejected.push(format!(
                        "{arm} {:?} approach ({:.2}, {:.2}, {:.2}) at {stage}: {e}",
                        grasp.kind, a.x, a.y, a.z
                    ));
                    // Keep the most telling failure: a path problem beats "unreachable".
                    if !matches!(e, PickPlaceError::Unreachable)
                        || matches!(last_error, PickPlaceError::Unreachable)
                    {
                        last_error = e;
                    }
                }
            }
        }
    }
    let decision = thread_cpu() - decision_start - setup_cpu + decision_cpu;
    report.decision_cpu_ms = decision * 1e3;
    report.phases.push(Phase {
        name: "plan".into(),
        ms: report.decision_cpu_ms,
        ok: chosen.is_some(),
        plan_ms: None,
    });
    mark("planned");
    let (group, seq, kind) = chosen.ok_or(last_error)?;
    report.arm = Some(group.arm.name.clone());
    report.grasp = Some(kind);
    report.planned_object_position = Some(seq.planned_object.translation.to_array());
    let gripper = group.gripper.clone().ok_or(PickPlaceError::Unreachable)?;
    // ---- Execute.
    let exec = |report: &mut PickPlaceReport,
                name: &str,
                plan: &Plan,
                d: &mut dyn FnMut(
        &tabula_robot::driver::JointTrajectory,
    ) -> Result<(), DriverError>| {
        report.trajectories.push(plan.trajectory.clone());
        if trace {
            tracing::debug!(
                "phase {name}: {:.2} s of motion",
                plan.trajectory.duration()
            );
        }
        let out = timed_phase(report, name, false, || Ok(d(&plan.trajectory)?));
        if let Some(p) = report.phases.last_mut() {
            p.plan_ms = Some(plan.planning_time * 1e3);
        }
        out
    };
    for g in robot.description.grippers.iter().filter(|g| !holding(g)) {
        driver.open(&g.name)?;
    }
    exec(report, "move to pre-grasp", &seq.to_pregrasp, &mut |t| {
        driver.execute(t)
    })?;
    exec(report, "approach", &seq.approach, &mut |t| {
        driver.execute(t)
    })?;
    let grip = timed_phase(report, "grasp", false, || Ok(driver.close(&gripper.name)?))?;
    if !grip.holding {
        if let Some(p) = report.phases.last_mut() {
            p.ok = false;
        }
        driver.open(&gripper.name)?;
        return Err(PickPlaceError::GraspSlipped);
    }
    exec(report, "lift", &seq.lift, &mut |t| driver.execute(t))?;
    exec(report, "retreat", &seq.retreat, &mut |t| driver.execute(t))?;
    exec(report, "transfer", &seq.transfer, &mut |t| {
        driver.execute(t)
    })?;
    exec(report, "place", &seq.place, &mut |t| driver.execute(t))?;
    timed_phase(report, "release", false, || Ok(driver.open(&gripper.name)?))?;
    exec(
        report,
        "retreat from object",
        &seq.release_retreat,
        &mut |t| driver.execute(t),
    )?;
    exec(report, "return", &seq.home, &mut |t| driver.execute(t))?;
    Ok(())
}

/// Something a gripper holds, as the planning scene carries it.
struct HeldElsewhere {
    gripper: tabula_robot::description::Gripper,
    /// In the tool frame.
    shape: SharedShape,
    /// Points the camera saw of it.
    points: usize,
}

/// What the grippers in `full` hold, as the camera saw it: the points between the
/// fingers and everything joined to them (neighbours within the cluster gap) up to
/// `held_reach` from the tool point. Those points leave `points` (and `origins`): they
/// move with the hand, they are not scene. Unseen, the held thing is a ball a little
/// wider than the finger gap.
fn held_in_grippers(
    robot: &NamedRobot,
    full: &[tabula_robot::description::Gripper],
    state: &tabula_robot::driver::JointState,
    world_from_root: Pose,
    points: &mut Vec<Vec3>,
    origins: &mut Vec<Vec3>,
    params: &PickPlaceParams,
) -> Vec<HeldElsewhere> {
    let values = state.model_values(&robot.model);
    let Ok(fk) = robot.model.forward_kinematics(&values) else {
        return Vec::new();
    };
    let gap = params.observe.cluster_gap;
    let mut held = Vec::new();
    for g in full {
        let (Some(j), Some(tool)) = (
            robot.model.joint(&g.finger_joint),
            robot.model.link(&g.tool_link).ok(),
        ) else {
            continue;
        };
        let width = g.width_at(&robot.model, values[j]);
        let world_from_tool = world_from_root * fk[tool];
        let tool_from_world = world_from_tool.inverse();
        let (approach, closing) = (g.approach(), g.closing());
        let third = approach.cross(closing);
        let near: Vec<usize> = (0..points.len())
            .filter(|&i| points[i].distance(world_from_tool.translation) <= params.held_reach)
            .collect();
        // Flood the occupied cells from those between the fingertips.
        let cell_of = |q: Vec3| tabula_geom::voxel_key(q, gap);
        let cells: rustc_hash::FxHashSet<[i64; 3]> =
            near.iter().map(|&i| cell_of(points[i])).collect();
        let mut reached: rustc_hash::FxHashSet<[i64; 3]> = near
            .iter()
            .map(|&i| points[i])
            .filter(|q| {
                let t = tool_from_world * *q;
                t.dot(closing).abs() <= width / 2.0 + gap
                    && t.dot(approach).abs() <= 0.03
                    && t.dot(third).abs() <= 0.03
            })
            .map(cell_of)
            .collect();
        let mut frontier: Vec<[i64; 3]> = reached.iter().copied().collect();
        while let Some(c) = frontier.pop() {
            for dx in -1..=1 {
                for dy in -1..=1 {
                    for dz in -1..=1 {
                        let n = [c[0] + dx, c[1] + dy, c[2] + dz];
                        if cells.contains(&n) && reached.insert(n) {
                            frontier.push(n);
                        }
                    }
                }
            }
        }
        let mine: rustc_hash::FxHashSet<usize> = near
            .into_iter()
            .filter(|&i| reached.contains(&cell_of(points[i])))
            .collect();
        let in_tool: Vec<Vec3> = mine.iter().map(|&i| tool_from_world * points[i]).collect();
        let hull = (in_tool.len() >= 10)
            .then(|| SharedShape::convex_hull(&in_tool))
            .flatten();
        let shape = hull.unwrap_or_else(|| SharedShape::ball(width / 2.0 + params.held_margin));
        let (kept, kept_origins): (Vec<Vec3>, Vec<Vec3>) = points
            .iter()
            .zip(origins.iter())
            .enumerate()
            .filter(|(i, _)| !mine.contains(i))
            .map(|(_, (p, o))| (*p, *o))
            .unzip();
        *points = kept;
        *origins = kept_origins;
        held.push(HeldElsewhere {
            gripper: g.clone(),
            shape,
            points: in_tool.len(),
        });
    }
    held
}

fn add_occupancy(world: &mut CollisionWorld, o: &Occupancy, voxel: f64) -> Result<(), MoveError> {
    world.add_occupancy("scene", &o.scene, voxel)?;
    // Absent slabs are empty placeholders, so stages can always remove them by name.
    let nothing = || {
        (
            SharedShape::ball(1e-6),
            Pose::from_translation(Vec3::splat(1e6)),
        )
    };
    for (name, slab) in [
        ("pick_support", &o.pick_support),
        ("place_support", &o.place_support),
    ] {
        let (shape, pose) = slab.clone().unwrap_or_else(nothing);
        world.add_object(name, shape, pose)?;
    }
    Ok(())
}

/// Grasps worth planning, best first: side grasps (the approach level or tilted down a
/// little, around the direction from the arm to the object), then top grasps; each only
/// if the object fits between the open fingers and the arm's IK reaches both the grasp
/// and the pre-grasp. IK is cheap next to planning (microseconds for an analytic
/// solver), so many are tried and only the best few planned.
fn grasp_candidates(
    group: &MoveGroup,
    object: &SeenObject,
    support: &Support,
    request: &PickPlaceRequest,
    start: &[f64],
    params: &PickPlaceParams,
    open_width: f64,
) -> Result<Vec<Grasp>, PickPlaceError> {
    let Some(g) = group.gripper.as_ref() else {
        return Ok(Vec::new());
    };
    let base = group
        .world
        .world_from_chain_base()
        .map_err(|e| PickPlaceError::Driver(e.to_string()))?;
    let c = object.footprint.center;
    let toward = c - base.translation.truncate();
    let facing = toward.y.atan2(toward.x);
    let fits =
        |closing: Vec2| object.width_along(closing) + 2.0 * params.finger_clearance <= open_width;
    let h = object.height();
    let side_z = object.bottom + (h / 2.0).max(params.min_grasp_height);
    let top_z = object.bottom + (h - 0.03).max(params.min_grasp_height);
    let mut scored: Vec<(f64, Grasp)> = Vec::new();
    let mut narrowest = f64::INFINITY;
    let steps = (params.yaw_range / params.yaw_step.max(1e-3)).ceil() as i64;
    for k in -steps..=steps {
        let yaw = facing + k as f64 * params.yaw_step;
        let closing = Vec2::new(-yaw.sin(), yaw.cos());
        narrowest = narrowest.min(object.width_along(closing));
        if !fits(closing) {
            continue;
        }
        let c3 = closing.extend(0.0);
        for (kind, tilt, z) in params
            .side_tilts
            .iter()
            .map(|&t| (GraspKind::Side, t, side_z))
            .chain(std::iter::once((
                GraspKind::Top,
                std::f64::consts::FRAC_PI_2,
                top_z,
            )))
        {
            let a = Vec3::new(yaw.cos() * tilt.cos(), yaw.sin() * tilt.cos(), -tilt.sin());
            let r = tool_rotation(g.approach(), g.closing(), a, c3);
            // The grasp point may sit a little deeper or shallower, higher or lower on
            // the object: an arm with few joints reaches some of these and not others.
            for (depth, rise) in grasp_offsets(kind, h, params) {
                let grasp = Grasp {
                    kind,
                    world_from_tool: Pose::from_parts(c.extend(z) + a * depth + Vec3::Z * rise, r),
                    approach: a,
                };
                let some_pre = pregrasp_offsets(&grasp, params).into_iter().any(|back| {
                    let pre = Pose::from_parts(grasp.world_from_tool.translation + back, r);
                    group.ik(&pre, start).is_ok()
                });
                if group.ik(&grasp.world_from_tool, start).is_err() || !some_pre {
                    continue;
                }
                // And somewhere to put it down, holding it so.
                if placements(group, object, support, request, &grasp, start, params).is_empty() {
                    continue;
                }
                let score = k.unsigned_abs() as f64 * params.yaw_step
                    + tilt
                    + 2.0 * (depth.abs() + rise.abs())
                    + if kind == GraspKind::Top { 0.5 } else { 0.0 };
                scored.push((score, grasp));
            }
        }
    }
    if scored.is_empty() && narrowest + 2.0 * params.finger_clearance > open_width {
        return Err(PickPlaceError::TooWide(narrowest));
    }
    scored.sort_by(|a, b| a.0.total_cmp(&b.0));
    Ok(scored
        .into_iter()
        .take(params.max_planned_grasps)
        .map(|(_, g)| g)
        .collect())
}

/// Offsets (along the approach, up) of the grasp point from the object's centre line.
fn grasp_offsets(kind: GraspKind, height: f64, params: &PickPlaceParams) -> Vec<(f64, f64)> {
    let mut out = vec![(0.0, 0.0)];
    for &d in &params.grasp_depth_offsets {
        out.push((d, 0.0));
    }
    if kind == GraspKind::Side && height > 2.0 * params.min_grasp_height + 0.03 {
        for &d in &[
            0.0,
            params.grasp_depth_offsets.first().copied().unwrap_or(0.0),
        ] {
            out.push((d, 0.015));
            out.push((d, -0.015));
        }
    }
    out
}

/// Poses where the held object can be put down (and the tool poses that do it), each
/// with IK, nearest the direction facing the target first: `(rank, world_from_object,
/// world_from_tool, level approach)`.
fn placements(
    group: &MoveGroup,
    object: &SeenObject,
    support: &Support,
    request: &PickPlaceRequest,
    grasp: &Grasp,
    seed: &[f64],
    params: &PickPlaceParams,
) -> Vec<(u64, Pose, Pose, Vec3)> {
    let Ok(base) = group.world.world_from_chain_base() else {
        return Vec::new();
    };
    let world_from_object = object.world_from_object();
    let tool_from_object = grasp.world_from_tool.inverse() * world_from_object;
    let toward = request.place.truncate() - base.translation.truncate();
    let facing = toward.y.atan2(toward.x);
    let current_yaw = grasp.approach.y.atan2(grasp.approach.x);
    let steps = (params.yaw_range / params.yaw_step.max(1e-3)).ceil() as i64;
    let mut out = Vec::new();
    for k in -steps..=steps {
        // Side grasps turn the held object about the vertical with the approach; top
        // grasps may turn it freely.
        let turn = match grasp.kind {
            GraspKind::Side => {
                tabula_geom::wrap_angle(facing + k as f64 * params.yaw_step - current_yaw)
            }
            GraspKind::Top => k as f64 * params.yaw_step,
        };
        let spin = Quat::from_rotation_z(turn);
        let placed_object = Pose::from_parts(
            Vec3::new(
                request.place.x,
                request.place.y,
                support.z + params.release_height,
            ),
            spin * world_from_object.rotation,
        );
        let place_tool = placed_object * tool_from_object.inverse();
        if group.ik(&place_tool, seed).is_err() {
            continue;
        }
        let a = spin * grasp.approach;
        out.push((
            k.unsigned_abs(),
            placed_object,
            place_tool,
            Vec3::new(a.x, a.y, 0.0).normalize_or(Vec3::X),
        ));
    }
    out.sort_by_key(|p| p.0);
    out
}

/// Straight lines out of a pose: `back` along the level approach and up by each rise
/// offset; a top grasp backs straight up. Arms like Golem-III's reach few level lines,
/// so lines that also rise are tried.
fn lines_out(kind: GraspKind, level: Vec3, backs: &[f64], params: &PickPlaceParams) -> Vec<Vec3> {
    let mut v = Vec::new();
    for &b in backs {
        for &r in &params.rise_offsets {
            v.push(match kind {
                GraspKind::Side => -level * b + Vec3::Z * r,
                GraspKind::Top => Vec3::Z * (b + r),
            });
        }
    }
    v
}

/// Where a pre-grasp may be relative to the grasp: straight back along the tool's own
/// approach axis (SPEC §3.2's 10 cm, or less of it — MoveIt Task Constructor's approach
/// takes a minimum and a desired distance), then the level and rising alternatives.
fn pregrasp_offsets(grasp: &Grasp, params: &PickPlaceParams) -> Vec<Vec3> {
    let level = Vec3::new(grasp.approach.x, grasp.approach.y, 0.0).normalize_or(Vec3::X);
    [1.0, 0.7, 0.5, 0.3]
        .iter()
        .map(|f| -grasp.approach * params.pregrasp_distance * f)
        .chain(lines_out(
            grasp.kind,
            level,
            &[params.pregrasp_distance, 0.0],
            params,
        ))
        .filter(|o| o.length() >= 0.025)
        .collect()
}

fn motion_error(e: MoveError) -> PickPlaceError {
    match e {
        MoveError::Unreachable => PickPlaceError::Unreachable,
        MoveError::GoalInCollision(why) => {
            PickPlaceError::NoPath(format!("every IK solution collides: {why}"))
        }
        other => PickPlaceError::NoPath(other.to_string()),
    }
}

/// Plans every stage of one grasp candidate; `full` is the group's whole world (the
/// stages plan in variants of it and leave the group's world changed); `stage` names
/// the stage being planned (the failing one on error).
#[allow(clippy::too_many_arguments)]
fn plan_sequence(
    group: &mut MoveGroup,
    full: &CollisionWorld,
    object: &SeenObject,
    support: &Support,
    request: &PickPlaceRequest,
    grasp: &Grasp,
    start: &[f64],
    params: &PickPlaceParams,
    stage: &mut &'static str,
) -> Result<Sequence, PickPlaceError> {
    let world_from_object = object.world_from_object();
    let (shape, object_from_shape) = object.collision_shape();
    let up = Vec3::Z;
    let shifted = |p: &Pose, d: Vec3| Pose::from_parts(p.translation + d, p.rotation);
    let level_of = |a: Vec3| Vec3::new(a.x, a.y, 0.0).normalize_or(Vec3::X);
    let driver_err = |e: tabula_motion::WorldError| PickPlaceError::Driver(e.to_string());
    // Straight lines out of (or into) a pose: `back` along the level approach and
    // `rise` up, for each rise offset; a top grasp backs straight up. Arms like
    // Golem-III's reach few level lines, so lines that also rise are tried.
    let lines = |kind: GraspKind, level: Vec3, backs: &[f64]| lines_out(kind, level, backs, params);
    let level = level_of(grasp.approach);
    // Worlds of the stages.
    // While the hand is at the object (approaching, backing away) it may touch it, but
    // not sweep through it: the object's core, shrunk by the padding and a few mm.
    let core_margin = group.world.params.padding + 0.004;
    let (core, core_offset) = object.shrunk_shape(core_margin);
    let mut touching_target = full.clone();
    touching_target
        .add_object("target core", core.clone(), world_from_object * core_offset)
        .map_err(driver_err)?;
    let mut with_target = full.clone();
    with_target
        .add_object(
            "target",
            shape.clone(),
            world_from_object * object_from_shape,
        )
        .map_err(driver_err)?;
    let mut without_pick_support = full.clone();
    without_pick_support
        .remove_object("pick_support")
        .map_err(driver_err)?;
    let tool_from_object = grasp.world_from_tool.inverse() * world_from_object;
    let holding = |group: &mut MoveGroup, world: &CollisionWorld| -> Result<(), PickPlaceError> {
        group.world = world.clone();
        group
            .attach(
                "target",
                shape.clone(),
                tool_from_object * object_from_shape,
            )
            .map_err(motion_error)
    };
    // 1–2. A pre-grasp whose straight approach works (the hand may touch the object
    // on the way in), then a path to it that avoids the object.
    *stage = "approach";
    let mut found = None;
    let mut last = PickPlaceError::Unreachable;
    'pre: for offset in pregrasp_offsets(grasp, params) {
        let pregrasp = shifted(&grasp.world_from_tool, offset);
        group.world = with_target.clone();
        let Ok(goals) = group.valid_ik(&pregrasp, start) else {
            continue;
        };
        for q_pre in goals.into_iter().take(3) {
            group.world = touching_target.clone();
            let approach = match group.cartesian(&q_pre, &grasp.world_from_tool) {
                Ok(a) => a,
                Err(e) => {
                    last = motion_error(e);
                    continue;
                }
            };
            group.world = with_target.clone();
            *stage = "move to pre-grasp";
            match group.plan_to_joints(start, &[q_pre]) {
                Ok(to) => {
                    found = Some((to, approach));
                    break 'pre;
                }
                Err(e) => last = motion_error(e),
            }
            *stage = "approach";
        }
    }
    let (to_pregrasp, approach) = found.ok_or(last)?;
    // 3. Lift the object off its support (backing out a little as it rises is fine).
    *stage = "lift";
    holding(group, &without_pick_support)?;
    let mut lifted_plan = Err(PickPlaceError::Unreachable);
    for back in [0.0, 0.02, 0.04] {
        let lifted = shifted(&grasp.world_from_tool, up * params.lift - level * back);
        lifted_plan = group
            .cartesian(approach.end(), &lifted)
            .map_err(motion_error);
        if lifted_plan.is_ok() {
            break;
        }
    }
    let lift = lifted_plan?;
    // 4. Retreat out of the shelf (side) or further up (top); the transfer's planner
    // takes it from there.
    *stage = "retreat";
    let lifted_pose = group.tip_pose(lift.end()).map_err(motion_error)?;
    // With the object lifted clear of its support, the support is an obstacle again.
    holding(group, full)?;
    let mut retreat_plan = None;
    for offset in lines(
        grasp.kind,
        level,
        &[params.retreat, params.retreat / 2.0, 0.0],
    ) {
        if offset.length() < 0.03 {
            continue;
        }
        if let Ok(p) = group.cartesian(lift.end(), &shifted(&lifted_pose, offset)) {
            retreat_plan = Some(p);
            break;
        }
    }
    // No line out: the transfer's planner starts where the lift ended.
    let retreat =
        retreat_plan.unwrap_or_else(|| group.timed(lift.end(), vec![lift.end().to_vec()], 0.0));
    // 5. Placements reachable by IK, nearest the direction facing the target first.
    *stage = "placement IK";
    let placements = placements(
        group,
        object,
        support,
        request,
        grasp,
        retreat.end(),
        params,
    );
    let mut without_both = without_pick_support.clone();
    without_both
        .remove_object("place_support")
        .map_err(driver_err)?;
    let mut last = PickPlaceError::Unreachable;
    let mut planned = 0;
    for (_, placed_object, place_tool, place_level) in placements {
        if planned >= params.max_planned_grasps {
            break;
        }
        // 6. A pre-place whose straight line down onto the target works; then the
        // transfer to it.
        *stage = "place";
        let mut place_found = None;
        let mut after = without_pick_support.clone();
        after
            .add_object("placed", shape.clone(), placed_object * object_from_shape)
            .map_err(driver_err)?;
        let mut counted = false;
        'pp: for offset in lines(grasp.kind, place_level, &[params.place_approach, 0.0]) {
            if offset.z < 0.0 || offset.length() < 0.05 {
                continue;
            }
            let pre_place = shifted(&place_tool, offset);
            holding(group, &without_pick_support)?;
            let Ok(goals) = group.valid_ik(&pre_place, retreat.end()) else {
                continue;
            };
            counted = true;
            for q_pp in goals.into_iter().take(2) {
                // The line down onto the target, holding the object.
                holding(group, &without_both)?;
                let place = match group.cartesian(&q_pp, &place_tool) {
                    Ok(p) => p,
                    Err(e) => {
                        last = motion_error(e);
                        continue;
                    }
                };
                // 7. Released, the hand backs away far enough that the placed object
                // is an obstacle again.
                *stage = "retreat from object";
                group.world = without_both.clone();
                group
                    .add_object("placed core", core.clone(), placed_object * core_offset)
                    .map_err(motion_error)?;
                // Straight back, back and up, or (side placements) straight up past the
                // object's top with the fingers open around it.
                let back = lines(
                    grasp.kind,
                    place_level,
                    &[params.place_retreat, params.place_retreat / 2.0, 0.0],
                )
                .into_iter()
                .filter(|o| o.z >= 0.0 && o.length() >= 0.03)
                .find_map(|o| {
                    group
                        .cartesian(place.end(), &shifted(&place_tool, o))
                        .ok()
                        .filter(|p| after.is_valid(p.end()))
                });
                let Some(release_retreat) = back else {
                    last = PickPlaceError::NoPath(
                        "the hand cannot back away from the placed object".into(),
                    );
                    continue;
                };
                // The transfer, last: it is the costly plan.
                *stage = "transfer";
                holding(group, full)?;
                match group.plan_to_joints(retreat.end(), &[q_pp]) {
                    Ok(t) => {
                        place_found = Some((t, place, release_retreat));
                        break 'pp;
                    }
                    Err(e) => last = motion_error(e),
                }
                *stage = "place";
            }
        }
        if counted {
            planned += 1;
        }
        let Some((transfer, place, release_retreat)) = place_found else {
            continue;
        };
        // 8. Back to where the arm started.
        *stage = "return";
        group.world = after;
        let home = match group.plan_to_joints(release_retreat.end(), &[start.to_vec()]) {
            Ok(h) => h,
            Err(e) => {
                last = motion_error(e);
                continue;
            }
        };
        return Ok(Sequence {
            to_pregrasp,
            approach,
            lift,
            retreat,
            transfer,
            place,
            release_retreat,
            home,
            planned_object: placed_object,
        });
    }
    Err(last)
}

impl Validate for PickPlaceParams {
    fn check(&self, at: &str) -> Result<(), String> {
        self.observe.check(&nested(at, "observe"))?;
        self.motion.check(&nested(at, "motion"))?;
        for (name, v) in [
            ("pregrasp_distance", self.pregrasp_distance),
            ("lift", self.lift),
            ("retreat", self.retreat),
            ("release_height", self.release_height),
            ("place_approach", self.place_approach),
            ("place_retreat", self.place_retreat),
            ("finger_clearance", self.finger_clearance),
            ("min_grasp_height", self.min_grasp_height),
            ("yaw_range", self.yaw_range),
            ("sweep_radius", self.sweep_radius),
            ("place_margin", self.place_margin),
            ("held_reach", self.held_reach),
            ("held_margin", self.held_margin),
        ] {
            check_non_negative(at, name, v)?;
        }
        check_positive(at, "yaw_step", self.yaw_step)?;
        check_count(at, "max_planned_grasps", self.max_planned_grasps, 1)
    }
}
