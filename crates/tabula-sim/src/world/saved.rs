//! Poses a saved scene can load again: the physics lets bodies squeezed together (two
//! objects jammed in an open hand, a pile pressed by a finger) interpenetrate deeper
//! than a scene file may place them, so the poses written are taken apart first.

use super::*;
use rapier3d_f64::parry::query::contact;
use rustc_hash::FxHashMap;

/// Deepest interpenetration a loaded scene may place a body at (m): bodies resting on
/// each other in a settled world overlap by a few millimetres; deeper is a mistake.
pub(crate) const MAX_LOAD_OVERLAP: f64 = 5e-3;

/// How far apart the saved poses are set when taken apart: within the load limit.
const SAVED_OVERLAP: f64 = 1e-3;

/// For every collider of an object, the colliders whose bounds come within
/// [`NEAR`] of its own: the only ones it can sink into, or be moved into when it is
/// taken out of another.
type Near = FxHashMap<ColliderHandle, Vec<ColliderHandle>>;

/// A wedged object is lifted in steps of this (m) …
const LIFT_STEP: f64 = 0.005;
/// … at most this many (a metre).
const LIFT_STEPS: usize = 200;

/// How far apart bounds may be for their colliders to count as neighbours (m): more
/// than a body is moved when taken apart (the physics' contact pairs alone missed the
/// body a move pushed it into).
const NEAR: f64 = 0.02;

impl SimWorld {
    /// Every object's pose as a scene file would place it: where the physics has it,
    /// moved out along the contact normal of anything it sinks into deeper than
    /// [`MAX_LOAD_OVERLAP`] (a few passes, as one move can make another overlap).
    /// Held objects stay where the hand holds them.
    pub(crate) fn saved_object_poses(&self, held: &[String]) -> Vec<(String, Pose)> {
        let mut poses = self.object_poses();
        // The same objects in the same order as `object_poses`.
        let bodies: Vec<RigidBodyHandle> = self
            .live_entities()
            .filter(|e| e.kind == EntityKind::Object)
            .map(|e| e.body)
            .collect();
        let by_body: FxHashMap<RigidBodyHandle, usize> =
            bodies.iter().enumerate().map(|(k, &b)| (b, k)).collect();
        let near = self.near_colliders(&by_body);
        let is_free: Vec<bool> = poses.iter().map(|(n, _)| !held.contains(n)).collect();
        let free = |i: usize| is_free[i];
        for _ in 0..50 {
            let mut moved = false;
            for (i, &body) in bodies.iter().enumerate().filter(|(i, _)| free(*i)) {
                if let Some(step) = self.way_out(&poses, &by_body, &near, body) {
                    poses[i].1.translation += step;
                    moved = true;
                }
            }
            if !moved {
                return poses;
            }
        }
        // Wedged (between a finger and its neighbours, each way out leads into another):
        // lifted until clear of everything, to fall back when the scene is loaded.
        let everything: Vec<ColliderHandle> =
            self.physics.colliders.iter().map(|(h, _)| h).collect();
        for (i, &body) in bodies.iter().enumerate() {
            if !free(i) || self.way_out(&poses, &by_body, &near, body).is_none() {
                continue;
            }
            let mut all = Near::default();
            for &own in self.physics.bodies[body].colliders() {
                all.insert(own, everything.clone());
            }
            for _ in 0..LIFT_STEPS {
                if self.way_out(&poses, &by_body, &all, body).is_none() {
                    break;
                }
                poses[i].1.translation.z += LIFT_STEP;
            }
        }
        poses
    }

