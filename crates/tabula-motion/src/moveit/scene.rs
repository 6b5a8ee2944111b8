//! A MoveIt planning scene (`moveit_msgs/PlanningScene` as YAML): the robot state, the
//! world's collision objects (boxes, spheres, cylinders, cones, meshes, each part at its
//! pose), objects attached to links, and the allowed-collision matrix — read into plain
//! shapes, then put into a [`CollisionWorld`].

use super::yaml::Node;
use super::{Limits, MoveItError, parse_yaml};
use crate::world::{AllowedCollisions, CollisionWorld};
use tabula_geom::parry::shape::SharedShape;
use tabula_geom::{Pose, Quat, Vec3};
use tabula_robot::model::Geometry;

/// A collision object: parts in the frame `frame_id` (empty: the planning frame).
#[derive(Clone)]
pub struct SceneObject {
    pub id: String,
    pub frame_id: String,
    /// Each part's shape and its pose in `frame_id`.
    pub parts: Vec<(SharedShape, Pose)>,
}

impl SceneObject {
    /// One shape for the object: the part itself, or a compound of them (a part that
    /// is itself a compound — a decomposed mesh — contributes its pieces: compounds do
    /// not nest).
    pub fn shape(&self) -> (SharedShape, Pose) {
        if let [(s, p)] = self.parts.as_slice() {
            return (s.clone(), *p);
        }
        let mut flat = Vec::with_capacity(self.parts.len());
        for (shape, pose) in &self.parts {
            match shape.as_compound() {
                Some(c) => flat.extend(c.shapes().iter().map(|(p, s)| (*pose * *p, s.clone()))),
                None => flat.push((*pose, shape.clone())),
            }
        }
        (SharedShape::compound(flat), Pose::IDENTITY)
    }
}

/// An object held by a link (`moveit_msgs/AttachedCollisionObject`).
#[derive(Clone)]
pub struct AttachedObject {
    pub link: String,
    pub object: SceneObject,
    pub touch_links: Vec<String>,
}

/// A planning scene read from YAML.
#[derive(Clone, Default)]
pub struct PlanningScene {
    pub name: String,
    /// The robot state's joint values by name.
    pub joints: Vec<(String, f64)>,
    pub objects: Vec<SceneObject>,
    pub attached: Vec<AttachedObject>,
    pub allowed: Option<AllowedCollisions>,
    /// Frames the scene defines as fixed (`fixed_frame_transforms`), in the planning frame.
    pub fixed_frames: Vec<(String, Pose)>,
}

impl PlanningScene {
    /// Reads a scene from YAML text.
    pub fn from_yaml(text: &str, limits: &Limits) -> Result<Self, MoveItError> {
        let tree = parse_yaml(text, limits)?;
        let root = Node::root(&tree);
        if root.value.as_mapping().is_none() {
            return Err(root.error("a planning scene is a map"));
        }
        if let Some(d) = root.get("is_diff")
            && d.value.as_bool() == Some(true)
        {
            return Err(d.error("scene diffs are not supported: give the whole scene"));
        }
        let mut scene = PlanningScene {
            name: match root.get("name") {
                Some(n) => n.text()?.to_string(),
                None => String::new(),
            },
            ..Default::default()
        };
        let mut budget = limits.parts;
        if let Some(state) = root.get("robot_state") {
            scene.joints = joint_state(&state)?;
            for a in state.list("attached_collision_objects")? {
                scene
                    .attached
                    .push(attached_object(&a, &mut budget, limits)?);
            }
        }
        for f in root.list("fixed_frame_transforms")? {
            let child = f.need("child_frame_id")?.text()?.to_string();
            let pose = match f.get("transform") {
                Some(t) => t.transform()?,
                None => Pose::IDENTITY,
            };
            scene.fixed_frames.push((child, pose));
        }
        if let Some(world) = root.get("world") {
            scene.objects =
                collision_objects(&world.list("collision_objects")?, &mut budget, limits)?;
            if world
                .get("octomap")
                .is_some_and(|o| o.get("octomap").is_some())
            {
                return Err(world.error(
                    "octomaps in a scene are not supported: give the cloud as occupancy instead",
                ));
            }
        }
        if let Some(acm) = root.get("allowed_collision_matrix") {
            scene.allowed = Some(allowed_collisions(&acm)?);
        }
        Ok(scene)
    }

