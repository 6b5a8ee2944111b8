//! The simulated world: rapier3d-f64 rigid bodies built from a scene, settling, pose
//! queries, and the seed's scene commands (SPEC §1.6).

mod checks;
mod commands;
mod furniture;
mod overlap;
mod prism;
#[cfg(test)]
mod recycling_tests;
pub mod robot;
mod rolling;
#[cfg(test)]
mod rolling_tests;
mod saved;
mod waking;
#[cfg(test)]
mod waking_tests;

use crate::scene::{FurnitureSpec, ObjectSpec, PoseSpec, Scene, ShapeSpec};
use rapier3d_f64::prelude::*;
use std::f64::consts::FRAC_PI_2;
use std::path::Path;
use tabula_geom::mesh::load_mesh;
use tabula_geom::{Pose, Quat, Vec3, pose_from_xyz_rpy, rotation_angle_between};
use tabula_robot::model::PEDESTAL_LINK;

/// What an entity is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EntityKind {
    Floor,
    Furniture,
    Object,
    RobotLink,
}

/// A named thing in the world with one rigid body; its label in camera images is its
/// index + 1 (0 = nothing).
#[derive(Debug, Clone)]
pub struct Entity {
    pub name: String,
    pub kind: EntityKind,
    pub body: RigidBodyHandle,
    pub color: [f64; 3],
    /// Deleted entities keep their slot so labels stay stable; their body is gone.
    pub deleted: bool,
    /// The radius an object rolls on, for its rolling resistance (0 for the rest).
    pub rolling_radius: f64,
}

/// Why a world operation failed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SimError {
    #[error("unknown model `{name}`; valid models: {valid}")]
    UnknownModel { name: String, valid: String },
    #[error("no entity named `{0}` in the world")]
    UnknownEntity(String),
    #[error("`{0}` is already in the world")]
    NameTaken(String),
    #[error("`{new}` would overlap `{existing}` at that pose")]
    Overlap { new: String, existing: String },
    #[error("nothing below `{0}` to put it on")]
    NoSurfaceBelow(String),
    #[error("{0}")]
    Robot(String),
    #[error("mesh `{path}`: {message}")]
    Mesh { path: String, message: String },
    #[error("pose values must be finite and within ±1000 m of the origin")]
    NonFinite,
    #[error("`{robot}` stopped: its link `{link}` would drive into `{by}`")]
    Blocked {
        robot: String,
        by: String,
        link: String,
    },
    #[error(transparent)]
    Scene(#[from] crate::scene::SceneError),
}

impl From<tabula_geom::mesh::MeshError> for SimError {
    fn from(e: tabula_geom::mesh::MeshError) -> Self {
        SimError::Mesh {
            path: e.path,
            message: e.message,
        }
    }
}

/// Parameters of the physics (SPEC §5); defaults favour resting accuracy over speed.
#[derive(Debug, Clone, serde::Deserialize, serde::Serialize)]
#[serde(default, deny_unknown_fields)]
pub struct PhysicsParams {
    /// Time step (s).
    pub dt: f64,
    /// Settling gives up after this much simulated time (s).
    pub settle_time_limit: f64,
    /// A contact pair that moved less than this (m) since its last full update keeps
    /// its old contact points (rapier's contact recycling; 0 = off). Rapier's default,
    /// 5 cm, let a robot's kinematic finger sliding down beside an object keep a stale
    /// point on the object's top edge whose separation, extrapolated along its slanted
    /// normal, turned negative: the finger pressed the object into the table from a
    /// centimetre away. Without recycling (or at 2 mm) objects dropped into a crowded
    /// bin were flung out of it, metres away (the pile suite lost 120 of 1,252 objects
    /// instead of 10). 1 cm, the planner's padding, keeps a stale point at most that far
    /// out of date and the piles in the bin (`BENCHMARKS.md`, issue 36 item 6).
    pub contact_recycle_distance: f64,
    /// Coefficient of rolling resistance (dimensionless, clamped to 0–1): the torque
    /// against an object's spin is at most this times its weight times the radius it
    /// rolls on. 0.01 is rubber or cardboard on wood; 0 leaves rolling to the engine,
    /// which lets a nudged can roll on for ever (see `rolling.rs`).
    pub rolling_resistance: f64,
}

