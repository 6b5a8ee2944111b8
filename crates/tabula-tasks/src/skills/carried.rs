//! After a lift: does the hand carry more than the object it took? An object resting on
//! or leaning against the one taken comes up with it and falls on the way (off the
//! table, where a bin is beside it); the camera sees it hanging with the hand.

use crate::scene::SeenObject;
use tabula_geom::parry::bounding_volume::BoundingVolume;
use tabula_geom::{PointCloud, Pose, Quat, Vec3};

/// What counts as carried along (see [`points_carried_along`]).
#[derive(Debug, Clone, Copy, PartialEq, serde::Deserialize, serde::Serialize)]
#[serde(default, deny_unknown_fields)]
pub struct CarriedCheck {
    /// A point this far (m) from the held object's lifted hull and from every other
    /// object's hull is not theirs: the hull is seen from one side, and a grasp moves
    /// the object in the hand by a few millimetres.
    pub margin: f64,
    /// This many such points hanging with the hand are another object (a thin can
    /// seen end-on at a decimated frame's resolution is ~50), fewer are the hand's
    /// mixed edge pixels.
    pub min_points: usize,
    /// Points farther than this (m) across from the tool are not in the hand.
    pub reach: f64,
}

impl Default for CarriedCheck {
    fn default() -> Self {
        Self {
            margin: 0.02,
            min_points: 20,
            reach: 0.25,
        }
    }
}

/// The held object and where the lift took it: `objects[held]` as it was seen, raised
/// by `lift` (world) with the tool at `tool` (world); the others as they were seen,
/// but those `moved` names (pushed aside by the fingers).
pub struct Lifted<'a> {
    pub objects: &'a [SeenObject],
    pub held: usize,
    pub moved: &'a [usize],
    pub lift: Vec3,
    pub tool: Vec3,
    pub up: Vec3,
}

/// How many points of `cloud` (world, the robot filtered out) hang in the air with the
/// hand but belong neither to the held object where the lift took it nor to another
/// object where it was seen: more than [`CarriedCheck::min_points`] is an object carried
/// along.
pub fn points_carried_along(cloud: &PointCloud, at: &Lifted<'_>, check: &CarriedCheck) -> usize {
    let up = at.up;
    // Above half the lift over the held object's bottom: in the air, not on the table.
    let held = &at.objects[at.held];
    let floor = held.bottom + 0.5 * at.lift.dot(up);
    let held_pose = Pose::from_parts(at.lift, Quat::IDENTITY);
    let near = |o: &SeenObject, pose: &Pose, p: Vec3| {
        o.hull.distance_to_point(pose, p, true) <= check.margin
    };
    // The box test first: most objects are far from most points.
    let near_seen = |o: &SeenObject, p: Vec3| {
        o.aabb.loosened(check.margin).contains_local_point(p) && near(o, &Pose::IDENTITY, p)
    };
    cloud
        .points
        .iter()
        .filter(|p| p.is_finite() && p.dot(up) > floor)
        .filter(|&&p| {
            let across = (p - at.tool) - up * (p - at.tool).dot(up);
            across.length() <= check.reach
        })
        .filter(|&&p| !near(held, &held_pose, p))
        .filter(|&&p| {
            !at.objects
                .iter()
                .enumerate()
                .any(|(k, o)| k != at.held && !at.moved.contains(&k) && near_seen(o, p))
        })
        .count()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::tabletop::seen_standing;

    /// A box's surface points, `size` (m) with its bottom centre at `at`.
    fn box_points(at: Vec3, size: Vec3) -> Vec<Vec3> {
        let n = 8;
        let mut points = Vec::new();
        for i in 0..=n {
            for j in 0..=n {
                for k in 0..=n {
                    let t = Vec3::new(i as f64, j as f64, k as f64) / n as f64;
                    let on_face = [t.x, t.y, t.z].iter().any(|&c| c == 0.0 || c == 1.0);
                    if on_face {
                        let p = at + (t - Vec3::new(0.5, 0.5, 0.0)) * size;
                        points.push(p);
                    }
                }
            }
        }
        points
    }

    #[test]
    fn an_object_lying_on_the_lifted_one_is_seen_hanging_with_the_hand() {
        let size = Vec3::splat(0.05);
        let held = seen_standing(box_points(Vec3::new(0.6, 0.0, 0.75), size), 0.75).unwrap();
        let beside = seen_standing(box_points(Vec3::new(0.6, 0.1, 0.75), size), 0.75).unwrap();
        let (up, lift) = (Vec3::Z, Vec3::Z * 0.2);
        let objects = [held, beside];
        let at = Lifted {
            objects: &objects,
            held: 0,
            moved: &[],
            lift,
            tool: Vec3::new(0.6, 0.0, 0.78) + lift,
            up,
        };
        let check = CarriedCheck::default();
        // The held box where the lift took it, the neighbour still on the table.
        let mut seen = box_points(Vec3::new(0.6, 0.0, 0.95), size);
        seen.extend(box_points(Vec3::new(0.6, 0.1, 0.75), size));
        let alone = PointCloud::unorganized(seen.clone());
        assert_eq!(points_carried_along(&alone, &at, &check), 0);
        // A second box came up lying across the first's top, half of it over the side.
        seen.extend(box_points(Vec3::new(0.64, 0.0, 1.0), size));
        let carried = points_carried_along(&PointCloud::unorganized(seen), &at, &check);
        assert!(carried >= check.min_points, "{carried} points");
    }
}