    /// Puts the scene into `world`: joint values of the robot state for the joints
    /// outside the planning group, objects placed in the planning frame (or relative to
    /// a robot link or a fixed frame), attached objects, and the scene's matrix over the
    /// robot's own. Returns notes about what was ignored (values of fixed joints).
    pub fn apply(&self, world: &mut CollisionWorld) -> Result<Vec<String>, MoveItError> {
        let ignored = world
            .set_joint_values(&self.joints)
            .map_err(|e| MoveItError::Scene(format!("robot state: {e}")))?;
        let mut notes = ignored.notes("the scene's robot state");
        let mut placed = Vec::with_capacity(self.objects.len());
        for o in &self.objects {
            let frame = self.frame_pose(world, &o.frame_id)?;
            let (shape, pose) = o.shape();
            placed.push((o.id.clone(), shape, frame * pose));
        }
        world
            .add_objects(placed)
            .map_err(|e| MoveItError::Scene(e.to_string()))?;
        for a in &self.attached {
            let frame = if a.object.frame_id.is_empty() || a.object.frame_id == a.link {
                Pose::IDENTITY
            } else {
                let link = self.frame_pose(world, &a.link)?;
                link.inverse() * self.frame_pose(world, &a.object.frame_id)?
            };
            let (shape, pose) = a.object.shape();
            let touch: Vec<&str> = a.touch_links.iter().map(String::as_str).collect();
            world
                .attach(&a.object.id, shape, &a.link, frame * pose, &touch)
                .map_err(|e| MoveItError::Scene(format!("attached `{}`: {e}", a.object.id)))?;
        }
        if let Some(acm) = &self.allowed {
            let unknown = world
                .set_allowed_collisions(acm)
                .map_err(|e| MoveItError::Scene(e.to_string()))?;
            if !unknown.is_empty() {
                notes.push(format!(
                    "the allowed-collision matrix names what is neither a link nor an object ({}): ignored",
                    unknown.join(", ")
                ));
            }
        }
        Ok(notes)
    }

    /// `world_from_frame` of a frame the scene may name: the planning frame (empty,
    /// `world`, the robot's root), a fixed frame of the scene, or a robot link at the
    /// scene's robot state.
    fn frame_pose(&self, world: &CollisionWorld, frame: &str) -> Result<Pose, MoveItError> {
        let frame = frame.trim_start_matches('/');
        if frame.is_empty() || frame == "world" || frame == "map" {
            return Ok(world.world_from_root());
        }
        if let Some((_, p)) = self.fixed_frames.iter().find(|(n, _)| n == frame) {
            return Ok(world.world_from_root() * *p);
        }
        world.world_from_link(frame).map_err(|_| {
            MoveItError::Scene(format!(
                "frame `{frame}` is neither the planning frame, a fixed frame of the scene nor a link of the robot"
            ))
        })
    }
}

/// `sensor_msgs/JointState` names and positions (of a `robot_state`'s `joint_state`).
pub(crate) fn joint_state(state: &Node) -> Result<Vec<(String, f64)>, MoveItError> {
    let Some(js) = state.get("joint_state") else {
        return Ok(Vec::new());
    };
    let names = match js.get("name") {
        Some(n) => n.texts()?,
        None => Vec::new(),
    };
    let positions = match js.get("position") {
        Some(p) => p.numbers()?,
        None => Vec::new(),
    };
    if names.len() != positions.len() {
        return Err(js.error(format!(
            "{} names but {} positions",
            names.len(),
            positions.len()
        )));
    }
    Ok(names.into_iter().map(String::from).zip(positions).collect())
}

fn attached_object(
    node: &Node,
    budget: &mut usize,
    limits: &Limits,
) -> Result<AttachedObject, MoveItError> {
    let link = node.need("link_name")?.text()?.to_string();
    let object = node.need("object")?;
    let mut objects = collision_objects(&[object], budget, limits)?;
    let touch_links = match node.get("touch_links") {
        Some(t) => t.texts()?.into_iter().map(String::from).collect(),
        None => Vec::new(),
    };
    let object = objects
        .pop()
        .ok_or_else(|| node.error("the attached object has no shapes"))?;
    Ok(AttachedObject {
        link,
        object,
        touch_links,
    })
}