impl Default for PhysicsParams {
    fn default() -> Self {
        Self {
            dt: 1.0 / 120.0,
            settle_time_limit: 10.0,
            contact_recycle_distance: 0.01,
            rolling_resistance: 0.01,
        }
    }
}

/// The outcome of [`SimWorld::settle`].
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct SettleReport {
    pub steps: usize,
    pub simulated_seconds: f64,
    /// True when every dynamic body fell asleep before the time limit.
    pub all_asleep: bool,
}

/// Catalogue of spawnable models (the seed's simulator scripts spawned named models).
pub const MODELS: &[(&str, &str)] = &[
    ("cube_5cm", "a 5 cm wooden cube"),
    ("box_small", "a 6×4×10 cm box"),
    ("can", "a soda can (r 3.3 cm, 12 cm)"),
    ("bottle", "a bottle (r 3.5 cm, 25 cm)"),
    ("ball", "a 7 cm ball"),
    ("cone_small", "a 6 cm cone, 10 cm tall"),
    ("capsule_small", "a capsule r 2.5 cm"),
    ("tall_box", "a 4×4×30 cm box"),
];

/// The shape and mass of catalogue model `name`.
pub fn model_shape(name: &str) -> Option<(ShapeSpec, f64)> {
    Some(match name {
        "cube_5cm" => (ShapeSpec::Box([0.05; 3]), 0.08),
        "box_small" => (ShapeSpec::Box([0.06, 0.04, 0.1]), 0.15),
        "can" => (
            ShapeSpec::Cylinder {
                radius: 0.033,
                height: 0.12,
            },
            0.35,
        ),
        "bottle" => (
            ShapeSpec::Cylinder {
                radius: 0.035,
                height: 0.25,
            },
            0.5,
        ),
        "ball" => (ShapeSpec::Sphere { radius: 0.035 }, 0.1),
        "cone_small" => (
            ShapeSpec::Cone {
                radius: 0.03,
                height: 0.1,
            },
            0.05,
        ),
        "capsule_small" => (
            ShapeSpec::Capsule {
                radius: 0.025,
                height: 0.08,
            },
            0.1,
        ),
        "tall_box" => (ShapeSpec::Box([0.04, 0.04, 0.3]), 0.3),
        _ => return None,
    })
}

/// The world.
pub struct SimWorld {
    pub physics: PhysicsWorld,
    pub entities: Vec<Entity>,
    pub params: PhysicsParams,
    pub robots: Vec<robot::PlacedRobot>,
    /// Objects held by grippers.
    pub attachments: Vec<robot::Attachment>,
    /// The scene's cameras; a camera on a robot link is placed where the link is when
    /// it captures (see [`Self::camera`]).
    pub cameras: Vec<crate::scene::CameraSpec>,
    /// Physics steps taken since the world was built: the simulator's clock.
    pub steps: u64,
    /// Labels a driver was given for moments of a task, with the simulated time.
    pub notes: Vec<(f64, String)>,
    /// A dry run (MoveIt's fake controllers, with the scene kept for the cameras):
    /// robots move by setting their joints, objects ride in a gripper that closes on
    /// them, and nothing falls, slides or is pushed; the clock still runs.
    pub kinematic_only: bool,
    /// The specs the world was built from, kept up to date with spawned and deleted
    /// objects, so the world can be written back as a scene ([`Self::to_scene`]).
    source: Scene,
    base_dir: Option<std::path::PathBuf>,
}

