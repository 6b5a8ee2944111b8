//! Load-time overlap checks: a body may not be placed sunk into another deeper than
//! [`saved::MAX_LOAD_OVERLAP`]. One sweep over x serves one object spawned into a world and a
//! scene's objects loaded all at once, so a scene of 10,000 objects loads in about n log n
//! instead of the n² of checking each against the world as it is added.

use super::{SUPPORT_PIECE, SimWorld, saved};
use rapier3d_f64::parry::bounding_volume::{Aabb, BoundingVolume};
use rapier3d_f64::parry::query::contact;
use rapier3d_f64::prelude::*;
use tabula_geom::Pose;

/// A body about to be placed: its name, shape and `world_from_shape`.
pub(super) struct Placement {
    pub name: String,
    pub shape: SharedShape,
    pub world_from_shape: Pose,
}

/// One box in the sweep: an existing collider or the `i`-th placement.
#[derive(Clone, Copy)]
enum Swept {
    Collider(ColliderHandle),
    Placed(usize),
}

impl SimWorld {
    /// The first placement (in order) sunk into something already in the world or into an
    /// earlier placement, with the name of what it is sunk into (the first such, in the
    /// order the world would have checked them one by one).
    pub(super) fn first_overlap(&self, placed: &[Placement]) -> Option<(usize, String)> {
        let mut boxes: Vec<(Aabb, usize, Swept)> = self
            .physics
            .colliders
            .iter()
            .enumerate()
            .map(|(order, (h, c))| (c.compute_aabb(), order, Swept::Collider(h)))
            .collect();
        let first_placed = boxes.len();
        boxes.extend(placed.iter().enumerate().map(|(i, p)| {
            let aabb = p
                .shape
                .compute_aabb(&p.world_from_shape)
                .loosened(saved::MAX_LOAD_OVERLAP);
            (aabb, first_placed + i, Swept::Placed(i))
        }));
        boxes.sort_by(|a, b| a.0.mins.x.total_cmp(&b.0.mins.x));
        // For each placement, the earliest (in order) thing it is sunk into.
        let mut sunk_into: Vec<Option<usize>> = vec![None; placed.len()];
        for (k, (a, a_order, a_what)) in boxes.iter().enumerate() {
            for (b, b_order, b_what) in &boxes[k + 1..] {
                if b.mins.x > a.maxs.x {
                    break;
                }
                if !a.intersects(b) {
                    continue;
                }
                let (later, (earlier_order, earlier)) = if a_order > b_order {
                    (a_what, (*b_order, b_what))
                } else {
                    (b_what, (*a_order, a_what))
                };
                let Swept::Placed(i) = *later else { continue };
                if sunk_into[i].is_some_and(|o| o < earlier_order) {
                    continue;
                }
                if self.sunk(&placed[i], earlier, placed) {
                    sunk_into[i] = Some(earlier_order);
                }
            }
        }
        let (i, order) = sunk_into
            .iter()
            .enumerate()
            .find_map(|(i, o)| o.map(|o| (i, o)))?;
        let name = match boxes.iter().find(|b| b.1 == order)?.2 {
            Swept::Placed(j) => placed[j].name.clone(),
            Swept::Collider(h) => {
                let label = self.physics.colliders[h].user_data & !SUPPORT_PIECE;
                match (label as usize)
                    .checked_sub(1)
                    .map(|e| self.entities.get(e))
                {
                    Some(Some(entity)) => entity.name.clone(),
                    // Built by hand, not from a scene: still an overlap.
                    _ => format!("collider {order} (no entity)"),
                }
            }
        };
        Some((i, name))
    }

    /// Whether `p` sinks into `other` deeper than the load tolerance.
    fn sunk(&self, p: &Placement, other: &Swept, placed: &[Placement]) -> bool {
        let (pose, shape) = match *other {
            Swept::Collider(h) => {
                let c = &self.physics.colliders[h];
                (*c.position(), c.shape())
            }
            Swept::Placed(j) => (placed[j].world_from_shape, placed[j].shape.as_ref()),
        };
        contact(&p.world_from_shape, p.shape.as_ref(), &pose, shape, 0.0)
            .ok()
            .flatten()
            .is_some_and(|k| k.dist < -saved::MAX_LOAD_OVERLAP)
    }
}

