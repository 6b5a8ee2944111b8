//! The collision world of a planning problem: one robot's links (URDF collision
//! geometry, padded), the objects around it, objects attached to links, and an allowed
//! collision matrix computed the way MoveIt's setup assistant does.

mod allowed;
mod check;
mod clearance;
mod cover;
mod edit;
mod gjk;
mod objects;
mod pair_table;
mod placed;
mod sweep;

pub use allowed::AllowedCollisions;
pub use clearance::Keep;
pub use edit::IgnoredJoints;
pub use sweep::SweepRates;

use cover::Cover;
use gjk::Hull;
use pair_table::PairTables;
use placed::{Outer, Placed};

use std::cell::Cell;
use std::collections::HashSet;
use tabula_geom::input::{Validate, check_in, check_non_negative};
use tabula_geom::parry::bounding_volume::Aabb;
use tabula_geom::parry::partitioning::{Bvh, BvhBuildStrategy};
use tabula_geom::parry::query;
use tabula_geom::parry::shape::SharedShape;
use tabula_geom::{Pose, Quat, Vec3};
use tabula_robot::model::Geometry;
use tabula_robot::{Chain, RobotError, RobotModel};

/// Why a world or a query is refused.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum WorldError {
    #[error("{0}")]
    Robot(String),
    #[error("expected {expected} joint values, got {got}")]
    WrongLength { expected: usize, got: usize },
    #[error("joint values must be finite")]
    NonFinite,
    #[error("no object named `{0}`")]
    UnknownObject(String),
    #[error("object `{0}` is already in the world")]
    NameTaken(String),
}

impl From<RobotError> for WorldError {
    fn from(e: RobotError) -> Self {
        WorldError::Robot(e.to_string())
    }
}

/// Parameters of the collision world.
#[derive(Debug, Clone, serde::Deserialize, serde::Serialize)]
#[serde(default, deny_unknown_fields)]
pub struct WorldParams {
    /// Extra clearance around every robot link (m) — SPEC §1.1's 0.9 cm self-filter
    /// padding is the same idea for perception; planning uses 1 cm by default.
    pub padding: f64,
    /// Random configurations sampled to find link pairs that never collide (MoveIt's
    /// setup assistant uses thousands).
    pub acm_samples: usize,
    pub acm_seed: u64,
    /// Pairs colliding in at least this fraction of the samples count as "always in
    /// collision" (MoveIt setup assistant's 95 %).
    pub always_fraction: f64,
    /// Padding of particular links (by name), instead of `padding` — e.g. more around a
    /// gripper that must not brush the table.
    pub link_padding: std::collections::BTreeMap<String, f64>,
    /// Edges are checked at configurations so close that no point of the robot moves
    /// more than this between two (m). With the padding at least this large, a path
    /// whose checked configurations are all valid cannot touch anything in between.
    pub max_step_displacement: f64,
    /// The robot's SRDF: when it has an allowed-collision matrix, that matrix is used
    /// (adjacent links always allowed) and nothing is sampled, as MoveIt does.
    #[serde(skip)]
    pub srdf: Option<tabula_robot::srdf::Srdf>,
}

impl Default for WorldParams {
    fn default() -> Self {
        Self {
            padding: 0.01,
            acm_samples: 5000,
            acm_seed: 0,
            always_fraction: 0.95,
            link_padding: Default::default(),
            max_step_displacement: 0.01,
            srdf: None,
        }
    }
}

#[derive(Clone)]
struct LinkBody {
    link: usize,
    name: String,
    padding: f64,
    shapes: Vec<(SharedShape, Pose)>,
    /// Each shape's sphere cover (in the link frame, like the shapes).
    covers: Vec<Cover>,
    /// Each shape's climbing hull, when it is a mesh hull.
    hulls: Vec<Option<Hull>>,
    /// For a link of several pieces (a convex decomposition): the hull of them all,
    /// queried first — when it is clear, every piece is.
    outer: Option<Outer>,
    /// Moves with the planning joints.
    moving: bool,
    /// A ball (link frame) holding every piece's cover: a check places the pieces only
    /// where this ball comes within the padding of something. `None` without shapes.
    bound: Option<(Vec3, f64)>,
}