fn pose_of(p: &PoseSpec) -> Pose {
    pose_from_xyz_rpy(p.xyz, p.rpy)
}

/// Parry aligns cylinders and cones with y; tabula's shapes stand along z.
pub(super) fn y_to_z() -> Pose {
    Pose::from_rotation(Quat::from_rotation_x(FRAC_PI_2))
}

/// The bounds of a shape at `pose`, from each part of a compound (a compound's own
/// bounds are its local box turned, centimetres loose once it is rotated).
fn tight_aabb(shape: &SharedShape, pose: &Pose) -> tabula_geom::parry::bounding_volume::Aabb {
    use tabula_geom::parry::bounding_volume::BoundingVolume;
    match shape.as_compound() {
        Some(c) => c
            .shapes()
            .iter()
            .map(|(p, s)| tight_aabb(s, &(*pose * *p)))
            .reduce(|a, b| a.merged(&b))
            .unwrap_or_else(|| shape.compute_aabb(pose)),
        None => shape.compute_aabb(pose),
    }
}

/// A mesh file's solid shape (see [`tabula_geom::mesh::mesh_shape`]).
fn mesh_shape(
    path: &Path,
    points: &[Vec3],
    triangles: &[[u32; 3]],
) -> Result<SharedShape, SimError> {
    tabula_geom::mesh::mesh_shape(points, triangles, true).map_err(|message| SimError::Mesh {
        path: path.display().to_string(),
        message,
    })
}

/// Half the width of the ground under the floor (m).
const GROUND_HALF_WIDTH: f64 = 5000.0;

/// Marks a collider as a [`support_pieces`] helper in its `user_data` (above the 32-bit
/// entity label): it carries contacts but is not part of what the entity looks like.
pub(crate) const SUPPORT_PIECE: u128 = 1 << 64;

/// Whether collider data belongs to a [`support_pieces`] helper.
pub(crate) fn is_support_piece(user_data: u128) -> bool {
    user_data & SUPPORT_PIECE != 0
}

/// Thin tetrahedra under every face of more than four vertices of a convex polyhedron
/// (or of each piece of a compound of them), as (shape, pose in the shape's frame).
///
/// Why: parry's contact manifold for a convex polyhedron resting on a face takes the
/// first four vertices of that face in order (its code says "TODO: … select four
/// vertices that maximize the area"), so a 32-sided base touches the table on a sliver
/// at one side: a cylinder, cone, mug or bottle mesh set down upright rocks on it,
/// tilts 1–3° and slides centimetres. Triangles fanned from each big face's centre,
/// each closed by a point inside the polyhedron, give contacts over the whole face;
/// added as mass-less colliders they change nothing else.
pub(crate) fn support_pieces(shape: &SharedShape) -> Vec<(SharedShape, Pose)> {
    let mut out = Vec::new();
    let mut add = |poly: &ConvexPolyhedron, local: Pose| {
        let points = poly.points();
        if points.is_empty() {
            return;
        }
        let inside = points.iter().copied().sum::<Vec3>() / points.len() as f64;
        let adjacent = poly.vertices_adj_to_face();
        for face in poly.faces() {
            let n = face.num_vertices_or_edges as usize;
            if n <= 4 {
                continue;
            }
            let first = face.first_vertex_or_edge as usize;
            let ring: Vec<Vec3> = adjacent[first..first + n]
                .iter()
                .map(|&v| points[v as usize])
                .collect();
            let centre = ring.iter().copied().sum::<Vec3>() / n as f64;
            // Halfway in: a shallow piece whose other faces never reach out of the hull.
            let apex = centre + 0.5 * (inside - centre);
            for k in 0..n {
                let tetra = [centre, ring[k], ring[(k + 1) % n], apex];
                if let Some(piece) = SharedShape::convex_hull(&tetra) {
                    out.push((piece, local));
                }
            }
        }
    };
    if let Some(poly) = shape.as_convex_polyhedron() {
        add(poly, Pose::IDENTITY);
    } else if let Some(compound) = shape.as_compound() {
        for (local, part) in compound.shapes() {
            if let Some(poly) = part.as_convex_polyhedron() {
                add(poly, *local);
            }
        }
    }
    out
}

