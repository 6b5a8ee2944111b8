//! Clearing a cluttered table — seed 002's system (SPEC §3): perceive the table, compute
//! the predicates from geometry, plan with the seed's PDDL domain in process, check IK
//! for the first action only (backtracking by `ik_unfeasible_*` facts), execute it
//! through the driver — a grasp that drops the object into the bin, or a push with the
//! closed gripper — and start again from a new frame.
//!
//! Beyond the seed (SPEC §3.7): a push is as long as it takes for the object's grasp to
//! become free (not k × its box), objects are tracked across frames so none is pushed
//! back where it came from, and every approach and transfer is planned collision-free
//! against the other objects' hulls and the workcell.

use crate::observe::robot_solids;
use crate::pick_place::tool_rotation;
use serde::Serialize;
use std::time::Duration;
use tabula_geom::input::{Validate, check_count, nested};
use tabula_geom::parry::bounding_volume::{Aabb, BoundingVolume};
use tabula_geom::parry::query;
use tabula_geom::parry::shape::SharedShape;
use tabula_geom::polygon::{
    Rectangle, convex_hull_2d, distance_to_boundary, inside_convex, min_area_rectangle,
};
use tabula_geom::{PointCloud, Pose, Quat, Vec2, Vec3};
use tabula_motion::group::thread_cpu;
use tabula_motion::{MoveError, MoveGroup, MoveGroupParams, Plan};
use tabula_pddl::{GroundAtom, Planner, SearchMode};
use tabula_perception::selffilter::self_filter;
use tabula_perception::tabletop::{TabletopParams, extract};
use tabula_robot::description::Gripper;
use tabula_robot::driver::{DriverError, RobotDriver};
use tabula_robot::robots::NamedRobot;

/// Seed 002's domain with `(not (removed ?o))` in every precondition (`pddl/README.md`).
const DOMAIN: &str = include_str!("../../../pddl/tablewclear-domain-fixed.pddl");

/// The four push directions of SPEC §3.2, in the domain's order: along the object's
/// principal (longer) footprint axis, against it, along the other axis, against it.
const DIRECTIONS: [&str; 4] = ["dir1", "dir2", "dir3", "dir4"];

/// Pre-grasp openings are modelled every 5 mm of finger gap.
const OPENING_STEP: f64 = 0.005;

/// Parameters of clearing (SPEC §3.2 and §6, seed 002's repository, where it gives them).
#[derive(Debug, Clone, serde::Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ClearParams {
    pub tabletop: TabletopParams,
    pub motion: MoveGroupParams,
    /// The fixed camera that sees the table.
    pub camera: String,
    /// Frames are decimated to every `decimate`-th pixel of every `decimate`-th row (the
    /// Kinect's 320 × 240 mode for 2); the tabletop pipeline's point counts and pixel
    /// steps are scaled to match.
    pub decimate: usize,
    /// Self-filter padding (m), SPEC §1.1: 0.9 cm.
    pub self_filter_padding: f64,
    /// The closing point lies this far below the object's top (m): SPEC §3.2's "lowered
    /// by half the finger height" with SPEC §6's 6 cm fingers.
    pub grasp_depth: f64,
    /// Fingertips stay at least this far above what the object stands on (m), SPEC §6's
    /// push height 1 cm.
    pub fingertip_clearance: f64,
    /// Pre-grasp distance back along the approach (m), SPEC §3.2: 10 cm.
    pub pregrasp: f64,
    /// Lift after grasping along the table normal (m), SPEC §3.2: 20 cm.
    pub lift: f64,
    /// The held object's bottom is let go this far above the drop point (m).
    pub drop_clearance: f64,
    /// The gripper opening must exceed the object's width by this much on each side (m).
    pub grasp_margin: f64,
    /// Before a grasp the fingers open to the object's width plus this on each side (m),
    /// not fully: in clutter a finger 1 cm from the object fits gaps a fully opened one
    /// (the seed's 7 cm, SPEC §6) does not. Not in the seed; a value at least the
    /// gripper's opening restores the seed's full opening.
    pub pregrasp_gap: f64,
    /// A grasp may hold an object only this deep below its top (m) where that passes
    /// over lower neighbours a full-depth grasp would meet (tried after the full-depth
    /// ones). Not in the seed.
    pub shallow_grip: f64,
    /// Distance between the closed fingers and the object before a push (m), SPEC §6
    /// (the seed's code): 3 cm.
    pub push_distance: f64,
    /// Longest push (m), SPEC §6: 0.6 m.
    pub push_max_length: f64,
    /// Push sweep resolution (m), SPEC §6: 3 cm.
    pub push_resolution: f64,
    /// Seed's push length factor k (× the box size along the push), SPEC §6: 1.0 —
    /// used when no length makes the grasp free.
    pub push_factor: f64,
    /// Pushed a little past the point where the grasp becomes free (m).
    pub push_margin: f64,
    /// After a push the fingers back off this far (m) before rising.
    pub push_back_off: f64,
    /// Pre-push and post-push height above the push (m), SPEC §3.2: 20 cm.
    pub pre_push_height: f64,
    /// Clearance the predicates demand between the gripper or a moving hull and
    /// another object (m).
    pub clearance: f64,
    /// A pushed hull may overlap a neighbour by this much (m) and still slide past it:
    /// touching objects seen with noise overlap by a few millimetres from the start.
    pub sweep_tolerance: f64,
    /// An object counts as the same one across frames when it is this near where it was
    /// (or where a push should have put it) (m).
    pub track_radius: f64,
    /// Most objects a chain push may shove along.
    pub max_chain: usize,
    /// Chain pushes are tried this many times the box's size along the push long (the
    /// seed's k = 1 first).
    pub chain_push_factors: Vec<f64>,
    /// The last resort when neither the seed's actions nor chain pushes can go on
    /// (pairs blocking each other's grasp in a pile): a grasp whose open fingers reach
    /// at most this far (m) into neighbours' hulls, pushing them aside as they come
    /// down — VPG's grasps do. The neighbours it moves are handled by the action, as a
    /// chain push's are. Not in the seed; 0 gives up instead.
    pub nudge_depth: f64,
    /// Pushes allowed per tracked object.
    pub max_pushes_per_object: usize,
    /// A push that moved its object less than this share of its length was jammed: it
    /// is not tried that way again. Not in the seed.
    pub push_jam_share: f64,
    /// Grasp attempts per tracked object before its grasp counts as infeasible.
    pub max_grasp_attempts: usize,
    /// Frames in a row without a plan before giving up.
    pub max_no_plan_frames: usize,
    /// Search time per plan (s).
    pub plan_timeout_s: f64,
    /// Optimal (A* + LM-cut) plans up to this many objects, greedy plans above.
    pub optimal_up_to: usize,
    /// IK restarts for the feasibility check of the first action.
    pub ik_attempts: usize,
}

impl ClearParams {
    /// Every length finite and in range, every step positive: a zero resolution or an
    /// infinite push would make the sweeps endless.
    pub fn validate(&self) -> Result<(), ClearError> {
        let positive = [
            ("push_resolution", self.push_resolution),
            ("push_max_length", self.push_max_length),
            ("push_factor", self.push_factor),
            ("plan_timeout_s", self.plan_timeout_s),
            ("track_radius", self.track_radius),
        ];
        let non_negative = [
            ("self_filter_padding", self.self_filter_padding),
            ("grasp_depth", self.grasp_depth),
            ("fingertip_clearance", self.fingertip_clearance),
            ("pregrasp", self.pregrasp),
            ("lift", self.lift),
            ("drop_clearance", self.drop_clearance),
            ("grasp_margin", self.grasp_margin),
            ("pregrasp_gap", self.pregrasp_gap),
            ("shallow_grip", self.shallow_grip),
            ("push_distance", self.push_distance),
            ("push_margin", self.push_margin),
            ("push_back_off", self.push_back_off),
            ("pre_push_height", self.pre_push_height),
            ("clearance", self.clearance),
            ("sweep_tolerance", self.sweep_tolerance),
            ("push_jam_share", self.push_jam_share),
            ("nudge_depth", self.nudge_depth),
        ];
        for (name, v) in positive {
            if !(v.is_finite() && v > 0.0 && v <= 100.0) {
                return Err(ClearError::Params(format!(
                    "`{name}` = {v}: must be in (0, 100]"
                )));
            }
        }
        for (name, v) in non_negative {
            if !(v.is_finite() && (0.0..=10.0).contains(&v)) {
                return Err(ClearError::Params(format!(
                    "`{name}` = {v}: must be in [0, 10]"
                )));
            }
        }
        if self.push_max_length / self.push_resolution > 10_000.0 {
            return Err(ClearError::Params(
                "`push_max_length` / `push_resolution` over 10,000 steps".into(),
            ));
        }
        if !(1..=16).contains(&self.decimate) {
            return Err(ClearError::Params(format!(
                "`decimate` = {}: must be 1 to 16",
                self.decimate
            )));
        }
        if let Some(f) = self
            .chain_push_factors
            .iter()
            .find(|f| !(f.is_finite() && **f > 0.0 && **f <= 100.0))
        {
            return Err(ClearError::Params(format!(
                "`chain_push_factors` holds {f}: each must be in (0, 100]"
            )));
        }
        Ok(())
    }
}

impl Default for ClearParams {
    fn default() -> Self {
        let mut motion = MoveGroupParams::default();
        // Pushes run the fingertips 1 cm above the table (SPEC §6).
        motion.world.padding = 0.008;
        // A push or a descent may leave its line by a few millimetres where the arm
        // cannot follow it exactly (the near-line fallback of the move group).
        motion.cartesian_tolerance = 0.005;
        Self {
            tabletop: TabletopParams::default(),
            motion,
            camera: "overhead".into(),
            decimate: 2,
            self_filter_padding: 0.009,
            grasp_depth: 0.03,
            fingertip_clearance: 0.01,
            pregrasp: 0.10,
            lift: 0.20,
            drop_clearance: 0.08,
            grasp_margin: 0.0,
            pregrasp_gap: 0.01,
            shallow_grip: 0.02,
            push_distance: 0.03,
            push_max_length: 0.6,
            push_resolution: 0.03,
            push_factor: 1.0,
            push_margin: 0.02,
            push_back_off: 0.015,
            pre_push_height: 0.20,
            clearance: 0.004,
            sweep_tolerance: 0.005,
            track_radius: 0.06,
            max_chain: 4,
            chain_push_factors: vec![1.0, 1.6, 2.2],
            nudge_depth: 0.008,
            max_pushes_per_object: 3,
            push_jam_share: 0.35,
            max_grasp_attempts: 2,
            max_no_plan_frames: 3,
            plan_timeout_s: 1.0,
            optimal_up_to: 10,
            ik_attempts: 40,
        }
    }
}

/// What to clear and where things go.
#[derive(Debug, Clone)]
pub struct ClearRequest {
    /// The arm to use (default: the robot's first arm with a gripper).
    pub arm: Option<String>,
    /// Where objects are let go (world): the centre of the bin's opening.
    pub drop_point: Vec3,
    /// Objects are let go over a square this far around `drop_point` (m), one spot after
    /// another, so they do not pile into a tower.
    pub drop_spread: f64,
    /// The workcell's fixed obstacles (world), as a planning scene knows them.
    pub obstacles: Vec<(String, SharedShape, Pose)>,
    /// Stop after this many actions (default: 3 per object seen first, plus 5).
    pub max_actions: Option<usize>,
}

/// An action of the domain on a tracked object.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ActionKind {
    Grasp,
    Push(usize),
}

impl ActionKind {
    fn pddl(self) -> String {
        match self {
            ActionKind::Grasp => "grasp".into(),
            ActionKind::Push(k) => format!("push_{}", DIRECTIONS[k]),
        }
    }
}

/// One executed action.
#[derive(Debug, Clone, Serialize)]
pub struct ActionRecord {
    pub frame: usize,
    pub action: String,
    /// Tracked object id.
    pub object: usize,
    /// Where the object was seen (world, footprint centre at mid-height).
    pub position: [f64; 3],
    /// For pushes: the direction (world, unit) and length (m).
    pub push: Option<([f64; 2], f64)>,
    /// For chain pushes: where the objects it shoves along were seen.
    pub shoves: Vec<[f64; 3]>,
    pub ok: bool,
    pub error: Option<String>,
}

/// Where the decision time of one frame went (CPU ms).
#[derive(Debug, Clone, Default, Serialize)]
pub struct FrameReport {
    pub objects: usize,
    pub perception_ms: f64,
    pub predicates_ms: f64,
    pub planning_ms: f64,
    pub ik_ms: f64,
    /// Frame in → first action chosen.
    pub decision_ms: f64,
    pub plan: Vec<String>,
    pub ik_backtracks: usize,
}

/// Median, 95th percentile and maximum (the IK benchmark's summary).
pub use tabula_robot::ik::bench::Spread as Stats;

