//! The planning world as a frame sees the table: the seen objects' hulls in the group's
//! world, and actions that take some of them out while they are checked.

use super::pick::object_name;
use crate::scene::SeenObject;
use tabula_geom::Pose;
use tabula_motion::MoveGroup;

/// Replaces every seen object in the group's world by `objects`' hulls.
pub fn load_objects(group: &mut MoveGroup, objects: &[SeenObject]) {
    for name in group.world.object_names() {
        if name.starts_with("obj:") {
            let _ = group.remove_object(&name);
        }
    }
    for o in objects {
        let _ = group.add_object(&object_name(o), o.hull.clone(), Pose::IDENTITY);
    }
}

/// Runs `check` with objects `moving` (indices into `objects`: what the action takes or
/// shoves) out of the group's world, then puts them back.
pub fn without<T>(
    group: &mut MoveGroup,
    objects: &[SeenObject],
    moving: &[usize],
    check: impl FnOnce(&mut MoveGroup) -> T,
) -> T {
    for &m in moving {
        let _ = group.remove_object(&object_name(&objects[m]));
    }
    let out = check(group);
    for &m in moving {
        let _ = group.add_object(
            &object_name(&objects[m]),
            objects[m].hull.clone(),
            Pose::IDENTITY,
        );
    }
    out
}