impl SimWorld {
    /// An empty world with gravity along −z.
    pub fn new(params: PhysicsParams) -> Self {
        let mut physics = PhysicsWorld {
            gravity: Vec3::new(0.0, 0.0, -9.81),
            ..Default::default()
        };
        let integration = &mut physics.integration_parameters;
        integration.dt = params.dt;
        integration.contact_recycling = params.contact_recycle_distance > 0.0;
        integration.normalized_contact_recycle_distance =
            params.contact_recycle_distance / integration.length_unit;
        Self {
            physics,
            entities: Vec::new(),
            params,
            robots: Vec::new(),
            attachments: Vec::new(),
            cameras: Vec::new(),
            steps: 0,
            notes: Vec::new(),
            kinematic_only: false,
            source: Scene::default(),
            base_dir: None,
        }
    }

    /// Builds the world of a scene.
    pub fn from_scene(scene: &Scene, params: PhysicsParams) -> Result<Self, SimError> {
        let mut w = Self::new(params);
        w.base_dir = scene.base_dir.clone();
        if let Some(f) = &scene.floor {
            w.add_floor(f.size, f.color);
        }
        for f in &scene.furniture {
            w.add_furniture(f)?;
        }
        w.add_objects(&scene.objects)?;
        for r in &scene.robots {
            w.add_robot(r)?;
        }
        w.check_names_apart_from_robots()?;
        let held: Vec<&str> = scene
            .robots
            .iter()
            .filter_map(|r| r.hold.as_ref().map(|h| h.object.as_str()))
            .collect();
        w.check_objects_clear_of_robots(&held)?;
        w.cameras = scene.cameras.clone();
        w.source = scene.clone();
        for r in &scene.robots {
            if let Some(h) = &r.hold {
                let robot = r.name.get_ref();
                w.open_gripper(robot, &h.finger_joint)?;
                let world_from_tool = w.link_pose(robot, &h.tool_link)?;
                let tool_from_object = h.tool_from_object.map(|p| pose_of(&p));
                w.move_to(
                    &h.object,
                    world_from_tool * tool_from_object.unwrap_or(Pose::IDENTITY),
                )?;
                let fingers = [h.fingers[0].as_str(), h.fingers[1].as_str()];
                if w.close_fingers(robot, &h.finger_joint, fingers, &h.palm, None, false)?
                    .as_deref()
                    != Some(h.object.as_str())
                {
                    return Err(SimError::Robot(format!(
                        "`{robot}` could not close its gripper on `{}`",
                        h.object
                    )));
                }
            }
        }
        Ok(w)
    }

    fn label_of(&self) -> u128 {
        self.entities.len() as u128 + 1
    }

    fn push_entity(
        &mut self,
        name: &str,
        kind: EntityKind,
        body: RigidBodyHandle,
        color: [f64; 3],
    ) {
        let rolling_radius = if kind == EntityKind::Object {
            self.rolling_radius(body)
        } else {
            0.0
        };
        self.entities.push(Entity {
            name: name.to_string(),
            kind,
            body,
            color,
            deleted: false,
            rolling_radius,
        });
    }