/// The metrics of a run (issue "Clearing a cluttered table", item 6); `collisions` and
/// accidental moves are judged by whoever watches the world (the simulator's harness).
#[derive(Debug, Clone, Default, Serialize)]
pub struct ClearReport {
    /// Objects seen in the first frame.
    pub objects: usize,
    /// Objects grasped and let go over the drop point.
    pub removed: usize,
    pub actions: usize,
    pub grasps: usize,
    pub failed_grasps: usize,
    pub pushes: usize,
    pub no_plan_frames: usize,
    pub ik_backtracks: usize,
    /// Pushes of an object against the direction it was pushed before.
    pub push_loops: usize,
    /// Objects the planner found it can never remove (they left the goal).
    pub dropped_from_goal: usize,
    pub decision_ms: Stats,
    /// Median CPU ms of each part of a decision.
    pub perception_ms: f64,
    pub predicates_ms: f64,
    pub planning_ms: f64,
    pub ik_ms: f64,
    /// Why the loop ended.
    pub stop: String,
    pub frames: Vec<FrameReport>,
    pub log: Vec<ActionRecord>,
}

/// Why a run could not start or had to stop.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ClearError {
    #[error("driver: {0}")]
    Driver(String),
    #[error("robot: {0}")]
    Robot(String),
    #[error("perception: {0}")]
    Perception(String),
    #[error("planner: {0}")]
    Planner(String),
    #[error("parameter {0}")]
    Params(String),
}

impl ClearError {
    pub fn kind(&self) -> &'static str {
        match self {
            ClearError::Driver(_) => "driver",
            ClearError::Robot(_) => "robot",
            ClearError::Perception(_) => "perception",
            ClearError::Planner(_) => "planner",
            ClearError::Params(_) => "params",
        }
    }
}

impl From<DriverError> for ClearError {
    fn from(e: DriverError) -> Self {
        ClearError::Driver(e.to_string())
    }
}

/// What a watcher of the run is told (the simulator's harness counts collisions and
/// objects moved by accident with it).
#[derive(Debug, Clone, Copy)]
pub enum ClearEvent<'a> {
    /// An action is about to run on the object seen at `position`.
    Before(&'a ActionRecord),
    /// It ran.
    After(&'a ActionRecord),
}

impl ClearEvent<'_> {
    /// Before an action: where the object it acts on and those it shoves along were
    /// seen; `None` after it (the shape a judge of the run takes).
    pub fn judged(&self) -> Option<(Vec3, Vec<Vec3>)> {
        match self {
            ClearEvent::Before(a) => Some((
                Vec3::from_array(a.position),
                a.shoves.iter().map(|p| Vec3::from_array(*p)).collect(),
            )),
            ClearEvent::After(_) => None,
        }
    }
}

/// A tabletop object as the predicates see it.
#[derive(Debug, Clone)]
pub struct SeenObject {
    /// Tracked id (stable across frames).
    pub id: usize,
    /// Points seen (world).
    pub points: Vec<Vec3>,
    /// Footprint in the table plane (world xy) and its minimal-area rectangle.
    pub footprint: Vec<Vec2>,
    pub rect: Rectangle,
    /// What it stands on (z of the table, or of the object under it) and its top (m).
    pub bottom: f64,
    pub top: f64,
    /// Convex hull of its points and their projection onto what it stands on (SPEC
    /// §3.1: the camera sees tops, the hull fills in the sides).
    pub hull: SharedShape,
    pub aabb: Aabb,
}

impl SeenObject {
    /// Centre of the footprint at mid-height.
    pub fn center(&self) -> Vec3 {
        Vec3::new(
            self.rect.center.x,
            self.rect.center.y,
            (self.bottom + self.top) / 2.0,
        )
    }

    /// The principal (longer) and the other footprint axis.
    fn axes(&self) -> (Vec2, Vec2) {
        let a = self.rect.axis.normalize_or(Vec2::X);
        if self.rect.size.x >= self.rect.size.y {
            (a, a.perp())
        } else {
            (a.perp(), a)
        }
    }

    /// Push direction `k` (world, unit).
    fn direction(&self, k: usize) -> Vec2 {
        let (major, minor) = self.axes();
        match k {
            0 => major,
            1 => -major,
            2 => minor,
            _ => -minor,
        }
    }
}

/// The gripper's collision shapes in its tool frame, open and closed, from the URDF.
#[derive(Clone)]
struct Hand {
    /// Palm and fingers opened to finger gaps every [`OPENING_STEP`] from closed to
    /// fully open, narrowest first (the last is fully open).
    openings: Vec<(f64, Vec<(SharedShape, Pose)>)>,
    closed: Vec<(SharedShape, Pose)>,
    /// Closed fingers only (what meets a pushed object).
    closed_fingers: Vec<(SharedShape, Pose)>,
    /// Open fingers only (what lands beside a grasped object).
    open_fingers: Vec<(SharedShape, Pose)>,
    /// Fingertips' distance from the tool origin along the approach (m).
    tip: f64,
    /// Finger length along the approach (m).
    finger_length: f64,
    approach: Vec3,
    closing: Vec3,
    open_width: f64,
}

impl Hand {
    fn new(robot: &NamedRobot, gripper: &Gripper) -> Result<Self, ClearError> {
        let model = &robot.model;
        let err = |e: String| ClearError::Robot(e);
        let fj = model
            .joint(&gripper.finger_joint)
            .ok_or_else(|| err(format!("no finger joint `{}`", gripper.finger_joint)))?;
        let limits = model.joints[fj].limits;
        let tool = model
            .link(&gripper.tool_link)
            .map_err(|e| err(e.to_string()))?;
        let shapes_at =
            |finger: f64, links: &[&str]| -> Result<Vec<(SharedShape, Pose)>, ClearError> {
                let mut values = tabula_robot::driver::JointState::default().model_values(model);
                values[fj] = finger;
                let fk = model
                    .forward_kinematics(&values)
                    .map_err(|e| err(e.to_string()))?;
                let tool_from_root = fk[tool].inverse();
                let mut out = Vec::new();
                for name in links {
                    let l = model.link(name).map_err(|e| err(e.to_string()))?;
                    for s in &model.links[l].collision {
                        let (shape, shape_pose) = s.geometry.collision_shape(false).map_err(err)?;
                        out.push((
                            shape,
                            tool_from_root * fk[l] * s.link_from_shape * shape_pose,
                        ));
                    }
                }
                Ok(out)
            };
        let fingers = [gripper.fingers[0].as_str(), gripper.fingers[1].as_str()];
        let all = [
            gripper.palm.as_str(),
            gripper.fingers[0].as_str(),
            gripper.fingers[1].as_str(),
        ];
        let closed_fingers = shapes_at(limits.lower, &fingers)?;
        let approach = gripper.approach();
        let (lo, hi) = extent_along(&closed_fingers, approach);
        // The gap is linear in the finger joint (see `Gripper::width_at`).
        let span = gripper.open_width - gripper.closed_width;
        let levels = (span / OPENING_STEP).ceil().max(0.0) as usize;
        let mut openings = Vec::with_capacity(levels + 1);
        for k in 0..=levels {
            let width = (gripper.closed_width + OPENING_STEP * k as f64).min(gripper.open_width);
            let share = if span > 1e-12 {
                (width - gripper.closed_width) / span
            } else {
                1.0
            };
            let value = limits.lower + (limits.upper - limits.lower) * share;
            openings.push((width, shapes_at(value, &all)?));
        }
        Ok(Self {
            openings,
            closed: shapes_at(limits.lower, &all)?,
            tip: hi,
            finger_length: hi - lo,
            closed_fingers,
            open_fingers: shapes_at(limits.upper, &fingers)?,
            approach,
            closing: gripper.closing(),
            open_width: gripper.open_width,
        })
    }

    /// The narrowest opening at least `width` wide (fully open when none is): its gap
    /// and the open palm and fingers.
    fn open_for(&self, width: f64) -> (f64, &[(SharedShape, Pose)]) {
        let (w, shapes) = self
            .openings
            .iter()
            .find(|(w, _)| *w >= width - 1e-9)
            .or(self.openings.last())
            .expect("a hand has at least its full opening");
        (*w, shapes)
    }

    /// `world_from_tool` with the approach pointing down (against the table normal
    /// `up`), the fingers closing along `closing` (world, horizontal) and the fingertips
    /// at `tips` (world).
    fn pose(&self, tips: Vec3, closing: Vec3, up: Vec3) -> Pose {
        let approach = -up;
        let closing = (closing - approach * closing.dot(approach)).normalize_or(Vec3::X);
        let rotation = tool_rotation(self.approach, self.closing, approach, closing);
        Pose::from_parts(tips - approach * self.tip, rotation)
    }
}

/// Lowest and highest extent of shapes (tool frame) along unit direction `d`.
fn extent_along(shapes: &[(SharedShape, Pose)], d: Vec3) -> (f64, f64) {
    let mut lo = f64::INFINITY;
    let mut hi = f64::NEG_INFINITY;
    for (s, p) in shapes {
        let b = s.compute_aabb(p);
        for i in 0..8 {
            let c = Vec3::new(
                if i & 1 == 0 { b.mins.x } else { b.maxs.x },
                if i & 2 == 0 { b.mins.y } else { b.maxs.y },
                if i & 4 == 0 { b.mins.z } else { b.maxs.z },
            );
            lo = lo.min(c.dot(d));
            hi = hi.max(c.dot(d));
        }
    }
    (lo, hi)
}

/// The table as one frame sees it.
struct Table {
    z: f64,
    up: Vec3,
    /// Convex outline (world xy).
    outline: Vec<Vec2>,
}

/// Perceives the table and its objects in a frame (world-frame cloud, organized or not).
fn perceive(
    cloud: &PointCloud,
    viewpoint: Vec3,
    tabletop: &TabletopParams,
) -> Result<(Table, Vec<SeenObject>), ClearError> {
    let top =
        extract(cloud, viewpoint, tabletop).map_err(|e| ClearError::Perception(e.to_string()))?;
    if tracing::enabled!(tracing::Level::DEBUG) {
        tracing::debug!("tabletop stages (ms): {:?}", top.times);
    }
    let up = top.plane.normal;
    let height_at = |p: Vec2| -> f64 {
        // Table plane: n·x + d = 0, solved for z.
        let n = top.plane.normal;
        if n.z.abs() < 1e-6 {
            return f64::NAN;
        }
        -(top.plane.d + n.x * p.x + n.y * p.y) / n.z
    };
    let mut idx: Vec<usize> = convex_hull_2d(
        &top.table
            .hull
            .iter()
            .map(|q| q.truncate())
            .collect::<Vec<_>>(),
    );
    if idx.is_empty() {
        idx = (0..top.table.hull.len()).collect();
    }
    let outline: Vec<Vec2> = idx.iter().map(|&i| top.table.hull[i].truncate()).collect();
    let table_z = height_at(top.table.centroid.truncate());
    let mut raw: Vec<(Vec<Vec3>, Vec<Vec2>, Rectangle, f64)> = Vec::new();
    for o in &top.objects {
        let points: Vec<Vec3> = o
            .indices
            .iter()
            .map(|&i| cloud.points[i])
            .filter(|q| q.is_finite())
            .collect();
        let flat: Vec<Vec2> = points.iter().map(|q| q.truncate()).collect();
        let hull = convex_hull_2d(&flat);
        let footprint: Vec<Vec2> = hull.iter().map(|&i| flat[i]).collect();
        let Some(rect) = min_area_rectangle(&footprint) else {
            continue;
        };
        let top_z = points.iter().map(|q| q.z).fold(f64::NEG_INFINITY, f64::max);
        raw.push((points, footprint, rect, top_z));
    }
    // What each object stands on: the table, or an object whose footprint holds most of
    // its points and whose top is near its lowest point (seed eq. 4.2's overlap test,
    // with shares instead of its 100-point counts so it holds at any resolution).
    let mut objects = Vec::new();
    for (i, (points, footprint, rect, top_z)) in raw.iter().enumerate() {
        let table_here = height_at(rect.center);
        let lowest = points.iter().map(|q| q.z).fold(f64::INFINITY, f64::min);
        let mut bottom = if table_here.is_finite() {
            table_here
        } else {
            table_z
        };
        if lowest > bottom + 0.015 {
            let candidates: Vec<&(Vec<Vec3>, Vec<Vec2>, Rectangle, f64)> = raw
                .iter()
                .enumerate()
                .filter(|(j, r)| *j != i && r.3 < lowest + 0.02 && r.3 > bottom + 0.01)
                .map(|(_, r)| r)
                .collect();
            let highest = |rs: &mut dyn Iterator<Item = f64>| rs.fold(f64::NEG_INFINITY, f64::max);
            let mut under = highest(&mut candidates.iter().filter_map(|r| {
                let inside = points
                    .iter()
                    .filter(|q| inside_convex(&r.1, q.truncate()))
                    .count();
                (inside as f64 / points.len().max(1) as f64 > 0.5).then_some(r.3)
            }));
            if !under.is_finite() {
                // Held up by something whose top it hides: the seen part of that
                // footprint only reaches to its edge. It stands a whole object's height
                // above that top (a segment seen only by its top face is no higher
                // than its neighbours and stands on the table).
                under = highest(&mut candidates.iter().filter_map(|r| {
                    (r.3 <= top_z - tabletop.min_object_height
                        && footprint.iter().any(|&p| {
                            inside_convex(&r.1, p) || distance_to_boundary(&r.1, p) < 0.01
                        }))
                    .then_some(r.3)
                }));
            }
            if under.is_finite() {
                bottom = under;
            }
        }
        let mut hull_points = points.clone();
        hull_points.extend(footprint.iter().map(|p| Vec3::new(p.x, p.y, bottom)));
        let Some(hull) = SharedShape::convex_hull(&hull_points) else {
            continue;
        };
        let aabb = hull.compute_aabb(&Pose::IDENTITY);
        objects.push(SeenObject {
            id: usize::MAX,
            points: points.clone(),
            footprint: footprint.clone(),
            rect: *rect,
            bottom,
            top: *top_z,
            hull,
            aabb,
        });
    }
    Ok((
        Table {
            z: table_z,
            up: if up.z < 0.0 { -up } else { up },
            outline,
        },
        objects,
    ))
}