    /// The neighbours of every collider of `bodies`: bounds sorted along x and swept,
    /// so a scene of thousands of objects costs its neighbour pairs, not every pair.
    fn near_colliders(&self, objects: &FxHashMap<RigidBodyHandle, usize>) -> Near {
        let mut spans: Vec<(f64, f64, ColliderHandle, Aabb)> = self
            .physics
            .colliders
            .iter()
            .map(|(h, c)| {
                let b = c.compute_aabb().loosened(NEAR / 2.0);
                (b.mins.x, b.maxs.x, h, b)
            })
            .collect();
        spans.sort_by(|a, b| a.0.total_cmp(&b.0));
        let of_object = |h: ColliderHandle| {
            self.physics.colliders[h]
                .parent()
                .is_some_and(|b| objects.contains_key(&b))
        };
        let mut near = Near::default();
        for (i, a) in spans.iter().enumerate() {
            for b in spans[i + 1..].iter().take_while(|b| b.0 <= a.1) {
                if !a.3.intersects(&b.3) {
                    continue;
                }
                if of_object(a.2) {
                    near.entry(a.2).or_default().push(b.2);
                }
                if of_object(b.2) {
                    near.entry(b.2).or_default().push(a.2);
                }
            }
        }
        near
    }

    /// How to move the object of `body` out of the deepest thing it sinks into too far,
    /// if any (colliders of objects taken at their `poses`).
    fn way_out(
        &self,
        poses: &[(String, Pose)],
        by_body: &FxHashMap<RigidBodyHandle, usize>,
        near: &Near,
        body: RigidBodyHandle,
    ) -> Option<Vec3> {
        let at_saved = |c: &Collider| match c.parent().and_then(|b| by_body.get(&b)) {
            Some(&k) => poses[k].1 * *c.position_wrt_parent().unwrap_or(&Pose::IDENTITY),
            None => *c.position(),
        };
        let mut deepest: Option<(f64, Vec3)> = None;
        for &own in self.physics.bodies.get(body)?.colliders() {
            let mine = &self.physics.colliders[own];
            if is_support_piece(mine.user_data) {
                continue;
            }
            let at = at_saved(mine);
            for &h in near.get(&own).into_iter().flatten() {
                let Some(other) = self.physics.colliders.get(h) else {
                    continue;
                };
                if other.parent() == Some(body) {
                    continue;
                }
                let Ok(Some(k)) = contact(&at, mine.shape(), &at_saved(other), other.shape(), 0.0)
                else {
                    continue;
                };
                if k.dist < -MAX_LOAD_OVERLAP + 1e-4 && deepest.is_none_or(|(d, _)| k.dist < d) {
                    deepest = Some((k.dist, -k.normal1 * (-k.dist - SAVED_OVERLAP)));
                }
            }
        }
        deepest.map(|(_, step)| step)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two boxes the physics has pressed 1 cm into each other are saved apart, and the
    /// saved scene loads (the loader refuses more than 5 mm).
    #[test]
    fn bodies_pressed_into_each_other_are_saved_apart() {
        let text = "[floor]\n\n[[object]]\nname = \"a\"\nshape = { box = [0.05, 0.05, 0.05] }\npose = { xyz = [0.0, 0.0, 0.025] }\n\n[[object]]\nname = \"b\"\nshape = { box = [0.05, 0.05, 0.05] }\npose = { xyz = [0.2, 0.0, 0.025] }\n";
        let scene = Scene::parse(text, "two.toml").unwrap();
        let mut world = SimWorld::from_scene(&scene, PhysicsParams::default()).unwrap();
        let b = world.entities[world.entity("b").unwrap()].body;
        world.physics.bodies[b].set_translation(Vec3::new(0.04, 0.0, 0.025), true);
        // Collision detection only (no time passes): the contact pairs of that state.
        world.physics.integration_parameters.dt = 0.0;
        world.physics.step();
        let saved = world.to_scene();
        let gap = |s: &Scene| {
            let x = |n: &str| {
                s.objects
                    .iter()
                    .find(|o| o.name.get_ref() == n)
                    .unwrap()
                    .pose
                    .xyz[0]
            };
            x("b") - x("a")
        };
        assert!(gap(&saved) > 0.05 - MAX_LOAD_OVERLAP, "{}", gap(&saved));
        let reloaded = Scene::parse(&saved.to_toml().unwrap(), "saved.toml").unwrap();
        SimWorld::from_scene(&reloaded, PhysicsParams::default()).expect("the saved scene loads");
    }
}