    fn add_floor(&mut self, size: [f64; 2], color: [f64; 3]) {
        let label = self.label_of();
        let body = self
            .physics
            .insert_body(RigidBodyBuilder::fixed().translation(Vec3::new(0.0, 0.0, -0.05)));
        let c = ColliderBuilder::cuboid(size[0] / 2.0, size[1] / 2.0, 0.05)
            .friction(0.8)
            .user_data(label);
        self.physics.insert_collider(c, Some(body));
        // Under the floor that is seen, ground 10 km across and 20 m deep: whatever
        // rolls off the floor's edge or is pressed into it comes back up instead of
        // falling forever. (A box, not parry's half-space, whose contact with convex
        // shapes gives wrong depths.)
        let ground = ColliderBuilder::cuboid(GROUND_HALF_WIDTH, GROUND_HALF_WIDTH, 10.0)
            .translation(Vec3::new(0.0, 0.0, 0.05 - 10.0))
            .friction(0.8)
            .user_data(label | SUPPORT_PIECE);
        self.physics.insert_collider(ground, Some(body));
        self.push_entity("floor", EntityKind::Floor, body, color);
    }

    /// Adds a fixed composite of boxes, cylinders and wedges.
    pub fn add_furniture(&mut self, f: &FurnitureSpec) -> Result<(), SimError> {
        let name = f.name.get_ref().clone();
        if self.entity(&name).is_some() {
            return Err(SimError::NameTaken(name));
        }
        let label = self.label_of();
        let body = self
            .physics
            .insert_body(RigidBodyBuilder::fixed().pose(pose_of(&f.pose)));
        let (parts, color) = furniture::parts(f, &name)?;
        for (shape, local) in parts {
            let c = ColliderBuilder::new(shape)
                .position(local)
                .friction(f.friction)
                .user_data(label);
            self.physics.insert_collider(c, Some(body));
        }
        self.push_entity(&name, EntityKind::Furniture, body, f.color.unwrap_or(color));
        Ok(())
    }

    fn object_shape(&self, shape: &ShapeSpec) -> Result<(SharedShape, Pose), SimError> {
        Ok(match shape {
            ShapeSpec::Box(s) => (
                SharedShape::cuboid(s[0] / 2.0, s[1] / 2.0, s[2] / 2.0),
                Pose::IDENTITY,
            ),
            ShapeSpec::Cylinder { radius, height } => {
                (SharedShape::cylinder(height / 2.0, *radius), y_to_z())
            }
            ShapeSpec::Sphere { radius } => (SharedShape::ball(*radius), Pose::IDENTITY),
            ShapeSpec::Cone { radius, height } => {
                (SharedShape::cone(height / 2.0, *radius), y_to_z())
            }
            ShapeSpec::Capsule { radius, height } => (
                SharedShape::capsule_z(height / 2.0, *radius),
                Pose::IDENTITY,
            ),
            ShapeSpec::Prism { outline, length } => {
                (prism::prism_shape(outline, *length)?, Pose::IDENTITY)
            }
            ShapeSpec::Mesh { path, scale } => {
                let full = match &self.base_dir {
                    Some(d) if Path::new(path).is_relative() => d.join(path),
                    _ => Path::new(path).to_path_buf(),
                };
                let (points, triangles) = load_mesh(&full, *scale).map_err(|e| SimError::Mesh {
                    path: e.path,
                    message: e.message,
                })?;
                (mesh_shape(&full, &points, &triangles)?, Pose::IDENTITY)
            }
        })
    }

    /// Adds a dynamic object; an object that would overlap another is refused.
    pub fn add_object(&mut self, o: &ObjectSpec) -> Result<(), SimError> {
        self.add_objects(std::slice::from_ref(o))
    }