/// `(on a b)` for every pair: `a`'s bottom is `b`'s top and most of `a`'s points are over
/// `b`'s footprint.
fn on_pairs(objects: &[SeenObject], table_z: f64) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    for (i, a) in objects.iter().enumerate() {
        if a.bottom < table_z + 0.01 {
            continue;
        }
        for (j, b) in objects.iter().enumerate() {
            if i == j || (b.top - a.bottom).abs() > 0.02 {
                continue;
            }
            let inside = a
                .points
                .iter()
                .filter(|q| inside_convex(&b.footprint, q.truncate()))
                .count();
            if inside * 2 > a.points.len() {
                out.push((i, j));
            }
        }
    }
    out
}

/// A moving shape's clearance test against object hulls: AABB first, then exact.
fn hits(shapes: &[(SharedShape, Pose)], world_from: &Pose, other: &SeenObject, pad: f64) -> bool {
    shapes.iter().any(|(s, p)| {
        let w = *world_from * *p;
        let aabb = s.compute_aabb(&w).loosened(pad);
        aabb.intersects(&other.aabb)
            && query::distance(&w, s.as_ref(), &Pose::IDENTITY, other.hull.as_ref())
                .is_ok_and(|d| d.distance <= pad)
    })
}

/// Whether two objects' hulls come within `pad` of each other.
fn hulls_touch(a: &SeenObject, b: &SeenObject, pad: f64) -> bool {
    a.aabb.loosened(pad).intersects(&b.aabb)
        && query::distance(
            &Pose::IDENTITY,
            a.hull.as_ref(),
            &Pose::IDENTITY,
            b.hull.as_ref(),
        )
        .is_ok_and(|d| d.distance <= pad)
}

/// Whether a hull moved by `by` runs into another by more than `tolerance`: a neighbour it
/// only grazes (touching objects seen with noise overlap by millimetres already) lets
/// it slide past; one ahead is entered by a whole sweep step.
fn hulls_collide(moved: &SeenObject, by: Vec3, other: &SeenObject, tolerance: f64) -> bool {
    Aabb::new(moved.aabb.mins + by, moved.aabb.maxs + by).intersects(&other.aabb)
        && query::contact(
            &Pose::from_translation(by),
            moved.hull.as_ref(),
            &Pose::IDENTITY,
            other.hull.as_ref(),
            0.0,
        )
        .ok()
        .flatten()
        .is_some_and(|c| c.dist < -tolerance)
}

/// A grasp or a push worked out in geometry.
#[derive(Debug, Clone)]
struct Grasp {
    /// Both yaws of the gripper (closing ±).
    poses: [Pose; 2],
    /// The finger gap the gripper opens to before it descends (m).
    width: f64,
}

#[derive(Debug, Clone)]
struct Push {
    direction: Vec2,
    length: f64,
    /// Objects this push shoves along (a chain push; empty for the seed's pushes).
    chain: Vec<usize>,
    /// For chain pushes: how many objects it makes graspable.
    gain: usize,
    /// Tool pose where the push starts, and the fingertip height.
    start: Pose,
    feasible: bool,
}

impl Push {
    /// How far the fingers travel: to the object, then the push.
    fn travel(&self, params: &ClearParams) -> f64 {
        self.length + params.push_distance
    }
}

/// Everything the predicates computed for one frame.
#[derive(Clone)]
struct Geometry {
    on: Vec<(usize, usize)>,
    block_grasp: Vec<(usize, usize)>,
    block_push: [Vec<(usize, usize)>; 4],
    /// The least-blocked grasp of each object; `None` when it fits the gripper no way.
    grasps: Vec<Option<Grasp>>,
    pushes: Vec<[Push; 4]>,
}

/// Top grasps of `o`: closing across the principal axis (SPEC §3.2), then across the
/// other one when the object fits that way too (a square box can be taken either way:
/// one of them may be free of a neighbour). When it fits neither way, grasps of its
/// narrow parts ([`part_grasps`]). Empty when nothing fits.
fn grasps_of(o: &SeenObject, hand: &Hand, table: &Table, params: &ClearParams) -> Vec<Grasp> {
    let (major, minor) = o.axes();
    let tip_z = |top: f64| {
        (top - params.grasp_depth - hand.finger_length / 2.0)
            .max(o.bottom + params.fingertip_clearance)
    };
    let grasp_at = |at: Vec2, z: f64, c: Vec2, across: f64| {
        let tips = Vec3::new(at.x, at.y, z);
        let closing = Vec3::new(c.x, c.y, 0.0);
        Grasp {
            poses: [
                hand.pose(tips, closing, table.up),
                hand.pose(tips, -closing, table.up),
            ],
            width: hand.open_for(across + 2.0 * params.pregrasp_gap).0,
        }
    };
    let grasp = |at: Vec2, top: f64, c: Vec2, across: f64| grasp_at(at, tip_z(top), c, across);
    let fits: Vec<Vec2> = [minor, major]
        .into_iter()
        .filter(|&c| o.rect.extent_along(c) + 2.0 * params.grasp_margin <= hand.open_width)
        .collect();
    if !fits.is_empty() {
        let mut whole: Vec<Grasp> = fits
            .iter()
            .map(|&c| grasp(o.rect.center, o.top, c, o.rect.extent_along(c)))
            .collect();
        // The same grasps held only `shallow_grip` deep, after the deep ones: the
        // fingertips pass over neighbours lower than the object.
        let shallow = o.top - params.shallow_grip;
        if shallow > tip_z(o.top) + 0.01 {
            whole.extend(
                fits.iter()
                    .map(|&c| grasp_at(o.rect.center, shallow, c, o.rect.extent_along(c))),
            );
        }
        return whole;
    }
    part_grasps(o, hand, params)
        .into_iter()
        .map(|(at, top, width)| grasp(at, top, minor, width))
        .collect()
}

/// Grasps of the narrow parts of an object too wide to take whole: slices across its
/// principal axis, a finger's width and a few millimetres, whose points fit the
/// gripper — narrowest first, at most three. A blob wider than the gripper is often two
/// objects the camera cannot tell apart (touching, tops level); taking one part first
/// lets the next frame see the other alone.
fn part_grasps(o: &SeenObject, hand: &Hand, params: &ClearParams) -> Vec<(Vec2, f64, f64)> {
    let (major, minor) = o.axes();
    let c = o.rect.center;
    let local: Vec<(f64, f64, f64)> = o
        .points
        .iter()
        .map(|p| {
            let d = p.truncate() - c;
            (d.dot(major), d.dot(minor), p.z)
        })
        .collect();
    let half = o.rect.extent_along(major) / 2.0;
    let (finger_lo, finger_hi) =
        extent_along(&hand.open_fingers, hand.closing.cross(hand.approach));
    let window = (finger_hi - finger_lo) / 2.0 + 0.003;
    let mut found: Vec<(f64, Vec2, f64)> = Vec::new();
    // Slice centres every centimetre from one end to the other, both ends included.
    let span = (2.0 * (half - window)).max(0.0);
    let steps = (span / 0.01).ceil() as usize;
    for k in 0..=steps {
        let t = -half + window + span * k as f64 / steps.max(1) as f64;
        let (lo, hi, top, count) = local.iter().filter(|q| (q.0 - t).abs() <= window).fold(
            (f64::INFINITY, f64::NEG_INFINITY, f64::NEG_INFINITY, 0usize),
            |(lo, hi, top, n), q| (lo.min(q.1), hi.max(q.1), top.max(q.2), n + 1),
        );
        let width = hi - lo;
        if count >= 20 && width + 2.0 * params.grasp_margin <= hand.open_width {
            found.push((width, c + major * t + minor * ((lo + hi) / 2.0), top));
        }
    }
    found.sort_by(|a, b| a.0.total_cmp(&b.0));
    found
        .into_iter()
        .take(3)
        .map(|(width, at, top)| (at, top, width))
        .collect()
}

/// Where the closed fingers start a push of `o` along `d`: `push_distance` behind the
/// object, their base at the object's top (or higher, for the palm to pass above the
/// objects along the path, up to `palm_over`), their tips no lower than the clearance.
fn push_start(
    o: &SeenObject,
    d: Vec2,
    along_major: bool,
    palm_over: f64,
    hand: &Hand,
    table: &Table,
    params: &ClearParams,
) -> Pose {
    let d3 = Vec3::new(d.x, d.y, 0.0);
    let across = Vec3::new(-d.y, d.x, 0.0);
    // SPEC §3.2: closing parallel to the push along the principal axis (narrow
    // footprint), across it otherwise (a wide pusher keeps a long object from turning)
    // — but only where the wide pusher fits the object's face with a centimetre to
    // spare on each side: a wider pusher would drag the neighbours beside the path.
    let width_across = |closing: Vec3| {
        let probe = hand.pose(Vec3::ZERO, closing, table.up);
        let (lo, hi) = extent_along(&hand.closed_fingers, probe.rotation.inverse() * across);
        hi - lo
    };
    let closing =
        if along_major || width_across(across) + 0.02 > o.rect.extent_along(across.truncate()) {
            d3
        } else {
            across
        };
    // The palm above the neighbours along the path (`palm_over`) while the fingers
    // still cover at least the object's top 2 cm.
    let palm_clear = (palm_over + params.clearance - hand.finger_length).min(o.top - 0.02);
    let tip_z = (o.top - hand.finger_length)
        .max(o.bottom + params.fingertip_clearance)
        .max(palm_clear);
    let probe = hand.pose(Vec3::ZERO, closing, table.up);
    // How far the fingers reach toward the object from the tool axis.
    let (_, reach) = extent_along(&hand.closed_fingers, probe.rotation.inverse() * d3);
    let back = o.rect.extent_along(d) / 2.0 + params.push_distance + reach;
    let tips = Vec3::new(o.rect.center.x, o.rect.center.y, tip_z) - d3 * back;
    hand.pose(tips, closing, table.up)
}

/// `o` moved by `by`; its hull too when `with_hull` (a new convex hull: costly).
fn translated(o: &SeenObject, by: Vec3, with_hull: bool) -> SeenObject {
    let mut t = o.clone();
    t.rect.center += by.truncate();
    for p in &mut t.points {
        *p += by;
    }
    for p in &mut t.footprint {
        *p += by.truncate();
    }
    if with_hull {
        // Hulls are kept in world coordinates: a moved copy is rebuilt around its
        // vertices.
        let moved: Vec<Vec3> = hull_vertices(&o.hull).into_iter().map(|p| p + by).collect();
        if let Some(h) = SharedShape::convex_hull(&moved) {
            t.hull = h;
        }
        t.aabb = t.hull.compute_aabb(&Pose::IDENTITY);
    }
    t
}

fn hull_vertices(s: &SharedShape) -> Vec<Vec3> {
    s.as_convex_polyhedron()
        .map(|c| c.points().to_vec())
        .unwrap_or_default()
}

/// A pose and its copies every 3 cm up to `height` along `up` (the way down to it).
fn descent_poses(pose: &Pose, up: Vec3, height: f64) -> Vec<Pose> {
    let steps = (height / 0.03).ceil().max(1.0) as usize;
    (0..=steps)
        .map(|k| {
            Pose::from_parts(
                pose.translation + up * (height * k as f64 / steps as f64),
                pose.rotation,
            )
        })
        .collect()
}

