//! Ground truth for placing a mesh: the true object's stable poses, which of them the
//! grip leaves free — what the placer should have found from its scan.

use tabula_geom::{Pose, Vec3};
use tabula_tasks::place::PlaceParams;

/// The true object's (the scene's held mesh's) stable poses as support normals in the
/// tool frame, each with whether it is a resting face the hand leaves free: it tilts at
/// least `min_topple_deg` before toppling, it is a flat face (not a curved side), and
/// the hand stays clear of its plane — the tests the placer applies to its scanned
/// model, here on the exact mesh (or the primitive's). When no
/// face leaves the hand clear, no placement can rest as planned without a regrasp (a
/// ball with a pocket held across the pocket). `None` for scenes without a held object
/// (or one of a shape it does not mesh).
pub(super) fn resting_faces(
    scene: &tabula_sim::Scene,
    params: &PlaceParams,
) -> Option<Vec<(Vec3, bool)>> {
    let (robot_spec, hold, object) = held(scene)?;
    let (vertices, triangles) = held_mesh(scene, &object.shape)?;
    // At the placer's own contact tolerance: a rim of slightly uneven vertices (a
    // pocket's) is one support, as a scanned one is to the placer.
    let tolerant = tabula_tasks::stable::StableParams {
        contact_tolerance: params.stable.cloud_contact_tolerance,
        ..params.stable.clone()
    };
    let poses = tabula_tasks::stable::of_mesh(&vertices, &triangles, &tolerant).ok()?;
    let com = Vec3::from_array(poses.center_of_mass);
    let robot = tabula_robot::robots::load(&robot_spec.urdf).ok()?;
    let arm = robot
        .description
        .arms
        .iter()
        .find(|a| {
            a.gripper
                .as_deref()
                .and_then(|g| robot.description.grippers.iter().find(|x| x.name == g))
                .is_some_and(|g| g.tool_link == hold.tool_link)
        })?
        .name
        .clone();
    let tool_from_object = hold.tool_from_object.as_ref().map_or(Pose::IDENTITY, |p| {
        tabula_geom::pose_from_xyz_rpy(p.xyz, p.rpy)
    });
    let object_from_tool = tool_from_object.inverse();
    let gripper: Vec<Vec3> = tabula_tasks::place::gripper_points(&robot, &arm)
        .into_iter()
        .map(|g| object_from_tool.transform_point(g))
        .collect();
    // A flat support (not a curved side that only looks flat within the tolerance:
    // most of its energy barrier really there), tilting far enough, the hand clear.
    Some(
        poses
            .poses
            .iter()
            .map(|s| {
                let flat =
                    s.topple_deg >= params.min_topple_deg && s.rocking(&vertices, com) >= 0.5;
                tracing::debug!(
                    "truth: pose {:?} (tool {:?}) topple {:.1}° hand margin {:.1} mm",
                    s.support_normal,
                    tool_from_object.rotation * s.normal(),
                    s.topple_deg,
                    s.hand_margin(&gripper) * 1e3
                );
                (
                    tool_from_object.rotation * s.normal(),
                    flat && s.clear_of(&gripper, params.gripper_clearance - params.release_height),
                )
            })
            .collect(),
    )
}

/// The robot holding an object in `scene`, its hold and the object.
pub(super) fn held(
    scene: &tabula_sim::Scene,
) -> Option<(
    &tabula_sim::scene::RobotSpec,
    &tabula_sim::scene::HoldSpec,
    &tabula_sim::scene::ObjectSpec,
)> {
    let (robot, hold) = scene
        .robots
        .iter()
        .find_map(|r| r.hold.as_ref().map(|h| (r, h)))?;
    let object = scene
        .objects
        .iter()
        .find(|o| *o.name.get_ref() == hold.object)?;
    Some((robot, hold, object))
}

/// The held object's exact surface: a mesh file as the scene scales it, a box, or a
/// cylinder as a 64-sided prism (its stable poses are the caps and the side).
fn held_mesh(
    scene: &tabula_sim::Scene,
    shape: &tabula_sim::scene::ShapeSpec,
) -> Option<(Vec<Vec3>, Vec<[u32; 3]>)> {
    use tabula_sim::objects::{cuboid, lathe};
    use tabula_sim::scene::ShapeSpec;
    match shape {
        ShapeSpec::Mesh { path, scale } => {
            let path = scene
                .base_dir
                .as_ref()
                .map_or_else(|| path.into(), |d| d.join(path));
            tabula_geom::mesh::load_mesh(&path, *scale).ok()
        }
        ShapeSpec::Box(size) => {
            let size = Vec3::from_array(*size);
            Some(cuboid(-size / 2.0, size))
        }
        ShapeSpec::Cylinder { radius, height } => Some(lathe(
            &[
                (0.0, -height / 2.0),
                (*radius, -height / 2.0),
                (*radius, height / 2.0),
                (0.0, height / 2.0),
            ],
            64,
        )),
        _ => None,
    }
}