    /// Adds objects, failing exactly where adding them one by one would first fail (a
    /// name taken, a shape that cannot be built, a body sunk into another) — but checked
    /// together, in one sweep ([`Self::first_overlap`]).
    pub fn add_objects(&mut self, objects: &[ObjectSpec]) -> Result<(), SimError> {
        let mut names: std::collections::HashSet<&str> =
            self.entities.iter().map(|e| e.name.as_str()).collect();
        let (mut placed, mut shape_from_body) = (Vec::new(), Vec::new());
        let mut failed = None;
        for o in objects {
            let name = o.name.get_ref();
            if !names.insert(name) {
                failed = Some(SimError::NameTaken(name.clone()));
                break;
            }
            match self.object_shape(&o.shape) {
                Ok((shape, local)) => {
                    placed.push(overlap::Placement {
                        name: name.clone(),
                        shape,
                        world_from_shape: pose_of(&o.pose) * local,
                    });
                    shape_from_body.push(local);
                }
                Err(e) => {
                    failed = Some(e);
                    break;
                }
            }
        }
        if let Some((i, existing)) = self.first_overlap(&placed) {
            return Err(SimError::Overlap {
                new: placed[i].name.clone(),
                existing,
            });
        }
        if let Some(e) = failed {
            return Err(e);
        }
        for ((o, p), local) in objects.iter().zip(placed).zip(shape_from_body) {
            self.insert_object(o, p.shape, local);
        }
        Ok(())
    }

    /// Builds a checked object's body and colliders.
    fn insert_object(&mut self, o: &ObjectSpec, shape: SharedShape, local: Pose) {
        let name = o.name.get_ref();
        let pose = pose_of(&o.pose);
        let volume = shape.mass_properties(1.0).mass();
        let density = match (o.mass, o.density) {
            (Some(m), _) => m / volume.max(1e-12),
            (None, Some(d)) => d,
            (None, None) => 600.0,
        };
        let label = self.label_of();
        let body = self
            .physics
            .insert_body(RigidBodyBuilder::dynamic().pose(pose).ccd_enabled(true));
        let pieces = support_pieces(&shape);
        let c = ColliderBuilder::new(shape)
            .position(local)
            .density(density)
            .friction(o.friction)
            .user_data(label);
        self.physics.insert_collider(c, Some(body));
        for (piece, piece_local) in pieces {
            let c = ColliderBuilder::new(piece)
                .position(local * piece_local)
                .density(0.0)
                .friction(o.friction)
                .user_data(label | SUPPORT_PIECE);
            self.physics.insert_collider(c, Some(body));
        }
        self.push_entity(name, EntityKind::Object, body, o.color);
    }

    /// Robot links as kinematic bodies at their FK poses (collision geometry).
    pub fn add_robot(&mut self, r: &crate::scene::RobotSpec) -> Result<(), SimError> {
        let robot = r
            .load(self.base_dir.as_deref())
            .map_err(|e| SimError::Robot(e.to_string()))?;
        let model = &robot.model;
        let mut values = model.mid_configuration();
        for (joint, v) in &r.joints {
            let j = model.joint(joint).ok_or_else(|| {
                SimError::Robot(format!(
                    "robot `{}` has no joint `{joint}`",
                    r.name.get_ref()
                ))
            })?;
            values[j] = *v;
        }
        let root_from_link = model
            .forward_kinematics(&values)
            .map_err(|e| SimError::Robot(e.to_string()))?;
        let world_from_root = pose_of(&r.pose);
        for (li, link) in model.links.iter().enumerate() {
            let mut colliders = Vec::new();
            for s in &link.collision {
                // A robot whose collision mesh is missing or broken is refused: a link
                // without its geometry would pass through the scene.
                let (shape, local) = s.geometry.collision_shape(true).map_err(|m| {
                    SimError::Robot(format!("link `{}`: collision geometry: {m}", link.name))
                })?;
                colliders.push((shape, s.link_from_shape * local));
            }
            if colliders.is_empty() {
                continue;
            }
            let name = format!("{}/{}", r.name.get_ref(), link.name);
            let label = self.label_of();
            let body = self.physics.insert_body(
                RigidBodyBuilder::kinematic_position_based()
                    .pose(world_from_root * root_from_link[li]),
            );
            for (shape, local) in colliders {
                self.physics.insert_collider(
                    ColliderBuilder::new(shape).position(local).user_data(label),
                    Some(body),
                );
            }
            // The pedestal is furniture to the world (what the arm must not hit, judged
            // as such) and a link to the robot's own planners.
            let (kind, color) = if r.pedestal.is_some() && link.name == PEDESTAL_LINK {
                (EntityKind::Furniture, [0.45, 0.45, 0.48])
            } else {
                (EntityKind::RobotLink, [0.75, 0.75, 0.78])
            };
            self.push_entity(&name, kind, body, color);
        }
        self.robots.push(robot::PlacedRobot {
            name: r.name.get_ref().clone(),
            model: robot.model,
            description: robot.description,
            srdf: robot.srdf,
            world_from_root,
            values,
        });
        Ok(())
    }