/// The objects the open gripper meets at `grasp` or on its way down from the
/// pre-grasp, except those `skip` names.
fn grasp_blockers(
    objects: &[SeenObject],
    grasp: &Grasp,
    skip: &dyn Fn(usize) -> bool,
    hand: &Hand,
    table: &Table,
    params: &ClearParams,
) -> Vec<usize> {
    let poses = descent_poses(&grasp.poses[0], table.up, params.pregrasp);
    (0..objects.len())
        .filter(|&a| !skip(a))
        .filter(|&a| {
            poses.iter().any(|p| {
                hits(
                    hand.open_for(grasp.width).1,
                    p,
                    &objects[a],
                    params.clearance,
                )
            })
        })
        .collect()
}

/// Which objects could be grasped now: nothing on them, and a grasp nothing is in the
/// way of.
fn graspable(
    objects: &[SeenObject],
    on: &[(usize, usize)],
    hand: &Hand,
    table: &Table,
    params: &ClearParams,
) -> Vec<bool> {
    (0..objects.len())
        .map(|b| graspable_one(objects, on, b, hand, table, params))
        .collect()
}

/// Whether object `b` could be grasped now (see [`graspable`]).
fn graspable_one(
    objects: &[SeenObject],
    on: &[(usize, usize)],
    b: usize,
    hand: &Hand,
    table: &Table,
    params: &ClearParams,
) -> bool {
    let skip = |a: usize| a == b || on.contains(&(a, b)) || on.contains(&(b, a));
    !on.iter().any(|&(_, under)| under == b)
        && grasps_of(&objects[b], hand, table, params)
            .iter()
            .any(|g| grasp_blockers(objects, g, &skip, hand, table, params).is_empty())
}

/// The predicates of SPEC §3.3 and the poses of SPEC §3.2 for every object; with
/// `chain`, pushes are chain pushes (each may shove what is in front of it along), the
/// fallback when the seed's actions cannot clear the table (packed objects).
fn predicates(
    objects: &[SeenObject],
    table: &Table,
    hand: &Hand,
    params: &ClearParams,
    with_chain: bool,
) -> Geometry {
    let n = objects.len();
    let on = on_pairs(objects, table.z);
    let pad = params.clearance;
    let descent = |pose: &Pose, height: f64| descent_poses(pose, table.up, height);
    let blockers = |grasp: &Grasp, skip: &dyn Fn(usize) -> bool| {
        grasp_blockers(objects, grasp, skip, hand, table, params)
    };
    let mut grasps = Vec::with_capacity(n);
    let mut block_grasp = Vec::new();
    for (b, o) in objects.iter().enumerate() {
        // Objects on b block its grasp through `on`, not through the gripper.
        let skip = |a: usize| a == b || on.contains(&(a, b)) || on.contains(&(b, a));
        // The candidate with the fewest objects in its way.
        let best = grasps_of(o, hand, table, params)
            .into_iter()
            .map(|g| {
                let by = blockers(&g, &skip);
                (g, by)
            })
            .min_by_key(|(_, by)| by.len());
        match best {
            Some((g, by)) => {
                block_grasp.extend(by.into_iter().map(|a| (a, b)));
                grasps.push(Some(g));
            }
            None => grasps.push(None),
        }
    }
    // Which objects are graspable now (only needed for chain pushes).
    let mut before: Option<Vec<bool>> = None;
    let mut block_push: [Vec<(usize, usize)>; 4] = Default::default();
    let mut block_chain: [Vec<(usize, usize)>; 4] = Default::default();
    let mut pushes = Vec::with_capacity(n);
    let mut chain_pushes = Vec::with_capacity(n);
    for (b, o) in objects.iter().enumerate() {
        let dirs: [Push; 4] = std::array::from_fn(|k| {
            let d = o.direction(k);
            let d3 = Vec3::new(d.x, d.y, 0.0);
            // The palm passes above whatever stands along the path, where the
            // fingers can still reach the object below it.
            let ahead = o.rect.extent_along(d) + params.push_max_length.min(0.15);
            let over = objects
                .iter()
                .enumerate()
                .filter(|&(a, x)| {
                    let rel = x.rect.center - o.rect.center;
                    a != b
                        && rel.dot(d) > -0.1
                        && rel.dot(d) < ahead
                        && rel.dot(d.perp()).abs() < 0.09
                })
                .map(|(_, x)| x.top)
                .fold(f64::NEG_INFINITY, f64::max);
            let start = push_start(o, d, k < 2, over, hand, table, params);
            let others = |a: usize| a != b && !on.contains(&(a, b)) && !on.contains(&(b, a));
            // Push until the grasp is free (SPEC §3.7), else k × the box (the seed).
            let steps = (params.push_max_length / params.push_resolution).floor() as usize;
            let mut length = None;
            for s in 1..=steps {
                let by = d3 * (s as f64 * params.push_resolution);
                if (0..n)
                    .filter(|&a| others(a))
                    .any(|a| hulls_collide(o, by, &objects[a], params.sweep_tolerance))
                {
                    break;
                }
                // Only its grasp is asked about: the hull need not move.
                let moved = translated(o, by, false);
                let skip = |a: usize| !others(a);
                let free = grasps_of(&moved, hand, table, params)
                    .iter()
                    .any(|g| blockers(g, &skip).is_empty());
                if free {
                    length = Some(s as f64 * params.push_resolution + params.push_margin);
                    break;
                }
            }
            let length = length
                .unwrap_or(params.push_factor * o.rect.extent_along(d))
                .min(params.push_max_length);
            // Stays on the table: the pushed footprint's centre keeps half its size
            // from the edge.
            let end = o.rect.center + d * length;
            let on_table = inside_convex(&table.outline, end)
                && tabula_geom::polygon::distance_to_boundary(&table.outline, end)
                    > o.rect.extent_along(d) / 2.0 + 0.02;
            Push {
                direction: d,
                length,
                chain: Vec::new(),
                gain: 0,
                start,
                feasible: on_table,
            }
        });
        let mut chained = dirs.clone();
        for (k, p) in dirs.iter().enumerate() {
            let d3 = Vec3::new(p.direction.x, p.direction.y, 0.0);
            // The closed hand coming down to the push and along it.
            let hand_path = |travel: f64| -> Vec<Pose> {
                let steps = (travel / params.push_resolution).ceil().max(1.0) as usize;
                let mut path = descent(&p.start, params.pre_push_height);
                path.extend((1..=steps).map(|s| {
                    Pose::from_parts(
                        p.start.translation + d3 * (travel * s as f64 / steps as f64),
                        p.start.rotation,
                    )
                }));
                path
            };
            let gripper_hits = |path: &[Pose]| -> Vec<usize> {
                (0..n)
                    .filter(|&a| a != b)
                    .filter(|&a| path.iter().any(|h| hits(&hand.closed, h, &objects[a], pad)))
                    .collect()
            };
            // A sweep: the offsets of an object along the push.
            let sweep_of = |length: f64| -> Vec<Vec3> {
                let steps = (length / params.push_resolution).ceil().max(1.0) as usize;
                (1..=steps)
                    .map(|s| d3 * (length * s as f64 / steps as f64))
                    .collect()
            };
            let collides = |x: &SeenObject, sweep: &[Vec3], a: usize| {
                sweep
                    .iter()
                    .any(|by| hulls_collide(x, *by, &objects[a], params.sweep_tolerance))
            };
            let solo_hits = gripper_hits(&hand_path(p.travel(params)));

            let sweep = sweep_of(p.length);
            for a in (0..n).filter(|&a| a != b) {
                let swept = collides(o, &sweep, a);
                let gripper = solo_hits.contains(&a);
                if swept || gripper {
                    if tracing::enabled!(tracing::Level::DEBUG) {
                        tracing::debug!(
                            "block_{} o{} o{}: swept {swept} gripper {gripper} (push {:.2} m along ({:.2}, {:.2}))",
                            DIRECTIONS[k],
                            objects[a].id,
                            o.id,
                            p.length,
                            p.direction.x,
                            p.direction.y
                        );
                    }
                    block_push[k].push((a, b));
                }
            }
            if !with_chain {
                continue;
            }
            // The chain variant: what the sweep runs into moves along (and what that
            // runs into, up to `max_chain`); only the gripper and what the chain runs
            // into block it. Lengths are multiples of the box's size along the push
            // (the seed's k × size), the one that makes the most objects graspable is
            // kept (then the shortest).
            let mut best: Option<(Push, Vec<usize>)> = None;
            for &factor in &params.chain_push_factors {
                let length =
                    (factor * o.rect.extent_along(p.direction)).min(params.push_max_length);
                let mut chain: Vec<usize> = Vec::new();
                let mut frontier = vec![b];
                while let Some(x) = frontier.pop() {
                    let sw = sweep_of(length);
                    for a in 0..n {
                        if a != b && !chain.contains(&a) && collides(&objects[x], &sw, a) {
                            chain.push(a);
                            frontier.push(a);
                        }
                    }
                }
                let fits_table = |x: &SeenObject| {
                    let end = x.rect.center + p.direction * length;
                    inside_convex(&table.outline, end)
                        && tabula_geom::polygon::distance_to_boundary(&table.outline, end)
                            > x.rect.extent_along(p.direction) / 2.0 + 0.02
                };
                let mut c = p.clone();
                c.length = length;
                c.feasible = chain.len() <= params.max_chain
                    && fits_table(o)
                    && chain.iter().all(|&a| fits_table(&objects[a]));
                let hits = gripper_hits(&hand_path(length + params.push_distance));
                let blockers: Vec<usize> = (0..n)
                    .filter(|&a| a != b && !chain.contains(&a) && hits.contains(&a))
                    .collect();
                // What it is worth: how many objects it makes graspable that are not
                // now (shoving a pair along together may help nothing).
                if c.feasible && blockers.is_empty() {
                    let before =
                        before.get_or_insert_with(|| graspable(objects, &on, hand, table, params));
                    let moved: Vec<SeenObject> = objects
                        .iter()
                        .enumerate()
                        .map(|(a, x)| {
                            if a == b || chain.contains(&a) {
                                translated(x, d3 * length, true)
                            } else {
                                x.clone()
                            }
                        })
                        .collect();
                    // Only objects near what moved (within an open hand's reach of where
                    // it was or went) can change.
                    let reach = hand.open_width + 0.05;
                    let moved_boxes: Vec<Aabb> = (0..n)
                        .filter(|&a| a == b || c.chain.contains(&a) || chain.contains(&a))
                        .map(|a| objects[a].aabb.merged(&moved[a].aabb).loosened(reach))
                        .collect();
                    c.gain = (0..n)
                        .filter(|&a| !before[a])
                        .filter(|&a| moved_boxes.iter().any(|m| m.intersects(&moved[a].aabb)))
                        .filter(|&a| graspable_one(&moved, &on, a, hand, table, params))
                        .count();
                }
                c.chain = chain;
                let score = |(c, blockers): &(Push, Vec<usize>)| {
                    (c.feasible && blockers.is_empty(), c.gain)
                };
                if best
                    .as_ref()
                    .is_none_or(|bst| score(&(c.clone(), blockers.clone())) > score(bst))
                {
                    best = Some((c, blockers));
                }
            }
            if let Some((c, blockers)) = best {
                block_chain[k].extend(blockers.into_iter().map(|a| (a, b)));
                chained[k] = c;
            }
        }
        pushes.push(dirs);
        chain_pushes.push(chained);
    }
    let (block_push, pushes) = if with_chain {
        (block_chain, chain_pushes)
    } else {
        (block_push, pushes)
    };
    Geometry {
        on,
        block_grasp,
        block_push,
        grasps,
        pushes,
    }
}

/// The PDDL problem of a frame.
fn problem_text(objects: &[SeenObject], g: &Geometry, goal: &[usize]) -> String {
    use std::fmt::Write;
    let name = |i: usize| format!("o{}", objects[i].id);
    let mut s = String::from("(define (problem clear) (:domain tablewclear)\n(:objects");
    for i in 0..objects.len() {
        let _ = write!(s, " {}", name(i));
    }
    s.push_str(" - obj)\n(:init");
    for &(a, b) in &g.on {
        let _ = write!(s, " (on {} {})", name(a), name(b));
    }
    for &(a, b) in &g.block_grasp {
        let _ = write!(s, " (block_grasp {} {})", name(a), name(b));
    }
    for (k, pairs) in g.block_push.iter().enumerate() {
        for &(a, b) in pairs {
            let _ = write!(s, " (block_{} {} {})", DIRECTIONS[k], name(a), name(b));
        }
    }
    s.push_str(")\n(:goal (and");
    for &i in goal {
        let _ = write!(s, " (removed {})", name(i));
    }
    s.push_str(")))\n");
    s
}

/// A tracked object: where it is expected next and what was done to it.
#[derive(Debug, Clone)]
struct Track {
    id: usize,
    expected: Vec2,
    seen: Vec2,
    pushes: Vec<Vec2>,
    /// Directions of pushes that could not be executed, or were jammed.
    failed_pushes: Vec<Vec2>,
    /// The last push, until the next frame sees how far it went: direction, length and
    /// where the object was.
    pending: Option<(Vec2, f64, Vec2)>,
    grasp_attempts: usize,
}

