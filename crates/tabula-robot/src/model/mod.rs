//! Robot models loaded from URDF: links, joints, collision shapes, limits.
//!
//! The URDF is parsed with `urdf-rs` and then checked here, because urdf-rs accepts
//! files that are not trees (cycles, two parents, dangling links) and numbers that are
//! not numbers (NaN limits); every such file gets one typed [`RobotError`].

use crate::RobotError;
use crate::packages::PackagePaths;
use std::collections::HashMap;
use std::path::Path;
use tabula_geom::{Pose, Vec3};

mod default_tool;
mod geometry;
mod urdf;

use geometry::MeshContext;
pub use geometry::{Geometry, Shape, UnreadableMesh, resolve_mesh_path};

/// The link [`RobotModel::add_pedestal`] adds.
pub const PEDESTAL_LINK: &str = "pedestal";

/// How a joint moves.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum JointKind {
    /// Rotation about `axis` within limits.
    Revolute,
    /// Rotation about `axis` without limits.
    Continuous,
    /// Translation along `axis` within limits.
    Prismatic,
    /// No motion.
    Fixed,
    /// URDF floating, planar or spherical joints: several axes, so never part of a chain.
    MultiAxis(&'static str),
}

impl JointKind {
    /// True for joints that carry one joint value.
    pub fn is_single_axis(self) -> bool {
        matches!(self, Self::Revolute | Self::Continuous | Self::Prismatic)
    }
}

/// Position, velocity and effort limits of one joint (SI units).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JointLimits {
    pub lower: f64,
    pub upper: f64,
    pub velocity: f64,
    pub effort: f64,
}

/// A joint that copies another: `value = multiplier * master + offset`.
#[derive(Debug, Clone, PartialEq)]
pub struct Mimic {
    pub master: usize,
    pub multiplier: f64,
    pub offset: f64,
}

/// One URDF joint, with indices into [`RobotModel::links`].
#[derive(Debug, Clone)]
pub struct Joint {
    pub name: String,
    pub kind: JointKind,
    pub parent: usize,
    pub child: usize,
    /// Pose of the joint frame (and of the child link at zero motion) in the parent link frame.
    pub parent_from_joint: Pose,
    /// Unit axis in the joint frame.
    pub axis: Vec3,
    /// Continuous joints have infinite position limits.
    pub limits: JointLimits,
    pub mimic: Option<Mimic>,
}

impl Joint {
    /// Pose of the child link in the parent link frame at joint value `q`.
    pub fn parent_from_child(&self, q: f64) -> Pose {
        self.parent_from_joint * joint_motion(self.kind, self.axis, q)
    }
}

/// The motion of a single-axis joint at value `q` (identity for other kinds).
pub fn joint_motion(kind: JointKind, axis: Vec3, q: f64) -> Pose {
    match kind {
        JointKind::Revolute | JointKind::Continuous => {
            Pose::from_rotation(tabula_geom::Quat::from_axis_angle(axis, q))
        }
        JointKind::Prismatic => Pose::from_translation(axis * q),
        _ => Pose::IDENTITY,
    }
}

/// One URDF link.
#[derive(Debug, Clone)]
pub struct Link {
    pub name: String,
    pub parent_joint: Option<usize>,
    pub child_joints: Vec<usize>,
    pub collision: Vec<Shape>,
    pub visual: Vec<Shape>,
    pub mass: f64,
}

/// A robot: a forest of links joined by joints (a URDF is normally one tree).
#[derive(Debug, Clone)]
pub struct RobotModel {
    pub name: String,
    pub links: Vec<Link>,
    pub joints: Vec<Joint>,
    /// Links without a parent joint (one for a well-formed URDF).
    pub roots: Vec<usize>,
    link_index: HashMap<String, usize>,
    joint_index: HashMap<String, usize>,
    /// Mesh files named by the URDF that cannot be found: kinematics works without
    /// them; anything that checks collisions must refuse the robot
    /// ([`Self::require_meshes`]).
    pub unreadable_meshes: Vec<UnreadableMesh>,
    /// What the URDF says that was ignored, one sentence each (a `<mimic>` on a fixed
    /// joint), for the caller to warn about.
    pub ignored: Vec<String>,
    /// Frames added after loading ([`Self::add_fixed_frame`]): not in the URDF.
    pub added_frames: Vec<usize>,
}

impl RobotModel {
    /// Loads a URDF file, or a xacro file (`.xacro`) expanded first, with no xacro
    /// arguments; `package://pkg/...` mesh paths resolve as [`PackagePaths`] finds them.
    pub fn from_urdf_file(path: impl AsRef<Path>) -> Result<Self, RobotError> {
        Self::from_file_with(path.as_ref(), &[], &PackagePaths::default())
    }

    /// [`Self::from_urdf_file`] with xacro arguments (`name`, `value`) and package folders.
    pub fn from_file_with(
        path: &Path,
        xacro_args: &[(String, String)],
        packages: &PackagePaths,
    ) -> Result<Self, RobotError> {
        let text = if crate::xacro::is_xacro(path) {
            crate::xacro::expand(path, xacro_args, packages)?
        } else {
            tabula_geom::input::read_text(path, tabula_geom::input::Format::Robot)?
        };
        Self::parse(&text, path.parent(), Some(path), packages)
    }