/// A fixed object in the world.
#[derive(Clone)]
pub struct WorldObject {
    pub name: String,
    pub shape: SharedShape,
    pub world_from_object: Pose,
    aabb: Aabb,
    /// Robot bodies allowed to touch it (a planning scene's matrix).
    allowed_bodies: Vec<usize>,
}

/// An object carried by a link (e.g. held in the gripper): checked against the world and
/// the robot except `touch_links`.
#[derive(Clone)]
pub struct Attached {
    pub name: String,
    pub shape: SharedShape,
    pub link_from_object: Pose,
    body: usize,
    touch: Vec<usize>,
}

/// Robot, objects and allowed collisions, for checking configurations of one chain.
/// Cloning keeps the (costly to sample) allowed collision matrix.
#[derive(Clone)]
pub struct CollisionWorld {
    model: RobotModel,
    pub chain: Chain,
    world_from_root: Pose,
    /// Values of every joint (indexed like the model's); the chain's are overwritten per query.
    values: Vec<f64>,
    bodies: Vec<LinkBody>,
    allowed: HashSet<(usize, usize)>,
    /// `allowed` as a dense symmetric matrix (bodies × bodies), for the hot loop.
    allowed_matrix: Vec<bool>,
    /// The robot's body pairs a check tests ([`Self::self_pair_checked`]), listed.
    checked_pairs: Vec<(usize, usize)>,
    /// Entries placing every body takes (pieces and outer hulls).
    pieces: usize,
    objects: Vec<WorldObject>,
    /// Broad phase over the world objects' boxes.
    objects_bvh: Bvh,
    /// Each object's box, packed for the scans of small scenes.
    object_boxes: Vec<Aabb>,
    attached: Vec<Attached>,
    pub params: WorldParams,
    checks: Cell<u64>,
    /// Buffers one check fills and the next reuses.
    scratch: std::cell::RefCell<Scratch>,
    /// Per chain variable: an upper bound on how far any point of the robot (and what it
    /// holds) can be from that joint's axis — so a joint step Δ moves no point by more
    /// than `radius · Δ`.
    motion_radius: Vec<f64>,
    /// Per chain element and body (`element · bodies + body`): how far the body's points
    /// can be from the element's joint origin (see [`SweepRates`]); empty when unanchored.
    levers: Vec<f64>,
    /// Distances of the robot's pairs that move by one or two joints, remembered.
    pair_tables: PairTables,
    /// How to place each body without full forward kinematics (see [`Anchor`]).
    anchors: Vec<Anchor>,
    /// Model joint of each chain element (descending chains only).
    element_joints: Option<Vec<usize>>,
    world_from_chain_base: Pose,
}

/// What a check fills per configuration, kept between checks.
#[derive(Clone, Default)]
struct Scratch {
    /// Every body's pose, only where the bodies could not be anchored
    /// ([`CollisionWorld::frames_into`]).
    poses: Vec<Pose>,
    /// The chain's frames after each element, in the world.
    frames: Vec<Pose>,
    balls: Vec<(Vec3, f64)>,
    /// Per body: where its entries are once placed ([`placed::OnDemand`]).
    spans: Vec<Option<std::ops::Range<usize>>>,
    /// Per body: its bounding ball in the world.
    bounds: Vec<Option<(Vec3, f64)>>,
}

/// A body's pose from the chain: `world_from_chain_base · F_k(q) · offset`, where `F_k`
/// is the chain's frame after element `k` (`None`: the body does not move; `offset` is
/// then its world pose). Computed once, so a check is one pass over the chain.
#[derive(Clone, Copy)]
struct Anchor {
    element: Option<usize>,
    offset: Pose,
    /// The body's bounding ball in the element's frame (`offset` applied).
    bound: Option<(Vec3, f64)>,
}