impl Track {
    /// Whether a push along `direction` is ruled out: too many pushes already, back
    /// against an earlier push (no pushing to and fro), or the way one failed.
    fn rules_out(&self, direction: Vec2, params: &ClearParams) -> bool {
        self.pushes.len() >= params.max_pushes_per_object
            || self.pushes.iter().any(|d| d.dot(direction) < -0.5)
            || self.failed_pushes.iter().any(|d| d.dot(direction) > 0.85)
    }
}

/// Gives every object the id of the track it continues (nearest expected position
/// within `radius`, greedily by distance) or a new one. A pushed object that moved
/// less than `jam_share` of the push's length along it was jammed (by neighbours the
/// predicates let it slide past): that way is not tried again.
fn track(objects: &mut [SeenObject], tracks: &mut Vec<Track>, radius: f64, jam_share: f64) {
    let mut pairs: Vec<(f64, usize, usize)> = Vec::new();
    for (i, o) in objects.iter().enumerate() {
        for (t, tr) in tracks.iter().enumerate() {
            // Where a push should have put it, or where it was (a push may fail).
            let d = (o.rect.center - tr.expected)
                .length()
                .min((o.rect.center - tr.seen).length());
            if d <= radius {
                pairs.push((d, i, t));
            }
        }
    }
    pairs.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut used_o = vec![false; objects.len()];
    let mut used_t = vec![false; tracks.len()];
    for (_, i, t) in pairs {
        if used_o[i] || used_t[t] {
            continue;
        }
        used_o[i] = true;
        used_t[t] = true;
        objects[i].id = tracks[t].id;
        if let Some((d, length, from)) = tracks[t].pending.take()
            && (objects[i].rect.center - from).dot(d) < jam_share * length
        {
            tracks[t].failed_pushes.push(d);
        }
        tracks[t].expected = objects[i].rect.center;
        tracks[t].seen = objects[i].rect.center;
    }
    let mut next = tracks.iter().map(|t| t.id + 1).max().unwrap_or(0);
    for (i, o) in objects.iter_mut().enumerate() {
        if !used_o[i] {
            o.id = next;
            tracks.push(Track {
                id: next,
                expected: o.rect.center,
                seen: o.rect.center,
                pushes: Vec::new(),
                failed_pushes: Vec::new(),
                pending: None,
                grasp_attempts: 0,
            });
            next += 1;
        }
    }
}

fn atom(predicate: &str, object: usize) -> GroundAtom {
    GroundAtom {
        predicate: predicate.into(),
        args: vec![format!("o{object}")],
    }
}

fn infeasible_atom(kind: ActionKind, object: usize) -> GroundAtom {
    match kind {
        ActionKind::Grasp => atom("ik_unfeasible_grasp", object),
        ActionKind::Push(k) => atom(&format!("ik_unfeasible_{}", DIRECTIONS[k]), object),
    }
}