    /// Loads a URDF from text; relative mesh paths resolve against `base_dir` if given.
    pub fn from_urdf_str(text: &str, base_dir: Option<&Path>) -> Result<Self, RobotError> {
        Self::parse(text, base_dir, None, &PackagePaths::default())
    }

    fn parse(
        text: &str,
        base_dir: Option<&Path>,
        file: Option<&Path>,
        packages: &PackagePaths,
    ) -> Result<Self, RobotError> {
        let parse_err = |message: String| RobotError::Parse {
            path: file.map(Path::to_path_buf),
            message,
        };
        let depth = tabula_geom::input::xml_depth(text, 256);
        if depth > 256 {
            return Err(RobotError::TooDeep(depth));
        }
        // urdf-rs panics on a few malformed inputs (found by the proptest over mutated
        // files); a panic is a parse error to our caller, never a crash.
        let parsed = tabula_geom::guard::catch_quietly(|| urdf_rs::read_from_string(text))
            .map_err(|_| parse_err("the XML could not be read as URDF".into()))?
            .map_err(|e| parse_err(e.to_string()))?;
        Self::from_urdf_robot(&parsed, base_dir, packages)
    }

    /// Builds and validates a model from an already parsed URDF.
    pub fn from_urdf_robot(
        robot: &urdf_rs::Robot,
        base_dir: Option<&Path>,
        packages: &PackagePaths,
    ) -> Result<Self, RobotError> {
        let meshes = MeshContext {
            base_dir,
            packages,
            unreadable: std::cell::RefCell::new(Vec::new()),
        };
        if robot.links.is_empty() {
            return Err(RobotError::NoLinks);
        }
        let mut links = Vec::with_capacity(robot.links.len());
        let mut link_index = HashMap::new();
        for l in &robot.links {
            if link_index.insert(l.name.clone(), links.len()).is_some() {
                return Err(RobotError::DuplicateLink(l.name.clone()));
            }
            links.push(urdf::link_of(l, &meshes)?);
        }
        let mut joints: Vec<Joint> = Vec::with_capacity(robot.joints.len());
        let mut joint_index = HashMap::new();
        for j in &robot.joints {
            if joint_index.insert(j.name.clone(), joints.len()).is_some() {
                return Err(RobotError::DuplicateJoint(j.name.clone()));
            }
            joints.push(urdf::joint_of(j, &link_index)?);
        }
        let ignored = urdf::resolve_mimics(&robot.joints, &mut joints, &joint_index)?;
        let roots = urdf::connect(&mut links, &joints)?;
        Ok(Self {
            name: robot.name.clone(),
            links,
            joints,
            roots,
            link_index,
            joint_index,
            unreadable_meshes: meshes.unreadable.into_inner(),
            ignored,
            added_frames: Vec::new(),
        })
    }

    /// An error naming the first collision mesh that cannot be read, for anything that
    /// checks collisions (a missing mesh must never become a link without geometry).
    pub fn require_meshes(&self) -> Result<(), RobotError> {
        match self
            .unreadable_meshes
            .iter()
            .find(|u| u.role == "collision")
        {
            Some(u) => Err(RobotError::BadMesh {
                owner: u.link.clone(),
                filename: u.filename.clone(),
                problem: format!(
                    "{} ({} collision mesh(es) of this robot cannot be read)",
                    u.problem,
                    self.unreadable_meshes
                        .iter()
                        .filter(|u| u.role == "collision")
                        .count()
                ),
            }),
            None => Ok(()),
        }
    }

    /// Index of a link by name, with a clear error listing the links if unknown.
    pub fn link(&self, name: &str) -> Result<usize, RobotError> {
        self.link_index.get(name).copied().ok_or_else(|| {
            let mut known: Vec<&str> = self.links.iter().map(|l| l.name.as_str()).collect();
            known.sort_unstable();
            RobotError::UnknownLink {
                name: name.to_string(),
                robot: self.name.clone(),
                known: known.join(", "),
            }
        })
    }

    /// Adds a frame without geometry fixed to `parent` (a grasp frame the URDF lacks),
    /// joined by a fixed joint `<name>_joint`; `Err` when either name is taken.
    pub fn add_fixed_frame(
        &mut self,
        parent: usize,
        name: &str,
        parent_from_frame: Pose,
    ) -> Result<usize, RobotError> {
        let joint_name = format!("{name}_joint");
        if self.link_index.contains_key(name) || self.joint_index.contains_key(&joint_name) {
            return Err(RobotError::Description(format!(
                "cannot add frame `{name}`: the name is taken"
            )));
        }
        let (link, joint) = (self.links.len(), self.joints.len());
        self.links.push(Link {
            name: name.into(),
            parent_joint: Some(joint),
            child_joints: Vec::new(),
            collision: Vec::new(),
            visual: Vec::new(),
            mass: 0.0,
        });
        self.joints.push(Joint {
            name: joint_name.clone(),
            kind: JointKind::Fixed,
            parent,
            child: link,
            parent_from_joint: parent_from_frame,
            axis: Vec3::Z,
            limits: JointLimits {
                lower: 0.0,
                upper: 0.0,
                velocity: 0.0,
                effort: 0.0,
            },
            mimic: None,
        });
        self.links[parent].child_joints.push(joint);
        self.link_index.insert(name.into(), link);
        self.joint_index.insert(joint_name, joint);
        self.added_frames.push(link);
        Ok(link)
    }

