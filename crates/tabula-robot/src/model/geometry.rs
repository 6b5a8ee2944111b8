//! Link geometry from URDF: primitives and meshes, mesh references resolved through the
//! package search, and meshes that cannot be found recorded rather than dropped.

use super::urdf::checked_value;
use crate::RobotError;
use crate::packages::PackagePaths;
use std::path::{Path, PathBuf};
use tabula_geom::{Pose, Vec3};

/// Shape of a visual or collision element.
#[derive(Debug, Clone, PartialEq)]
pub enum Geometry {
    Box {
        half_extents: Vec3,
    },
    /// Along the z axis of the shape frame.
    Cylinder {
        radius: f64,
        length: f64,
    },
    /// Along the z axis of the shape frame; `length` excludes the caps.
    Capsule {
        radius: f64,
        length: f64,
    },
    Sphere {
        radius: f64,
    },
    /// A mesh file, `package://` already resolved to a path.
    Mesh {
        path: PathBuf,
        scale: Vec3,
    },
}

impl Geometry {
    /// The vertices of a mesh geometry, scaled; `None` for primitives and unreadable
    /// files.
    pub fn hull_points(&self) -> Option<Vec<Vec3>> {
        match self {
            Geometry::Mesh { path, scale } => tabula_geom::mesh::load_mesh(path, scale.to_array())
                .ok()
                .map(|(p, _)| p),
            _ => None,
        }
    }

    /// The one URDF-geometry → collision-shape path (simulator, planner and tools all
    /// use it): the parry shape and its pose in the URDF shape frame (parry's cylinders
    /// stand along y, URDF's along z). Meshes become solids by
    /// [`tabula_geom::mesh::mesh_shape`]; a missing or broken mesh is an error the caller
    /// reports or skips.
    pub fn collision_shape(
        &self,
        decompose: bool,
    ) -> Result<(tabula_geom::parry::shape::SharedShape, Pose), String> {
        use tabula_geom::parry::shape::SharedShape;
        let y_to_z = Pose::from_rotation(tabula_geom::Quat::from_rotation_x(
            std::f64::consts::FRAC_PI_2,
        ));
        Ok(match self {
            Geometry::Box { half_extents } => (
                SharedShape::cuboid(half_extents.x, half_extents.y, half_extents.z),
                Pose::IDENTITY,
            ),
            Geometry::Cylinder { radius, length } => {
                (SharedShape::cylinder(length / 2.0, *radius), y_to_z)
            }
            Geometry::Capsule { radius, length } => (
                SharedShape::capsule_z(length / 2.0, *radius),
                Pose::IDENTITY,
            ),
            Geometry::Sphere { radius } => (SharedShape::ball(*radius), Pose::IDENTITY),
            Geometry::Mesh { path, scale } => {
                let (points, triangles) = tabula_geom::mesh::load_mesh(path, scale.to_array())
                    .map_err(|e| e.to_string())?;
                let shape = tabula_geom::mesh::mesh_shape(&points, &triangles, decompose)
                    .map_err(|m| format!("mesh `{}`: {m}", path.display()))?;
                (shape, Pose::IDENTITY)
            }
        })
    }
}

/// A placed shape on a link.
#[derive(Debug, Clone, PartialEq)]
pub struct Shape {
    pub link_from_shape: Pose,
    pub geometry: Geometry,
}

/// A mesh a link names that is not there (or is not a file).
#[derive(Debug, Clone, PartialEq)]
pub struct UnreadableMesh {
    pub link: String,
    /// `visual` or `collision`.
    pub role: &'static str,
    pub filename: String,
    pub problem: String,
}

impl std::fmt::Display for UnreadableMesh {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "link `{}`: {} mesh `{}` {}",
            self.link, self.role, self.filename, self.problem
        )
    }
}

/// Where mesh references resolve, and what could not be.
pub(super) struct MeshContext<'a> {
    pub(super) base_dir: Option<&'a Path>,
    pub(super) packages: &'a PackagePaths,
    pub(super) unreadable: std::cell::RefCell<Vec<UnreadableMesh>>,
}