/// Clears the table the driver's camera sees. `watch` is told before and after every
/// action (the simulator's harness judges collisions with it); pass `|_, _| {}` when
/// nobody watches.
pub fn clear<D: RobotDriver>(
    driver: &mut D,
    robot: &NamedRobot,
    request: &ClearRequest,
    params: &ClearParams,
    watch: &mut dyn FnMut(&mut D, ClearEvent<'_>),
) -> Result<ClearReport, ClearError> {
    let mut report = ClearReport::default();
    let arm_name = match &request.arm {
        Some(a) => a.clone(),
        None => robot
            .description
            .arms
            .iter()
            .find(|a| a.gripper.is_some())
            .map(|a| a.name.clone())
            .ok_or_else(|| ClearError::Robot("no arm with a gripper".into()))?,
    };
    let arm = robot
        .description
        .arm(&arm_name)
        .map_err(|e| ClearError::Robot(e.to_string()))?
        .clone();
    let gripper = robot
        .description
        .gripper_of(&arm)
        .cloned()
        .ok_or_else(|| ClearError::Robot(format!("arm `{arm_name}` has no gripper")))?;
    params.validate()?;
    if !(request.drop_point.is_finite() && request.drop_spread.is_finite()) {
        return Err(ClearError::Params("the drop point must be finite".into()));
    }
    let hand = Hand::new(robot, &gripper)?;
    let domain =
        tabula_pddl::parse_domain(DOMAIN).map_err(|e| ClearError::Planner(e.to_string()))?;
    let state = driver.joint_state()?;
    let world_from_root = driver.world_from_root()?;
    // The hand and what it holds keep the predicates' clearance, not the arm's padding:
    // what the predicates call free, the planner must too.
    let mut motion = params.motion.clone();
    for link in [
        &gripper.palm,
        &gripper.fingers[0],
        &gripper.fingers[1],
        &gripper.tool_link,
    ] {
        motion
            .world
            .link_padding
            .entry(link.clone())
            .or_insert(params.clearance);
    }
    // The allowed-collision matrix is sampled once per run (setup, not a decision).
    let mut group = MoveGroup::new(robot, &arm_name, &state, world_from_root, motion)
        .map_err(|e| ClearError::Robot(e.to_string()))?;
    for (i, (name, shape, pose)) in request.obstacles.iter().enumerate() {
        group
            .add_object(&format!("fixed{i}:{name}"), shape.clone(), *pose)
            .map_err(|e| ClearError::Robot(e.to_string()))?;
    }
    // Out of the camera's view between actions: the arm's tucked pose, else where it
    // started.
    let start = group.arm_values(&state);
    let home: Vec<f64> = group
        .joint_names()
        .iter()
        .zip(&start)
        .map(|(n, s)| arm.tucked.get(n).copied().unwrap_or(*s))
        .collect();
    let single = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .map_err(|e| ClearError::Perception(e.to_string()))?;
    // Point counts and pixel steps of the tabletop pipeline are for full frames; a
    // decimated frame has `decimate`² fewer points and pixels `decimate` times as far.
    let mut tabletop = params.tabletop.clone();
    let d = params.decimate.max(1);
    tabletop.min_object_points = (tabletop.min_object_points / (d * d)).max(1);
    tabletop.concavity_step = (tabletop.concavity_step / d).max(1);
    let mut tracks: Vec<Track> = Vec::new();
    let mut no_plan_run = 0usize;
    let mut frame_no = 0usize;
    let mut max_actions = request.max_actions;
    loop {
        // ---- Perceive.
        let frame = driver.capture(&params.camera)?;
        let state = driver.joint_state()?;
        let world_from_root = driver.world_from_root()?;
        // On one thread, so its CPU time is all of the work.
        let (perceived, perception, filtered) = single.install(|| {
            let c0 = thread_cpu();
            let solids = robot_solids(
                &robot.model,
                &state.model_values(&robot.model),
                world_from_root,
            );
            let mut cloud = frame
                .cloud
                .decimated(params.decimate)
                .transformed(&frame.world_from_camera);
            let keep = self_filter(
                &cloud.points,
                &solids,
                &tabula_perception::selffilter::SelfFilterParams {
                    padding: params.self_filter_padding,
                },
            );
            for (q, k) in cloud.points.iter_mut().zip(keep) {
                if !k {
                    *q = Vec3::NAN;
                }
            }
            let filtered = thread_cpu() - c0;
            let perceived = perceive(&cloud, frame.world_from_camera.translation, &tabletop);
            (perceived, thread_cpu() - c0, filtered)
        });
        if tracing::enabled!(tracing::Level::DEBUG) {
            tracing::debug!(
                "perception CPU {:.1} ms, of which transform + self-filter {:.1} ms",
                perception * 1e3,
                filtered * 1e3
            );
        }
        let (table, mut objects) = match perceived {
            Ok(x) => x,
            Err(e) if frame_no == 0 => return Err(e),
            Err(e) => {
                report.stop = format!("lost the table: {e}");
                break;
            }
        };
        track(
            &mut objects,
            &mut tracks,
            params.track_radius,
            params.push_jam_share,
        );
        if frame_no == 0 {
            report.objects = objects.len();
            max_actions.get_or_insert(3 * objects.len() + 5);
        }
        let mut fr = FrameReport {
            objects: objects.len(),
            perception_ms: perception * 1e3,
            ..FrameReport::default()
        };
        if objects.is_empty() {
            report.stop = "table clear".into();
            break;
        }
        if report.actions >= max_actions.unwrap_or(usize::MAX) {
            report.stop = "action limit".into();
            break;
        }
        // ---- Predicates.
        let c1 = thread_cpu();
        let solo = predicates(&objects, &table, &hand, params, false);
        fr.predicates_ms = (thread_cpu() - c1) * 1e3;
        // ---- Plan, check IK of the first action, backtrack.
        let c2 = thread_cpu();
        let solo_predicates_ms = fr.predicates_ms;
        // The seed's actions first; chain pushes only when those cannot go on.
        let mut geometry = solo;
        let mut chosen = decide(
            &objects,
            &geometry,
            &tracks,
            &domain,
            &mut group,
            robot,
            &state,
            params,
            &mut fr,
            &mut report,
        );
        if matches!(chosen, Decision::NothingRemovable) {
            let c = thread_cpu();
            let chain = predicates(&objects, &table, &hand, params, true);
            fr.predicates_ms += (thread_cpu() - c) * 1e3;
            chosen = decide_chain(
                &objects, &chain, &tracks, &mut group, robot, &state, params, &mut fr,
            );
            // A nudge grasp is one of the seed's grasps: it keeps the seed's geometry.
            if matches!(chosen, Decision::NothingRemovable) && params.nudge_depth > 0.0 {
                chosen = decide_nudge(
                    &objects, &geometry, &tracks, &hand, &table, &mut group, robot, &state, params,
                    &mut fr,
                );
            } else {
                geometry = chain;
            }
        }
        // Chain predicates (when needed) ran inside this span: counted as predicates.
        let decision_total = (thread_cpu() - c2) * 1e3;
        let chain_predicates_ms = fr.predicates_ms - solo_predicates_ms;
        fr.planning_ms = decision_total - fr.ik_ms - chain_predicates_ms;
        fr.decision_ms = fr.perception_ms + solo_predicates_ms + decision_total;
        report.ik_backtracks += fr.ik_backtracks;
        tracing::info!(
            frame = frame_no,
            objects = fr.objects,
            decision_ms = fr.decision_ms,
            perception_ms = fr.perception_ms,
            predicates_ms = fr.predicates_ms,
            planning_ms = fr.planning_ms,
            ik_ms = fr.ik_ms,
            plan = fr.plan.join(" "),
            "clear: decision"
        );
        report.frames.push(fr);
        frame_no += 1;
        let (i, kind, ik, nudged) = match chosen {
            Decision::Act(i, kind, ik, nudged) => (i, kind, ik, nudged),
            Decision::NothingRemovable => {
                report.stop = "nothing left that can be removed".into();
                break;
            }
            Decision::NoPlan => {
                report.no_plan_frames += 1;
                no_plan_run += 1;
                if no_plan_run >= params.max_no_plan_frames {
                    report.stop = "no plan".into();
                    break;
                }
                continue;
            }
        };
        no_plan_run = 0;
        // ---- Execute.
        let o = &objects[i];
        let t = tracks.iter().position(|t| t.id == o.id).unwrap_or_default();
        let mut record = ActionRecord {
            frame: frame_no - 1,
            action: kind.pddl(),
            object: o.id,
            position: o.center().to_array(),
            push: None,
            shoves: nudged
                .iter()
                .map(|&a| objects[a].center().to_array())
                .collect(),
            ok: false,
            error: None,
        };
        if let ActionKind::Push(k) = kind {
            let p = &geometry.pushes[i][k];
            record.push = Some((p.direction.to_array(), p.length));
            record.shoves = p
                .chain
                .iter()
                .map(|&a| objects[a].center().to_array())
                .collect();
            if tracks[t].pushes.iter().any(|d| d.dot(p.direction) < -0.5) {
                report.push_loops += 1;
            }
        }
        watch(driver, ClearEvent::Before(&record));
        report.actions += 1;
        let result = match kind {
            ActionKind::Grasp => {
                report.grasps += 1;
                tracks[t].grasp_attempts += 1;
                match &geometry.grasps[i] {
                    Some(g) => execute_grasp(
                        driver,
                        robot,
                        &mut group,
                        &objects,
                        i,
                        g,
                        ik,
                        &hand,
                        &gripper,
                        &table,
                        request,
                        report.removed,
                        &home,
                        &nudged,
                        params,
                    ),
                    None => Err(ExecError::Motion("no grasp fits the object".into())),
                }
            }
            ActionKind::Push(k) => {
                report.pushes += 1;
                let p = &geometry.pushes[i][k];
                tracks[t].pushes.push(p.direction);
                tracks[t].expected = o.rect.center + p.direction * p.length;
                tracks[t].pending = Some((p.direction, p.length, o.rect.center));
                execute_push(
                    driver, robot, &mut group, &objects, i, p, ik, &gripper, &table, &home, params,
                )
            }
        };
        match result {
            Ok(()) => {
                record.ok = true;
                if kind == ActionKind::Grasp {
                    report.removed += 1;
                    // It is in the bin: whatever is seen there next is something else.
                    tracks.remove(t);
                }
            }
            Err(e) => {
                match kind {
                    ActionKind::Grasp => report.failed_grasps += 1,
                    // A push whose motion could not be made is not tried that way again.
                    ActionKind::Push(k) => {
                        if let Some(tr) = tracks.iter_mut().find(|tr| tr.id == objects[i].id) {
                            tr.failed_pushes.push(geometry.pushes[i][k].direction);
                        }
                    }
                }
                record.error = Some(e.to_string());
                // Back out of the camera's view whatever happened. A grasp that failed
                // after closing leaves its object attached in the planning world: the
                // hand has let go of it, and the next frame sees where it fell.
                let _ = driver.open(&gripper.name);
                let _ = group.remove_object(&format!("obj:{}", objects[i].id));
                let _ = go_home(driver, robot, &mut group, &home);
                if matches!(e, ExecError::Driver(_)) {
                    report.log.push(record.clone());
                    watch(driver, ClearEvent::After(&record));
                    report.stop = format!("driver failed: {e}");
                    break;
                }
            }
        }
        watch(driver, ClearEvent::After(&record));
        if record.action != "grasp" {
            // Grasps are moments already (the hand takes and lets go); pushes are not.
            driver.annotate(&format!(
                "{} o{}{}",
                record.action,
                record.object,
                if record.ok { "" } else { " (failed)" }
            ));
        }
        tracing::info!(
            frame = record.frame,
            action = record.action.as_str(),
            object = record.object,
            ok = record.ok,
            error = record.error.as_deref().unwrap_or(""),
            "clear: action"
        );
        report.log.push(record);
    }
    let decisions: Vec<f64> = report.frames.iter().map(|f| f.decision_ms).collect();
    report.decision_ms = Stats::of(&decisions);
    let median = |f: fn(&FrameReport) -> f64| {
        Stats::of(&report.frames.iter().map(f).collect::<Vec<_>>()).median
    };
    report.perception_ms = median(|f| f.perception_ms);
    report.predicates_ms = median(|f| f.predicates_ms);
    report.planning_ms = median(|f| f.planning_ms);
    report.ik_ms = median(|f| f.ik_ms);
    Ok(report)
}

enum Decision {
    /// Object index, action, the IK solution found for its first pose, and the
    /// neighbours a nudge grasp pushes aside (empty otherwise).
    Act(usize, ActionKind, Vec<f64>, Vec<usize>),
    NoPlan,
    NothingRemovable,
}

/// Plans, then checks IK for the first action only; an infeasible action becomes an
/// `ik_unfeasible_*` fact and the planner runs again (SPEC §3.5). Facts the tracks
/// already know (pushes back, too many pushes or grasp attempts, grasps too wide,
/// pushes off the table) are set before the first plan: every lazily discovered
/// infeasibility is an `ik_unfeasible_*` fact to the domain.
#[allow(clippy::too_many_arguments)]
fn decide(
    objects: &[SeenObject],
    g: &Geometry,
    tracks: &[Track],
    domain: &tabula_pddl::Domain,
    group: &mut MoveGroup,
    robot: &NamedRobot,
    state: &tabula_robot::driver::JointState,
    params: &ClearParams,
    fr: &mut FrameReport,
    report: &mut ClearReport,
) -> Decision {
    let n = objects.len();
    let all: Vec<usize> = (0..n).collect();
    // Objects no grasp of this gripper can hold never leave the table: out of the goal.
    let goal: Vec<usize> = all
        .iter()
        .copied()
        .filter(|&i| g.grasps[i].is_some())
        .collect();
    report.dropped_from_goal = report.dropped_from_goal.max(n - goal.len());
    if goal.is_empty() {
        return Decision::NothingRemovable;
    }
    let text = problem_text(objects, g, &goal);
    let trace = tracing::enabled!(tracing::Level::DEBUG);
    if trace {
        for (i, o) in objects.iter().enumerate() {
            tracing::debug!(
                "o{}: centre ({:.3}, {:.3}) rect {:.3} × {:.3}, bottom {:.3} top {:.3}, grasp {}",
                o.id,
                o.rect.center.x,
                o.rect.center.y,
                o.rect.size.x,
                o.rect.size.y,
                o.bottom,
                o.top,
                if g.grasps[i].is_some() {
                    "fits"
                } else {
                    "too wide"
                }
            );
        }
        tracing::debug!("{text}");
    }
    let Ok(problem) = tabula_pddl::parse_problem(&text, domain) else {
        return Decision::NoPlan;
    };
    let Ok(mut planner) = Planner::for_table_clearing(domain.clone(), problem) else {
        return Decision::NoPlan;
    };
    for (i, o) in objects.iter().enumerate() {
        let track = tracks.iter().find(|t| t.id == o.id);
        let mut set = |kind: ActionKind| {
            let _ = planner.set_fact(&infeasible_atom(kind, o.id), true);
        };
        if g.grasps[i].is_none()
            || track.is_some_and(|t| t.grasp_attempts >= params.max_grasp_attempts)
        {
            set(ActionKind::Grasp);
        }
        for k in 0..4 {
            let p = &g.pushes[i][k];
            if !p.feasible || track.is_some_and(|t| t.rules_out(p.direction, params)) {
                set(ActionKind::Push(k));
            }
        }
    }
    // The group sees the objects (the target is taken out per pose below).
    let _ = group.set_state(robot, state);
    for name in group.world.object_names() {
        if name.starts_with("obj:") {
            let _ = group.remove_object(&name);
        }
    }
    for o in objects {
        let _ = group.add_object(&format!("obj:{}", o.id), o.hull.clone(), Pose::IDENTITY);
    }
    let seed = group.arm_values(state);
    let mode = if n <= params.optimal_up_to {
        SearchMode::Optimal
    } else {
        SearchMode::Fast
    };
    let timeout = Some(Duration::from_secs_f64(params.plan_timeout_s.max(1e-3)));
    for _ in 0..(5 * n + 5) {
        let plan = match planner.plan(mode, timeout) {
            Ok(p) => p,
            Err(tabula_pddl::NoPlan::Unsolvable) => {
                // Objects that can never be removed leave the goal (SPEC §3.5) — again
                // after every IK backtrack that makes more of them so.
                match planner.drop_unreachable_goals(timeout) {
                    Ok(d) if !d.is_empty() => {
                        report.dropped_from_goal = report.dropped_from_goal.max(d.len());
                        if planner.goal_atoms().is_some_and(|a| a.is_empty()) {
                            return Decision::NothingRemovable;
                        }
                        continue;
                    }
                    _ => return Decision::NothingRemovable,
                }
            }
            Err(_) => return Decision::NoPlan,
        };
        fr.plan = plan.steps.iter().map(|s| s.to_string()).collect();
        let Some(first) = plan.steps.first() else {
            return Decision::NothingRemovable;
        };
        let Some(i) = first
            .args
            .first()
            .and_then(|a| a.strip_prefix('o'))
            .and_then(|id| id.parse::<usize>().ok())
            .and_then(|id| objects.iter().position(|o| o.id == id))
        else {
            return Decision::NoPlan;
        };
        let kind = if first.action == "grasp" {
            ActionKind::Grasp
        } else {
            match DIRECTIONS
                .iter()
                .position(|d| first.action == format!("push_{d}"))
            {
                Some(k) => ActionKind::Push(k),
                None => return Decision::NoPlan,
            }
        };
        let c = thread_cpu();
        let ik = first_pose_ik(group, objects, i, kind, g, &seed, &[], params);
        fr.ik_ms += (thread_cpu() - c) * 1e3;
        match ik {
            Some(q) => return Decision::Act(i, kind, q, Vec::new()),
            None => {
                fr.ik_backtracks += 1;
                let _ = planner.set_fact(&infeasible_atom(kind, objects[i].id), true);
            }
        }
    }
    Decision::NoPlan
}

/// The chain-push fallback (packed objects, where the seed's actions are stuck): the
/// domain cannot tell what a push that shoves others along achieves, so the pushes are
/// ranked by a one-step look-ahead in geometry — how many objects each makes
/// graspable, then how few it shoves — and the first whose poses have IK is taken.
#[allow(clippy::too_many_arguments)]
fn decide_chain(
    objects: &[SeenObject],
    g: &Geometry,
    tracks: &[Track],
    group: &mut MoveGroup,
    robot: &NamedRobot,
    state: &tabula_robot::driver::JointState,
    params: &ClearParams,
    fr: &mut FrameReport,
) -> Decision {
    let mut candidates: Vec<(usize, usize)> = Vec::new();
    for (i, o) in objects.iter().enumerate() {
        let track = tracks.iter().find(|t| t.id == o.id);
        let stacked = g.on.iter().any(|&(a, b)| a == i || b == i);
        for k in 0..4 {
            let p = &g.pushes[i][k];
            let ruled_out = track.is_some_and(|t| t.rules_out(p.direction, params));
            if p.feasible && !ruled_out && !stacked && !g.block_push[k].iter().any(|&(_, b)| b == i)
            {
                candidates.push((i, k));
            }
        }
    }
    candidates.sort_by_key(|&(i, k)| {
        let p = &g.pushes[i][k];
        (std::cmp::Reverse(p.gain), p.chain.len())
    });
    let _ = group.set_state(robot, state);
    let seed = group.arm_values(state);
    for (i, k) in candidates {
        fr.plan = vec![format!(
            "(push_{} o{}) [chain]",
            DIRECTIONS[k], objects[i].id
        )];
        let c = thread_cpu();
        let ik = first_pose_ik(
            group,
            objects,
            i,
            ActionKind::Push(k),
            g,
            &seed,
            &[],
            params,
        );
        fr.ik_ms += (thread_cpu() - c) * 1e3;
        match ik {
            Some(q) => return Decision::Act(i, ActionKind::Push(k), q, Vec::new()),
            None => fr.ik_backtracks += 1,
        }
    }
    Decision::NothingRemovable
}

/// The last resort (see [`ClearParams::nudge_depth`]): grasps of objects nothing stands
/// on whose open fingers, at the grasp and on the way down to it, reach at most
/// `nudge_depth` into their blockers' hulls — shallowest first, the first with IK.
#[allow(clippy::too_many_arguments)]
fn decide_nudge(
    objects: &[SeenObject],
    g: &Geometry,
    tracks: &[Track],
    hand: &Hand,
    table: &Table,
    group: &mut MoveGroup,
    robot: &NamedRobot,
    state: &tabula_robot::driver::JointState,
    params: &ClearParams,
    fr: &mut FrameReport,
) -> Decision {
    let mut candidates: Vec<(f64, usize, Vec<usize>)> = Vec::new();
    for (i, o) in objects.iter().enumerate() {
        let Some(grasp) = &g.grasps[i] else { continue };
        let tried_enough = tracks
            .iter()
            .find(|t| t.id == o.id)
            .is_some_and(|t| t.grasp_attempts >= params.max_grasp_attempts);
        if tried_enough || g.on.iter().any(|&(_, under)| under == i) {
            continue;
        }
        let blockers: Vec<usize> = g
            .block_grasp
            .iter()
            .filter(|&&(_, b)| b == i)
            .map(|&(a, _)| a)
            .collect();
        if blockers.is_empty() {
            continue;
        }
        let poses = descent_poses(&grasp.poses[0], table.up, params.pregrasp);
        let shapes = hand.open_for(grasp.width).1;
        let depth = blockers
            .iter()
            .map(|&a| penetration(shapes, &poses, &objects[a]))
            .fold(0.0, f64::max);
        if depth <= params.nudge_depth {
            candidates.push((depth, i, blockers));
        }
    }
    candidates.sort_by(|a, b| a.0.total_cmp(&b.0));
    let _ = group.set_state(robot, state);
    let seed = group.arm_values(state);
    for (depth, i, nudged) in candidates {
        fr.plan = vec![format!(
            "(grasp o{}) [nudging {} by {:.1} mm]",
            objects[i].id,
            nudged
                .iter()
                .map(|&a| format!("o{}", objects[a].id))
                .collect::<Vec<_>>()
                .join(" "),
            depth * 1e3
        )];
        let c = thread_cpu();
        let ik = first_pose_ik(
            group,
            objects,
            i,
            ActionKind::Grasp,
            g,
            &seed,
            &nudged,
            params,
        );
        fr.ik_ms += (thread_cpu() - c) * 1e3;
        match ik {
            Some(q) => return Decision::Act(i, ActionKind::Grasp, q, nudged),
            None => fr.ik_backtracks += 1,
        }
    }
    Decision::NothingRemovable
}

/// How deep (m) `shapes` at any of `poses` reach into `other`'s hull (0 when apart).
fn penetration(shapes: &[(SharedShape, Pose)], poses: &[Pose], other: &SeenObject) -> f64 {
    let mut deepest: f64 = 0.0;
    for pose in poses {
        for (s, p) in shapes {
            let w = *pose * *p;
            if !s.compute_aabb(&w).intersects(&other.aabb) {
                continue;
            }
            if let Ok(Some(c)) =
                query::contact(&w, s.as_ref(), &Pose::IDENTITY, other.hull.as_ref(), 0.0)
            {
                deepest = deepest.max(-c.dist);
            }
        }
    }
    deepest
}

/// The poses an action must reach, first one first: pre-grasp and grasp, or pre-push,
/// push start and push end.
fn action_poses(
    kind: ActionKind,
    grasp: Option<&Grasp>,
    push: &[Push; 4],
    yaw: usize,
    up: Vec3,
    params: &ClearParams,
) -> Vec<Pose> {
    match kind {
        ActionKind::Grasp => {
            let Some(g) = grasp.map(|g| g.poses[yaw]) else {
                return Vec::new();
            };
            vec![
                Pose::from_parts(g.translation + up * params.pregrasp, g.rotation),
                g,
            ]
        }
        ActionKind::Push(k) => {
            let p = &push[k];
            let d3 = Vec3::new(p.direction.x, p.direction.y, 0.0);
            vec![
                Pose::from_parts(
                    p.start.translation + up * params.pre_push_height,
                    p.start.rotation,
                ),
                p.start,
                Pose::from_parts(
                    p.start.translation + d3 * p.travel(params),
                    p.start.rotation,
                ),
            ]
        }
    }
}

/// IK (collision-free, the target object out of the world) for every pose of the
/// action, the gripper at either yaw; the solution of the first pose when all have one.
#[allow(clippy::too_many_arguments)]
fn first_pose_ik(
    group: &mut MoveGroup,
    objects: &[SeenObject],
    i: usize,
    kind: ActionKind,
    g: &Geometry,
    seed: &[f64],
    nudged: &[usize],
    params: &ClearParams,
) -> Option<Vec<f64>> {
    let up = Vec3::Z;
    // The target, what a chain push shoves along and what a nudge grasp pushes aside
    // move: out of the world here.
    let mut moving = vec![i];
    moving.extend(nudged);
    if let ActionKind::Push(k) = kind {
        moving.extend(&g.pushes[i][k].chain);
    }
    for &m in &moving {
        let _ = group.remove_object(&format!("obj:{}", objects[m].id));
    }
    let yaws: &[usize] = match kind {
        ActionKind::Grasp => &[0, 1],
        ActionKind::Push(_) => &[0],
    };
    let mut found = None;
    'yaw: for &yaw in yaws {
        let poses = action_poses(kind, g.grasps[i].as_ref(), &g.pushes[i], yaw, up, params);
        let mut first = None;
        let mut from = seed.to_vec();
        for p in &poses {
            match group.valid_ik(p, &from) {
                Ok(sols) => {
                    from = sols[0].clone();
                    first.get_or_insert(sols[0].clone());
                }
                Err(e) => {
                    if tracing::enabled!(tracing::Level::DEBUG) {
                        tracing::debug!(
                            "IK {} o{} yaw {yaw} at ({:.3}, {:.3}, {:.3}): {e}",
                            kind.pddl(),
                            objects[i].id,
                            p.translation.x,
                            p.translation.y,
                            p.translation.z
                        );
                    }
                    continue 'yaw;
                }
            }
        }
        found = first;
        break;
    }
    for &m in &moving {
        let _ = group.add_object(
            &format!("obj:{}", objects[m].id),
            objects[m].hull.clone(),
            Pose::IDENTITY,
        );
    }
    found
}