    /// The name of an entity that `shape` at `pose` would penetrate by more than a
    /// millimetre (touching, as an object resting on a table does, is fine).
    /// Index of a named entity.
    pub fn entity(&self, name: &str) -> Option<usize> {
        self.entities.iter().position(|e| e.name == name)
    }

    /// `world_from_entity` of a named entity.
    pub fn pose(&self, name: &str) -> Result<Pose, SimError> {
        let i = self
            .entity(name)
            .ok_or_else(|| SimError::UnknownEntity(name.into()))?;
        Ok(*self.physics.bodies[self.entities[i].body].position())
    }

    /// `world_from_link` of a robot link, even one without collision geometry (a
    /// camera's optical frame): FK from the robot's nearest link that has a body.
    pub fn link_pose(&self, robot: &str, link: &str) -> Result<Pose, SimError> {
        let r = self.robot(robot)?;
        let li = r
            .model
            .link(link)
            .map_err(|e| SimError::Robot(e.to_string()))?;
        let all = r
            .model
            .forward_kinematics(&r.values)
            .map_err(|e| SimError::Robot(e.to_string()))?;
        Ok(r.world_from_root * all[li])
    }

    /// The collision shapes of every piece of furniture, in the world (a workcell's
    /// known obstacles, as a MoveIt planning scene loads them).
    pub fn furniture_shapes(&self) -> Vec<(String, SharedShape, Pose)> {
        self.shapes_of(EntityKind::Furniture)
    }

    /// The planning scene of `robot`: the furniture (but its own pedestal) and every
    /// object it does not hold, where the world has them (name, shape, world pose).
    pub fn planning_scene(&self, robot: &str) -> Vec<(String, SharedShape, Pose)> {
        let held = self.held_objects(robot);
        // The robot's own pedestal is a link of its model, not an obstacle to it.
        let mut obstacles = self.furniture_shapes();
        obstacles.retain(|(name, _, _)| self.owner(name) != Some(robot));
        obstacles.extend(
            self.object_shapes()
                .into_iter()
                .filter(|(name, _, _)| !held.contains(name)),
        );
        obstacles
    }

    /// The workcell's furniture as a task is told of it: every piece but the robots'
    /// pedestals (each robot's planners have its own as a link).
    pub fn workcell_shapes(&self) -> Vec<(String, SharedShape, Pose)> {
        let mut shapes = self.furniture_shapes();
        shapes.retain(|(name, _, _)| self.owner(name).is_none());
        shapes
    }

    /// The robot an entity named `name` is part of (its links, its pedestal).
    fn owner(&self, name: &str) -> Option<&str> {
        let (robot, _) = name.split_once('/')?;
        self.robots
            .iter()
            .find(|r| r.name == robot)
            .map(|r| r.name.as_str())
    }

    /// Every object's collider shapes where they are now (name, shape, world pose).
    pub fn object_shapes(&self) -> Vec<(String, SharedShape, Pose)> {
        self.shapes_of(EntityKind::Object)
    }