/// Collision objects, `APPEND` parts merged into the object of the same id.
pub(crate) fn collision_objects(
    nodes: &[Node],
    budget: &mut usize,
    limits: &Limits,
) -> Result<Vec<SceneObject>, MoveItError> {
    if nodes.len() > limits.objects {
        return Err(MoveItError::TooLarge(format!(
            "{} collision objects, over the limit of {}",
            nodes.len(),
            limits.objects
        )));
    }
    let mut objects: Vec<SceneObject> = Vec::with_capacity(nodes.len());
    let mut index = std::collections::HashMap::new();
    for node in nodes {
        let append = match node.get("operation") {
            None => false,
            Some(op) => operation_is_append(&op)?,
        };
        let object = collision_object(node, budget, limits)?;
        match index.get(&object.id) {
            Some(&i) if append => {
                let existing: &mut SceneObject = &mut objects[i];
                existing.parts.extend(object.parts);
            }
            Some(_) => {
                return Err(node.error(format!("a second object with id `{}`", object.id)));
            }
            None => {
                index.insert(object.id.clone(), objects.len());
                objects.push(object);
            }
        }
    }
    Ok(objects)
}

/// `ADD` (0) and `APPEND` (2) build a scene; `REMOVE` and `MOVE` only edit one.
fn operation_is_append(op: &Node) -> Result<bool, MoveItError> {
    let code = match op.value {
        serde_yaml::Value::Number(n) => n.as_i64(),
        serde_yaml::Value::String(s) => match s.to_ascii_lowercase().as_str() {
            "add" => Some(0),
            "remove" => Some(1),
            "append" => Some(2),
            "move" => Some(3),
            _ => None,
        },
        _ => None,
    };
    match code {
        Some(0) => Ok(false),
        Some(2) => Ok(true),
        Some(1 | 3) => Err(op.error("REMOVE and MOVE edit a scene; give the whole scene")),
        _ => Err(op.error("unknown operation (ADD, REMOVE, APPEND or MOVE)")),
    }
}

fn collision_object(
    node: &Node,
    budget: &mut usize,
    limits: &Limits,
) -> Result<SceneObject, MoveItError> {
    let id = node.need("id")?.text()?.to_string();
    if id.is_empty() {
        return Err(node.error("an object needs a non-empty `id`"));
    }
    let frame_id = match node.get("header").and_then(|h| h.get("frame_id")) {
        Some(f) => f.text()?.to_string(),
        None => String::new(),
    };
    // Newer MoveIt: the object's pose, parts relative to it.
    let frame_from_object = match node.get("pose") {
        Some(p) => p.pose()?,
        None => Pose::IDENTITY,
    };
    let mut parts = Vec::new();
    let primitives = node.list("primitives")?;
    let poses = node.list("primitive_poses")?;
    let meshes = node.list("meshes")?;
    let mesh_poses = node.list("mesh_poses")?;
    for (what, shapes, poses) in [
        ("primitive", &primitives, &poses),
        ("mesh", &meshes, &mesh_poses),
    ] {
        if shapes.len() != poses.len() {
            return Err(node.error(format!(
                "{} {what}s but {} {what} poses",
                shapes.len(),
                poses.len()
            )));
        }
    }
    if !node.list("planes")?.is_empty() {
        return Err(node.error(format!(
            "object `{id}`: planes are not supported (give a thin box)"
        )));
    }
    if primitives.len() + meshes.len() > *budget {
        return Err(MoveItError::TooLarge(format!(
            "more than {} shapes in the scene",
            limits.parts
        )));
    }
    *budget -= primitives.len() + meshes.len();
    for (shape, pose) in primitives.iter().zip(&poses) {
        let (s, local) = primitive(shape, limits)?;
        parts.push((s, frame_from_object * pose.pose()? * local));
    }
    for (shape, pose) in meshes.iter().zip(&mesh_poses) {
        parts.push((mesh(shape, limits)?, frame_from_object * pose.pose()?));
    }
    if parts.is_empty() {
        return Err(node.error(format!("object `{id}` has no shapes")));
    }
    Ok(SceneObject {
        id,
        frame_id,
        parts,
    })
}