/// The `k`-th spot of a 3 × 3 grid over the drop square (centre first, then around).
fn drop_offset(k: usize, spread: f64) -> Vec3 {
    const SPOTS: [(f64, f64); 9] = [
        (0.0, 0.0),
        (1.0, 1.0),
        (-1.0, -1.0),
        (1.0, -1.0),
        (-1.0, 1.0),
        (0.0, 1.0),
        (1.0, 0.0),
        (0.0, -1.0),
        (-1.0, 0.0),
    ];
    let (x, y) = SPOTS[k % SPOTS.len()];
    Vec3::new(x * spread, y * spread, 0.0)
}

/// Why an action failed while executing.
#[derive(Debug, Clone, thiserror::Error)]
enum ExecError {
    #[error("motion: {0}")]
    Motion(String),
    #[error("the gripper closed on nothing")]
    Slipped,
    #[error("driver: {0}")]
    Driver(String),
}

impl From<MoveError> for ExecError {
    fn from(e: MoveError) -> Self {
        ExecError::Motion(e.to_string())
    }
}

impl From<DriverError> for ExecError {
    fn from(e: DriverError) -> Self {
        ExecError::Driver(e.to_string())
    }
}

fn current_arm(driver: &mut impl RobotDriver, group: &MoveGroup) -> Result<Vec<f64>, ExecError> {
    Ok(group.arm_values(&driver.joint_state()?))
}

fn run(driver: &mut impl RobotDriver, plan: &Plan, phase: &str) -> Result<(), ExecError> {
    if tracing::enabled!(tracing::Level::DEBUG) {
        let t = driver.joint_state().map(|s| s.stamp).unwrap_or(f64::NAN);
        tracing::debug!(
            "exec {phase} from t = {t:.2} s ({:.2} s)",
            plan.trajectory.duration()
        );
    }
    Ok(driver.execute(&plan.trajectory)?)
}

fn go_home(
    driver: &mut impl RobotDriver,
    robot: &NamedRobot,
    group: &mut MoveGroup,
    home: &[f64],
) -> Result<(), ExecError> {
    let state = driver.joint_state()?;
    group.set_state(robot, &state)?;
    let q = group.arm_values(&state);
    let plan = group.plan_to_joints(&q, &[home.to_vec()])?;
    run(driver, &plan, "home")
}

#[allow(clippy::too_many_arguments)]
fn execute_grasp(
    driver: &mut impl RobotDriver,
    robot: &NamedRobot,
    group: &mut MoveGroup,
    objects: &[SeenObject],
    i: usize,
    grasp: &Grasp,
    ik: Vec<f64>,
    hand: &Hand,
    gripper: &Gripper,
    table: &Table,
    request: &ClearRequest,
    drop_count: usize,
    home: &[f64],
    nudged: &[usize],
    params: &ClearParams,
) -> Result<(), ExecError> {
    let o = &objects[i];
    let name = format!("obj:{}", o.id);
    driver.open_to(&gripper.name, grasp.width)?;
    let state = driver.joint_state()?;
    group.set_state(robot, &state)?;
    let q = group.arm_values(&state);
    // The yaw whose pre-grasp the decision solved.
    let yaw = (0..2)
        .min_by(|&a, &b| {
            let d = |y: usize| {
                group
                    .tip_pose(&ik)
                    .map(|p| p.rotation.angle_between(grasp.poses[y].rotation))
                    .unwrap_or(f64::INFINITY)
            };
            d(a).total_cmp(&d(b))
        })
        .unwrap_or(0);
    let g = grasp.poses[yaw];
    let pre = Pose::from_parts(g.translation + table.up * params.pregrasp, g.rotation);
    let to_pre = group
        .plan_to_joints(&q, std::slice::from_ref(&ik))
        .or_else(|_| group.plan_to_pose(&q, &pre))?;
    run(driver, &to_pre, "to pre-grasp")?;
    group.remove_object(&name)?;
    // A nudge grasp's fingers push these aside on the way down: out of the world until
    // the object is lifted.
    for &a in nudged {
        group.remove_object(&format!("obj:{}", objects[a].id))?;
    }
    let q = current_arm(driver, group)?;
    let down = group.cartesian(&q, &g)?;
    run(driver, &down, "descend")?;
    let held = driver.close(&gripper.name)?;
    let q = current_arm(driver, group)?;
    if !held.holding {
        let up = group.cartesian(&q, &pre)?;
        run(driver, &up, "back up")?;
        group.add_object(&name, o.hull.clone(), Pose::IDENTITY)?;
        return Err(ExecError::Slipped);
    }
    // The held hull leaves what it stood on: its bottom is taken off (it touches the
    // table at the start of the lift, as the object does).
    let raised: Vec<Vec3> = hull_vertices(&o.hull)
        .into_iter()
        .map(|p| Vec3::new(p.x, p.y, p.z.max(o.bottom + 0.02)))
        .collect();
    let held_hull = SharedShape::convex_hull(&raised).unwrap_or_else(|| o.hull.clone());
    let tool = group.tip_pose(&q)?;
    group.attach(&name, held_hull, tool.inverse())?;
    // Straight up cannot hit what stands beside the object: its neighbours (within the
    // padding of its hull) are out of the world while it lifts.
    let neighbours: Vec<&SeenObject> = objects
        .iter()
        .enumerate()
        .filter(|&(j, n)| j != i && hulls_touch(o, n, 0.02))
        .map(|(_, n)| n)
        .collect();
    for n in &neighbours {
        // (What a nudge grasp pushed aside is out already.)
        let _ = group.remove_object(&format!("obj:{}", n.id));
    }
    let lifted = Pose::from_parts(g.translation + table.up * params.lift, g.rotation);
    let lift = group.cartesian(&q, &lifted);
    for n in &neighbours {
        group.add_object(&format!("obj:{}", n.id), n.hull.clone(), Pose::IDENTITY)?;
    }
    run(driver, &lift?, "lift")?;
    for &a in nudged {
        let n = &objects[a];
        if !neighbours.iter().any(|x| x.id == n.id) {
            group.add_object(&format!("obj:{}", n.id), n.hull.clone(), Pose::IDENTITY)?;
        }
    }
    // Over the bin, the object's bottom `drop_clearance` above the drop point.
    let hang = g.translation.dot(table.up) - o.bottom;
    let over = request.drop_point
        + drop_offset(drop_count, request.drop_spread)
        + table.up * (params.drop_clearance + hang.max(0.0));
    let q = current_arm(driver, group)?;
    let mut last = Err(ExecError::Motion("no drop pose".into()));
    for a in 0..4 {
        let closing = Quat::from_rotation_z(a as f64 * std::f64::consts::FRAC_PI_4) * Vec3::X;
        let pose = hand.pose(over - table.up * hand.tip, closing, table.up);
        match group.plan_to_pose(&q, &pose) {
            Ok(p) => {
                last = Ok(p);
                break;
            }
            Err(e) => last = Err(e.into()),
        }
    }
    run(driver, &last?, "to the bin")?;
    driver.open(&gripper.name)?;
    group.remove_object(&name)?;
    go_home(driver, robot, group, home)
}

#[allow(clippy::too_many_arguments)]
fn execute_push(
    driver: &mut impl RobotDriver,
    robot: &NamedRobot,
    group: &mut MoveGroup,
    objects: &[SeenObject],
    i: usize,
    push: &Push,
    ik: Vec<f64>,
    gripper: &Gripper,
    table: &Table,
    home: &[f64],
    params: &ClearParams,
) -> Result<(), ExecError> {
    let o = &objects[i];
    let name = format!("obj:{}", o.id);
    let _ = driver.close(&gripper.name)?;
    let state = driver.joint_state()?;
    group.set_state(robot, &state)?;
    let q = group.arm_values(&state);
    let pre = Pose::from_parts(
        push.start.translation + table.up * params.pre_push_height,
        push.start.rotation,
    );
    let to_pre = group
        .plan_to_joints(&q, &[ik])
        .or_else(|_| group.plan_to_pose(&q, &pre))?;
    run(driver, &to_pre, "to pre-push")?;
    let q = current_arm(driver, group)?;
    let down = group.cartesian(&q, &push.start)?;
    run(driver, &down, "down to the push")?;
    // The pushed object (and what it shoves) moves with the fingers: out of the world
    // for the push.
    group.remove_object(&name)?;
    for &a in &push.chain {
        group.remove_object(&format!("obj:{}", objects[a].id))?;
    }
    let d3 = Vec3::new(push.direction.x, push.direction.y, 0.0);
    let end = Pose::from_parts(
        push.start.translation + d3 * push.travel(params),
        push.start.rotation,
    );
    let q = current_arm(driver, group)?;
    let along = group.cartesian(&q, &end)?;
    run(driver, &along, "push")?;
    // Back off the object before rising, so the fingers do not drag it up with them.
    let back = Pose::from_parts(end.translation - d3 * params.push_back_off, end.rotation);
    let q = current_arm(driver, group)?;
    if let Ok(off) = group.cartesian(&q, &back) {
        run(driver, &off, "back off")?;
    }
    let q = current_arm(driver, group)?;
    let up = Pose::from_parts(
        back.translation + table.up * params.pre_push_height,
        back.rotation,
    );
    let rise = group.cartesian(&q, &up)?;
    run(driver, &rise, "rise")?;
    go_home(driver, robot, group, home)
}