/// Per link: does a chain joint (or a joint mimicking one) lie on its path to the root?
fn moving_links(model: &RobotModel, chain: &Chain) -> Vec<bool> {
    let chain_joints: HashSet<usize> = chain.joint_indices.iter().copied().collect();
    (0..model.links.len())
        .map(|mut l| {
            while let Some(j) = model.links[l].parent_joint {
                if chain_joints.contains(&j)
                    || model.joints[j]
                        .mimic
                        .as_ref()
                        .is_some_and(|m| chain_joints.contains(&m.master))
                {
                    return true;
                }
                l = model.joints[j].parent;
            }
            false
        })
        .collect()
}

/// Distance bounds from each joint to the tip, plus the largest shape beyond it (a
/// gripper, a held object) as a margin; tightened once anchors are known.
fn coarse_motion_radius(chain: &Chain) -> Vec<f64> {
    let largest_shape = 0.3;
    let mut motion_radius = vec![0.0; chain.dof()];
    let mut tail = chain.tip_offset.translation.length() + largest_shape;
    for e in chain.elements.iter().rev() {
        motion_radius[e.var] = f64::max(motion_radius[e.var], tail * e.multiplier.abs());
        tail += e.pre.translation.length();
        if e.prismatic {
            motion_radius[e.var] = motion_radius[e.var].max(e.multiplier.abs());
        }
    }
    motion_radius
}

/// A link shape for planning: a mesh as its convex hull when that hull is within 5 % of
/// the mesh's volume, else as its convex decomposition (a hull can be far bigger than
/// the link: the PR2's torso shell would swallow its own tucked fingers); decompositions
/// are cached on disk. A mesh that cannot be read is an error naming the link: a link
/// planned without its geometry would let paths pass through it.
fn shape_of(link: &str, g: &Geometry) -> Result<(SharedShape, Pose), WorldError> {
    g.collision_shape(true)
        .map_err(|m| WorldError::Robot(format!("link `{link}`: collision geometry: {m}")))
}

impl CollisionWorld {
    /// The world of `chain` of `model` placed at `world_from_root`, other joints at
    /// `fixed_values` (all joints, model order; `None` = mid-range), with the allowed
    /// collision matrix computed by sampling.
    pub fn new(
        model: RobotModel,
        chain: Chain,
        world_from_root: Pose,
        fixed_values: Option<Vec<f64>>,
        params: WorldParams,
    ) -> Result<Self, WorldError> {
        let values = fixed_values.unwrap_or_else(|| model.mid_configuration());
        if values.len() != model.joints.len() {
            return Err(WorldError::WrongLength {
                expected: model.joints.len(),
                got: values.len(),
            });
        }
        let moves = moving_links(&model, &chain);
        let mut bodies = Vec::new();
        for (li, link) in model.links.iter().enumerate() {
            let mut shapes: Vec<(SharedShape, Pose)> = Vec::new();
            for s in &link.collision {
                let (shape, local) = shape_of(&link.name, &s.geometry)?;
                // A decomposition's pieces stand alone: each gets its own box, cover
                // and hull, and only the pieces near something are queried.
                match shape.as_compound() {
                    Some(c) => shapes.extend(
                        c.shapes()
                            .iter()
                            .map(|(p, part)| (part.clone(), s.link_from_shape * local * *p)),
                    ),
                    None => shapes.push((shape, s.link_from_shape * local)),
                }
            }
            if !shapes.is_empty() {
                let covers: Vec<Cover> =
                    shapes.iter().map(|(s, p)| Cover::of(s).placed(p)).collect();
                bodies.push(LinkBody {
                    outer: Outer::of(&shapes),
                    bound: placed::ball_around(
                        covers.iter().flat_map(|c| c.spheres.iter().copied()),
                    ),
                    covers,
                    hulls: shapes
                        .iter()
                        .map(|(s, _)| s.as_convex_polyhedron().and_then(Hull::of))
                        .collect(),
                    link: li,
                    padding: params
                        .link_padding
                        .get(&link.name)
                        .copied()
                        .unwrap_or(params.padding),
                    name: link.name.clone(),
                    shapes,
                    moving: moves[li],
                });
            }
        }
        let motion_radius = coarse_motion_radius(&chain);
        let mut world = Self {
            anchors: Vec::new(),
            element_joints: None,
            world_from_chain_base: Pose::IDENTITY,
            motion_radius,
            levers: Vec::new(),
            pair_tables: PairTables::default(),
            model,
            chain,
            world_from_root,
            values,
            bodies,
            allowed: HashSet::new(),
            allowed_matrix: Vec::new(),
            checked_pairs: Vec::new(),
            pieces: 0,
            objects: Vec::new(),
            objects_bvh: Bvh::new(),
            object_boxes: Vec::new(),
            attached: Vec::new(),
            params,
            checks: Cell::new(0),
            scratch: Default::default(),
        };
        world.compute_allowed_collisions();
        world.rebuild_allowed_matrix();
        world.compute_anchors()?;
        Ok(world)
    }