#[cfg(test)]
mod tests {
    use crate::Scene;
    use crate::world::{PhysicsParams, SimError, SimWorld};
    use proptest::prelude::*;
    use std::fmt::Write as _;

    fn scene(objects: &[([f64; 3], [f64; 3], f64)]) -> Scene {
        let mut text = String::from(
            "[floor]\nsize = [1.0, 1.0]\n\n[[furniture]]\nname = \"table\"\nkind = \"table\"\n\
             pose = { xyz = [2.0, 0.0, 0.0] }\nsize = [0.6, 0.6, 0.7]\n",
        );
        for (i, (size, xyz, yaw)) in objects.iter().enumerate() {
            write!(
                text,
                "\n[[object]]\nname = \"o{i}\"\nshape = {{ box = {size:?} }}\n\
                 pose = {{ xyz = {xyz:?}, rpy = [0.0, 0.0, {yaw}] }}\n"
            )
            .unwrap();
        }
        Scene::parse(&text, "test.toml").unwrap()
    }

    fn overlap(scene: &Scene) -> Option<(String, String)> {
        match SimWorld::from_scene(scene, PhysicsParams::default()) {
            Err(SimError::Overlap { new, existing }) => Some((new, existing)),
            Err(e) => panic!("{e}"),
            Ok(_) => None,
        }
    }

    /// What adding the objects one by one reports first: each a sweep of one placement
    /// against every collider already built, the plain pairwise check.
    fn overlap_one_by_one(scene: &Scene) -> Option<(String, String)> {
        let mut w = SimWorld::from_scene(
            &Scene {
                objects: Vec::new(),
                ..scene.clone()
            },
            PhysicsParams::default(),
        )
        .unwrap();
        for o in &scene.objects {
            match w.add_object(o) {
                Err(SimError::Overlap { new, existing }) => return Some((new, existing)),
                Err(e) => panic!("{e}"),
                Ok(()) => {}
            }
        }
        None
    }

    #[test]
    fn the_first_sunk_object_names_the_first_thing_it_is_sunk_into() {
        let cube = [0.1, 0.1, 0.1];
        let clear = scene(&[(cube, [0.0, 0.0, 0.05], 0.0), (cube, [0.2, 0.0, 0.05], 0.0)]);
        assert_eq!(overlap(&clear), None);
        // o2 sinks into both o0 and o1: o0 was there first.
        let both = scene(&[
            (cube, [0.0, 0.0, 0.05], 0.0),
            (cube, [0.09, 0.0, 0.05], 0.0),
            (cube, [0.045, 0.0, 0.06], 0.3),
        ]);
        assert_eq!(overlap(&both), Some(("o1".into(), "o0".into())));
        let table = scene(&[(cube, [2.0, 0.0, 0.7], 0.0)]);
        assert_eq!(overlap(&table), Some(("o0".into(), "table".into())));
        // Off the floor's edge, sunk into the ground under it: still the floor.
        let ground = scene(&[(cube, [3.0, 3.0, 0.0], 0.0)]);
        assert_eq!(overlap(&ground), Some(("o0".into(), "floor".into())));
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(64))]
        /// Checking a scene's objects together finds what checking them one by one does.
        #[test]
        fn checked_together_as_one_by_one(
            objects in prop::collection::vec(
                (
                    [0.02f64..0.3, 0.02..0.3, 0.02..0.3],
                    [-0.6f64..2.4, -0.6..0.6, -0.1..0.9],
                    0.0f64..3.2,
                ),
                1..24,
            )
        ) {
            let s = scene(&objects);
            prop_assert_eq!(overlap(&s), overlap_one_by_one(&s));
        }
    }
}