impl Validate for ClearParams {
    fn check(&self, at: &str) -> Result<(), String> {
        self.tabletop.check(&nested(at, "tabletop"))?;
        self.motion.check(&nested(at, "motion"))?;
        check_count(at, "decimate", self.decimate, 1)?;
        ClearParams::validate(self).map_err(|e| e.to_string())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A box standing at `center` (world xy) on the table at z 0.72 (or on `bottom`),
    /// seen as points on its top and sides every 5 mm.
    fn seen_box(id: usize, center: Vec2, size: Vec2, height: f64, bottom: f64) -> SeenObject {
        let mut points = Vec::new();
        let (nx, ny) = ((size.x / 0.005) as i32, (size.y / 0.005) as i32);
        for i in 0..=nx {
            for j in 0..=ny {
                let x = center.x - size.x / 2.0 + i as f64 * 0.005;
                let y = center.y - size.y / 2.0 + j as f64 * 0.005;
                points.push(Vec3::new(x, y, bottom + height));
                if i == 0 || j == 0 || i == nx || j == ny {
                    for k in 1..(height / 0.005) as i32 {
                        points.push(Vec3::new(x, y, bottom + k as f64 * 0.005));
                    }
                }
            }
        }
        let flat: Vec<Vec2> = points.iter().map(|q| q.truncate()).collect();
        let footprint: Vec<Vec2> = convex_hull_2d(&flat).iter().map(|&i| flat[i]).collect();
        let rect = min_area_rectangle(&footprint).unwrap();
        let mut hull_points = points.clone();
        hull_points.extend(footprint.iter().map(|p| Vec3::new(p.x, p.y, bottom)));
        let hull = SharedShape::convex_hull(&hull_points).unwrap();
        let aabb = hull.compute_aabb(&Pose::IDENTITY);
        SeenObject {
            id,
            points,
            footprint,
            rect,
            bottom,
            top: bottom + height,
            hull,
            aabb,
        }
    }

    fn table() -> Table {
        Table {
            z: 0.72,
            up: Vec3::Z,
            outline: vec![
                Vec2::new(0.3, -0.5),
                Vec2::new(0.9, -0.5),
                Vec2::new(0.9, 0.5),
                Vec2::new(0.3, 0.5),
            ],
        }
    }

    fn hand() -> Hand {
        let robot = tabula_robot::robots::load("wam").unwrap();
        let g = robot.description.grippers[0].clone();
        Hand::new(&robot, &g).unwrap()
    }

    #[test]
    fn the_hand_model_comes_from_the_urdf() {
        let h = hand();
        // The WAM's fingers: 6 cm long, tips 2.25 cm beyond the tool frame.
        assert!((h.finger_length - 0.06).abs() < 1e-9, "{}", h.finger_length);
        assert!((h.tip - 0.0225).abs() < 1e-9, "{}", h.tip);
        assert_eq!(h.open_width, 0.07);
    }

    #[test]
    fn a_box_on_a_box_is_on_it_and_blocks_nothing_else() {
        let base = seen_box(0, Vec2::new(0.6, 0.0), Vec2::new(0.06, 0.06), 0.05, 0.72);
        let top = seen_box(1, Vec2::new(0.6, 0.0), Vec2::new(0.04, 0.04), 0.04, 0.77);
        let lone = seen_box(2, Vec2::new(0.6, 0.3), Vec2::new(0.05, 0.05), 0.08, 0.72);
        let objects = vec![base, top, lone];
        assert_eq!(on_pairs(&objects, 0.72), vec![(1, 0)]);
        let g = predicates(&objects, &table(), &hand(), &ClearParams::default(), false);
        // The lone box is free in every way; nothing blocks grasping the top one.
        assert!(
            g.block_grasp
                .iter()
                .all(|&(a, b)| a != 2 && b != 2 && b != 1)
        );
        assert!(
            g.block_push
                .iter()
                .flatten()
                .all(|&(a, b)| a != 2 && b != 2)
        );
        assert!(g.grasps.iter().all(Option::is_some));
    }

    #[test]
    fn touching_boxes_block_the_grasp_across_them_and_the_push_into_each_other() {
        // Two boxes side by side along x, 2 mm apart, the right one 3 cm lower. Closing
        // across `a` at full depth puts a finger in the gap; held only 2 cm deep, the
        // fingertips pass over `b`.
        let a = seen_box(0, Vec2::new(0.6, 0.0), Vec2::new(0.04, 0.075), 0.08, 0.72);
        let b = seen_box(1, Vec2::new(0.647, 0.0), Vec2::new(0.05, 0.05), 0.05, 0.72);
        let objects = vec![a, b];
        let g = predicates(&objects, &table(), &hand(), &ClearParams::default(), false);
        assert!(!g.block_grasp.contains(&(1, 0)), "{:?}", g.block_grasp);
        let full_depth_only = ClearParams {
            shallow_grip: 1.0,
            ..ClearParams::default()
        };
        let g = predicates(&objects, &table(), &hand(), &full_depth_only, false);
        assert!(g.block_grasp.contains(&(1, 0)), "{:?}", g.block_grasp);
        // Pushing `a` into `b` is blocked; along y it slides past `b` (grazing is
        // allowed, the palm passes above the lower box) until its grasp is free.
        let into_b = (0..4).find(|&k| g.pushes[0][k].direction.x > 0.9).unwrap();
        let along = (0..4).find(|&k| g.pushes[0][k].direction.y > 0.9).unwrap();
        assert!(g.block_push[into_b].contains(&(1, 0)));
        assert!(!g.block_push[along].contains(&(1, 0)), "{:?}", g.block_push);
        let p = &g.pushes[0][along];
        assert!(p.length > 0.05 && p.length < 0.12, "{}", p.length);
    }

    #[test]
    fn a_blob_too_wide_is_grasped_by_its_narrow_part() {
        // Two boxes segmentation could not tell apart: 4 × 7.5 cm beside 5 × 5 cm.
        let a = seen_box(0, Vec2::new(0.60, 0.0), Vec2::new(0.04, 0.075), 0.09, 0.72);
        let b = seen_box(0, Vec2::new(0.6455, 0.0), Vec2::new(0.05, 0.05), 0.09, 0.72);
        let mut points = a.points.clone();
        points.extend(b.points);
        let flat: Vec<Vec2> = points.iter().map(|q| q.truncate()).collect();
        let footprint: Vec<Vec2> = convex_hull_2d(&flat).iter().map(|&i| flat[i]).collect();
        let blob = SeenObject {
            rect: min_area_rectangle(&footprint).unwrap(),
            footprint,
            points,
            ..a
        };
        let h = hand();
        assert!(blob.rect.size.x.min(blob.rect.size.y) > h.open_width);
        let parts = part_grasps(&blob, &h, &ClearParams::default());
        assert!(!parts.is_empty());
        // The narrowest part is the square box's.
        assert!((parts[0].0.x - 0.645).abs() < 0.015, "{:?}", parts[0]);
        assert_eq!(
            grasps_of(&blob, &h, &table(), &ClearParams::default()).len(),
            parts.len()
        );
    }

    #[test]
    fn tracks_follow_objects_and_pushes_where_they_went() {
        let mut tracks = Vec::new();
        let mut first = vec![
            seen_box(0, Vec2::new(0.6, 0.0), Vec2::new(0.05, 0.05), 0.08, 0.72),
            seen_box(0, Vec2::new(0.6, 0.2), Vec2::new(0.05, 0.05), 0.08, 0.72),
        ];
        track(&mut first, &mut tracks, 0.06, 0.35);
        assert_eq!((first[0].id, first[1].id), (0, 1));
        // Object 1 was pushed 10 cm along +x; object 0 did not move.
        tracks[1].expected = Vec2::new(0.7, 0.2);
        let mut next = vec![
            seen_box(0, Vec2::new(0.705, 0.2), Vec2::new(0.05, 0.05), 0.08, 0.72),
            seen_box(0, Vec2::new(0.6, 0.0), Vec2::new(0.05, 0.05), 0.08, 0.72),
            seen_box(0, Vec2::new(0.4, -0.3), Vec2::new(0.05, 0.05), 0.08, 0.72),
        ];
        track(&mut next, &mut tracks, 0.06, 0.35);
        assert_eq!((next[0].id, next[1].id, next[2].id), (1, 0, 2));
    }

    /// How far the open hand reaches into a neighbour: nothing when it is clear, about
    /// the overlap when a finger comes down a few millimetres into it.
    #[test]
    fn penetration_measures_how_far_the_fingers_reach_into_a_neighbour() {
        let h = hand();
        let target = seen_box(0, Vec2::new(0.6, 0.0), Vec2::new(0.04, 0.04), 0.08, 0.72);
        let params = ClearParams::default();
        let g = grasps_of(&target, &h, &table(), &params).remove(0);
        let shapes = h.open_for(g.width).1;
        let poses = descent_poses(&g.poses[0], Vec3::Z, params.pregrasp);
        // Neighbours beside it along the closing axis, nearer and nearer: clear, then
        // reached into by as much as they come nearer.
        let closing = (g.poses[0].rotation * h.closing).truncate().normalize();
        let (_, outer) = extent_along(shapes, h.closing);
        let beside = |gap: f64| {
            let c = target.rect.center + closing * (outer + gap + 0.02);
            seen_box(1, c, Vec2::new(0.04, 0.04), 0.08, 0.72)
        };
        assert_eq!(penetration(shapes, &poses, &beside(0.01)), 0.0);
        let (near, nearer) = (
            penetration(shapes, &poses, &beside(-0.01)),
            penetration(shapes, &poses, &beside(-0.02)),
        );
        assert!(near > 0.0);
        assert!((nearer - near - 0.01).abs() < 1e-3, "{near} {nearer}");
    }

    /// A push that moved its object less than a third of its length jammed: that way is
    /// ruled out; one that went most of the way is not.
    #[test]
    fn a_jammed_push_is_not_tried_that_way_again() {
        let params = ClearParams::default();
        let mut tracks = Vec::new();
        let mut first = vec![
            seen_box(0, Vec2::new(0.6, 0.0), Vec2::new(0.05, 0.05), 0.08, 0.72),
            seen_box(0, Vec2::new(0.6, 0.2), Vec2::new(0.05, 0.05), 0.08, 0.72),
        ];
        track(&mut first, &mut tracks, 0.06, params.push_jam_share);
        // Both pushed 6 cm along +x: the first moves 1 cm, the second 5 cm.
        for (t, o) in tracks.iter_mut().zip(&first) {
            t.pushes.push(Vec2::X);
            t.expected = o.rect.center + Vec2::X * 0.06;
            t.pending = Some((Vec2::X, 0.06, o.rect.center));
        }
        let mut next = vec![
            seen_box(0, Vec2::new(0.61, 0.0), Vec2::new(0.05, 0.05), 0.08, 0.72),
            seen_box(0, Vec2::new(0.65, 0.2), Vec2::new(0.05, 0.05), 0.08, 0.72),
        ];
        track(&mut next, &mut tracks, 0.06, params.push_jam_share);
        assert_eq!((next[0].id, next[1].id), (0, 1));
        assert!(tracks[0].rules_out(Vec2::X, &params));
        assert!(!tracks[1].rules_out(Vec2::X, &params));
        assert!(tracks.iter().all(|t| t.pending.is_none()));
    }

    #[test]
    fn drops_go_around_the_bin() {
        let spots: Vec<Vec3> = (0..9).map(|k| drop_offset(k, 0.1)).collect();
        assert_eq!(spots[0], Vec3::ZERO);
        for (i, a) in spots.iter().enumerate() {
            assert!(a.x.abs() <= 0.1 && a.y.abs() <= 0.1);
            assert!(spots[i + 1..].iter().all(|b| b != a));
        }
        assert_eq!(drop_offset(9, 0.1), spots[0]);
    }

    #[test]
    fn params_load_from_toml_with_the_seed_defaults_elsewhere() {
        let p: ClearParams =
            toml::from_str("push_distance = 0.05\n[tabletop]\nmin_object_points = 150\n").unwrap();
        assert_eq!(p.push_distance, 0.05);
        assert_eq!(p.tabletop.min_object_points, 150);
        assert_eq!(p.push_max_length, 0.6);
        assert_eq!(p.push_resolution, 0.03);
        assert_eq!(p.pregrasp, 0.10);
        assert_eq!(p.lift, 0.20);
        assert!(toml::from_str::<ClearParams>("nope = 1").is_err());
        assert!(p.validate().is_ok());
        for bad in [
            "push_resolution = 0.0",
            "push_max_length = inf",
            "clearance = nan",
            "decimate = 0",
            "chain_push_factors = [-1.0]",
        ] {
            let q: ClearParams = toml::from_str(bad).unwrap();
            assert_eq!(q.validate().unwrap_err().kind(), "params", "{bad}");
        }
    }
}