    /// The same robot, objects, attached objects and allowed collisions for another
    /// chain of the robot (the other arm), other values of the joints outside the chain
    /// (all joints, model order) or another root pose: only the sampled allowed-collision
    /// matrix is costly, and it depends on none of these.
    pub fn rebased(
        &self,
        chain: Chain,
        values: Vec<f64>,
        world_from_root: Pose,
    ) -> Result<Self, WorldError> {
        if values.len() != self.model.joints.len() {
            return Err(WorldError::WrongLength {
                expected: self.model.joints.len(),
                got: values.len(),
            });
        }
        if values.iter().any(|v| !v.is_finite()) || !tabula_geom::pose_is_finite(&world_from_root) {
            return Err(WorldError::NonFinite);
        }
        let mut w = self.clone();
        let moves = moving_links(&w.model, &chain);
        for b in &mut w.bodies {
            b.moving = moves[b.link];
        }
        w.rebuild_body_index();
        w.motion_radius = coarse_motion_radius(&chain);
        w.chain = chain;
        w.values = values;
        w.world_from_root = world_from_root;
        w.element_joints = None;
        w.compute_anchors()?;
        Ok(w)
    }

    /// Values of every joint (model order) used for the joints outside the chain.
    pub fn values(&self) -> &[f64] {
        &self.values
    }

    /// Names of the world objects.
    pub fn object_names(&self) -> Vec<String> {
        self.objects.iter().map(|o| o.name.clone()).collect()
    }

    /// Anchors of every body (and the element → joint map they need).
    fn compute_anchors(&mut self) -> Result<(), WorldError> {
        let base = self.model.link(&self.chain.base_link)?;
        let tip = self.model.link(&self.chain.tip_link)?;
        // Joints from the tip up to the base; the chain descends iff the base is reached.
        let mut path = Vec::new();
        let mut l = tip;
        while l != base {
            let Some(j) = self.model.links[l].parent_joint else {
                break;
            };
            path.push(j);
            l = self.model.joints[j].parent;
        }
        let root_poses = self.model.forward_kinematics(&self.values)?;
        self.world_from_chain_base = self.world_from_root * root_poses[base];
        if l == base {
            path.reverse();
            let in_chain: HashSet<usize> = self.chain.joint_indices.iter().copied().collect();
            let elements: Vec<usize> = path
                .into_iter()
                .filter(|&j| {
                    let joint = &self.model.joints[j];
                    joint.kind.is_single_axis()
                        && joint
                            .mimic
                            .as_ref()
                            .is_none_or(|m| in_chain.contains(&m.master))
                })
                .collect();
            if elements.len() == self.chain.elements.len() {
                self.element_joints = Some(elements);
            }
        }
        self.anchors = (0..self.bodies.len())
            .map(|b| self.anchor_for(b, &root_poses))
            .collect();
        self.tighten_motion_radius();
        self.pair_tables = PairTables::build(self);
        Ok(())
    }

