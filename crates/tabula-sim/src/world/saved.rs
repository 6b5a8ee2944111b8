//! Poses a saved scene can load again: the physics lets bodies squeezed together (two
//! objects jammed in an open hand, a pile pressed by a finger) interpenetrate deeper
//! than a scene file may place them, so the poses written are taken apart first.

use super::*;
use rapier3d_f64::parry::query::contact;

/// Deepest interpenetration a loaded scene may place a body at (m): bodies resting on
/// each other in a settled world overlap by a few millimetres; deeper is a mistake.
pub(crate) const MAX_LOAD_OVERLAP: f64 = 5e-3;

/// How far apart the saved poses are set when taken apart: within the load limit.
const SAVED_OVERLAP: f64 = 1e-3;

impl SimWorld {
    /// Every object's pose as a scene file would place it: where the physics has it,
    /// moved out along the contact normal of anything it sinks into deeper than
    /// [`MAX_LOAD_OVERLAP`] (a few passes, as one move can make another overlap).
    /// Held objects stay where the hand holds them.
    pub(crate) fn saved_object_poses(&self, held: &[String]) -> Vec<(String, Pose)> {
        let mut poses = self.object_poses();
        let index: Vec<Option<usize>> = self
            .entities
            .iter()
            .map(|e| poses.iter().position(|(n, _)| *n == e.name))
            .collect();
        for _ in 0..10 {
            let mut moved = false;
            for i in 0..poses.len() {
                if held.contains(&poses[i].0) {
                    continue;
                }
                if let Some(step) = self.way_out(&poses, &index, i) {
                    poses[i].1.translation += step;
                    moved = true;
                }
            }
            if !moved {
                break;
            }
        }
        poses
    }

    /// How to move object `i` of `poses` out of the deepest thing it sinks into too
    /// far, if any (colliders of objects taken at their `poses`).
    fn way_out(&self, poses: &[(String, Pose)], index: &[Option<usize>], i: usize) -> Option<Vec3> {
        let e = self.entity(&poses[i].0)?;
        let body = &self.physics.bodies[self.entities[e].body];
        let mut deepest: Option<(f64, Vec3)> = None;
        for &own in body.colliders() {
            let mine = &self.physics.colliders[own];
            if is_support_piece(mine.user_data) {
                continue;
            }
            let at = poses[i].1 * *mine.position_wrt_parent().unwrap_or(&Pose::IDENTITY);
            for (_, other) in self.physics.colliders.iter() {
                if other.parent() == Some(self.entities[e].body) {
                    continue;
                }
                let owner = ((other.user_data & 0xFFFF_FFFF) as usize).wrapping_sub(1);
                let other_at = match index.get(owner).copied().flatten() {
                    Some(j) => poses[j].1 * *other.position_wrt_parent().unwrap_or(&Pose::IDENTITY),
                    None => *other.position(),
                };
                let Ok(Some(k)) = contact(&at, mine.shape(), &other_at, other.shape(), 0.0) else {
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