pub(super) fn convert_geometry(
    owner: &str,
    role: &'static str,
    g: &urdf_rs::Geometry,
    meshes: &MeshContext,
) -> Result<Geometry, RobotError> {
    let check = |field: &'static str, v: f64| {
        let v = checked_value(owner, field, v)?;
        if v >= 0.0 {
            Ok(v)
        } else {
            Err(RobotError::NonFinite {
                joint: owner.to_string(),
                field,
                value: v,
            })
        }
    };
    Ok(match g {
        urdf_rs::Geometry::Box { size } => Geometry::Box {
            half_extents: Vec3::new(
                check("box size", size.0[0])?,
                check("box size", size.0[1])?,
                check("box size", size.0[2])?,
            ) * 0.5,
        },
        urdf_rs::Geometry::Cylinder { radius, length } => Geometry::Cylinder {
            radius: check("cylinder radius", *radius)?,
            length: check("cylinder length", *length)?,
        },
        urdf_rs::Geometry::Capsule { radius, length } => Geometry::Capsule {
            radius: check("capsule radius", *radius)?,
            length: check("capsule length", *length)?,
        },
        urdf_rs::Geometry::Sphere { radius } => Geometry::Sphere {
            radius: check("sphere radius", *radius)?,
        },
        urdf_rs::Geometry::Mesh { filename, scale } => {
            let s = scale.as_ref().map(|s| s.0).unwrap_or([1.0; 3]);
            for v in s {
                checked_value(owner, "mesh scale", v)?;
            }
            let bad_mesh = |problem: &str| RobotError::BadMesh {
                owner: owner.to_string(),
                filename: tabula_geom::input::clip(filename, 200),
                problem: problem.to_string(),
            };
            // `package://pkg/../..` must stay inside the package (and so inside the
            // robot's folder tree), as ROS's resolver keeps it.
            if let Some(rest) = filename.strip_prefix("package://")
                && Path::new(rest)
                    .components()
                    .any(|c| matches!(c, std::path::Component::ParentDir))
            {
                return Err(bad_mesh("climbs out of its package with `..`"));
            }
            let resolved = resolve_mesh_path(filename, meshes.base_dir, meshes.packages);
            if let Ok(p) = &resolved
                && p.exists()
                && !p.is_file()
            {
                // A device or folder named as a mesh is a hostile file, not a missing one.
                return Err(bad_mesh(&format!(
                    "resolves to {}, which is not a regular file",
                    p.display()
                )));
            }
            // A file-loaded URDF's meshes are checked where they are named, not when a
            // collision world first needs them: kinematics goes on without them, and
            // collision users refuse the robot (`require_meshes`).
            let problem = match &resolved {
                Err(problem) => Some(problem.clone()),
                Ok(p) if meshes.base_dir.is_some() && !p.is_file() => {
                    Some(format!("resolves to {}, which is missing", p.display()))
                }
                Ok(_) => None,
            };
            if let Some(problem) = problem {
                meshes.unreadable.borrow_mut().push(UnreadableMesh {
                    link: owner.to_string(),
                    role,
                    filename: tabula_geom::input::clip(filename, 200),
                    problem,
                });
            }
            let path = resolved.unwrap_or_else(|_| PathBuf::from(filename));
            Geometry::Mesh {
                path,
                scale: Vec3::from_array(s),
            }
        }
    })
}

/// Resolves a URDF mesh reference without ROS: `package://pkg/rest` through the
/// package resolver ([`PackagePaths`]: package folders, `ROS_PACKAGE_PATH`, the folders
/// above the URDF); `file://` as an absolute path; relative paths against the URDF's
/// folder. The error names every folder searched.
pub fn resolve_mesh_path(
    filename: &str,
    base_dir: Option<&Path>,
    packages: &PackagePaths,
) -> Result<PathBuf, String> {
    if filename.starts_with("package://") {
        return packages.resolve_url(filename, base_dir);
    }
    if let Some(abs) = filename.strip_prefix("file://") {
        return Ok(PathBuf::from(abs));
    }
    Ok(match base_dir {
        Some(dir) if Path::new(filename).is_relative() => dir.join(filename),
        _ => PathBuf::from(filename),
    })
}