    /// A ball that holds every body the chain moves, and what they hold, in every
    /// configuration: centred on the first joint, its radius the longest lever from
    /// there plus the farthest shape. Nothing outside it can ever touch the arm, so a
    /// scene need not be modelled there (MoveIt's octomap is bounded the same way).
    /// `None` when the chain's bodies could not be anchored (a chain not descending
    /// from its base).
    pub fn moving_bound(&self) -> Option<(Vec3, f64)> {
        let first = self.chain.elements.first()?;
        self.element_joints.as_ref()?;
        let n = self.bodies.len();
        let radius = self.levers.get(..n)?.iter().copied().fold(0.0, f64::max);
        let centre = self
            .world_from_chain_base
            .transform_point(first.pre.translation);
        Some((centre, radius))
    }

    fn anchor_for(&self, body: usize, root_poses: &[Pose]) -> Anchor {
        let link = self.bodies[body].link;
        let placed = |offset: Pose| Anchor {
            element: None,
            offset,
            bound: self.bodies[body].bound.map(|(c, r)| (offset * c, r)),
        };
        let world = placed(self.world_from_root * root_poses[link]);
        let Some(elements) = &self.element_joints else {
            return world;
        };
        let mut l = link;
        while let Some(j) = self.model.links[l].parent_joint {
            if let Some(k) = elements.iter().position(|&e| e == j) {
                let child = self.model.joints[j].child;
                return Anchor {
                    element: Some(k),
                    ..placed(root_poses[child].inverse() * root_poses[link])
                };
            }
            l = self.model.joints[j].parent;
        }
        world
    }

    /// World poses of every body's link at `q`.
    #[cfg(test)]
    fn body_poses(&self, q: &[f64]) -> Result<Vec<Pose>, WorldError> {
        let (mut frames, mut poses) = (Vec::new(), Vec::new());
        self.frames_into(q, &mut frames, &mut poses)?;
        Ok((0..self.bodies.len())
            .map(|b| self.body_pose(b, &frames, &poses))
            .collect())
    }

    /// One check's start: counts it, computes the chain's frames at `q` in the world's
    /// buffers (fresh ones when a caller up the stack holds them) and hands them to `f`
    /// with the first joint outside its limits, if any.
    fn with_bodies_at<R>(
        &self,
        q: &[f64],
        f: impl FnOnce(&mut Scratch, Option<usize>) -> R,
    ) -> Result<R, WorldError> {
        self.checks.set(self.checks.get() + 1);
        let mut kept = self.scratch.try_borrow_mut().ok();
        let mut own = Scratch::default();
        let scratch = kept.as_deref_mut().unwrap_or(&mut own);
        self.frames_into(q, &mut scratch.frames, &mut scratch.poses)?;
        scratch.balls.clear();
        let outside = q
            .iter()
            .enumerate()
            .position(|(i, v)| *v < self.chain.lower[i] - 1e-9 || *v > self.chain.upper[i] + 1e-9);
        Ok(f(scratch, outside))
    }

    /// Whether every body hangs from a chain element or stands still
    /// ([`Anchor`]): then a check computes the chain's frames only, and a body's pose
    /// from them when a test needs it.
    fn anchored(&self) -> bool {
        self.element_joints.is_some() && self.anchors.len() == self.bodies.len()
    }

    /// The chain's frames at `q` in the world into `frames` — or, where the bodies
    /// could not be anchored, every body's pose into `poses` (else left empty).
    fn frames_into(
        &self,
        q: &[f64],
        frames: &mut Vec<Pose>,
        poses: &mut Vec<Pose>,
    ) -> Result<(), WorldError> {
        frames.clear();
        poses.clear();
        if !self.anchored() {
            let links = self.root_from_links(q)?;
            poses.extend(
                self.bodies
                    .iter()
                    .map(|b| self.world_from_root * links[b.link]),
            );
            return Ok(());
        }
        self.check_length_and_finite(q)?;
        let mut t = self.world_from_chain_base;
        for e in &self.chain.elements {
            let v = e.multiplier * q[e.var] + e.offset;
            // `t · pre · motion`, with the motion's zero part left out (a joint's motion
            // is a pure rotation or a pure translation).
            let at = t * e.pre;
            t = if e.prismatic {
                Pose::from_parts(at.translation + at.rotation * (e.axis * v), at.rotation)
            } else {
                Pose::from_parts(
                    at.translation,
                    at.rotation * Quat::from_axis_angle(e.axis, v),
                )
            };
            frames.push(t);
        }
        Ok(())
    }