    /// Adds the robot's mount: a solid box `size` (x, y, height; m) centred under the
    /// root link, its top at the root's origin, as link [`PEDESTAL_LINK`] — what a cell's
    /// URDF adds so that planners keep the arm off what it stands on (nothing else sees
    /// it from there: it is below the table and out of the cameras' views).
    pub fn add_pedestal(&mut self, size: [f64; 3]) -> Result<usize, RobotError> {
        if size.iter().any(|d| !(d.is_finite() && *d > 0.0)) {
            return Err(RobotError::Description(format!(
                "a pedestal's size must be positive and finite, got {size:?}"
            )));
        }
        let root = *self.roots.first().ok_or_else(|| {
            RobotError::Description("a robot without a root link has no pedestal".into())
        })?;
        let link = self.add_fixed_frame(root, PEDESTAL_LINK, Pose::IDENTITY)?;
        let shape = Shape {
            link_from_shape: Pose::from_translation(Vec3::new(0.0, 0.0, -size[2] / 2.0)),
            geometry: Geometry::Box {
                half_extents: Vec3::from_array(size) / 2.0,
            },
        };
        self.links[link].collision.push(shape.clone());
        self.links[link].visual.push(shape);
        // A body, not a frame the user asked for: `added_frames` lists grasp frames.
        self.added_frames.retain(|&f| f != link);
        Ok(link)
    }

    /// Index of a joint by name.
    pub fn joint(&self, name: &str) -> Option<usize> {
        self.joint_index.get(name).copied()
    }

    /// Joints that carry their own value (single-axis, not mimic), in URDF order.
    pub fn active_joints(&self) -> Vec<usize> {
        (0..self.joints.len())
            .filter(|&j| self.joints[j].kind.is_single_axis() && self.joints[j].mimic.is_none())
            .collect()
    }

    /// A full joint-value vector (indexed like [`Self::joints`]) at the middle of every
    /// limited joint and 0 for continuous ones.
    pub fn mid_configuration(&self) -> Vec<f64> {
        self.joints
            .iter()
            .map(|j| {
                if j.limits.lower.is_finite() && j.limits.upper.is_finite() {
                    0.5 * (j.limits.lower + j.limits.upper)
                } else {
                    0.0
                }
            })
            .collect()
    }

    /// The value of joint `j` given the values of all joints (mimic joints follow their master).
    pub fn joint_value(&self, values: &[f64], j: usize) -> f64 {
        match &self.joints[j].mimic {
            Some(m) => m.multiplier * values.get(m.master).copied().unwrap_or(0.0) + m.offset,
            None => values.get(j).copied().unwrap_or(0.0),
        }
    }

    /// Pose of every link in the frame of its tree's root, given one value per joint
    /// (indexed like [`Self::joints`]; values of fixed joints are ignored).
    pub fn forward_kinematics(&self, values: &[f64]) -> Result<Vec<Pose>, RobotError> {
        if values.len() != self.joints.len() {
            return Err(RobotError::WrongJointCount {
                expected: self.joints.len(),
                got: values.len(),
            });
        }
        let mut root_from_link = vec![Pose::IDENTITY; self.links.len()];
        let mut stack = self.roots.clone();
        while let Some(l) = stack.pop() {
            for &j in &self.links[l].child_joints {
                let joint = &self.joints[j];
                root_from_link[joint.child] =
                    root_from_link[l] * joint.parent_from_child(self.joint_value(values, j));
                stack.push(joint.child);
            }
        }
        Ok(root_from_link)
    }
}

#[cfg(test)]
mod depth_tests {
    use super::*;

    #[test]
    fn nesting_is_counted_without_recursion() {
        assert_eq!(
            tabula_geom::input::xml_depth("<a><b/><c><d></d></c><!-- <e><f> --></a>", 10),
            3
        );
        assert_eq!(
            tabula_geom::input::xml_depth("<?xml version=\"1.0\"?><r><![CDATA[<x><y>]]></r>", 10),
            1
        );
        let deep = format!("{}{}", "<l>".repeat(100_000), "</l>".repeat(100_000));
        assert!(tabula_geom::input::xml_depth(&deep, 256) > 256);
        assert!(matches!(
            RobotModel::from_urdf_str(&format!("<robot name=\"r\">{deep}</robot>"), None),
            Err(RobotError::TooDeep(_))
        ));
    }
}