/// A `shape_msgs/SolidPrimitive` (`type` as the message's number or its name) and the
/// pose of the parry shape in the primitive's frame (ROS cylinders and cones stand
/// along z, parry's along y).
fn primitive(node: &Node, limits: &Limits) -> Result<(SharedShape, Pose), MoveItError> {
    let kind = node.need("type")?;
    let kind = match kind.value {
        serde_yaml::Value::Number(n) => match n.as_i64() {
            Some(1) => "box",
            Some(2) => "sphere",
            Some(3) => "cylinder",
            Some(4) => "cone",
            Some(5) => "prism",
            _ => return Err(kind.error("unknown primitive type (1–5)")),
        },
        _ => kind.text()?,
    }
    .to_ascii_lowercase();
    let dims = node.need("dimensions")?;
    let d = dims.numbers()?;
    let need = |n: usize| -> Result<(), MoveItError> {
        if d.len() != n {
            return Err(dims.error(format!("a {kind} has {n} dimensions, got {}", d.len())));
        }
        if d.iter().any(|&v| v <= 0.0 || v > limits.max_size) {
            return Err(dims.error(format!(
                "dimensions must be positive and at most {} m",
                limits.max_size
            )));
        }
        Ok(())
    };
    let y_to_z = Pose::from_rotation(Quat::from_rotation_x(std::f64::consts::FRAC_PI_2));
    let shape = match kind.as_str() {
        "box" => {
            need(3)?;
            Geometry::Box {
                half_extents: Vec3::new(d[0], d[1], d[2]) / 2.0,
            }
        }
        "sphere" => {
            need(1)?;
            Geometry::Sphere { radius: d[0] }
        }
        "cylinder" => {
            need(2)?;
            Geometry::Cylinder {
                length: d[0],
                radius: d[1],
            }
        }
        "cone" => {
            need(2)?;
            return Ok((SharedShape::cone(d[0] / 2.0, d[1]), y_to_z));
        }
        other => return Err(kind_error(node, other)),
    };
    shape.collision_shape(false).map_err(|m| node.error(m))
}

fn kind_error(node: &Node, kind: &str) -> MoveItError {
    node.error(format!(
        "primitive type `{kind}` is not supported (box, sphere, cylinder, cone)"
    ))
}

/// A `shape_msgs/Mesh`: vertices and triangles, as a solid (its hull, or a convex
/// decomposition where it is notably concave: a shelf keeps its openings).
fn mesh(node: &Node, limits: &Limits) -> Result<SharedShape, MoveItError> {
    let vertices = node.list("vertices")?;
    let triangles = node.list("triangles")?;
    if vertices.len() > limits.mesh_vertices || triangles.len() > 2 * limits.mesh_vertices {
        return Err(MoveItError::TooLarge(format!(
            "{}: a mesh of {} vertices and {} triangles, over the limit of {} vertices",
            node.path(),
            vertices.len(),
            triangles.len(),
            limits.mesh_vertices
        )));
    }
    let points: Vec<Vec3> = vertices.iter().map(Node::vec3).collect::<Result<_, _>>()?;
    let mut tris = Vec::with_capacity(triangles.len());
    for t in &triangles {
        let idx = t.need("vertex_indices")?;
        let v = idx.numbers()?;
        if v.len() != 3
            || v.iter()
                .any(|&i| i < 0.0 || i.fract() != 0.0 || i as usize >= points.len())
        {
            return Err(idx.error(format!(
                "three vertex indices below {} expected",
                points.len()
            )));
        }
        tris.push([v[0] as u32, v[1] as u32, v[2] as u32]);
    }
    tabula_geom::mesh::mesh_shape(&points, &tris, true).map_err(|m| node.error(m))
}

fn allowed_collisions(node: &Node) -> Result<AllowedCollisions, MoveItError> {
    let names: Vec<String> = match node.get("entry_names") {
        Some(n) => n.texts()?.into_iter().map(String::from).collect(),
        None => Vec::new(),
    };
    let mut allowed = Vec::with_capacity(names.len());
    for row in node.list("entry_values")? {
        let values = row
            .get("enabled")
            .unwrap_or_else(|| row.clone())
            .items()?
            .iter()
            .map(|v| {
                v.value
                    .as_bool()
                    .ok_or_else(|| v.error("expected true or false"))
            })
            .collect::<Result<Vec<bool>, _>>()?;
        if values.len() != names.len() {
            return Err(row.error(format!(
                "{} values for {} entry names",
                values.len(),
                names.len()
            )));
        }
        allowed.push(values);
    }
    if allowed.len() != names.len() {
        return Err(node.error(format!(
            "{} rows for {} entry names",
            allowed.len(),
            names.len()
        )));
    }
    let default_names = match node.get("default_entry_names") {
        Some(n) => n.texts()?,
        None => Vec::new(),
    };
    let default_values = node.list("default_entry_values")?;
    if default_names.len() != default_values.len() {
        return Err(node.error("default entry names and values differ in number"));
    }
    let defaults = default_names
        .into_iter()
        .zip(&default_values)
        .map(|(n, v)| {
            v.value
                .as_bool()
                .map(|b| (n.to_string(), b))
                .ok_or_else(|| v.error("expected true or false"))
        })
        .collect::<Result<_, _>>()?;
    Ok(AllowedCollisions {
        names,
        allowed,
        defaults,
    })
}