    /// Body `b`'s world pose from a check's [`Self::frames_into`].
    fn body_pose(&self, b: usize, frames: &[Pose], poses: &[Pose]) -> Pose {
        if !poses.is_empty() {
            return poses[b];
        }
        let a = &self.anchors[b];
        match a.element {
            Some(k) => frames[k] * a.offset,
            None => a.offset,
        }
    }

    /// Body `b`'s bounding ball in the world from a check's [`Self::frames_into`]: one
    /// point moved, not the body's pose composed.
    fn body_bound(&self, b: usize, frames: &[Pose], poses: &[Pose]) -> Option<(Vec3, f64)> {
        if !poses.is_empty() {
            return self.bodies[b].bound.map(|(c, r)| (poses[b] * c, r));
        }
        let a = &self.anchors[b];
        a.bound.map(|(c, r)| match a.element {
            Some(k) => (frames[k] * c, r),
            None => (c, r),
        })
    }

    /// Scales every link's padding (and the default for links added later) by `factor`.
    pub fn scale_padding(&mut self, factor: f64) {
        self.params.padding *= factor;
        for body in &mut self.bodies {
            body.padding *= factor;
        }
    }

    /// The largest padding of any link (what conservative advancement must keep).
    pub fn max_padding(&self) -> f64 {
        self.bodies
            .iter()
            .map(|b| b.padding)
            .fold(self.params.padding, f64::max)
    }

    /// How far (m) any point of the robot can move between configurations `a` and `b` on
    /// the straight segment joining them (an upper bound).
    pub fn displacement_bound(&self, a: &[f64], b: &[f64]) -> f64 {
        a.iter()
            .zip(b)
            .zip(&self.motion_radius)
            .map(|((x, y), r)| (x - y).abs() * r)
            .sum()
    }

    /// How many configurations have been checked (for collision-checks-per-second).
    pub fn checks(&self) -> u64 {
        self.checks.get()
    }

    fn check_length_and_finite(&self, q: &[f64]) -> Result<(), WorldError> {
        if q.len() != self.chain.dof() {
            return Err(WorldError::WrongLength {
                expected: self.chain.dof(),
                got: q.len(),
            });
        }
        if q.iter().any(|v| !v.is_finite()) {
            return Err(WorldError::NonFinite);
        }
        Ok(())
    }

    fn root_from_links(&self, q: &[f64]) -> Result<Vec<Pose>, WorldError> {
        self.check_length_and_finite(q)?;
        let mut values = self.values.clone();
        for (v, &j) in q.iter().zip(&self.chain.joint_indices) {
            values[j] = *v;
        }
        Ok(self.model.forward_kinematics(&values)?)
    }

    /// Why `q` is invalid, given the pair [`Self::first_collision`] reported: a joint
    /// outside its limits (named, with the value and the limits), a contact, or a link
    /// only within its padding of something — three different things to fix.
    pub fn why_invalid(&self, q: &[f64], (a, b): &(String, String)) -> String {
        use tabula_geom::input::shown;
        if a == "joint limits" {
            return match self.chain.joint_names.iter().position(|n| n == b) {
                Some(i) => format!(
                    "joint `{b}` = {} is outside its limits [{}, {}]",
                    shown(q.get(i).copied().unwrap_or(f64::NAN)),
                    shown(self.chain.lower[i]),
                    shown(self.chain.upper[i])
                ),
                None => format!("joint `{b}` is outside its limits"),
            };
        }
        let padding = self
            .bodies
            .iter()
            .find(|l| &l.name == a || &l.name == b)
            .map_or(self.params.padding, |l| l.padding);
        match self.exact_collision(q) {
            Ok(None) => format!(
                "{a} is within the {:.0} mm padding of {b}, without touching it",
                padding * 1e3
            ),
            _ => format!("{a} touches {b}"),
        }
    }