    fn shapes_of(&self, kind: EntityKind) -> Vec<(String, SharedShape, Pose)> {
        let mut out = Vec::new();
        for e in self.live_entities().filter(|e| e.kind == kind) {
            let body = &self.physics.bodies[e.body];
            for &ch in body.colliders() {
                let c = &self.physics.colliders[ch];
                if is_support_piece(c.user_data) {
                    continue;
                }
                let pose = *body.position() * *c.position_wrt_parent().unwrap_or(&Pose::IDENTITY);
                out.push((e.name.clone(), c.shared_shape().clone(), pose));
            }
        }
        out
    }

    /// The world bounds of a named entity's colliders.
    pub fn entity_bounds(&self, name: &str) -> Option<tabula_geom::parry::bounding_volume::Aabb> {
        use tabula_geom::parry::bounding_volume::BoundingVolume;
        let i = self.entity(name)?;
        let body = &self.physics.bodies[self.entities[i].body];
        body.colliders()
            .iter()
            .map(|&ch| &self.physics.colliders[ch])
            .filter(|c| !is_support_piece(c.user_data))
            .map(|c| {
                let pose = *body.position() * *c.position_wrt_parent().unwrap_or(&Pose::IDENTITY);
                tight_aabb(c.shared_shape(), &pose)
            })
            .reduce(|a, b| a.merged(&b))
    }

    /// Every object's name and pose.
    pub fn object_poses(&self) -> Vec<(String, Pose)> {
        self.live_entities()
            .filter(|e| e.kind == EntityKind::Object)
            .map(|e| (e.name.clone(), *self.physics.bodies[e.body].position()))
            .collect()
    }

    /// One physics step (in a dry run, only the clock advances).
    pub fn step(&mut self) {
        if !self.kinematic_only {
            self.resist_rolling();
            let slept = self.sleeping_bodies();
            self.physics.step();
            self.undo_wake_fall(&slept);
        }
        self.steps += 1;
    }

    /// Simulated seconds since the world was built.
    pub fn time(&self) -> f64 {
        self.steps as f64 * self.physics.integration_parameters.dt
    }

    /// Entities that have not been deleted.
    pub fn live_entities(&self) -> impl Iterator<Item = &Entity> {
        self.entities.iter().filter(|e| !e.deleted)
    }

    /// Steps until every dynamic body sleeps or the time limit passes.
    pub fn settle(&mut self) -> SettleReport {
        if self.kinematic_only {
            return SettleReport {
                steps: 0,
                simulated_seconds: 0.0,
                all_asleep: true,
            };
        }
        let dt = self.physics.integration_parameters.dt;
        let max_steps = (self.params.settle_time_limit / dt).ceil() as usize;
        let mut steps = 0;
        while steps < max_steps {
            self.step();
            steps += 1;
            if self.all_dynamic_asleep() {
                return SettleReport {
                    steps,
                    simulated_seconds: steps as f64 * dt,
                    all_asleep: true,
                };
            }
        }
        SettleReport {
            steps,
            simulated_seconds: steps as f64 * dt,
            all_asleep: self.all_dynamic_asleep(),
        }
    }

    fn all_dynamic_asleep(&self) -> bool {
        self.physics
            .bodies
            .iter()
            .all(|(_, b)| !b.is_dynamic() || b.is_sleeping())
    }

    /// Position error (m) and rotation error (rad) of an entity against `expected`.
    pub fn pose_error(&self, name: &str, expected: &Pose) -> Result<(f64, f64), SimError> {
        let p = self.pose(name)?;
        Ok((
            (p.translation - expected.translation).length(),
            rotation_angle_between(p.rotation, expected.rotation),
        ))
    }

    /// True when the entity's up axis has turned more than `tolerance` rad from where
    /// `reference` had it — it fell over rather than rested as planned.
    pub fn has_toppled(
        &self,
        name: &str,
        reference: &Pose,
        tolerance: f64,
    ) -> Result<bool, SimError> {
        let p = self.pose(name)?;
        let now = p.rotation * Vec3::Z;
        let then = reference.rotation * Vec3::Z;
        Ok(now.angle_between(then) > tolerance)
    }
}
