//! The robot's own body as solids, placed by forward kinematics: what the self-filter
//! removes from a frame.

use tabula_geom::Pose;
use tabula_perception::selffilter::{PlacedSolid, Solid};
use tabula_robot::RobotModel;
use tabula_robot::model::Geometry;

/// The robot's collision shapes placed at joint values `values` (model order): the
/// solids the self-filter removes.
pub fn robot_solids(model: &RobotModel, values: &[f64], world_from_root: Pose) -> Vec<PlacedSolid> {
    let Ok(root_from_link) = model.forward_kinematics(values) else {
        return Vec::new();
    };
    let mut out = Vec::new();
    for (l, link) in model.links.iter().enumerate() {
        for shape in &link.collision {
            let solid = match &shape.geometry {
                Geometry::Box { half_extents } => Solid::Box {
                    half_extents: *half_extents,
                },
                Geometry::Sphere { radius } => Solid::Sphere { radius: *radius },
                Geometry::Cylinder { radius, length } => Solid::Cylinder {
                    radius: *radius,
                    half_length: length / 2.0,
                },
                Geometry::Capsule { radius, length } => Solid::Capsule {
                    radius: *radius,
                    half_length: length / 2.0,
                },
                Geometry::Mesh { .. } => match shape
                    .geometry
                    .hull_points()
                    .and_then(|p| Solid::convex_hull(&p))
                {
                    Some(s) => s,
                    None => continue,
                },
            };
            out.push(PlacedSolid {
                world_from_solid: world_from_root * root_from_link[l] * shape.link_from_shape,
                solid,
            });
        }
    }
    out
}