    /// The first colliding pair at `q` on the exact geometry (no padding).
    pub fn exact_collision(&self, q: &[f64]) -> Result<Option<(String, String)>, WorldError> {
        let mut bare = self.clone();
        for body in &mut bare.bodies {
            body.padding = 0.0;
        }
        bare.first_collision(q)
    }

    /// Whether two bodies of the robot can newly collide: different bodies, at least one
    /// moving, not allowed by the matrix.
    fn self_pair_checked(&self, a: usize, b: usize) -> bool {
        a != b
            && (self.bodies[a].moving || self.bodies[b].moving)
            && !self.allowed_matrix[a * self.bodies.len() + b]
    }

    /// True when `q` is within limits and collision-free (with padding). Bad input is
    /// not valid.
    pub fn is_valid(&self, q: &[f64]) -> bool {
        matches!(self.first_collision(q), Ok(None))
    }

    /// The smallest distance between the moving robot (and attached objects) and the
    /// world objects at `q` (m; negative = penetration depth).
    pub fn min_distance(&self, q: &[f64]) -> Result<f64, WorldError> {
        let poses = self.root_from_links(q)?;
        let mut best = f64::INFINITY;
        for lb in self.bodies.iter().filter(|b| b.moving) {
            for (s, p) in &lb.shapes {
                let w = self.world_from_root * poses[lb.link] * *p;
                for o in &self.objects {
                    if let Ok(d) =
                        query::distance(&w, s.as_ref(), &o.world_from_object, o.shape.as_ref())
                    {
                        best = best.min(d.distance);
                    }
                    if let Ok(Some(c)) =
                        query::contact(&w, s.as_ref(), &o.world_from_object, o.shape.as_ref(), 0.0)
                    {
                        best = best.min(c.dist);
                    }
                }
            }
        }
        Ok(best)
    }

    /// `world_from_tip` of the chain at `q`.
    pub fn tip_pose(&self, q: &[f64]) -> Result<Pose, WorldError> {
        let poses = self.root_from_links(q)?;
        let tip = self.model.link(&self.chain.tip_link)?;
        Ok(self.world_from_root * poses[tip])
    }

    /// `world_from_link` of the chain's base link (IK targets are in this frame).
    pub fn world_from_chain_base(&self) -> Result<Pose, WorldError> {
        let poses = self.model.forward_kinematics(&self.values)?;
        Ok(self.world_from_root * poses[self.model.link(&self.chain.base_link)?])
    }

    /// `world_from_root` of the robot.
    pub fn world_from_root(&self) -> Pose {
        self.world_from_root
    }
}

impl Validate for WorldParams {
    fn check(&self, at: &str) -> Result<(), String> {
        check_non_negative(at, "padding", self.padding)?;
        check_in(at, "always_fraction", self.always_fraction, 0.0, 1.0)?;
        // Conservative advancement's step: under 10 µm an edge is millions of steps.
        check_in(
            at,
            "max_step_displacement",
            self.max_step_displacement,
            1e-5,
            1.0,
        )?;
        for (link, pad) in &self.link_padding {
            check_non_negative(at, &format!("link_padding.{link}"), *pad)?;
        }
        Ok(())
    }
}

#[cfg(test)]
pub(crate) mod test_worlds {
    use super::{CollisionWorld, WorldParams};
    use tabula_geom::Pose;
    use tabula_robot::robots;

    /// A world for every arm of the WAM, the PR2 and Golem-III (a 7R arm, a tree with a
    /// torso lift, a prismatic torso), named `robot arm`.
    pub(crate) fn every_arm(params: &WorldParams) -> Vec<(String, CollisionWorld)> {
        let mut worlds = Vec::new();
        for name in ["wam", "pr2", "golem3"] {
            let robot = robots::load(name).expect("robot");
            for arm in &robot.description.arms {
                let chain = arm.chain(&robot.model).expect("chain");
                let world = CollisionWorld::new(
                    robot.model.clone(),
                    chain,
                    Pose::IDENTITY,
                    None,
                    params.clone(),
                )
                .expect("world");
                worlds.push((format!("{name} {}", arm.name), world));
            }
        }
        worlds
    }
}
